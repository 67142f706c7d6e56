"""Benchmark: is the Eq. 16 tail of a patch-law bank physical? (the beam-scale model, docs/beam.md)

    nice -n 10 python benchmarks/bench_bank_tail.py [--laws 3000] [--shape 32 32] [--spacing 20e-9]
        [--rh 0.3 0.6 0.9] [--top 16] [--family beam S1 S2 table4 smooth rough]
        [--beams 1000 --lengths 150 200 250 300]

A bank of the beam command (``rs.beam.build_patch_bank``, Table-4 PSD of ``roughstick beam``, the
modified DMT of Eq. 16, the tail check switched off; ``--family``: the five surface families of
``rs.datasets`` instead) is ranked at each RH, and its ``--top``
largest laws plus the laws at P = 1e-2, 0.1, 0.25 and 0.5 are re-evaluated with the FFT
boundary-element model (``rough_contact_curves(model="fft_bem")``). The largest laws set the beam's
small P(stuck): a released front stops at the first patch able to hold it. Prints, per RH, each
rank's Eq. 16 and BEM energies and their ratio, and the median ratio over the top ranks (what
``build_patch_bank(check_tail=8)`` reports as ``tail_bem_ratio``); and the cost of one law with
each model, as a multiple of one rfft2 + irfft2 pair of the patch timed in the same process.
With ``--beams N``: the whole bank is also computed with the FFT-BEM (the same patches) and
``rs.beam.simulate`` draws the same N beams per length from both banks: P(stuck) of the
beam-scale model on each, with 95 % Wilson intervals (what the tail error does to the beams).
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

import roughstick as rs
from roughstick._core.progress import fft_pair_seconds
from roughstick.cli.beam import _psd


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--laws", type=int, default=3000)
    ap.add_argument("--shape", type=int, nargs=2, default=(32, 32))
    ap.add_argument("--spacing", type=float, default=20e-9)
    ap.add_argument("--rh", type=float, nargs="+", default=(0.3, 0.6, 0.9))
    ap.add_argument("--top", type=int, default=16)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--beams", type=int, default=0, help="N beams per length on both banks")
    ap.add_argument("--lengths", type=float, nargs="+", default=(150, 200, 250, 300), help="beam lengths [um]")
    ap.add_argument("--family", nargs="+", default=["beam"],
                    choices=("beam",) + rs.datasets.FAMILIES, help="'beam': the beam command's Table-4 PSD")
    args = ap.parse_args()
    warnings.filterwarnings("ignore", category=rs.ValidityWarning)  # Eq. 16 outside validity: the point
    warnings.filterwarnings("ignore", message="patches of")  # independence of patches: not the point here
    for family in args.family:
        if len(args.family) > 1:
            print(f"=== family {family}")
        psd = _psd({}) if family == "beam" else rs.surface.self_affine_psd(
            np.geomspace(1e5, 4e9, 400), **rs.datasets.family_parameters(family))
        args.label = "the beam command's Table-4 PSD" if family == "beam" else f"family {family}"
        one_family(psd, args)


def one_family(psd, args):
    shape = tuple(args.shape)
    t0 = time.perf_counter()
    bank = rs.beam.build_patch_bank(psd, relative_humidity=list(args.rh), n=args.laws, shape=shape,
                               spacing=args.spacing, seed=args.seed, check_tail=0)
    t_dmt = (time.perf_counter() - t0) / args.laws
    print(f"bank: {args.laws} laws of {shape[0]}x{shape[1]} px at {args.spacing * 1e9:g} nm, Table-4 PSD, "
          f"RH {list(args.rh)}, Eq. 16, in {t_dmt * args.laws:.1f} s")
    n = args.laws
    ranks = list(range(1, args.top + 1)) + [r for r in (n // 100, n // 10, n // 4, n // 2) if r > args.top]
    t_bem, n_bem = 0.0, 0
    for j, rh in enumerate(bank.rh.values):
        g = bank.values[:, j]
        order = np.argsort(g, kind="stable")[::-1]
        laws = order[np.asarray(ranks) - 1]
        surf = rs.surface.generate_surfaces(psd, realizations=laws, shape=shape, spacing=args.spacing,
                                    seed=args.seed).compute(scheduler="sync")
        print(f"RH {rh:g}:  rank  P(law above)  Eq.16 Gamma  FFT-BEM Gamma [mJ/m2]  BEM/Eq.16")
        ratios = []
        for k, (r, law) in enumerate(zip(ranks, laws)):
            t1 = time.perf_counter()
            c = rs.contact.curves(surf.isel(realization=k), relative_humidity=[float(rh)],
                                        model="fft_bem", check_validity=False)
            b = float(rs.contact.summary(c)["adhesive_energy"].squeeze())
            t_bem += time.perf_counter() - t1
            n_bem += 1
            ratios.append(b / g[law])
            print(f"       {r:5d}  {r / n:11.1e}  {g[law] * 1e3:11.2f}  {b * 1e3:14.2f}  {ratios[-1]:9.2f}",
                  flush=True)
        print(f"RH {rh:g}: median BEM/Eq.16 over the top {args.top}: {np.median(ratios[:args.top]):.2f}"
              + (f"; over the top 8: {np.median(ratios[:8]):.2f}" if args.top > 8 else ""))
    if args.beams:
        compare_beams(bank, psd, shape, args)
    pair = fft_pair_seconds(shape, repeats=20)
    per_rh = t_dmt / len(args.rh)
    print(f"one law at one RH: Eq. 16 {per_rh * 1e3:.2f} ms = {per_rh / pair:.0f} x one FFT pair of the patch; "
          f"FFT-BEM {t_bem / n_bem * 1e3:.2f} ms = {t_bem / n_bem / pair:.0f} x ({t_bem / n_bem / per_rh:.1f} x Eq. 16)")


def compare_beams(bank, psd, shape, args):
    """P(stuck) of the same beams on the Eq. 16 bank and on the BEM bank of the same patches."""
    t0 = time.perf_counter()
    bem = rs.beam.build_patch_bank(psd, relative_humidity=list(bank.rh.values), n=bank.sizes["law"], shape=shape,
                              spacing=args.spacing, seed=args.seed, model="fft_bem")
    print(f"BEM bank of the same {bank.sizes['law']} patches in {time.perf_counter() - t0:.1f} s")
    lengths = np.asarray(args.lengths) * 1e-6
    got = {m: rs.beam.simulate(b, beam_length=lengths, n=args.beams, seed=1)
           for m, b in (("Eq. 16", bank), ("FFT-BEM", bem))}
    print(f"P(stuck) of {args.beams} beams per length (the same patch draws on both banks), 95 % Wilson:")
    for rh in bank.rh.values:
        for length in lengths:
            row = []
            for m, ds in got.items():
                d = ds.sel(rh=rh, beam_length=length)
                row.append(f"{m} {float(d.stuck_probability):.3f} [{float(d.stuck_probability_lower):.3f}, "
                           f"{float(d.stuck_probability_upper):.3f}]")
            print(f"  RH {rh:g} l {length * 1e6:5.0f} um: " + "   ".join(row))


if __name__ == "__main__":
    main()
