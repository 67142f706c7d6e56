"""Benchmark of roughstick.surface.generate_surfaces (not run by pytest).

    python benchmarks/bench_generate.py            # all three parts (about 1-2 minutes)
    python benchmarks/bench_generate.py --quick    # n = 20 / 100 for the memory part

Prints, measured in this run:

1. time per 1024 x 1024 surface (public lazy path, synchronous scheduler, setup amortised over
   the batch) against one bare numpy inverse FFT of the same size (``numpy.fft.irfft2`` of the
   half spectrum, the transform the generator performs, and ``numpy.fft.ifft2`` of a full complex
   1024 x 1024 array, the literal Eq. 34), for the band-limited S1 PSD of Table 3 (qmax =
   289 rad/um < Nyquist 628 rad/um) and for a PSD that is non-zero at every grid mode;
2. peak resident memory of generating and reducing n surfaces of 1024 x 1024 through dask
   (threads, chunks of 8 surfaces), each n in a fresh subprocess, so the growth with n shows;
3. float32 against float64: largest height difference and the relative error of m0, m2, m4.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time

import numpy as np

SHAPE = 1024
SPACING = 5e-9


def s1_psd():
    import roughstick as rs

    fit = rs.surface.fit_self_affine(m0=15.7e-18, m2=0.040, m4=5.08e-4 * 1e18, qmax=289e6)
    p = {k: float(fit[k]) for k in ("s0", "s1", "q0", "qmax")}

    def psd(q):
        q = np.asarray(q, dtype=float)
        return rs.surface.self_affine_psd(q.ravel(), **p).values.reshape(q.shape)

    return psd


def full_band_psd(q):
    """Non-zero at every grid mode (worst case for the generator: every amplitude is drawn)."""
    return 1e-34 / (1 + (np.asarray(q) / 5e7) ** 2) ** 2


def best_of(fn, repeat=7):
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def part_speed(rounds: int = 8):
    """Interleaved rounds (bare FFTs and generator alternate), minimum over rounds: robust to
    other processes loading the machine."""
    import dask

    import roughstick as rs

    rng = np.random.default_rng(0)
    half = rng.standard_normal((SHAPE, SHAPE // 2 + 1)) + 1j * rng.standard_normal((SHAPE, SHAPE // 2 + 1))
    full = rng.standard_normal((SHAPE, SHAPE)) + 1j * rng.standard_normal((SHAPE, SHAPE))
    batch = 16
    psds = {"S1 (band-limited, Table 3)": s1_psd(), "full-band PSD": full_band_psd}
    graphs = {k: rs.surface.generate_surfaces(p, n=batch, shape=SHAPE, spacing=SPACING, seed=1, chunks=batch)
              for k, p in psds.items()}
    single = rs.surface.generate_surfaces(psds["S1 (band-limited, Table 3)"], n=1, shape=SHAPE,
                                  spacing=SPACING, seed=1)
    best = {}

    def clock(key, fn, per=1):
        t0 = time.perf_counter()
        fn()
        dt = (time.perf_counter() - t0) / per
        best[key] = min(best.get(key, np.inf), dt)

    with dask.config.set(scheduler="synchronous"):
        for _ in range(rounds):
            # the bare FFTs are timed in batches of the same length as the generator's, so a
            # loaded machine slows both alike
            clock("irfft2", lambda: [np.fft.irfft2(half, s=(SHAPE, SHAPE)) for _ in range(batch)],
                  per=batch)
            clock("ifft2", lambda: [np.fft.ifft2(full) for _ in range(batch)], per=batch)
            for k, h in graphs.items():
                clock(k, lambda h=h: h.data.compute(), per=batch)
            clock("one call", lambda: rs.surface.generate_surfaces(
                psds["S1 (band-limited, Table 3)"], n=1, shape=SHAPE, spacing=SPACING, seed=1).values)
            clock("one surface graph", lambda: single.data.compute())
    t_irfft, t_ifft = best["irfft2"], best["ifft2"]
    print(f"bare numpy.fft.irfft2 (1024 x 513 -> 1024 x 1024 real): {t_irfft * 1e3:7.2f} ms "
          f"(mean of {batch} calls)")
    print(f"bare numpy.fft.ifft2  (1024 x 1024 complex):            {t_ifft * 1e3:7.2f} ms "
          f"(mean of {batch} calls)")
    for k in psds:
        t = best[k]
        print(f"generate_surfaces, {k}: {t * 1e3:7.2f} ms per surface (batch of {batch} in one "
              f"chunk, computed) = {t / t_irfft:.2f} x irfft2, {t / t_ifft:.2f} x ifft2")
    t = best["one surface graph"]
    print(f"one S1 surface computed from its graph (n=1):        {t * 1e3:7.2f} ms = "
          f"{t / t_irfft:.2f} x irfft2")
    t = best["one call"]
    print(f"one S1 surface incl. building the graph and the PSD filter: {t * 1e3:7.2f} ms = "
          f"{t / t_irfft:.2f} x irfft2")
    print(f"(minimum over {rounds} interleaved rounds)")


def _vm(key: str) -> float:
    """A VmXXX line of /proc/self/status in MiB (Linux)."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1024
    raise RuntimeError(f"{key} not in /proc/self/status")


