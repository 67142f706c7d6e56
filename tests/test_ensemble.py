"""Tests of roughstick.ensemble: laziness, chunk/scheduler invariance, streaming+resume, bands.

The pipeline is tested twice: with small *stand-in* functions defined here (a toy surface
generator and a toy contact model, so the ensemble machinery is tested on its own), and with the
real generate_surfaces / rough_contact_curves / adhesion_summary (the §4.3 findings).
"""

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

import roughstick as rs
from roughstick._core.conventions import ATTRS
from roughstick._core.dask import is_lazy, realization_rng
from roughstick.testing import raise_if_dask_computes

# ----------------------------------------------------------------------------- stand-ins
SIGMA = 4e-9  # rms height of the toy surfaces [m]


def toy_psd(sigma=SIGMA, n=16, spacing=5e-9):
    """A flat (white) 2-D PSD with variance sigma**2 on an n x n grid (architecture.md normalisation)."""
    q = np.fft.fftshift(np.fft.fftfreq(n, spacing)) * 2 * np.pi
    dq = q[1] - q[0]
    s = np.full((n, n), sigma**2 / (n * n * dq * dq))
    return xr.DataArray(s, dims=("qy", "qx"), coords={"qy": q, "qx": q}, name="psd",
                        attrs=dict(ATTRS["psd"]))


def toy_generate(psd, *, n, shape, spacing, seed, chunks=None, **kw):
    """Smoothed Gaussian noise, realization k from realization_rng(seed, k); heights sum to zero."""
    m0 = float(psd.sum()) * float(psd.qx[1] - psd.qx[0]) ** 2
    out = np.empty((n,) + tuple(shape))
    for k in range(n):
        z = realization_rng(seed, k).standard_normal(shape)
        z = (z + np.roll(z, 1, 0) + np.roll(z, 1, 1) + np.roll(z, (1, 1), (0, 1))) / 2
        z -= z.mean()
        out[k] = z * np.sqrt(m0)
    h = rs.testing.make_topography(out, spacing=spacing, periodic=True).rename({"dim_0": "realization"})
    return h.assign_coords(realization=np.arange(n)).chunk({"realization": chunks or n})


def toy_curves(height, *, relative_humidity, distance, material=None, adsorbed_layer="paper", **kw):
    """A monotone toy of Eq. 16: linear 'Hertz' on the interference plus Laplace pressure on the wet area."""
    rh = rs.as_relative_humidity(relative_humidity)
    hw = rs.water_height(rh, adsorbed_layer=adsorbed_layer)
    dp = rs.laplace_pressure(rh)
    z = height.stack(p=("y", "x"))
    contact = (z >= distance).mean("p")
    wet = (z >= distance - hw).mean("p") - contact
    rep = 2e11 * np.maximum(z - distance, 0).mean("p") / 1e-8
    ds = xr.Dataset({
        "pressure": rep + dp * wet,
        "repulsive_pressure": rep + 0 * rh,
        "wet_fraction": wet,
        "contact_fraction": contact + 0 * rh,
        "n_contacts": ((z >= distance).sum("p") + 0 * rh).astype(np.int64),
    })
    for v in ds.data_vars:
        ds[v].attrs = dict(ATTRS[v])
    return ds.transpose("realization", "rh", "distance")


def toy_summary(curves):
    p = curves["pressure"]
    d = curves["distance"]
    neg = np.minimum(p, 0)
    gamma = -neg.integrate("distance")
    eq = d.where((p.shift(distance=1) > 0) & (p <= 0)).max("distance")  # approx: sign change
    out = xr.Dataset({
        "adhesive_energy": gamma.assign_attrs(ATTRS["surface_adhesive_energy"]),
        "pull_off_pressure": (-neg.min("distance")).assign_attrs(ATTRS["pull_off_pressure"]),
        "equilibrium_distance": eq.assign_attrs(ATTRS["equilibrium_distance"]),
    })
    return out


