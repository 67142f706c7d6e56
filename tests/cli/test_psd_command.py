"""`roughstick psd MAPS...`: PSD and statistics of AFM maps written as CF NetCDF."""

from __future__ import annotations

import numpy as np
import xarray as xr

import roughstick as rs
from conftest import filtered_noise, lorentz


def test_cli_psd(tmp_path, capsys):
    from roughstick.cli import main

    rng = np.random.default_rng(16)
    for i in range(2):
        h, _ = filtered_noise((64, 64), 5e-9, lorentz, rng)
        np.save(tmp_path / f"m{i}.npy", h.values * 1e9)
    out = tmp_path / "psd.nc"
    args = ["psd", str(tmp_path / "m0.npy"), str(tmp_path / "m1.npy"), "--spacing", "5 nm",
            "--units", "nm", "--submaps", "4", "--out", str(out)]
    assert main(args) == 0
    assert "wrote" in capsys.readouterr().out
    ds = xr.open_dataset(out)
    assert ds.psd.dims == ("qy", "qx") and ds.attrs["n_maps"] == 2
    assert "roughstick psd" in ds.attrs["history"]
    ref = rs.psd_summary(
        xr.concat([rs.level(rs.read_afm(tmp_path / f"m{i}.npy", spacing=5e-9, units="nm"))
                   for i in range(2)], dim="map"), n=4)
    np.testing.assert_allclose(ds.psd.values, ref.psd.values, rtol=1e-10)
    ds.close()
    np.save(tmp_path / "small.npy", np.random.default_rng(1).normal(size=(32, 32)))
    assert main(["psd", str(tmp_path / "m0.npy"), str(tmp_path / "small.npy"), "--spacing",
                 "5 nm", "--units", "nm", "--out", str(tmp_path / "x.nc")]) == 1
    assert "same size" in capsys.readouterr().err
