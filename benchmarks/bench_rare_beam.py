"""Benchmark: P(stuck) of the beam-scale model at about 1e-4 by subset simulation (issue 15,
must-be-true 2, on the beam limit state).

    nice -n 10 python benchmarks/bench_rare_beam.py [--target 1e-4] [--laws 200000] [--repeat 100]
        [--samples-per-level 900] [--seed 1000] [--level-probability 0.2] [--target-acceptance 0.44]

Case: the paper's cantilever (Table 4) with the sharp-front beam model on a bank of ``--laws``
log-normal patch energies (median 10 mJ/m², log-sd 0.5, as tests/reliability/test_beam_limit_state.py), at
the beam length where the bank's exact P(stuck) = 1 - prod_j (1 - q_j) is ``--target`` (computed
here from Eq. 36's equilibrium positions, independently of the package). Runs
``rs.stuck_probability(bank, method="subset")`` once per seed with no stopping rule (one subset run of
``--samples-per-level`` beams per level) and prints, against the exact value: the mean estimate,
the true cv of one run (rms error / P, with a chi-square interval), the mean reported cv, the 95 %
interval's coverage, the evaluations (mean and largest) and the wall time per run, also as a
multiple of one 1024² iFFT. Crude Monte Carlo would need 1/(P cv²) beams for the same cv.

The stuck set is {z : z_j > c_j for some patch j} whatever the bank (laws sorted by energy, drawn
as Φ(z_j)): the bank only sets the c_j, so this geometry, and the estimator's cost on it, is that
of any bank of this beam. The surface limit state P(Γ > Γ_crit) is another geometry and another
cost: benchmarks/bench_rare_events.py.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
import xarray as xr
from _yardstick import ifft_seconds, spread_interval
from scipy.optimize import brentq

import roughstick as rs
from roughstick.stiction.cantilever import PAPER_CANTILEVER

K = PAPER_CANTILEVER.stiffness_term
PATCH = PAPER_CANTILEVER.interaction_zone_length


def exact_stuck(energy, length):
    """1 - prod_j (1 - q_j): q_j the fraction of laws whose Eq. 36 equilibrium lies before patch
    j's far edge."""
    m = int(np.ceil(length / PATCH - 1e-9))
    far_edge = np.minimum((np.arange(m) + 1) * PATCH, length)
    q = ((K / energy)[None, :] ** 0.25 < far_edge[:, None]).mean(axis=1)
    return float(-np.expm1(np.sum(np.log1p(-q))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--target", type=float, default=1e-4)
    ap.add_argument("--laws", type=int, default=200_000)
    ap.add_argument("--repeat", type=int, default=100)
    ap.add_argument("--samples-per-level", type=int, default=900)
    ap.add_argument("--seed", type=int, default=1000)
    ap.add_argument("--level-probability", type=float, default=0.2)
    ap.add_argument("--target-acceptance", type=float, default=0.44)
    args = ap.parse_args()
    warnings.simplefilter("ignore", rs.ValidityWarning)
    energy = np.exp(np.random.default_rng(7).normal(np.log(0.01), 0.5, size=args.laws))
    bank = xr.DataArray(energy[:, None], dims=("law", "rh"), coords={"rh": [0.5]})
    with np.errstate(divide="ignore"):  # P = 0 below the shortest beam any law can hold
        length = brentq(lambda x: np.log(exact_stuck(energy, x)) - np.log(args.target), 100e-6, 300e-6, xtol=1e-12)
    exact = exact_stuck(energy, length)
    unit = ifft_seconds()
    print(f"case: sharp-front beam of {length * 1e6:.3f} um ({int(np.ceil(length / PATCH - 1e-9))} patches), "
          f"bank of {args.laws} log-normal laws, exact P(stuck) = {exact:.3e}; "
          f"N = {args.samples_per_level} per level, p0 {args.level_probability}, target acceptance "
          f"{args.target_acceptance}, one run per seed, no stopping rule", flush=True)
    ps, cvs, ns, walls, cover = [], [], [], [], 0
    for s in range(args.seed, args.seed + args.repeat):
        t0 = time.perf_counter()
        ds = rs.stuck_probability(bank, method="subset", beam_length=length, n_per_level=args.samples_per_level,
                                                 seed=s, target_cv=None, level_probability=args.level_probability,
                                                 target_acceptance=args.target_acceptance).squeeze()
        walls.append(time.perf_counter() - t0)
        ps.append(float(ds.stiction_probability))
        cvs.append(float(ds.coefficient_of_variation))
        ns.append(int(ds.n_evaluations))
        cover += float(ds.stiction_probability_lower) <= exact <= float(ds.stiction_probability_upper)
    ps = np.array(ps)
    k = ps.size
    true_cv = float(np.sqrt(np.mean((ps - exact) ** 2)) / exact)
    lo, hi = spread_interval(true_cv, k)
    print(f"{k} runs: mean P = {ps.mean():.3e} ± {ps.std(ddof=1) / np.sqrt(k):.1e} (s.e.), exact {exact:.3e}; "
          f"true cv of one run (rms error / P) {true_cv:.3f}, 95% [{lo:.3f}, {hi:.3f}]; mean reported cv "
          f"{np.mean(cvs):.3f}; 95% interval coverage {cover}/{k}")
    print(f"evaluations per run: mean {np.mean(ns):.0f}, largest {max(ns)}; wall per run {np.mean(walls):.2f} s = "
          f"{np.mean(walls) / unit:.0f} x one 1024^2 iFFT; crude Monte Carlo for the same cv: "
          f"{1 / (exact * true_cv**2):.2e} beams")


if __name__ == "__main__":
    main()