TOY = dict(generate=toy_generate, curves=toy_curves, summary=toy_summary)
RH = [0.3, 0.5, 0.7, 0.9]


def toy_run(n=6, shape=(16, 16), chunks=2, **kw):
    kw = {**TOY, **kw}
    return rs.run_ensemble(toy_psd(), n=n, shape=shape, spacing=5e-9, relative_humidity=kw.pop("rh", RH),
                           seed=kw.pop("seed", 3), chunks=chunks, **kw)


def values(ds):
    return {v: ds[v].values for v in ds.data_vars}


def assert_same_values(a, b):
    assert sorted(a.data_vars) == sorted(b.data_vars)
    for v in a.data_vars:
        np.testing.assert_array_equal(a[v].values, b[v].transpose(*a[v].dims).values, err_msg=v)
    for c in ("realization", "rh", "distance"):
        np.testing.assert_array_equal(a[c].values, b[c].values)


# ----------------------------------------------------------------------------- lazy pipeline
def test_lazy_nothing_computed_and_layout():
    with raise_if_dask_computes():
        ds = toy_run(n=7, chunks=3)
    assert is_lazy(ds)
    assert ds["pressure"].dims == ("realization", "rh", "distance")
    assert ds["adhesive_energy"].dims == ("realization", "rh")
    assert ds["max_height"].dims == ("realization",)
    assert ds.chunksizes["realization"] == (3, 3, 1)
    assert ds.chunksizes["rh"] == (4,)
    assert ds.chunksizes["distance"] == (ds.sizes["distance"],) and ds.sizes["distance"] >= 100
    for name in list(ds.variables):
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs, name
    assert ds.attrs["Conventions"] == "CF-1.10"
    assert ds.attrs["seed"] == "3" and ds.attrs["n_realizations"] == 7
    np.testing.assert_array_equal(ds.rh.values, RH)


def test_results_independent_of_chunking_and_equal_to_single_realization():
    a = toy_run(n=6, chunks=2).compute()
    b = toy_run(n=6, chunks=4).compute(scheduler="sync")
    assert_same_values(a, b)
    # humidity blocks: the same numbers up to rounding (the curves function sees fewer humidities)
    c = toy_run(n=6, chunks={"realization": 4, "rh": 1}).compute()
    assert c.chunksizes == {} and toy_run(n=6, chunks={"realization": 4, "rh": 1}).chunksizes["rh"] == (1,) * 4
    xr.testing.assert_allclose(a.reset_coords(drop=True), c.reset_coords(drop=True), rtol=1e-13)
    # realization 4 on its own, directly from the stand-in functions
    h = toy_generate(toy_psd(), n=5, shape=(16, 16), spacing=5e-9,
                     seed=np.random.SeedSequence(3)).isel(realization=[4]).compute()
    c = toy_curves(h, relative_humidity=RH, distance=a.distance)
    np.testing.assert_array_equal(c.pressure.values[0], a.pressure.sel(realization=4).values)
    np.testing.assert_allclose(a.max_height.values[4], float(h.max() - h.mean()), rtol=1e-15)


def test_rh_chunk_blocks_and_seed_changes_results():
    a = toy_run(n=3, chunks=1, seed=1).compute()
    b = toy_run(n=3, chunks=1, seed=2).compute()
    assert not np.array_equal(a.pressure.values, b.pressure.values)


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"n": 0}, "at least 1"),
        ({"n": -3}, "at least 1"),
        ({"n": "many"}, "positive integer or 'auto'"),
        ({"n": 2.5}, "positive integer"),
        ({"rh": []}, "relative_humidity is empty"),
        ({"rh": [0.3, 1.2]}, "between 0 and 1"),
        ({"rh": [0.3, 0.3]}, "repeated"),
        ({"chunks": 0}, "chunks must be positive"),
    ],
)
def test_bad_input(kw, match):
    with pytest.raises(ValueError, match=match):
        toy_run(**{"n": 4, **kw})


