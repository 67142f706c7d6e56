"""Tests of roughstick.io.read_afm: built-in formats, vendor formats via SurfaceTopography."""

from __future__ import annotations

import os
import pathlib
import sys

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.testing import make_topography

# same location as tests/conftest.py's SHARED_AFM: ../shared/afm beside the project
# (or $ROUGHSTICK_AFM_DIR, e.g. from a git worktree elsewhere)
SHARED_AFM = pathlib.Path(os.environ.get("ROUGHSTICK_AFM_DIR", "")
                          or pathlib.Path(__file__).resolve().parents[2].parent / "shared" / "afm")

needs_afm = pytest.mark.skipif(
    not SHARED_AFM.is_dir(), reason=f"real AFM files not found at {SHARED_AFM}"
)


def test_a_measured_map_is_levelled_by_its_plane_as_it_is_read(tmp_path):
    """read_afm's default removes the least-squares plane (an independent lstsq fit here), says
    so in history and attrs, and leaves a periodic map (read back exactly) alone."""
    y, x = np.meshgrid(np.arange(20), np.arange(30), indexing="ij")
    z = np.random.default_rng(4).normal(size=(20, 30)) + 0.3 * x - 0.2 * y + 7.0  # nm, tilted
    np.save(tmp_path / "tilt.npy", z)
    h = rs.io.read_afm(tmp_path / "tilt.npy", spacing="5 nm", units="nm")
    a = np.column_stack([np.ones(z.size), x.ravel(), y.ravel()])
    expected = z.ravel() - a @ np.linalg.lstsq(a, z.ravel(), rcond=None)[0]
    np.testing.assert_allclose(h.values.ravel(), expected * 1e-9, rtol=0, atol=1e-21)
    assert h.attrs["levelling"] == "plane" and "least-squares plane" in h.attrs["history"]
    assert "levelling='none'" in h.attrs["history"]  # how to keep the raw heights
    raw = rs.io.read_afm(tmp_path / "tilt.npy", spacing="5 nm", units="nm", levelling="none")
    np.testing.assert_allclose(raw.values, z * 1e-9)
    # levelled already: read back as it is
    rs.io.write(h.to_dataset(), tmp_path / "levelled.nc")
    xr.testing.assert_allclose(rs.io.read_afm(tmp_path / "levelled.nc"), h)
    with pytest.raises(ValueError, match="levelling must be one of"):
        rs.io.read_afm(tmp_path / "tilt.npy", spacing="5 nm", units="nm", levelling="polynomial")


def test_npy_and_text(tmp_path):
    z = np.random.default_rng(0).normal(size=(9, 13))
    np.save(tmp_path / "m.npy", z)
    h = rs.io.read_afm(tmp_path / "m.npy", spacing="5 nm", units="nm", levelling="none")
    assert h.dims == ("y", "x") and h.shape == (9, 13) and h.attrs["units"] == "m"
    np.testing.assert_allclose(h.values, z * 1e-9)
    np.testing.assert_allclose(np.diff(h.x.values), 5e-9)
    assert h.attrs["periodic"] == 0 and h.attrs["source"].endswith("m.npy")
    assert "read_afm" in h.attrs["history"]
    np.savetxt(tmp_path / "m.txt", z, header="a plain grid")
    t = rs.io.read_afm(tmp_path / "m.txt", spacing=(2e-9, 5e-9), units="um", levelling="none")
    np.testing.assert_allclose(t.values, z * 1e-6)
    np.testing.assert_allclose(np.diff(t.y.values), 2e-9)
    np.savetxt(tmp_path / "m.csv", z, delimiter=",")
    with pytest.warns(UserWarning, match="implausible for an AFM map"):  # heights of metres
        np.testing.assert_allclose(rs.io.read_afm(tmp_path / "m.csv", spacing=1e-9, units="m",
                                                  levelling="none").values, z)
    with pytest.raises(ValueError, match="spacing="):
        rs.io.read_afm(tmp_path / "m.npy")
    with pytest.raises(rs.UnitsError, match="not a length"):
        rs.io.read_afm(tmp_path / "m.npy", spacing=1e-9, units="s")
    with pytest.raises(ValueError, match="positive length"):
        rs.io.read_afm(tmp_path / "m.npy", spacing=-1.0, units="m")
    np.save(tmp_path / "v.npy", np.zeros(5))
    with pytest.raises(ValueError, match="2-D"):
        rs.io.read_afm(tmp_path / "v.npy", spacing=1e-9, units="m")
    with pytest.raises(FileNotFoundError):
        rs.io.read_afm(tmp_path / "nope.npy")


