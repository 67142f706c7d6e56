"""The automatic distance grid of the modified DMT: the Python half of the grid policy.

The compiled controller (:mod:`._controller`, parameters :class:`._policy.GridPolicy`) places the
levels of each humidity's curve in one pass; here each humidity's own levels are then refined
until the trapezoid of Eq. 13 is resolved (:data:`GAMMA_TOLERANCE`), and the grid is the union
(:func:`auto_curves`).
"""

from __future__ import annotations

import numpy as np

from ..adhesion import summary_kernel
from . import _controller as _k

__all__ = ["GAMMA_TOLERANCE", "GAMMA_TOLERANCE_MAX", "auto_curves", "refine_gamma", "allowed", "gamma_tolerance"]

#: Error of Γ allowed per interval, relative, on maps of up to 128 x 128 pixels
#: (:func:`gamma_tolerance`, :func:`allowed`; what it achieves: docs/rough_contact.md).
GAMMA_TOLERANCE = 1e-2
#: ... on larger maps it grows as the side, up to this.
GAMMA_TOLERANCE_MAX = 8e-2
_MAX_ROUNDS = 20


def gamma_tolerance(npix):
    """The tolerance of :func:`allowed` on a map of ``npix`` valid pixels: ``GAMMA_TOLERANCE`` ×
    sqrt(npix / 128²), between ``GAMMA_TOLERANCE`` and ``GAMMA_TOLERANCE_MAX``. A larger map has
    more contacting pixels per level, so its curves are smoother between the controller's
    levels and need fewer Γ midpoints for the same error (measured: docs/rough_contact.md)."""
    f = float(np.sqrt(max(npix, 1) / 128.0**2))
    return min(GAMMA_TOLERANCE_MAX, max(GAMMA_TOLERANCE, GAMMA_TOLERANCE * f))


def allowed(gamma, width, levels, tolerance=GAMMA_TOLERANCE):
    """Error of Γ allowed to an interval: ``tolerance`` Γ × max(its share of the range, 1/64)."""
    span = max(float(levels[-1] - levels[0]), 1e-300)
    return tolerance * gamma * np.maximum(width / span, 1 / 64)