def test_bad_shapes():
    with pytest.raises(ValueError, match="exactly one of shape"):
        rs.run_ensemble(toy_psd(), n=2, shape=16, size=1e-6, spacing=5e-9, relative_humidity=RH, **TOY)
    with pytest.raises(ValueError, match="whole number of pixels"):
        rs.run_ensemble(toy_psd(), n=2, size=1.003e-7, spacing=5e-9, relative_humidity=RH, **TOY)
    with pytest.raises(ValueError, match="shape"):
        rs.run_ensemble(toy_psd(), n=2, shape=(2, 16), spacing=5e-9, relative_humidity=RH, **TOY)
    with pytest.raises(TypeError, match="DataArray"):
        rs.run_ensemble(np.ones((4, 4)), n=2, shape=16, spacing=5e-9, relative_humidity=RH, **TOY)


def test_distance_grid_covers_highest_point_and_bottom_check():
    ds = toy_run(n=6).compute()
    top = float(ds.max_height.max()) + float(rs.water_height(max(RH)))
    assert top < float(ds.distance.max())
    # every curve crosses from attractive to repulsive on the grid
    assert bool((ds.pressure.isel(distance=0) > 0).all())
    # a grid too low at the top is detected, with the fix in the message
    with pytest.raises(ValueError, match="above the top of the common distance grid"):
        toy_run(n=2, distance=np.linspace(0, 2 * SIGMA, 50)).compute()
    with pytest.raises(ValueError, match="still attractive"):
        toy_run(n=2, distance=np.linspace(5 * SIGMA, 12 * SIGMA, 50)).compute()


def test_gamma_converges_with_distance_grid_toy():
    """Γ (Eq. 13) on ensemble_distance_grid: the error against a 3200-point grid shrinks with num.

    The toy's wetted area is a step function of d (16 x 16 pixels), so convergence is O(step).
    """
    g = {}
    for num in (100, 400, 1600, 3200):
        d = rs.ensemble_distance_grid(toy_psd(), shape=(16, 16), n=4, relative_humidity=RH, num=num)
        g[num] = toy_run(n=4, distance=d).adhesive_energy.values
    err = {k: np.mean(np.abs(g[k] / g[3200] - 1)) for k in (100, 400, 1600)}
    assert err[1600] < err[400] < err[100]
    assert err[1600] < 0.01


# ----------------------------------------------------------------------------- execution
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
    from roughstick.ensemble import _interactive

    monkeypatch.setenv("CI", "true")
    assert not _interactive()
    toy_run(n="auto", n_max=4, batch=2)
    assert capsys.readouterr().err == ""
    monkeypatch.delenv("CI")
    toy_run(n="auto", n_max=4, batch=2, progress=True)
    assert "block" in capsys.readouterr().err


def test_auto_n_stops_and_matches_fixed_n():
    ds = toy_run(n="auto", batch=4, tolerance=0.05, n_max=24, chunks=4)
    n = ds.attrs["n_final"]
    assert ds.sizes["realization"] == n and 12 <= n <= 24
    assert "moves by less than 0.05" in ds.attrs["auto_stopping_rule"]
    changes = json.loads(ds.attrs["auto_band_changes"])
    if ds.attrs["auto_converged"]:
        assert all(c < 0.05 for _, c in changes[-2:])
    fixed = toy_run(n=n, chunks=4, distance=ds.distance.values).compute()
    assert_same_values(fixed, ds)


# ----------------------------------------------------------------------------- streaming
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
        rs.open_ensemble(folder)
    part = rs.open_ensemble(folder, allow_incomplete=True)
    assert part.attrs["incomplete"]
    out = toy_run(n=6, chunks=2, output=folder)
    assert_same_values(full, out.compute())
    assert not any(".tmp-" in p.name for p in folder.iterdir())


