"""Tests of roughstick.ensemble.store: streaming, resume after a kill, manifests and block files."""

from __future__ import annotations

import json
import os
import pathlib
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest
import xarray as xr
from ensemble_toys import (
    assert_same_values,
    toy_run,
)

import roughstick as rs
from roughstick.ensemble import store
from roughstick.io import netcdf as nc

SCRIPT = textwrap.dedent(
    """
    import sys, time
    sys.path.insert(0, {tests!r})
    import dask
    import ensemble_toys as T
    import roughstick as rs

    # one block at a time: on a machine with >= 8 cores all 8 blocks would finish together and
    # the kill could not land midway
    dask.config.set(num_workers=1)

    def slow_curves(height, **kw):
        time.sleep(0.25)
        return T.toy_curves(height, **kw)

    slow_curves.__qualname__ = "slow_curves"
    rs.ensemble.run(T.toy_psd(), n=16, shape=(16, 16), spacing=5e-9, relative_humidity=T.RH, seed=5,
                    chunks=2, generate=T.toy_generate, curves=slow_curves, summary=T.toy_summary,
                    output={out!r}, scheduler="threads", progress=False)
    print("done")
    """
)


def test_stream_then_open_equals_lazy(tmp_path):
    lazy = toy_run(n=5, chunks=2).compute()
    out = toy_run(n=5, chunks=2, output=tmp_path / "run")
    assert_same_values(lazy, out.compute())
    for v in out.variables:
        assert out[v].attrs["units"] == lazy[v].attrs["units"], v
    assert out.attrs["params_hash"] == lazy.attrs["params_hash"]
    files = sorted(p.name for p in (tmp_path / "run").iterdir())
    assert files == ["block-r00000-h000.nc", "block-r00001-h000.nc", "block-r00002-h000.nc",
                     "manifest.json"]
    m = json.loads((tmp_path / "run" / "manifest.json").read_text())
    assert m["complete"] and len(m["completed"]) == 3
    # a second call with the same parameters computes nothing (resume of a finished run)
    again = toy_run(n=5, chunks=2, output=tmp_path / "run")
    assert_same_values(lazy, again.compute())


def test_stream_refuses_other_parameters_and_overwrite(tmp_path):
    toy_run(n=2, chunks=2, output=tmp_path / "run")
    with pytest.raises(FileExistsError, match="different parameters.*overwrite"):
        toy_run(n=2, chunks=2, seed=99, output=tmp_path / "run")
    out = toy_run(n=2, chunks=2, seed=99, output=tmp_path / "run", overwrite=True)
    assert out.attrs["seed"] == "99"
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "notes.txt").write_text("mine")
    with pytest.raises(FileExistsError, match="not empty"):
        toy_run(n=2, output=tmp_path / "other")


def test_resume_ignores_partial_and_corrupt_blocks(tmp_path):
    folder = tmp_path / "run"
    full = toy_run(n=6, chunks=2).compute()
    toy_run(n=6, chunks=2, output=folder)
    # simulate an interruption: one block lost, a half-written temp file, a corrupt final file
    (folder / "block-r00001-h000.nc").unlink()
    (folder / ".block-r00001-h000.nc.tmp-123-456").write_bytes(b"CDF\x01partial")
    (folder / "block-r00002-h000.nc").write_bytes(b"CDF\x01garbage")
    with pytest.raises(ValueError, match="incomplete.*Resume"):
        rs.ensemble.open_ensemble(folder)
    part = rs.ensemble.open_ensemble(folder, allow_incomplete=True)
    assert part.attrs["incomplete"]
    out = toy_run(n=6, chunks=2, output=folder)
    assert_same_values(full, out.compute())
    assert not any(".tmp-" in p.name for p in folder.iterdir())


def test_killed_subprocess_resumes_bit_identical(tmp_path):
    folder = tmp_path / "run"
    script = tmp_path / "run.py"
    script.write_text(SCRIPT.format(tests=str(pathlib.Path(__file__).parent), out=str(folder)))
    env = {**os.environ, "CI": "true"}
    proc = subprocess.Popen([sys.executable, str(script)], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    t0 = time.time()
    while time.time() - t0 < 60:
        if folder.exists() and len(list(folder.glob("block-*.nc"))) >= 2:
            break
        if proc.poll() is not None:
            break
        time.sleep(0.05)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    written = len(list(folder.glob("block-*.nc")))
    assert 2 <= written < 8, "the kill must land midway"
    with pytest.raises(ValueError, match="incomplete"):
        rs.ensemble.open_ensemble(folder)
    res = subprocess.run([sys.executable, str(script)], env=env, capture_output=True, text=True,
                         timeout=120)
    assert res.returncode == 0, res.stderr
    resumed = rs.ensemble.open_ensemble(folder).compute()
    uninterrupted = toy_run(n=16, shape=(16, 16), chunks=2, seed=5).compute()
    assert_same_values(uninterrupted, resumed)


def test_auto_n_streams_to_folder(tmp_path):
    ds = toy_run(n="auto", batch=4, target_precision=1e-9, n_max=8, chunks=2, output=tmp_path / "a")
    assert ds.attrs["n_final"] == 8 and not ds.attrs["auto_converged"]
    m = json.loads((tmp_path / "a" / "manifest.json").read_text())
    assert m["complete"] and m["n"] == 8 and len(m["completed"]) == 4
    assert_same_values(toy_run(n=8, chunks=2, distance=ds.distance.values).compute(), ds)


def test_manifest_roundtrip_and_block_validation(tmp_path):
    m = {"format": store.MANIFEST_FORMAT, "params_hash": "abc", "realization_chunks": [[0, 3]],
         "rh_chunks": [[0, 1]], "attrs": {"title": "x"}}
    store.write_manifest(tmp_path, m)
    assert store.read_manifest(tmp_path) == m
    (tmp_path / "manifest.json").write_text(json.dumps({"format": "other"}))
    with pytest.raises(ValueError, match="not a roughstick ensemble manifest"):
        store.read_manifest(tmp_path)
    d = xr.Dataset({"pressure": ("distance", np.arange(4.0), {"units": "Pa", "long_name": "p"})},
                   coords={"distance": ("distance", np.linspace(1e-9, 4e-9, 4), {"units": "m", "long_name": "d"})})
    d.attrs = {"roughstick_params_hash": "abc", "roughstick_block_realization": 0,
               "roughstick_block_rh": 0, "roughstick_block_complete": 1}
    nc.write(d, tmp_path / store.block_name(0, 0), compute=True)
    assert store.valid_block(tmp_path / store.block_name(0, 0), params_hash="abc", block=(0, 0))
    assert not store.valid_block(tmp_path / store.block_name(0, 0), params_hash="xyz", block=(0, 0))
    assert not store.valid_block(tmp_path / store.block_name(0, 0), params_hash="abc", block=(1, 0))
    (tmp_path / "junk.nc").write_bytes(b"\x89HDF garbage")
    assert not store.valid_block(tmp_path / "junk.nc", params_hash="abc", block=(0, 0))
