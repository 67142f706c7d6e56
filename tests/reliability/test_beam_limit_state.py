"""P(stuck) of the beam-scale model by subset simulation (stuck_probability(bank, method="subset"))."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.reliability import _beam as _b
from roughstick.stiction.cantilever import PAPER_CANTILEVER

K = PAPER_CANTILEVER.stiffness_term
PATCH = PAPER_CANTILEVER.interaction_zone_length


def lognormal_bank(n_law=5000, median=(0.01,), seed=7):
    rng = np.random.default_rng(seed)
    e = np.exp(rng.normal(np.log(median), 0.5, size=(n_law, len(median))))
    return xr.DataArray(e, dims=("law", "rh"), coords={"rh": np.linspace(0.3, 0.9, len(median))})


def closed_form(energy, length):
    """1 - prod_j (1 - q_j) from the equilibrium positions of Eq. 36 (independent of reliability._beam)."""
    m = int(np.ceil(length / PATCH - 1e-9))
    far_edge = np.minimum((np.arange(m) + 1) * PATCH, length)
    s_eq = (K / energy) ** 0.25
    q = (s_eq[None, :] < far_edge[:, None]).mean(axis=1)
    return 1 - np.prod(1 - q)


def test_margin_above_one_is_the_stuck_flag_of_the_beam_model():
    """R(z) > 1 exactly when beam_crack_length (the sharp-front kernel) finds the beam stuck."""
    bank = lognormal_bank(n_law=300)
    length = 170e-6
    m = int(np.ceil(length / PATCH - 1e-9))
    margin = _b.BeamMargin(bank.values[:, 0], _b.edge_weights(m, PATCH, length, K))
    z = np.random.default_rng(0).standard_normal((3000, m)) + 1.0  # shifted: both outcomes occur
    r = np.array([margin(zi) for zi in z])
    energy = margin.energy[np.stack([margin.laws(zi) for zi in z])]
    beam = rs.Cantilever(length=length, width=PAPER_CANTILEVER.width, thickness=PAPER_CANTILEVER.thickness,
                         gap=PAPER_CANTILEVER.gap, youngs_modulus=PAPER_CANTILEVER.youngs_modulus)
    stuck = np.isfinite(rs.beam.crack_length(energy, beam=beam))
    assert 0.1 < stuck.mean() < 0.9
    np.testing.assert_array_equal(r > 1.0, stuck)


def test_closed_form_on_the_bank_agrees_with_counting_simulated_beams():
    bank = lognormal_bank(n_law=400, median=(0.01, 0.012))
    lengths = [128e-6, 134e-6]
    ds = rs.stuck_probability(bank, method="subset", beam_length=lengths, target_cv=None, n_per_level=100)
    mc = rs.beam.simulate(bank, beam_length=lengths, n=20000, seed=5)
    for k in range(2):
        for b, length in enumerate(lengths):
            p = float(ds.bank_stiction_probability[k, b])
            assert p == pytest.approx(closed_form(bank.values[:, k], length), rel=1e-12)
            lo, hi = float(mc.stuck_probability_lower[k, b]), float(mc.stuck_probability_upper[k, b])
            assert lo <= p <= hi, (k, b, p, lo, hi)


def test_subset_reaches_1e_3_within_its_interval_in_few_evaluations():
    """P(stuck) = 1.0e-3 on a 5000-law bank: target cv 0.3 met by the 3 runs the stopping rule
    needs at least (< 3,000 beams each), closed form inside."""
    bank = lognormal_bank()
    ds = rs.stuck_probability(bank, method="subset", beam_length=130e-6, n_per_level=500, seed=3).squeeze()
    exact = closed_form(bank.values[:, 0], 130e-6)
    assert exact == pytest.approx(1e-3, rel=0.01)
    assert float(ds.bank_stiction_probability) == pytest.approx(exact, rel=1e-12)
    assert float(ds.stiction_probability_lower) <= exact <= float(ds.stiction_probability_upper)
    assert float(ds.coefficient_of_variation) <= 0.3 and int(ds.converged) == 1
    assert int(ds.n_evaluations) < 9000


def test_zero_on_the_bank_gives_zero_with_an_upper_bound():
    bank = lognormal_bank(n_law=500)
    ds = rs.stuck_probability(bank, method="subset", beam_length=100e-6, n_per_level=200,
                                             max_evaluations=3000).squeeze()
    assert float(ds.bank_stiction_probability) == 0.0
    assert float(ds.stiction_probability) == 0.0 and float(ds.stiction_probability_upper) > 0
    assert int(ds.converged) == 0


def test_step_up_keeps_the_stuck_flags_of_the_first_humidity():
    bank = lognormal_bank(n_law=400, median=(0.01, 0.02, 0.03))
    kw = dict(beam_length=[128e-6], target_cv=None, n_per_level=200, seed=1)
    up = rs.stuck_probability(bank, method="subset", protocol="step_up", **kw)
    first = rs.stuck_probability(bank.isel(rh=[0]), method="subset", **kw)
    for k in range(3):
        xr.testing.assert_equal(up.stiction_probability.isel(rh=k, drop=True),
                                first.stiction_probability.isel(rh=0, drop=True))
    sim = rs.beam.simulate(bank, beam_length=128e-6, n=500, protocol="step_up")
    assert (sim.stuck == sim.stuck.isel(rh=0)).all()


def test_resumes_from_its_levels(tmp_path):
    bank = lognormal_bank(n_law=1000)
    kw = dict(beam_length=[140e-6], n_per_level=500, target_cv=None, seed=2, output=tmp_path / "lv")
    a = rs.stuck_probability(bank, method="subset", **kw)
    assert any((tmp_path / "lv").rglob("*.nc"))
    b = rs.stuck_probability(bank, method="subset", **kw)
    xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())


@pytest.mark.parametrize("bad, match", [
    (xr.DataArray(np.ones((3, 2, 4)), dims=("law", "rh", "gap")), "dims"),
    (xr.DataArray([[np.nan], [1.0]], dims=("law", "rh")), "NaN"),
])
def test_bad_bank(bad, match):
    with pytest.raises(ValueError, match=match):
        rs.stuck_probability(bad, method="subset", beam_length=1e-4)


@pytest.mark.slow
def test_interval_coverage_over_seeds():
    """40 seeds at P = 1e-3: the 95 % interval holds the closed form at least 33 times (binomial
    5 % quantile of 40 x 0.95 is 35; 33 leaves room for the log-normal approximation)."""
    bank = lognormal_bank()
    exact = closed_form(bank.values[:, 0], 130e-6)
    hits = 0
    for seed in range(40):
        ds = rs.stuck_probability(bank, method="subset", beam_length=130e-6, n_per_level=500,
                                                 seed=100 + seed).squeeze()
        hits += float(ds.stiction_probability_lower) <= exact <= float(ds.stiction_probability_upper)
    assert hits >= 33


def test_bit_identical_across_chunks_and_threads():
    bank = lognormal_bank(n_law=1000)
    kw = dict(beam_length=[140e-6], n_per_level=200, target_cv=None, seed=4)
    a = rs.stuck_probability(bank, method="subset", **kw)
    b = rs.stuck_probability(bank, method="subset", chunks=7, scheduler="threads", **kw)
    xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())
