"""The designer's answer on the beam's own zone: P(stuck) of the paper's beams versus RH.

Table 4 PSD, the paper's adsorbed layer, the paper's beam (w 30 µm, t 2.62 µm, gap 1.9 µm,
E 164 GPa), strips Δs × w = 2.62 × 30 µm at 5 nm composed of 12 sub-zones of 524 × 500 pixels
(``rs.stiction.strip_stuck_probability``: Eq. 16 on every sub-zone, fft_bem on the first
``--n-accurate`` where the answer depends on it, the strips' tail by importance-sampled
recombination of the sub-zone laws, the accurate model through the pairs' strip ratio).

    python benchmarks/bench_designer.py table            # RH 0.60-0.85 x l 150-300 µm, crossing at 1e-3
    python benchmarks/bench_designer.py table --refine 1 # the same, the crossings refined (refine_crossing)
    python benchmarks/bench_designer.py seeds --rh 0.75  # true cv and coverage over independent seeds
    python benchmarks/bench_designer.py convergence      # the 1e-3 crossing as zone, pixel, grid, model refine
    python benchmarks/bench_designer.py cohesive         # the sharp front against the cohesive beam, same strips
    python benchmarks/bench_designer.py composition --rh 0.77 --cache DIR  # the hybrid on strong strips, across seeds
    python benchmarks/bench_designer.py replicates --rh 0.77 --cache DIR   # true cv over pooled-pair replicates
    python benchmarks/bench_designer.py whole --rh 0.77 --cache DIR        # fft_bem on whole strong strips
    python benchmarks/bench_designer.py whole --rh 0.77 --family S1 --fresh 480  # the same on another PSD

``cohesive`` draws beams from one bank of the strips' pressure laws (Eq. 16, composed of the
sub-zones) and releases each twice, as a sharp front on the strips' Γ and as the cohesive
Euler-Bernoulli beam on their full laws, same patches: where the two disagree the sharp-front
product of the strips route is not enough.

``seeds`` repeats the estimate with independent seeds and compares the reported cv with the
spread (the true cv) and each interval with the mean of the *other* seeds (leave-one-out
reference), at the beam length whose P(stuck) is nearest 1e-4.

``composition`` reads the laws ``seeds --cache DIR`` kept and checks the two-fidelity hybrid
where the tail is: strips holding j of the strongest sub-zones (the other seeds' tails, as if
the accurate model had seen them) and 12 - j random ones, and strips of unseen strong
sub-zones (the strongest of the other seeds' pairs), each predicted from one seed's accurate
sub-zones and compared with its accurate Γ (the bias in log Γ, its spread between fits, and
the z-scores of the prediction).

``replicates`` reads the same laws and forms new independent estimates from them: seed k's
Eq. 16 sub-zones with the k-th disjoint set of pairs drawn from all seeds' pairs (a one-seed
outlier of the pairs then counts once, not in every run that shares them), and the pairs'
share of the spread alone (one seed's sub-zones with every set).

``whole`` checks the composition itself where the tail is, with the accurate model on both
sides: strips of 12 of the seeds' pair sub-zones (drawn from the strongest quarter by Eq. 16
Γ, every third strip from all of them), each sub-zone regenerated from its seed and index and
rolled so that its edges avoid its tallest summits (a periodic sub-zone's law does not change),
laid side by side and solved whole by ``fft_bem`` (about 5 min per strip at one RH on the 2-core
machine), against the composed law of the same sub-zones' cached ``fft_bem`` laws. With
``--fresh N`` it draws N sub-zones of ``--family``'s PSD itself instead (Eq. 16 on all of them to
find the strongest quarter, ``fft_bem`` on those a strip picks): the model band on another PSD.
"""

from __future__ import annotations

import argparse
import math
import os
import time
import warnings

import numpy as np
import xarray as xr

import roughstick as rs

RH = [0.60, 0.65, 0.70, 0.75, 0.80, 0.85]
LENGTHS = [150e-6, 200e-6, 250e-6, 300e-6]


def _fmt(p, lo, hi):
    if p == 0:
        return "0 (beyond reach)".ljust(30)
    return f"{p:9.3g} [{lo:8.2g}, {hi:8.2g}]".ljust(30)


def _crossings(r, level=1e-3):
    """crossing_humidity of a strips result, a beyond-reach cell's missing upper bound taken as 0
    (the crossing's lower end is then the first RH where the sample reaches failures)."""
    fill = r.copy()
    for v in ("stiction_probability_upper", "stiction_probability_model_upper"):
        if v in fill:
            fill[v] = fill[v].fillna(0.0)
    return rs.stiction.crossing_humidity(fill, probability=level)


def _logit_between(r, b, rh):
    """The estimate at ``rh`` interpolated linearly in logit P between its grid neighbours (nan next
    to a 0 or a 1)."""
    grid, p = r.rh.values, r.stiction_probability.isel(beam_length=b).values
    k = np.searchsorted(grid, rh)
    p0, p1 = p[k - 1], p[k]
    if not (0 < p0 < 1 and 0 < p1 < 1):
        return float("nan")
    lg = np.interp(rh, grid[k - 1:k + 1], np.log(np.array([p0, p1]) / (1 - np.array([p0, p1]))))
    return float(1 / (1 + np.exp(-lg)))


