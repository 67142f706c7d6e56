"""Tests of roughstick.io.netcdf: CF checks, atomic zlib writes, reading back."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from dask.delayed import Delayed

import roughstick as rs
from roughstick.io import netcdf as nc


def _ds(lazy=False):
    d = xr.Dataset(
        {"pressure": (("realization", "distance"), np.arange(12.0).reshape(3, 4))},
        coords={"realization": np.arange(3), "distance": np.linspace(1e-9, 4e-9, 4)},
    )
    d["pressure"].attrs = {"units": "Pa", "long_name": "mean pressure"}
    d["realization"].attrs = {"units": "1", "long_name": "realization index"}
    d["distance"].attrs = {"units": "m", "long_name": "distance"}
    d.attrs = {"title": "t", "flag": True}
    return d.chunk({"realization": 1}) if lazy else d


def test_cf_check_names_missing_attrs(tmp_path):
    d = _ds()
    del d["pressure"].attrs["long_name"]
    del d["distance"].attrs["units"]
    with pytest.raises(ValueError, match="'pressure' lacks long_name; 'distance' lacks units"):
        nc.write(d, tmp_path / "a.nc", compute=True)
    assert not list(tmp_path.iterdir())


def test_write_writes_now_by_default_as_xarray_does(tmp_path):
    """rs.io.write(ds, path) returned a Delayed and wrote nothing unless compute=True."""
    path = rs.io.write(_ds(lazy=True), tmp_path / "now.nc")
    assert path == tmp_path / "now.nc" and [p.name for p in tmp_path.iterdir()] == ["now.nc"]
    xr.testing.assert_equal(rs.io.open_dataset(path), _ds())


def test_write_delayed_atomic_and_roundtrip(tmp_path):
    path = tmp_path / "a.nc"
    d = _ds(lazy=True)
    task = nc.write(d, path, compute=False)
    assert isinstance(task, Delayed)
    assert not path.exists()  # only a temporary file until the write completes
    assert all(".tmp-" in p.name for p in tmp_path.iterdir())
    task.compute()
    assert path.exists() and [p.name for p in tmp_path.iterdir()] == ["a.nc"]
    back = rs.io.open_dataset(path)
    xr.testing.assert_equal(back, _ds())
    assert back.attrs["flag"] == 1  # bools stored as ints
    enc = back["pressure"].encoding
    assert enc["zlib"] and enc["complevel"] == 4
    assert back["distance"].attrs["units"] == "m"


def test_open_refuses_partial_and_missing(tmp_path):
    with pytest.raises(FileNotFoundError):
        rs.io.open_dataset(tmp_path / "nope.nc")
    partial = tmp_path / ".a.nc.tmp-1-2"
    partial.write_bytes(b"CDF")
    with pytest.raises(ValueError, match="temporary file"):
        rs.io.open_dataset(partial)
    with pytest.raises(FileNotFoundError, match="manifest"):
        rs.ensemble.open_ensemble(tmp_path)
    with pytest.raises(ValueError, match="open_ensemble"):
        rs.io.open_dataset(tmp_path)
    with pytest.raises(FileNotFoundError, match="does not exist"):
        nc.write(_ds(), tmp_path / "sub" / "a.nc", compute=True)


def test_write_refuses_an_existing_file_unless_overwrite(tmp_path):
    """rs.io.write replaced an unrelated file without a word (the command line refuses it)."""
    path = tmp_path / "a.nc"
    path.write_text("my notes")
    for compute in (True, False):  # refused when called, before anything is written
        with pytest.raises(FileExistsError, match=r"a\.nc' exists \(a file\); write refuses to replace it: "
                                                  r"pass overwrite=True"):
            rs.io.write(_ds(), path, compute=compute)
    assert path.read_text() == "my notes" and [p.name for p in tmp_path.iterdir()] == ["a.nc"]
    with pytest.raises(FileExistsError, match=r"exists \(a folder\)"):
        rs.io.write(_ds(), tmp_path, compute=True)
    rs.io.write(_ds(), path, compute=True, overwrite=True)
    xr.testing.assert_equal(rs.io.open_dataset(path), _ds())
