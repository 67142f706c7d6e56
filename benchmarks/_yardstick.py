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