def table(args):
    psd = rs.datasets.family_psd("table4")
    rhs = RH if args.rhs is None else [float(x) for x in args.rhs.split(",")]
    kw = dict(beam_length=LENGTHS, n=args.n, n_accurate=args.n_accurate, n_tail=args.n_tail, seed=args.seed,
              target_cv=args.target_cv, max_accurate=args.max_accurate,
              **({} if args.n_accurate else {"accurate_model": None}))
    t = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        r = rs.stiction.strip_stuck_probability(psd, relative_humidity=rhs, refine_crossing=1e-3 if args.refine else None,
                                                **kw)
    wall = time.perf_counter() - t
    grid = r.sel(rh=rhs)
    for rh in r.attrs.get("refined_humidities", []):  # what the grid alone would have said there
        for b, length in enumerate(LENGTHS):
            guess = _logit_between(grid, b, rh)
            c = r.sel(rh=rh).isel(beam_length=b)
            if np.isfinite(guess) or 0 < float(c.stiction_probability) < 1:
                print(f"refined RH {rh:.3f}, l = {length * 1e6:.0f} µm: the grid's logit interpolation {guess:.3g}, "
                      f"the estimate there {float(c.stiction_probability):.3g} [{float(c.stiction_probability_lower):.2g}, "
                      f"{float(c.stiction_probability_upper):.2g}]", flush=True)
    a = r.attrs
    print(f"Table 4, paper layer and beam; strips of {a['subzones']} sub-zones {a['subzone_shape']} at 5 nm; "
          f"{a['n_cheap_subzones']} Eq. 16 sub-zones ({a['cheap_zone_equivalents']:.0f} zone equivalents, "
          f"all RH), up to {a['n_accurate_subzones']} fft_bem sub-zones ({a['n_random_pairs']} random + "
          f"{a['n_tail_subzones']} strongest; {a['accurate_zone_equivalents']:.0f} zone equivalents) per RH "
          f"where needed: {args.n_accurate} random pairs, doubled where their ratios hold a beam's cv above "
          f"{rs.stiction.strip_tail.TARGET_MARGIN:g} x {a['target_cv']:g} at P >= "
          f"{rs.stiction.strip_tail.TARGET_FLOOR:g}")
    n_acc_rh = int(r.accurate_model_run.sum())
    print(f"wall {wall:.0f} s: Eq. 16 {a['seconds_cheap']:.0f} s (all RH), fft_bem {a['seconds_accurate']:.0f} s "
          f"({n_acc_rh} RH: {a['seconds_accurate'] / max(n_acc_rh, 1):.0f} s per RH), estimator "
          f"{a['seconds_estimator']:.0f} s")
    if a.get("refined_humidities"):
        print(f"refined (up to {rs.stiction.strip_tail.REFINE_CALLS} further calls at the 1e-3 crossings): RH "
              + ", ".join(f"{v:.3f}" for v in a["refined_humidities"]) + "; the times above include them")
    print(f"{'RH':>5} {'pairs':>7} {'eff.sub':>7} {'R(med)':>6}  " + "".join(
        f"{f'l = {length * 1e6:.0f} µm: P [95 %]  cv':>36}" for length in LENGTHS))
    for k, rh in enumerate(r.rh.values):
        row = r.isel(rh=k)
        ratio = float(row.accurate_ratio.sel(quantile=0.5)) if bool(row.accurate_model_run) else float("nan")
        cells = ""
        for b in range(len(LENGTHS)):
            c = row.isel(beam_length=b)
            cells += "  " + _fmt(float(c.stiction_probability), float(c.stiction_probability_lower),
                                 float(c.stiction_probability_upper)) + f"{float(c.coefficient_of_variation):4.2f}"
        print(f"{rh:5.3f} {int(row.random_pairs) if bool(row.accurate_model_run) else 'none':>7} "
              f"{float(row.effective_subzones.min()):7.0f} {ratio:6.2f}{cells}"
              + ("  few sub-zones" if bool(row.few_subzones.any()) else ""))
    for k, rh in enumerate(r.rh.values):
        row = r.isel(rh=k)
        if bool(row.accurate_model_run):
            q = row.accurate_ratio.values
            share = ", ".join(f"{v:.2f}" for v in row.accurate_share.values)
            print(f"RH {rh:.2f}: Γ_bem/Γ_eq16 of the random pairs' sub-zones {q[0]:.2f} / {q[1]:.2f} / {q[2]:.2f} "
                  f"(10/50/90 %); held-out pair strips ({int(row.ratio_check_strips)}): rms z "
                  f"{float(row.ratio_check_rms_z):.2f}, within 2 sd {100 * float(row.ratio_check_within_2sd):.0f} %; "
                  f"tail influence on fft_bem sub-zones per length: {share}")
    band = r.attrs.get("model_band")
    if band is not None:
        print(f"with the model band (every strip's Γ x {1 + band[0]:g} to x {1 + band[1]:g}): P(stuck) interval")
        for k, rh in enumerate(r.rh.values):
            row = r.isel(rh=k)
            print(f"{rh:5.3f} " + "".join(
                f"  {float(c.stiction_probability_model_lower):9.2g} - {float(c.stiction_probability_model_upper):<9.2g}"
                for c in (row.isel(beam_length=b) for b in range(len(LENGTHS)))))
    x = _crossings(r)  # beyond reach: no upper bound from the sample (said below)
    x0 = _crossings(r.sel(rh=rhs)) if r.rh.size > len(rhs) else None
    for b, length in enumerate(LENGTHS):
        c = x.isel(beam_length=b)
        print(f"l = {length * 1e6:.0f} µm: P(stuck) = 1e-3 at RH {float(c.crossing_humidity):.3f} "
              f"[{float(c.crossing_humidity_lower):.3f}, {float(c.crossing_humidity_upper):.3f}]"
              + (f", with the model band [{float(c.crossing_humidity_model_lower):.3f}, "
                 f"{float(c.crossing_humidity_model_upper):.3f}]" if "crossing_humidity_model_lower" in c else "")
              + (f"; the grid alone {float(x0.crossing_humidity[b]):.3f} [{float(x0.crossing_humidity_lower[b]):.3f}, "
                 f"{float(x0.crossing_humidity_upper[b]):.3f}]" if x0 is not None else ""))
    beyond = r.beyond_reach.values.astype(bool)
    if beyond.any():
        m = r.reach_margin.values[beyond]
        print(f"beyond reach ({beyond.sum()} cells): thresholds {m.min():.1f}-{m.max():.3g} x the largest strip "
              "Γ of any combination of the sample")


