"""Speed and answers of the FFT boundary-element model's default call (the speed-up).

Per case (map x size), in one process: the default call ``rs.contact.fft_bem_curves(height,
relative_humidity=RH)`` of this code (``new``) and of the code before the speed-up (``old``: the
frozen kernels of benchmarks/_fft_bem_kernels_v0.py swapped into the same wrapper), each timed
best of ``--repeat``, and the tight reference (``old`` kernels at tolerance 1e-4, double
precision, timed once). Printed per case and call: states, FFT pairs (``rfft2`` + ``irfft2``),
conjugate-gradient iterations, wall seconds and seconds / one 1024² complex iFFT timed in the same
process (benchmarks/_yardstick.py, best of 5, re-timed before every case); then Γ (Eq. 13), the
pull-off and d_eq per humidity and the largest relative difference over the humidities of new
and old to the tight reference, and of new to old.

    nice -n 5 python benchmarks/bench_fft_bem_speed.py                     # all cases, 512² and 1024²
    python benchmarks/bench_fft_bem_speed.py --sizes 512 --maps S2A smooth  # a subset
    python benchmarks/bench_fft_bem_speed.py --cache /tmp/refs.json         # reuse tight references

Maps: S1A and S2A (bundled 1024² samples at 5 nm; cropped to the size), the Table 4, smooth and
rough families (``surface_family(name, shape=(n, n), seed=1)``), and ``untuned``: a self-affine
map nobody tuned the solver on (Hurst 0.35, rms 5 nm, roll-off 1e8 rad/m, 3 nm pixels, seed 7).
``--cache FILE`` keeps the tight references (keyed by map, size and humidities) in a JSON file:
the 1024² tight solves take minutes each.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import json
import pathlib
import sys
import time
import warnings

import numpy as np
from _yardstick import ifft_seconds

import roughstick as rs

HERE = pathlib.Path(__file__).resolve().parent
RH = (0.3, 0.5, 0.6, 0.7, 0.8, 0.9)
MAPS = ("S1A", "S2A", "table4", "smooth", "rough", "untuned")
QUANT = ("adhesive_energy", "pull_off_pressure", "equilibrium_distance")
SHORT = {"adhesive_energy": "Γ", "pull_off_pressure": "pull-off", "equilibrium_distance": "d_eq"}


def height_map(name, n):
    if name in ("S1A", "S2A"):
        h = rs.datasets.load_sample(name)
        if h.sizes["y"] < n or h.sizes["x"] < n:
            raise ValueError(f"{name} has {dict(h.sizes)} pixels, fewer than {n}")
        return h.isel(y=slice(0, n), x=slice(0, n))
    if name == "untuned":
        q0, qmax, hurst, rms = 1e8, np.pi / 3e-9, 0.35, 5e-9
        s1_over_s0 = (qmax / q0) ** (-2 * (1 + hurst))
        m0 = float(rs.self_affine_moments(s0=1.0, s1=s1_over_s0, q0=q0, qmax=qmax).m0)
        s0 = rms**2 / m0
        psd = dict(s0=s0, s1=s0 * s1_over_s0, q0=q0, qmax=qmax)
        ens = rs.generate_surfaces(lambda q: rs.self_affine_psd(q, **psd), n=1, shape=(n, n),
                                   spacing=3e-9, seed=7)
        return ens.isel(realization=0).compute()
    return rs.datasets.surface_family(name, shape=(n, n), seed=1)


def _wrapper_module():
    return importlib.import_module("roughstick.contact.fft_bem._curves")


@contextlib.contextmanager
def old_kernels():
    """The wrapper with the kernels before the speed-up (the module the wrapper calls ``_k``)."""
    sys.path.insert(0, str(HERE))
    import _fft_bem_kernels_v0 as v0

    mod = _wrapper_module()
    new = mod._k
    mod._k = v0
    try:
        yield
    finally:
        mod._k = new


def run(h, rh, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        ds = rs.contact.fft_bem_curves(h, relative_humidity=list(rh), **kw)
        dt = time.perf_counter() - t
        s = rs.contact.summary(ds)
    out = {q: [float(v) for v in np.atleast_1d(s[q].values)] for q in QUANT}
    out.update(seconds=dt, fft_calls=int(ds.attrs["fft_calls"]), states=int(ds.attrs["states"]),
               iterations=int(ds.attrs["iterations"]), unconverged=int(ds.attrs["unconverged"]))
    return out


def best(h, rh, repeat, **kw):
    runs = [run(h, rh, **kw) for _ in range(repeat)]
    out = runs[-1]
    out["seconds"] = min(r["seconds"] for r in runs)
    return out


def rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(b != 0, a / b - 1, np.where(a == 0, 0.0, np.inf))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[512, 1024])
    ap.add_argument("--maps", nargs="+", default=list(MAPS), choices=MAPS)
    ap.add_argument("--rh", type=float, nargs="+", default=list(RH))
    ap.add_argument("--repeat", type=int, default=3, help="timings of each default call (best of)")
    ap.add_argument("--no-old", action="store_true", help="skip the old default call")
    ap.add_argument("--no-tight", action="store_true", help="skip the tight reference")
    ap.add_argument("--cache", type=pathlib.Path, help="JSON file of tight references to reuse")
    args = ap.parse_args(argv)
    cache = json.loads(args.cache.read_text()) if args.cache and args.cache.exists() else {}
    rh = tuple(args.rh)
    # compile the numba kernels of both versions outside the timings
    small = height_map("S1A", 64)
    run(small, rh[:1])
    with old_kernels():
        run(small, rh[:1])
    print(f"RH {list(rh)}; default call rs.contact.fft_bem_curves(height, relative_humidity=RH); "
          "'x iFFT' = seconds / one 1024² complex iFFT timed in the same process")
    summary = []
    for n in args.sizes:
        for name in args.maps:
            h = height_map(name, n)
            unit = ifft_seconds()
            res = {"new": best(h, rh, args.repeat)}
            if not args.no_old:
                with old_kernels():
                    res["old"] = best(h, rh, args.repeat)
            key = f"{name}/{n}/{','.join(f'{r:g}' for r in rh)}"
            if not args.no_tight:
                if key not in cache:
                    with old_kernels():
                        cache[key] = run(h, rh, solver_tolerance=1e-4, precision="double")
                    cache[key]["unit"] = min(unit, ifft_seconds())
                    if args.cache:
                        args.cache.write_text(json.dumps(cache, indent=1))
                    res["tight"] = cache[key]
                else:
                    res["tight (cached)"] = cache[key]
            unit = min(unit, ifft_seconds())
            print(f"\n{name} {n}² (1024² iFFT {unit * 1e3:.1f} ms)")
            print(f"  {'call':6s} {'states':>6s} {'FFT pairs':>9s} {'iters':>6s} {'seconds':>8s} "
                  f"{'x iFFT':>7s} {'unconv':>6s}   (tight: timed once; cached: timed in its own run)")
            for k, r in res.items():
                u = r.get("unit", unit) if k.startswith("tight") else unit
                print(f"  {k:6s} {r['states']:6d} {r['fft_calls']:9d} {r['iterations']:6d} "
                      f"{r['seconds']:8.2f} {r['seconds'] / u:7.0f} {r['unconverged']:6d}")
            if "tight (cached)" in res:
                res["tight"] = res.pop("tight (cached)")
            row = {"map": name, "n": n, "x_ifft": res["new"]["seconds"] / unit}
            if "old" in res:
                row["old_x_ifft"] = res["old"]["seconds"] / unit
                print(f"  new/old: FFT pairs {res['new']['fft_calls'] / res['old']['fft_calls']:.2f}, "
                      f"time {res['new']['seconds'] / res['old']['seconds']:.2f}")
            for q in QUANT:
                vals = " ".join(f"{v:.4g}" for v in res["new"][q])
                line = f"  {SHORT[q]:8s} new [{vals}]"
                for a, b in (("new", "tight"), ("old", "tight"), ("new", "old")):
                    if a in res and b in res:
                        d = rel(res[a][q], res[b][q])
                        m = float(np.max(np.abs(d)))
                        line += f" | {a}/{b}-1 max {m:.2%}"
                        row[f"{q}:{a}/{b}"] = m
                print(line)
                if "tight" in res:
                    d = rel(res["new"][q], res["tight"][q])
                    print(f"  {'':8s} new/tight-1 per RH: " + " ".join(f"{x:+.2%}" for x in d))
            summary.append(row)
            sys.stdout.flush()
    print("\nsummary: x iFFT new (old) | max |rel. diff| to tight: Γ, pull-off, d_eq (new; old)")
    for r in summary:
        old = f"({r['old_x_ifft']:.0f})" if "old_x_ifft" in r else ""
        errs = " ".join(
            f"{r.get(f'{q}:new/tight', np.nan):.2%}"
            + (f"; {r[f'{q}:old/tight']:.2%}" if f"{q}:old/tight" in r else "")
            for q in QUANT)
        print(f"  {r['map']:8s} {r['n']:5d}² {r['x_ifft']:6.0f} {old:>7s} | {errs}")


if __name__ == "__main__":
    main()