SCRIPT = textwrap.dedent(
    """
    import sys, time
    sys.path.insert(0, {tests!r})
    import test_ensemble as T
    import roughstick as rs

    def slow_curves(height, **kw):
        time.sleep(0.25)
        return T.toy_curves(height, **kw)

    slow_curves.__qualname__ = "slow_curves"
    rs.run_ensemble(T.toy_psd(), n=16, shape=(16, 16), spacing=5e-9, relative_humidity=T.RH, seed=5,
                    chunks=2, generate=T.toy_generate, curves=slow_curves, summary=T.toy_summary,
                    output={out!r}, scheduler="threads", progress=False)
    print("done")
    """
)


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
        rs.open_ensemble(folder)
    res = subprocess.run([sys.executable, str(script)], env=env, capture_output=True, text=True,
                         timeout=120)
    assert res.returncode == 0, res.stderr
    resumed = rs.open_ensemble(folder).compute()
    uninterrupted = toy_run(n=16, shape=(16, 16), chunks=2, seed=5).compute()
    assert_same_values(uninterrupted, resumed)


def test_local_cluster_processes_bit_identical(tmp_path):
    """The real pipeline on a LocalCluster of two worker processes = threads = other chunking."""
    distributed = pytest.importorskip("distributed")
    from roughstick.demos.s50_ensemble import sample_psd

    run = dict(n=6, shape=64, spacing=5e-9, relative_humidity=RH, seed=11)
    psd = sample_psd("S2")
    threaded = rs.run_ensemble(psd, chunks=2, **run).compute(scheduler="threads")
    other_chunks = rs.run_ensemble(psd, chunks=5, **run).compute(scheduler="sync")
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        on_cluster = rs.run_ensemble(psd, chunks=3, **run).compute(scheduler=client)
        streamed = rs.run_ensemble(psd, chunks=2, output=tmp_path / "c",
                                   scheduler=cluster.scheduler_address, **run)
        streamed = streamed.compute(scheduler="sync")
    assert_same_values(threaded, on_cluster)
    assert_same_values(threaded, other_chunks)
    assert_same_values(threaded, streamed)


# ----------------------------------------------------------------------------- bands
def _sample(n=400, seed=0):
    rng = np.random.default_rng(seed)
    return xr.DataArray(rng.lognormal(size=(n, 3)), dims=("realization", "rh"),
                        coords={"rh": [0.3, 0.5, 0.9]}, name="adhesive_energy",
                        attrs=dict(ATTRS["surface_adhesive_energy"]))


def test_confidence_band_values_and_metadata(backend):
    x = backend(_sample(), chunks={"realization": 50})
    with raise_if_dask_computes():
        b = rs.confidence_band(x, level=0.9)
    ref = np.quantile(_sample().values, [0.05, 0.5, 0.95], axis=0)
    np.testing.assert_allclose(b.adhesive_energy.values, ref, rtol=1e-12)
    np.testing.assert_allclose(b.adhesive_energy_mean.values, _sample().mean("realization").values)
    np.testing.assert_allclose(b.adhesive_energy_mean_stderr.values,
                               _sample().std("realization", ddof=1).values / np.sqrt(400))
    assert b.adhesive_energy.dims == ("quantile", "rh")
    assert b.adhesive_energy.attrs["units"] == "J m-2"
    assert b["quantile"].attrs["units"] == "1"
    assert b.attrs["n_samples"] == 400 and b.attrs["level"] == 0.9
    assert (b.adhesive_energy_ci_lower <= b.adhesive_energy).all()
    assert (b.adhesive_energy_ci_upper >= b.adhesive_energy).all()


def test_band_independent_of_chunking():
    a = rs.confidence_band(_sample().chunk({"realization": 7})).compute()
    b = rs.confidence_band(_sample()).compute()
    xr.testing.assert_allclose(a, b, rtol=1e-14)


