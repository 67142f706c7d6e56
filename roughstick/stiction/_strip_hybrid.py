"""The two-fidelity hybrid of the strips estimator (:mod:`roughstick.stiction.strip_tail`): the
law each sub-zone carries and the strip Γ predicted from them.

Eq. 13 of a law scaled by r is r times its Γ, so a sub-zone's accurate Γ is its cheap law scaled
by its own Γ_accurate/Γ_cheap ratio where the accurate model ran, and by a ratio drawn from the
random pairs of similar cheap Γ elsewhere. The two models' laws differ in shape, so a strip
composed of scaled laws misses the accurate strip's Γ (its equilibrium moves): a residual drawn
from the pairs' own recombined strips of similar Γ adds what scaling misses, and a
leave-one-strip-out check on the pairs' strips measures the whole prediction.
"""

from __future__ import annotations

import math

import numpy as np

from ..contact.adhesion import summary_kernel

#: Accurate-to-cheap ratio of strip Γ assumed possible when deciding where the accurate model
#: is needed (Table 4, RH 0.6-0.85: 0.66-0.98 measured).
RATIO_BRACKET = (0.5, 2.0)


def _gamma(pbar, d):
    """Eq. 13 of composed laws (rows)."""
    return summary_kernel(pbar, np.zeros_like(pbar), d)[0]


def _compose(p, idx, chunk=20_000):
    """Mean law of each row of ``idx`` (rows of ``p``), in chunks."""
    out = np.empty((idx.shape[0], p.shape[1]))
    for s in range(0, idx.shape[0], chunk):
        out[s:s + chunk] = p[idx[s:s + chunk]].mean(1)
    return out


#: A sub-zone the accurate model did not see draws its ratio from the random pairs nearest to it
#: in cheap Γ (this many, or a fifth of the pairs where that is more): the ratio's spread shrinks
#: as Γ grows, and ratios far from 1 belong to weak sub-zones (a tall asperity that holds the flat
#: off in the cheap model alone).
RATIO_NEIGHBOURS = 20


def _log(x):
    with np.errstate(divide="ignore"):
        return np.log(x)


def _near(keys, x, u, k, window=0.0):
    """Indices into the sorted ``keys`` of one element near each ``x`` (log scale): at quantile
    ``u`` in [0, 1) of those within ``window`` of it or, where they are fewer than ``k``, of the
    ``k`` nearest (a run [a, a + k) of the sorted keys: the first whose left end is no farther
    from x than the key after its right end)."""
    n = keys.size
    k = min(k, n)
    pos = np.searchsorted(keys, x)
    a, b = np.clip(pos - k, 0, n - k), np.clip(pos, 0, n - k)
    ext = np.append(keys, np.inf)
    while np.any(a < b):
        mid = (a + b) // 2
        right = (x - keys[mid]) > (ext[mid + k] - x)
        a, b = np.where(right, mid + 1, a), np.where(right, b, mid)
    lo, hi = a, a + k
    if window > 0:
        wlo, whi = np.searchsorted(keys, x - window), np.searchsorted(keys, x + window, side="right")
        wide = whi - wlo >= k
        lo, hi = np.where(wide, wlo, lo), np.where(wide, whi, hi)
    return np.minimum(lo + (u * (hi - lo)).astype(np.int64), hi - 1)


def _ratio_pool(pc, pa, d):
    """Per-sub-zone Γ_accurate/Γ_cheap of the random pairs, from those whose cheap Γ is at least a
    tenth of the pairs' median (a ratio of two near-zero energies says nothing), clipped to
    :data:`RATIO_BRACKET`. Returns (log cheap Γ, sorted; the ratios in that order)."""
    gc, ga = _gamma(pc, d), _gamma(pa, d)
    ok = (gc > 0.1 * np.median(gc)) & (gc > 0) & (ga >= 0)
    if not ok.any():
        return np.zeros(1), np.ones(1)
    order = np.argsort(gc[ok], kind="stable")
    return np.log(gc[ok][order]), np.clip(ga[ok][order] / gc[ok][order], *RATIO_BRACKET)