HITS = []


def _cache_laws(folder):
    """Keep each sub-zone law computation of the seeds on disk (keyed by its arguments), so that a
    second pass re-runs only the estimator on the same laws."""
    import hashlib
    import pathlib

    from roughstick.stiction import strip_tail

    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    compute = strip_tail._subzone_laws

    def cached(psd, rh, n, start, shape, spacing, model, seed, distance, *a, index=None, **kw):
        key = repr((list(map(float, rh)), n, start, list(shape), spacing, model, seed,
                    np.asarray(distance).round(15).tolist(), None if index is None else np.asarray(index).tolist(),
                    a[2:], sorted(kw.items())))
        path = folder / f"{model}_{seed}_{hashlib.sha1(key.encode()).hexdigest()[:16]}.nc"
        if path.exists():
            HITS.append(path.name)
            return xr.open_dataarray(path).load()
        p = compute(psd, rh, n, start, shape, spacing, model, seed, distance, *a, index=index, **kw)
        p.to_netcdf(path.with_suffix(".part"))
        path.with_suffix(".part").rename(path)
        return p

    strip_tail._subzone_laws = cached


def seeds(args):
    psd = rs.datasets.family_psd("table4")
    if args.cache:
        _cache_laws(args.cache)
    est, cvs, walls = [], [], []
    for s in range(args.seeds):
        t = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            r = rs.stiction.strip_stuck_probability(
                psd, relative_humidity=[args.rh], beam_length=LENGTHS, n=args.n, n_accurate=args.n_accurate,
                n_tail=args.n_tail, accurate_model=None if args.n_accurate == 0 else "fft_bem", seed=1000 + s,
                target_cv=args.target_cv, max_accurate=args.max_accurate)
        walls.append(time.perf_counter() - t)
        est.append(r.stiction_probability.values[0])
        cvs.append(r.coefficient_of_variation.values[0])
        print(f"seed {s}: " + "  ".join(f"{p:.3g} (cv {c:.2f})" for p, c in zip(est[-1], cvs[-1]))
              + f"  {walls[-1]:.0f} s, eff. sub-zones {float(r.effective_subzones.min()):.0f}", flush=True)
    est, cvs = np.array(est), np.array(cvs)
    z = 1.959963984540054
    print(f"RH {args.rh}, n = {args.n} Eq. 16 sub-zones, {args.n_accurate} fft_bem, {args.seeds} seeds, "
          f"{np.mean(walls):.0f} s per estimate" + (f" (the laws of {len(HITS)} model runs read from the cache: "
                                                    "the estimator's time only)" if HITS else ""))
    for b, length in enumerate(LENGTHS):
        p = est[:, b]
        if not np.all(p > 0):
            print(f"l = {length * 1e6:.0f} µm: some seeds beyond reach ({np.sum(p == 0)} of {p.size})")
            continue
        true_cv = p.std(ddof=1) / p.mean()
        if true_cv == 0:
            print(f"l = {length * 1e6:.0f} µm: P {p.mean():.3g} on every seed (no spread to compare the cv with)")
            continue
        covered = 0
        for s in range(p.size):
            ref = np.delete(p, s).mean()
            covered += p[s] * math.exp(-z * cvs[s, b]) <= ref <= p[s] * math.exp(z * cvs[s, b])
        print(f"l = {length * 1e6:.0f} µm: mean P {p.mean():.3g}, true cv {true_cv:.2f}, reported cv (mean) "
              f"{np.mean(cvs[:, b]):.2f} ({np.mean(cvs[:, b]) / true_cv:.2f} x true), intervals covering the "
              f"other seeds' mean {covered}/{p.size}")


def _cached_seeds(folder, rh):
    """The laws ``seeds --cache`` kept, per seed at ``rh``: (seed, cheap, accurate), each over
    ``(realization, distance)``: the Eq. 16 laws of all the seed's sub-zones and the fft_bem laws
    of every sub-zone it ran on (each once, its index the realization coordinate)."""
    import glob

    for s in range(1000, 2000):
        files = {m: sorted(glob.glob(os.path.join(folder, f"{m}_{s}_*.nc"))) for m in ("modified_dmt", "fft_bem")}
        if not files["fft_bem"]:
            return
        got = {m: [] for m in files}
        for m, fs in files.items():
            for f in fs:
                with xr.open_dataarray(f) as a:
                    if a.sizes.get("rh") == 1 and abs(float(a.rh[0]) - rh) < 1e-9:
                        got[m].append(a.isel(rh=0).transpose("realization", "distance").load())
        if not got["modified_dmt"] or not got["fft_bem"]:
            continue
        cheap = max(got["modified_dmt"], key=lambda a: a.sizes["realization"])
        acc = xr.concat(got["fft_bem"], "realization")
        acc = acc.isel(realization=np.unique(acc.realization.values, return_index=True)[1])
        yield s, cheap, acc


