"""A designer's question: at which RH does P(stuck) of a beam reach 1e-3? (docs/rare_events.md)

    nice -n 10 python examples/small_stiction_probability.py [--length 200e-6] [--shape 128 128]
        [--model fft_bem]

P(Γ > Γ_crit(l)) (Eq. 13 on Table-4 zones, Eq. 36 for the beam) by subset simulation at each RH
of a sweep, each stopped at cv <= 0.3 (or 6,000 evaluations), then the crossing of 1e-3 with its
interval (rs.stiction.crossing_humidity on the estimate and its 95 % bounds). Writes the result
to --output (NetCDF) and prints one line per RH, with the fraction of failure states the FFT-BEM
confirms. Use --model fft_bem on these zones: the Eq. 16 tail is made of artefacts there
(docs/rare_events.md).
"""

from __future__ import annotations

import argparse
import time
import warnings

import roughstick as rs


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--length", type=float, default=200e-6)
    ap.add_argument("--shape", type=int, nargs=2, default=(128, 128))
    ap.add_argument("--rh", type=float, nargs="+", default=[0.5, 0.6, 0.65, 0.7])
    ap.add_argument("--n-per-level", type=int, default=500)
    ap.add_argument("--target-cv", type=float, default=0.3, help="0: no stopping rule")
    ap.add_argument("--max-evaluations", type=int, default=6000)
    ap.add_argument("--probability", type=float, default=1e-3)
    ap.add_argument("--output", default="small_stiction_probability.nc")
    ap.add_argument("--model", default="modified_dmt", choices=("modified_dmt", "fft_bem"))
    args = ap.parse_args()
    warnings.simplefilter("ignore", rs.ValidityWarning)  # Table-4 zones at 86.6 GPa: see docs/accuracy.md
    psd = rs.datasets.family_psd("table4")
    t0 = time.perf_counter()
    ds = rs.stuck_probability(
        psd, method="subset", relative_humidity=args.rh, shape=tuple(args.shape), spacing=5e-9,
        beam_length=args.length, n_per_level=args.n_per_level, target_cv=args.target_cv or None,
        max_evaluations=args.max_evaluations, seed=15, model=args.model)
    wall = time.perf_counter() - t0
    print(f"beam length {args.length * 1e6:.0f} um, Gamma_crit = {ds.attrs['critical_adhesive_energy'] * 1e3:.3f} "
          f"mJ/m2, zones {args.shape[0]}x{args.shape[1]} px at 5 nm, {args.model}, wall {wall:.0f} s")
    for i, rh in enumerate(ds.rh.values):
        d = ds.isel(rh=i)
        print(f"RH {rh:.2f}: P = {float(d.stiction_probability):.3e} 95% [{float(d.stiction_probability_lower):.3e}, "
              f"{float(d.stiction_probability_upper):.3e}] cv {float(d.coefficient_of_variation):.2f} "
              f"evaluations {int(d.n_evaluations)} converged {int(d.converged)}"
              + (f" confirmed by the FFT-BEM {float(d.failures_confirmed_by_bem):.2f}, median BEM/Eq. 16 "
                 f"{float(d.failure_bem_ratio):.2f}" if "failure_bem_ratio" in d else ""))
    ch = rs.stiction.crossing_humidity(ds[["stiction_probability", "stiction_probability_lower",
                                           "stiction_probability_upper"]], probability=args.probability)
    print(f"P(stuck) reaches {args.probability:g} at RH {float(ch.crossing_humidity):.3f} "
          f"[{float(ch.crossing_humidity_lower):.3f}, {float(ch.crossing_humidity_upper):.3f}]")
    keep = ds[["stiction_probability", "stiction_probability_lower", "stiction_probability_upper",
               "coefficient_of_variation", "n_evaluations", "converged"]]
    rs.io.write(keep, args.output, compute=True, overwrite=True)  # this script's own output file


if __name__ == "__main__":
    main()
