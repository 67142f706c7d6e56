"""`roughstick risk CONFIG.toml`: from a given sample of Gamma, and bad configs."""

from __future__ import annotations

import numpy as np
import xarray as xr

import roughstick as rs
from conftest import lognormal_gamma


def test_cli_risk_from_given_sample(tmp_path, capsys):
    from roughstick.cli import main

    g, _ = lognormal_gamma(n=25, rh=np.arange(0.3, 0.951, 0.05))
    g = rs.conventions.set_attrs(g, "surface_adhesive_energy")
    sample = xr.concat([g, 2 * g], dim=xr.DataArray(["none", "paper"], dims="adsorbed_layer"))
    sample["adsorbed_layer"].attrs = {"units": "1", "long_name": "adsorbed water layer model"}
    ds = sample.to_dataset(name="adhesive_energy")
    rs.io.netcdf.write(ds, tmp_path / "gamma.nc", compute=True)
    (tmp_path / "points.csv").write_text("relative_humidity,crack_length [um]\n0.4,420\n0.7,380\n")
    cfg = tmp_path / "risk.toml"
    cfg.write_text(
        '[output]\nfolder = "out"\n'
        '[beam]\nlengths = ["250 um", "350 um", "500 um"]\n'
        '[ensemble]\nadhesive_energy = "gamma.nc"\n'
        "[risk]\nlevels = [0.1, 0.5]\n"
        '[[measured]]\nfile = "points.csv"\nlabel = "csv"\n'
        '[[measured]]\nrelative_humidity = [0.5]\nadhesive_energy = ["0.5 mJ m-2"]\n'
    )
    assert main(["risk", str(cfg)]) == 0
    text = capsys.readouterr().out
    assert "RH where P(stuck) reaches 0.5" in text
    out = tmp_path / "out"
    for f in ("risk.nc", "stiction_probability.png", "stiction_vs_length.png",
              "adhesive_energy_bands.png", "crack_length.png"):
        assert (out / f).stat().st_size > 1000, f
    got = rs.open_dataset(out / "risk.nc").load()
    ref = rs.stiction_risk(sample, length=[250e-6, 350e-6, 500e-6], levels=[0.1, 0.5])
    np.testing.assert_allclose(got.stiction_probability.transpose(*ref.stiction_probability.dims),
                               ref.stiction_probability)
    np.testing.assert_allclose(got.crossing_humidity.transpose(*ref.crossing_humidity.dims),
                               ref.crossing_humidity)
    # the layer doubles Gamma here, so P(stuck) with the layer is never below the no-layer one
    assert (got.stiction_probability.sel(adsorbed_layer="paper")
            >= got.stiction_probability.sel(adsorbed_layer="none")).all()


def test_cli_risk_bad_config(tmp_path):
    from roughstick.cli import main

    cfg = tmp_path / "bad.toml"
    cfg.write_text("[beam]\nlength_um = 300\n")
    assert main(["risk", str(cfg)]) == 1
    cfg.write_text("[beems]\n")
    assert main(["risk", str(cfg)]) == 1
    assert main(["risk", str(tmp_path / "missing.toml")]) == 1
