"""Accuracy against time of the rough-surface modified DMT (not run by pytest).

Two tables for the adhesive energy Gamma (Eq. 13) of data_samples/S1A.nc (a 512 x 512 crop,
5 nm pixels) at RH 30, 70 and 90 %:

1. versus the distance-grid step: uniform grids of 25 ... 800 points over the same range, and
   the automatic grid (refined where the curve turns); error against a 3200-point uniform grid;
2. versus the pixel size: the same surface subsampled to 10 and 20 nm pixels (every 2nd / 4th
   pixel of each row and column), error against the 5 nm map (each on its automatic grid).

    python benchmarks/convergence_rough_contact.py
"""

from __future__ import annotations

import time

import numpy as np
import xarray as xr

import roughstick as rs

RH = [0.3, 0.7, 0.9]


def gamma(h, **kw):
    t0 = time.perf_counter()
    c = rs.contact.curves(h, relative_humidity=RH, **kw)
    g = rs.contact.summary(c).adhesive_energy.values
    return g, time.perf_counter() - t0, c.distance.size


def main():
    h = xr.open_dataset(rs.datasets.sample_path("S1A")).height.isel(x=slice(0, 512), y=slice(0, 512)).load()
    rs.contact.curves(h, relative_humidity=0.5, distance=[0.0])  # compile
    d = rs.contact.contact_distance_grid(h, relative_humidity=RH, n=200).values
    lo, hi = d.min(), d.max()
    ref, tref, _ = gamma(h, distance=np.linspace(lo, hi, 3200))
    print("Gamma [mJ/m2] reference (3200 uniform points):", np.round(ref * 1e3, 5), f"({tref:.2f} s)")
    print("\n1. distance grid       step [nm]  time [s]   relative error of Gamma at RH 30 / 70 / 90 %")
    for n in (25, 50, 100, 200, 400, 800):
        g, t, _ = gamma(h, distance=np.linspace(lo, hi, n))
        err = np.abs(g - ref) / ref
        print(f"   uniform {n:5d}       {(hi - lo) / (n - 1) * 1e9:8.4f}  {t:8.3f}   "
              + "  ".join(f"{e:.1e}" for e in err))
    for n in (50, 100, 200):
        g, t, m = gamma(h, n_distance=n)
        err = np.abs(g - ref) / ref
        print(f"   automatic {m:3d}       (adaptive) {t:7.3f}   " + "  ".join(f"{e:.1e}" for e in err))
    print("\n2. pixel size (same surface, subsampled)   time [s]   Gamma [mJ/m2]   relative change vs 5 nm")
    base = None
    for step in (1, 2, 4):
        hs = h.isel(x=slice(0, None, step), y=slice(0, None, step))
        g, t, _ = gamma(hs)
        base = g if base is None else base
        print(f"   {5 * step:2d} nm ({hs.sizes['x']}^2)                       {t:8.3f}   "
              + " ".join(f"{v * 1e3:.4g}" for v in g) + "   "
              + "  ".join(f"{e:.1e}" for e in np.abs(g - base) / base))


if __name__ == "__main__":
    main()
