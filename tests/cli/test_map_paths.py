"""One map-to-answer path: every command and function that takes a measured map levels it the
same way by default, says so, and gives the same Γ for the same map.

The bundled sample maps are checked always; the real AFM files of ``../shared/afm`` (or
$ROUGHSTICK_AFM_DIR) when they are there.
"""

from __future__ import annotations

import os
import pathlib
import re
import warnings

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.cli import main
from roughstick.cli._config import RunConfig
from roughstick.ensemble.maps import as_maps

SHARED_AFM = pathlib.Path(os.environ.get("ROUGHSTICK_AFM_DIR", "")
                          or pathlib.Path(__file__).resolve().parents[2].parent / "shared" / "afm")
AFM_FILES = ("ST_di-1.di", "ST_di-3.di", "ST_di-6.di", "ST_example_ps.tiff")
#: The pixels compared with the contact model: a centre crop keeps the test fast (the levelling
#: is decided on the whole map first).
CROP = 96


def _targets():
    out = [pytest.param("bundled:S1A", id="bundled-S1A")]
    for name in AFM_FILES:
        out.append(pytest.param(str(SHARED_AFM / name), id=name, marks=pytest.mark.skipif(
            not (SHARED_AFM / name).is_file(), reason=f"real AFM file not found at {SHARED_AFM / name}")))
    return out