def _tail_set(cheap, n_pairs, n_tail):
    """The indices of a seed's tail set: its ``n_tail`` sub-zones of largest Eq. 16 Γ beyond its
    first ``n_pairs`` (the random pairs), as the estimator picks them."""
    from roughstick.stiction._strip_hybrid import _gamma

    g = _gamma(cheap.values, cheap.distance.values)
    g[:n_pairs] = -np.inf
    return np.sort(np.argsort(-g, kind="stable")[:n_tail])


def _seed_laws(folder, rh, n_pairs, n_tail):
    """Per seed with the fft_bem laws of its pairs and tail set at ``rh``: the cheap and accurate
    laws of the ``n_pairs`` random pairs and of the tail set, and the distance grid."""
    out = []
    for _, cheap, acc in _cached_seeds(folder, rh):
        pairs, tail = np.arange(n_pairs), _tail_set(cheap, n_pairs, n_tail)
        if not np.isin(np.concatenate([pairs, tail]), acc.realization.values).all():
            continue
        pc, pa = (x.values for x in (cheap.isel(realization=pairs), acc.sel(realization=pairs)))
        tc, ta = (x.values for x in (cheap.isel(realization=tail), acc.sel(realization=tail)))
        out.append((pc, pa, tc, ta, cheap.distance.values))
    return out


def composition(args):
    """Strips of j strong sub-zones (the tails of the *other* seeds, seen by the accurate model)
    and m - j random ones (the other seeds' pairs, unseen), and strips of unseen strong
    sub-zones (the strongest of the other seeds' pairs): their accurate Γ against the hybrid's
    prediction fitted on one seed's accurate sub-zones (ratios drawn for the unseen, the seen
    ones' own ratio, the residual), and against the hybrid that mixes the seen sub-zones'
    accurate laws themselves with the scaled cheap laws."""
    from roughstick.stiction._strip_hybrid import (
        _gamma,
        _hybrid_gamma,
        _hybrid_laws,
        _ratio_pool,
        _residual_pool,
        _with_residual,
    )
    seeds = _seed_laws(args.cache, args.rh, args.n_accurate, args.n_tail)
    if len(seeds) < 3:
        raise SystemExit(f"composition needs the laws of >= 3 seeds at RH {args.rh} in --cache (run `seeds --rh "
                         f"{args.rh} --cache DIR` first); found {len(seeds)}")
    m, n, draws = 12, 200, 64
    d = seeds[0][4]
    rng = np.random.default_rng(args.seed)
    print(f"RH {args.rh}: {len(seeds)} seeds, {n} strips per fit and row; log(prediction / accurate Γ) and "
          "z = (accurate - prediction mean) / prediction sd")
    print(f"{'strips':>36} {'hybrid':>12} {'Γ [J/m2]':>9} {'mean log':>9} {'sd over fits':>12} {'z mean':>7} "
          f"{'z rms':>6} {'|z|<=2':>7}")
    rows = [(f"{j} seen strong + {m - j} unseen random", j, None) for j in (0, 2, 4, 6, 8)]
    rows += [(f"{m} unseen, strongest {f:.0%} of pairs", 0, f) for f in (0.5, 0.25, 0.1)]
    for label, j, frac in rows:
        for how in (("own ratio", "accurate law") if j else ("own ratio",)):
            logs, zs, zero = [], [], 0
            for s, (pc, pa, _, _, _) in enumerate(seeds):
                others = [t for t in range(len(seeds)) if t != s]
                oc, oa, qc, qa = (np.concatenate([seeds[t][k] for t in others]) for k in (2, 3, 0, 1))
                if frac is not None:
                    g = _gamma(qc, d)
                    strong = g >= np.quantile(g, 1 - frac)
                    qc, qa = qc[strong], qa[strong]
                pool = _ratio_pool(pc, pa, d)
                res = _residual_pool(pc, pa, pool, d, m, rng)
                it, ip = rng.integers(0, oc.shape[0], (n, j)), rng.integers(0, qc.shape[0], (n, m - j))
                c, a = np.concatenate([oc[it], qc[ip]], 1), np.concatenate([oa[it], qa[ip]], 1)
                if j and how == "own ratio":
                    c[:, :j] = _hybrid_laws(c[:, :j].reshape(-1, d.size), a[:, :j].reshape(-1, d.size), d,
                                            np.median(_gamma(pc, d))).reshape(n, j, -1)
                elif j:
                    c[:, :j] = a[:, :j]
                free = np.ones((n, m), bool)
                free[:, :j] = False
                u = rng.random((n, draws, m)).reshape(n * draws, m)
                # every strip ``draws`` times, its unseen slots' ratios drawn afresh, as the estimator does
                slots = np.repeat(np.arange(n * m).reshape(n, m), draws, axis=0)
                key = np.log(np.maximum(_gamma(c.reshape(n * m, -1), d), 1e-300))
                g = _hybrid_gamma(c.reshape(n * m, -1), free.reshape(-1), key, pool, slots, u, d)
                pred = _with_residual(g, res, rng.random(n * draws)).reshape(n, draws)
                true = _gamma(a.mean(1), d)
                ok = (pred.mean(1) > 0) & (pred.std(1) > 0)  # a strip the hybrid puts at Γ = 0 is counted apart
                zero += int(np.sum(~ok))
                logs.append(np.log(pred.mean(1)[ok] / true[ok]).mean())
                zs.append((true[ok] - pred.mean(1)[ok]) / pred.std(1)[ok])
            logs, zs = np.array(logs), np.concatenate(zs)
            print(f"{label:>36} {how:>12} {np.median(true):9.4f} {logs.mean():+9.3f} {logs.std():12.3f} "
                  f"{zs.mean():+7.2f} {np.sqrt(np.mean(zs ** 2)):6.2f} {np.mean(np.abs(zs) <= 2):7.2f}"
                  + (f"  ({zero} strips predicted at Γ = 0)" if zero else ""), flush=True)


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


