"""Benchmark of the multi-fidelity ensemble estimator (roughstick.ensemble.multifidelity).

The estimator (``multifidelity_band``) combines the modified DMT (Eq. 16) on every realization with
``fft_bem`` on a seeded subset into the accurate model's Γ median and band edges. This script
measures it against all-``fft_bem`` ensembles of the same surfaces.

pool
    For each PSD family (S1, S2, table4, smooth, rough: ``rs.datasets.family_parameters``, and
    ``own``: a self-affine PSD no other benchmark uses) and humidities 0.3/0.5/0.7/0.9, N
    realizations (5 nm pixel, seed 0, the ensemble's own seeding) run through BOTH models, each
    humidity on each model's own automatic distance grid, exactly the summaries
    ``rs.ensemble.run(psd, ..., model="modified_dmt", accurate_model="fft_bem", n_accurate=N)``
    stores (checked on the first realizations by ``check``). Γ, pull-off and d_eq of both models
    are cached in ``benchmarks/.cache/mf_pool_<family>_<shape>.npz`` (gitignored), in blocks, so a
    stopped run resumes.
accuracy
    Multi-fidelity estimates of Γ's 2.5/50/97.5 % quantiles from subsets of the pool (drawn by
    ``accurate_subset`` with several seeds; n_accurate from a 40-realization pilot via
    ``accurate_subset_size`` and fixed 50/100/200/400) against the all-fft_bem quantiles of the
    same N realizations; Eq. 16 alone against the same truth.
coverage
    The reported 95 % intervals over >= 20 seeds: the ``correction`` interval (claims: the
    all-fft_bem quantile of the same N realizations) on the whole pool with different subset
    seeds, and the total interval (claims: the population quantile, sampling + correction) on
    n-realization ensembles drawn from the pool (target: the pool's all-fft_bem quantile, the
    pool being a larger sample of the population).
cost
    fft_bem / Eq. 16 time per map (six RH, default calls) at 128²-1024² with one 1024² complex
    iFFT timed in the same process, a 40-map pilot with both models, and the projected cost of
    the paper-scale ensemble (3000 × 1024², six RH, S2 PSD).
pilot, pilot-report
    The paper-scale run's own pilot (its 40 realizations, both models, one call per humidity as
    the ensemble runs them) split over processes, then the n_accurate it asks for and the
    projected cost from its CPU times per map.

    python benchmarks/bench_multifidelity.py pool --family S2 --n 1000 --shape 128
    python benchmarks/bench_multifidelity.py check --family S2
    python benchmarks/bench_multifidelity.py report --shape 128
    python benchmarks/bench_multifidelity.py cost --pilot-shape 512
    python benchmarks/bench_multifidelity.py pilot --pilot-shape 1024 --index 0 --of 2   # and 1
    python benchmarks/bench_multifidelity.py pilot-report --pilot-shape 1024 --of 2
    python benchmarks/bench_multifidelity.py atom
"""

from __future__ import annotations

import argparse
import pathlib
import time
import warnings

import numpy as np

import roughstick as rs

HERE = pathlib.Path(__file__).resolve().parent
CACHE = HERE / ".cache"
RH = (0.3, 0.5, 0.7, 0.9)
RH6 = (0.3, 0.5, 0.6, 0.7, 0.8, 0.9)
SPACING = 5e-9
FAMILIES = ("S1", "S2", "table4", "smooth", "rough", "own")
QUANTITIES = ("adhesive_energy", "pull_off_pressure", "equilibrium_distance")
SHORT = {"adhesive_energy": "Γ", "pull_off_pressure": "pull-off", "equilibrium_distance": "d_eq"}
Q = np.geomspace(1e5, 1e10, 2000)
#: The self-affine PSD of no other benchmark: Hurst 0.55, roll-off 2π/q0 ≈ 180 nm, rms 3.5 nm.
OWN = dict(hurst=0.55, q0=3.5e7, qmax=2.89e8, rms=3.5e-9)


def family_psd(name: str):
    if name == "own":
        ratio = (OWN["qmax"] / OWN["q0"]) ** (-2 * (1 + OWN["hurst"]))
        m0 = float(rs.surface.self_affine_moments(s0=1.0, s1=ratio, q0=OWN["q0"], qmax=OWN["qmax"]).m0)
        s0 = OWN["rms"] ** 2 / m0
        params = dict(s0=s0, s1=s0 * ratio, q0=OWN["q0"], qmax=OWN["qmax"])
    else:
        params = rs.datasets.family_parameters(name)
    return rs.surface.self_affine_psd(Q, **params)


