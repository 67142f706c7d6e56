"""Speed of the rough-surface modified DMT (not run by pytest).

Prints, in one run on this machine:
1. for one 1024 x 1024 map (5 nm pixels; data_samples S1A and S2A, S1-/S2-like statistics), six
   humidities (30, 50, 60, 70, 80, 90 %) and a 200-point distance grid: the time of the full set of
   curves as a multiple of one 1024 x 1024 complex inverse FFT (numpy) measured in the same run
   (target: <= 10x);
2. the speed-up over the literal reference (relabel per distance, scipy least_squares per
   asperity) on a 256 x 256 crop: the reference runs on 10 of the 200 distances (every 20th) and
   its time is scaled by 20 (target: >= 100x), with the largest pressure difference on those 10;
3. the opt-in warm start of the fits (``curves_kernel(..., warm_start=True)``): its time and its
   largest pressure difference from the default cold fits (speed against error; Eq. 21 is not
   convex, so the warm start can follow another local minimum);
4. the one-time numba compile cost (fresh cache, in a subprocess) and the load from cache.
   Compilation is never inside the timed runs above (one call on an 8 x 8 map first).

    python benchmarks/bench_rough_contact.py
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np
import xarray as xr

import roughstick as rs
from roughstick.contact import _rough_kernels as k
from roughstick.contact._rough_reference import reference_curves

RH = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]


def best_of(fn, n=3):
    t = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        t.append(time.perf_counter() - t0)
    return min(t)


def main():
    rng = np.random.default_rng(0)
    spec = np.fft.fft2(rng.standard_normal((1024, 1024)))
    t_fft = best_of(lambda: np.fft.ifft2(spec))
    print(f"one 1024^2 complex inverse FFT (numpy): {t_fft * 1e3:.1f} ms")
    # compile once
    rs.rough_contact_curves(rs.testing.make_topography(np.zeros((8, 8))), relative_humidity=0.5, distance=[0.0])
    for name in ("S1A", "S2A"):
        h = xr.open_dataset(rs.datasets.sample_path(name)).height.load()
        d = rs.contact_distance_grid(h, relative_humidity=RH, n=200).values
        t = best_of(lambda h=h, d=d: rs.rough_contact_curves(h, relative_humidity=RH, distance=d))
        t_auto = best_of(lambda h=h: rs.rough_contact_curves(h, relative_humidity=RH), n=1)
        ds = rs.rough_contact_curves(h, relative_humidity=RH, distance=d)
        print(
            f"{name} 1024^2, 6 RH, 200 distances: {t:.3f} s = {t / t_fft:.1f} x FFT "
            f"(automatic grid incl. its search: {t_auto:.3f} s = {t_auto / t_fft:.1f} x FFT); "
            f"tail pixels at the lowest distance: {int((h - h.mean() >= d.min()).sum())}, "
            f"max asperities at one distance: {int(ds.n_contacts.max())}"
        )
    # speed-up over the literal reference on 256^2
    h = xr.open_dataset(rs.datasets.sample_path("S1A")).height.isel(x=slice(0, 256), y=slice(0, 256)).load()
    d = rs.contact_distance_grid(h, relative_humidity=RH, n=200).values
    hw = rs.water_height(RH).values
    dp = rs.laplace_pressure(RH).values
    kw = dict(dx=5e-9, dy=5e-9, K=rs.hertz_modulus(), periodic=False, connectivity=4)
    z = h.values
    t_fast = best_of(lambda: k.curves_kernel(z, d, hw, dp, **kw))
    sub = d[::20]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        ref = reference_curves(z, sub, hw, dp, **kw)
        t_ref = (time.perf_counter() - t0) * (d.size / sub.size)
    fast = k.curves_kernel(z, sub, hw, dp, **kw)
    big = np.abs(ref[0]) > 1e-3 * np.abs(ref[0]).max()
    rel = np.max(np.abs(fast[0] - ref[0])[big] / np.abs(ref[0])[big], initial=0)
    print(
        f"S1A 256^2 crop, 6 RH, 200 distances: fast {t_fast * 1e3:.1f} ms, literal reference "
        f"{t_ref:.1f} s (ran {sub.size} distances, scaled x{d.size // sub.size}): speed-up "
        f"{t_ref / t_fast:.0f} x; max relative pressure difference on those {sub.size}: {rel:.1e}"
    )
    # warm start: speed against error (same 200-point grids as above)
    kw = dict(dx=5e-9, dy=5e-9, K=rs.hertz_modulus(), periodic=False, connectivity=4)
    for name in ("S1A", "S2A"):
        h = xr.open_dataset(rs.datasets.sample_path(name)).height.load()
        d = rs.contact_distance_grid(h, relative_humidity=RH, n=200).values
        z = h.values
        cold = k.curves_kernel(z, d, hw, dp, **kw)
        warm = k.curves_kernel(z, d, hw, dp, **kw, warm_start=True)
        t_c = best_of(lambda z=z, d=d: k.curves_kernel(z, d, hw, dp, **kw))
        t_w = best_of(lambda z=z, d=d: k.curves_kernel(z, d, hw, dp, **kw, warm_start=True))
        big = np.abs(cold[0]) > 1e-3 * np.abs(cold[0]).max()
        rel = np.where(big, np.abs(warm[0] - cold[0]) / np.where(big, np.abs(cold[0]), 1.0), 0.0)
        print(
            f"{name} warm start: {t_w:.3f} s = {t_w / t_fft:.1f} x FFT vs cold {t_c:.3f} s = "
            f"{t_c / t_fft:.1f} x FFT; max relative pressure difference {rel.max():.1e}, "
            f"distances differing by > 1e-8: {int(np.sum(rel.max(axis=0) > 1e-8))} of {d.size}"
        )
    # one-time compile cost: a fresh numba cache in a subprocess, then the same with the cache
    code = (
        "import time; t0 = time.perf_counter(); import numpy as np; import roughstick as rs; "
        "t1 = time.perf_counter(); rs.rough_contact_curves(rs.testing.make_topography(np.zeros((8, 8))), "
        "relative_humidity=0.5, distance=[0.0]); print(time.perf_counter() - t1)"
    )
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        run = [sys.executable, "-c", code]
        first = float(subprocess.run(run, env=env, capture_output=True, text=True, check=True).stdout)
        again = float(subprocess.run(run, env=env, capture_output=True, text=True, check=True).stdout)
    print(f"numba compile, first call with an empty cache: {first:.1f} s; with the cache (cache=True): {again:.2f} s")


if __name__ == "__main__":
    main()
