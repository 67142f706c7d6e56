"""Tests of roughstick._core.intervals: the median of a few numbers with its order-statistic interval."""

from __future__ import annotations

import numpy as np
import pytest

from roughstick._core.intervals import median_interval


@pytest.mark.parametrize("n, coverage", [(8, 1 - 2 * 0.5**8), (20, 0.9586)])
def test_median_interval_covers_the_true_median_as_the_binomial_says(n, coverage):
    """Independent check by simulation: over 4,000 samples of a skewed law (log-normal, true
    median 1) the interval covers 1 as often as the order-statistic theory says (n = 8:
    [min, max], 1 - 2/256 = 0.992; n = 20: ranks 6 and 15, 0.9586), within 4 binomial s.e."""
    rng = np.random.default_rng(11)
    hits = 0
    for _ in range(4000):
        med, lo, hi = median_interval(rng.lognormal(0.0, 1.0, n))
        assert lo <= med <= hi
        hits += lo <= 1.0 <= hi
    se = np.sqrt(coverage * (1 - coverage) / 4000)
    assert abs(hits / 4000 - coverage) < 4 * se + 1e-3, hits / 4000


def test_median_interval_says_when_n_is_too_small():
    med, lo, hi = median_interval([3.0, 1.0, 2.0, np.nan, 5.0, 4.0])  # 5 finite values
    assert med == 3.0 and np.isnan(lo) and np.isnan(hi)
    assert all(np.isnan(median_interval([])))
