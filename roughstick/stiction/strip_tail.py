r"""Small P(stuck) on the beam's own interaction zone: strips recomposed from sub-zone laws.

The strip :math:`\Delta s \times w` under the beam is :math:`m` independent sub-zones under one
rigid flat; its law is the mean of theirs and its Γ is Eq. 13 of that mean
(:func:`roughstick.stiction.compose_zone_law`). A strip is therefore a function of ``m``
independent draws from one distribution of sub-zone laws, and so is the event
:math:`\Gamma_{strip} > t`. :func:`strip_ccdf` estimates
:math:`P(\Gamma_{strip} > t)` from ``N`` computed sub-zone laws by the plug-in estimator: the
probability under the empirical distribution of the laws, computed by importance sampling over
combinations of ``m`` of them (exponentially tilted towards sub-zones whose attraction at the
typical equilibrium is large; a mixture of tilts, one per threshold, and the untilted draw).
``N`` sub-zones thereby stand for far more than ``N/m`` strips: a strip fails when several of
its sub-zones are strong together, and the combinations of the sample reach that event at
probabilities far below :math:`m/N`.

Two fidelities: the accurate model (``fft_bem``) runs on a random sample of the sub-zones (the
pairs) and on the sub-zones with the largest cheap Γ (the ones strong strips are made of, and
where Eq. 16's fitting artefacts live). Every sub-zone then carries its cheap law scaled by a
Γ_accurate/Γ_cheap ratio (Eq. 13 of a scaled law is the scaled Γ): its own where the accurate
model ran (its accurate law where that ratio says nothing: a near-zero cheap Γ, a cheap
artefact), elsewhere one drawn from the pairs nearest to it in cheap Γ, a fresh draw in every
combination, so the estimate averages over the ratios the unseen sub-zones may have instead of
fixing one each; the strips are recombined from these laws, plus a residual for what scaling
misses in a composed strip (the two models' laws differ in shape), drawn from the pairs'
recombined strips of similar Γ (a tall asperity that holds the flat off in one model only moves
a near-zero strip Γ by far more than a strong strip's). The interval adds the sampling of the
``N`` sub-zones (the plug-in's first-order variance), a bootstrap of the pairs' ratios (the same
ratio quantiles in every replicate; its spread taken on the log scale of the interval) and the
importance-sampling error. ``accurate_share`` says how much of the tail's influence lies on
sub-zones the accurate model saw; a run whose variance rests on a handful of sub-zones is
flagged (``few_subzones``): its interval is not to be trusted.

The models' own error in a strip's Γ (the composed law leaves out the sub-zones' elastic
interaction; the two-fidelity correction is not exact) is a band of relative errors,
:data:`MODEL_BAND` by default: :func:`strip_stuck_probability` gives the interval of P(stuck)
with every strip's Γ at each end of it too, from the same combinations (a scaled Γ exceeds a
threshold where the Γ exceeds the threshold over the scale).
"""

from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr
from scipy.stats import norm

from .._core.arguments import check_numbers
from .._core.conventions import append_history
from .._core.validate import relative_humidity_array
from ..contact import curves as contact_curves
from ..contact.adhesion import summary_kernel
from ..ensemble.pipeline import distance_grid
from ..surface import generate_surfaces
from ._strip_answer import (
    MODEL_BAND,  # noqa: F401  (the route's default band: strip_tail.MODEL_BAND)
    REFINE_CALLS,  # noqa: F401  (most further calls of refine_crossing)
    _model_band,
    _patch_thresholds,
    _refined,
    _stuck_dataset,
    model_band_problem,  # noqa: F401  (the band's rule, for the CLI's config check)
)
from ._strip_hybrid import (
    RATIO_BRACKET,
    _compose,
    _gamma,
    _holdout,
    _hybrid_gamma,
    _hybrid_laws,
    _ratio_pool,
    _residual_pool,
    _with_residual,
)
from .cantilever import PAPER_CANTILEVER
from .zone import _callable_m0, subzone_shape

__all__ = ["strip_ccdf", "strip_stuck_probability"]

#: An estimate whose variance rests on fewer sub-zones than this (participation ratio of their
#: influence) is flagged ``few_subzones``: a handful of strong sub-zones makes the tail.
MIN_EFFECTIVE_SUBZONES = 5


def _work_above(p, d, d_star):
    """Net work of separating each law from ``d_star`` to the grid's end [J m-2], -∫ p dd by
    trapezoids (attraction counts positive): the score that tilts the draws."""
    keep = d >= d_star
    pp, dd = p[:, keep], d[keep]
    return -np.sum((pp[:, 1:] + pp[:, :-1]) * 0.5 * np.diff(dd), axis=1)