def test_order_statistic_interval_covers_true_quantile():
    """Coverage of the distribution-free interval of the median and of the 90 % quantile."""
    from scipy.stats import binom, norm

    n, trials = 60, 3000
    rng = np.random.default_rng(1)
    x = xr.DataArray(rng.standard_normal((trials, n)), dims=("trial", "realization"))
    lo, hi = rs.quantile_interval(x, [0.5, 0.9], confidence=0.95)
    for k, p in enumerate([0.5, 0.9]):
        truth = norm.ppf(p)
        cover = float(((lo[k] <= truth) & (truth <= hi[k])).mean())
        r = int(binom.ppf(0.025, n, p))
        s = int(binom.ppf(0.975, n, p)) + 1
        exact = binom.cdf(s - 1, n, p) - binom.cdf(r - 1, n, p)
        assert exact >= 0.95
        assert abs(cover - exact) < 3 * np.sqrt(exact * (1 - exact) / trials) + 1e-3


def test_interval_unbounded_when_n_too_small():
    x = xr.DataArray(np.arange(10.0), dims="realization")
    lo, hi = rs.quantile_interval(x, [0.025, 0.975])
    assert np.isneginf(lo[0]) and np.isposinf(hi[1])


def test_bootstrap_seeded_and_comparable():
    x = _sample(300)
    a = rs.quantile_interval(x, [0.5], method="bootstrap", rng=4, n_bootstrap=200)
    b = rs.quantile_interval(x.chunk({"rh": 1}), [0.5], method="bootstrap", rng=4, n_bootstrap=200)
    xr.testing.assert_identical(a[0], b[0].compute())
    o = rs.quantile_interval(x, [0.5])
    w_boot = (a[1] - a[0]).values
    w_os = (o[1] - o[0]).values
    assert np.all(w_boot > 0.4 * w_os) and np.all(w_boot < 2.5 * w_os)
    with pytest.raises(ValueError, match="method"):
        rs.quantile_interval(x, [0.5], method="jackknife")


def test_histogram_and_ecdf(backend):
    raw = _sample()
    x = backend(raw, chunks={"realization": 100})
    h = rs.ensemble_histogram(x, bins=20, range=(0, 10))
    ref = np.histogram(raw.values[:, 1], bins=20, range=(0, 10), density=True)[0]
    np.testing.assert_allclose(h.sel(rh=0.5).values, ref)
    assert h.dims == ("rh", "bin") and h.attrs["units"] == "J-1 m2"
    assert h.bin_upper.values[-1] == 10
    e = rs.ensemble_ecdf(x)
    np.testing.assert_array_equal(e.values, np.sort(raw.values, axis=0).T)
    assert e.cumulative_probability.values[-1] == 1.0
    assert e.dims == ("rh", "cumulative_probability")
    if backend.kind == "dask":
        with pytest.raises(ValueError, match="range"):
            rs.ensemble_histogram(x, bins=10)


def test_surface_size_study_shares_grid():
    ds = rs.surface_size_study(toy_psd(), shapes=[(16, 16), (32, 32)], spacing=5e-9, n=3,
                               relative_humidity=RH, chunks=3, **TOY)
    assert ds.adhesive_energy.dims == ("surface_size", "realization", "rh")
    np.testing.assert_allclose(ds.surface_size.values, [80e-9, 160e-9])
    assert ds.surface_size.attrs["units"] == "m"
    ds = ds.compute()
    assert np.isfinite(ds.adhesive_energy.values).all()


# ----------------------------------------------------------------------------- the real pipeline
RH6 = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]


@pytest.fixture(scope="module")
def sample_psds():
    from roughstick.demos.s50_ensemble import sample_psd

    return {s: sample_psd(s) for s in ("S1", "S2")}


