"""Which FFT window for measured (non-periodic) scans? Bias of the PSD moments m0, m2, m4 of
crops of periodic generated surfaces against the periodic truth (issue 16 item 4; not run by
pytest).

Each family surface (5 nm pixels) is generated periodic at 1024^2; its own PSD (no window: exact
for a periodic map) gives the truth m0, m2, m4 up to qmax = 289 rad/um (Table 3). Crops of
N^2 pixels taken at random offsets are not periodic (their opposite edges do not match, as in a
measured scan): their moments with each window are compared with the truth. Printed: the median
over crops of (crop moment / truth - 1), per family and window.

    nice -n 10 python benchmarks/psd_window.py [--quick]
"""
from __future__ import annotations

import argparse

import numpy as np

import roughstick as rs

QMAX = 289e6


def moments(h, window, detrend):
    if detrend:
        h = rs.surface.level(h, method="plane") if hasattr(rs, "level") else h
    m = rs.surface.psd_moments(rs.surface.power_spectrum(h, window=window), qmax=QMAX)
    return np.array([float(m.m0), float(m.m2), float(m.m4)])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    fams = ("S1", "smooth", "rough") if args.quick else ("S1", "S2", "table4", "smooth", "rough")
    crops = (128, 256)
    n_crops = 8 if args.quick else 16
    windows = [("none", None, False), ("none+plane", None, True), ("hann", "hann", False),
               ("hann+plane", "hann", True), ("blackman", "blackman", False),
               ("tukey0.25", ("tukey", 0.25), False)]
    rng = np.random.default_rng(0)
    print("family  crop  window        dm0/m0   dm2/m2   dm4/m4   (median over crops)")
    for fam in fams:
        full = rs.datasets.surface_family(fam, shape=(1024, 1024), seed=5)
        truth = moments(full, None, False)
        for n in crops:
            errs = {w[0]: [] for w in windows}
            for _ in range(n_crops):
                iy, ix = rng.integers(0, 1024 - n, size=2)
                crop = full.isel(y=slice(iy, iy + n), x=slice(ix, ix + n))
                crop.attrs["periodic"] = 0
                for name, win, det in windows:
                    errs[name].append(moments(crop, win, det) / truth - 1)
            for name, _, _ in windows:
                e = np.median(np.array(errs[name]), axis=0)
                print(f"{fam:7s} {n:4d}  {name:12s} {e[0]:+8.1%} {e[1]:+8.1%} {e[2]:+8.1%}", flush=True)


if __name__ == "__main__":
    main()
