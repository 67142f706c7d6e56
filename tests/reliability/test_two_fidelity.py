"""The two-fidelity rare-event estimator: subset simulation on a cheap limit state to a relaxed
threshold, corrected by the accurate one on the final level (docs/rare_events.md)."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from scipy.stats import beta as beta_dist
from scipy.stats import norm

import roughstick as rs
from roughstick.reliability import _fidelity as _f

pytestmark = pytest.mark.filterwarnings("ignore::roughstick.ValidityWarning")


class Accurate:
    """Linear limit state z . u (u a unit vector): P(Y > b) = Phi(-b) exactly."""

    noise_shape = (8,)

    def __init__(self):
        u = np.zeros(8)
        u[0], u[1] = 0.8, 0.6
        self.u = u

    def __call__(self, z):
        return float(np.dot(self.u, np.ravel(z)))


class Cheap(Accurate):
    """The accurate response times 1 + 0.5 sigmoid(z_2): overestimates by up to 25 % on a
    coordinate the accurate response does not see (ratio accurate / cheap in (0.8, 1))."""

    def __call__(self, z):
        z = np.ravel(z)
        return super().__call__(z) * (1.0 + 0.25 / (1.0 + math.exp(-2.0 * z[2])))


class Fooling(Accurate):
    """Overestimates by 50 % at moderate responses (where the pilot looks) and by ~4 % at the
    accurate failures beyond 3: the pilot's ratio bound (about 0.8) is too tight there."""

    def __call__(self, z):
        y = super().__call__(z)
        return y * (1.0 + 0.5 / (1.0 + math.exp(4.0 * (y - 2.5))))


def estimate(seed, threshold, cheap=None, **kw):
    cheap = cheap or Cheap()
    runs = kw.pop("independent_runs", 1)
    run = functools.partial(rs.reliability.subset_simulation, cheap, noise_shape=cheap.noise_shape,
                            n_per_level=kw.pop("n_per_level", 400), scheduler="sync", independent_runs=runs)
    return _f.two_fidelity(cheap, Accurate(), threshold=threshold, run=lambda t, s, attempt: run(threshold=t, seed=s),
                           n_accurate=kw.pop("n_accurate", 150), ratio_bound=kw.pop("ratio_bound", None),
                           n_pool=kw.pop("n_pool", 400), seed=seed, confidence=0.95, independent_runs=runs)


def test_two_fidelity_covers_the_exact_probability_of_a_linear_limit_state():
    """P(accurate > 3.09) = 1e-3 exactly, while the cheap model puts several times more above it; the
    combined intervals hold the exact value in at least 8 of 10 seeds (nominal 9.5), none of
    their containment checks finds an accurate failure below the relaxed level, and the mean
    estimate is within 3 standard errors of the exact value."""
    b = 3.0902
    exact = norm.sf(b)
    ests = [estimate(s, b) for s in range(10)]
    held = sum(float(d.failure_probability_lower) <= exact <= float(d.failure_probability_upper) for d in ests)
    p = np.array([float(d.failure_probability) for d in ests])
    assert held >= 8, [(float(d.failure_probability_lower), float(d.failure_probability_upper)) for d in ests]
    assert abs(p.mean() - exact) < 3 * p.std(ddof=1) / math.sqrt(p.size)
    assert all(int(d.containment_violations) == 0 and int(d.containment_checked) > 0 for d in ests)
    # the cheap run alone is far off: Eq. 16-like overestimation is what the correction removes
    assert float(np.mean([float(d.cheap_probability) for d in ests])) > 2 * exact
    assert all(int(d.n_accurate_evaluations) <= 150 + _f.PILOT_STATES for d in ests)


def test_independent_runs_share_the_accurate_budget_and_average():
    """Three cheap runs, each corrected by its third of the accurate evaluations: the estimate is
    their mean and its cv about 1/sqrt(3) of one run's."""
    exact = norm.sf(3.0902)
    one = estimate(0, 3.0902, n_accurate=150)
    three = estimate(0, 3.0902, n_accurate=450, independent_runs=3)
    assert three.sizes["run"] == 3 and three.combined_lineages.size == 3
    assert int(three.n_accurate_evaluations) <= 450 + _f.PILOT_STATES
    assert float(three.failure_probability_lower) < exact < float(three.failure_probability_upper)
    assert float(three.coefficient_of_variation) < float(one.coefficient_of_variation)


def test_a_too_tight_ratio_bound_is_caught_by_the_containment_check():
    """With ratio_bound 0.5 the relaxed level is twice the threshold: every accurate failure of
    the band just below it is a containment violation, and the warning names the fix."""
    with pytest.warns(UserWarning, match="ratio_bound="):
        ds = estimate(0, 2.0, ratio_bound=0.5)
    assert int(ds.containment_violations) > 0
    assert int(ds.containment_violations) == int(ds.containment_checked)
    assert float(ds.failure_probability_upper) < norm.sf(2.0)  # what the check exists to expose


