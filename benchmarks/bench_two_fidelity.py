"""Benchmark of the two-fidelity rare-event estimator (``failure_probability(..., accurate_model=)``).

The estimator runs subset simulation on the modified DMT (Eq. 16) to a relaxed threshold set by a
measured bound on the ratio fft_bem / Eq. 16 on tail states, then ``fft_bem`` on a few hundred
final-level states (docs/rare_events.md, "Two fidelities"). This script measures it where crude
Monte Carlo with ``fft_bem`` alone is affordable: small Table-4 zones at 5 nm, a threshold at
P of about 1e-2.

crude
    ``--n`` zones (white noise from ``SeedSequence(--crude-seed)``) through both models, the
    same limit states the estimator evaluates; cached in ``benchmarks/.cache/two_fidelity_crude_*.npz``
    (gitignored) block by block, so a stopped run resumes. Prints P(fft_bem > threshold) with its
    Clopper-Pearson interval and P(Eq. 16 > threshold).
coverage
    The two-fidelity estimate for seeds 0..S-1 against the crude reference: per seed the estimate,
    its 95 % interval, cv, cheap / accurate evaluations, the containment check and wall time; then
    how many intervals hold the reference.
containment
    The estimator's pilot rule (its constants) replayed on subsets of the crude sample: the ratio
    bound it sets and the share of the fft_bem failures that would lie below the run's threshold.

    nice -n 10 python benchmarks/bench_two_fidelity.py crude --n 20000
    nice -n 10 python benchmarks/bench_two_fidelity.py coverage --seeds 20
    nice -n 10 python benchmarks/bench_two_fidelity.py containment
    nice -n 10 python benchmarks/bench_two_fidelity.py coverage --shape 128 --threshold 0.0095 --seeds 4 \
        --reference 5.25e-5     # deeper: against the mean of four fft_bem-only subset runs
"""

from __future__ import annotations

import argparse
import json
import pathlib
import time
import warnings

import numpy as np
from scipy.stats import beta

import roughstick as rs
from roughstick.contact import water_height
from roughstick.reliability import _fidelity as _f
from roughstick.reliability import _surface as _s

HERE = pathlib.Path(__file__).resolve().parent
CACHE = HERE / ".cache"
SPACING = 5e-9
BLOCK = 500


def responses(shape, rh):
    """The limit states of the estimator: Eq. 16 and fft_bem on the same white noise."""
    psd = rs.datasets.family_psd("table4")
    f = _s.NoiseToSurface(psd, shape=shape, spacing=SPACING)
    hw = float(water_height(rh).values)
    return (_s.SurfaceResponse(f, relative_humidity=rh, water_height=hw, model="modified_dmt"),
            _s.SurfaceResponse(f, relative_humidity=rh, water_height=hw, model="fft_bem"))


def crude(args):
    shape = (args.shape, args.shape)
    path = CACHE / f"two_fidelity_crude_table4_{args.shape}_rh{args.rh:g}_seed{args.crude_seed}.npz"
    CACHE.mkdir(exist_ok=True)
    yc, ya, wall = (np.empty(0),) * 2 + (0.0,)
    if path.exists():
        d = np.load(path)
        yc, ya, wall = d["cheap"], d["accurate"], float(d["wall"])
    cheap, accurate = responses(shape, args.rh)
    while yc.size < args.n:
        b = yc.size // BLOCK
        rng = np.random.default_rng([args.crude_seed, b])
        t0 = time.perf_counter()
        zs = rng.standard_normal((BLOCK,) + shape)
        yc = np.concatenate([yc, [cheap(z) for z in zs]])
        ya = np.concatenate([ya, [accurate(z) for z in zs]])
        wall += time.perf_counter() - t0
        np.savez(path, cheap=yc, accurate=ya, wall=wall)
        print(f"  {yc.size} zones, {wall:.0f} s", flush=True)
    return yc[:args.n], ya[:args.n], wall


def reference(args):
    yc, ya, wall = crude(args)
    n, k = ya.size, int(np.sum(ya > args.threshold))
    lo = beta.ppf(0.025, k, n - k + 1) if k else 0.0
    hi = beta.ppf(0.975, k + 1, n - k)
    return k / n, lo, hi, k, n, yc, ya, wall