def _tilts(score, targets):
    """Exponential tilts of the empirical score distribution whose tilted means are ``targets``
    (clipped to the sample's reach), as log-probabilities over the sub-zones; the untilted draw first."""
    n = score.size
    z = (score - score.mean()) / (score.std() + 1e-300)
    logq = [np.full(n, -math.log(n))]
    reach = np.quantile(z, 0.995)
    # one tilt per distinct target (thresholds beyond the sample's reach share the last one), and
    # a ladder of milder tilts below the highest: the mixture then holds every combination that
    # fails, however few of the thresholds the caller asked for
    tzs = np.minimum((np.asarray(targets, float) - score.mean()) / (score.std() + 1e-300), reach)
    if tzs.max() > 0.05:
        tzs = np.concatenate([tzs, np.linspace(0.0, tzs.max(), 9)[1:]])
    tzs = np.unique(np.round(tzs, 2))
    for tz in tzs:
        if tz <= 0.05:
            continue
        lo, hi = 0.0, 50.0
        for _ in range(60):
            th = 0.5 * (lo + hi)
            w = np.exp(th * z - np.max(th * z))
            if np.sum(w * z) / np.sum(w) < tz:
                lo = th
            else:
                hi = th
        a = th * z
        logq.append(a - (np.max(a) + math.log(np.sum(np.exp(a - np.max(a))))))
    return np.array(logq)


@check_numbers(subzones="count", n_combinations="count", n_boot="count", seed="seed", confidence="fraction",
               random_pairs="count?")
def strip_ccdf(cheap: xr.DataArray, thresholds, *, subzones: int, accurate: xr.DataArray | None = None,
               random_pairs: int | None = None, n_combinations: int = 100_000, n_boot: int = 20, seed=0,
               confidence: float = 0.95, tilt_to=None) -> xr.Dataset:
    r"""P(Γ of a strip of ``subzones`` sub-zones > t) at ``thresholds``, from sub-zone laws.

    The plug-in estimator of the module docstring: the strip's law is the mean of ``subzones``
    independent sub-zone laws (:func:`compose_zone_law`), its Γ Eq. 13 of that mean, and the
    probability is taken under the empirical distribution of the ``N`` laws of ``cheap`` by
    importance sampling over their combinations. With ``accurate`` (the accurate model's laws of
    some of the sub-zones, on the same distance grid) the probability is that of the accurate
    model: every sub-zone carries its cheap law scaled by a Γ_accurate/Γ_cheap ratio, its own
    where the accurate model ran and elsewhere one drawn from the random pairs of similar cheap
    Γ, afresh in every combination (module docstring).

    Parameters
    ----------
    cheap : xarray.DataArray
        Pressure [Pa] of ``N`` sub-zones over ``(realization, distance)`` (and ``rh``): e.g.
        ``rs.stiction.strip_adhesive_energy(..., subzones=1, keep_curves=True).pressure``.
    thresholds : array-like
        Γ values [J m-2] at which to estimate the exceedance probability (1-D; or over ``rh``
        as a DataArray ``(rh, threshold)``).
    subzones : int
        Sub-zones per strip, ``m``.
    accurate : xarray.DataArray, optional
        Pressure of the accurate model on some sub-zones of ``cheap``, its ``realization``
        coordinate their indices in ``cheap`` (e.g. ``0 ... n-1``, and those that carry the tail).
    random_pairs : int, optional
        The accurate sub-zones with an index below this are a random sample of the sub-zones
        (their ratios scale the others' laws; at least 8); default all of them.
    n_combinations : int
        Importance-sampled combinations per humidity.
    n_boot : int
        Bootstrap replicates of the interval.
    seed : int
        Seed of the combinations and the bootstrap.
    confidence : float
        Level of the interval.
    tilt_to : array-like, optional
        The Γ values the importance sampling aims its tilts at (as ``thresholds``; default
        ``thresholds``): any proposal leaves the estimates unbiased, and those at thresholds near
        the aimed ones are about as precise.

    Returns
    -------
    xarray.Dataset
        Over ``(rh, threshold)``: ``exceedance_probability`` with ``_lower``/``_upper``,
        ``coefficient_of_variation`` (and its parts ``importance_sampling_cv``,
        ``emulator_cv``), ``effective_subzones`` (how many sub-zones its variance rests on;
        ``few_subzones`` below :data:`MIN_EFFECTIVE_SUBZONES`), ``accurate_share`` (how much of
        the tail's influence lies on sub-zones the accurate model ran on); over ``rh``
        ``accurate_ratio`` and the hold-out check ``ratio_check_*``. attrs ``subzones``,
        ``n_subzones``, ``n_accurate``.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> d = np.linspace(0.0, 4e-9, 41)
    >>> depth = rng.gamma(4.0, 0.25, size=(400, 1))  # attraction of 400 sub-zone laws
    >>> p = np.where(d < 1e-9, 1e6 * (1e-9 - d) / 1e-9, 0.0) - 1e5 * depth * (d > 1e-9) * (d < 3e-9)
    >>> laws = xr.DataArray(p, dims=("realization", "distance"), coords={"distance": d})
    >>> c = rs.stiction.strip_ccdf(laws, [2.5e-4, 3e-4], subzones=12, n_combinations=20_000, n_boot=20)
    >>> bool(c.exceedance_probability[0, 0] > c.exceedance_probability[0, 1])
    True
    """
    m = int(subzones)
    cheap = _with_rh(cheap, "cheap")
    acc = None if accurate is None else _with_rh(accurate, "accurate")
    d = np.asarray(cheap["distance"].values, dtype=float)
    known = None
    if acc is not None:
        known = np.asarray(acc["realization"].values)
        if known.dtype.kind not in "iu" or known.min() < 0 or known.max() >= cheap.sizes["realization"] \
                or np.unique(known).size != known.size:
            raise ValueError("accurate's realization coordinate must hold distinct indices of cheap's sub-zones "
                             "(0 ... N-1): the sub-zones the accurate model ran on")
        n_pairs = cheap.sizes["realization"] if random_pairs is None else int(random_pairs)
        if np.sum(known < n_pairs) < 8:
            raise ValueError(f"accurate has {np.sum(known < n_pairs)} random pairs: the ratio needs at least 8 "
                             "pairs (compute the accurate model on more of the sub-zones)")
        if not np.allclose(acc["distance"].values, d, rtol=1e-9, atol=0.0):
            raise ValueError("accurate must be on the same distance grid as cheap: compute both with one distance= "
                             "grid and the same seed")
    thr = _thresholds(thresholds, cheap)
    aim = thr if tilt_to is None else _thresholds(tilt_to, cheap)
    rng = np.random.default_rng(seed)
    out = []
    for k in range(cheap.sizes["rh"]):
        pc = np.asarray(cheap.isel(rh=k).transpose("realization", "distance").values, dtype=float)
        pa = None if acc is None else (known, np.asarray(acc.isel(rh=k).transpose("realization", "distance").values,
                                                         dtype=float), n_pairs)
        out.append(_one_humidity(pc, pa, d, thr[k], m, n_combinations, n_boot, rng, confidence, aim[k]))
    return _assemble(out, cheap, thr, m, acc, confidence, n_combinations, n_boot)


