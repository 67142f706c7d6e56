"""The designer's answer on the beam's own zone: P(stuck) of the paper's beams versus RH.

Table 4 PSD, the paper's adsorbed layer, the paper's beam (w 30 µm, t 2.62 µm, gap 1.9 µm,
E 164 GPa), strips Δs × w = 2.62 × 30 µm at 5 nm composed of 12 sub-zones of 524 × 500 pixels
(``rs.stiction.strip_stuck_probability``: Eq. 16 on every sub-zone, fft_bem on the first
``--n-accurate`` where the answer depends on it, the strips' tail by importance-sampled
recombination of the sub-zone laws, the accurate model through the pairs' strip ratio).

    python benchmarks/bench_designer.py table            # RH 0.60-0.85 x l 150-300 µm, crossing at 1e-3
    python benchmarks/bench_designer.py seeds --rh 0.75  # true cv and coverage over independent seeds
    python benchmarks/bench_designer.py convergence      # the 1e-3 crossing as zone, pixel, grid, model refine

``seeds`` repeats the estimate with independent seeds and compares the reported cv with the
spread (the true cv) and each interval with the mean of the *other* seeds (leave-one-out
reference), at the beam length whose P(stuck) is nearest 1e-4.
"""

from __future__ import annotations

import argparse
import math
import time
import warnings

import numpy as np

import roughstick as rs

RH = [0.60, 0.65, 0.70, 0.75, 0.80, 0.85]
LENGTHS = [150e-6, 200e-6, 250e-6, 300e-6]


def _fmt(p, lo, hi):
    if p == 0:
        return "0 (beyond reach)".ljust(30)
    return f"{p:9.3g} [{lo:8.2g}, {hi:8.2g}]".ljust(30)


def table(args):
    psd = rs.datasets.family_psd("table4")
    t = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        r = rs.stiction.strip_stuck_probability(psd, relative_humidity=RH, beam_length=LENGTHS, n=args.n,
                                                n_accurate=args.n_accurate, n_tail=args.n_tail, seed=args.seed)
    wall = time.perf_counter() - t
    a = r.attrs
    print(f"Table 4, paper layer and beam; strips of {a['subzones']} sub-zones {a['subzone_shape']} at 5 nm; "
          f"{a['n_cheap_subzones']} Eq. 16 sub-zones ({a['cheap_zone_equivalents']:.0f} zone equivalents, "
          f"all RH), {a['n_accurate_subzones']} fft_bem sub-zones ({a['n_random_pairs']} random + "
          f"{a['n_tail_subzones']} strongest; {a['accurate_zone_equivalents']:.0f} zone equivalents) per RH "
          "where needed")
    n_acc_rh = int(r.accurate_model_run.sum())
    print(f"wall {wall:.0f} s: Eq. 16 {a['seconds_cheap']:.0f} s (all RH), fft_bem {a['seconds_accurate']:.0f} s "
          f"({n_acc_rh} RH: {a['seconds_accurate'] / max(n_acc_rh, 1):.0f} s per RH), estimator "
          f"{a['seconds_estimator']:.0f} s")
    print(f"{'RH':>5} {'fft_bem':>7} {'eff.sub':>7} {'R(med)':>6}  " + "".join(
        f"{f'l = {length * 1e6:.0f} µm: P [95 %]  cv':>36}" for length in LENGTHS))
    for k, rh in enumerate(RH):
        row = r.isel(rh=k)
        ratio = float(row.accurate_ratio.sel(quantile=0.5)) if bool(row.accurate_model_run) else float("nan")
        cells = ""
        for b in range(len(LENGTHS)):
            c = row.isel(beam_length=b)
            cells += "  " + _fmt(float(c.stiction_probability), float(c.stiction_probability_lower),
                                 float(c.stiction_probability_upper)) + f"{float(c.coefficient_of_variation):4.2f}"
        print(f"{rh:5.2f} {'yes' if bool(row.accurate_model_run) else 'no':>7} "
              f"{float(row.effective_subzones.min()):7.0f} {ratio:6.2f}{cells}"
              + ("  few sub-zones" if bool(row.few_subzones.any()) else ""))
    for k, rh in enumerate(RH):
        row = r.isel(rh=k)
        if bool(row.accurate_model_run):
            q = row.accurate_ratio.values
            share = ", ".join(f"{v:.2f}" for v in row.accurate_share.values)
            print(f"RH {rh:.2f}: Γ_bem/Γ_eq16 of the random pairs' sub-zones {q[0]:.2f} / {q[1]:.2f} / {q[2]:.2f} "
                  f"(10/50/90 %); held-out pair strips ({int(row.ratio_check_strips)}): rms z "
                  f"{float(row.ratio_check_rms_z):.2f}, within 2 sd {100 * float(row.ratio_check_within_2sd):.0f} %; "
                  f"tail influence on fft_bem sub-zones per length: {share}")
    fill = r.copy()
    # beyond reach: the estimate 0 has no upper bound from the sample; the crossing's lower end
    # is then the first RH where the sample reaches failures (said below)
    fill["stiction_probability_upper"] = fill.stiction_probability_upper.fillna(0.0)
    x = rs.stiction.crossing_humidity(fill, probability=1e-3)
    for b, length in enumerate(LENGTHS):
        c = x.isel(beam_length=b)
        print(f"l = {length * 1e6:.0f} µm: P(stuck) = 1e-3 at RH {float(c.crossing_humidity):.3f} "
              f"[{float(c.crossing_humidity_lower):.3f}, {float(c.crossing_humidity_upper):.3f}]")
    beyond = r.beyond_reach.values.astype(bool)
    if beyond.any():
        m = r.reach_margin.values[beyond]
        print(f"beyond reach ({beyond.sum()} cells): thresholds {m.min():.1f}-{m.max():.3g} x the largest strip "
              "Γ of any combination of the sample")