def cohesive(args):
    from roughstick.beam.sharp_front import _draw_indices, n_patches
    from roughstick.contact.adhesion import summary_kernel

    psd = rs.datasets.family_psd("table4")
    rh = RH if args.rhs is None else [float(x) for x in args.rhs.split(",")]
    t = time.perf_counter()
    cache = None if args.cache is None else f"{args.cache}/bank_{args.laws}_{args.seed}_{'_'.join(map(str, rh))}.nc"
    if cache is not None and os.path.exists(cache):
        bank = xr.open_dataarray(cache).load()
    else:
        with warnings.catch_warnings():  # Eq. 16's validity warning: the comparison is of the beam models
            warnings.simplefilter("ignore", UserWarning)
            bank = rs.beam.pressure_law_bank(psd, relative_humidity=rh, n=args.laws, spacing=5e-9, seed=args.seed)
        if cache is not None:
            os.makedirs(args.cache, exist_ok=True)
            bank.to_netcdf(cache)
    t_bank = time.perf_counter() - t
    p = bank.transpose("law", "rh", "gap").values
    gap = bank["gap"].values
    energy = np.stack([summary_kernel(p[:, k], np.zeros_like(p[:, k]), gap)[0] for k in range(len(rh))], axis=1)
    ebank = xr.DataArray(energy, {"law": bank["law"].values, "rh": rh}, ("law", "rh"), attrs={"units": "J m-2"})
    kw = dict(beam_length=LENGTHS, n=args.beams, seed=args.seed)
    sharp = rs.beam.simulate(ebank, **kw)
    t = time.perf_counter()
    coh = rs.beam.simulate(bank, beam_model="cohesive", **kw)
    t_coh = time.perf_counter() - t
    print(f"Table 4, paper layer and beam, Eq. 16: {args.laws} strip laws ({bank.attrs['subzones']} sub-zones "
          f"{bank.attrs['subzone_shape']} each, {bank.sizes['gap']} gaps) in {t_bank:.0f} s; {args.beams} beams "
          f"per length drawn from them, released as a sharp front and as the cohesive beam ({t_coh:.0f} s, "
          f"{int(coh.solver_failed.sum())} solves failed)")
    print("disagree: beams stuck in one model, free in the other; of them 'tip' the sharp-front beams held by\n"
          "their last strip only (s > l - Δs) and 'arc' the cohesive beams left as an arc held by the tip")
    print(f"{'RH':>5} {'l [µm]':>6}  {'P sharp [95 %]':>22}  {'P cohesive [95 %]':>22}  {'P coh. + arc [95 %]':>22}  "
          f"{'disagree':>8} {'tip':>4} {'arc':>4}  {'s_coh - s_sharp [µm] (both stuck)':>34}")
    beam = rs.stiction.PAPER_CANTILEVER
    dx = beam.interaction_zone_length
    idx = _draw_indices(args.seed, np.arange(args.beams), bank.sizes["law"], n_patches(max(LENGTHS), dx))
    z = 1.959963984540054
    rule_rows = []
    for k, h in enumerate(rh):
        for b, length in enumerate(LENGTHS):
            a = sharp.stuck.isel(rh=k, beam_length=b).values.astype(bool)
            ok = ~coh.solver_failed.isel(rh=k, beam_length=b).values
            c = coh.stuck.isel(rh=k, beam_length=b).values.astype(bool)

            def wilson(x):
                nn, pp = x.size, x.mean()
                h_ = z * math.sqrt(pp * (1 - pp) / nn + z * z / (4 * nn * nn)) / (1 + z * z / nn)
                mid = (pp + z * z / (2 * nn)) / (1 + z * z / nn)
                return f"{pp:.3f} [{max(mid - h_, 0):.3f}, {min(mid + h_, 1):.3f}]"

            arc = coh.arc.isel(rh=k, beam_length=b).values.astype(bool)
            s_sharp = sharp.crack_length.isel(rh=k, beam_length=b).values
            dis = ok & (a != c)
            tip = int(np.sum(dis & a & (s_sharp > length - rs.stiction.PAPER_CANTILEVER.interaction_zone_length)))
            both = a & c & ok
            ds = (coh.crack_length.isel(rh=k, beam_length=b).values[both]
                  - sharp.crack_length.isel(rh=k, beam_length=b).values[both]) * 1e6
            dtxt = f"mean {ds.mean():+.1f}, range {ds.min():+.1f} to {ds.max():+.1f}" if ds.size else "-"
            # the arc rule: the tip strip holds an arc when its Γ exceeds K / (4 l^4)
            tip_g = energy[idx[:, n_patches(length, dx) - 1], k]
            rule = a | (tip_g > beam.stiffness_term / (4 * length**4))
            rule_rows.append(f"{h:5.2f} {length * 1e6:6.0f}  {wilson(rule[ok]):>22}  {wilson((c | arc)[ok]):>22}  "
                             f"{int(np.sum(rule[ok] != (c | arc)[ok])):>8}")
            print(f"{h:5.2f} {length * 1e6:6.0f}  {wilson(a[ok]):>22}  {wilson(c[ok]):>22}  "
                  f"{wilson((c | arc)[ok]):>22}  {int(dis.sum()):>8} {tip:>4} {int(np.sum(dis & arc)):>4}  "
                  f"{dtxt:>34}", flush=True)


    if args.cache is not None:
        np.savez(cache.replace(".nc", f"_beams{args.beams}.npz"), energy=energy, idx=idx, rh=rh,
                 sharp=sharp.stuck.values, sharp_s=sharp.crack_length.values, coh=coh.stuck.values,
                 arc=coh.arc.values, failed=coh.solver_failed.values, lengths=LENGTHS)
    print("\nThe sharp front with the arc rule (stuck when an S-front holds or the tip strip's Γ exceeds "
          "K/(4 l^4),\nthe force a tip-held arc needs) against the cohesive beam, arcs counted as stuck:")
    print(f"{'RH':>5} {'l [µm]':>6}  {'P sharp + arc rule':>22}  {'P cohesive + arc':>22}  {'disagree':>8}")
    print("\n".join(rule_rows))


