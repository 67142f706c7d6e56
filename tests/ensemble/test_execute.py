"""Tests of roughstick.ensemble.execute: schedulers, progress, auto-n, a LocalCluster."""

from __future__ import annotations

import json
import time

import pytest
from ensemble_toys import RH, assert_same_values, toy_run

import roughstick as rs


def test_unreachable_scheduler_fails_fast(tmp_path):
    for kw in ({"n": "auto", "n_max": 2, "batch": 2}, {"n": 2, "output": tmp_path / "run"}):
        t0 = time.perf_counter()
        with pytest.raises(ConnectionError, match="could not connect to the dask scheduler"):
            toy_run(scheduler="tcp://127.0.0.1:9", connect_timeout=1, **kw)
        assert time.perf_counter() - t0 < 15


def test_bad_scheduler_name():
    with pytest.raises(ValueError, match="scheduler must be"):
        toy_run(n="auto", n_max=2, batch=2, scheduler="gpu")


def test_progress_quiet_when_not_interactive(monkeypatch, capsys):
    from roughstick._core.progress import interactive

    monkeypatch.setenv("CI", "true")
    assert not interactive()
    toy_run(n="auto", n_max=4, batch=2)
    assert capsys.readouterr().err == ""
    monkeypatch.delenv("CI")
    toy_run(n="auto", n_max=4, batch=2, progress=True)
    assert "block" in capsys.readouterr().err


def test_auto_n_stops_and_matches_fixed_n():
    ds = toy_run(n="auto", batch=4, target_precision=0.05, n_max=24, chunks=4)
    n = ds.attrs["n_final"]
    assert ds.sizes["realization"] == n and 12 <= n <= 24
    assert "moves by less than 0.05" in ds.attrs["auto_stopping_rule"]
    changes = json.loads(ds.attrs["auto_band_changes"])
    if ds.attrs["auto_converged"]:
        assert all(c < 0.05 for _, c in changes[-2:])
    fixed = toy_run(n=n, chunks=4, distance=ds.distance.values).compute()
    assert_same_values(fixed, ds)


def test_local_cluster_processes_bit_identical(tmp_path):
    """The real pipeline on a LocalCluster of two worker processes = threads = other chunking."""
    distributed = pytest.importorskip("distributed")

    run = dict(n=6, shape=64, spacing=5e-9, relative_humidity=RH, seed=11, model="modified_dmt")
    psd = rs.datasets.sample_psd("S2")
    threaded = rs.ensemble.run(psd, chunks=2, **run).compute(scheduler="threads")
    other_chunks = rs.ensemble.run(psd, chunks=5, **run).compute(scheduler="sync")
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        on_cluster = rs.ensemble.run(psd, chunks=3, **run).compute(scheduler=client)
        streamed = rs.ensemble.run(psd, chunks=2, output=tmp_path / "c",
                                   scheduler=cluster.scheduler_address, **run)
        streamed = streamed.compute(scheduler="sync")
    assert_same_values(threaded, on_cluster)
    assert_same_values(threaded, other_chunks)
    assert_same_values(threaded, streamed)


def test_auto_converged_saved_in_the_run_folder(tmp_path):
    """An auto run stopped at n_max unconverged must not look like a converged one on disk."""
    ds = toy_run(n="auto", batch=2, target_precision=1e-9, n_max=4, chunks=2, output=tmp_path / "run")
    assert ds.attrs["auto_converged"] == 0
    reopened = rs.ensemble.open_ensemble(tmp_path / "run")
    assert reopened.attrs["auto_converged"] == 0 and reopened.attrs["n_final"] == 4
    band = rs.ensemble.confidence_band(reopened[["adhesive_energy"]])
    assert band.attrs["auto_converged"] == 0


def test_an_active_client_is_the_default_scheduler(tmp_path):
    """As for any dask computation, an active distributed.Client runs run_ensemble(output=...)'s
    blocks without scheduler=; the numbers are those of local threads, and the client stays open."""
    distributed = pytest.importorskip("distributed")

    run = dict(n=4, chunks=2, rh=RH[:2])
    local = toy_run(output=tmp_path / "threads", **run).compute(scheduler="sync")
    with distributed.LocalCluster(n_workers=1, processes=False, threads_per_worker=2,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        with distributed.get_task_stream(client) as stream:
            on_client = toy_run(output=tmp_path / "client", **run)
        blocks = [t["key"] for t in stream.data if str(t["key"]).startswith("roughstick-ensemble-block")]
        assert len(blocks) == 2  # both blocks ran on the client's worker
        assert client.submit(sum, [1, 2]).result() == 3  # not closed by roughstick
    assert_same_values(local, on_client.compute(scheduler="sync"))