def _with_rh(laws, name):
    if not isinstance(laws, xr.DataArray) or not {"realization", "distance"} <= set(laws.dims):
        raise ValueError(f"{name} must be a DataArray of sub-zone pressure over ('realization', 'distance') "
                         "(strip_adhesive_energy(..., subzones=1, keep_curves=True).pressure)")
    if "rh" not in laws.dims:
        laws = laws.expand_dims(rh=[float(laws["rh"])] if "rh" in laws.coords else [np.nan])
    if not np.all(np.isfinite(laws.values)):
        raise ValueError(f"{name} has non-finite pressures: recompute those sub-zones (or drop them) first")
    return laws


def _thresholds(thresholds, cheap):
    t = thresholds
    if isinstance(t, xr.DataArray) and "rh" in t.dims:
        t = t.sel(rh=cheap["rh"]).transpose("rh", ...).values
    t = np.asarray(t, dtype=float)
    t = np.broadcast_to(t, (cheap.sizes["rh"], t.shape[-1])) if t.ndim <= 1 else t
    if t.ndim != 2 or t.shape[0] != cheap.sizes["rh"] or not np.all(np.isfinite(t)) or np.any(t <= 0):
        raise ValueError("thresholds must be positive adhesive energies [J m-2], one list or one per rh")
    return np.atleast_2d(t)


