"""The search between the local minima of Eq. 21 for one asperity footprint (compiled).

Where a fit leaves pixels outside its sphere or ends with its centre on the bound, the cost of
Eq. 21 is not smooth (a pixel entering the sphere's projection meets its vertical tangent) and
has several local minima, typically on steep asperities cut by the edge of a measured map; the
local iteration (:func:`._rough_lm.lm`) from the documented starts can stop in a poor one. The
functions here decide when that is the case and search further (see :func:`._rough_fit.fit_sphere`).
"""

from __future__ import annotations

import math

import numba as nb

from ._rough_lm import cost_at, lm

__all__ = ["outside", "grid_search"]


_FASTMATH = {"reassoc", "contract"}
_GRID_CENTRES = 7  # the search where a fit leaves pixels outside its sphere: 7 x 7 centres,
_GRID_CAPS = 8  # 8 cap heights, the 5 best polished (M's 4 x 5 entries hold them)


@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH, error_model="numpy", _nrt=False)
def outside(xs, ys, wt, x0, y0, t):  # pragma: no cover - compiled
    """Whether some pixel lies outside the projection of the sphere (r > R, profile clamped)."""
    Q = 1.0 + t * t
    QQ = Q * Q
    ft2 = 4.0 * t * t
    out = 0.0
    for p in range(xs.size):
        dx = xs[p] - x0
        dy = ys[p] - y0
        if QQ - ft2 * (dx * dx + dy * dy) <= 0.0:
            out += wt[p]
    return out > 0.0


@nb.njit(cache=True, nogil=True, error_model="numpy", _nrt=False)
def grid_search(xs, ys, hs, wt, lo0, lo1, hi0, hi1, t, cost, x0, y0, M):  # pragma: no cover - compiled
    """Global search for fits that leave pixels outside their sphere or end on the centre's bound.

    There the cost of Eq. 21 is not smooth (a pixel entering the sphere's projection meets its
    vertical tangent) and has several local minima, typically on asperities cut by the edge of a
    measured map, so the iteration from the documented starts can stop in a poor one. The cost
    is evaluated on a grid of centres over the footprint's box and cap heights, and the
    iteration restarted from the best grid points; returns the best of those and the given fit.
    """
    nb_ = M.shape[1]
    for k in range(nb_):
        M[0, k] = math.inf
    for i in range(_GRID_CENTRES):
        gx = lo0 + (hi0 - lo0) * i / (_GRID_CENTRES - 1)
        for j in range(_GRID_CENTRES):
            gy = lo1 + (hi1 - lo1) * j / (_GRID_CENTRES - 1)
            for m in range(_GRID_CAPS):
                gt = (m + 1.0) / _GRID_CAPS
                c = cost_at(xs, ys, hs, wt, gx, gy, gt)
                if c < M[0, nb_ - 1]:  # insert into the sorted list of the best
                    k = nb_ - 1
                    while k > 0 and M[0, k - 1] > c:
                        for r in range(4):
                            M[r, k] = M[r, k - 1]
                        k -= 1
                    M[0, k] = c
                    M[1, k] = gx
                    M[2, k] = gy
                    M[3, k] = gt
    for k in range(nb_):
        if not math.isfinite(M[0, k]):
            break
        t2, cost2, x2, y2, _s = lm(xs, ys, hs, wt, M[1, k], M[2, k], M[3, k], lo0, lo1, 0.0, hi0, hi1, 1.0,
                                   0.0, 0.0, 0.0, False)
        if cost2 < cost:
            t, cost, x0, y0 = t2, cost2, x2, y2
    return t, cost, x0, y0