def refine_gamma(more, d, out, mem, hw, dp, tolerance=GAMMA_TOLERANCE):
    """Refine each humidity's own grid until the trapezoid of Eq. 13 (Γ) is resolved.

    The controller's midpoint test bounds the pressure's deviation from a chord, which a
    staircase curve (few contacting pixels on small maps) can pass by chance. Here, per humidity and on that humidity's own levels only (so
    its grid, and its Γ, do not depend on the other humidities requested), every attractive
    interval above the equilibrium whose ends differ enough to matter gets its midpoint; an
    interval whose two-half trapezoid differs from its one-interval trapezoid by more than
    :func:`allowed` (with ``tolerance``) has its halves tested in the next round. New levels are evaluated once for
    every humidity (a level's values do not depend on the others), by ``more`` (a
    :class:`._controller.MoreLevels` of the map).
    """
    out = [np.asarray(a) for a in out]
    todo = [None] * hw.size  # per humidity: intervals to test (None: every attractive one)
    known = [None] * hw.size  # per humidity: (Γ, d_eq) on its own levels as they are now
    for _ in range(_MAX_ROUNDS):
        asks = []
        for j in range(hw.size):
            if todo[j] is not None and todo[j].size == 0:
                asks.append(np.empty(0))
                continue
            own = np.flatnonzero(mem[j])
            dj, pj = d[own], out[0][j, own]
            if known[j] is None:
                known[j] = summary_kernel(pj, out[2][j, own], dj)[::2][:2]
            g, deq = known[j]
            mid = 0.5 * (dj[:-1] + dj[1:])
            w, q = np.diff(dj), np.maximum(-pj, 0.0)
            # an interval whose ends differ too little to move Γ (a monotone integrand lies
            # between its ends' values) is not tested
            room = 0.5 * w * np.abs(np.diff(q)) > allowed(g, w, dj, tolerance)
            cand = room & ((pj[:-1] < 0) | (pj[1:] < 0)) & (mid > dj[:-1]) & (mid < dj[1:])
            if np.isfinite(deq):
                cand &= dj[1:] > deq
            if todo[j] is not None:
                cand &= np.isin(dj[:-1], todo[j])
            asks.append(mid[cand])
        new = np.setdiff1d(np.concatenate(asks), d)
        if new.size == 0:
            break
        added = more(new)
        srt = np.argsort(np.concatenate([d, new]), kind="stable")
        d = np.concatenate([d, new])[srt]
        out = [np.concatenate([a, b], axis=1)[:, srt] for a, b in zip(out, added, strict=True)]
        mem = np.concatenate([mem, np.zeros((hw.size, new.size), bool)], axis=1)[:, srt]
        for j, m in enumerate(asks):
            if m.size == 0:
                todo[j] = m
                continue
            mem[j, np.searchsorted(d, m)] = True
            own = np.flatnonzero(mem[j])
            dj, qj = d[own], np.maximum(-out[0][j, own], 0.0)
            known[j] = summary_kernel(out[0][j, own], out[2][j, own], dj)[::2][:2]
            g = known[j][0]
            i = np.searchsorted(dj, m)  # each asked midpoint, between own levels i-1 and i+1
            lo, hi = dj[i - 1], dj[i + 1]
            w = hi - lo
            err = np.abs(0.25 * w * (qj[i - 1] + 2 * qj[i] + qj[i + 1]) - 0.5 * w * (qj[i - 1] + qj[i + 1]))
            bad = err > allowed(g, w, dj, tolerance)
            todo[j] = np.concatenate([lo[bad], m[bad]])
    return d, out


def auto_curves(z, hw, dp, *, dx, dy, K, periodic, connectivity, n):
    """Distance grid and curves of one eager map (see :func:`contact_distance_grid`).

    The grid is strictly increasing: levels the controller placed at one distance are kept
    once, and an interval is split only if its midpoint is a float strictly between its ends
    (the controller bisects sign changes down to adjacent floats, whose midpoint is an end).
    """
    kw = dict(dx=dx, dy=dy, K=K, periodic=periodic, connectivity=connectivity)
    d, out, *rest = _k.curves(z, hw, dp, per_rh="union", **kw)
    d, keep = np.unique(np.asarray(d, dtype=float), return_index=True)
    out = [np.asarray(a)[:, keep] for a in out]
    if rest:  # not a flat map (its grid is uniform): refine each humidity's Γ on its own grid
        mem, more = rest
        d, out = refine_gamma(more, d, out, np.asarray(mem)[:, keep], hw, dp,
                              gamma_tolerance(round(more.apparent / (dx * dy))))
    else:
        more = _k.MoreLevels(z, hw, dp, kw, None, apparent=0.0, zmax=0.0)
    if n is None or d.size >= int(n):
        return d, list(out)
    # more points on request: split the widest intervals (each level is evaluated on its own, so
    # the added levels do not change the others)
    n = int(n)
    while d.size < n:
        widths = np.diff(d)
        mids = 0.5 * (d[:-1] + d[1:])
        splittable = np.flatnonzero((mids > d[:-1]) & (mids < d[1:]))
        if splittable.size == 0:  # every interval is two adjacent floats: nothing left to split
            break
        order = np.argsort(-widths[splittable], kind="stable")
        pick = np.sort(splittable[order[: n - d.size]])
        new = mids[pick]
        added = more(new)
        d = np.concatenate([d, new])
        srt = np.argsort(d, kind="stable")
        d = d[srt]
        out = [np.concatenate([a, b], axis=1)[:, srt] for a, b in zip(out, added, strict=True)]
    return d, list(out)