def test_real_pipeline_layout_and_single_realization(sample_psds):
    psd = sample_psds["S2"]
    with raise_if_dask_computes():
        ds = rs.run_ensemble(psd, n=3, shape=64, spacing=5e-9, relative_humidity=RH6, seed=9, chunks=2)
    for v in ("pressure", "wet_fraction", "contact_fraction", "n_contacts", "fit_error"):
        assert ds[v].dims == ("realization", "rh", "distance"), v
    for v in ("adhesive_energy", "pull_off_pressure", "equilibrium_distance"):
        assert ds[v].dims == ("realization", "rh"), v
    ds = ds.compute()
    # realization 2 regenerated alone and run through the public functions directly
    h = rs.generate_surfaces(psd, realizations=[2], shape=64, spacing=5e-9, seed=9).compute()
    c = rs.rough_contact_curves(h, relative_humidity=RH6, distance=ds.distance)
    s = rs.adhesion_summary(c)
    np.testing.assert_array_equal(c.pressure.isel(realization=0).transpose("rh", "distance").values,
                                  ds.pressure.sel(realization=2).values)
    np.testing.assert_array_equal(s.adhesive_energy.isel(realization=0).values,
                                  ds.adhesive_energy.sel(realization=2).values)
    assert (ds.adhesive_energy > 0).all() and np.isfinite(ds.equilibrium_distance).all()


def test_real_gamma_converges_on_default_grid(sample_psds):
    """Γ on the default grid (step = h_water(30 %)/10) against a 4x finer grid."""
    for name, psd in sample_psds.items():
        kw = dict(shape=(128, 128), n=4, relative_humidity=RH6)
        coarse = rs.ensemble_distance_grid(psd, **kw)
        fine = rs.ensemble_distance_grid(psd, points_per_water_height=40, **kw)
        assert fine.size > 3.5 * coarse.size
        run = dict(n=4, shape=128, spacing=5e-9, relative_humidity=RH6, seed=4, chunks=4)
        g0 = rs.run_ensemble(psd, distance=coarse, **run).adhesive_energy.values
        g1 = rs.run_ensemble(psd, distance=fine, **run).adhesive_energy.values
        err = np.abs(g0 / g1 - 1)
        assert np.median(err) < 0.01, (name, err)
        assert err.max() < 0.06, (name, err)


def _findings(psd, n, seed):
    ds = rs.surface_size_study(psd, shapes=[128, 256], spacing=5e-9, n=n, relative_humidity=[0.3, 0.9],
                               seed=seed, chunks=8).compute()
    g = ds.adhesive_energy
    mean, sd = g.mean("realization"), g.std("realization", ddof=1)
    cv = sd / mean
    lo, hi = 0.3, 0.9
    small, large = 128 * 5e-9, 256 * 5e-9
    # scatter (relative) larger at low RH than at high RH, at both sizes
    assert (cv.sel(rh=lo) > 1.5 * cv.sel(rh=hi)).all(), cv.values
    # larger surfaces: lower mean Γ at low RH, by several standard errors
    se = np.hypot(sd.sel(rh=lo, surface_size=small), sd.sel(rh=lo, surface_size=large)) / np.sqrt(n)
    drop = mean.sel(rh=lo, surface_size=small) - mean.sel(rh=lo, surface_size=large)
    assert drop > 3 * se, (float(drop), float(se))
    # larger surfaces: narrower band (standard deviation) at high RH
    assert sd.sel(rh=hi, surface_size=large) < 0.8 * sd.sel(rh=hi, surface_size=small), sd.values


def test_section_4_3_findings_S2(sample_psds):
    _findings(sample_psds["S2"], n=32, seed=3)


@pytest.mark.slow
def test_section_4_3_findings_S1(sample_psds):
    _findings(sample_psds["S1"], n=48, seed=3)


def test_auto_n_streams_to_folder(tmp_path):
    ds = toy_run(n="auto", batch=4, tolerance=1e-9, n_max=8, chunks=2, output=tmp_path / "a")
    assert ds.attrs["n_final"] == 8 and not ds.attrs["auto_converged"]
    m = json.loads((tmp_path / "a" / "manifest.json").read_text())
    assert m["complete"] and m["n"] == 8 and len(m["completed"]) == 4
    assert_same_values(toy_run(n=8, chunks=2, distance=ds.distance.values).compute(), ds)