def main_crude(args):
    p, lo, hi, k, n, yc, ya, wall = reference(args)
    print(f"Table 4, {args.shape}^2 px at 5 nm, RH {args.rh}: {n} zones through Eq. 16 and fft_bem, {wall:.0f} s")
    for q in (0.9, 0.97, 0.99, 0.995):
        print(f"  quantile {q}: fft_bem {np.quantile(ya, q) * 1e3:.2f} mJ/m2, Eq. 16 {np.quantile(yc, q) * 1e3:.2f}")
    print(f"P(fft_bem > {args.threshold * 1e3:g} mJ/m2) = {p:.4e} [{lo:.4e}, {hi:.4e}] (Clopper-Pearson 95 %), "
          f"{k} failures of {n}")
    print(f"P(Eq. 16 > threshold) = {np.mean(yc > args.threshold):.4e}")
    r = ya / yc
    top = np.argsort(yc)[::-1][:200]
    print(f"ratio fft_bem / Eq. 16: all zones max {r.max():.3f}, 99.9 % {np.quantile(r, 0.999):.3f}; "
          f"200 highest Eq. 16 max {r[top].max():.3f}; fft_bem failures max {r[ya > args.threshold].max():.3f} "
          f"min Eq. 16 of fft_bem failures {yc[ya > args.threshold].min() * 1e3:.2f} mJ/m2")


def estimate(args, seed):
    """One two-fidelity estimate, cached in benchmarks/.cache (a rerun prints it again)."""
    path = CACHE / (f"two_fidelity_est_table4_{args.shape}_rh{args.rh:g}_t{args.threshold:g}_"
                    f"a{args.n_accurate}_n{args.n_per_level}_seed{seed}.json")
    if path.exists():
        return json.loads(path.read_text())
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        ds = rs.reliability.failure_probability(
            rs.datasets.family_psd("table4"), threshold=args.threshold, relative_humidity=args.rh,
            shape=(args.shape, args.shape), spacing=SPACING, model="modified_dmt", accurate_model="fft_bem",
            n_accurate=args.n_accurate, n_per_level=args.n_per_level, seed=seed, scheduler="sync")
    row = {v: float(ds[v]) for v in ("failure_probability", "failure_probability_lower",
                                     "failure_probability_upper", "coefficient_of_variation", "n_evaluations",
                                     "n_accurate_evaluations", "ratio_bound", "containment_checked",
                                     "containment_violations", "cheap_probability", "conditional_fraction",
                                     "passes")}
    row["wall"] = time.perf_counter() - t0
    CACHE.mkdir(exist_ok=True)
    path.write_text(json.dumps(row))
    return row


def passes(row, args):
    """Passes of a stored estimate (rows stored before the field: a first pass never spends more
    than n_accurate plus the pilot's 32 accurate evaluations)."""
    if "passes" in row:
        return int(row["passes"])
    return 2 if row["n_accurate_evaluations"] > args.n_accurate + _f.PILOT_STATES else 1


def main_coverage(args):
    crude_path = CACHE / f"two_fidelity_crude_table4_{args.shape}_rh{args.rh:g}_seed{args.crude_seed}.npz"
    print(f"Table 4, {args.shape}^2 px at 5 nm, RH {args.rh}, threshold {args.threshold * 1e3:g} mJ/m2; "
          f"n_per_level {args.n_per_level}, n_accurate {args.n_accurate}")
    print("seed  P           95% interval              cv     P(Eq.16>t_b)  fraction  Eq.16 evals  fft_bem evals  "
          "ratio bound  band fails  passes  wall")
    rows = []
    for seed in range(args.first_seed, args.first_seed + args.seeds):
        r = estimate(args, seed)
        rows.append(r)
        print(f"{seed:4d}  {r['failure_probability']:.3e}  [{r['failure_probability_lower']:.3e}, "
              f"{r['failure_probability_upper']:.3e}]  {r['coefficient_of_variation']:.3f}  "
              f"{r['cheap_probability']:12.3e}  {r['conditional_fraction']:8.3f}  {int(r['n_evaluations']):11d}  "
              f"{int(r['n_accurate_evaluations']):13d}  {r['ratio_bound']:11.3f}  "
              f"{int(r['containment_violations'])}/{int(r['containment_checked']):<8d}  {passes(r, args)}       "
              f"{r['wall']:5.1f} s", flush=True)
    est = np.array([r["failure_probability"] for r in rows])
    cvs = np.array([r["coefficient_of_variation"] for r in rows])
    print(f"mean estimate {est.mean():.4e}; spread of the estimates (true cv of one run) "
          f"{est.std(ddof=1) / est.mean():.3f}; mean reported cv {cvs.mean():.3f}; "
          f"mean evaluations Eq. 16 {np.mean([r['n_evaluations'] for r in rows]):.0f}, "
          f"fft_bem {np.mean([r['n_accurate_evaluations'] for r in rows]):.0f}; "
          f"mean wall {np.mean([r['wall'] for r in rows]):.1f} s")
    if args.reference is not None:  # where crude fft_bem Monte Carlo is not affordable
        hold = [r["failure_probability_lower"] <= args.reference <= r["failure_probability_upper"] for r in rows]
        print(f"given reference P = {args.reference:.3e}: mean estimate / reference {est.mean() / args.reference:.2f}; "
              f"{sum(hold)}/{len(rows)} intervals hold it")
        return
    if not crude_path.exists() or np.load(crude_path)["accurate"].size < args.n:
        print("crude reference not complete yet: run the 'crude' part (or give --reference)")
        return
    p, lo, hi, k, n, *_ = reference(args)
    hold = [r["failure_probability_lower"] <= p <= r["failure_probability_upper"] for r in rows]
    print(f"reference (crude fft_bem, {n} zones, {k} failures): P = {p:.4e} [{lo:.4e}, {hi:.4e}] (Clopper-Pearson)")
    print(f"coverage: {sum(hold)}/{len(rows)} intervals hold the reference (missed by seeds "
          f"{[args.first_seed + i for i, h in enumerate(hold) if not h]}); mean estimate / reference "
          f"{est.mean() / p:.3f} (+- {est.std(ddof=1) / np.sqrt(est.size) / p:.3f} s.e.)")


