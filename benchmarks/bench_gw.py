"""Greenwood–Williamson (Eq. 14): speed against error, and the numbers of docs/greenwood_williamson.md.

Run:  python benchmarks/bench_gw.py            (speed/error tables, about a minute)
      python benchmarks/bench_gw.py --paper    (also the Fig. 9 and Gamma tables, a few minutes)

1. Time of one set of curves (6 humidities x 200 distances, S1 moments of Table 3, modified DMT)
   against the quadrature resolution (n_height, n_curvature), with the largest relative error of
   the adhesive energy Gamma (Eq. 13) and of the pressure curve against a fine reference
   (n_height = 256, n_curvature = 192) computed in the same run.
2. The same for the Maugis and DMT summit models: direct kernel calls against the force table.
3. Gamma against the distance-grid step.
4. (--paper) The cutoff study of Fig. 9 and Gamma at RH 30..90 % for S1 and S2.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import xarray as xr

import roughstick as rs

NM = 1e-9
RH6 = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]


def moments(m0, m2, m4):
    return xr.Dataset(
        {"m0": ((), m0, {"units": "nm2"}), "m2": ((), m2, {"units": "1"}), "m4": ((), m4, {"units": "nm-2"})}
    )


S1 = moments(15.7, 0.040, 5.08e-4)
S2 = moments(4.32, 0.021, 3.99e-4)


def gamma(p):
    return -np.trapezoid(np.minimum(p.values, 0.0), p["distance"].values, axis=-1)


def timed(fn, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def speed_vs_error(ds, label, cutoff):
    d = np.linspace(-2, 30, 200) * NM
    print(f"\n## {label}, height_cutoff={cutoff}: 6 RH x 200 distances, modified DMT per summit")
    ref = rs.contact.gw_curves(ds, relative_humidity=RH6, distance=d, height_cutoff=cutoff,
                               n_height=256, n_curvature=192)
    g_ref = gamma(ref.pressure)
    ok = g_ref > 1e-9  # J m-2: humidities where GW predicts any stiction at all
    scale = np.abs(ref.pressure.values).max(axis=-1, keepdims=True)
    print(f"(Gamma errors over RH with Gamma_ref > 1e-9 J m-2: {np.asarray(RH6)[ok]})")
    print(f"{'n_height':>8} {'n_curv':>7} {'time [s]':>9} {'max rel err Gamma':>18} "
          f"{'max |dp|/max|p|':>16}")
    for nh, nk in [(8, 6), (12, 8), (16, 12), (24, 16), (32, 24), (48, 32), (64, 48)]:
        t, c = timed(lambda nh=nh, nk=nk: rs.contact.gw_curves(
            ds, relative_humidity=RH6, distance=d, height_cutoff=cutoff, n_height=nh, n_curvature=nk))
        eg = np.max(np.abs(gamma(c.pressure)[ok] / g_ref[ok] - 1))
        ep = np.max(np.abs(c.pressure.values - ref.pressure.values) / scale)
        mark = "  <- default" if (nh, nk) == (32, 24) else ""
        print(f"{nh:8d} {nk:7d} {t:9.3f} {eg:18.2e} {ep:16.2e}{mark}")


def models_table():
    d = np.linspace(-2, 30, 200) * NM
    print("\n## summit models, S1, cutoff 2.5 sqrt(m0), 6 RH x 200 distances: direct kernel vs table")
    print(f"{'model':>13} {'force_table':>11} {'time [s]':>9} {'max rel err Gamma vs direct':>28}")
    for model in ("modified_dmt", "dmt", "maugis"):
        t0, direct = timed(lambda model=model: rs.contact.gw_curves(
            S1, relative_humidity=RH6, distance=d, height_cutoff=2.5, sphere_model=model,
            force_table=0), repeat=1)
        g0 = gamma(direct.pressure)
        print(f"{model:>13} {'0 (direct)':>11} {t0:9.3f} {'-':>28}")
        for tab in (64, 256):
            t, c = timed(lambda model=model, tab=tab: rs.contact.gw_curves(
                S1, relative_humidity=RH6, distance=d, height_cutoff=2.5, sphere_model=model,
                force_table=tab), repeat=1)
            print(f"{model:>13} {tab:11d} {t:9.3f} {np.max(np.abs(gamma(c.pressure) / g0 - 1)):28.2e}"
                  f"   ({t0 / t:.0f}x faster)")


def distance_step_table():
    print("\n## Gamma (mJ m-2) vs distance-grid step, S1, cutoff 2.5 sqrt(m0), d in [-2, 40] nm")
    print(f"{'step [nm]':>9} {'time [s]':>9}  " + " ".join(f"{'RH ' + str(int(r * 100)):>10}" for r in RH6))
    for step in (0.4, 0.2, 0.1, 0.05, 0.025):
        d = np.arange(-2, 40 + step / 2, step) * NM
        t, c = timed(lambda d=d: rs.contact.gw_curves(S1, relative_humidity=RH6, distance=d,
                                                      height_cutoff=2.5), repeat=1)
        print(f"{step:9.3f} {t:9.3f}  " + " ".join(f"{g * 1e3:10.5f}" for g in gamma(c.pressure)))


def paper_tables():
    d = np.arange(-5, 45.0001, 0.02) * NM
    print("\n## Fig. 9: Gamma (mJ m-2) vs height cutoff h_max/sqrt(m0), S1, d step 0.02 nm")
    cuts = [2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0, 6.5, 7.0, None]
    st = rs.contact.gw_cutoff_study(S1, relative_humidity=[0.3, 0.9], distance=d, height_cutoffs=cuts)
    g = gamma(st.pressure)
    pmin = st.pressure.min("distance").values / 1e6
    print(f"{'h_max':>8} {'Gamma RH30':>12} {'Gamma RH90':>12} {'p_min RH30 [MPa]':>17} {'p_min RH90':>11}")
    for i, c in enumerate(cuts):
        lab = "none" if c is None else f"{c:g}"
        print(f"{lab:>8} {g[i, 0] * 1e3:12.4e} {g[i, 1] * 1e3:12.4e} {pmin[i, 0]:17.4e} {pmin[i, 1]:11.3f}")
    print("\n## Gamma (mJ m-2), max tension (MPa) and max wet fraction vs RH, d step 0.02 nm")
    for name, ds in (("S1", S1), ("S2", S2)):
        for cut in (None, 2.5):
            c = rs.contact.gw_curves(ds, relative_humidity=RH6, distance=d, height_cutoff=cut)
            g = gamma(c.pressure) * 1e3
            pm = -c.pressure.min("distance").values / 1e6
            wf = c.wet_fraction.max("distance").values
            lab = f"{name} cutoff {'none' if cut is None else cut}"
            print(f"{lab:>18}  Gamma " + " ".join(f"{x:10.4g}" for x in g))
            print(f"{'':>18}  -pmin " + " ".join(f"{x:10.4g}" for x in pm))
            print(f"{'':>18}  wetmx " + " ".join(f"{x:10.4g}" for x in wf))
    print("   (RH columns:", ", ".join(f"{int(r * 100)} %" for r in RH6), ";",
          "|dP| [MPa]:", ", ".join(f"{abs(float(rs.contact.laplace_pressure(r))) / 1e6:.1f}" for r in RH6), ")")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--paper", action="store_true", help="also print the Fig. 9 and Gamma tables")
    args = ap.parse_args()
    speed_vs_error(S1, "S1", None)
    speed_vs_error(S1, "S1", 2.5)
    models_table()
    distance_step_table()
    if args.paper:
        paper_tables()


if __name__ == "__main__":
    main()
