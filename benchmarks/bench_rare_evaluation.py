"""Benchmark: the cost of one rare-event evaluation on every surface family (issue 15).

    nice -n 10 python benchmarks/bench_rare_evaluation.py [--n 40] [--shape 128 128] [--rh 0.5]

One evaluation of ``rs.reliability.failure_probability``'s limit state (white noise -> surface,
Eqs. 33-34 -> modified-DMT curve on the surface's own grid, Eq. 16 -> adhesive energy, Eq. 13) on ``--n``
random zones of each family at 5 nm; then, on one full grid per zone (first water contact to below
every pixel), the numpy kernels the limit state calls against the public xarray path it called
before (``rs.contact.curves`` + ``rs.contact.summary``) and the largest relative difference
of their Gamma (the same kernel: 0 expected); and the FFT-BEM (``model="fft_bem"``). Times
are also given as multiples of one 1024^2 complex iFFT timed in the same process.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
from _yardstick import ifft_seconds

import roughstick as rs
from roughstick.reliability._surface import NoiseToSurface, SurfaceResponse

SPACING = 5e-9


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--shape", type=int, nargs=2, default=(128, 128))
    ap.add_argument("--rh", type=float, default=0.5)
    args = ap.parse_args()
    warnings.filterwarnings("ignore", category=rs.ValidityWarning)
    shape = tuple(args.shape)
    unit = ifft_seconds(7)
    hw = float(rs.contact.water_height(args.rh).values)
    print(f"{shape[0]}x{shape[1]} zones at 5 nm, RH {args.rh}, {args.n} zones per family; one 1024^2 iFFT "
          f"= {unit * 1e3:.1f} ms")
    print("family  limit state (default) | full grid: numpy kernels, xarray path, ratio | FFT-BEM | "
          "max |dGamma|/Gamma numpy vs xarray")
    for fam in rs.datasets.FAMILIES:
        psd = rs.datasets.family_psd(fam)
        f = NoiseToSurface(psd, shape=shape, spacing=SPACING)
        model = SurfaceResponse(f, relative_humidity=args.rh, water_height=hw)
        bem = SurfaceResponse(f, relative_humidity=args.rh, water_height=hw, model="fft_bem")
        rng = np.random.default_rng(1)
        noise = [rng.standard_normal(shape) for _ in range(args.n)]
        model(noise[0])
        bem(noise[0])  # compiled kernels warm
        t0 = time.perf_counter()
        g = [model(w) for w in noise]
        t_np = (time.perf_counter() - t0) / args.n
        # the two paths on one grid per zone: from first water contact to below every pixel
        grids = []
        for w in noise:
            zc = f(w) - f(w).mean()
            top = float(zc.max()) + hw
            grids.append((zc, top - model.step * np.arange(int(np.ceil((top - zc.min()) / model.step)) + 2)[::-1]))
        t0 = time.perf_counter()
        g_k = [float(rs.contact.adhesion.summary_kernel(*model._curves(zc, d, True), d)[0]) for zc, d in grids]
        t_k = (time.perf_counter() - t0) / args.n
        t0 = time.perf_counter()
        g_x = [float(rs.contact.summary(rs.contact.curves(
            f.height_array(zc), relative_humidity=args.rh, distance=d, check_validity=False),
            check_grid=False).adhesive_energy) for zc, d in grids]
        t_x = (time.perf_counter() - t0) / args.n
        nb = max(4, args.n // 4)
        t0 = time.perf_counter()
        for w in noise[:nb]:
            bem(w)
        t_b = (time.perf_counter() - t0) / nb
        rel = np.max(np.abs(np.array(g_k) - np.array(g_x)) / np.maximum(np.abs(g_x), 1e-30))
        print(f"{fam:7s} {t_np * 1e3:6.2f} ms {t_np / unit:5.2f}x | {t_k * 1e3:6.2f} ms {t_k / unit:5.2f}x "
              f"{t_x * 1e3:6.2f} ms {t_x / unit:5.2f}x {t_x / t_k:5.1f}x | {t_b * 1e3:6.1f} ms {t_b / unit:5.2f}x | "
              f"{rel:.1e}  (median Gamma {np.median(g) * 1e3:.2f} mJ/m2)")


if __name__ == "__main__":
    main()
