r"""Intervals that several stages share: the ranks of a quantile's distribution-free interval
(:func:`order_statistic_ranks`, the binomial quantiles of scipy.stats), the median of a few
numbers with its interval (:func:`median_interval`) and the names of the binomial intervals
(:func:`interval_method`).

The public intervals built on them are :func:`roughstick.ensemble.quantile_interval`,
:func:`roughstick.ensemble.confidence_band` and :func:`roughstick.ensemble.binomial_interval`.

"""

from __future__ import annotations

import numpy as np
from scipy import stats

from .arguments import check_numbers

__all__ = ["order_statistic_ranks", "median_interval", "interval_method"]


def order_statistic_ranks(n: int, p: float, *, confidence: float) -> tuple[int, int]:
    r"""1-based ranks :math:`(r, s)` of the order statistics that bracket the ``p``-quantile.

    :math:`P(X_{(r)} \le \xi_p \le X_{(s)}) = F_B(s-1) - F_B(r-1) \ge` ``confidence`` with
    :math:`F_B` the Binomial(n, p) CDF (Conover, *Practical Nonparametric Statistics*, §3.2),
    the two tails split equally. ``r < 1`` or ``s > n`` means that ``n`` samples cannot bound
    that side of the quantile.

    Examples
    --------
    >>> from roughstick._core.intervals import order_statistic_ranks
    >>> order_statistic_ranks(100, 0.5, confidence=0.95)
    (40, 61)
    """
    a = (1.0 - confidence) / 2.0
    r = int(stats.binom.ppf(a, n, p))  # P(B <= r - 1) <= a  -> rank r
    s = int(stats.binom.ppf(1.0 - a, n, p)) + 1
    return r, s


@check_numbers(confidence="fraction")
def median_interval(values, *, confidence: float = 0.95) -> tuple[float, float, float]:
    r"""Median of a few numbers and its distribution-free confidence interval.

    :math:`[X_{(r)}, X_{(s)}]` of :func:`order_statistic_ranks` at :math:`p = 1/2`; a side that
    ``n`` finite values cannot bound at ``confidence`` is NaN (n <= 5 at 95 %: both sides).
    Used where a result carries the median of a small check (the BEM re-checks of rare-event
    failure states and of a patch bank's tail).

    Examples
    --------
    >>> from roughstick._core.intervals import median_interval
    >>> median_interval([0.8, 0.9, 1.0, 1.1, 0.95, 0.85, 1.05, 0.99])
    (0.97, 0.8, 1.1)
    >>> median_interval([1.0, 2.0, 3.0])[1:]
    (nan, nan)
    """
    x = np.sort(np.asarray(values, dtype=float).ravel())
    x = x[np.isfinite(x)]
    if x.size == 0:
        return np.nan, np.nan, np.nan
    r, s = order_statistic_ranks(x.size, 0.5, confidence=confidence)
    return (float(np.median(x)), float(x[r - 1]) if r >= 1 else np.nan,
            float(x[s - 1]) if s <= x.size else np.nan)


_METHODS = {"wilson": "wilson", "clopper-pearson": "clopper-pearson", "exact": "clopper-pearson"}


def interval_method(method: str, *, confidence: float) -> str:
    """Check a binomial interval request: ``confidence`` in (0, 1) and ``method`` known; return the
    canonical method name (``"exact"`` is ``"clopper-pearson"``)."""
    if not (isinstance(confidence, float | int) and 0 < confidence < 1):
        raise ValueError(f"confidence must lie strictly between 0 and 1 (e.g. 0.95), got {confidence!r}.")
    if method not in _METHODS:
        raise ValueError(f"interval must be 'wilson' or 'clopper-pearson' (alias 'exact'), got {method!r}.")
    return _METHODS[method]