def seeds(args):
    psd = rs.datasets.family_psd("table4")
    est, cvs, walls = [], [], []
    for s in range(args.seeds):
        t = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            r = rs.stiction.strip_stuck_probability(
                psd, relative_humidity=[args.rh], beam_length=LENGTHS, n=args.n, n_accurate=args.n_accurate,
                n_tail=args.n_tail, accurate_model=None if args.n_accurate == 0 else "fft_bem", seed=1000 + s)
        walls.append(time.perf_counter() - t)
        est.append(r.stiction_probability.values[0])
        cvs.append(r.coefficient_of_variation.values[0])
        print(f"seed {s}: " + "  ".join(f"{p:.3g} (cv {c:.2f})" for p, c in zip(est[-1], cvs[-1]))
              + f"  {walls[-1]:.0f} s, eff. sub-zones {float(r.effective_subzones.min()):.0f}", flush=True)
    est, cvs = np.array(est), np.array(cvs)
    z = 1.959963984540054
    print(f"RH {args.rh}, n = {args.n} Eq. 16 sub-zones, {args.n_accurate} fft_bem, {args.seeds} seeds, "
          f"{np.mean(walls):.0f} s per estimate")
    for b, length in enumerate(LENGTHS):
        p = est[:, b]
        if not np.all(p > 0):
            print(f"l = {length * 1e6:.0f} µm: some seeds beyond reach ({np.sum(p == 0)} of {p.size})")
            continue
        true_cv = p.std(ddof=1) / p.mean()
        covered = 0
        for s in range(p.size):
            ref = np.delete(p, s).mean()
            covered += p[s] * math.exp(-z * cvs[s, b]) <= ref <= p[s] * math.exp(z * cvs[s, b])
        print(f"l = {length * 1e6:.0f} µm: mean P {p.mean():.3g}, true cv {true_cv:.2f}, reported cv (mean) "
              f"{np.mean(cvs[:, b]):.2f} ({np.mean(cvs[:, b]) / true_cv:.2f} x true), intervals covering the "
              f"other seeds' mean {covered}/{p.size}")


def convergence(args):
    """The 1e-3 crossing RH of a 200 µm beam as the zone's tiling, the pixel, the distance grid and
    the model are refined: each row one call, its crossing with its interval and its wall time."""
    psd = rs.datasets.family_psd("table4")
    rh = [0.70, 0.72, 0.74, 0.76, 0.78, 0.80]
    n = args.n
    rows = [
        ("Eq. 16, 5 nm, 12 x 524x500 (base)", dict(n=n)),
        ("Eq. 16, 5 nm, 6 x 524x1000 (zone tiling)", dict(n=n // 2, subzones=6)),
        ("Eq. 16, 5 nm, distance grid x 2", dict(n=n, n_distance="x2")),
        ("Eq. 16, 10 nm pixel", dict(n=n, spacing=10e-9)),
        ("Eq. 16, 2.5 nm pixel", dict(n=n // 4, spacing=2.5e-9)),
    ] + ([(f"Eq. 16 + fft_bem on {args.n_accurate} sub-zones", dict(n=n, n_accurate=args.n_accurate,
                                                                   accurate_model="fft_bem"))]
         if args.n_accurate else [])
    base_points = None
    print(f"Table 4, 200 µm beam, RH {rh[0]}-{rh[-1]}: the RH where P(stuck) = 1e-3 [95 %]")
    for name, kw in rows:
        kw = dict(kw)
        kw.setdefault("accurate_model", None)
        if kw.get("n_distance") == "x2":
            kw["n_distance"] = 2 * base_points
        t = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            r = rs.stiction.strip_stuck_probability(psd, relative_humidity=rh, beam_length=[200e-6],
                                                    seed=args.seed, **kw)
        wall = time.perf_counter() - t
        base_points = base_points or r.attrs["n_distance"]
        fill = r.copy()
        fill["stiction_probability_upper"] = fill.stiction_probability_upper.fillna(0.0)
        x = rs.stiction.crossing_humidity(fill, probability=1e-3).isel(beam_length=0)
        p = r.stiction_probability.isel(beam_length=0).values
        print(f"{name:44s} {float(x.crossing_humidity):.3f} [{float(x.crossing_humidity_lower):.3f}, "
              f"{float(x.crossing_humidity_upper):.3f}]  n = {r.attrs['n_cheap_subzones']}, "
              f"{r.attrs['n_distance']} distances, {wall:.0f} s;  P: "
              + " ".join(f"{v:.2g}" for v in p), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("part", choices=["table", "seeds", "convergence"])
    ap.add_argument("--n", type=int, default=12_000, help="Eq. 16 sub-zones")
    ap.add_argument("--n-accurate", type=int, default=240, help="fft_bem sub-zones per RH (0: Eq. 16 alone)")
    ap.add_argument("--n-tail", type=int, default=48, help="strongest sub-zones also through fft_bem")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--rh", type=float, default=0.75)
    args = ap.parse_args()
    {"table": table, "seeds": seeds, "convergence": convergence}[args.part](args)


if __name__ == "__main__":
    main()
