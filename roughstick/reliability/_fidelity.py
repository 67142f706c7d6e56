r"""Two fidelities in the tail: subset simulation on a cheap limit state, corrected by an accurate one.

Private to :mod:`roughstick.reliability` (``failure_probability(..., accurate_model=)``). The
target is :math:`P = P(y_a > t)`, :math:`y_a` the accurate response (the FFT boundary-element
model) of a white-noise state; :math:`y_c` is the cheap one (Eq. 16). With
:math:`y_a \le r\,y_c` on the tail (``r`` the ratio bound, measured by a pilot), the accurate
failure domain lies inside the cheap one above :math:`t_c = t / r`, and

.. math:: P = P(y_c > t_b)\; P(y_a > t \mid y_c > t_b), \qquad t_b = (1 - \beta)\, t_c \le t_c,

the first factor by subset simulation on the cheap model to :math:`t_b`, the second from the
accurate model on a random subset of the final level's states. The states between :math:`t_b` and
:math:`t_c` (just outside the relaxed level) are sampled too: they check the containment (an
accurate failure there means the bound was too tight) and, weighted, stay in the estimate.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import xarray as xr
from scipy.special import stdtrit

from .._core.dask import as_seed_sequence
from .._core.validate import external_stacklevel
from . import _kernels as _k
from ._engine import MIN_LINEAGES

__all__: list[str] = []

#: cheap states (of a separate crude sample of ``n_per_level``) whose accurate response sets the bound
PILOT_STATES = 32
#: the ratio bound is the pilot's largest accurate / cheap ratio times 1 + this
RATIO_MARGIN = 0.1
#: the band just outside the relaxed level: t_b = (1 - BAND) t_c
BAND = 0.1
#: share of the accurate evaluations of the final level spent on the band (the containment check)
BAND_SHARE = 0.2
#: relative error of the cheap model on the pilot's tail states within which it could stand alone
CHEAP_ACCURACY = 0.1


#: spawn-key tag of the pilot and the picks: (tag, k) keys have 2 entries, the subset run's 1
#: (level-0 samples) or 5 (chain steps), so they never collide
_TAG = 0x5446  # "TF"


def _child(root, k):
    return np.random.SeedSequence(root.entropy, spawn_key=tuple(root.spawn_key) + (_TAG, k))


def pilot_ratio(cheap, accurate, *, noise_shape, n_pool, seed):
    """Accurate / cheap response on the :data:`PILOT_STATES` highest cheap states of a crude sample
    of ``n_pool`` (its own seed): ``(ratios, cheap responses, accurate responses)``."""
    rng = np.random.default_rng(_child(as_seed_sequence(seed), 1))
    zs = rng.standard_normal((int(n_pool),) + tuple(noise_shape))
    yc = np.array([cheap(z) for z in zs])
    top = np.argsort(np.where(np.isfinite(yc), yc, -np.inf))[::-1][:PILOT_STATES]
    ya = np.array([accurate(zs[i]) for i in top])
    with np.errstate(divide="ignore", invalid="ignore"):
        return ya / yc[top], yc[top], ya


def _final_roots(ds, r):
    """Level-0 ancestor of each final-level state of run ``r`` above the run's last threshold (the
    order of ``failure_noise``)."""
    nl = int(ds.run_levels[r])
    chains, kept = [], []
    for j in range(nl):
        y = ds.response.values[r, j]
        n = int(np.sum(ds.chain.values[r, j] >= 0))
        y = y[:n]
        chains.append(ds.chain.values[r, j, :n])
        kept.append(np.flatnonzero(np.where(np.isnan(y), False, y > float(ds.next_threshold[r, j]))))
    roots = _k.root_ancestors(chains, kept)
    return roots[-1][kept[-1]]


def _split(n_in, n_band, budget, rng):
    """Random picks of the inside and band states for ``budget`` accurate evaluations."""
    k_b = min(n_band, int(round(BAND_SHARE * budget))) if n_band else 0
    k_a = min(n_in, budget - k_b)
    k_b = min(n_band, budget - k_a)  # the inside set may leave some of the budget over
    return (np.sort(rng.choice(n_in, k_a, replace=False)) if k_a else np.empty(0, int),
            np.sort(rng.choice(n_band, k_b, replace=False)) if k_b else np.empty(0, int))


def _run_part(ds, r, accurate, threshold, t_relaxed, budget, rng, shape):
    """One run's accurate part: its estimate, cv, effective lineages and the checks."""
    sel = np.flatnonzero(ds.failure_run.values == r)
    yc = ds.failure_response.values[sel]
    noise = ds.failure_noise.values[sel]
    roots = _final_roots(ds, r)
    inside, band = np.flatnonzero(yc > t_relaxed), np.flatnonzero(yc <= t_relaxed)
    pa, pb = _split(inside.size, band.size, budget, rng)
    picks = np.concatenate([inside[pa], band[pb]])
    weights = np.concatenate([np.full(pa.size, inside.size / max(pa.size, 1)),
                              np.full(pb.size, band.size / max(pb.size, 1))])
    ya = np.array([accurate(noise[i].reshape(shape)) for i in picks])
    fails = np.where(np.isnan(ya), False, ya > threshold)
    contrib = weights * fails
    p_cheap = float(ds.run_probability[r])
    n_final = max(yc.size, 1)
    p = p_cheap * float(contrib.sum()) / n_final
    n0 = int(np.sum((ds.chain.values[r, 0] >= 0) & ~np.isnan(ds.response.values[r, 0])))  # NaN: no ancestor
    if contrib.sum() > 0:
        per_root = np.bincount(roots[picks], weights=contrib)
        frac = per_root[per_root > 0] / contrib.sum()
        lineages = float(1.0 / np.dot(frac, frac))
        cv2 = _k.lineage_cv2(max(n0 / (n0 - 1) * (float(np.dot(frac, frac)) - 1.0 / n0), 0.0), lineages)
    else:
        lineages, cv2 = 0.0, math.inf
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = ya / yc[picks]
    in_band = picks.size - pa.size
    return dict(probability=p, cv2=cv2, lineages=lineages, accurate=int(picks.size),
                cheap_probability=p_cheap, fraction=float(contrib.sum()) / n_final,
                checked=int(in_band), violations=int(fails[pa.size:].sum()),
                ratio_max=float(np.nanmax(ratio)) if ratio.size else math.nan,
                inside=int(inside.size), band=int(band.size), nan=int(np.isnan(ya).sum()),
                zero_upper=p_cheap * _k.wilson_interval(0, max(picks.size, 1), 0.95)[1])