def test_netcdf_round_trip_exact(tmp_path):
    h = make_topography(np.random.default_rng(1).normal(size=(12, 10)) * 1e-9, periodic=True)
    h.attrs["source"] = "roughstick 0.1.0"
    rs.conventions.append_history(h, "made for a test")
    h.to_netcdf(tmp_path / "h.nc")
    back = rs.io.read_afm(tmp_path / "h.nc")
    xr.testing.assert_identical(back, h)
    ds = xr.Dataset({"height": h, "other": h * 2})
    ds.to_netcdf(tmp_path / "d.nc")
    xr.testing.assert_identical(rs.io.read_afm(tmp_path / "d.nc"), h)
    np.testing.assert_array_equal(rs.io.read_afm(tmp_path / "d.nc", channel="other").values, 2 * h.values)
    with pytest.raises(ValueError, match="no variable"):
        rs.io.read_afm(tmp_path / "d.nc", channel="zz")


def test_vendor_without_surfacetopography(tmp_path, monkeypatch):
    p = tmp_path / "x.spm"
    p.write_bytes(b"\0" * 10)
    monkeypatch.setitem(sys.modules, "SurfaceTopography", None)
    with pytest.raises(ImportError, match=r"pip install roughstick\[afm\]"):
        rs.io.read_afm(p)


@needs_afm
@pytest.mark.parametrize(
    "name, channel, sq_nm, shape",
    [
        ("ST_di-1.di", None, 9.8, (512, 512)),
        ("ST_di-6.di", None, 14.3, (512, 512)),
        ("ST_example_ps.tiff", "Z Height", 3.9, (512, 512)),
        ("ST_di-3.di", 3, 45.5, (256, 256)),
        ("ST_di-3.di", None, 45.5, (256, 256)),  # the Height channel by name, not ZSensor (35.2)
        ("ST_di-3.di", 0, 35.2, (256, 256)),
    ],
)
def test_real_files_sq_after_plane_removal(name, channel, sq_nm, shape):
    pytest.importorskip("SurfaceTopography")
    h = rs.io.read_afm(SHARED_AFM / name, channel=channel)
    assert h.shape == shape and h.attrs["units"] == "m" and name in h.attrs["source"]
    sq = float(rs.surface.level(h, method="plane").std())
    np.testing.assert_allclose(sq, sq_nm * 1e-9, rtol=0.01)  # README of shared/afm


@needs_afm
def test_real_file_scan_line_alignment_and_channels():
    pytest.importorskip("SurfaceTopography")
    h = rs.io.read_afm(SHARED_AFM / "ST_di-1.di")
    np.testing.assert_allclose(np.diff(h.x.values), 500e-9 / 512)
    sq = float(rs.surface.level(h, method="line").std())
    np.testing.assert_allclose(sq, 7.7e-9, rtol=0.01)
    with pytest.raises(ValueError, match="not a height channel"):
        rs.io.read_afm(SHARED_AFM / "ST_di-1.di", channel=2)
    with pytest.raises(ValueError, match="no channel"):
        rs.io.read_afm(SHARED_AFM / "ST_example_ps.tiff", channel="Phase")
    # pixel size given by the user overrides the file's scan size
    h2 = rs.io.read_afm(SHARED_AFM / "ST_di-3.di", channel=3, spacing="10 nm")
    np.testing.assert_allclose(np.diff(h2.x.values), 10e-9)
    # a real map goes through the whole statistics chain
    st = rs.surface.roughness_statistics(rs.surface.level(h))
    assert float(st.summit_density) > 0 and np.isfinite(float(st.bandwidth))


@needs_afm
def test_channel_reported_and_metadata_kept():
    pytest.importorskip("SurfaceTopography")
    h = rs.io.read_afm(SHARED_AFM / "ST_di-3.di")
    assert h.attrs["channel"] == "3: Height"
    assert "0: ZSensor" in h.attrs["channels_in_file"]
    assert h.attrs["instrument_name"] == "Dimension Icon" and h.attrs["instrument_vendor"] == "Bruker"
    assert h.attrs["acquisition_time"].startswith("2014-12-15")


