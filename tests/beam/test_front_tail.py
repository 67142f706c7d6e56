"""P(stuck) of every beam length from one Γ CCDF (roughstick.beam.front_tail) against the
bank-and-simulate path and the exact CCDF of a known distribution."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.reliability._beam import BeamMargin, edge_weights

LENGTHS = np.array([200e-6, 225e-6, 250e-6, 275e-6, 300e-6])


def _bank(n=300, seed=3):
    rng = np.random.default_rng(seed)
    # log-normal laws near the critical energies of 200-300 µm beams (Eq. 36: 2-10 mJ m-2 at the tip)
    values = np.exp(rng.normal(np.log([7e-4, 1.2e-3]), 1.0, size=(n, 2)))
    return xr.DataArray(values, dims=("law", "rh"), coords={"rh": [0.5, 0.7]}, attrs={"units": "J m-2"})


def test_closed_form_agrees_with_simulated_beams_on_the_bank():
    bank = _bank()
    p = rs.beam.stuck_probability_from_ccdf(rs.beam.adhesive_energy_ccdf(bank, dim="law"), beam_length=LENGTHS)
    n = 20_000
    sim = rs.beam.simulate(bank, beam_length=LENGTHS, n=n, seed=2)
    ps, pc = sim.stuck_probability.values, p.stuck_probability.transpose("rh", "beam_length").values
    assert np.mean((pc > 0.02) & (pc < 0.98)) >= 0.5  # a case where the comparison means something
    sigma = np.sqrt(pc * (1 - pc) / n)
    assert np.all(np.abs(ps - pc) <= 4.5 * sigma), (ps, pc)


def test_closed_form_is_the_bank_closed_form_of_the_rare_event_path():
    bank = _bank(n=50, seed=1)
    p = rs.beam.stuck_probability_from_ccdf(rs.beam.adhesive_energy_ccdf(bank, dim="law"), beam_length=LENGTHS)
    beam = rs.stiction.PAPER_CANTILEVER
    dx = beam.interaction_zone_length
    for k in range(2):
        for b, length in enumerate(LENGTHS):
            w = edge_weights(int(np.ceil(length / dx - 1e-9)), dx, length, beam.stiffness_term)
            exact = BeamMargin(bank.values[:, k], w).exact()
            assert p.stuck_probability.isel(rh=k, beam_length=b) == pytest.approx(exact, rel=1e-12, abs=1e-15)


def test_longer_beams_stick_more_and_a_uniform_interface_gives_eq36():
    g0 = 1e-3
    sample = xr.DataArray(np.full(10, g0), dims="realization", attrs={"units": "J m-2"})
    s36 = float(rs.stiction.crack_length_from_adhesive_energy(g0, beam=rs.stiction.PAPER_CANTILEVER))
    lengths = np.array([0.9 * s36, 1.01 * s36 + rs.stiction.PAPER_CANTILEVER.interaction_zone_length])
    p = rs.beam.stuck_probability_from_ccdf(rs.beam.adhesive_energy_ccdf(sample), beam_length=lengths)
    assert p.stuck_probability.values.tolist() == [0.0, 1.0]
    q = rs.beam.stuck_probability_from_ccdf(rs.beam.adhesive_energy_ccdf(_bank(), dim="law"), beam_length=LENGTHS)
    assert np.all(np.diff(q.stuck_probability.values, axis=-1) >= 0)


def test_band_covers_the_exact_p_stuck_of_a_known_distribution():
    """Exponential Γ: the exact CCDF exp(-g/mu) gives P(stuck) of every length; the DKW band of 40
    draws must cover it (all lengths at once) in >= 95 % of 300 samples (allowing 2.5 % slack)."""
    mu = 1.5e-3
    beam = rs.stiction.PAPER_CANTILEVER
    dx = beam.interaction_zone_length
    exact = []
    for length in LENGTHS:
        hi = np.minimum((np.arange(int(np.ceil(length / dx - 1e-9))) + 1) * dx, length)
        exact.append(-np.expm1(np.sum(np.log1p(-np.exp(-beam.stiffness_term / hi**4 / mu)))))
    exact = np.array(exact)
    assert 1e-3 < exact.min() and exact.max() < 0.99
    rng = np.random.default_rng(7)
    draws = rng.exponential(mu, size=(300, 40))
    sample = xr.DataArray(draws, dims=("trial", "realization"), attrs={"units": "J m-2"})
    p = rs.beam.stuck_probability_from_ccdf(rs.beam.adhesive_energy_ccdf(sample), beam_length=LENGTHS)
    inside = ((p.stuck_probability_lower <= exact) & (exact <= p.stuck_probability_upper)).all("beam_length")
    assert float(inside.mean()) >= 0.925
    # not vacuous: the band bounds P(stuck) of the longest beam away from 0 (the upper side is near 1
    # here: a distribution-free band cannot bound the tail beyond the largest of 40 draws)
    assert float((p.stuck_probability_lower.isel(beam_length=-1) > 0.05).mean()) > 0.5


def test_bad_ccdf_is_refused_naming_the_fix():
    with pytest.raises(ValueError, match="adhesive_energy_ccdf"):
        rs.beam.stuck_probability_from_ccdf(xr.Dataset(), beam_length=2e-4)
    with pytest.raises(ValueError, match="dim="):
        rs.beam.adhesive_energy_ccdf(_bank())  # a bank's sample dimension is 'law'


def test_the_p_stuck_verb_composes_every_length_from_the_strips():
    bank = _bank()
    by_verb = rs.stuck_probability(bank, method="front", beam_length=LENGTHS)
    direct = rs.beam.stuck_probability_from_ccdf(rs.beam.adhesive_energy_ccdf(bank, dim="law"),
                                                 beam_length=LENGTHS)
    xr.testing.assert_allclose(by_verb.stuck_probability, direct.stuck_probability)
    strips = bank.rename(law="realization")
    same = rs.stuck_probability(strips, method="front", beam_length=LENGTHS)
    np.testing.assert_allclose(same.stuck_probability.values, direct.stuck_probability.values)
    with pytest.raises(TypeError, match="needs beam_length="):
        rs.stuck_probability(strips, method="front")
    with pytest.raises(TypeError, match="n= is for method"):
        rs.stuck_probability(strips, method="front", beam_length=LENGTHS, n=5)
