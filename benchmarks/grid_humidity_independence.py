"""Γ of one humidity alone and within other humidity sets, on the modified DMT's automatic grid.

    python benchmarks/grid_humidity_independence.py S1,S2,table4,smooth,rough 128

prints, per family, map and RH, the spread max/min - 1 of Γ(RH) over the call alone and in 5 sets.
"""
import warnings, numpy as np, roughstick as rs, sys, itertools
warnings.simplefilter("ignore")
n = int(sys.argv[2]) if len(sys.argv)>2 else 128
G = lambda c: rs.adhesion_summary(c).adhesive_energy.values
sets = [[0.1,0.5,0.9],[0.3,0.5,0.7],[0.2,0.4,0.6,0.8],[0.05,0.5,0.95],[0.5,0.65,0.66]]
for fam in sys.argv[1].split(","):
  for seed in (1,2):
    h = rs.datasets.surface_family(fam, shape=(n,n), seed=seed)
    worst = 0
    for r in [0.05,0.1,0.2,0.3,0.4,0.5,0.6,0.65,0.66,0.7,0.8,0.9,0.95]:
        alone = G(rs.rough_contact_curves(h, relative_humidity=[r], check_validity=False))[0]
        vals = [alone]
        for s in sets:
            ss = sorted(set(s)|{r})
            c = rs.rough_contact_curves(h, relative_humidity=ss, check_validity=False)
            vals.append(G(c)[ss.index(r)])
        vals=np.array(vals); spread = vals.max()/vals.min()-1
        worst=max(worst,spread)
        print(f"{fam} seed{seed} rh={r}: alone {alone:.5g} spread {spread:.3%}", flush=True)
    print(f"== {fam} seed{seed} worst spread {worst:.3%}", flush=True)
