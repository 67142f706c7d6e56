"""Γ of the modified DMT over Γ of the FFT boundary-element model on one map per family, for
Young's moduli from soft polymers to poly-silicon (docs/rough_contact.md, soft materials):

    python benchmarks/soft_material_scan.py S1 1e9,2e9,5e9,10e9,20e9,50e9,164e9 [64]

prints the pressure ratio |ΔP|/(E* rms slope), the Maugis parameter of the mean summit, both Γ,
their ratio, the modified DMT's d_eq and whether fft_bem converged.
"""

import sys
import warnings

import numpy as np

import roughstick as rs

RH = [0.1, 0.3, 0.5, 0.7, 0.9]


def main(families, moduli, n=64):
    warnings.simplefilter("ignore")
    for fam in families:
        h = rs.datasets.surface_family(fam, shape=(n, n), seed=1)
        for E in moduli:
            m = rs.Material(youngs_modulus=E, poisson_ratio=0.3, name="x")
            g = rs.contact.surface_groups(h, relative_humidity=RH, material=m)
            sm = rs.contact.summary(rs.contact.curves(
                h, relative_humidity=RH, model="modified_dmt", material=m, check_validity=False))
            with warnings.catch_warnings(record=True) as w:
                warnings.simplefilter("always")
                cf = rs.contact.curves(h, relative_humidity=RH, model="fft_bem", material=m,
                                             max_iterations=3000)
            sf = rs.contact.summary(cf)
            unconverged = any("far from convergence" in str(x.message) for x in w)
            for i, r in enumerate(RH):
                a, b = float(sm.adhesive_energy[i]), float(sf.adhesive_energy[i])
                print(f"{fam:7s} E={E / 1e9:6.1f} rh={r:.1f} pr={float(g.pressure_ratio[i]):.4f} "
                      f"lam={float(g.maugis_lambda[i]):.3f} Gdmt={a:.4g} Gfft={b:.4g} "
                      f"ratio={a / b if b > 0 else np.inf:.3g} "
                      f"deq_dmt={float(sm.equilibrium_distance[i]) * 1e9:.2f} "
                      f"unconv={unconverged}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1].split(","), [float(a) for a in sys.argv[2].split(",")],
         int(sys.argv[3]) if len(sys.argv) > 3 else 64)