def _pass(cheap, accurate, threshold, run, n_accurate, ratio_bound, seed, attempt):
    """One subset run on ``cheap`` to the band threshold of ``ratio_bound`` and its accurate part."""
    t_relaxed = float(threshold) / float(ratio_bound)
    t_band = (1.0 - BAND) * t_relaxed
    root = as_seed_sequence(seed)
    ds = run(t_band, root if attempt == 0 else _child(root, 3), attempt)
    rng = np.random.default_rng(_child(root, 2 if attempt == 0 else 4))
    R = ds.sizes["run"]
    per = [_run_part(ds, r, accurate, float(threshold), t_relaxed, int(n_accurate) // R, rng,
                     cheap.noise_shape)
           if "failure_run" in ds and np.any(ds.failure_run.values == r) else None for r in range(R)]
    parts = [q if q is not None else dict(probability=0.0, cv2=math.inf, lineages=0.0, accurate=0,
                                          cheap_probability=float(ds.run_probability[r]), fraction=0.0,
                                          checked=0, violations=0, ratio_max=math.nan, inside=0, band=0,
                                          nan=0, zero_upper=float(ds.failure_probability_upper))
             for r, q in enumerate(per)]
    return ds, parts, t_relaxed, t_band


def two_fidelity(cheap, accurate, *, threshold, run, n_accurate, ratio_bound, n_pool, seed,
                 confidence, independent_runs):
    """The two-fidelity estimate of P(accurate > threshold) as a Dataset (module notes).

    ``run(t, seed, attempt)`` is subset simulation on ``cheap`` to threshold ``t`` (the caller's
    settings; ``attempt`` 1 for a second pass). ``ratio_bound`` None: measured by :func:`pilot_ratio` on ``n_pool`` crude cheap
    states; then, when the containment check finds accurate failures in the band, the bound is
    re-measured on the final states evaluated (their largest ratio times 1 + RATIO_MARGIN) and
    a second pass with fresh random numbers gives the estimate (both passes' evaluations counted).
    """
    pilot = np.empty(0)
    pilot_evals = 0
    measured = ratio_bound is None
    if measured:
        pilot, _, _ = pilot_ratio(cheap, accurate, noise_shape=cheap.noise_shape, n_pool=n_pool, seed=seed)
        pilot_evals = pilot.size
        finite = pilot[np.isfinite(pilot)]
        ratio_bound = max(float(finite.max()) if finite.size else 1.0, 1e-6) * (1.0 + RATIO_MARGIN)
    spent = {"cheap": 0, "accurate": 0, "violations": 0, "bound": float(ratio_bound)}
    for attempt in (0, 1):
        ds, parts, t_relaxed, t_band = _pass(cheap, accurate, threshold, run, n_accurate, ratio_bound, seed, attempt)
        violations = sum(q["violations"] for q in parts)
        seen = max((q["ratio_max"] for q in parts if np.isfinite(q["ratio_max"])), default=math.nan)
        if attempt == 1 or not measured or violations == 0 or not np.isfinite(seen):
            break
        spent = {"cheap": int(ds.n_evaluations), "accurate": sum(q["accurate"] for q in parts),
                 "violations": violations, "bound": float(ratio_bound)}
        ratio_bound = max(float(ratio_bound), seen) * (1.0 + RATIO_MARGIN)
    return _assemble(ds, parts, pilot, pilot_evals, float(ratio_bound), t_relaxed, t_band, threshold,
                     confidence, cheap, spent if attempt else None)


