"""FFT boundary-element model after its speed-up : same answers as a tight
solve, fewer FFT pairs than the kernels before it, and the pieces that make it cheaper (direct
sums of the kernel, incremental gaps, the secant predictor) exact to rounding.

The kernels before the speed-up are the frozen copy benchmarks/_fft_bem_kernels_v0.py (the "old
default" and the old tight reference of benchmarks/bench_fft_bem_speed.py); the tests that use
them are skipped where that file is absent. Costs are counted (FFT pairs), not timed.
"""

from __future__ import annotations

import contextlib
import importlib
import importlib.util
import pathlib
import sys
import warnings

import numpy as np
import pytest

import roughstick as rs
from roughstick.contact.fft_bem import _kernels as K

FAMILIES = ("S1", "S2", "table4", "smooth", "rough")
RH = [0.3, 0.6, 0.9]
QUANT = ("adhesive_energy", "pull_off_pressure", "equilibrium_distance")
V0 = pathlib.Path(__file__).resolve().parents[2] / "benchmarks" / "_fft_bem_kernels_v0.py"


def summary(h, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = rs.contact.fft_bem_curves(h, relative_humidity=RH, **kw)
        s = rs.contact.summary(ds)
    return {q: s[q].values for q in QUANT}, int(ds.attrs["fft_calls"])


def worst(a, b):
    return {q: float(np.max(np.abs(a[q] / b[q] - 1))) for q in QUANT}


def kernels_v0():
    """The module of the kernels before the speed-up."""
    if not V0.exists():
        pytest.skip(f"{V0} (the kernels before the speed-up) is absent")
    name = "_fft_bem_kernels_v0"
    if name not in sys.modules:  # numba's cache finds the module by its name
        spec = importlib.util.spec_from_file_location(name, V0)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


@contextlib.contextmanager
def old_kernels():
    """The public model run on the kernels before the speed-up (swapped into its module)."""
    v0 = kernels_v0()
    mod = importlib.import_module("roughstick.contact.fft_bem._curves")
    names = [n for n, v in vars(mod).items() if getattr(v, "auto_curve", None) is K.auto_curve]
    assert names, "the wrapper's kernels module was not found"
    saved = {n: getattr(mod, n) for n in names}
    for n in names:
        setattr(mod, n, v0)
    try:
        yield
    finally:
        for n, v in saved.items():
            setattr(mod, n, v)


@pytest.mark.parametrize("n", [64, 96])
@pytest.mark.parametrize("family", FAMILIES)
def test_default_agrees_with_the_tight_solve(family, n):
    """Default call (tolerance 1e-3, single precision) against tolerance 1e-4 in double
    precision, RH 0.3/0.6/0.9: measured at most 0.13 % (Γ), 0.11 % (pull-off), 0.35 % (d_eq)."""
    h = rs.datasets.surface_family(family, shape=(n, n), seed=1)
    new, _ = summary(h)
    tight, _ = summary(h, solver_tolerance=1e-4, precision="double")
    err = worst(new, tight)
    assert err["adhesive_energy"] < 0.01, err
    assert err["pull_off_pressure"] < 0.01, err
    assert err["equilibrium_distance"] < 0.01, err


@pytest.mark.parametrize("n", [64, 96])
@pytest.mark.parametrize("family", FAMILIES)
def test_same_answers_and_a_fifth_of_the_fft_pairs_of_the_old_kernels(family, n):
    """Against the kernels before the speed-up: Γ, pull-off and d_eq within 1.5 %, 2 % and 0.5 % of
    their tight solve (measured at most 0.58 %, 0.43 %, 0.04 %; the old default call itself:
    0.40 %, 1.59 %, 0.03 %), with at most a fifth of the old default call's FFT pairs (measured
    0.00-0.18; the rest are direct sums of the kernel, counted apart)."""
    h = rs.datasets.surface_family(family, shape=(n, n), seed=1)
    new, new_ffts = summary(h)
    with old_kernels():
        _, old_ffts = summary(h)
        tight, _ = summary(h, solver_tolerance=1e-4, precision="double")
    err = worst(new, tight)
    assert err["adhesive_energy"] < 0.015, err
    assert err["pull_off_pressure"] < 0.02, err
    assert err["equilibrium_distance"] < 0.005, err
    assert new_ffts <= 0.2 * old_ffts, (new_ffts, old_ffts)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_direct_sums_are_the_fft_operator(dtype):
    """A traction on few pixels is summed from the real-space kernel: the same operator as the
    FFT pair, on odd and even, square and oblong grids, to rounding."""
    rng = np.random.default_rng(1)
    for shape in [(48, 40), (33, 65)]:
        direct = K.FFTGrid(shape, (5.0, 4.0), dtype)
        fft = K.FFTGrid(shape, (5.0, 4.0), dtype, sparse_max=0)
        for k in (1, 3, 4, 7, direct.sparse_max):
            a = np.zeros(shape, dtype)
            a.flat[rng.choice(a.size, k, replace=False)] = rng.standard_normal(k)
            u, ref = direct.displacement(a), fft.displacement(a)
            tol = 1e-6 if dtype == np.float32 else 1e-13
            np.testing.assert_allclose(u, ref, atol=tol * np.abs(ref).max())
            out = np.ones(shape, dtype)
            direct.add_displacement(a, out)
            np.testing.assert_allclose(out, 1 + ref, atol=tol * (1 + np.abs(ref).max()))
        assert direct.calls == 0 and direct.sparse_calls == 10
        assert fft.sparse_calls == 0


def test_states_carry_their_exact_gap():
    """A state's gap is updated by increments along the path (no transform of the whole
    traction); it stays the gap of its pressure and wet set: G[p - sigma0 1_W] + d - z."""
    h = rs.datasets.surface_family("table4", shape=(64, 64), seed=1)
    z = h.values / 1e-9
    s0 = abs(float(rs.contact.laplace_pressure(0.7))) / rs.materials.reduced_modulus()
    hw = float(rs.contact.water_height(0.7)) / 1e-9
    for dtype, tol in ((np.float64, 1e-9), (np.float32, 1e-4)):
        dd, states, grid = K.auto_curve(z, (5.0, 5.0), s0, hw, dtype=dtype)
        assert grid.sparse_calls > grid.calls  # most transforms were direct sums
        exact = K.FFTGrid(z.shape, (5.0, 5.0), np.float64, sparse_max=0)
        for st in states:
            g = exact.displacement(st["p"] - s0 * st["W"]) + (st["d"] - z)
            assert np.abs(st["g"] - g).max() < tol * np.std(z)
            np.testing.assert_array_equal(st["W"], st["g"] < dtype(hw))


def test_gaps_recomputed_from_the_traction_give_the_same_curve(monkeypatch):
    """MAX_AGE bounds the increments a gap may carry; recomputing every gap from its traction
    (MAX_AGE = 1) gives the same curve to the solver's tolerance."""
    h = rs.datasets.surface_family("smooth", shape=(64, 64), seed=1)
    ref, ref_ffts = summary(h)
    monkeypatch.setattr(K, "MAX_AGE", 1)
    fresh, fresh_ffts = summary(h)
    err = worst(fresh, ref)
    assert max(err.values()) < 0.01, err
    assert fresh_ffts > ref_ffts


def test_predictor_changes_the_path_not_the_answer(monkeypatch):
    """The secant predictor (two previous states extrapolated) and the plain continuation (the
    last state with its gaps opened) reach the same summaries to the tolerance, the predictor
    in fewer iterations."""
    h = rs.datasets.surface_family("smooth", shape=(96, 96), seed=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with_ = rs.contact.fft_bem_curves(h, relative_humidity=RH)
        monkeypatch.setattr(K, "PREDICT_MAX_RATIO", 0.0)
        without = rs.contact.fft_bem_curves(h, relative_humidity=RH)
    a, b = rs.contact.summary(with_), rs.contact.summary(without)
    for q in QUANT:
        np.testing.assert_allclose(a[q].values, b[q].values, rtol=0.01, err_msg=q)
    assert with_.attrs["iterations"] < without.attrs["iterations"]


@pytest.mark.parametrize("d", [7.1049, 7.1088])
def test_bistable_wet_set_keeps_the_old_update_order(d):
    """Where a wet pixel's own tension holds it wet (RH 1e-6 on Table 4: sigma0 G(0) = 1.6 h0)
    the order of the updates picks one of several equilibria a pixel apart: the solver keeps the
    order of the kernels before the speed-up there and finds their state (in the order used
    elsewhere it finds 34 pixels in contact and 6-7 wet outside it where they find 27-31 and
    none, and Γ of the automatic grid moved by 13 %)."""
    h = rs.datasets.surface_family("table4", shape=(64, 64), seed=1)
    z = h.values / 1e-9
    s0 = abs(float(rs.contact.laplace_pressure(1e-6))) / rs.materials.reduced_modulus()
    hw = float(rs.contact.water_height(1e-6)) / 1e-9
    kw = dict(scale=float(np.std(z)), max_iterations=500)
    grid = K.FFTGrid(z.shape, (5.0, 5.0))
    assert s0 * grid.self_displacement > K.SEQUENTIAL_WET * hw
    new = K.solve_state(grid, z, d, s0, hw, **kw)
    v0 = kernels_v0()
    old = v0.solve_state(v0.FFTGrid(z.shape, (5.0, 5.0)), z, d, s0, hw, **kw)
    for q in ("contact_fraction", "wet_fraction"):
        assert new[q] == old[q], q
    assert new["pbar"] == pytest.approx(old["pbar"], rel=1e-5)