def main_containment(args):
    """The estimator's pilot rule replayed on the crude sample: how often, and how much of the
    fft_bem failure probability, lies below the run's threshold (missed by construction)."""
    p, lo, hi, k, n, yc, ya, _ = reference(args)
    fails, ratio = ya > args.threshold, ya / yc
    print(f"{n} crude zones, {k} fft_bem failures above {args.threshold * 1e3:g} mJ/m2; their fft_bem / Eq. 16 "
          f"ratio: median {np.median(ratio[fails]):.3f}, 90 % {np.quantile(ratio[fails], 0.9):.3f}, "
          f"max {ratio[fails].max():.3f}; all zones: max {ratio.max():.3f}")
    rng = np.random.default_rng(0)
    bounds, missed = [], []
    for _ in range(args.replays):
        pool = rng.choice(n, args.n_per_level, replace=False)
        pilot = pool[np.argsort(yc[pool])[::-1][:_f.PILOT_STATES]]
        rb = ratio[pilot].max() * (1 + _f.RATIO_MARGIN)
        bounds.append(rb)
        missed.append(np.sum(fails & (yc <= (1 - _f.BAND) * args.threshold / rb)) / k)
    bounds, missed = np.array(bounds), np.array(missed)
    print(f"pilot rule replayed {args.replays} x ({_f.PILOT_STATES} highest Eq. 16 of {args.n_per_level} zones, "
          f"max ratio x {1 + _f.RATIO_MARGIN:g}, band {_f.BAND:g}): ratio bound 10/50/90 % "
          f"{np.quantile(bounds, 0.1):.3f} / {np.median(bounds):.3f} / {np.quantile(bounds, 0.9):.3f}; "
          f"share of the fft_bem failures below the run's threshold: mean {missed.mean():.2e}, max {missed.max():.3f}, "
          f"nonzero in {np.mean(missed > 0):.1%} of the replays")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("part", choices=("crude", "coverage", "containment"))
    ap.add_argument("--shape", type=int, default=32)
    ap.add_argument("--rh", type=float, default=0.5)
    ap.add_argument("--threshold", type=float, default=0.07, help="J/m2")
    ap.add_argument("--n", type=int, default=20000, help="crude Monte Carlo zones")
    ap.add_argument("--crude-seed", type=int, default=2026)
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--n-accurate", type=int, default=300)
    ap.add_argument("--n-per-level", type=int, default=1000)
    ap.add_argument("--reference", type=float, default=None,
                    help="coverage: a reference P from elsewhere (e.g. fft_bem-only subset runs) instead of crude MC")
    ap.add_argument("--replays", type=int, default=1000, help="containment: pilot replays")
    args = ap.parse_args()
    warnings.filterwarnings("ignore", category=rs.ValidityWarning)
    {"crude": main_crude, "coverage": main_coverage, "containment": main_containment}[args.part](args)


if __name__ == "__main__":
    main()