def summaries(h2d, model: str, rh=RH) -> np.ndarray:
    """(3, len(rh)) Γ, pull-off, d_eq of one map, each humidity alone on the model's own grid
    (what the ensemble pipeline stores for the cheap and the accurate model)."""
    out = np.full((3, len(rh)), np.nan)
    for j, r in enumerate(rh):
        try:
            c = rs.contact.curves(h2d, relative_humidity=[float(r)], model=model, check_validity=False)
            s = rs.contact.summary(c, check_grid=False)
        except Exception as exc:  # noqa: BLE001 - a failed map is NaN, counted in the report
            print(f"  {model} rh={r}: {type(exc).__name__}: {exc}")
            continue
        for i, v in enumerate(QUANTITIES):
            out[i, j] = float(np.asarray(s[v].values).ravel()[0])
    return out


def pool_path(family: str, shape: int) -> pathlib.Path:
    return CACHE / f"mf_pool_{family}_{shape}.npz"


def load_pool(family: str, shape: int) -> dict | None:
    p = pool_path(family, shape)
    if not p.exists():
        return None
    with np.load(p) as z:
        return {k: z[k] for k in z.files}


def build_pool(family: str, n: int, shape: int, block: int = 50) -> None:
    """Both models on realizations 0..n-1 (seed 0), appended to the cache block by block."""
    CACHE.mkdir(exist_ok=True)
    psd = family_psd(family)
    ens = rs.surface.generate_surfaces(psd, n=n, shape=(shape, shape), spacing=SPACING, seed=0)
    old = load_pool(family, shape)
    cheap = list(old["cheap"]) if old is not None else []
    acc = list(old["accurate"]) if old is not None else []
    secs = list(old["seconds"]) if old is not None else []
    t_start = time.perf_counter()
    while len(cheap) < n:
        a = len(cheap)
        b = min(n, a + block)
        h = ens.isel(realization=slice(a, b)).compute(scheduler="sync")
        for k in range(b - a):
            hk = h.isel(realization=k)
            t0 = time.perf_counter()
            cheap.append(summaries(hk, "modified_dmt"))
            t1 = time.perf_counter()
            acc.append(summaries(hk, "fft_bem"))
            secs.append((t1 - t0, time.perf_counter() - t1))
        np.savez(pool_path(family, shape), cheap=np.array(cheap), accurate=np.array(acc),
                 seconds=np.array(secs), rh=np.array(RH), shape=shape, family=family)
        print(f"{family} {shape}²: {b}/{n} realizations, {time.perf_counter() - t_start:.0f} s",
              flush=True)


def check(family: str, shape: int, n: int = 3) -> None:
    """The pool's first realizations against rs.ensemble.run with both models (same numbers)."""
    import dask

    pool = load_pool(family, shape)
    with dask.config.set(scheduler="sync"):
        ds = rs.ensemble.run(family_psd(family), n=n, shape=shape, spacing=SPACING,
                             relative_humidity=list(RH), model="modified_dmt",
                             accurate_model="fft_bem", n_accurate=n, seed=0).compute()
    for i, v in enumerate(QUANTITIES):
        lo = ds[v].transpose("realization", "rh").values
        hi = ds[f"{v}_accurate"].transpose("realization", "rh").values
        d_lo = np.nanmax(np.abs(lo / pool["cheap"][:n, i] - 1))
        d_hi = np.nanmax(np.abs(hi / pool["accurate"][:n, i] - 1))
        print(f"{family} {SHORT[v]}: pool vs ensemble.run, max relative difference Eq. 16 "
              f"{d_lo:.1e}, fft_bem {d_hi:.1e}")


# ----------------------------------------------------------------------------- estimates

PROBS = (0.025, 0.5, 0.975)
PILOT = 40  # realizations of the pilot (roughstick.ensemble.runner.PILOT_SIZE)
SEEDS = 20  # subset seeds per configuration (coverage)
FIXED = (50, 100, 200, 400)
DRAW_N, DRAW_ACC = 300, 60  # ensembles drawn from the pool for the total interval


def _truth(values: np.ndarray) -> np.ndarray:
    """(len(PROBS),) quantiles of the accurate values (the inverse of their ECDF, as the estimator)."""
    v = values[np.isfinite(values)]
    return np.quantile(v, PROBS, method="inverted_cdf") if v.size else np.full(len(PROBS), np.nan)


def _band(cheap: np.ndarray, accurate: np.ndarray, subset: np.ndarray) -> dict:
    """multifidelity_band on (realization, rh) arrays with the accurate values on ``subset`` only."""
    import xarray as xr

    from roughstick.ensemble.multifidelity import multifidelity_band

    hi = np.full_like(accurate, np.nan)
    hi[subset] = accurate[subset]
    dims = ("realization", "rh")
    b = multifidelity_band(xr.DataArray(cheap, dims=dims), xr.DataArray(hi, dims=dims),
                           quantiles=PROBS)
    return {k: b[k].transpose("rh", ...).values for k in b.data_vars}