def replicates(args):
    """Independent replicates from the seeds' cached laws: seed k's Eq. 16 sub-zones and tail set
    with the k-th of disjoint sets of ``--n-accurate`` random pairs drawn from all seeds' pairs
    pooled (they are random sub-zones of the same PSD, so each set is a new sample of pairs); and
    the pairs' share alone, seed 0's sub-zones with each set. The true cv and the reported one of
    the 200 µm beam's P(stuck), as in ``seeds``."""
    from roughstick.stiction._strip_answer import _beam_probability
    from roughstick.stiction.strip_tail import (
        PAPER_CANTILEVER,
        TARGET_MARGIN,
        _patch_thresholds,
        _short_of_target,
    )

    n_pairs, z = args.n_accurate, 1.959963984540054
    n_own = args.pool_pairs or n_pairs  # the pairs each seed gives to the pool
    seeds = []
    for _, c, a in _cached_seeds(args.cache, args.rh):
        tail = _tail_set(c, n_own, args.n_tail)
        if np.isin(np.concatenate([np.arange(n_own), tail]), a.realization.values).all():
            seeds.append((c, a, tail))
    if not seeds:
        raise SystemExit(f"no seed in {args.cache} holds fft_bem laws of {n_own} pairs and of its tail set: "
                         f"run 'seeds --n-accurate {n_own} --cache {args.cache}' first")
    beam = PAPER_CANTILEVER
    allt, per = _patch_thresholds(np.array([200e-6]), beam, beam.interaction_zone_length)
    pc_pool = np.concatenate([c.values[:n_own] for c, _, _ in seeds])
    pa_pool = np.concatenate([a.sel(realization=np.arange(n_own)).values for _, a, _ in seeds])
    perm = np.random.default_rng(args.seed).permutation(pc_pool.shape[0])
    k_sets = pc_pool.shape[0] // n_pairs
    print(f"RH {args.rh}: {len(seeds)} seeds' laws, {pc_pool.shape[0]} pooled pairs in {k_sets} sets of {n_pairs}; "
          f"200 µm beam's P(stuck)")
    for label, rows in (("replicates (seed k's sub-zones, set k)", range(min(len(seeds), k_sets))),
                        ("pairs alone (seed 0's sub-zones, every set)", range(k_sets))):
        est, cvs, used, first = [], [], [], []
        for k in rows:
            c, a, tail = seeds[k if label.startswith("replicates") else 0]
            sel = perm[k * n_pairs:(k + 1) * n_pairs]
            # the seed's own pairs give way to the set (its tail set, all beyond them, moves along)
            pc = np.concatenate([pc_pool[sel], c.values[n_own:]])
            cheap = xr.DataArray(pc, dims=("realization", "distance"),
                                 coords={"realization": np.arange(pc.shape[0]), "distance": c.distance.values,
                                         "rh": c.rh.values})
            # --target-cv: the default call's rule, half the pairs first and all of them where the
            # 200 µm beam's cv is above the target with the pairs' ratios half its variance
            for size in ([n_pairs // 2, n_pairs] if args.target_cv else [n_pairs]):
                known = np.concatenate([np.arange(size), tail - n_own + n_pairs])
                acc = xr.DataArray(np.concatenate([pa_pool[sel[:size]], a.sel(realization=tail).values]),
                                   dims=("realization", "distance"),
                                   coords={"realization": known, "distance": c.distance})
                r = rs.stiction.strip_ccdf(cheap, allt, subzones=12, accurate=acc, random_pairs=size,
                                           n_combinations=100_000, n_boot=20, seed=k)
                e = r.exceedance_probability.values[0]
                p, sd = _beam_probability(e, np.nan_to_num(r.coefficient_of_variation.values[0]) * e, per[0])
                sd_pairs = _beam_probability(e, np.nan_to_num(r.emulator_cv.values[0]) * e, per[0])[1]
                if size < n_pairs:
                    first.append((p, sd / p))
                if not _short_of_target(p, sd / max(p, 1e-300), sd_pairs / max(p, 1e-300), args.target_cv):
                    break
            est.append(p)
            cvs.append(sd / p)
            used.append(size)
        p, c = np.array(est), np.array(cvs)
        if args.target_cv:
            h = np.array(first)
            print(f"    with {n_pairs // 2} pairs: " + " ".join(f"{x:.3g} ({y:.2f})" for x, y in h)
                  + f"; true cv {h[:, 0].std(ddof=1) / h[:, 0].mean():.2f}")
            print(f"    pairs used (target cv {args.target_cv:g}, more pairs above {TARGET_MARGIN * args.target_cv:g}): "
                  f"{used}")
        cov = sum(p[i] * np.exp(-z * c[i]) <= np.delete(p, i).mean() <= p[i] * np.exp(z * c[i]) for i in range(p.size))
        print(f"  {label}: " + " ".join(f"{x:.3g} ({y:.2f})" for x, y in zip(p, c)))
        print(f"    {p.size} estimates: mean P {p.mean():.3g}, true cv {p.std(ddof=1) / p.mean():.2f}, reported cv "
              f"mean {c.mean():.2f} ({c.mean() / (p.std(ddof=1) / p.mean()):.2f} x true), intervals covering the "
              f"others' mean {cov}/{p.size}", flush=True)


def _fresh_subzones(psd, rh, n, seed):
    """``n`` sub-zones of 524 × 500 px at 5 nm drawn with ``seed``: (seed, index, Eq. 16 Γ, None)
    of each (its fft_bem law computed when a strip picks it), and the distance grid."""
    from roughstick.stiction import strip_tail
    from roughstick.stiction._strip_hybrid import _gamma
    from roughstick.stiction.zone import _callable_m0

    shape = (524, 500)
    grid_psd = {"psd": psd} if isinstance(psd, xr.DataArray) else {"m0": _callable_m0(psd, shape, 5e-9)}
    d = np.asarray(rs.ensemble.distance_grid(**grid_psd, shape=shape, n=n, relative_humidity=[rh],
                                             adsorbed_layer="paper").values, dtype=float)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        cheap = strip_tail._subzone_laws(psd, [rh], n, 0, shape, 5e-9, "modified_dmt", seed, d, "threads", None)
    g = _gamma(cheap.isel(rh=0).transpose("realization", "distance").values, d)
    return [(seed, k, float(g[k]), None) for k in range(n)], d


def whole(args):
    """``fft_bem`` on whole strips of sub-zones against their composed ``fft_bem`` law: the
    seeds' cached pairs (``--cache``, Table 4) or ``--fresh N`` sub-zones of ``--family`` drawn
    here."""
    from bench_zone_size import seam_roll

    from roughstick.contact.adhesion import summary_kernel
    from roughstick.stiction import strip_tail
    from roughstick.stiction._strip_hybrid import _gamma

    psd = rs.datasets.family_psd(args.family)
    rows, d = [], None  # (seed, index, Eq. 16 Γ, fft_bem law) of every candidate sub-zone
    if args.fresh:
        rows, d = _fresh_subzones(psd, args.rh, args.fresh, args.seed + 1000)
        what = f"{len(rows)} {args.family} sub-zones drawn with seed {args.seed + 1000}"
    else:
        if args.family != "table4":
            raise SystemExit("the seeds' cached laws are Table 4's: pass --fresh N for another --family")
        for s, cheap, acc in _cached_seeds(args.cache, args.rh):
            acc = acc.isel(realization=np.flatnonzero(acc.realization.values < args.n_accurate))
            d = cheap.distance.values
            pc = cheap.sel(realization=acc.realization).values
            g = _gamma(pc, d)
            pa = acc.values
            rows += [(s, int(k), float(g[i]), pa[i]) for i, k in enumerate(acc.realization.values)]
        what = f"{len(rows)} cached pairs of {len({r[0] for r in rows})} seeds"
    if len(rows) < 48:
        raise SystemExit(f"whole needs the seeds' cached pairs at RH {args.rh} in --cache (run `seeds --rh {args.rh} "
                         f"--cache DIR` first) or --fresh N (N >= 48); found {len(rows)}")

    def accurate_law(i):
        if rows[i][3] is None:  # a fresh sub-zone: its fft_bem law now, once
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)
                law = strip_tail._subzone_laws(psd, [args.rh], 0, 0, shape, 5e-9, "fft_bem", rows[i][0], d,
                                               "threads", None, index=[rows[i][1]])
            rows[i] = rows[i][:3] + (law.isel(rh=0, realization=0).values,)
        return rows[i][3]

    g16 = np.array([r[2] for r in rows])
    strong = np.flatnonzero(g16 >= np.quantile(g16, 0.75))
    rng = np.random.default_rng(args.seed)
    shape, m = (524, 500), 12
    print(f"RH {args.rh}: {what}; strips of {m} side by side, fft_bem whole (max_iterations "
          f"{args.max_iterations}) against the composed law of the same sub-zones", flush=True)
    out = {"strong": [], "random": []}
    try:
        for j in range(args.strips):
            kind = "random" if j % 3 == 2 else "strong"
            pick = rng.choice(strong if kind == "strong" else np.arange(len(rows)), m, replace=False)
            t = time.perf_counter()
            parts = []
            for i in pick:
                s, k = rows[i][0], rows[i][1]
                h = rs.surface.generate_surfaces(psd, n=k + 1, shape=shape, spacing=5e-9, seed=s,
                                                 chunks=1).isel(realization=k).compute()
                parts.append(np.roll(h.values, -seam_roll(h.values, shape[1]), axis=1))
            z = np.concatenate(parts, axis=1)
            strip = xr.DataArray((z - z.mean())[None], dims=("realization", "y", "x"), attrs=dict(h.attrs),
                                 coords={"realization": [0], "y": np.arange(z.shape[0]) * 5e-9,
                                         "x": np.arange(z.shape[1]) * 5e-9})
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)
                c = rs.contact.curves(strip, relative_humidity=[args.rh], model="fft_bem", distance=d,
                                      check_validity=False, adsorbed_layer="paper",
                                      max_iterations=args.max_iterations).compute()
            res = c.solver_residual.isel(realization=0, rh=0).values
            law = c.pressure.isel(realization=0, rh=0).values
            gd = float(_gamma(law[None], d)[0])
            # Γ is the work from the equilibrium outwards: a state left unconverged on the repulsive
            # side, below the first grid point past the equilibrium, does not enter it
            deq = summary_kernel(law[None], np.zeros((1, d.size)), d)[2][0]
            bad = res >= 1e-2
            bad_in = int(np.sum(bad & (d >= d[max(np.searchsorted(d, deq) - 1, 0)])))
            gc = float(_gamma(np.mean([accurate_law(i) for i in pick], axis=0)[None], d)[0])
            out[kind].append(math.log(gd / gc))
            print(f"  strip {j:2d} ({kind:6}): whole {gd * 1e3:7.4f}  composed {gc * 1e3:7.4f} mJ/m2  "
                  f"whole/composed {gd / gc:.4f}  states not converged {int(bad.sum())}/{res.size} ({bad_in} "
                  "of them at or beyond the equilibrium)  "
                  f"{time.perf_counter() - t:.0f} s", flush=True)
            if j + 1 < args.strips:  # so far: a run killed during a strip's solve keeps its summary
                _whole_summary(out, args.slope, prefix="    so far, ")
    except KeyboardInterrupt:  # kill -INT between strips: the summary of the strips done
        print(f"stopped after {sum(map(len, out.values()))} strips")
    _whole_summary(out, args.slope)


