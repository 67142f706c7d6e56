"""Benchmark: the zone-size law of Γ, and the composed-strip law checked against whole strips.

    nice -n 10 python benchmarks/bench_zone_size.py [--families table4 S1] [--rh 0.3 0.5 0.7 0.9]
        [--n-eq16 40] [--n-bem 12 4 2] [--strips 8] [--bem-strip 128 768] [--full N] [--grooved]
        [--parts 1 2 3 4] [--beams 20000]

All surfaces are periodic Gaussian surfaces at 5 nm of the Table-4 PSD (``rs.datasets.family_psd
("table4")``, the §5.2 zone surface) and of the S1 PSD, the paper's interaction zone being
524 × 6000 pixels (Δs × w = 2.62 × 30 µm).

1. **Zone-size law**: Γ (Eq. 13) of ``--n-eq16`` independent zones of each size (128², 256²,
   524 × 500 (a sub-zone), 524 × 1500, 524 × 6000 (the strip)) with Eq. 16 (``model=
   "modified_dmt"``), and of ``--n-bem`` zones of 128², 256² and 524 × 500 with ``fft_bem``
   (``--full``: also composed fft_bem strips). Printed per RH: mean, cv, the 10/50/90 %
   quantiles with their 95 % order-statistic intervals (``rs.ensemble.quantile_interval``).
2. **The composed law on the same surfaces** (the criterion): ``--strips`` whole strips are
   simulated directly and cut into sub-zones (524 × 500 for Eq. 16 on the 524 × 6000 strip;
   128 × 128 for fft_bem on ``--bem-strip`` strips); each sub-zone's law, on the strip's
   distance grid, goes through ``rs.stiction.compose_zone_law``. The periodic strip is rolled
   so that no cut runs through one of its tallest summits (``seam_roll``; Eq. 16 fits a split
   summit as two, a cutting artefact of up to 20 % at 70 % RH in a first run). ``--grooved``
   lowers every strip 5 rms along its cuts first (no contact near a cut, so a periodic
   solver's wrap of a cut cannot act either). Printed: the 10/50/90 %
   quantiles of Γ of the direct and the composed strips, their largest relative difference
   (PASS within 5 %) and the largest per-strip difference.
3. **Prediction from independent sub-zones** (what ``rs.stiction.strip_adhesive_energy`` does):
   the strips composed from independently drawn periodic 524 × 500 sub-zones against the direct
   strips of part 1 (Eq. 16): quantiles with their 95 % intervals; "overlap" when the two
   intervals of every quantile overlap.

4. **Every beam length from one tail**: P(stuck) of the paper's beam (sharp front, release) at
   100-1500 µm from the CCDF of part 3's strips (``rs.stuck_probability(strips, method="front")``)
   against ``--beams`` beams simulated on the same strips as a bank (``rs.beam.simulate``), with
   the largest difference in binomial standard deviations.

Timings are wall seconds in this process; the machine-load yardstick (one 1024² complex iFFT)
is printed first.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import xarray as xr

import roughstick as rs

sys.path.insert(0, str(Path(__file__).parent))
from _yardstick import ifft_seconds  # noqa: E402

SPACING = 5e-9
STRIP = (524, 6000)
SUB = (524, 500)
QUANTILES = (0.1, 0.5, 0.9)


def zone_curves(psd, shape, n, rh, model, seed, distance=None):
    """Curves (pressure, wet_fraction) of ``n`` periodic zones of ``shape`` on one grid."""
    surf = rs.surface.generate_surfaces(psd, n=n, shape=shape, spacing=SPACING, seed=seed)
    if distance is None:
        m0 = float(rs.stiction.zone._callable_m0(psd, shape, SPACING))
        distance = rs.ensemble.distance_grid(m0=m0, shape=shape, n=n, relative_humidity=rh).values
    c = rs.contact.curves(surf, relative_humidity=rh, model=model, distance=distance)
    return c[["pressure", "wet_fraction"]].compute(scheduler="threads"), surf


def gamma(curves):
    return rs.contact.summary(curves, check_grid=False).adhesive_energy.transpose("realization", "rh")


def describe(g: xr.DataArray, label: str):
    """One line per RH: mean, cv, quantiles with 95 % order-statistic intervals [µJ m-2]."""
    lo, hi = rs.ensemble.quantile_interval(g, list(QUANTILES), dim="realization", confidence=0.95)
    q = g.quantile(list(QUANTILES), dim="realization")
    for r in g.rh.values:
        v = g.sel(rh=r).values * 1e6
        parts = [f"q{int(p * 100)} {float(q.sel(quantile=p, rh=r)) * 1e6:.4g} "
                 f"[{float(lo.sel(quantile=p, rh=r)) * 1e6:.4g}, {float(hi.sel(quantile=p, rh=r)) * 1e6:.4g}]"
                 for p in QUANTILES]
        print(f"  {label:>22} RH {r:.1f}: mean {v.mean():9.4g} cv {v.std(ddof=1) / v.mean():5.2f}  "
              + "  ".join(parts))


def size_law(psd, args, fam):
    print(f"\n--- 1. zone-size law, {fam} PSD (Γ in µJ m-2; n zones per size)")
    direct_strips, eq16 = None, {}
    sizes = [((128, 128), args.n_eq16), ((256, 256), args.n_eq16), (SUB, args.n_eq16),
             ((524, 1500), args.n_eq16), (STRIP, args.n_eq16)]
    for shape, n in sizes:
        t = time.perf_counter()
        c, _ = zone_curves(psd, shape, n, args.rh, "modified_dmt", seed=args.seed)
        g = gamma(c)
        area = shape[0] * shape[1] * SPACING**2 * 1e12
        describe(g, f"Eq16 {shape[0]}x{shape[1]} n={n}")
        print(f"  {'':>22} ({area:.3g} µm², {time.perf_counter() - t:.1f} s)")
        eq16[shape] = g
        if shape == STRIP:
            direct_strips = g
    for shape, n in zip([(128, 128), (256, 256), SUB], args.n_bem):
        if n <= 0:
            continue
        t = time.perf_counter()
        c, _ = zone_curves(psd, shape, n, args.rh, "fft_bem", seed=args.seed)
        g = gamma(c)
        describe(g, f"BEM {shape[0]}x{shape[1]} n={n}")
        if shape in eq16 and eq16[shape].sizes["realization"] >= n:  # the same zones (same seed)
            ratio = (g / eq16[shape].isel(realization=slice(0, n))).median("realization")
            print(f"  {'':>22} BEM/Eq16 on the same zones, median per RH: "
                  + "  ".join(f"{float(v):.2f}" for v in ratio.values))
        print(f"  {'':>22} ({shape[0] * shape[1] * SPACING**2 * 1e12:.3g} µm², {time.perf_counter() - t:.1f} s)")
    if args.full:
        t = time.perf_counter()
        g = rs.stiction.strip_adhesive_energy(psd, relative_humidity=args.rh, n=args.full, model="fft_bem",
                                              seed=args.seed + 1)
        describe(g.adhesive_energy, f"BEM strip (composed) n={args.full}")
        print(f"  {'':>22} ({time.perf_counter() - t:.1f} s)")
    return direct_strips


def seam_roll(z, cols, band=10):
    """Roll of a periodic strip that puts its cuts (every ``cols`` columns) where the tallest
    height within ``band`` columns of a cut is lowest: a summit split by a cut is fitted as two
    by Eq. 16, which is a cutting artefact, not part of the law (the strip's own law does not
    change when it is rolled)."""
    col = z.max(axis=0)
    best, out = np.inf, 0
    for r in range(0, cols, max(1, cols // 25)):
        seams = (np.arange(0, z.shape[1], cols)[:, None] - r + np.arange(-band, band + 1)[None, :]) % z.shape[1]
        worst = col[seams].max()
        if worst < best:
            best, out = worst, r
    return int(out)


def groove(h, cols, depth, half_width):
    """``h`` lowered by ``depth`` (a cosine profile ``half_width`` columns either side) along every
    cut: neither the strip nor its cuts touch the flat near a cut, so a periodic solver's wrap of
    a cut (a height jump joining its two edges) cannot act, and what remains is the law itself."""
    x = np.arange(h.shape[1])
    dist = np.abs(((x + cols // 2) % cols) - cols // 2)  # columns to the nearest cut
    profile = np.where(dist < half_width, 0.5 * (1 + np.cos(np.pi * dist / half_width)), 0.0)
    return h - depth * profile[None, :]


def cut_and_compose(psd, strip_shape, sub_cols, n, rh, model, seed, grooved=False):
    """Direct Γ of ``n`` strips and Γ composed from their own cuts (paired)."""
    c, surf = zone_curves(psd, strip_shape, n, rh, model, seed)
    d = c.distance.values
    laws, direct = [], []
    for k in range(n):
        h = surf.isel(realization=k).compute()
        h = h - float(h.mean())
        h = h.roll(x=seam_roll(h.values, sub_cols), roll_coords=False)
        if grooved:
            h = h.copy(data=groove(h.values, sub_cols, 5 * float(h.std()), 12))
            h = h - float(h.mean())
            direct.append(rs.contact.curves(h, relative_humidity=rh, model=model, distance=d)[
                ["pressure", "wet_fraction"]].compute())
        for j in range(strip_shape[1] // sub_cols):
            cut = h.isel(x=slice(j * sub_cols, (j + 1) * sub_cols))
            # a cut is not periodic: Eq. 16 must not join clusters across its seam (fft_bem is periodic anyway)
            cut.attrs["periodic"] = int(model == "fft_bem")
            off = float(cut.mean())
            cc = rs.contact.curves(cut - off, relative_humidity=rh, model=model, distance=d - off)
            laws.append(cc[["pressure", "wet_fraction"]].compute().assign_coords(distance=d))
    direct = gamma(xr.concat(direct, dim="realization")) if grooved else gamma(c)
    stacked = xr.concat(laws, dim="realization")
    comp = rs.stiction.compose_zone_law(stacked, subzones=strip_shape[1] // sub_cols)
    return direct, comp.adhesive_energy.transpose("realization", "rh").assign_coords(realization=direct.realization)


def law_check(psd, args, fam):
    print(f"\n--- 2. composed law vs direct strips, same surfaces, {fam} PSD (Γ in µJ m-2)")
    worst = {}
    for model, shape, cols in (("modified_dmt", STRIP, SUB[1]),
                               ("fft_bem", tuple(args.bem_strip), args.bem_strip[0])):
        t = time.perf_counter()
        direct, comp = cut_and_compose(psd, shape, cols, args.strips, args.rh, model, seed=args.seed + 7,
                                       grooved=args.grooved)
        qd = direct.quantile(list(QUANTILES), dim="realization")
        qc = comp.quantile(list(QUANTILES), dim="realization")
        print(f"  {model}, {args.strips} strips of {shape[0]}x{shape[1]}, cut into {shape[1] // cols} "
              f"sub-zones of {shape[0]}x{cols} ({time.perf_counter() - t:.1f} s)")
        for r in direct.rh.values:
            a, b = qd.sel(rh=r).values, qc.sel(rh=r).values
            rel = np.abs(b / a - 1)
            per = np.abs(comp.sel(rh=r).values / direct.sel(rh=r).values - 1)
            worst[model] = max(worst.get(model, 0.0), float(np.max(rel)))
            print(f"    RH {r:.1f}: direct q10/50/90 " + " ".join(f"{v * 1e6:.4g}" for v in a)
                  + "  composed " + " ".join(f"{v * 1e6:.4g}" for v in b)
                  + f"  max quantile diff {100 * np.max(rel):.2f} %  max per strip {100 * np.max(per):.2f} %"
                  + ("  PASS" if np.max(rel) <= 0.05 else "  FAIL"))
    return worst


def prediction_check(psd, args, fam, direct):
    print(f"\n--- 3. strips composed from independent sub-zones vs direct strips, {fam}, Eq. 16")
    t = time.perf_counter()
    g = rs.stiction.strip_adhesive_energy(psd, relative_humidity=args.rh, n=args.n_eq16, seed=args.seed + 3)
    print(f"  rs.stiction.strip_adhesive_energy: {args.n_eq16} strips of {g.attrs['subzones']} sub-zones "
          f"{tuple(g.attrs['subzone_shape'])} in {time.perf_counter() - t:.1f} s")
    comp = g.adhesive_energy
    describe(comp, "composed strips")
    describe(direct, "direct strips")
    lo1, hi1 = rs.ensemble.quantile_interval(comp, list(QUANTILES), dim="realization")
    lo2, hi2 = rs.ensemble.quantile_interval(direct, list(QUANTILES), dim="realization")
    overlap = bool(((lo1 <= hi2) & (lo2 <= hi1)).all())
    print(f"  every quantile interval overlaps: {'yes' if overlap else 'NO'}")


def every_length(psd, args, fam, strips=None):
    print(f"\n--- 4. P(stuck) of every beam length from the strips' Γ CCDF, {fam}, Eq. 16 "
          "(paper's beam, sharp front, release)")
    if strips is None:
        strips = rs.stiction.strip_adhesive_energy(psd, relative_humidity=args.rh, n=args.n_eq16,
                                                   seed=args.seed + 3).adhesive_energy
    bank = strips.rename(realization="law")
    lengths = np.array([100, 200, 300, 600, 800, 1000, 1200, 1500]) * 1e-6
    t = time.perf_counter()
    closed = rs.stuck_probability(strips, method="front", beam_length=lengths)
    t_closed = time.perf_counter() - t
    t = time.perf_counter()
    beams = rs.beam.simulate(bank, beam_length=lengths, n=args.beams, seed=1)
    t_sim = time.perf_counter() - t
    print(f"  closed form {t_closed * 1e3:.1f} ms for {lengths.size} lengths; {args.beams} simulated beams on the "
          f"same {bank.sizes['law']} strips (rs.beam.simulate) {t_sim:.2f} s")
    worst = 0.0
    for r in strips.rh.values:
        for b, length in enumerate(lengths):
            pc = float(closed.stuck_probability.sel(rh=r).isel(beam_length=b))
            sel = dict(rh=r, beam_length=length)
            ps = float(beams.stuck_probability.sel(sel))
            lo, hi = float(beams.stuck_probability_lower.sel(sel)), float(beams.stuck_probability_upper.sel(sel))
            z = abs(ps - pc) / max(np.sqrt(pc * (1 - pc) / args.beams), 1e-12)
            worst = max(worst, z if 0 < pc < 1 else 0.0)
            print(f"    RH {r:.1f} l {length * 1e6:6.0f} µm: closed form {pc:.4f} "
                  f"[{float(closed.stuck_probability_lower.sel(rh=r).isel(beam_length=b)):.3f}, "
                  f"{float(closed.stuck_probability_upper.sel(rh=r).isel(beam_length=b)):.3f}]  "
                  f"simulated {ps:.4f} [{lo:.4f}, {hi:.4f}]")
    print(f"  largest |simulated - closed form| / binomial sd: {worst:.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--families", nargs="+", default=["table4", "S1"])
    ap.add_argument("--rh", type=float, nargs="+", default=[0.3, 0.5, 0.7, 0.9])
    ap.add_argument("--n-eq16", type=int, default=40, help="Eq. 16 zones per size (part 1, 3)")
    ap.add_argument("--n-bem", type=int, nargs=3, default=[12, 4, 2], help="fft_bem zones of 128², 256², 524x500")
    ap.add_argument("--strips", type=int, default=8, help="strips of part 2 per model")
    ap.add_argument("--bem-strip", type=int, nargs=2, default=[128, 768], help="fft_bem strip of part 2 (px)")
    ap.add_argument("--full", type=int, default=0, help="also N composed fft_bem strips (≈ 10 min each)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--parts", type=int, nargs="+", default=[1, 2, 3, 4])
    ap.add_argument("--beams", type=int, default=20000, help="simulated beams per length and RH (part 4)")
    ap.add_argument("--grooved", action="store_true",
                    help="part 2 on strips grooved 5 rms deep along every cut (no contact near a cut)")
    args = ap.parse_args()
    warnings.simplefilter("ignore")  # validity warnings of Eq. 16 outside its map: not the point here
    print(f"yardstick: one 1024² complex iFFT {ifft_seconds() * 1e3:.1f} ms; command: {' '.join(sys.argv)}")
    t0 = time.perf_counter()
    worst = {}
    for fam in args.families:
        psd = rs.datasets.family_psd(fam)
        direct = size_law(psd, args, fam) if 1 in args.parts or 3 in args.parts else None
        if 2 in args.parts:
            for model, w in law_check(psd, args, fam).items():
                worst[model] = max(worst.get(model, 0.0), w)
        if 3 in args.parts and direct is not None:
            prediction_check(psd, args, fam, direct)
        if 4 in args.parts:
            every_length(psd, args, fam)
    if 2 in args.parts:
        for model, w in worst.items():
            print(f"\ncomposed-strip law vs direct strips, {model}, largest quantile difference over "
                  f"{', '.join(args.families)} and RH {args.rh}: {100 * w:.2f} % "
                  f"({'PASS' if w <= 0.05 else 'FAIL'}: criterion 5 %)")
    print(f"total {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