def test_a_pilot_fooled_by_the_cheap_model_is_corrected_by_a_second_pass():
    """The pilot (the 32 highest cheap states of 60) sees ratios of 0.7-0.9, the failures have
    0.96-1: the first pass finds accurate failures in its band, the bound is re-measured on the
    final states and the second pass has no violation left and holds the exact 1e-3. (The cheap
    model overstates the bulk by 50 %, so the second pass's fraction is about 0.02 and its
    interval wide: a few accurate failures in the final level.)"""
    exact = norm.sf(3.0902)
    for seed in range(2):
        ds = estimate(seed, 3.0902, cheap=Fooling(), n_accurate=800, n_pool=60, n_per_level=1000)
        assert int(ds.passes) == 2 and int(ds.first_pass_violations) > 0
        assert float(ds.first_pass_ratio_bound) < 0.96 < float(ds.ratio_bound)
        assert int(ds.containment_violations) == 0
        assert exact / 3 < float(ds.failure_probability) < 3 * exact
        assert float(ds.failure_probability_lower) < exact < float(ds.failure_probability_upper)
        # both passes are counted: the pilot, the first pass (at least its violations) and the second
        assert int(ds.n_accurate_evaluations) > _f.PILOT_STATES + int(ds.first_pass_violations) + int(ds.containment_checked)


def test_failure_probability_with_an_accurate_model_on_a_tiny_zone():
    """The public call: Eq. 16 subset run corrected by fft_bem, its counts and its checks."""
    ds = rs.reliability.failure_probability(
        rs.datasets.family_psd("table4"), threshold=0.09, relative_humidity=0.5, shape=(16, 16),
        spacing=5e-9, model="modified_dmt", accurate_model="fft_bem", n_accurate=40, n_per_level=100,
        scheduler="sync", seed=1)
    assert ds.attrs["method"] == "two_fidelity" and ds.attrs["accurate_model"] == "fft_bem"
    assert 0 < int(ds.n_accurate_evaluations) <= 40 + _f.PILOT_STATES
    assert float(ds.failure_probability_lower) <= float(ds.failure_probability) <= float(ds.failure_probability_upper)
    # the accurate model's failures are a part of the cheap failures at the (lower) band threshold
    assert float(ds.failure_probability) <= float(ds.cheap_probability)
    assert float(ds.band_threshold) < float(ds.relaxed_threshold)
    assert float(ds.relaxed_threshold) == pytest.approx(0.09 / float(ds.ratio_bound))
    assert ds.pilot_ratio.size == _f.PILOT_STATES


@pytest.mark.parametrize("kw, match", [
    ({"accurate_model": "gw"}, "accurate_model must be 'fft_bem'"),
    ({"accurate_model": "fft_bem", "model": "fft_bem"}, "corrects the modified DMT"),
    ({"accurate_model": "fft_bem", "target_cv": 0.3}, "independent_runs"),
    ({"accurate_model": "fft_bem", "patches": 2}, "periodic=True and patches=1"),
    ({"accurate_model": "fft_bem", "n_accurate": 3}, "n_accurate must be"),
    ({"accurate_model": "fft_bem", "ratio_bound": -1.0}, "ratio_bound=-1.0: must be a finite number > 0"),
])
def test_two_fidelity_requests_it_cannot_run_are_refused_with_the_fix(kw, match):
    with pytest.raises(ValueError, match=match):
        rs.reliability.failure_probability(rs.datasets.family_psd("table4"), threshold=0.05,
                                           relative_humidity=0.5, shape=(16, 16), spacing=5e-9, **kw)


@pytest.mark.slow
def test_two_fidelity_agrees_with_crude_fft_bem_monte_carlo_on_small_zones():
    """16 x 16 Table-4 zones at 50 % RH: crude Monte Carlo with fft_bem alone (3,000 zones) and
    the two-fidelity estimate agree (the Clopper-Pearson interval of the crude count overlaps the
    estimate's interval)."""
    psd = rs.datasets.family_psd("table4")
    kw = dict(relative_humidity=0.5, shape=(16, 16), spacing=5e-9, scheduler="sync")
    t = 0.09
    crude = rs.reliability.failure_probability(psd, threshold=t, model="fft_bem", method="monte_carlo",
                                               n_per_level=3000, seed=7, **kw)
    k, n = int(round(float(crude.failure_probability) * 3000)), 3000
    lo, hi = beta_dist.ppf(0.025, k, n - k + 1), beta_dist.ppf(0.975, k + 1, n - k)
    ds = rs.reliability.failure_probability(psd, threshold=t, model="modified_dmt", accurate_model="fft_bem",
                                            n_accurate=300, n_per_level=1000, seed=3, **kw)
    assert k >= 30
    assert float(ds.failure_probability_lower) <= hi and lo <= float(ds.failure_probability_upper)


def test_stuck_probability_takes_the_accurate_model_on_a_psd():
    """rs.stuck_probability(psd, method="subset", accurate_model="fft_bem"): one corrected run
    (its default target_cv steps aside), P(stuck) of the boundary-element model's zones."""
    with pytest.warns(UserWarning, match="smaller than the beam's interaction zone"):
        ds = rs.stuck_probability(rs.datasets.family_psd("table4"), method="subset", relative_humidity=0.5,
                                  shape=(16, 16), spacing=5e-9, beam_length=115e-6, model="modified_dmt",
                                  accurate_model="fft_bem", n_accurate=20, n_per_level=100, seed=2)
    assert ds.attrs["method"] == "two_fidelity"
    assert 0 <= float(ds.stiction_probability) <= float(ds.cheap_probability)
    assert float(ds.relaxed_threshold) == pytest.approx(float(ds.critical_adhesive_energy) / float(ds.ratio_bound))
