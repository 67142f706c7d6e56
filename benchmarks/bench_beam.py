"""Benchmark of the beam-scale stochastic model (issue 14): bank build, beams, and a rerun.

Target: 1 RH x 1000 beams of 1500 µm on a 1000-law bank in <= 10 min, and a rerun that reads the
bank back from its cache. Each patch law is one 64² patch at 40 nm (2.56 µm, about the §5.2
interaction-zone length = the beam thickness) of the Table 4 PSD (Eq. 37) through the modified
DMT. Times are printed with a machine-load yardstick measured in the same process: one 1024²
numpy complex iFFT (min of 5), so the figure can be rescaled to a quiet machine.

    nice -n 10 python benchmarks/bench_beam.py                 # 1000 laws, 1000 beams, RH 0.6
    python benchmarks/bench_beam.py --laws 100 --beams 1000    # quicker

The cohesive model (``rs.beam.simulate(beam_model="cohesive")``: Euler-Bernoulli beam on each patch's
law, here main's energy bank with the short-range law shape) is timed beside the sharp front on
``--cohesive-beams`` of the same beams (same seed, same patches), with the crack lengths of the
two models compared.
"""

from __future__ import annotations

import argparse
import tempfile
import time
import warnings

import numpy as np
from _yardstick import ifft_seconds

import roughstick as rs


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--laws", type=int, default=1000)
    ap.add_argument("--beams", type=int, default=1000)
    ap.add_argument("--rh", type=float, default=0.6)
    ap.add_argument("--shape", type=int, default=64)
    ap.add_argument("--spacing-nm", type=float, default=40.0)
    ap.add_argument("--cohesive-beams", type=int, default=20)
    ap.add_argument("--cache", default=None, help="cache folder (default: a fresh temporary one)")
    args = ap.parse_args()
    c = rs.stiction.cantilever_psd()
    psd = rs.surface.self_affine_psd(np.geomspace(1e5, 4e9, 400), s0=float(c.s0), s1=float(c.s1),
                             q0=float(c.q0), qmax=float(c.qmax))
    cache = args.cache or tempfile.mkdtemp(prefix="beam-bank-")
    y0 = ifft_seconds(5)
    kw = dict(relative_humidity=args.rh, n=args.laws, shape=(args.shape, args.shape),
              spacing=args.spacing_nm * 1e-9, seed=0, cache_dir=cache)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        bank = rs.beam.build_patch_bank(psd, **kw)
        t_bank = time.perf_counter() - t
        t = time.perf_counter()
        ds = rs.beam.simulate(bank, beam_length=1500e-6, n=args.beams, seed=1)
        t_beams = time.perf_counter() - t
        t = time.perf_counter()
        bank2 = rs.beam.build_patch_bank(psd, **kw)
        ds2 = rs.beam.simulate(bank2, beam_length=1500e-6, n=args.beams, seed=1)
        t_rerun = time.perf_counter() - t
        nc = args.cohesive_beams
        t = time.perf_counter()
        coh = rs.beam.simulate(bank, beam_length=1500e-6, n=nc, seed=1,
                               beam_model="cohesive")
        t_coh = time.perf_counter() - t
    y1 = ifft_seconds(5)
    ref = min(y0, y1)
    same = bool((ds.crack_length.fillna(-1) == ds2.crack_length.fillna(-1)).all())
    print(f"yardstick: 1024² complex iFFT {ref * 1e3:.1f} ms (before {y0 * 1e3:.1f}, after {y1 * 1e3:.1f})")
    print(f"bank: {args.laws} laws x 1 RH ({args.shape}² at {args.spacing_nm:g} nm) "
          f"{t_bank:.1f} s = {t_bank / ref:.0f} iFFTs; {t_bank / args.laws * 1e3:.0f} ms/law")
    print(f"beams: {args.beams} x 1500 µm {t_beams:.3f} s; first run total {t_bank + t_beams:.1f} s "
          f"(target 600 s)")
    print(f"rerun (bank read from cache + beams): {t_rerun:.2f} s, "
          f"from_cache={bank2.attrs['from_cache']}, identical={same}")
    sub = ds.isel(realization=slice(0, nc))
    d = (coh.crack_length - sub.crack_length).values * 1e6
    per_sf = t_beams / args.beams
    print(f"cohesive: {nc} x 1500 µm {t_coh:.1f} s = {t_coh / nc:.2f} s/beam "
          f"({t_coh / nc / per_sf:.0f} x the sharp front per beam; 1000 beams ~ "
          f"{t_coh / nc * 1000:.0f} s); solver_failed {int(coh.solver_failed.sum())}/{nc}; "
          f"s(cohesive) - s(sharp) [µm]: mean {np.nanmean(d):.1f}, "
          f"range [{np.nanmin(d):.1f}, {np.nanmax(d):.1f}]")
    g = bank.values[:, 0]
    print(f"patch Γ: median {np.median(g):.3g} J/m², 5-95 % [{np.quantile(g, 0.05):.3g}, "
          f"{np.quantile(g, 0.95):.3g}]; P(stuck) {float(ds.stuck_probability.squeeze()):.3f} "
          f"[{float(ds.stuck_probability_lower.squeeze()):.3f}, "
          f"{float(ds.stuck_probability_upper.squeeze()):.3f}]")


if __name__ == "__main__":
    main()