def _centre(h: xr.DataArray) -> xr.DataArray:
    y0, x0 = ((h.sizes[d] - CROP) // 2 for d in ("y", "x"))
    return h.isel(y=slice(y0, y0 + CROP), x=slice(x0, x0 + CROP))


def _plane_coefficients(h: xr.DataArray) -> np.ndarray:
    z = np.asarray(h.values, dtype=float)
    y, x = np.meshgrid(h.y.values, h.x.values, indexing="ij")
    good = np.isfinite(z)
    a = np.column_stack([np.ones(good.sum()), x[good], y[good]])
    return np.linalg.lstsq(a, z[good], rcond=None)[0]


@pytest.mark.parametrize("path", _targets())
def test_every_path_levels_a_measured_map_the_same_way(path, tmp_path, capsys):
    raw = rs.io.read_afm(path, levelling="none")
    h = rs.io.read_afm(path)  # the Python path's default
    # levelled: no plane left (tilt below 1e-9 of the rms height per pixel), and said
    coef = _plane_coefficients(h)
    sq = float(np.nanstd(h.values))
    pixel = float(h.x[1] - h.x[0])
    assert abs(coef[0]) < 1e-9 * sq and max(abs(coef[1:])) * pixel < 1e-9 * sq
    assert h.attrs["levelling"] == "plane" and "least-squares plane" in h.attrs["history"]
    # roughstick run ([psd] files) and ensemble.run(maps=) see the same heights, levelled once
    cfg = RunConfig.__new__(RunConfig)
    cfg.psd = {"source": "samples", "files": [path]}
    (from_run,) = cfg.sample_maps()
    (from_ensemble,) = as_maps([h])
    (from_raw,) = as_maps([raw])
    for other in (from_run, from_ensemble, from_raw):
        np.testing.assert_allclose(other.values, h.values, rtol=0, atol=1e-12 * sq)
    # roughstick psd prints it
    assert main(["psd", path, "--out", str(tmp_path / "psd.nc"), "--surrogates", "0"]) == 0
    assert "levelled: removed its least-squares plane" in capsys.readouterr().out
    # roughstick curves: the same map, hence the same Γ as the Python path (modified DMT on the
    # map's centre, written to a file the command reads)
    crop = _centre(h).assign_attrs(h.attrs)
    crop_path = tmp_path / "crop.nc"
    rs.io.write(crop.to_dataset(name="height"), crop_path)
    out = tmp_path / "curves.nc"
    assert main(["curves", str(crop_path), "--rh", "0.5", "--model", "modified_dmt",
                 "--out", str(out)]) == 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the validity and pixel warnings: said by the command
        api = rs.contact.summary(rs.contact.curves(_centre(rs.io.read_afm(path)), relative_humidity=[0.5],
                                                   model="modified_dmt", n_distance=200))
    with xr.open_dataset(out) as ds:
        np.testing.assert_allclose(ds.adhesive_energy.values, api.adhesive_energy.values, rtol=1e-9)


def test_curves_levels_a_tilted_map_as_psd_does(tmp_path, capsys):
    """A tilted measured map: `roughstick curves` levels it by default (printed), and its Γ is that
    of the untilted map, not that of the raw one (which the tilt changes)."""
    h = rs.datasets.surface_family("smooth", shape=(64, 64), seed=3)
    z = h.values * 1e9
    x = np.arange(64)[None, :]
    np.save(tmp_path / "flat.npy", z)
    np.save(tmp_path / "tilted.npy", z + 0.3 * x)  # 19 nm across 64 pixels, rms height ~1-2 nm
    gammas = {}
    for name, extra in (("flat", []), ("tilted", []), ("raw", ["--level", "none"])):
        src = "flat" if name == "flat" else "tilted"
        out = tmp_path / f"{name}.nc"
        assert main(["curves", str(tmp_path / f"{src}.npy"), "--spacing", "5 nm", "--units", "nm",
                     "--rh", "0.7", "--model", "modified_dmt", "--out", str(out), *extra]) == 0
        text = capsys.readouterr().out
        assert ("not levelled" if extra else "levelled: removed its least-squares plane") in text
        with xr.open_dataset(out) as ds:
            gammas[name] = float(ds.adhesive_energy.values[0])
    # the same levelled heights to round-off (the automatic distance grid may move a little)
    assert gammas["tilted"] == pytest.approx(gammas["flat"], rel=1e-4)
    assert abs(gammas["raw"] / gammas["flat"] - 1) > 0.1  # the tilt is not a small matter


def test_maps_of_different_surfaces_are_said_before_they_are_averaged():
    rng = np.random.default_rng(0)
    a = rs.testing.make_topography(rng.normal(size=(48, 48)) * 1e-9, spacing=2e-9)
    b = rs.testing.make_topography(rng.normal(size=(48, 48)) * 1e-9, spacing=2e-9)
    c = rs.testing.make_topography(rng.normal(size=(48, 48)) * 4e-9, spacing=2e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        as_maps([a, b])  # one surface: silent
    with pytest.warns(rs.surface.IncompatibleMapsWarning, match=r"rms height Sq .* \(3\.9"):
        as_maps([a, c])


def test_psd_says_when_the_maps_it_averages_are_of_different_surfaces(tmp_path, capsys):
    rng = np.random.default_rng(1)
    for name, rms in (("a", 1.0), ("b", 1.1), ("c", 5.0)):
        np.save(tmp_path / f"{name}.npy", rng.normal(size=(48, 48)) * rms)
    common = ["--spacing", "2 nm", "--units", "nm", "--surrogates", "0"]
    assert main(["psd", str(tmp_path / "a.npy"), str(tmp_path / "b.npy"), "--out", str(tmp_path / "ab.nc"),
                 *common]) == 0
    assert "IncompatibleMapsWarning" not in "".join(capsys.readouterr())
    assert main(["psd", str(tmp_path / "a.npy"), str(tmp_path / "c.npy"), "--out", str(tmp_path / "ac.nc"),
                 *common]) == 0
    said = "".join(capsys.readouterr())
    assert "IncompatibleMapsWarning" in said and "c.npy: Sq" in said


def test_maps_of_one_surface_at_two_scan_sizes_are_compared_by_their_spectra():
    """A self-affine surface is rougher over a larger scan, so maps of two sizes are compared by
    their PSDs over the band both resolve: one surface passes, three times its heights does not."""
    big = rs.datasets.surface_family("S1", shape=(256, 256), seed=2)
    small = big.isel(y=slice(0, 96), x=slice(0, 96))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        kept = as_maps([big, small])  # silent
    with pytest.warns(rs.surface.IncompatibleMapsWarning, match=r"PSDs [\d.]+x apart over the band") as said:
        as_maps([big, small * 3])
    # three times the heights: nine times the variance in the band, within the spread of crops of
    # one surface (up to 1.8x on the AFM maps, docs/evidence/non_gaussian.md)
    ratio = float(re.search(r"PSDs ([\d.]+)x", str(said[0].message)).group(1))
    assert 9 / 1.8 < ratio < 9 * 1.8
    assert len(kept) == 2