def _one_humidity(pc, acc, d, thr, m, n_comb, n_boot, rng, confidence, tilt_to):
    n_sub = pc.shape[0]
    laws, pool, known = pc, None, None
    known_idx = pa_known = pairs = None
    if acc is not None:
        known_idx, pa_known, n_pairs = acc
        known = np.zeros(n_sub, bool)
        known[known_idx] = True
        pairs = known_idx < n_pairs
        pool = _ratio_pool(pc[known_idx[pairs]], pa_known[pairs], d)
        key = np.log(np.maximum(_gamma(pc, d), 1e-300))  # where each unseen sub-zone draws its ratio
        res = _residual_pool(pc[known_idx[pairs]], pa_known[pairs], pool, d, m, rng)
        # a sub-zone the accurate model saw carries its cheap law scaled by its own ratio, as the
        # pairs do in the residual's strips: its accurate law, mixed with scaled cheap laws in one
        # strip, misplaces the strip's equilibrium (the laws differ in shape). Its accurate law
        # only where the ratio says nothing (near-zero cheap Γ) or lies outside the bracket (a
        # cheap artefact)
        base = pc.copy()
        base[known_idx] = _hybrid_laws(pc[known_idx], pa_known, d, np.median(_gamma(pc[known_idx[pairs]], d)))
        # the tilts' laws: unknown ratios at the pairs' median (any proposal is unbiased)
        laws = base * np.where(known, 1.0, np.median(pool[1]))[:, None]
    d_star = _typical_equilibrium(laws.mean(0), d)
    score = _work_above(laws, d, d_star)
    logq = _tilts(score, list(tilt_to) + [1.2 * float(tilt_to.min())])
    comp = rng.integers(0, logq.shape[0], size=n_comb)
    idx = np.empty((n_comb, m), dtype=np.int64)
    for c in range(logq.shape[0]):
        sel = comp == c
        q = np.exp(logq[c] - logq[c].max())
        idx[sel] = rng.choice(n_sub, size=(int(sel.sum()), m), p=q / q.sum())
    # log density of each combination under the mixture, and under the empirical distribution
    comp_logq = np.stack([logq[c][idx].sum(1) for c in range(logq.shape[0])])
    log_mix = np.logaddexp.reduce(comp_logq, axis=0) - math.log(logq.shape[0])
    w0 = np.exp(-m * math.log(n_sub) - log_mix)
    if acc is None:
        g0 = _gamma(_compose(laws, idx), d)
    else:  # the unknown ratios and the residual drawn afresh in every combination (the same
        # quantiles reused by the bootstrap of the pairs: common random numbers)
        u, u_res = rng.random(idx.shape), rng.random(n_comb)
        g0 = _with_residual(_hybrid_gamma(base, ~known, key, pool, idx, u, d), res, u_res)
    wf = w0[:, None] * (g0[:, None] > thr[None, :])
    est = np.minimum(wf.mean(0), 1.0)  # the weights' mean is 1 only on average: no probability above 1
    var_is = wf.var(0) / n_comb
    # the sampling of the N sub-zones: the plug-in's first-order (Hoeffding) variance,
    # m^2/N Var_i h1(i), h1(i) = P(fail | one of the strip's sub-zones is i)
    var_n, eff, checked = np.zeros(thr.size), np.zeros(thr.size), np.full(thr.size, np.nan)
    for j in np.flatnonzero(est > 0):
        scale = n_sub / (m * n_comb)
        h1 = np.bincount(idx.ravel(), weights=np.repeat(wf[:, j], m), minlength=n_sub) * scale
        # each h1(i) is itself estimated from the few combinations holding i; that noise (the
        # compound-Poisson variance scale^2 sum wf^2 of its terms) would add ~m times the
        # importance-sampling variance to Var_i h1, and is taken off
        noise = np.bincount(idx.ravel(), weights=np.repeat(wf[:, j] ** 2, m), minlength=n_sub) * scale**2
        v = (h1 - est[j]) ** 2 - noise
        var_n[j] = m * m / n_sub * max(np.mean(v), 0.0)
        v = np.maximum(v, 0.0)
        # how many sub-zones that variance rests on (participation ratio): few = the tail is theirs
        eff[j] = v.sum() ** 2 / max(np.sum(v * v), 1e-300)
        if known is not None:  # the share of the excess h1 (the tail's sub-zones) the accurate model saw
            excess = np.maximum(h1 - est[j], 0.0)
            checked[j] = excess[known].sum() / max(excess.sum(), 1e-300)
    var_pairs = np.zeros(thr.size)
    check = (np.nan, np.nan, 0)
    if acc is not None:
        reps = np.empty((n_boot, thr.size))
        pc_pairs, pa_pairs = pc[known_idx[pairs]], pa_known[pairs]
        for b in range(n_boot):
            pick = rng.integers(0, pc_pairs.shape[0], size=pc_pairs.shape[0])
            pool_b = _ratio_pool(pc_pairs[pick], pa_pairs[pick], d)
            res_b = _residual_pool(pc_pairs[pick], pa_pairs[pick], pool_b, d, m, rng, n_comb=2000)
            g = _with_residual(_hybrid_gamma(base, ~known, key, pool_b, idx, u, d), res_b, u_res)
            reps[b] = (w0[:, None] * (g[:, None] > thr[None, :])).mean(0)
        # on the log scale of the interval: one resample that duplicates a pair of extreme
        # ratio can move a replicate tenfold, and its square would then be the whole variance
        with np.errstate(divide="ignore", invalid="ignore"):
            logs = np.log(np.maximum(reps, 1e-3 * est[None, :]))
            var_pairs = np.where(est > 0, est**2 * np.nan_to_num(logs.var(0, ddof=1)), 0.0)
        check = _holdout(pc[known_idx[pairs]], pa_known[pairs], d, m, rng)
    var = var_is + var_n + var_pairs
    a = (1.0 - confidence) / 2
    z = float(norm.ppf(1 - a))
    with np.errstate(divide="ignore", invalid="ignore"):
        cv = np.sqrt(var) / est
        # the log-sd taken equal to the cv: wider than the log-normal's sqrt(log(1 + cv^2)), as
        # the estimate's left tail is heavier than log-normal where few combinations fail
        lo = np.where(est > 0, est * np.exp(-np.minimum(z * cv, 700.0)), 0.0)
        hi = np.where(est > 0, np.minimum(est * np.exp(np.minimum(z * cv, 700.0)), 1.0), 0.0)
        is_cv, pair_cv = np.sqrt(var_is) / est, np.sqrt(var_pairs) / est
    ratio = np.quantile(pool[1], [0.1, 0.5, 0.9]) if pool is not None else np.full(3, np.nan)
    return dict(est=est, lo=lo, hi=hi, cv=cv, is_cv=is_cv, pair_cv=pair_cv, eff=eff, d_star=d_star,
                top=float(np.max(g0)), ratio=ratio, checked=checked, check=check)


def _typical_equilibrium(law, d):
    """Equilibrium of the sample's mean law (Eq. 13's crossing); the grid's start if none."""
    deq = summary_kernel(law[None, :], np.zeros((1, law.size)), d)[2][0]
    return float(deq) if np.isfinite(deq) else float(d[0])