@needs_afm
def test_surfacetopography_netcdf_accepted(tmp_path):
    """NetCDF written by SurfaceTopography / contact.engineering: attribute 'unit', dims (x, y)."""
    st = pytest.importorskip("SurfaceTopography")
    t = st.open_topography(str(SHARED_AFM / "ST_di-3.di")).topography(channel_index=3)
    t.to_netcdf(str(tmp_path / "ce.nc"))
    h = rs.io.read_afm(tmp_path / "ce.nc", levelling="none")
    vendor = rs.io.read_afm(SHARED_AFM / "ST_di-3.di", channel=3, levelling="none")
    np.testing.assert_allclose(h.values, vendor.values, rtol=1e-12)
    np.testing.assert_allclose(h.x.values, vendor.x.values, rtol=1e-12)
    assert h.attrs["units"] == "m" and h.attrs["instrument_vendor"] == "Bruker"
    # --units overrides the file's unit
    with pytest.warns(UserWarning, match="implausible for an AFM map"):  # 1e3 x: mm heights
        h_um = rs.io.read_afm(tmp_path / "ce.nc", units="um", levelling="none")
    np.testing.assert_allclose(h_um.values, 1e3 * h.values, rtol=1e-12)


def test_foreign_netcdf_without_units_is_refused(tmp_path):
    xr.Dataset({"z": (("x", "y"), np.zeros((16, 16)))},
               coords={"x": np.arange(16.0), "y": np.arange(16.0)}).to_netcdf(tmp_path / "z.nc")
    with pytest.raises(ValueError, match="no 'units'.*--units nm"):
        rs.io.read_afm(tmp_path / "z.nc")
    with pytest.raises(ValueError, match="coordinate 'y' has no units"):
        rs.io.read_afm(tmp_path / "z.nc", units="nm")
    with pytest.warns(UserWarning, match="a flat map"):
        h = rs.io.read_afm(tmp_path / "z.nc", units="nm", spacing="5 nm")
    assert h.dims == ("y", "x") and float(h.x[1] - h.x[0]) == pytest.approx(5e-9)


def test_files_that_are_not_what_their_extension_says(tmp_path):
    (tmp_path / "a.nc").write_text("this is text, not NetCDF")
    with pytest.raises(ValueError, match="not NetCDF despite its extension"):
        rs.io.read_afm(tmp_path / "a.nc")
    (tmp_path / "b.di").write_bytes(b"\x00" * 64)
    pytest.importorskip("SurfaceTopography")
    with pytest.raises(ValueError, match="Is it what its extension says"):
        rs.io.read_afm(tmp_path / "b.di")


def test_line_scan_netcdf_refused_clearly(tmp_path):
    xr.Dataset({"heights": (("x",), np.zeros(64), {"unit": "nm"})},
               coords={"x": ("x", np.arange(64.0), {"unit": "nm"})}).to_netcdf(tmp_path / "l.nc")
    with pytest.raises(ValueError, match="line scan.*2-D height map.*line_scan=True"):
        rs.io.read_afm(tmp_path / "l.nc")


def test_line_scans_read_with_line_scan_true(tmp_path):
    """1-D .npy, one text column, one csv row and a 1-D NetCDF variable (SurfaceTopography style:
    'unit', a coordinate in nm) all read as height over x; a 2-D map reads as before."""
    z = np.sin(np.arange(100) / 7.0) * 3.0  # nm
    np.save(tmp_path / "p.npy", z)
    np.savetxt(tmp_path / "p.txt", z[:, None])
    np.savetxt(tmp_path / "p.csv", z[None, :], delimiter=",")
    xr.Dataset({"heights": (("s",), z, {"unit": "nm"})},
               coords={"s": ("s", np.arange(100) * 2.0, {"unit": "nm"})}).to_netcdf(tmp_path / "p.nc")
    for name in ("p.npy", "p.txt", "p.csv", "p.nc"):
        kw = {} if name == "p.nc" else {"spacing": "2 nm", "units": "nm"}
        with pytest.raises(ValueError, match="line scan"):
            rs.io.read_afm(tmp_path / name, **kw)
        h = rs.io.read_afm(tmp_path / name, line_scan=True, **kw)
        assert h.dims == ("x",) and h.attrs["line_scan"] == 1 and h.attrs["units"] == "m", name
        np.testing.assert_allclose(h.values, z * 1e-9, rtol=1e-12)
        np.testing.assert_allclose(float(h.x[1] - h.x[0]), 2e-9, rtol=1e-12)
        c = rs.surface.profile_psd(rs.surface.level_profile(h, method="mean"), window=None)
        np.testing.assert_allclose(float(c.sum()) * float(c.qx[1] - c.qx[0]), (z * 1e-9).var(), rtol=1e-10)
        with pytest.raises(ValueError, match="line scan.*profile_psd"):
            rs.surface.level(h)
    # a line scan written by roughstick reads back the same
    rs.io.read_afm(tmp_path / "p.npy", spacing="2 nm", units="nm", line_scan=True).to_netcdf(tmp_path / "own.nc")
    back = rs.io.read_afm(tmp_path / "own.nc", line_scan=True)
    np.testing.assert_allclose(back.values, z * 1e-9, rtol=1e-12)
    np.save(tmp_path / "m.npy", np.random.default_rng(0).normal(size=(16, 12)))
    assert rs.io.read_afm(tmp_path / "m.npy", spacing="2 nm", units="nm", line_scan=True).dims == ("y", "x")