def _interval(parts, confidence):
    """P, cv, interval and how, from the runs' parts (the engine's rules: genealogical cv with
    Student's t on the effective lineages; the between-run spread from 3 runs when larger)."""
    ps = np.array([q["probability"] for q in parts])
    cv2s = np.array([q["cv2"] for q in parts])
    R, p = ps.size, float(ps.mean())
    gen = math.sqrt(float(np.mean(cv2s)) / R) if np.all(np.isfinite(cv2s)) else math.inf
    between = float(ps.std(ddof=1) / math.sqrt(R) / p) if R >= 2 and p > 0 else math.nan
    if R >= 3 and np.isfinite(between) and between > gen:
        cv, dof, how = between, R - 1.0, f"log-normal, between-run cv, Student t with {R - 1} dof"
    else:
        dof = max(sum(q["lineages"] - 1.0 for q in parts), 1e-3)
        cv, how = gen, f"log-normal, genealogical cv of the combined estimate, Student t with {dof:.3g} dof"
    if p > 0 and np.isfinite(cv):
        lo, hi = _k.lognormal_interval(p, cv, confidence, quantile=float(stdtrit(dof, 0.5 + confidence / 2)))
    elif p > 0:
        lo, hi = 0.0, 1.0
    else:
        lo, hi, cv = 0.0, float(np.mean([q["zero_upper"] for q in parts])), math.inf
    return p, cv, lo, min(hi, 1.0), how, between


