"""Print the paper's Table 1 computed by roughstick next to the printed values.

Usage: ``python benchmarks/table1.py [--speed]``

All 18 cells (Maugis, DMT and modified DMT; RH 30/50/70 %; R = 100 and 800 nm), the relative
differences, the Maugis transition parameter of each column, and the same energies from a slow
literal integral of -F 1(F < 0) on a 200 001-point interference grid (an independent check of the
closed-form / Gauss-Legendre integration). ``--speed`` adds the throughput of the numpy force
kernel used by the Greenwood-Williamson model (ns per evaluation, one run on this machine).
"""

from __future__ import annotations

import sys
import time

import numpy as np
from scipy.integrate import trapezoid

import roughstick as rs
from roughstick.contact.sphere import _kernels

COLUMNS = [(0.3, 100e-9), (0.3, 800e-9), (0.5, 100e-9), (0.5, 800e-9), (0.7, 100e-9), (0.7, 800e-9)]
_T1 = rs.datasets.paper_table(1).adhesive_energy  # the paper's Table 1, bundled
PRINTED = {m: [float(_T1.sel(model=m, rh=rh, radius=r)) for rh, r in COLUMNS] for m in ("maugis", "dmt", "modified_dmt")}
LABEL = {"maugis": "Maugis", "dmt": "DMT", "modified_dmt": "Modified DMT"}


def literal(model, rh, radius, n=200_001):
    """Slow reference: trapezoid of -F 1(F<0) over a dense interference grid."""
    h = float(rs.contact.water_height(rh))
    d = np.linspace(-1.5 * h, 3e-9, n)
    f = rs.contact.sphere_force(d, sphere_model=model, radius=radius, relative_humidity=rh).values
    return trapezoid(np.where(f < 0, -f, 0.0), d)


def main(argv):
    head = " | ".join(f"RH{int(rh * 100)} R{int(r * 1e9)}nm" for rh, r in COLUMNS)
    print("Table 1: adhesive energy [J], computed / printed / relative difference")
    print(f"{'':14s}| {head}")
    worst = {}
    for model, row in PRINTED.items():
        comp = [float(rs.contact.sphere_adhesive_energy(sphere_model=model, radius=r, relative_humidity=rh)) for rh, r in COLUMNS]
        lit = [literal(model, rh, r) for rh, r in COLUMNS]
        rel = [c / p - 1 for c, p in zip(comp, row, strict=True)]
        worst[model] = max(abs(x) for x in rel)
        print(f"{LABEL[model]:14s}| " + " | ".join(f"{c:11.3e}" for c in comp))
        print(f"{'  printed':14s}| " + " | ".join(f"{p:11.3e}" for p in row))
        print(f"{'  rel. diff':14s}| " + " | ".join(f"{x:+11.2%}" for x in rel))
        print(f"{'  literal-1':14s}| " + " | ".join(f"{lt / c - 1:+11.1e}" for lt, c in zip(lit, comp, strict=True)))
    lam = [float(rs.contact.transition_parameter(radius=r, relative_humidity=rh)) for rh, r in COLUMNS]
    print(f"{'lambda (Eq. 7)':14s}| " + " | ".join(f"{x:11.4f}" for x in lam))
    print("largest |relative difference|: " + ", ".join(f"{LABEL[m]} {v:.2%}" for m, v in worst.items()))

    if "--speed" in argv:
        rng = np.random.default_rng(0)
        n = 200_000
        d = rng.uniform(-3e-9, 3e-9, n)
        R = rng.uniform(20e-9, 500e-9, n)
        K = rs.materials.hertz_modulus()
        print(f"\nforce kernel throughput, {n} random (delta, R) pairs at RH 50 %:")
        for model in _kernels.MODELS:
            _kernels.sphere_force_kernel(model, d[:1000], R[:1000], K, 96.05e6, 1.529e-9)
            t = time.perf_counter()
            _kernels.sphere_force_kernel(model, d, R, K, 96.05e6, 1.529e-9)
            dt = time.perf_counter() - t
            print(f"  {model:13s} {dt / n * 1e9:8.0f} ns per evaluation")


if __name__ == "__main__":
    main(sys.argv[1:])