def _assemble(out, cheap, thr, m, acc, confidence, n_comb, n_boot):
    rh = cheap["rh"].values
    dims = ("rh", "threshold")
    tcoord = np.arange(thr.shape[1])
    ds = xr.Dataset({
        "exceedance_probability": (dims, np.stack([o["est"] for o in out]), {
            "units": "1", "long_name": "P(strip adhesive energy > threshold)"}),
        "exceedance_probability_lower": (dims, np.stack([o["lo"] for o in out]), {
            "units": "1", "long_name": f"lower bound, {100 * confidence:g} % bootstrap interval"}),
        "exceedance_probability_upper": (dims, np.stack([o["hi"] for o in out]), {
            "units": "1", "long_name": f"upper bound, {100 * confidence:g} % bootstrap interval"}),
        "importance_sampling_cv": (dims, np.stack([o["is_cv"] for o in out]), {
            "units": "1", "long_name": "cv from the finite number of combinations"}),
        "adhesive_energy": (dims, thr, {"units": "J m-2", "long_name": "threshold on the strip's Γ"}),
        "coefficient_of_variation": (dims, np.stack([o["cv"] for o in out]), {
            "units": "1", "long_name": "cv of the estimate (sub-zone sampling, pairs, importance sampling)"}),
        "emulator_cv": (dims, np.stack([o["pair_cv"] for o in out]), {
            "units": "1", "long_name": "cv from the random pairs' ratios (bootstrap sd of the log estimate)"}),
        "accurate_ratio": (("rh", "quantile"), np.stack([o["ratio"] for o in out]), {
            "units": "1", "long_name": "Γ_accurate/Γ_cheap of the random pairs' sub-zones (10, 50, 90 %)"}),
        "accurate_share": (dims, np.stack([o["checked"] for o in out]), {
            "units": "1", "long_name": "share of the tail's excess influence on sub-zones the accurate model ran on"}),
        "ratio_check_rms_z": ("rh", np.array([o["check"][0] for o in out]), {
            "units": "1", "long_name": "rms of held-out strips' Γ error over the spread of their prediction"}),
        "ratio_check_within_2sd": ("rh", np.array([o["check"][1] for o in out]), {
            "units": "1", "long_name": "fraction of held-out strips within 2 sd of their prediction"}),
        "ratio_check_strips": ("rh", np.array([o["check"][2] for o in out]), {
            "units": "1", "long_name": "held-out strips of the ratio check"}),
        "largest_strip_energy": ("rh", np.array([o["top"] for o in out]), {
            "units": "J m-2", "long_name": "largest strip Γ among the combinations"}),
        "effective_subzones": (dims, np.stack([o["eff"] for o in out]), {
            "units": "1", "long_name": "sub-zones the estimate's variance rests on (participation ratio)"}),
        "few_subzones": (dims, np.stack([(o["eff"] < MIN_EFFECTIVE_SUBZONES) & (o["est"] > 0) for o in out]), {
            "units": "1", "long_name": "the tail rests on a handful of sub-zones: its interval is not to be trusted"}),
        "typical_equilibrium_distance": ("rh", np.array([o["d_star"] for o in out]), {"units": "m"}),
    }, coords={"rh": rh, "threshold": tcoord,
               "quantile": ("quantile", [0.1, 0.5, 0.9], {"units": "1", "long_name": "quantile level"})})
    ds.attrs.update(subzones=m, n_subzones=int(cheap.sizes["realization"]),
                    n_accurate=0 if acc is None else int(acc.sizes["realization"]),
                    n_combinations=int(n_comb), n_boot=int(n_boot), confidence=float(confidence),
                    estimator="plug-in over combinations of sub-zone laws (importance sampled)")
    append_history(ds, f"strip_ccdf(subzones={m}, n_subzones={ds.attrs['n_subzones']}, "
                       f"n_accurate={ds.attrs['n_accurate']})")
    return ds


def _subzone_laws(psd, rh, n, start, shape, spacing, model, seed, distance, scheduler, workers, layer="paper",
                  index=None, material=None):
    """Pressure of sub-zones ``start ... n-1`` (or of ``index``) of the seed's realizations on one
    distance grid; the ``realization`` coordinate holds their indices."""
    index = np.arange(start, n) if index is None else np.asarray(index, dtype=np.int64)
    surf = generate_surfaces(psd, n=int(index.max()) + 1, shape=shape, spacing=spacing, seed=seed, chunks=1)
    surf = surf.isel(realization=index).assign_coords(realization=index)
    c = contact_curves(surf, relative_humidity=list(rh), model=model, check_validity=False, distance=distance,
                       adsorbed_layer=layer, **({} if material is None else {"material": material}))
    kw = {} if workers is None else {"num_workers": int(workers)}
    p = c["pressure"].compute(scheduler=scheduler, **kw)
    p = p.drop_vars([k for k in p.coords if k not in ("rh", "distance", "realization")])
    return p.assign_coords(realization=index)


@check_numbers(n="count", n_accurate="count0", n_tail="count0", seed="seed", confidence="fraction", spacing="length",
               n_combinations="count", n_boot="count", workers="count?", subzones="count?", n_distance="count?",
               target_cv="positive?", max_accurate="count?")