@needs_afm
def test_cli_psd_names_the_channel(tmp_path, capsys):
    pytest.importorskip("SurfaceTopography")
    from roughstick.cli import main

    assert main(["psd", str(SHARED_AFM / "ST_di-3.di"), "--submaps", "1",
                 "--out", str(tmp_path / "p.nc")]) == 0
    out = capsys.readouterr().out
    assert "channel 3: Height (of 0: ZSensor, 1: AmplitudeError, 2: Phase, 3: Height)" in out


@pytest.mark.parametrize(
    "array, match",
    [
        (np.zeros((8, 8), dtype=complex), "complex numbers"),
        (np.zeros((8, 8), dtype=bool), "booleans"),
        (np.array([["a"] * 4] * 4), "text"),
        (np.zeros((0, 8)), "empty"),
        (np.zeros((1, 8)), "line scan.*line_scan=True"),
        (np.zeros((8, 1)), "line scan.*roughstick psd"),
        (np.full((8, 8), np.inf), "infinite pixel"),
        (np.full((8, 8), np.nan), "no finite pixel"),
    ],
)
def test_arrays_a_height_map_cannot_be(tmp_path, array, match):
    np.save(tmp_path / "a.npy", array)
    with pytest.raises(ValueError, match=match):
        rs.io.read_afm(tmp_path / "a.npy", spacing="5 nm", units="nm")


def test_implausible_or_flat_heights_warn_with_the_fix(tmp_path):
    rng = np.random.default_rng(0)
    np.save(tmp_path / "nm.npy", rng.normal(scale=5.0, size=(16, 16)) * 1e3)  # nm typed as m
    with pytest.warns(UserWarning, match="pass units='nm'"):
        rs.io.read_afm(tmp_path / "nm.npy", spacing="5 nm", units="m")
    np.save(tmp_path / "flat.npy", np.zeros((16, 16)))
    with pytest.warns(UserWarning, match="flat map"):
        rs.io.read_afm(tmp_path / "flat.npy", spacing="5 nm", units="nm")


def test_surfacetopography_line_scan_netcdf(tmp_path):
    """A line scan as SurfaceTopography / contact.engineering write it (UniformLineScan)."""
    st = pytest.importorskip("SurfaceTopography")
    z = np.sin(np.arange(100) / 7.0) * 3.0
    st.UniformLineScan(z, 200.0, unit="nm", info={"instrument": {"name": "profiler"}}).to_netcdf(
        str(tmp_path / "ls.nc"))
    with pytest.raises(ValueError, match="line scan.*line_scan=True"):
        rs.io.read_afm(tmp_path / "ls.nc")
    h = rs.io.read_afm(tmp_path / "ls.nc", line_scan=True)
    assert h.dims == ("x",) and h.attrs["instrument_name"] == "profiler"
    np.testing.assert_allclose(h.values, z * 1e-9, rtol=1e-12)
    np.testing.assert_allclose(float(h.x[1] - h.x[0]), 2e-9, rtol=1e-12)


def test_a_config_file_given_as_a_map_is_named_as_such(tmp_path):
    """`roughstick curves CONFIG.toml` used to end in a traceback asking to install
    SurfaceTopography; a .toml is a configuration, refused with what to run instead."""
    cfg = tmp_path / "c.toml"
    cfg.write_text("[run]\n")
    with pytest.raises(ValueError, match=r"c.toml is a configuration file \(roughstick run"):
        rs.io.read_afm(cfg)
