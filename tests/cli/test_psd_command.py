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
    ref = rs.surface.psd_summary(
        xr.concat([rs.surface.level(rs.io.read_afm(tmp_path / f"m{i}.npy", spacing=5e-9, units="nm"))
                   for i in range(2)], dim="map"), n=4)
    np.testing.assert_allclose(ds.psd.values, ref.psd.values, rtol=1e-10)
    ds.close()
    # maps of different sizes: averaged on a common q grid, each map's statistics kept over 'map'
    h, _ = filtered_noise((48, 40), 5e-9, lorentz, rng)
    np.save(tmp_path / "small.npy", h.values * 1e9)
    assert main(["psd", str(tmp_path / "m0.npy"), str(tmp_path / "small.npy"), "--spacing",
                 "5 nm", "--units", "nm", "--submaps", "1", "--out", str(tmp_path / "x.nc")]) == 0
    assert "common band" in capsys.readouterr().out
    with xr.open_dataset(tmp_path / "x.nc") as ds:
        assert ds.psd_isotropic.dims == ("q",) and ds.contributed.dims == ("map", "q")
        assert list(ds["map"].values) == ["m0.npy", "small.npy"] and ds.spatial_m2.dims == ("map",)
        # the small map's first ring: q = min(dqx, dqy) = 2 pi / (48 x 5 nm)
        np.testing.assert_allclose(float(ds.q[0]), 2 * np.pi / (48 * 5e-9), rtol=1e-9)
        assert np.all(ds.n_maps == 2)


def test_cli_psd_line_scans(tmp_path, capsys):
    """Rows of a synthetic map saved as line scans: roughstick psd writes their profile PSD and
    moments; the profile m2 equals the rows' mean cubic-spline slope variance; a mix of line scans
    and maps is refused."""
    from roughstick.cli import main

    h, _ = filtered_noise((8, 256), 2e-9, lorentz, np.random.default_rng(3))
    for i in range(3):
        np.savetxt(tmp_path / f"s{i}.txt", h.values[i] * 1e9)
    np.savetxt(tmp_path / "short.txt", h.values[5, :200] * 1e9)
    args = ["psd", *(str(tmp_path / f"s{i}.txt") for i in range(3)), "--spacing", "2 nm", "--units",
            "nm", "--window", "hann", "--out", str(tmp_path / "p.nc")]
    assert main(args) == 0
    assert "3 line scans" in capsys.readouterr().out
    with xr.open_dataset(tmp_path / "p.nc") as ds:
        assert ds.psd_1d.dims == ("qx",) and ds.psd_1d.attrs["units"] == "m3"
        ref = rs.surface.profile_moments(rs.surface.level_profile(
            rs.io.read_afm(tmp_path / "s0.txt", spacing="2 nm", units="nm", line_scan=True)))
        rows = [rs.surface.profile_moments(rs.surface.level_profile(rs.io.read_afm(
            tmp_path / f"s{i}.txt", spacing="2 nm", units="nm", line_scan=True))).m2 for i in range(3)]
        np.testing.assert_allclose(float(ds.spatial_m2), np.mean([float(r) for r in rows]), rtol=1e-10)
        assert float(ref.m2) > 0
    # different lengths: common log-spaced grid
    assert main(["psd", str(tmp_path / "s0.txt"), str(tmp_path / "short.txt"), "--spacing", "2 nm",
                 "--units", "nm", "--window", "hann", "--out", str(tmp_path / "q.nc")]) == 0
    with xr.open_dataset(tmp_path / "q.nc") as ds:
        assert ds.psd_1d.dims == ("qx",) and float(ds.qx[0]) > 0 and ds.contributed.dims == ("map", "qx")
    import netCDF4

    for name in ("p.nc", "q.nc"):  # CF: every variable labelled, numbers with units (compliance-checker
        with netCDF4.Dataset(tmp_path / name) as nc:  # cf:1.10 also passes on them, checked by hand)
            for v, var in nc.variables.items():
                assert "long_name" in var.ncattrs(), (name, v)
                assert ("units" in var.ncattrs()) == (var.dtype is not str), (name, v)
    np.save(tmp_path / "map.npy", h.values * 1e9)
    assert main(["psd", str(tmp_path / "s0.txt"), str(tmp_path / "map.npy"), "--spacing", "2 nm",
                 "--units", "nm", "--out", str(tmp_path / "r.nc")]) == 1
    assert "mix line scans" in capsys.readouterr().err


