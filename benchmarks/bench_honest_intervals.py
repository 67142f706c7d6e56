"""Benchmark: are subset simulation's reported cv and interval honest? (exact limit states)

    nice -n 10 python benchmarks/bench_honest_intervals.py [--seeds 200] [--cases linear3,linear4,...]

Every case is a limit state whose failure probability is known exactly: the linear limit state
``Y = a . z`` of standard-normal white noise ``z`` (16 x 16 or 32 x 32), a unit direction
``a``, P(Y > beta) = Phi(-beta). Each case runs ``--seeds`` independent estimates (one run
each, or a ``target_cv`` stopping rule) and prints

- the true cv of one estimate, sqrt(mean (P_hat - P)^2) / P, with its chi-square 95 % interval,
- the reported cv: its mean over the seeds (and ratio to the true cv) and root mean square,
- how often the 95 % interval covers P,
- the effective number of final lineages and the share of runs flagged (``few_lineages``),
- beside them, in the same run, what the estimator reported before: the genealogical cv
  without the lineage correction (it cannot exceed 1) and its interval with the normal
  quantile (from ``run_cv`` and ``run_lineages``, which determine it).

Cases: ``linear3`` P = 1e-3, N = 300; ``linear4`` P = 1e-4, N = 900 (the estimator's
defaults at the 1e-4 target of docs/rare_events.md); ``collapse`` P = 1e-5, N = 100: a run built to lose its
lineages (10 levels of 20 chains of 5); ``nan`` the linear limit state with P = 1e-3 returning
NaN on half the space (where z_1 > 0, independent of Y): the old estimator counted NaN as no
failure and gave P / 2; ``target`` P = 1e-4, N = 300 with ``target_cv=0.3`` (at least 3 runs
that agree). ``--sweep``: the uncorrected against the corrected cv over 12 settings.
"""

from __future__ import annotations

import argparse
import math
import time
import warnings

import numpy as np
from _yardstick import spread_interval
from scipy.stats import norm

import roughstick as rs


class Linear:
    """Y = a . z, a a unit direction; NaN where z_1 > 0 when ``nan`` (a is orthogonal to z_1)."""

    def __init__(self, shape, nan=False):
        a = np.random.default_rng(1).standard_normal(shape)
        if nan:
            a.flat[1] = 0.0
        self.a = a / np.linalg.norm(a)
        self.nan = nan

    def __call__(self, z):
        if self.nan and z.flat[1] > 0:
            return math.nan
        return float(np.sum(self.a * z))


CASES = {
    "linear3": dict(beta=norm.isf(1e-3), shape=(16, 16), n_per_level=300),
    "linear4": dict(beta=norm.isf(1e-4), shape=(32, 32), n_per_level=900),
    "collapse": dict(beta=norm.isf(1e-5), shape=(16, 16), n_per_level=100),
    "nan": dict(beta=norm.isf(1e-3), shape=(16, 16), n_per_level=300, nan=True),
    "target": dict(beta=norm.isf(1e-4), shape=(16, 16), n_per_level=300, target_cv=0.3,
                   max_evaluations=40_000),
}


def _old_interval(p, cv, confidence=0.95):
    """The log-normal interval with the normal quantile (the estimator's interval before)."""
    z = norm.isf((1 - confidence) / 2)
    s = math.sqrt(math.log1p(cv * cv))
    c = p * math.sqrt(1 + cv * cv)
    return c * math.exp(-z * s), c * math.exp(z * s)


def run_case(name, seeds, first_seed):
    c = dict(CASES[name])
    beta, shape, nan = c.pop("beta"), c.pop("shape"), c.pop("nan", False)
    exact = norm.sf(beta)
    limit_state = Linear(shape, nan=nan)
    rows = []
    t0 = time.perf_counter()
    for s in range(first_seed, first_seed + seeds):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ds = rs.reliability.subset_simulation(limit_state, noise_shape=shape, threshold=beta, seed=s,
                                                  scheduler="sync", chunks=100_000, **c)
        p = float(ds.failure_probability)
        lin = ds.run_lineages.values
        n0 = ds.run_samples.values - ds.nan_responses.values[:, 0]  # the finite level-0 samples
        old_cv = float(np.sqrt(np.mean(n0 / (n0 - 1) * (1 / lin - 1 / n0)) / lin.size))
        old_p = p
        if nan:  # the old level 0 counted NaN as no failure: P (1 - NaN share of level 0)
            old_p = p * (1 - float(ds.nan_responses[0, 0]) / int(ds.run_samples[0]))
        rows.append(dict(p=p, cv=float(ds.coefficient_of_variation), lo=float(ds.failure_probability_lower),
                         hi=float(ds.failure_probability_upper), lin=float(lin.min()), few=int(ds.few_lineages),
                         runs=ds.sizes["run"], ev=int(ds.n_evaluations), old_p=old_p, old_cv=old_cv,
                         nan=float(ds.nan_responses.sum()), conv=int(ds.converged)))
    wall = time.perf_counter() - t0
    _report(name, c, exact, rows, wall)


