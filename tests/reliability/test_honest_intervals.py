"""Honest intervals of subset simulation: lineage collapse, the stopping rule, NaN responses.

Every check is against a limit state with an exactly known probability (linear in the white
noise: P(a . z > beta) = Phi(-beta)).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.stats import norm

import roughstick as rs
from roughstick.reliability import _engine as _e
from roughstick.reliability import _kernels as _k


class Linear:
    """Y = a . z, a a unit direction; with ``nan``, NaN where z_1 > 0 (a has no z_1 component,
    so the NaN half-space is independent of Y and P(Y > beta) = Phi(-beta) still)."""

    def __init__(self, shape, nan=False, seed=1):
        a = np.random.default_rng(seed).standard_normal(shape)
        if nan:
            a.flat[1] = 0.0
        self.a = a / np.linalg.norm(a)
        self.nan = nan

    def __call__(self, z):
        if self.nan and z.flat[1] > 0:
            return math.nan
        return float(np.sum(self.a * z))


def _runs(shape, beta, seeds, *, nan=False, **kw):
    out = []
    for s in seeds:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out.append(rs.reliability.subset_simulation(Linear(shape, nan=nan), noise_shape=shape, threshold=beta,
                                                        seed=s, scheduler="sync", chunks=100_000, **kw))
    return out


def _spread_and_coverage(results, exact):
    p = np.array([float(d.failure_probability) for d in results])
    cv = np.array([float(d.coefficient_of_variation) for d in results])
    cover = sum(float(d.failure_probability_lower) <= exact <= float(d.failure_probability_upper) for d in results)
    return math.sqrt(np.mean((p - exact) ** 2)) / exact, cv, cover


# ------------------------------------------------------------------------------ lineages
def test_genealogical_cv_cannot_exceed_one_and_the_lineage_correction_can():
    """The genealogical cv^2 is N/(N-1) (1/N_eff - 1/N): at most 1 however few the lineages
    (the reason it is optimistic when they collapse); Bessel's correction on N_eff is not bounded,
    and is infinite for one lineage."""
    roots = np.array([7] * 30 + [2] * 10)  # 40 failures from 2 of 500 ancestors
    ind = np.ones(roots.size, bool)
    lin = _k.effective_lineages(roots, ind)
    assert math.isclose(lin, 1 / (0.75**2 + 0.25**2))
    cv2 = _k.genealogical_cv2(roots, ind, 500)
    assert math.isclose(cv2, 500 / 499 * (1 / lin - 1 / 500), rel_tol=1e-12) and cv2 < 1
    assert math.isclose(_k.lineage_cv2(cv2, lin), cv2 * lin / (lin - 1)) and _k.lineage_cv2(cv2, lin) > 1
    one = np.full(40, 3)
    assert _k.genealogical_cv2(one, ind, 500) <= 1 and _k.lineage_cv2(_k.genealogical_cv2(one, ind, 500), 1.0) == math.inf
    assert _k.effective_lineages(roots, np.zeros(roots.size, bool)) == 0.0


def test_lineage_collapse_is_flagged_warned_and_widened():
    """A constructed collapse: P = 1e-5 with 100 samples per level (10 levels of 20 chains of
    5): the final failures descend from 1-3 effective lineages. Each run is flagged
    (few_lineages, run_lineages < 5), the warning names the remedy (n_per_level), and the widened
    interval covers the truth where the uncorrected one (genealogical cv, normal quantile)
    misses it."""
    shape, beta = (16, 16), norm.isf(1e-5)
    with pytest.warns(UserWarning, match=r"effective independent level-0 lineages.*n_per_level=200 \(now 100\)"):
        rs.reliability.subset_simulation(Linear(shape), noise_shape=shape, threshold=beta, seed=0,
                                         n_per_level=100, scheduler="sync", chunks=100_000)
    res = _runs(shape, beta, range(20), n_per_level=100)
    flagged = sum(int(d.few_lineages) == 1 and float(d.run_lineages[0]) < _e.MIN_LINEAGES for d in res)
    assert flagged >= 18
    _, _, cover = _spread_and_coverage(res, 1e-5)
    z = norm.isf(0.025)
    old = 0
    for d in res:  # the interval of the genealogical cv alone (bounded by 1) with the normal quantile
        lin, n = float(d.run_lineages[0]), int(d.run_samples[0])
        g = math.sqrt(n / (n - 1) * (1 / lin - 1 / n))
        s, c = math.sqrt(math.log1p(g * g)), float(d.failure_probability) * math.sqrt(1 + g * g)
        old += c * math.exp(-z * s) <= 1e-5 <= c * math.exp(z * s)
    assert cover >= 19 and cover > old, (cover, old)


def test_many_lineages_are_not_flagged():
    """P = 1e-2 with 500 samples per level: over 10 effective final lineages, no flag, no warning."""
    shape = (8, 8)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ds = rs.reliability.subset_simulation(Linear(shape), noise_shape=shape, threshold=norm.isf(1e-2), seed=3,
                                              n_per_level=500, scheduler="sync")
    assert float(ds.run_lineages[0]) > 10 and int(ds.few_lineages) == 0


# ------------------------------------------------------------------------------ the stopping rule
def test_target_cv_stops_only_after_three_runs_that_agree():
    """A target one run meets (0.9) still takes 3 runs, whose spread is tested against their cv."""
    shape = (8, 8)
    ds = _runs(shape, norm.isf(1e-3), [4], n_per_level=300, target_cv=0.9)[0]
    assert ds.sizes["run"] >= _e.MIN_STOPPING_RUNS and int(ds.converged) == 1
    assert 0.0 <= float(ds.spread_p_value) <= 1.0
    assert float(ds.run_cv[0]) <= 0.9  # one run alone would have stopped


def test_runs_that_disagree_do_not_stop_until_their_spread_stands_alone():
    base = dict(probability=1e-4, cv=0.2, au_beck_cv=0.2, between_run_cv=0.2, lower=5e-5, upper=2e-4,
                interval="log-normal")
    assert not _e.Estimate(**base, spread_p_value=0.5).agrees(2)
    assert _e.Estimate(**base, spread_p_value=0.5).agrees(3)
    assert not _e.Estimate(**base, spread_p_value=0.01).agrees(9)
    assert _e.Estimate(**base, spread_p_value=0.01).agrees(_e.SPREAD_RUNS)


# ------------------------------------------------------------------------------ NaN responses
def test_nan_responses_are_counted_not_taken_as_no_failure():
    """The limit state is NaN on half the space (independent of Y): counted per level, left out
    of the level fractions, so the mean of 20 runs is Phi(-beta) (NaN as "no failure" gives half
    of it, 8 standard errors away), the intervals cover it, and a warning says so."""
    shape, beta = (8, 8), norm.isf(1e-2)
    with pytest.warns(UserWarning, match="NaN responses"):
        rs.reliability.subset_simulation(Linear(shape, nan=True), noise_shape=shape, threshold=beta, seed=0,
                                         n_per_level=400, scheduler="sync")
    res = _runs(shape, beta, range(20), nan=True, n_per_level=400)
    nan0 = np.array([float(d.nan_responses[0, 0]) for d in res])
    assert abs(nan0.mean() / 400 - 0.5) < 0.05  # half of level 0
    assert all(float(d.nan_responses.sum()) > float(d.nan_responses[0, 0]) for d in res)  # and proposals
    p = np.array([float(d.failure_probability) for d in res])
    se = p.std(ddof=1) / math.sqrt(p.size)
    assert abs(p.mean() - 1e-2) < 3 * se and abs(p.mean() - 0.5e-2) > 5 * se
    _, _, cover = _spread_and_coverage(res, 1e-2)
    assert cover >= 18


def test_nan_interval_covers_nan_as_failure_or_not():
    """Crude Monte Carlo with NaN on half the space: P over the finite responses, the interval from
    the Wilson bound of NaN as no failure up to that of NaN as failure."""
    shape = (4,)
    ds = _runs(shape, 1.0, [2], nan=True, method="monte_carlo", n_per_level=2000)[0]
    u = int(ds.nan_responses.sum())
    k = round(float(ds.failure_probability) * (2000 - u))
    lo = float(rs.ensemble.binomial_interval(k, 2000)[0])
    hi = float(rs.ensemble.binomial_interval(k + u, 2000)[1])
    assert 900 < u < 1100
    assert math.isclose(float(ds.failure_probability_lower), lo, rel_tol=1e-9)
    assert math.isclose(float(ds.failure_probability_upper), hi, rel_tol=1e-9)
    assert lo < norm.sf(1.0) < hi


def test_all_nan_is_refused_with_the_fix():
    with pytest.raises(ValueError, match=r"every one of the 50 responses of level 0 is NaN.*-inf"):
        rs.reliability.subset_simulation(lambda z: math.nan, noise_shape=(3,), threshold=1.0, n_per_level=50,
                                         scheduler="sync")


# ------------------------------------------------------------------------------ honesty, measured
@pytest.mark.parametrize("nan", [False, True])
def test_reported_cv_and_coverage_fast(nan):
    """40 seeds, P = 1e-3, N = 300 (with and without a NaN half-space): the mean reported cv is
    the true cv (root mean square error / P) within the sampling error of 40 runs (+-35 %), and
    >= 34 of 40 intervals cover (P(<= 33 | 0.95) < 1 %)."""
    shape, exact = (16, 16), 1e-3
    res = _runs(shape, norm.isf(exact), range(100, 140), nan=nan, n_per_level=300)
    true, cv, cover = _spread_and_coverage(res, exact)
    mean = np.mean(cv[np.isfinite(cv)])
    assert 0.65 < mean / true < 1.35, (mean, true)
    assert cover >= 34


@pytest.mark.slow
@pytest.mark.parametrize("case", [dict(beta=norm.isf(1e-3), shape=(16, 16), n_per_level=300),
                                  dict(beta=norm.isf(1e-4), shape=(32, 32), n_per_level=900),
                                  dict(beta=norm.isf(1e-3), shape=(16, 16), n_per_level=300, nan=True)])
def test_reported_cv_within_25_percent_and_coverage_90(case):
    """200 seeds, the runs of benchmarks/bench_honest_intervals.py's linear3, linear4 and nan cases:
    the mean reported cv within +-25 % of the true cv, >= 90 % of the 95 % intervals cover."""
    case = dict(case)
    beta, shape = case.pop("beta"), case.pop("shape")
    res = _runs(shape, beta, range(10_000, 10_200), **case)
    true, cv, cover = _spread_and_coverage(res, norm.sf(beta))
    mean = np.mean(cv[np.isfinite(cv)])
    assert 0.75 < mean / true < 1.25, (mean, true)
    assert cover >= 180


def test_the_remedy_is_spelled_where_the_user_is():
    """From Python the collapse warning names n_per_level=; from `roughstick beam`/`risk` the key of
    their configuration."""
    from roughstick._core.remedy import spell, spelled
    from roughstick.cli._common import config_spellings

    assert spell("samples_per_level", 2000) == "n_per_level=2000"
    with spelled(**config_spellings(contact_model="bank", key="model", samples="ensemble")):
        assert spell("samples_per_level", 2000) == "[ensemble] n_per_level = 2000"
    with spelled(**config_spellings(contact_model="risk", key="model", samples="risk")):
        assert spell("samples_per_level", 600) == "[risk] n_per_level = 600"