def _assemble(ds, parts, pilot, pilot_evals, ratio_bound, t_relaxed, t_band, threshold, confidence, cheap,
              first=None):
    """The cheap run's Dataset with the two-fidelity estimate in front and its checks."""
    p, cv, lo, hi, how, between = _interval(parts, confidence)
    first = first or {"cheap": 0, "accurate": 0, "violations": 0, "bound": ratio_bound}
    cheap_run = {k: ds[k].copy() for k in ("failure_probability", "failure_probability_lower",
                                           "failure_probability_upper", "coefficient_of_variation")}
    ds = ds.drop_vars(["failure_noise", "failure_run", "failure_response"], errors="ignore")
    ds["cheap_probability"] = cheap_run["failure_probability"].assign_attrs(
        long_name="probability that the cheap response exceeds band_threshold (subset simulation)")
    ds["cheap_probability_lower"] = cheap_run["failure_probability_lower"]
    ds["cheap_probability_upper"] = cheap_run["failure_probability_upper"]
    ds["cheap_cv"] = cheap_run["coefficient_of_variation"].assign_attrs(
        long_name="coefficient of variation of cheap_probability")
    n_pool = ds.attrs["samples_per_level"] if pilot_evals else 0
    total = {k: sum(q[k] for q in parts) for k in ("accurate", "checked", "violations", "inside", "band", "nan")}
    ratio_max = np.nanmax([q["ratio_max"] for q in parts]) if any(np.isfinite(q["ratio_max"]) for q in parts) else np.nan
    finite = pilot[np.isfinite(pilot)]
    within = int(finite.size > 0 and bool(np.all(np.abs(finite - 1.0) <= CHEAP_ACCURACY)))
    new = {
        "failure_probability": (p, "estimated probability that the accurate response exceeds the threshold"),
        "failure_probability_lower": (lo, "lower bound of the confidence interval on the failure probability"),
        "failure_probability_upper": (hi, "upper bound of the confidence interval on the failure probability"),
        "coefficient_of_variation": (cv, "coefficient of variation of the two-fidelity estimate (lineage clusters)"),
        "between_run_cv": (between, "coefficient of variation from the spread of the independent runs (NaN with one run)"),
        "conditional_fraction": (float(np.mean([q["fraction"] for q in parts])),
                                 "weighted fraction of the final cheap states whose accurate response exceeds the threshold"),
        "n_evaluations": (np.int64(int(ds.n_evaluations) + n_pool + first["cheap"]),
                          "cheap-model evaluations (pilot sample and a first pass included)"),
        "n_accurate_evaluations": (np.int64(total["accurate"] + pilot_evals + first["accurate"]),
                                   "accurate-model evaluations (pilot and a first pass included)"),
        "passes": (np.int8(2 if first["cheap"] else 1), "2 if a first pass found accurate failures in its band and the bound was re-measured"),
        "first_pass_violations": (np.int64(first["violations"]), "accurate failures in the band of the first pass (0: one pass)"),
        "first_pass_ratio_bound": (first["bound"], "ratio bound of the first pass (the pilot's)"),
        "ratio_bound": (ratio_bound, "bound on accurate / cheap response setting the relaxed threshold"),
        "pilot_ratio_max": (float(finite.max()) if finite.size else np.nan,
                            "largest accurate / cheap response of the pilot's tail states"),
        "pilot_ratio_median": (float(np.median(finite)) if finite.size else np.nan,
                               "median accurate / cheap response of the pilot's tail states"),
        "final_ratio_max": (float(ratio_max), "largest accurate / cheap response of the final states evaluated"),
        "relaxed_threshold": (t_relaxed, "cheap threshold threshold / ratio_bound"),
        "band_threshold": (t_band, "cheap threshold of the subset run: the band below relaxed_threshold is checked"),
        "containment_checked": (np.int64(total["checked"]), "accurately evaluated states between band_threshold and relaxed_threshold"),
        "containment_violations": (np.int64(total["violations"]), "of them, accurate failures (0: the accurate failure domain lies inside the relaxed level there)"),
        "accurate_nan_responses": (np.int64(total["nan"]), "accurate evaluations that returned NaN (counted as no failure)"),
        "cheap_within_accuracy": (np.int8(within), "1 if every pilot tail state's cheap response is within the accuracy of the accurate one"),
        "few_lineages": (np.int64(sum(q["probability"] > 0 and q["lineages"] < MIN_LINEAGES for q in parts)),
                         "number of runs whose accurate failures descend from fewer effective lineages than "
                         "min_lineages: the cv rests on too few independent contributions"),
    }
    units = ds.response.attrs.get("units", "1")
    for k, (v, ln) in new.items():
        u = units if k in ("relaxed_threshold", "band_threshold") else "1"
        ds[k] = xr.DataArray(v, attrs={"units": u, "long_name": ln})
    ds["failure_probability_lower"].attrs["confidence"] = float(confidence)
    ds["few_lineages"].attrs["min_lineages"] = MIN_LINEAGES
    ds["combined_lineages"] = xr.DataArray([q["lineages"] for q in parts], dims="run", attrs={
        "units": "1", "long_name": "effective number of level-0 lineages of the run's weighted accurate failures"})
    ds["pilot_ratio"] = xr.DataArray(pilot, dims="pilot", attrs={
        "units": "1", "long_name": "accurate / cheap response of each pilot tail state"})
    ds.attrs.update({"method": "two_fidelity", "interval_method": how, "threshold": float(threshold),
                     "cheap_model": getattr(cheap, "model", "cheap"), "accurate_model": "fft_bem"})
    _warn(ds, total, ratio_bound, ratio_max, cheap)
    return ds


