"""Speed against error of the modified DMT's automatic grid, with and without the per-humidity
Γ refinement (docs/rough_contact.md, automatic grid step 5).

    nice -n 5 python benchmarks/grid_refinement_tradeoff.py SIZE on|off

For one map of each of the five families (SIZE² pixels at 5 nm, seed 1) and six humidities:
the largest spread max/min - 1 of Γ(RH) over the call alone and within five other humidity sets,
the largest error of Γ(RH) alone against 8,000 uniform distances over the same range, and the
CPU time of the default call with six humidities (min of 3). ``off`` replaces the refinement by
the grid of the per-humidity controllers alone (what the refinement buys).
"""

import sys
import time
import warnings

import numpy as np
from grid_humidity_independence import SETS

import roughstick as rs
from roughstick.contact.modified_dmt import _grid as rough

HUMIDITIES = [0.1, 0.3, 0.5, 0.66, 0.7, 0.9]


def gamma(h, rh, **kw):
    return rs.contact.summary(rs.contact.curves(h, relative_humidity=rh, check_validity=False,
                                                       **kw)).adhesive_energy.values


def main(n, mode):
    warnings.simplefilter("ignore")
    if mode == "off":
        rough.refine_gamma = lambda z, d, out, mem, hw, dp, kw: (d, out)
    for fam in rs.datasets.FAMILIES:
        h = rs.datasets.surface_family(fam, shape=(n, n), seed=1)
        spread = error = 0.0
        for r in HUMIDITIES:
            grid = rs.contact.curves(h, relative_humidity=[r], check_validity=False).distance.values
            vals = [gamma(h, [r])[0]]
            for s in SETS:
                ss = sorted(set(s) | {r})
                vals.append(gamma(h, ss)[ss.index(r)])
            spread = max(spread, max(vals) / min(vals) - 1)
            ref = gamma(h, [r], distance=np.linspace(grid.min(), grid.max(), 8000))[0]
            error = max(error, abs(vals[0] / ref - 1))
        t = []
        for _ in range(3):
            t0 = time.process_time()
            rs.contact.curves(h, relative_humidity=[0.3, 0.5, 0.6, 0.7, 0.8, 0.9])
            t.append(time.process_time() - t0)
        print(f"{n} refine {mode} {fam}: spread over RH sets {spread:.2%}, alone vs 8000-pt grid "
              f"{error:.2%}, 6-RH default call {min(t) * 1e3:.0f} ms", flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]), sys.argv[2])
