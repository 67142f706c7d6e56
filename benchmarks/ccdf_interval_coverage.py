"""Benchmark: coverage of P(stuck) intervals built from a sample of strip energies.

    python benchmarks/ccdf_interval_coverage.py [--samples 200] [--bootstrap 400]

Γ of the strips follows a known law (exponential, mean 1.5 mJ m-2; log-normal, median 1 mJ m-2,
σ 1), so P(stuck) of the paper's beam at 200-300 µm (sharp front, release) is exact from its
CCDF. For n = 40 and 200 strips, ``--samples`` samples are drawn; each gives the 95 % interval of
``rs.beam.stuck_probability_from_ccdf`` (the CCDF's simultaneous DKW band carried through) and a
95 % percentile-bootstrap interval over the strips. Printed: the pointwise coverage of each, and
how often all five lengths are covered at once, and the mean width of each interval.
"""

from __future__ import annotations

import argparse

import numpy as np
import xarray as xr
from scipy import stats

import roughstick as rs

LENGTHS = np.array([200e-6, 225e-6, 250e-6, 275e-6, 300e-6])
LAWS = {"exponential": stats.expon(scale=1.5e-3), "log-normal": stats.lognorm(s=1.0, scale=1e-3)}


def exact(law):
    beam = rs.stiction.PAPER_CANTILEVER
    dx = beam.interaction_zone_length
    out = []
    for length in LENGTHS:
        hi = np.minimum((np.arange(int(np.ceil(length / dx - 1e-9))) + 1) * dx, length)
        out.append(-np.expm1(np.sum(np.log1p(-law.sf(beam.stiffness_term / hi**4)))))
    return np.array(out)


def p_stuck(values):
    """P(stuck) with its DKW interval for each row of ``values`` (rows, n)."""
    g = xr.DataArray(values, dims=("row", "realization"), attrs={"units": "J m-2"})
    p = rs.beam.stuck_probability_from_ccdf(rs.beam.adhesive_energy_ccdf(g), beam_length=LENGTHS)
    return (p.stuck_probability.values, p.stuck_probability_lower.values, p.stuck_probability_upper.values)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--samples", type=int, default=200)
    ap.add_argument("--bootstrap", type=int, default=400)
    args = ap.parse_args()
    rng = np.random.default_rng(1)
    for name, law in LAWS.items():
        truth = exact(law)
        for n in (40, 200):
            dkw, boot = np.zeros(LENGTHS.size), np.zeros(LENGTHS.size)
            dkw_width, boot_width = np.zeros(LENGTHS.size), np.zeros(LENGTHS.size)
            dkw_all = boot_all = 0
            for _ in range(args.samples):
                x = law.rvs(size=n, random_state=rng)
                _, lo, hi = p_stuck(x[None, :])
                inside = (lo[0] <= truth) & (truth <= hi[0])
                dkw += inside
                dkw_all += inside.all()
                dkw_width += hi[0] - lo[0]
                pb, _, _ = p_stuck(x[rng.integers(0, n, (args.bootstrap, n))])
                blo, bhi = np.quantile(pb, [0.025, 0.975], axis=0)
                inside = (blo <= truth) & (truth <= bhi)
                boot += inside
                boot_all += inside.all()
                boot_width += bhi - blo
            s = args.samples
            print(f"{name:>11}, n = {n:3d}: P exact {' / '.join(f'{v:.3g}' for v in truth)}")
            print(f"{'':>20} DKW band coverage {' / '.join(f'{v / s:.2f}' for v in dkw)} (all at once "
                  f"{dkw_all / s:.2f}), mean width {' / '.join(f'{v / s:.2f}' for v in dkw_width)}")
            print(f"{'':>20} bootstrap coverage {' / '.join(f'{v / s:.2f}' for v in boot)} (all at once "
                  f"{boot_all / s:.2f}), mean width {' / '.join(f'{v / s:.2f}' for v in boot_width)}")


if __name__ == "__main__":
    main()
