"""The machine-load yardstick every benchmark divides by: one 1024² numpy complex inverse FFT.

Scripts in this folder are run as ``python benchmarks/<name>.py``, so they import this module as
``from _yardstick import ifft_seconds``.
"""

from __future__ import annotations

import time

import numpy as np


def ifft_seconds(repeat: int = 5) -> float:
    """Best of ``repeat`` timings [s] of ``numpy.fft.ifft2`` on a 1024² complex array."""
    a = np.random.default_rng(0).standard_normal((1024, 1024)) + 0j
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        np.fft.ifft2(a)
        best = min(best, time.perf_counter() - t)
    return best


def best_of(call, repeat: int = 2):
    """(result of the last call, best wall time [s] of ``repeat`` calls of ``call()``)."""
    best, out = np.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = call()
        best = min(best, time.perf_counter() - t)
    return out, best


def spread_interval(spread: float, k: int, confidence: float = 0.95) -> tuple[float, float]:
    """Chi-square interval of a relative spread (std/mean) measured on ``k`` runs (normal
    approximation): how well K repeated runs pin down the true cv of one run."""
    from scipy.stats import chi2

    a = (1 - confidence) / 2
    lo, hi = spread * np.sqrt((k - 1) / chi2.ppf([1 - a, a], k - 1))
    return float(lo), float(hi)