def _whole_summary(out, slope, prefix=""):
    """Mean log(whole/composed) per kind of strip with its 95 % Student interval, and the factor
    it makes on P near the threshold."""
    from scipy.stats import t as student

    for kind, v in out.items():
        v = np.array(v)
        if v.size < 2:
            continue
        half = student.ppf(0.975, v.size - 1) * v.std(ddof=1) / math.sqrt(v.size)
        print(f"{prefix}{kind} strips: mean log(whole/composed) {v.mean():+.4f} [{v.mean() - half:+.4f}, "
              f"{v.mean() + half:+.4f}] (95 %), sd {v.std(ddof=1):.4f}, n {v.size}; P near the threshold moves as "
              f"exp({slope:g} dΓ/Γ): a factor {math.exp(slope * v.mean()):.2f} [{math.exp(slope * (v.mean() - half)):.2f}, "
              f"{math.exp(slope * (v.mean() + half)):.2f}]", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("part", choices=["table", "seeds", "convergence", "cohesive", "composition", "replicates",
                                         "whole"])
    ap.add_argument("--n", type=int, default=12_000, help="Eq. 16 sub-zones")
    ap.add_argument("--n-accurate", type=int, default=240, help="fft_bem sub-zones per RH (0: Eq. 16 alone)")
    ap.add_argument("--n-tail", type=int, default=48, help="strongest sub-zones also through fft_bem")
    ap.add_argument("--target-cv", type=lambda v: None if v == "none" else float(v), default=0.3,
                    help="table, seeds: pairs doubled where a beam's cv is above 0.6 x this ('none': n-accurate "
                         "everywhere); replicates: half of --n-accurate first, all of them where the cv asks for it")
    ap.add_argument("--max-accurate", type=int, default=None, help="table, seeds: most random pairs per RH (default 4 x --n-accurate)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--refine", type=int, default=0, help="table: 1: refine_crossing=1e-3, up to three further "
                    "calls near the crossings (35-75 min more on 2 cores); 0: the grid alone")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--rh", type=float, default=0.75)
    ap.add_argument("--cache", default=None, help="seeds: folder keeping the sub-zone laws (a second pass "
                    "re-runs the estimator only; composition reads them); cohesive: folder keeping the bank")
    ap.add_argument("--rhs", default=None, help="table, cohesive: RH list, e.g. 0.76,0.78 (default the table's)")
    ap.add_argument("--laws", type=int, default=400, help="strip laws of the cohesive comparison's bank")
    ap.add_argument("--beams", type=int, default=400, help="beams per length of the cohesive comparison")
    ap.add_argument("--pool-pairs", type=int, default=None, help="replicates: pairs each seed gives to the pool "
                    "(default --n-accurate; sets of --n-accurate are dealt from the pool)")
    ap.add_argument("--max-iterations", type=int, default=500, help="whole: fft_bem's max_iterations")
    ap.add_argument("--strips", type=int, default=9, help="whole: strips solved whole by fft_bem")
    ap.add_argument("--family", default="table4", help="whole: the surface family's PSD (with --fresh)")
    ap.add_argument("--fresh", type=int, default=0, help="whole: draw this many sub-zones here (Eq. 16 on all, "
                                                         "fft_bem on those a strip picks) instead of --cache")
    ap.add_argument("--slope", type=float, default=27.0, help="whole: d log P / d log Γ of the tail at the "
                    "binding threshold (25-28 measured at 77 %% RH), to print what a bias in Γ does to P")
    args = ap.parse_args()
    {"table": table, "seeds": seeds, "convergence": convergence, "cohesive": cohesive,
     "composition": composition, "replicates": replicates, "whole": whole}[args.part](args)


if __name__ == "__main__":
    main()