def _draw_ratios(pool, key, u):
    """Ratios of sub-zones of log cheap Γ ``key``, each from the pairs nearest to it
    (:data:`RATIO_NEIGHBOURS`) at quantile ``u``."""
    keys, ratios = pool
    return ratios[_near(keys, key, u, max(keys.size // 5, RATIO_NEIGHBOURS))]


def _hybrid_gamma(base, free, key, pool, idx, u, d, chunk=5000):
    """Γ (Eq. 13) of the strips ``idx`` of accurate laws: ``base`` (the hybrid law where the
    accurate model ran, else the cheap law) with every ``free`` slot scaled by a ratio of the pairs
    nearest to it in log cheap Γ ``key`` (:func:`_draw_ratios`, at quantile ``u``), a fresh draw in
    every combination (Eq. 13 of a scaled law is the scaled Γ)."""
    out = np.empty(idx.shape[0])
    for s in range(0, idx.shape[0], chunk):
        i = idx[s:s + chunk]
        r = np.where(free[i], _draw_ratios(pool, key[i], u[s:s + chunk]), 1.0)
        out[s:s + chunk] = _gamma((base[i] * r[..., None]).mean(1), d)
    return out


def _own_ratios(pc, pa, d, ref):
    """Each sub-zone's own Γ_accurate/Γ_cheap where its cheap Γ is at least a tenth of ``ref`` and
    the ratio lies in :data:`RATIO_BRACKET`; NaN elsewhere (a ratio of near-zero energies, or an
    artefact of the cheap model, says nothing about the law's scale)."""
    gc, ga = _gamma(pc, d), _gamma(pa, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = ga / gc
    return np.where((gc > 0.1 * ref) & (gc > 0) & (r >= RATIO_BRACKET[0]) & (r <= RATIO_BRACKET[1]), r, np.nan)


def _hybrid_laws(pc, pa, d, ref):
    """The law a sub-zone the accurate model saw carries in the hybrid: its cheap law scaled by its
    own ratio (:func:`_own_ratios`; Eq. 13 of it is the accurate Γ), or its accurate law where
    that ratio says nothing."""
    own = _own_ratios(pc, pa, d, ref)
    return np.where(np.isnan(own)[:, None], pa, pc * np.nan_to_num(own)[:, None])


#: The residual of a strip is drawn from the pairs' recombined strips whose scaled Γ lies within
#: this factor of its own (at least :data:`RESIDUAL_NEIGHBOURS` of the nearest): what scaling misses
#: depends on the strip (a tall asperity that holds the flat off in one model and not in the other
#: moves a near-zero Γ by mJ m-2, a strong strip's by a few per cent).
RESIDUAL_WINDOW = 1.1
#: Fewest recombined strips a residual is drawn from (a fortieth of them where that is more).
RESIDUAL_NEIGHBOURS = 20


def _residual_pool(pc, pa, pool, d, m, rng, n_comb=4000):
    """What scaling the laws misses in a composed strip (the equilibrium moves, the law's shape
    differs), beside the ratios' own spread that the hybrid draws: strips recombined from the
    random pairs, each pair's cheap law scaled by its own ratio. Returns their Γ_scaled (sorted;
    those above 0) and Γ_accurate - Γ_scaled [J m-2] (additive: a ratio of a near-zero Γ would
    blow up)."""
    gc, ga1 = _gamma(pc, d), _gamma(pa, d)
    own = np.where(gc > 0.1 * np.median(gc), np.clip(ga1 / np.where(gc > 0, gc, 1.0), *RATIO_BRACKET),
                   np.median(pool[1]))
    idx = rng.integers(0, pc.shape[0], size=(n_comb, m))
    ga = _gamma(_compose(pa, idx), d)
    gh = _gamma(_compose(pc * own[:, None], idx), d)
    order = np.argsort(gh, kind="stable")
    order = order[gh[order] > 0]  # a strip at Γ = 0 gets no residual: none is drawn from one
    return gh[order], ga[order] - gh[order]


def _with_residual(g, res, u):
    """Strip Γ of the hybrid laws plus the residual of one of the pairs' recombined strips of
    similar scaled Γ (within :data:`RESIDUAL_WINDOW`, or the :data:`RESIDUAL_NEIGHBOURS` nearest
    in log Γ), picked by ``u`` in [0, 1), never below 0; none where Γ = 0."""
    gh, r = res
    if gh.size == 0:
        return np.maximum(g, 0.0)
    pick = _near(np.log(gh), _log(g), u, max(gh.size // 40, RESIDUAL_NEIGHBOURS), math.log(RESIDUAL_WINDOW))
    return np.where(g > 0, np.maximum(g + r[pick], 0.0), 0.0)


def _holdout(pc, pa_pairs, d, m, rng, draws=50):
    """The hybrid's check on the pairs' own strips (consecutive groups of ``m`` random pairs):
    each strip's accurate Γ against its prediction from its cheap laws scaled by ratios of the
    *other* pairs (:func:`_draw_ratios`), in units of the prediction's spread. Returns (rms z, fraction within ±2, strips)."""
    k = pc.shape[0] // m
    if k < 2:  # one strip of pairs: none left to predict it from
        return np.nan, np.nan, 0
    z = []
    for j in range(k):
        sl = slice(j * m, (j + 1) * m)
        keep = np.ones(pc.shape[0], bool)
        keep[sl] = False
        pool = _ratio_pool(pc[keep], pa_pairs[keep], d)
        res = _residual_pool(pc[keep], pa_pairs[keep], pool, d, m, rng, n_comb=1000)
        r = _draw_ratios(pool, np.broadcast_to(_log(_gamma(pc[sl], d)), (draws, m)), rng.random((draws, m)))
        pred = _with_residual(_gamma((pc[sl][None, :, :] * r[:, :, None]).mean(1), d), res, rng.random(draws))
        actual = _gamma(pa_pairs[sl].mean(0)[None], d)[0]
        if pred.std() > 0:
            z.append((actual - pred.mean()) / pred.std())
    z = np.array(z)
    return (float(np.sqrt(np.mean(z**2))) if z.size else np.nan,
            float(np.mean(np.abs(z) <= 2)) if z.size else np.nan, int(z.size))