def memory_child(n: int) -> dict:
    """Run in a subprocess: generate n surfaces 1024^2 and reduce them; report peak RSS.

    The peak (VmHWM) is reset after the imports by writing 5 to /proc/self/clear_refs, so it is
    the peak of the generation and reduction alone (importing the stack peaks higher)."""
    import dask

    import roughstick as rs

    psd = s1_psd()
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")
    base = _vm("VmRSS")
    t0 = time.perf_counter()
    h = rs.surface.generate_surfaces(psd, n=n, shape=SHAPE, spacing=SPACING, seed=3, chunks=8)
    with dask.config.set(scheduler="threads", num_workers=2):
        m0 = (h**2).mean(("y", "x")).compute()
    dt = time.perf_counter() - t0
    peak = _vm("VmHWM")
    return {"n": n, "baseline_MiB": base, "peak_MiB": peak, "seconds": dt,
            "ensemble_GiB": n * SHAPE * SHAPE * 8 / 2**30, "mean_m0_nm2": float(m0.mean()) * 1e18}


def part_memory(ns):
    for n in ns:
        out = subprocess.run([sys.executable, __file__, "--child", str(n)], capture_output=True,
                             text=True, check=True)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"n = {r['n']:5d}: peak RSS {r['peak_MiB']:7.0f} MiB (RSS before generating "
              f"{r['baseline_MiB']:.0f} MiB) for an ensemble of {r['ensemble_GiB']:.2f} GiB, "
              f"{r['seconds']:.1f} s, mean m0 {r['mean_m0_nm2']:.3f} nm2")


def part_precision():
    import roughstick as rs

    psd = s1_psd()
    n = 8
    h64 = rs.surface.generate_surfaces(psd, n=n, shape=SHAPE, spacing=SPACING, seed=5).values
    h32 = rs.surface.generate_surfaces(psd, n=n, shape=SHAPE, spacing=SPACING, seed=5, dtype="float32").values
    qx = 2 * np.pi * np.fft.fftfreq(SHAPE, SPACING)[None, :]

    def moments(z):
        Z = np.fft.fft2(z.astype(np.float64))
        p = np.abs(Z) ** 2 / z[0].size ** 2
        return np.array([p.sum(), (p * qx**2).sum(), (p * qx**4).sum()]) / len(z)

    m64, m32 = moments(h64), moments(h32)
    rel = np.abs(m32 / m64 - 1)
    print(f"float32 vs float64 ({n} surfaces 1024^2, same random draws): max |dz| = "
          f"{np.abs(h32 - h64).max() / h64.std():.2e} x std(z); relative error of m0, m2, m4 = "
          f"{rel[0]:.1e}, {rel[1]:.1e}, {rel[2]:.1e}; memory per surface 4 MiB vs 8 MiB")
    g64 = rs.surface.generate_surfaces(psd, n=4, shape=SHAPE, spacing=SPACING, seed=5, chunks=4)
    g32 = rs.surface.generate_surfaces(psd, n=4, shape=SHAPE, spacing=SPACING, seed=5, chunks=4,
                               dtype="float32")
    t64 = t32 = np.inf
    for _ in range(4):  # interleaved, minimum
        t64 = min(t64, best_of(lambda: g64.data.compute(scheduler="synchronous"), repeat=1))
        t32 = min(t32, best_of(lambda: g32.data.compute(scheduler="synchronous"), repeat=1))
    print(f"time for 4 surfaces: float64 {t64 * 1e3:.0f} ms, float32 {t32 * 1e3:.0f} ms")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--only", choices=["speed", "memory", "precision"])
    args = parser.parse_args()
    if args.child:
        print(json.dumps(memory_child(args.child)))
        return
    if args.only in (None, "speed"):
        print("== 1. speed ==")
        part_speed()
    if args.only in (None, "memory"):
        print("== 2. memory (generate + reduce, streamed through dask) ==")
        part_memory([20, 100] if args.quick else [100, 1000])
    if args.only in (None, "precision"):
        print("== 3. float32 vs float64 ==")
        part_precision()


if __name__ == "__main__":
    main()
