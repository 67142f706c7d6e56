"""Γ of one humidity alone and within other humidity sets, on the modified DMT's automatic grid.

    python benchmarks/grid_humidity_independence.py S1,S2,table4,smooth,rough 128

prints, per family, map and RH, the spread max/min - 1 of Γ(RH) over the call alone and in 5 sets
(docs/rough_contact.md, item 5 of the automatic grid).
"""

import sys
import warnings

import roughstick as rs

SETS = [[0.1, 0.5, 0.9], [0.3, 0.5, 0.7], [0.2, 0.4, 0.6, 0.8], [0.05, 0.5, 0.95], [0.5, 0.65, 0.66]]
HUMIDITIES = [0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.65, 0.66, 0.7, 0.8, 0.9, 0.95]


def gamma(curves):
    return rs.adhesion_summary(curves).adhesive_energy.values


def main(families, n):
    warnings.simplefilter("ignore")
    for fam in families:
        for seed in (1, 2):
            h = rs.datasets.surface_family(fam, shape=(n, n), seed=seed)
            worst = 0.0
            for r in HUMIDITIES:
                alone = gamma(rs.rough_contact_curves(h, relative_humidity=[r], check_validity=False))[0]
                vals = [alone]
                for s in SETS:
                    ss = sorted(set(s) | {r})
                    c = rs.rough_contact_curves(h, relative_humidity=ss, check_validity=False)
                    vals.append(gamma(c)[ss.index(r)])
                spread = max(vals) / min(vals) - 1
                worst = max(worst, spread)
                print(f"{fam} seed{seed} rh={r}: alone {alone:.5g} spread {spread:.3%}", flush=True)
            print(f"== {fam} seed{seed} worst spread {worst:.3%}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1].split(",") if len(sys.argv) > 1 else ["S1", "S2", "table4", "smooth", "rough"],
         int(sys.argv[2]) if len(sys.argv) > 2 else 128)
