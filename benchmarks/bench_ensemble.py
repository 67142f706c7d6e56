"""Benchmark of the Monte Carlo ensemble (issue 6): speed, memory and convergence of the Γ band.

Part 1 (speed): the paper-scale run is 3000 surfaces of 1024² (5 nm), six humidities, S2-like PSD
(the bundled S2 maps, scheme 3, cut at 289 rad/µm), streamed to NetCDF on the local threaded
scheduler. The script runs it at n = --n (default 300; pass several, e.g. ``--n 100 300``) and
prints wall time, realizations per second and the process's peak resident memory, then the
paper-scale time *extrapolated* linearly from the largest n measured (clearly labelled: it is not
a measurement unless --n 3000 is given). Linear scaling is shown by the realizations/s staying
flat across the n values.

Part 2 (accuracy): the band of Γ versus n (100, 300, 1000, 3000) on --conv-shape surfaces
(default 256², labelled), with the order-statistic 95 % confidence interval of each band edge and
the cumulative time to reach each n (the same run extended: realizations 0..n-1 are nested).

    python benchmarks/bench_ensemble.py                       # both parts, n=300 at 1024²
    python benchmarks/bench_ensemble.py --part speed --n 100 300
    python benchmarks/bench_ensemble.py --part convergence --conv-shape 128 --conv-n 100 300 1000
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import threading
import time

import numpy as np
from _yardstick import ifft_seconds

import roughstick as rs
from roughstick.datasets import sample_psd

RH = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]


class PeakRSS:
    """Sample the resident memory of this process every 50 ms."""

    def __init__(self):
        import psutil

        self.proc = psutil.Process(os.getpid())
        self.peak = self.proc.memory_info().rss
        self._stop = threading.Event()

    def __enter__(self):
        self.base = self.proc.memory_info().rss
        self.t = threading.Thread(target=self._run, daemon=True)
        self.t.start()
        return self

    def _run(self):
        while not self._stop.wait(0.05):
            self.peak = max(self.peak, self.proc.memory_info().rss)

    def __exit__(self, *exc):
        self._stop.set()
        self.t.join()


def speed(ns, shape, chunks, scheduler, own_grid=False):
    psd = sample_psd("S2")
    dist = None if own_grid else rs.ensemble.distance_grid(psd, shape=(shape, shape), n=3000,
                                                            relative_humidity=RH)
    grid = ("each map's own grid per humidity (the default call)" if own_grid else
            f"one {dist.size}-point distance grid for every map and humidity")
    print(f"## speed: S2 PSD (bundled maps, scheme 3), {shape}² at 5 nm, six RH, Eq. 16, {grid}, "
          f"scheduler={scheduler or 'threads'}, {os.cpu_count()} cores")
    fft = ifft_seconds()
    print(f"one 1024² complex iFFT: {fft * 1e3:.1f} ms wall; per surface: wall and process CPU time "
          "(all threads) as multiples of it")
    print("| n | wall time [s] | realizations/s | wall / surface [× iFFT] | CPU / surface [× iFFT] "
          "| peak RSS [MiB] | RSS growth [MiB] |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    rate = None
    for n in ns:
        with tempfile.TemporaryDirectory() as tmp, PeakRSS() as mem:
            t0 = time.perf_counter()
            c0 = time.process_time()
            ds = rs.ensemble.run(psd, n=n, shape=shape, spacing=5e-9, relative_humidity=RH, seed=0,
                                 chunks=chunks, distance=dist, output=os.path.join(tmp, "e"),
                                 scheduler=scheduler, progress=False, model="modified_dmt")
            g = ds.adhesive_energy.values  # noqa: F841  (read back from the files)
            wall = time.perf_counter() - t0
            cpu = time.process_time() - c0
        rate = n / wall
        print(f"| {n} | {wall:.1f} | {rate:.3f} | {wall / n / fft:.1f} | {cpu / n / fft:.1f} | "
              f"{mem.peak / 2**20:.0f} | {(mem.peak - mem.base) / 2**20:.0f} |", flush=True)
    if 3000 not in ns:
        print(f"\nEXTRAPOLATED (not measured): n = 3000 at {rate:.3f} realizations/s -> "
              f"{3000 / rate / 60:.1f} min (issue 12: <= 5 min on the 2-core machine); memory does not grow with n "
              "(blocks stream to disk), see the RSS column.")


def convergence(ns, shape, chunks, scheduler):
    psd = sample_psd("S2")
    nmax = max(ns)
    dist = rs.ensemble.distance_grid(psd, shape=(shape, shape), n=nmax, relative_humidity=RH)
    print(f"\n## convergence of the 95 % band of Γ: S2 PSD, {shape}² at 5 nm "
          f"({shape * 5e-3:.2f} µm surfaces, smaller than the paper's 5.12 µm), nested runs")
    print("Γ in mJ/m²; [a, b] = 95 % order-statistic confidence interval of the band edge; "
          "time = cumulative wall time to reach n")
    with tempfile.TemporaryDirectory() as tmp:
        folder = os.path.join(tmp, "conv")
        total = 0.0
        rows = []
        for n in sorted(ns):
            t0 = time.perf_counter()
            ds = rs.ensemble.run(psd, n=n, shape=shape, spacing=5e-9, relative_humidity=RH, seed=0,
                                 chunks=chunks, distance=dist, output=folder, scheduler=scheduler,
                                 progress=False, model="modified_dmt")
            total += time.perf_counter() - t0
            b = rs.ensemble.confidence_band(ds[["adhesive_energy"]].load())
            rows.append((n, total, b))
        print("| RH | n | 2.5 % [CI] | median | 97.5 % [CI] | mean ± s.e. | time [s] |")
        print("|---:|---:|---|---:|---|---|---:|")
        for k, r in enumerate(RH):
            for n, t, b in rows:
                q = b.adhesive_energy.values[:, k] * 1e3
                lo = b.adhesive_energy_ci_lower.values[:, k] * 1e3
                hi = b.adhesive_energy_ci_upper.values[:, k] * 1e3
                m = float(b.adhesive_energy_mean[k]) * 1e3
                se = float(b.adhesive_energy_mean_stderr[k]) * 1e3
                print(f"| {r:.0%} | {n} | {q[0]:.4g} [{lo[0]:.4g}, {hi[0]:.4g}] | {q[1]:.4g} | "
                      f"{q[2]:.4g} [{lo[2]:.4g}, {hi[2]:.4g}] | {m:.4g} ± {se:.2g} | {t:.0f} |")
        ref = rows[-1][2].adhesive_energy
        print(f"\nlargest relative change of the band edges against n = {rows[-1][0]}:")
        for n, _, b in rows[:-1]:
            ch = float(np.nanmax(np.abs(b.adhesive_energy.values[[0, 2]] / ref.values[[0, 2]] - 1)))
            print(f"  n = {n}: {ch:.1%}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--part", choices=["speed", "convergence", "both"], default="both")
    ap.add_argument("--n", type=int, nargs="+", default=[300])
    ap.add_argument("--shape", type=int, default=1024)
    ap.add_argument("--chunks", type=int, default=2)
    ap.add_argument("--conv-n", type=int, nargs="+", default=[100, 300, 1000, 3000])
    ap.add_argument("--conv-shape", type=int, default=256)
    ap.add_argument("--scheduler", default=None)
    ap.add_argument("--own-grid", action="store_true",
                    help="speed part: no distance= (each map's own grid per humidity, the default call)")
    a = ap.parse_args(argv)
    print(f"roughstick {rs.__version__}, python {sys.version.split()[0]}")
    if a.part in ("speed", "both"):
        speed(a.n, a.shape, a.chunks, a.scheduler, own_grid=a.own_grid)
    if a.part in ("convergence", "both"):
        convergence(a.conv_n, a.conv_shape, max(a.chunks, 4), a.scheduler)


if __name__ == "__main__":
    main()
