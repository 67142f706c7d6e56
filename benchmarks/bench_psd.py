"""Speed of the PSD path, measured in one run: python benchmarks/bench_psd.py [n]

Prints ratios (not absolute claims) and the error traded:
- psd_isotropic (one sparse matrix product) vs a literal per-ring loop;
- roughness moments by cubic splines vs spectrally;
- power_spectrum on a stack of maps, numpy vs dask (threads).
"""

from __future__ import annotations

import sys
import time

import numpy as np

import roughstick as rs


def timed(f, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t)
    return best, out


def literal_ring_average(psd):
    qx, qy = psd.qx.values, psd.qy.values
    dq = min(qx[1] - qx[0], qy[1] - qy[0])
    qm = np.hypot(qx[None, :], qy[:, None])
    k = np.rint(qm / dq).astype(int)
    kmax = int(np.floor(min(abs(qx).max(), abs(qy).max()) / dq))
    s = psd.values
    return np.array([s[k == i].mean() for i in range(kmax + 1)])


def main(n=1024):
    rng = np.random.default_rng(0)
    h = rs.testing.make_topography(rng.normal(size=(n, n)) * 1e-9)
    s = rs.surface.power_spectrum(h)
    t_fast, fast = timed(lambda: rs.surface.psd_isotropic(s).values)
    t_lit, lit = timed(lambda: literal_ring_average(s), repeat=1)
    print(f"psd_isotropic {n}x{n}: sparse {t_fast * 1e3:.1f} ms, literal loop {t_lit * 1e3:.1f} ms, "
          f"ratio {t_lit / t_fast:.1f}x, max rel diff {np.max(np.abs(fast / lit - 1)):.1e}")
    t_spl, spl = timed(lambda: rs.surface.roughness_moments(h), repeat=1)
    t_spe, spe = timed(lambda: rs.surface.roughness_moments(h, method="spectral"), repeat=1)
    print(f"roughness_moments {n}x{n}: spline {t_spl:.2f} s, spectral {t_spe:.2f} s "
          f"(ratio {t_spl / t_spe:.1f}x); m4 spline/spectral = {float(spl.m4 / spe.m4):.3f} "
          "(white noise: power up to Nyquist, where they differ by construction)")
    stack = rs.testing.make_topography(rng.normal(size=(8, n // 2, n // 2)) * 1e-9)
    t_np, a = timed(lambda: rs.surface.power_spectrum(stack).values, repeat=1)
    t_da, b = timed(lambda: rs.surface.power_spectrum(stack.chunk({"dim_0": 1})).values, repeat=1)
    print(f"power_spectrum stack 8x{n // 2}^2: numpy {t_np:.2f} s, dask {t_da:.2f} s "
          f"(ratio {t_np / t_da:.2f}x), max abs diff {np.max(np.abs(a - b)):.1e}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1024)
