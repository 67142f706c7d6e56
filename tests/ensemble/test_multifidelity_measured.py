"""The multi-fidelity estimator on measured ensembles: Γ of 500 generated S2 surfaces (128², 5 nm,
seed 0) at RH 0.3 and 0.7 by both the modified DMT (Eq. 16) and fft_bem, stored from
``benchmarks/bench_multifidelity.py`` (its pool; docs/evidence/multifidelity.md)."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

from roughstick.ensemble.multifidelity import accurate_subset, multifidelity_kernel

PROBS = np.array([0.025, 0.5, 0.975])
DATA = pathlib.Path(__file__).parent / "data" / "gamma_S2_128px.npz"


@pytest.fixture(scope="module")
def pool():
    with np.load(DATA) as z:
        return z["modified_dmt"], z["fft_bem"]


def test_eq16_alone_misses_the_accurate_median(pool):
    """The error the multi-fidelity estimate removes: Eq. 16's median Γ is 14-17 % above
    fft_bem's on these surfaces (more than the 10 % accuracy target)."""
    cheap, accurate = pool
    bias = np.median(cheap, axis=0) / np.median(accurate, axis=0) - 1
    assert (bias > 0.10).all(), bias


@pytest.mark.parametrize("j", [0, 1])
def test_correction_interval_covers_the_all_fft_bem_quantiles(pool, j):
    """With 100 of the 500 realizations run by fft_bem, over 20 subset seeds: the 95 % correction
    interval holds the all-fft_bem quantile of the same realizations in at least 17 of 20 seeds
    per quantile (at 95 % coverage, 16 or fewer happens with probability 0.016), and so is the
    median, or it lies within 3 % of the all-fft_bem median (the benchmark's criterion)."""
    cheap, accurate = pool[0][:, j], pool[1][:, j]
    truth = np.quantile(accurate, PROBS, method="inverted_cdf")
    hits = np.zeros(PROBS.size, int)
    median_ok = 0
    for seed in range(20):
        hi = np.full(cheap.size, np.nan)
        sub = accurate_subset(cheap.size, 100, seed=seed)
        hi[sub] = accurate[sub]
        r = multifidelity_kernel(cheap, hi, probabilities=PROBS)
        # an edge back-transformed from log may miss its value by a rounding error
        lo = np.where(np.isnan(r["correction_lower"]), -np.inf, r["correction_lower"]) * (1 - 1e-9)
        up = np.where(np.isnan(r["correction_upper"]), np.inf, r["correction_upper"]) * (1 + 1e-9)
        inside = (lo <= truth) & (truth <= up)
        hits += inside
        median_ok += bool(abs(r["quantile"][1] / truth[1] - 1) <= 0.03 or inside[1])
    assert (hits >= 17).all() and median_ok >= 17, (hits, median_ok)