def test_cli_psd_reads_bundled_maps_by_name(tmp_path, capsys):
    """`roughstick psd bundled:S2A bundled:S2B` works from any folder (a wheel has no data_samples/)."""
    from roughstick.cli import main

    out = tmp_path / "psd.nc"
    assert main(["psd", "bundled:S2A", "bundled:S2B", "--submaps", "4", "--window", "none",
                 "--out", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert ds.attrs["input_files"] == "bundled:S2A bundled:S2B" and ds.attrs["n_maps"] == 2
        ref = rs.surface.psd_summary(rs.datasets.sample_maps("S2").isel(map=[0, 1]), n=4, window=None)
        np.testing.assert_allclose(ds.psd.values, ref.psd.values, rtol=1e-10)
    capsys.readouterr()
    assert main(["psd", "bundled:S2A", "bundled:S4A", "--out", str(tmp_path / "x.nc")]) == 1
    err = capsys.readouterr().err.strip()
    assert "unknown bundled map 'bundled:S4A'" in err and "bundled:S2C" in err and "\n" not in err
    assert not (tmp_path / "x.nc").exists()


def test_cli_psd_prints_moments_with_their_interval_over_maps(tmp_path, capsys):
    """Several maps: the mean spatial moments with the range across maps and the 95 % Student-t
    interval of the mean (checked against scipy.stats.t); one map: n = 1 is too small to bound."""
    import scipy.stats

    from roughstick.cli import main

    rng = np.random.default_rng(5)
    paths = []
    for i in range(3):
        h, _ = filtered_noise((64, 64), 5e-9, lorentz, rng)
        paths.append(tmp_path / f"m{i}.npy")
        np.save(paths[-1], h.values * 1e9)
    out = tmp_path / "psd.nc"
    assert main(["psd", *map(str, paths), "--spacing", "5 nm", "--units", "nm", "--submaps", "4",
                 "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "mean over the 3 maps [range across them; 95% interval of the mean, Student t with 2 dof]" in text
    per = rs.surface.roughness_moments(xr.concat([rs.surface.level(rs.io.read_afm(p, spacing="5 nm", units="nm"))
                                          for p in paths], dim="map"))
    t = scipy.stats.t.ppf(0.975, df=2)
    with xr.open_dataset(out) as ds:
        for k in ("m0", "m2", "m4"):
            v = per[k].values
            np.testing.assert_allclose(ds[f"map_spatial_{k}"].values, v, rtol=1e-12)
            np.testing.assert_allclose(float(ds[f"spatial_{k}"]), v.mean(), rtol=1e-12)
            half = t * v.std(ddof=1) / np.sqrt(3)
            np.testing.assert_allclose(ds[f"spatial_{k}"].attrs["interval_95_percent"],
                                       [max(v.mean() - half, 0), v.mean() + half], rtol=1e-9)
    v = per["m2"].values
    half = t * v.std(ddof=1) / np.sqrt(3)
    assert (f"  m2 = {v.mean():.3g} [{v.min():.3g}-{v.max():.3g}; {max(v.mean() - half, 0):.3g}-"
            f"{v.mean() + half:.3g}]") in text
    assert main(["psd", str(paths[0]), "--spacing", "5 nm", "--units", "nm", "--submaps", "4",
                 "--out", str(tmp_path / "one.nc")]) == 0
    text = capsys.readouterr().out
    assert "1 map, 4 sub-maps each" in text
    assert "n = 1 map is too small to bound their map-to-map spread (give 2 or more maps)" in text
    with xr.open_dataset(tmp_path / "one.nc") as ds:
        assert "interval_95_percent" not in ds.spatial_m0.attrs