def _warn(ds, total, ratio_bound, ratio_max, cheap):
    """Warn when the accurate failures descend from few lineages (the cv is a rough figure), when
    the containment check finds accurate failures just outside the relaxed level, or when a final
    state's ratio exceeds what the run's band covers, ``ratio_bound / (1 - BAND)`` (an accurate
    failure of a larger ratio may lie below the run's threshold)."""
    if int(ds.few_lineages):
        lin = ", ".join(f"{v:.1f}" for v in ds.combined_lineages.values)
        warnings.warn(
            f"two-fidelity estimate: the accurate failures descend from few effective level-0 lineages ({lin}; "
            f"fewer than {MIN_LINEAGES:g} is flagged), so its cv ({float(ds.coefficient_of_variation):.2g}) "
            f"is a rough figure and the interval is wide (Student's t on them). Pass more independent_runs= "
            f"(each run is cheap) or a larger n_per_level= (now {ds.attrs['samples_per_level']}).",
            UserWarning, stacklevel=external_stacklevel())
    seen = max(ratio_bound, ratio_max if np.isfinite(ratio_max) else 0.0)
    fix = (f"pass ratio_bound={1.1 * seen / (1 - BAND):.3g} (now {ratio_bound:.3g}) to failure_probability, "
           "or more independent_runs")
    rh = getattr(cheap, "rh", None)
    at = f" at RH {rh:g}" if rh is not None else ""
    if total["violations"]:
        warnings.warn(
            f"two-fidelity estimate{at}: {total['violations']} of the {total['checked']} states just below the "
            f"relaxed threshold fail with the accurate model: its failure domain is not inside the cheap one "
            f"there, and states further below may be missed (the estimate counts the band, weighted). Relax "
            f"the threshold further: {fix}.", UserWarning, stacklevel=external_stacklevel())
    elif np.isfinite(ratio_max) and ratio_max > ratio_bound / (1 - BAND):
        warnings.warn(
            f"two-fidelity estimate{at}: a final state has accurate / cheap response {ratio_max:.3g}, above "
            f"the {ratio_bound / (1 - BAND):.3g} the run's band covers (ratio bound {ratio_bound:.3g} from the "
            f"pilot): accurate failures may lie below the run's threshold. Relax the threshold further: {fix}.",
            UserWarning, stacklevel=external_stacklevel())
