"""Cost model of the boundary-element models (issue 16 item 2; not run by pytest).

The constants of ``roughstick/_core/progress.py`` (``BEM_SOLVE_FFTS``, ``FFT_BEM_STATE_FFTS``)
come from this script: the time of one Tamaas solve (``model="bem"``, one distance, one
humidity) and of one fft_bem state, each divided by the time of one ``rfft2`` + ``irfft2`` pair
of the same map timed in the same process (min of 5), so that the estimate printed before a run
is ``constant x (that FFT pair timed on the user's machine) x number of solves``.

    nice -n 19 python benchmarks/bench_bem_cost.py [--quick]
"""
from __future__ import annotations

import argparse
import time
import warnings

import roughstick as rs
from roughstick._core.progress import fft_pair_seconds


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    sizes = (64, 128) if args.quick else (64, 128, 256)
    families = ("S1", "rough") if args.quick else ("S1", "smooth", "rough")
    print("family  N    model    solves  seconds  s/solve   fft_pair_s   solve/fft_pair")
    for fam in families:
        for n in sizes:
            h = rs.datasets.surface_family(fam, shape=(n, n), seed=1)
            for model in ("bem", "fft_bem"):
                t_fft = fft_pair_seconds((n, n), repeats=5)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    t0 = time.perf_counter()
                    if model == "bem":
                        ds = rs.contact.bem_curves(h, relative_humidity=0.5, n_distance=8)
                        solves = int(ds.attrs["bem_solves"])
                    else:
                        ds = rs.contact.fft_bem_curves(h, relative_humidity=0.5)
                        solves = int(ds.attrs["states"])
                    dt = time.perf_counter() - t0
                t_fft = min(t_fft, fft_pair_seconds((n, n), repeats=5))
                per = dt / max(solves, 1)
                print(f"{fam:7s} {n:4d} {model:8s} {solves:6d} {dt:8.2f} {per:8.4f} "
                      f"{t_fft:12.2e} {per / t_fft:12.0f}", flush=True)


if __name__ == "__main__":
    main()
