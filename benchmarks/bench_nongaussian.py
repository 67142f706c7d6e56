"""Benchmark of non-Gaussian surface generation, and the headline check on a real AFM map (not
run by pytest).

    python benchmarks/bench_nongaussian.py               # everything (a few minutes)
    python benchmarks/bench_nongaussian.py --quick       # 8 surfaces per target, no headline
    python benchmarks/bench_nongaussian.py --no-headline
    python benchmarks/bench_nongaussian.py --only ST_di-3 --n 64    # one target, more surfaces

The real AFM maps are read from $ROUGHSTICK_AFM_DIR, else from ../shared/afm beside the project;
absent files are skipped with a message.

1. Methods. For every target (each AFM map: its own levelled map, Hann PSD on its own grid and
   empirical height distribution; synthetic Johnson distributions of skewness -0.5 to 1 and
   kurtosis 3 to 6 on the paper's Table 4 PSD, which has a cutoff, and on a PSD without cutoff,
   256 x 256 at 5 nm), n surfaces per method (16 per map, 32 per synthetic target), all from
   the same seeds:

   - PSD: ensemble-mean periodogram in 8 log-spaced bands over the target's support; the largest
     band error against the target (``psd``) and against the Gaussian generator's on the same
     seeds (``twin``: the method's own error, the sampling noise the two share removed); for the
     translation also its expected spectrum (``exp``, exact, no sampling);
   - tail: the pooled 99th and 99.9th height percentiles against the target's (for the Gaussian
     generator: against the target, and against the Gaussian's own, its sampling noise);
   - KS distance of the pooled heights from the target distribution;
   - the tallest point of each surface (mean and sd over surfaces, in rms heights);
   - cost per surface relative to the Gaussian generator, interleaved rounds in this process
     (minimum), and the one-off setup (the pre-corrected spectrum).

2. Diagnostics: how often Gaussian maps (128 x 128 crops of S1 and Table 4 surfaces) fall inside
   the Gaussian's sampling intervals of height_diagnostics, and its verdict on each AFM map.

3. Headline (ST_example_ps.tiff): the map's own Γ at RH 0.5, 0.7, 0.9 (fft_bem, the levelled
   map at its own size and pixel, its automatic distance grid) against the 95 % band of 16
   surfaces from its own PSD (one curve each on a common grid of 100 distances), Gaussian and with
   its own height distribution (roughstick.ensemble.run(..., maps=...)); the containment warnings
   are printed as they come.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import time
import warnings

import numpy as np
from scipy import special

import roughstick as rs
from roughstick.surface import _marginal_kernels as kernels
from roughstick.surface.distribution import SCORE, evaluate, standardised
from roughstick.surface.generate import _half_plane_power

ROOT = pathlib.Path(__file__).resolve().parents[1]
AFM = pathlib.Path(os.environ.get("ROUGHSTICK_AFM_DIR", "") or ROOT.parent / "shared" / "afm")
AFM_FILES = ("ST_example_ps.tiff", "ST_di-1.di", "ST_di-3.di", "ST_di-6.di")
JOHNSON = ((-0.5, 3.5), (0.0, 4.0), (0.5, 3.0), (0.5, 4.5), (1.0, 4.0), (1.0, 6.0))
METHODS = (("translation", None), ("iaaft", 10), ("iaaft", 1))


def no_cutoff_psd(q):
    """Flat below a roll-off at 2 pi / 40 nm, q^-4 above, up to the Nyquist wave number."""
    return 1e-35 * (1 + (np.asarray(q) * 40e-9 / (2 * np.pi)) ** 2) ** -2


def targets():
    """(name, psd, shape, spacing, distribution) of every target."""
    out = []
    for name in AFM_FILES:
        if not (AFM / name).is_file():
            print(f"skipped {name}: not found in {AFM} (set ROUGHSTICK_AFM_DIR)")
            continue
        h = rs.surface.level(rs.io.read_afm(AFM / name))
        out.append((name, rs.surface.power_spectrum(h), h.shape, float(h.attrs["spacing_x"]),
                    rs.surface.height_distribution(h)))
    for psd_name, psd in (("table4", rs.datasets.family_psd("table4")), ("no cutoff", no_cutoff_psd)):
        for s, k in JOHNSON:
            out.append((f"{psd_name} S={s:+.1f} K={k:.1f}", psd, (256, 256), 5e-9,
                        rs.surface.height_distribution(skewness=s, kurtosis=k)))
    return out


def generate(psd, shape, spacing, n, dist=None, method="translation", iterations=None, seed=1):
    if iterations is not None:
        kernels.IAAFT_ITERATIONS = iterations
    kw = {} if dist is None else {"height_distribution": dist, "distribution_method": method}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # the distribution's rms is the map's, not the PSD's
        return rs.surface.generate_surfaces(psd, n=n, shape=shape, spacing=spacing, seed=seed,
                                            chunks=-1, **kw)


def bands(power, shape, spacing, support):
    ny, nx = shape
    q = 2 * np.pi * np.hypot(*np.meshgrid(np.fft.fftfreq(nx, spacing), np.fft.fftfreq(ny, spacing)))
    edges = np.geomspace(q[q > 0].min() * 0.999, q[support].max() * 1.001, 9)
    return np.array([power[(q >= lo) & (q < hi)].sum() for lo, hi in zip(edges[:-1], edges[1:], strict=True)])


def expected_translation_error(psd, shape, spacing, dist):
    """Largest band error of the translation's expected spectrum (its correlation map applied to
    the pre-corrected Gaussian spectrum) against the target."""
    ny, nx = shape
    P, _ = _half_plane_power(psd, ny, nx, spacing, spacing)
    (A, rows, ncols), _, table, _ = kernels.translation_setup(P, nx, dist.height.values, "rayleigh")
    G = np.zeros_like(P)
    G[rows, :ncols] = 2 * A**2
    forward, _ = kernels._correlation_map(kernels.hermite_coefficients(table))
    expected = np.fft.ifft2(forward(np.fft.fft2(kernels._full_plane(G, nx=nx)).real)).real
    target = kernels._full_plane(kernels._symmetrise(P, nx), nx=nx)
    target /= target.sum()
    inside = target > 0
    return np.abs(bands(expected, shape, spacing, inside) / bands(target, shape, spacing, inside) - 1).max()


def per_surface_seconds(fn, n, rounds=3):
    fn()  # setup (pre-correction, numba) out of the timing
    best = np.inf
    for _ in range(rounds):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best / n


def measure(name, psd, shape, spacing, dist, n):
    """One target: a printed row per generator."""
    target_p = np.fft.ifftshift(rs.surface.surface_filter(psd, shape=shape, spacing=spacing).values)
    support = target_p > 0
    sigma = np.sqrt(target_p.sum() * (2 * np.pi) ** 2 / (shape[0] * shape[1] * spacing**2))
    table = standardised(dist.height.values)
    want = sigma * evaluate(table, special.ndtri([0.99, 0.999]))
    scale = (shape[0] * shape[1] * spacing**2) / (2 * np.pi) ** 2 / (shape[0] * shape[1]) ** 2
    gauss = np.asarray(generate(psd, shape, spacing, n).values)
    g_bands = bands((np.abs(np.fft.fft2(gauss)) ** 2).mean(0) * scale, shape, spacing, support)
    t_bands = bands(target_p, shape, spacing, support)
    t_gauss = per_surface_seconds(lambda: generate(psd, shape, spacing, n).values, n)
    print(f"\n{name}: {shape[0]} x {shape[1]} px of {spacing * 1e9:.3g} nm, {dist.attrs['family']} "
          f"(skewness {dist.attrs['skewness']:.2f}, kurtosis {dist.attrs['kurtosis']:.2f}); n = {n}")
    print(f"  {'method':14s} {'psd':>6s} {'twin':>6s} {'exp':>6s} {'q99':>7s} {'q99.9':>7s} {'KS':>6s} "
          f"{'max/rms':>11s} {'cost':>6s} {'setup':>7s}")
    gq = np.quantile(gauss, [0.99, 0.999])
    noise = gq / (sigma * special.ndtri([0.99, 0.999])) - 1
    row("gaussian", np.abs(g_bands / t_bands - 1).max(), 0.0, None, gq / want - 1, ks(gauss, sigma, table),
        gauss, sigma, t_gauss, t_gauss, None, extra=f"  (its own noise: q99 {noise[0]:+.1%}, q99.9 {noise[1]:+.1%})")
    for method, iterations in METHODS:
        label = method if iterations is None else f"{method}-{iterations}"
        t0 = time.perf_counter()
        z = np.asarray(generate(psd, shape, spacing, n, dist, method, iterations).values)
        setup = time.perf_counter() - t0 - n * t_gauss
        t = per_surface_seconds(lambda m=method, i=iterations: generate(psd, shape, spacing, n, dist, m, i).values, n)
        z_bands = bands((np.abs(np.fft.fft2(z)) ** 2).mean(0) * scale, shape, spacing, support)
        exp = expected_translation_error(psd, shape, spacing, dist) if method == "translation" else None
        row(label, np.abs(z_bands / t_bands - 1).max(), np.abs(z_bands / g_bands - 1).max(), exp,
            np.quantile(z, [0.99, 0.999]) / want - 1, ks(z, sigma, table), z, sigma, t, t_gauss,
            setup if method == "translation" else None)
    kernels.IAAFT_ITERATIONS = 10


def ks(z, sigma, table) -> float:
    x = np.sort(z.ravel()[::3])
    cdf = special.ndtr(np.interp(x / sigma, evaluate(table, SCORE), SCORE))
    n = x.size
    return float(max(np.max(np.arange(1, n + 1) / n - cdf), np.max(cdf - np.arange(n) / n)))


def row(label, psd_err, twin, exp, q, ks_d, z, sigma, t, t_gauss, setup, extra=""):
    top = (z.max(axis=(1, 2)) - z.mean(axis=(1, 2))) / sigma
    RESULTS.append((label, psd_err, twin, exp, q, t / t_gauss))
    print(f"  {label:14s} {psd_err:6.1%} {twin:6.1%} {'' if exp is None else f'{exp:.1%}':>6s} "
          f"{q[0]:+7.1%} {q[1]:+7.1%} {ks_d:6.4f} {top.mean():5.2f}±{top.std():4.2f} "
          f"{t / t_gauss:5.2f}x {'' if setup is None else f'{setup:.2f} s':>7s}{extra}")


RESULTS: list = []


def verdict():
    print("\n== verdict over all targets (PSD: the method's own error, 'twin'; tail: q99 and q99.9 "
          "against the target; cost per surface) ==")
    for label in dict.fromkeys(r[0] for r in RESULTS):
        rows = [r for r in RESULTS if r[0] == label]
        psd_ok = sum(r[2] <= 0.05 for r in rows)
        tail_ok = sum(bool(np.all(np.abs(r[4]) <= 0.05)) for r in rows)
        cost = [r[5] for r in rows]
        print(f"  {label:14s} PSD within 5 %: {psd_ok}/{len(rows)}, tail within 5 %: {tail_ok}/{len(rows)}, "
              f"cost {min(cost):.2f}-{max(cost):.2f} x Gaussian (median {np.median(cost):.2f})")


def headline(n: int):
    name = "ST_example_ps.tiff"
    if not (AFM / name).is_file():
        print(f"\nheadline skipped: {name} not found in {AFM}")
        return
    h = rs.surface.level(rs.io.read_afm(AFM / name))
    psd = rs.surface.power_spectrum(h)
    spacing = float(h.attrs["spacing_x"])
    rh = [0.5, 0.7, 0.9]
    print(f"\n== headline: {name}, {h.shape[0]} x {h.shape[1]} px of {spacing * 1e9:.3g} nm, fft_bem, "
          f"RH {rh}, n = {n} ==")
    warnings.simplefilter("default")
    measured = rs.surface.height_distribution(h)
    for choice in ("gaussian", "maps"):
        t0 = time.perf_counter()
        # one curve per surface on a common grid of 100 distances from 2.5 rms heights up to the
        # tallest summit the distribution expects (Γ within 1-20 % at RH 0.5 and 1 % at RH 0.9 of
        # the automatic grid the map gets, at a third of the cost of the default ensemble grid)
        grid = rs.ensemble.distance_grid(psd, shape=h.shape, n=n, relative_humidity=rh, n_distance=100,
                                         lower=2.5,
                                         height_distribution=None if choice == "gaussian" else measured)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            ds = rs.ensemble.run(psd, n=n, relative_humidity=rh, spacing=spacing, shape=h.shape,
                                 model="fft_bem", maps=h, height_distribution=choice, seed=0,
                                 distance=grid).load()
            check = rs.ensemble.map_containment(ds)
        band = rs.ensemble.confidence_band(ds.adhesive_energy, uncertainty=None)
        print(f"-- height_distribution={choice!r} ({ds.attrs['height_distribution_reason']}), "
              f"{time.perf_counter() - t0:.0f} s")
        top = ds.max_height.values * 1e9
        print(f"   tallest point of the surfaces {top.min():.1f}-{top.max():.1f} nm (map: "
              f"{float(h.max() - h.mean()) * 1e9:.1f} nm)")
        for r in rh:
            lo, med, hi = (float(v) * 1e3 for v in band["adhesive_energy"].sel(rh=r).values)
            g = float(ds.map_adhesive_energy.sel(rh=r).values.ravel()[0]) * 1e3
            p = float(ds.map_percentile.sel(rh=r).values.ravel()[0])
            inside = bool(check.inside.sel(rh=r).values.ravel()[0])
            print(f"   RH {r}: band [{lo:.3g}, {hi:.3g}] mJ/m², median {med:.3g}; the map {g:.3g} "
                  f"mJ/m² at percentile {p:.0f}: {'inside' if inside else 'OUTSIDE'}")
        for w in caught:
            if issubclass(w.category, rs.ensemble.ContainmentWarning):
                print(f"   warning: {w.category.__name__}: {w.message}")


def coverage(seeds: int):
    """How often a Gaussian map passes: 128 x 128 crops of larger Gaussian surfaces (not periodic,
    like a measured map), and the verdict on each real AFM map."""
    print(f"\n== diagnostics: Gaussian maps within their sampling error? ({seeds} seeds, 50 "
          "surrogates each, nominal 95 % per statistic) ==")
    for family in ("S1", "table4"):
        h = rs.surface.generate_surfaces(rs.datasets.family_psd(family), n=seeds, shape=256, spacing=5e-9,
                                         seed=11).compute().isel(x=slice(0, 128), y=slice(0, 128))
        h.attrs["periodic"] = 0
        inside, verdict = [], []
        for k in range(seeds):
            d = rs.surface.height_diagnostics(h.isel(realization=k), seed=k)
            inside.append([float(d[f"{v}_gaussian_lower"]) <= float(d[v]) <= float(d[f"{v}_gaussian_upper"])
                           for v in ("skewness", "kurtosis")]
                          + list(((d.tail_quantile_gaussian_lower <= d.tail_quantile)
                                  & (d.tail_quantile <= d.tail_quantile_gaussian_upper)).values))
            verdict.append(bool(d.gaussian))
        rate = np.mean(inside, axis=0)
        print(f"  {family} 128 x 128 crops: inside the Gaussian's interval: skewness {rate[0]:.0%}, "
              f"kurtosis {rate[1]:.0%}, q99 {rate[2]:.0%}, q99.9 {rate[3]:.0%}; verdict Gaussian "
              f"{np.mean(verdict):.0%}")
    for name in AFM_FILES:
        if (AFM / name).is_file():
            t0 = time.perf_counter()
            d = rs.surface.height_diagnostics(rs.io.read_afm(AFM / name))
            cells = ", ".join(f"{v} {float(d[v]):.2f} [{float(d[f'{v}_gaussian_lower']):.2f}, "
                              f"{float(d[f'{v}_gaussian_upper']):.2f}]" for v in ("skewness", "kurtosis"))
            q = d.tail_quantile.sel(probability=0.999)
            cells += (f", q99.9 {float(q):.2f} [{float(d.tail_quantile_gaussian_lower.sel(probability=0.999)):.2f}, "
                      f"{float(d.tail_quantile_gaussian_upper.sel(probability=0.999)):.2f}]")
            print(f"  {name}: {cells}: {'Gaussian' if bool(d.gaussian) else 'NOT Gaussian'} "
                  f"({time.perf_counter() - t0:.1f} s)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--no-headline", action="store_true")
    ap.add_argument("--only", default=None, help="part 1 only, for the targets whose name holds this")
    ap.add_argument("--n", type=int, default=None, help="surfaces per AFM target, twice that per "
                    "synthetic one (default 16; quick 8)")
    args = ap.parse_args()
    n = args.n or (8 if args.quick else 16)
    found = [f for f in AFM_FILES if (AFM / f).is_file()]
    print(f"{time.strftime('%H:%M:%S')} load average {os.getloadavg()[0]:.2f}; real AFM maps: "
          f"{len(found)} of {len(AFM_FILES)} found")
    t0 = time.perf_counter()
    for target in targets():
        if args.only and args.only not in target[0]:
            continue
        # the synthetic 256 x 256 targets are cheap: twice the surfaces
        measure(*target, n if target[0].startswith("ST_") or args.only else 2 * n)
    verdict()
    print(f"(part 1: {time.perf_counter() - t0:.0f} s)")
    if args.only:
        return
    coverage(40 if args.quick else 100)
    if not (args.quick or args.no_headline):
        headline(16)
    print(f"{time.strftime('%H:%M:%S')} load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
