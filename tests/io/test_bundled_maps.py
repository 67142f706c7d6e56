"""The sample maps shipped in the package are named ``bundled:S1A`` ... wherever a map path is
accepted; a real file of that name wins; an unknown name lists the bundled ones."""

from __future__ import annotations

import os

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.io.afm import BUNDLED_MAPS, resolve_map_path


def test_bundled_name_reads_the_packaged_sample():
    # load_sample keeps the raw heights; read_afm levels them by default, as every command does
    xr.testing.assert_identical(rs.io.read_afm("bundled:S2C", levelling="none"), rs.datasets.load_sample("S2C"))
    xr.testing.assert_allclose(rs.io.read_afm("bundled:S2C").drop_attrs(),
                               rs.datasets.sample_maps("S2").sel(map="S2C", drop=True).drop_attrs(),
                               rtol=0, atol=1e-20)
    assert resolve_map_path("bundled:s1a") == rs.datasets.sample_path("S1A")  # case ignored
    assert resolve_map_path("bundled:S1A.nc") == rs.datasets.sample_path("S1A")
    assert rs.datasets.SAMPLES == BUNDLED_MAPS


def test_unknown_bundled_name_lists_the_bundled_names():
    with pytest.raises(ValueError, match="unknown bundled map 'bundled:S3A'") as err:
        rs.io.read_afm("bundled:S3A")
    assert all(f"bundled:{n}" in str(err.value) for n in BUNDLED_MAPS)


def test_bare_sample_name_that_is_no_file_names_the_bundled_spelling(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(FileNotFoundError, match="named bundled:S1B"):
        rs.io.read_afm("S1B")
    with pytest.raises(FileNotFoundError) as err:
        rs.io.read_afm("some/dir/S1B.nc")  # a path, not a name: no hint
    assert "bundled" not in str(err.value)


@pytest.mark.skipif(os.name == "nt", reason="':' is not allowed in Windows file names")
def test_a_real_file_of_that_name_wins(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    h = rs.testing.make_topography(np.arange(64.0).reshape(8, 8) * 1e-10, spacing=5e-9)
    h.to_netcdf(tmp_path / "bundled:S1A.nc")
    assert rs.io.read_afm("bundled:S1A.nc").shape == (8, 8)  # the local file, not the 1024² sample
    assert str(resolve_map_path("bundled:S1A.nc")) == "bundled:S1A.nc"
