"""The two-fidelity hybrid of the strips estimator (:mod:`roughstick.stiction.strip_tail`): the
law each sub-zone carries and the strip Γ predicted from them.

Eq. 13 of a law scaled by r is r times its Γ, so a sub-zone's accurate Γ is its cheap law scaled
by its own Γ_accurate/Γ_cheap ratio where the accurate model ran, and by a ratio drawn from the
random pairs elsewhere. The two models' laws differ in shape, so a strip composed of scaled laws
misses the accurate strip's Γ (its equilibrium moves): a residual drawn from the pairs' own
recombined strips adds what scaling misses, and a leave-one-strip-out check on the pairs'
strips measures the whole prediction.
"""

from __future__ import annotations

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


def _ratio_pool(pc, pa, d):
    """Per-sub-zone Γ_accurate/Γ_cheap of the random pairs, from those whose cheap Γ is at least a
    tenth of the pairs' median (a ratio of two near-zero energies says nothing), clipped to
    :data:`RATIO_BRACKET`."""
    gc, ga = _gamma(pc, d), _gamma(pa, d)
    ok = (gc > 0.1 * np.median(gc)) & (gc > 0) & (ga >= 0)
    if not ok.any():
        return np.ones(1)
    return np.clip(ga[ok] / gc[ok], *RATIO_BRACKET)


def _hybrid_gamma(base, free, pool, idx, u, d, chunk=5000):
    """Γ (Eq. 13) of the strips ``idx`` of accurate laws: ``base`` (the hybrid law where the
    accurate model ran, else the cheap law) with every ``free`` slot scaled by the ratio at quantile ``u`` of the
    random pairs' sorted ``pool``, a fresh draw in every combination (Eq. 13 of a scaled law is
    the scaled Γ)."""
    out = np.empty(idx.shape[0])
    for s in range(0, idx.shape[0], chunk):
        i = idx[s:s + chunk]
        r = np.where(free[i], pool[np.minimum((u[s:s + chunk] * pool.size).astype(np.int64), pool.size - 1)], 1.0)
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


def _residual_pool(pc, pa, pool, d, m, rng, n_comb=4000):
    """Γ_accurate - Γ_scaled [J m-2] of strips recombined from the random pairs, each pair's cheap law
    scaled by its own ratio: what scaling the laws misses in the composed strip (the equilibrium
    moves, the law's shape differs), beside the ratios' own spread that the hybrid draws."""
    gc, ga1 = _gamma(pc, d), _gamma(pa, d)
    own = np.where(gc > 0.1 * np.median(gc), np.clip(ga1 / np.where(gc > 0, gc, 1.0), *RATIO_BRACKET),
                   np.median(pool))
    idx = rng.integers(0, pc.shape[0], size=(n_comb, m))
    ga = _gamma(_compose(pa, idx), d)
    gh = _gamma(_compose(pc * own[:, None], idx), d)
    return ga - gh


def _with_residual(g, res, u):
    """Strip Γ of the hybrid laws plus the residual at quantile ``u`` of the pairs' sorted ``res``
    (additive: a ratio of a near-zero Γ would blow up), never below 0; none where Γ = 0."""
    return np.where(g > 0, np.maximum(g + res[np.minimum((u * res.size).astype(np.int64), res.size - 1)], 0.0), 0.0)


def _holdout(pc, pa_pairs, d, m, rng, draws=50):
    """The hybrid's check on the pairs' own strips (consecutive groups of ``m`` random pairs):
    each strip's accurate Γ against its prediction from its cheap laws scaled by ratios of the
    *other* pairs, in units of the prediction's spread. Returns (rms z, fraction within ±2, strips)."""
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
        r = pool[rng.integers(0, pool.size, size=(draws, m))]
        pred = _with_residual(_gamma((pc[sl][None, :, :] * r[:, :, None]).mean(1), d), np.sort(res),
                              rng.random(draws))
        actual = _gamma(pa_pairs[sl].mean(0)[None], d)[0]
        if pred.std() > 0:
            z.append((actual - pred.mean()) / pred.std())
    z = np.array(z)
    return (float(np.sqrt(np.mean(z**2))) if z.size else np.nan,
            float(np.mean(np.abs(z) <= 2)) if z.size else np.nan, int(z.size))