def pilot_size(cheap: np.ndarray, accurate: np.ndarray, seed: int, accuracy: float,
               margin: float | None = None) -> int:
    """n_accurate="auto" of rs.ensemble.run: a 40-realization pilot (the first of the seed's
    permutation), the largest accurate_subset_size over the humidities (Γ); ``margin`` replaces
    PILOT_MARGIN for the call (a trial, not the package's setting)."""
    from roughstick.ensemble import multifidelity as mf

    n = cheap.shape[0]
    pilot = mf.accurate_subset(n, PILOT, seed=seed)
    saved = mf.PILOT_MARGIN
    mf.PILOT_MARGIN = saved if margin is None else margin
    try:
        return max(mf.accurate_subset_size(cheap[pilot, j], accurate[pilot, j], n_total=n,
                                           accuracy=accuracy) for j in range(cheap.shape[1]))
    finally:
        mf.PILOT_MARGIN = saved


def estimates(family: str, shape: int, fixed=FIXED, seeds: int = SEEDS) -> list[dict]:
    """Records of every multi-fidelity estimate of the family's pool (see the module docstring)."""
    from roughstick.ensemble.multifidelity import accurate_subset

    pool = load_pool(family, shape)
    cheap_all, acc_all = pool["cheap"], pool["accurate"]
    N = cheap_all.shape[0]
    recs = []

    def add(kind, config, seed, i, b, same, popq, cheap_q, n_acc):
        for j, r in enumerate(RH):
            for m, p in enumerate(PROBS):
                recs.append(dict(family=family, kind=kind, config=config, seed=seed,
                                 quantity=QUANTITIES[i], rh=r, p=p, n_accurate=int(n_acc),
                                 est=b["value"][j, m], lower=b["lower"][j, m], upper=b["upper"][j, m],
                                 clower=b["correction_lower"][j, m],
                                 cupper=b["correction_upper"][j, m], same=same[j, m],
                                 population=popq[j, m], eq16=cheap_q[j, m]))

    t0 = time.perf_counter()
    # (b) and the correction interval: the whole pool, subsets of several sizes and seeds
    i = 0  # Γ
    cheap, acc = cheap_all[:, i], acc_all[:, i]
    same = np.array([_truth(acc[:, j]) for j in range(len(RH))])
    cq = np.array([_truth(cheap[:, j]) for j in range(len(RH))])
    configs = ([("auto", s) for s in range(seeds)] + [("auto1", s) for s in range(seeds)]
               + [(k, s) for k in fixed if k <= N // 2 for s in range(seeds if k == 100 else 5)])
    for config, seed in configs:
        n_acc = (pilot_size(cheap, acc, seed, 0.1) if config == "auto" else
                 pilot_size(cheap, acc, seed, 0.1, margin=1.0) if config == "auto1" else config)
        sub = accurate_subset(N, n_acc, seed=seed)
        add("pool", config, seed, i, _band(cheap, acc, sub), same, same, cq, n_acc)
    print(f"  {family}: pool estimates {time.perf_counter() - t0:.0f} s", flush=True)
    # (c) the total interval: ensembles of DRAW_N realizations drawn (with replacement) from the
    # pool, whose empirical distribution is then the population; target: the pool's quantiles
    for i in range(len(QUANTITIES)):
        cheap, acc = cheap_all[:, i], acc_all[:, i]
        popq = np.array([_truth(acc[:, j]) for j in range(len(RH))])
        for seed in range(seeds):
            draw = np.random.default_rng([7, seed]).integers(0, N, DRAW_N)
            c, a = cheap[draw], acc[draw]
            same = np.array([_truth(a[:, j]) for j in range(len(RH))])
            cq = np.array([_truth(c[:, j]) for j in range(len(RH))])
            sub = accurate_subset(DRAW_N, DRAW_ACC, seed=seed)
            add("draw", DRAW_ACC, seed, i, _band(c, a, sub), same, popq, cq, DRAW_ACC)
    print(f"  {family}: drawn ensembles {time.perf_counter() - t0:.0f} s", flush=True)
    pilots = {acc_target: [pilot_size(cheap_all[:, 0], acc_all[:, 0], s, acc_target)
                           for s in range(seeds)] for acc_target in (0.1, 0.05, 0.03)}
    recs.append(dict(family=family, kind="pilot", pilots=pilots, N=N,
                     nan_cheap=int(np.isnan(cheap_all).sum()), nan_acc=int(np.isnan(acc_all).sum()),
                     seconds=pool["seconds"].mean(axis=0).tolist()))
    return recs


# ----------------------------------------------------------------------------- cost


def _timed(call):
    """(result, wall seconds, process CPU seconds of all threads) of one call."""
    t, c = time.perf_counter(), time.process_time()
    out = call()
    return out, time.perf_counter() - t, time.process_time() - c


def cost(pilot_shape: int, sizes=(128, 256, 512, 1024), n_paper: int = 3000) -> None:
    """Time per map of both models (six RH) against one 1024² complex iFFT, a 40-map pilot of the
    paper-scale S2 ensemble, and the projected cost of that ensemble."""
    from _yardstick import ifft_seconds

    from roughstick.ensemble.multifidelity import accurate_subset, accurate_subset_size

    psd = family_psd("S2")
    fft = ifft_seconds()
    _, _, fft_cpu = _timed(lambda: [np.fft.ifft2(np.ones((1024, 1024), complex)) for _ in range(5)])
    fft_cpu /= 5
    print(f"\n### Cost per map, S2 PSD, six RH (0.3-0.9), 5 nm pixel; one 1024² complex iFFT: "
          f"{fft * 1e3:.1f} ms wall (best of 5), {fft_cpu * 1e3:.1f} ms CPU\n")
    print("default call: rs.contact.curves(h, relative_humidity=six RH, model=m) + summary; per "
          "RH: one call per humidity on its own grid (what the ensemble runs). Process CPU time [s] "
          "(all threads; × the iFFT's CPU time), wall time in brackets: the machine is shared, "
          "so wall times carry the other users' load.\n")
    print("| map | Eq. 16 default | fft_bem default | ratio | Eq. 16 per RH | fft_bem per RH | ratio |")
    print("|---|---|---|---:|---|---|---:|")
    warm = rs.surface.generate_surfaces(psd, n=1, shape=(64, 64), spacing=SPACING, seed=1).isel(
        realization=0).compute()
    for m in ("modified_dmt", "fft_bem"):  # compile and load the kernels before timing
        summaries(warm, m, RH6[:1])
        rs.contact.curves(warm, relative_humidity=list(RH6), model=m)
    per = {}
    for n in sizes:
        h = rs.surface.generate_surfaces(psd, n=1, shape=(n, n), spacing=SPACING, seed=0).isel(
            realization=0).compute()
        row = {}
        for m in ("modified_dmt", "fft_bem"):
            _, w, c = _timed(lambda m=m, h=h: rs.contact.summary(rs.contact.curves(
                h, relative_humidity=list(RH6), model=m), check_grid=False))
            row[m, "default"] = (c, w)
            if m == "fft_bem" and n >= 1024:
                row[m, "per"] = (np.nan, np.nan)  # the default call stands in (saves minutes)
                continue
            _, w, c = _timed(lambda m=m, h=h: summaries(h, m, RH6))
            row[m, "per"] = (c, w)
        per[n] = row

        def cell(v):
            return "–" if not np.isfinite(v[0]) else f"{v[0]:.2f} ({v[0] / fft_cpu:.0f} ×) [{v[1]:.2f}]"

        def ratio(kind, row=row):
            return row["fft_bem", kind][0] / row["modified_dmt", kind][0]

        print(f"| {n}² | {cell(row['modified_dmt', 'default'])} | {cell(row['fft_bem', 'default'])} | "
              f"{ratio('default'):.1f} | {cell(row['modified_dmt', 'per'])} | "
              f"{cell(row['fft_bem', 'per'])} | {ratio('per'):.1f} |", flush=True)
    # the paper-scale run's pilot: its first 40 realizations of the seed-0 permutation
    ens = rs.surface.generate_surfaces(psd, n=n_paper, shape=(pilot_shape, pilot_shape),
                                       spacing=SPACING, seed=0)
    pilot = accurate_subset(n_paper, PILOT, seed=0)
    lo, hi = [], []
    t0 = time.perf_counter()
    for k in pilot:
        hk = ens.isel(realization=int(k)).compute(scheduler="sync")
        lo.append(summaries(hk, "modified_dmt", RH6)[0])
        hi.append(summaries(hk, "fft_bem", RH6)[0])
    lo, hi = np.array(lo), np.array(hi)
    t_pilot = time.perf_counter() - t0
    CACHE.mkdir(exist_ok=True)
    np.savez(CACHE / f"mf_pilot_S2_{pilot_shape}.npz", cheap=lo, accurate=hi, rh=np.array(RH6))
    need = {a: max(accurate_subset_size(lo[:, j], hi[:, j], n_total=n_paper, accuracy=a)
                   for j in range(len(RH6))) for a in (0.1, 0.05, 0.03)}
    rel = np.median(lo / hi - 1, axis=0) * 100
    print(f"\npilot: {PILOT} realizations of the paper-scale S2 run at {pilot_shape}² (both models, six "
          f"RH, {t_pilot:.0f} s wall); Eq. 16 / fft_bem - 1 median per RH: "
          + ", ".join(f"{r:+.1f} %" for r in rel))
    print("n_accurate the pilot asks for (of 3000): " + ", ".join(
        f"accuracy {a}: {v}" for a, v in need.items()))
    big = per[max(sizes)]
    t_lo = big["modified_dmt", "per"][0]
    t_hi = big["fft_bem", "default"][0]
    print(f"\n### PROJECTION (not measured): the paper-scale ensemble, {n_paper} × {max(sizes)}², six "
          f"RH, S2 PSD, from the per-map CPU times above (Eq. 16 per RH {t_lo:.1f} s, fft_bem "
          f"default call {t_hi:.1f} s; the pilot's {PILOT} maps counted with both): core-hours, "
          "and minutes on two cores if both are busy\n")
    print("| plan | maps with fft_bem | projected [core-h] | [min on two cores] |")
    print("|---|---:|---:|---:|")
    plans = [("Eq. 16 alone", 0, n_paper * t_lo), ("all fft_bem", n_paper, n_paper * t_hi)]
    for a, v in need.items():
        plans.append((f"multi-fidelity (pilot, accuracy {a})", v,
                      n_paper * t_lo + v * t_hi + PILOT * (t_lo + t_hi)))
    for name, k, sec in plans:
        print(f"| {name} | {k} | {sec / 3600:.2f} | {sec / 120:.0f} |")


def pilot_part(pilot_shape: int, index: int, of: int, n_paper: int = 3000) -> None:
    """The paper-scale run's pilot maps ``index::of`` (both models, six RH), cached: the pilot
    split over ``of`` processes."""
    from roughstick.ensemble.multifidelity import accurate_subset

    ens = rs.surface.generate_surfaces(family_psd("S2"), n=n_paper, shape=(pilot_shape, pilot_shape),
                                       spacing=SPACING, seed=0)
    keys = accurate_subset(n_paper, PILOT, seed=0)[index::of]
    lo, hi, secs = [], [], []
    for k in keys:
        hk = ens.isel(realization=int(k)).compute(scheduler="sync")
        _, _, c0 = _timed(lambda hk=hk: lo.append(summaries(hk, "modified_dmt", RH6)[0]))
        _, _, c1 = _timed(lambda hk=hk: hi.append(summaries(hk, "fft_bem", RH6)[0]))
        secs.append((c0, c1))
        print(f"pilot map {k} at {pilot_shape}²: CPU {c0:.1f} s Eq. 16, {c1:.1f} s fft_bem", flush=True)
    CACHE.mkdir(exist_ok=True)
    np.savez(CACHE / f"mf_pilot_S2_{pilot_shape}_{index}of{of}.npz", cheap=np.array(lo),
             accurate=np.array(hi), realization=keys, seconds=np.array(secs))


def pilot_report(pilot_shape: int, of: int, t_cheap: float | None, t_accurate: float | None,
                 n_paper: int = 3000) -> None:
    """n_accurate of the paper-scale run from its pilot's parts, and the projected cost from the
    per-map CPU times ``t_cheap`` (Eq. 16, per RH) and ``t_accurate`` (fft_bem) [s] (default: the
    pilot's own means, one call per humidity as the ensemble runs them)."""
    from roughstick.ensemble.multifidelity import accurate_subset_size

    parts = [np.load(CACHE / f"mf_pilot_S2_{pilot_shape}_{i}of{of}.npz") for i in range(of)]
    lo = np.concatenate([p["cheap"] for p in parts])
    hi = np.concatenate([p["accurate"] for p in parts])
    secs = np.concatenate([p["seconds"] for p in parts])
    t_cheap = float(secs[:, 0].mean()) if t_cheap is None else t_cheap
    t_accurate = float(secs[:, 1].mean()) if t_accurate is None else t_accurate
    need = {a: max(accurate_subset_size(lo[:, j], hi[:, j], n_total=n_paper, accuracy=a)
                   for j in range(len(RH6))) for a in (0.1, 0.05, 0.03)}
    rel = np.median(lo / hi - 1, axis=0) * 100
    print(f"pilot: {lo.shape[0]} realizations of the paper-scale S2 run at {pilot_shape}² (both "
          f"models, six RH; CPU per map {secs[:, 0].mean():.1f} s Eq. 16 per RH, "
          f"{secs[:, 1].mean():.1f} s fft_bem per RH); Eq. 16 / fft_bem - 1 median per RH: "
          + ", ".join(f"{r:+.1f} %" for r in rel))
    print("n_accurate the pilot asks for (of 3000): " + ", ".join(
        f"accuracy {a}: {v}" for a, v in need.items()))
    print(f"\n### PROJECTION (not measured): {n_paper} × {pilot_shape}², six RH, S2 PSD, from per-map CPU "
          f"times {t_cheap:.2f} s (Eq. 16) and {t_accurate:.2f} s (fft_bem), the pilot's maps "
          "counted with both\n")
    print("| plan | maps with fft_bem | projected [core-h] | [min on two cores] |")
    print("|---|---:|---:|---:|")
    plans = [("Eq. 16 alone", 0, n_paper * t_cheap), ("all fft_bem", n_paper, n_paper * t_accurate)]
    for a, v in need.items():
        plans.append((f"multi-fidelity (pilot, accuracy {a})", v,
                      n_paper * t_cheap + v * t_accurate + PILOT * (t_cheap + t_accurate)))
    for name, k, sec in plans:
        print(f"| {name} | {k} | {sec / 3600:.2f} | {sec / 120:.0f} |")


def atom(shape: int = 128) -> None:
    """The smooth pool's pull-off at RH 0.9, an atom of the distribution: do the total intervals
    of the median of drawn ensembles hold it, compared exactly?"""
    from roughstick.ensemble.multifidelity import accurate_subset, multifidelity_kernel

    pool = load_pool("smooth", shape)
    c, a = pool["cheap"][:, 1, RH.index(0.9)], pool["accurate"][:, 1, RH.index(0.9)]
    target = np.quantile(a, 0.5, method="inverted_cdf")
    hits = exact = 0
    for seed in range(SEEDS):
        draw = np.random.default_rng([7, seed]).integers(0, a.size, DRAW_N)
        hi = np.full(DRAW_N, np.nan)
        sub = accurate_subset(DRAW_N, DRAW_ACC, seed=seed)
        hi[sub] = a[draw][sub]
        r = multifidelity_kernel(c[draw], hi, probabilities=[0.5])
        lo = -np.inf if np.isnan(r["quantile_lower"][0]) else r["quantile_lower"][0]
        up = np.inf if np.isnan(r["quantile_upper"][0]) else r["quantile_upper"][0]
        hits += bool(lo <= target <= up)
        exact += bool(r["quantile"][0] == target)
    print(f"smooth pull-off at RH 0.9: {np.mean(a == target):.0%} of the maps at the median value; "
          f"total interval of the median (ensembles of {DRAW_N}, {DRAW_ACC} accurate) holds it, "
          f"compared exactly, in {hits}/{SEEDS} seeds; the estimate is that value in {exact}/{SEEDS}")


# ----------------------------------------------------------------------------- report


def family_records(family: str, shape: int, n: int, redo: bool = False) -> list[dict] | None:
    """The family's estimate records, cached in benchmarks/.cache (recomputed with ``redo``)."""
    import json

    path = CACHE / f"mf_est_{family}_{shape}.json"
    pool = load_pool(family, shape)
    if pool is None or pool["cheap"].shape[0] < n:
        return None
    if path.exists() and not redo:
        return json.loads(path.read_text())
    recs = estimates(family, shape)
    path.write_text(json.dumps(recs, default=float))
    return recs


def _cp(k: int, n: int) -> str:
    from scipy import stats

    if n == 0:
        return "–"
    ci = stats.binomtest(k, n).proportion_ci(0.95, method="exact")
    return f"{k}/{n} = {k / n:.2f} [{ci.low:.2f}, {ci.high:.2f}]"


def _err(r, key="est", ref="same"):
    return 100.0 * (r[key] / r[ref] - 1.0)


#: Relative slack of "inside": an edge back-transformed from log (exp(log v)) can miss the value
#: v it came from by a rounding error, which matters where the target is an atom of the
#: distribution (the pull-off at RH 0.9 is the same value on half of the smooth maps)
ROUNDING = 1e-9


def _inside(r, lo="clower", hi="cupper", ref="same"):
    """Whether the interval holds the target (a NaN edge: the interval is open on that side)."""
    t = r[ref] * (1 - ROUNDING * np.sign(r[ref]))
    u = r[ref] * (1 + ROUNDING * np.sign(r[ref]))
    lo_ok = not np.isfinite(r[lo]) or r[lo] <= u
    hi_ok = not np.isfinite(r[hi]) or t <= r[hi]
    return bool(lo_ok and hi_ok and np.isfinite(r["est"]))


def report(shape: int, families, n: int, redo: bool = False) -> None:
    recs = {}
    for f in families:
        got = family_records(f, shape, n, redo=redo)
        if got is None:
            print(f"({f}: no complete pool of {n} at {shape}², skipped)")
            continue
        recs[f] = got
    if not recs:
        return
    fams = list(recs)
    print(f"\n### Pools ({shape}², 5 nm pixel, seed 0, RH {', '.join(map(str, RH))})\n")
    print("| family | N | NaN Eq. 16 / fft_bem (of 3 quantities × 4 RH × N) | wall s per map Eq. 16 / "
          "fft_bem (4 RH, shared machine) | pilot n_accurate, accuracy 0.1 / 0.05 / 0.03 (median [range], 20 seeds) |")
    print("|---|---:|---:|---:|---|")
    for f in fams:
        pr = next(r for r in recs[f] if r["kind"] == "pilot")
        pil = " / ".join(f"{int(np.median(v))} [{min(v)}–{max(v)}]" for v in pr["pilots"].values())
        print(f"| {f} | {pr['N']} | {pr['nan_cheap']} / {pr['nan_acc']} | {pr['seconds'][0]:.2f} / "
              f"{pr['seconds'][1]:.2f} | {pil} |")
    pool = {f: [r for r in recs[f] if r["kind"] == "pool"] for f in fams}
    N = next(r for r in recs[fams[0]] if r["kind"] == "pilot")["N"]
    print(f"\n### Γ quantiles of the whole pool (N = {N}): Eq. 16 alone and multi-fidelity against "
          "all-fft_bem on the same realizations\n")
    print("Eq. 16: signed error of its own quantile. MF: largest |error| over the seeds (20 for the "
          "pilot's n_accurate and for 100). ok: share of (seed, quantile) within 3 % or inside "
          "the estimate's own correction interval.\n")
    print("| family | RH | Eq. 16 2.5 / 50 / 97.5 % | MF pilot n (median) | MF pilot max \\|err\\| "
          "2.5 / 50 / 97.5 % | ok | MF n=100 max \\|err\\| | ok |")
    print("|---|---:|---|---:|---|---:|---|---:|")
    for f in fams:
        for r_h in RH:
            rows = [r for r in pool[f] if r["rh"] == r_h]
            eq = [np.mean([_err(r, "eq16") for r in rows if r["p"] == p]) for p in PROBS]
            cells = []
            for config in ("auto", 100):
                sel = [r for r in rows if r["config"] == config]
                if not sel:
                    cells.append(([np.nan] * len(PROBS), np.nan, 0))
                    continue
                mx = [max(abs(_err(r)) for r in sel if r["p"] == p) for p in PROBS]
                ok = np.mean([abs(_err(r)) <= 3 or _inside(r) for r in sel])
                cells.append((mx, ok, int(np.median([r["n_accurate"] for r in sel]))))
            print(f"| {f} | {r_h} | {' / '.join(f'{e:+.1f}' for e in eq)} | {cells[0][2]} | "
                  f"{' / '.join(f'{e:.1f}' for e in cells[0][0])} | {cells[0][1]:.2f} | "
                  f"{' / '.join(f'{e:.1f}' for e in cells[1][0])} | {cells[1][1]:.2f} |")
    allpool = [r for f in fams for r in pool[f]]
    print(f"\n### Γ against n_accurate (all families and RH; the whole pool, N = {N})\n")
    print("| n_accurate | estimates | median \\|err\\| 2.5 / 50 / 97.5 % | max \\|err\\| 2.5 / 50 "
          "/ 97.5 % | mean signed err (± s.e.) 2.5 / 50 / 97.5 % | within 3 % | inside own "
          "correction interval | either | within 10 % |")
    print("|---|---:|---|---|---|---:|---:|---:|---:|")
    eq = [abs(_err(r, "eq16")) for r in allpool if r["config"] == "auto" and r["seed"] == 0]
    for config in ("auto", "auto1", *FIXED):
        sel = [r for r in allpool if r["config"] == config]
        if not sel:
            continue
        by_p = [[_err(r) for r in sel if r["p"] == p] for p in PROBS]
        med = " / ".join(f"{np.median(np.abs(e)):.2f}" for e in by_p)
        mx = " / ".join(f"{np.max(np.abs(e)):.1f}" for e in by_p)
        bias = " / ".join(f"{np.mean(e):+.2f} ± {np.std(e) / np.sqrt(len(e)):.2f}" for e in by_p)
        w3 = np.mean([abs(_err(r)) <= 3 for r in sel])
        ins = np.mean([_inside(r) for r in sel])
        eith = np.mean([abs(_err(r)) <= 3 or _inside(r) for r in sel])
        w10 = np.mean([abs(_err(r)) <= 10 for r in sel])
        name = {"auto": "pilot (accuracy 0.1), n median "
                        f"{int(np.median([r['n_accurate'] for r in sel]))}",
                "auto1": "trial: pilot with PILOT_MARGIN = 1, n median "
                         f"{int(np.median([r['n_accurate'] for r in sel]))}"}.get(config, str(config))
        print(f"| {name} | {len(sel)} | {med} | {mx} | {bias} | {w3:.3f} | {ins:.3f} | {eith:.3f} "
              f"| {w10:.3f} |")
    print(f"| Eq. 16 alone | {len(eq)} | median {np.median(eq):.1f} | max {np.max(eq):.1f} | | "
          f"{np.mean(np.array(eq) <= 3):.3f} | | | {np.mean(np.array(eq) <= 10):.3f} |")
    for config in ("auto", "auto1"):
        cells = []
        for key in sorted({(r["family"], r["rh"], r["p"]) for r in allpool}):
            sel = [r for r in allpool if r["config"] == config
                   and (r["family"], r["rh"], r["p"]) == key]
            k = sum(abs(_err(r)) <= 10 for r in sel)
            if sel and k < len(sel) - 1:
                cells.append(f"{key[0]} RH {key[1]} {100 * key[2]:g} %: {k}/{len(sel)}")
        print(f"\n{'pilot' if config == 'auto' else 'trial PILOT_MARGIN = 1'}: cells (family, RH, "
              "quantile) with fewer than 19 of 20 seeds within the pilot's accuracy (10 %): "
              + ("; ".join(cells) if cells else "none"))
    print("\n### Coverage of the correction interval (95 %): does it hold the all-fft_bem Γ quantile "
          "of the same realizations (the whole pool)? (20 subset seeds × 4 RH per cell)\n")
    print("| family | n_accurate | 2.5 % | 50 % | 97.5 % |")
    print("|---|---|---|---|---|")
    for config in ("auto", "auto1", 100):
        for f in [*fams, "all"]:
            sel = [r for r in (allpool if f == "all" else pool[f]) if r["config"] == config]
            if not sel:
                continue
            cells = [_cp(sum(_inside(r) for r in sel if r["p"] == p),
                         sum(1 for r in sel if r["p"] == p)) for p in PROBS]
            name = {"auto": "pilot", "auto1": "pilot, margin 1"}.get(config, config)
            print(f"| {f} | {name} | {' | '.join(cells)} |")
    draw = [r for f in fams for r in recs[f] if r["kind"] == "draw"]
    print(f"\n### Coverage of the total interval (95 %): ensembles of {DRAW_N} realizations drawn "
          f"with replacement from the pool, {DRAW_ACC} with fft_bem; target: the pool's all-fft_bem "
          "quantile (the population the draws sample); 20 seeds × 4 RH per cell\n")
    print("| family | quantity | 2.5 % | 50 % | 97.5 % | MF mean \\|err\\| vs population, 2.5 / 50 "
          "/ 97.5 % | Eq. 16 mean \\|err\\| |")
    print("|---|---|---|---|---|---|---|")
    for f in [*fams, "all"]:
        for q in QUANTITIES:
            sel = [r for r in draw if r["quantity"] == q and (f == "all" or r["family"] == f)]
            cells = [_cp(sum(_inside(r, "lower", "upper", "population") for r in sel if r["p"] == p),
                         sum(1 for r in sel if r["p"] == p)) for p in PROBS]
            mf = " / ".join(f"{np.nanmean([abs(_err(r, ref='population')) for r in sel if r['p'] == p]):.1f}"
                            for p in PROBS)
            eqe = " / ".join(f"{np.nanmean([abs(_err(r, 'eq16', 'population')) for r in sel if r['p'] == p]):.1f}"
                             for p in PROBS)
            print(f"| {f} | {SHORT[q]} | {' | '.join(cells)} | {mf} | {eqe} |")
    low = []
    for key in sorted({(r["family"], r["quantity"], r["rh"], r["p"]) for r in draw}):
        sel = [r for r in draw if (r["family"], r["quantity"], r["rh"], r["p"]) == key]
        k = sum(_inside(r, "lower", "upper", "population") for r in sel)
        if k <= len(sel) - 4:  # P(X <= 16 of 20 | 0.95) = 0.016
            low.append(f"{key[0]} {SHORT[key[1]]} RH {key[2]} {100 * key[3]:g} %: {k}/{len(sel)}")
    print("\ncells (family, quantity, RH, quantile) of the total interval covering in at most 16 of "
          "20 seeds: " + ("; ".join(low) if low else "none"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("part", choices=("pool", "check", "report", "cost", "pilot", "pilot-report",
                                       "atom"))
    ap.add_argument("--family", nargs="+", default=list(FAMILIES))
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--shape", type=int, default=128)
    ap.add_argument("--pilot-shape", type=int, default=512)
    ap.add_argument("--index", type=int, default=0, help="pilot: this process's share")
    ap.add_argument("--of", type=int, default=1, help="pilot: number of processes")
    ap.add_argument("--t-cheap", type=float, default=None,
                    help="pilot-report: Eq. 16 CPU s/map (default: the pilot's mean)")
    ap.add_argument("--t-accurate", type=float, default=None,
                    help="pilot-report: fft_bem CPU s/map (default: the pilot's mean)")
    ap.add_argument("--redo", action="store_true", help="recompute the cached estimates")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    if args.part == "pool":
        for f in args.family:
            build_pool(f, args.n, args.shape)
    elif args.part == "report":
        report(args.shape, args.family, args.n, redo=args.redo)
    elif args.part == "cost":
        cost(args.pilot_shape)
    elif args.part == "atom":
        atom(args.shape)
    elif args.part == "pilot":
        pilot_part(args.pilot_shape, args.index, args.of)
    elif args.part == "pilot-report":
        pilot_report(args.pilot_shape, args.of, args.t_cheap, args.t_accurate)
    elif args.part == "check":
        for f in args.family:
            check(f, args.shape)


if __name__ == "__main__":
    main()