def _report(name, c, exact, rows, wall):
    k = len(rows)
    col = {key: np.array([r[key] for r in rows]) for key in rows[0]}
    p, cv = col["p"], col["cv"]
    true = math.sqrt(np.mean((p - exact) ** 2)) / exact
    tlo, thi = spread_interval(true, k)
    fin = np.isfinite(cv)
    rms = math.sqrt(np.mean(cv[fin] ** 2)) if fin.any() else math.inf
    cover = int(np.sum((col["lo"] <= exact) & (exact <= col["hi"])))
    old = [_old_interval(a, b) for a, b in zip(col["old_p"], col["old_cv"], strict=True)]
    old_cover = int(sum(lo <= exact <= hi for lo, hi in old))
    old_true = math.sqrt(np.mean((col["old_p"] - exact) ** 2)) / exact
    print(f"{name}: P = {exact:.1e} exactly, {c}, {k} seeds, {wall:.0f} s")
    print(f"  mean P / exact {p.mean() / exact:.3f} +- {p.std(ddof=1) / math.sqrt(k) / exact:.3f} (s.e.); "
          f"evaluations {col['ev'].mean():.0f}; runs {col['runs'].mean():.1f} (converged {col['conv'].sum()}/{k})")
    mean = np.mean(cv[fin]) if fin.any() else math.inf
    print(f"  true cv {true:.3f} 95% [{tlo:.3f}, {thi:.3f}]; reported cv mean {mean:.3f} (ratio {mean / true:.2f}), "
          f"rms {rms:.3f}, infinite {int((~fin).sum())}; 95% interval coverage {cover}/{k}")
    print(f"  smallest effective final lineages per estimate: mean {col['lin'].mean():.1f}, "
          f"10% quantile {np.quantile(col['lin'], 0.1):.1f}; flagged (few_lineages) {int((col['few'] > 0).sum())}/{k}")
    if col["nan"].sum():
        print(f"  NaN responses per estimate {col['nan'].mean():.0f}")
    if "target_cv" in c:  # the stopping rule changed too: no like-for-like "before" here
        return
    print(f"  before (genealogical cv <= 1, normal quantile{', NaN as no failure' if col['nan'].sum() else ''}): "
          f"mean P / exact {col['old_p'].mean() / exact:.3f}, true cv {old_true:.3f}, reported cv mean "
          f"{np.mean(col['old_cv']):.3f} (ratio {np.mean(col['old_cv']) / old_true:.2f}), "
          f"coverage {old_cover}/{k}", flush=True)


def _cover(p, cv, q, exact):
    """Share of log-normal intervals (cv, quantile q) covering ``exact``; an infinite cv: [0, 1]."""
    with np.errstate(all="ignore"):
        w = np.minimum(q * np.sqrt(np.log1p(cv * cv)), 700)
        c = p * np.sqrt(1 + cv * cv)
        ok = (c * np.exp(-w) <= exact) & (exact <= c * np.exp(w))
    return float(np.mean(np.where(np.isfinite(cv), ok, True)))


def sweep(seeds, first_seed):
    """The uncorrected against the corrected cv over 12 settings (N = 100-600 per level, P = 1e-3 to
    1e-5, 16 x 16 white noise): mean reported / true cv and coverage, per setting."""
    from scipy.special import stdtrit

    limit_state, shape = Linear((16, 16)), (16, 16)
    for n in (100, 200, 300, 600):
        for beta in (3.09, 3.719, 4.265):
            p_exact = norm.sf(beta)
            rows = []
            for s in range(first_seed, first_seed + seeds):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # the few-lineage warning of every run
                    ds = rs.reliability.subset_simulation(limit_state, noise_shape=shape, threshold=beta, seed=s,
                                                          n_per_level=n, scheduler="sync", chunks=100_000)
                lin = float(ds.run_lineages[0])
                gen = math.sqrt(n / (n - 1) * (1 / lin - 1 / n)) if lin > 0 else math.inf
                rows.append((float(ds.failure_probability), gen, float(ds.coefficient_of_variation), lin))
            p, gen, cv, lin = (np.array(c) for c in zip(*rows, strict=True))
            true = math.sqrt(np.mean((p - p_exact) ** 2)) / p_exact
            z, t = norm.isf(0.025), stdtrit(np.maximum(lin - 1, 1e-3), 0.975)

            fin = np.isfinite(cv)
            print(f"N {n} P {p_exact:.1e}: true cv {true:.3f}, N_eff mean {lin.mean():.1f}, flagged "
                  f"{np.mean(lin < 5):.2f} | uncorrected cv mean / true {gen.mean() / true:.2f}, coverage "
                  f"(normal) {_cover(p, gen, z, p_exact):.3f} | corrected mean / true {cv[fin].mean() / true:.2f} "
                  f"(infinite {int((~fin).sum())}), coverage (t) {_cover(p, cv, t, p_exact):.3f}", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=200)
    ap.add_argument("--first-seed", type=int, default=10_000)
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--sweep", action="store_true", help="the uncorrected and corrected cv over 12 settings "
                    "(with --seeds 150 --first-seed 2000: docs/evidence/small_probabilities.md)")
    args = ap.parse_args(argv)
    if args.sweep:
        sweep(args.seeds, args.first_seed)
        return
    for name in args.cases.split(","):
        run_case(name, args.seeds, args.first_seed)


if __name__ == "__main__":
    main()