def strip_stuck_probability(psd, *, relative_humidity, beam_length, n: int = 12_000, n_accurate: int = 240,
                            n_tail: int = 48, target_cv: float | None = 0.3, max_accurate: int | None = None,
                            model: str = "modified_dmt", accurate_model: str | None = "fft_bem",
                            beam=None, spacing=5e-9, seed=0, n_combinations: int = 100_000,
                            n_boot: int = 20, confidence: float = 0.95, subzones: int | None = None,
                            n_distance: int | None = None, adsorbed_layer="paper", material=None,
                            model_band=None, refine_crossing=None, scheduler: str = "threads",
                            workers: int | None = None) -> xr.Dataset:
    r"""P(stuck) of released sharp-front beams on their own interaction zone, small values included.

    The beam's zone :math:`\Delta s \times w` (:func:`subzone_shape`: 12 sub-zones of 524 × 500
    pixels at 5 nm for the paper's beam) is composed of independent sub-zones; ``n`` sub-zones
    are drawn from the PSD and run through ``model`` at every humidity, the first
    ``n_accurate`` of them through ``accurate_model`` too, and :func:`strip_ccdf` estimates the
    strips' Γ exceedance at every patch threshold :math:`K/x_{j+1}^4` of every beam (Eq. 36);
    P(stuck) is :math:`1 - \prod_j (1 - \bar F(K/x_{j+1}^4))` (the sharp front on independent
    strips, :func:`roughstick.beam.stuck_probability_from_ccdf`): S-shaped stiction. Near a
    beam's detachment length the cohesive beam (:func:`roughstick.beam.simulate` with
    ``beam_model="cohesive"``) sticks fewer beams S-shaped and leaves others as arcs held by the
    tip, which this count does not include (docs/rare_events.md).

    Parameters
    ----------
    psd : xarray.DataArray or callable
        PSD of the equivalent surface (e.g. ``rs.datasets.family_psd("table4")``).
    relative_humidity : float or sequence
        RH fractions in (0, 1).
    beam_length : float or sequence
        Beam lengths [m].
    n : int
        Sub-zones of the cheap model (``n / m`` strips' worth of area).
    n_accurate : int
        Sub-zones, the first of the ``n`` (a random sample), also through ``accurate_model`` (0 or
        ``accurate_model=None``: the cheap model alone, its answer is then that model's).
    n_tail : int
        Further sub-zones through ``accurate_model``: those with the largest own Γ (Eq. 16) at
        the humidities where it runs, the ones strong strips are made of.
    target_cv : float or None
        Where a beam's P(stuck) is at least :data:`TARGET_FLOOR` and its cv above
        :data:`TARGET_MARGIN` × this, with the random pairs' ratios at least half its variance,
        the pairs at that humidity are doubled (the next sub-zones of the ``n``, up to
        ``max_accurate``) and the estimate redone there; None: ``n_accurate`` pairs everywhere.
    max_accurate : int, optional
        Most random pairs per humidity (default ``4 * n_accurate``, at most ``n``): the pairs
        double up to twice, 240 → 480 → 960 by default.
    model, accurate_model : str
        The contact models (:func:`roughstick.contact.curves`).
    beam : Cantilever
        The beams' geometry (default the paper's); sets the zone and the thresholds.
    spacing : float
        Pixel size [m].
    seed : int
        Root seed of the sub-zones and of the estimator.
    n_combinations, n_boot : int
        Importance-sampled combinations and bootstrap refits of :func:`strip_ccdf`.
    confidence : float
        Level of the intervals.
    subzones : int, optional
        Sub-zones per strip (a divisor of the zone's width in pixels); default
        :func:`subzone_shape`'s, the squarest.
    n_distance : int, optional
        Points of the distance grid (:func:`roughstick.ensemble.distance_grid`'s default if None).
    adsorbed_layer : str or float
        The adsorbed water layer of the contact models ("paper": 0.9 nm per surface above 65 % RH).
    material : Material, optional
        The surfaces' material (:func:`roughstick.contact.curves`'s default, polysilicon, if None).
    model_band : (float, float), optional
        Relative error of the strips' Γ from the models, (below, above): the composition of
        the strip from its sub-zones and the two-fidelity correction. Default
        :data:`MODEL_BAND` with an accurate model; none with a model alone (its own answer).
    refine_crossing : float or sequence of float, optional
        P(stuck) levels whose crossing humidity is wanted (e.g. 1e-3): after the grid, up to
        :data:`REFINE_CALLS` (3) more calls at the humidities
        where a crossing is not yet held: first where the estimate crosses (inverse quadratic
        interpolation in logit P, as in Brent's root finder; bisection next to a 0 or a 1) until
        a point next to it has an interval holding the level, then where the interval's ends
        cross while their grid points lie further apart than the interval is wide. The points
        join the result's ``rh`` (attrs ``refined_humidities``), so that
        :func:`crossing_humidity`'s interval rests on estimates near the crossing, not on the
        interpolation between distant grid humidities (an error the interval does not hold).
    scheduler : str
        Dask scheduler of the contact curves (one task per sub-zone).
    workers : int, optional
        Number of dask workers.

    Returns
    -------
    xarray.Dataset
        Over ``(rh, beam_length)``: ``stiction_probability`` with ``_lower``/``_upper``,
        ``coefficient_of_variation`` and ``beyond_reach`` (no combination of the sample fails:
        the estimate 0 has no interval; the margin is ``reach_margin``, the beam's threshold over
        the largest strip Γ the combinations found); with a model band
        ``stiction_probability_model_lower``/``_upper``, the interval of P(stuck) with every
        strip's Γ at the band's lower and upper end (sampling and model); over ``rh`` the diagnostics of
        :func:`strip_ccdf`. attrs: evaluations of each model (sub-zones and zone equivalents),
        seconds of each stage. :func:`roughstick.stiction.crossing_humidity` reads it.

    Examples
    --------
    >>> psd = rs.datasets.family_psd("table4")
    >>> r = rs.stiction.strip_stuck_probability(psd, relative_humidity=[0.6, 0.8], beam_length=[300e-6],
    ...                                         n=48, accurate_model=None, n_combinations=2000)
    >>> r.stiction_probability.values  # 300 µm: free below the adsorbed layer's onset, stuck at 80 %
    array([[0.],
           [1.]])
    """
    if refine_crossing is not None:
        args = {k: v for k, v in locals().items() if k != "refine_crossing"}
        return _refined(strip_stuck_probability, args, refine_crossing)
    beam = PAPER_CANTILEVER if beam is None else beam
    rh = relative_humidity_array(relative_humidity)
    lengths = np.atleast_1d(np.asarray(beam_length, dtype=float))
    patch_length = beam.interaction_zone_length
    if lengths.ndim != 1 or lengths.size == 0 or not np.all(np.isfinite(lengths)) or np.any(lengths < patch_length):
        raise ValueError(f"beam_length must be lengths in m of at least one strip ({patch_length:.3g} m), got "
                         f"{beam_length!r}: e.g. beam_length=[200e-6, 300e-6]")
    band = _model_band(model_band, accurate_model is not None and n_accurate > 0)
    shape, m = subzone_shape(beam, spacing=spacing)
    if subzones is not None:
        width = shape[1] * m
        if width % int(subzones):
            raise ValueError(f"subzones={subzones} does not divide the zone's {width} pixels across the beam: "
                             f"pass a divisor of {width} (default {m})")
        shape, m = (shape[0], width // int(subzones)), int(subzones)
    n_acc = 0 if accurate_model is None else int(n_accurate)
    if n < 4 * m:
        raise ValueError(f"n={n} sub-zones are fewer than 4 strips of {m}: pass n >= {4 * m} (thousands for "
                         "probabilities below 1e-3)")
    if accurate_model is not None and not 8 <= n_acc <= n:
        raise ValueError(f"n_accurate={n_accurate} must lie in [8, n] for two fidelities (a few hundred: its "
                         "pairs set the accurate-to-cheap ratio), or pass accurate_model=None")
    grid_psd = {"psd": psd} if isinstance(psd, xr.DataArray) else {"m0": _callable_m0(psd, shape, spacing)}
    distance = np.asarray(distance_grid(**grid_psd, shape=shape, n=n, relative_humidity=rh,
                                        n_distance=n_distance, adsorbed_layer=adsorbed_layer).values, dtype=float)
    t0 = time.perf_counter()
    cheap = _subzone_laws(psd, rh, n, 0, shape, spacing, model, seed, distance, scheduler, workers, adsorbed_layer,
                          material=material)
    t1 = time.perf_counter()
    allt, per_beam = _patch_thresholds(lengths, beam, patch_length)
    # the patch thresholds, then with every strip's Γ at the model band's upper and lower end
    every_t = allt if band is None else np.concatenate([allt, allt / (1 + band[1]), allt / (1 + band[0])])
    need = _needs_accurate(cheap, allt, per_beam, m, seed) if n_acc else np.zeros(rh.size, bool)
    most = min(int(n), 4 * n_acc if max_accurate is None else max(int(max_accurate), n_acc))
    acc, pairs, tail = {}, np.zeros(rh.size, np.int64), np.zeros(0, np.int64)
    seconds = {"accurate": 0.0, "estimator": 0.0}

    def run_accurate(ks, index):
        t = time.perf_counter()
        a = _subzone_laws(psd, rh[ks], n_acc, 0, shape, spacing, accurate_model, seed, distance, scheduler, workers,
                          adsorbed_layer, index=index, material=material)
        for j, k in enumerate(ks):
            acc[k] = a.isel(rh=[j]) if k not in acc else xr.concat([acc[k], a.isel(rh=[j])], "realization")
        seconds["accurate"] += time.perf_counter() - t

    def estimate(k):
        t = time.perf_counter()
        c = strip_ccdf(cheap.isel(rh=[k]), every_t, subzones=m, accurate=acc.get(k),
                       random_pairs=int(pairs[k]) or None, n_combinations=n_combinations, n_boot=n_boot,
                       seed=np.random.SeedSequence([int(seed), k]), confidence=confidence, tilt_to=allt)
        seconds["estimator"] += time.perf_counter() - t
        return c

    if need.any():
        # the random pairs, and the sub-zones that carry the tail at some humidity: the accurate
        # model sees exactly the sub-zones whose cheap law would otherwise make the tail
        tail = _tail_subzones(cheap.isel(rh=np.flatnonzero(need)), distance, n_acc, n_tail)
        run_accurate(np.flatnonzero(need), np.concatenate([np.arange(n_acc), tail]))
        pairs[need] = n_acc
    parts = [estimate(k) for k in range(rh.size)]
    out = _stuck_dataset(xr.concat(parts, "rh"), rh, lengths, per_beam, allt, confidence, band)
    grow = _humidities_short_of_target(out, target_cv) & (pairs > 0) & (pairs < most)
    while grow.any():
        # more random pairs where their ratios keep the cv above the target: the next sub-zones
        # of the sample (a random one), those the tail already holds not run again
        for size in np.unique(pairs[grow]):
            ks = np.flatnonzero(grow & (pairs == size))
            new = min(2 * int(size), most)
            run_accurate(ks, np.setdiff1d(np.arange(size, new), tail))
            for k in ks:
                acc[k] = acc[k].sortby("realization")
                pairs[k] = new
                parts[k] = estimate(k)
        out = _stuck_dataset(xr.concat(parts, "rh"), rh, lengths, per_beam, allt, confidence, band)
        grow = _humidities_short_of_target(out, target_cv) & (pairs > 0) & (pairs < most)
    n_seen = np.array([acc[k].sizes["realization"] if k in acc else 0 for k in range(rh.size)])
    out.attrs.update(
        n_cheap_subzones=int(n), n_accurate_subzones=int(n_seen.max()), n_random_pairs=int(pairs.max()),
        n_tail_subzones=int(tail.size), subzones=m, subzone_shape=list(shape), cheap_zone_equivalents=n / m,
        accurate_zone_equivalents=float(n_seen.max()) / m, contact_model=model, accurate_model=str(accurate_model),
        patch_length=patch_length, spacing=float(spacing), adsorbed_layer=str(adsorbed_layer),
        ratio_bracket=list(RATIO_BRACKET), n_distance=int(distance.size), seconds_cheap=t1 - t0,
        seconds_accurate=seconds["accurate"], seconds_estimator=seconds["estimator"],
        target_cv=np.nan if target_cv is None else float(target_cv), **beam.attrs())
    append_history(out, f"strip_stuck_probability(n={n}, n_accurate={n_acc}, pairs per RH up to {int(pairs.max())})")
    out["accurate_model_run"] = ("rh", need, {"units": "1", "long_name": "the accurate model ran at this humidity"})
    out["random_pairs"] = ("rh", pairs, {"units": "1", "long_name": "random sub-zones the accurate model ran on"})
    out["accurate_subzones"] = ("rh", n_seen, {"units": "1", "long_name": "sub-zones the accurate model ran on"})
    return out


#: The smallest P(stuck) whose cv ``target_cv`` holds :func:`strip_stuck_probability` to.
TARGET_FLOOR = 1e-6

#: Pairs are added where the reported cv exceeds this fraction of ``target_cv``: the reported cv
#: of one run is 0.7-1.3 × the true one (0.23-0.43 over twenty runs whose true cv is 0.33), and
#: it is low in the runs whose estimate came out high, so a run stopped on a low report keeps
#: its high estimate: at 0.8 two of ten such runs stopped at 1.6 × the mean.
TARGET_MARGIN = 0.6


def _short_of_target(p, cv, pair_cv, target_cv):
    """Whether P(stuck) ``p`` (at least :data:`TARGET_FLOOR`) has a cv above :data:`TARGET_MARGIN`
    × ``target_cv`` with the random pairs' ratios (``pair_cv``) at least half its variance: more
    pairs help there. Elementwise; False everywhere when ``target_cv`` is None."""
    p, cv, pair_cv = (np.nan_to_num(np.asarray(v, dtype=float)) for v in (p, cv, pair_cv))
    if target_cv is None:
        return np.zeros(p.shape, bool)
    return (p >= TARGET_FLOOR) & (cv > TARGET_MARGIN * target_cv) & (2 * pair_cv**2 >= cv**2)


def _humidities_short_of_target(out, target_cv):
    """Humidities where some beam of ``out`` is :func:`_short_of_target`."""
    return _short_of_target(out["stiction_probability"].values, out["coefficient_of_variation"].values,
                            out["emulator_cv"].values, target_cv).any(axis=1)


def _tail_subzones(cheap, distance, n_pairs, n_tail):
    """Indices (>= ``n_pairs``) of the ``n_tail`` sub-zones with the largest own Γ (Eq. 13 of their
    cheap law) at any of the humidities of ``cheap``: the ones strong strips are made of."""
    if n_tail == 0:
        return np.zeros(0, np.int64)
    rank = []
    for k in range(cheap.sizes["rh"]):
        g = _gamma(np.asarray(cheap.isel(rh=k).transpose("realization", "distance").values, dtype=float), distance)
        g[:n_pairs] = -np.inf
        rank.append(np.argsort(-g, kind="stable"))
    picked, j = [], 0
    while len(picked) < n_tail and j < rank[0].size - n_pairs:
        for r in rank:  # round robin over humidities
            if r[j] not in picked and len(picked) < n_tail:
                picked.append(int(r[j]))
        j += 1
    return np.array(sorted(picked), dtype=np.int64)


def _needs_accurate(cheap, allt, per_beam, m, seed):
    """Humidities where some beam's P(stuck) is neither 0 nor 1 for any accurate-to-cheap ratio in
    :data:`RATIO_BRACKET`: there the accurate model must run; elsewhere the cheap answer holds."""
    need = np.zeros(cheap.sizes["rh"], bool)
    for k in range(cheap.sizes["rh"]):
        c = strip_ccdf(cheap.isel(rh=[k]), np.concatenate([allt / RATIO_BRACKET[1], allt / RATIO_BRACKET[0]]),
                       subzones=m, n_combinations=20_000, n_boot=1, seed=np.random.SeedSequence([int(seed), 99, k]))
        e = c["exceedance_probability"].values[0]
        hi, lo = e[: allt.size], e[allt.size:]
        for patches in per_beam:
            p_hi = -np.expm1(np.sum(np.log1p(-np.minimum(hi[patches], 1 - 1e-16))))
            p_lo = -np.expm1(np.sum(np.log1p(-np.minimum(lo[patches], 1 - 1e-16))))
            need[k] |= (p_hi > 0) and (p_lo < 1 - 1e-9)
    return need
