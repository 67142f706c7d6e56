"""The search between the local minima of Eq. 21 for one asperity footprint (compiled).

Where a fit leaves pixels outside its sphere, has one on its rim or ends with its centre on the
bound (:func:`awry`), the cost of Eq. 21 is not smooth (a pixel entering the sphere's projection
meets its vertical tangent) and has several local minima, typically on steep asperities cut by
the edge of a measured map; the local iteration (:func:`._lm.lm`) from the documented
starts can stop in a poorer one than the reference's ``least_squares``. The compass search
(:func:`pattern_search`) and the grids (:func:`grid_search`) search on from there; see
:func:`._fit.fit_sphere` for when, and docs/rough_contact.md for what it was measured on.
"""

from __future__ import annotations

import math

import numba as nb

from ._lm import cost_at, lm

__all__ = ["outside", "awry", "pattern_search", "grid_search", "GRID_KEEP"]


_FASTMATH = {"reassoc", "contract"}
GRID_KEEP = 20  # at most this many grid points polished (the columns of the (4, GRID_KEEP) work array)
_RIM = 1e-2  # a pixel at r^2 > (1 - _RIM) R^2 is on the sphere's rim (see awry)
_SAME_MINIMUM = 1e-6  # two local iterations ending this close (units of a_f) reached one minimum
_PATTERN_STEP = 0.05  # compass search: first step (units of a_f), halved down to
_PATTERN_STOP = 1e-6  # this, then the local iteration
# its directions: the three axes, and the diagonals of the three coordinate planes
_DIRECTIONS = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 1.0, 0.0), (1.0, -1.0, 0.0),
               (1.0, 0.0, 1.0), (0.0, 1.0, 1.0), (1.0, 0.0, -1.0), (0.0, 1.0, -1.0))


@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH, error_model="numpy", _nrt=False)
def outside(xs, ys, wt, x0, y0, t, margin):  # pragma: no cover - compiled
    """Whether some pixel lies outside the projection of the sphere (r > R, profile clamped) or
    within ``r^2 > (1 - margin) R^2`` of its rim."""
    Q = 1.0 + t * t
    QQ = Q * Q
    ft2 = 4.0 * t * t
    lim = margin * QQ
    out = 0.0
    for p in range(xs.size):
        dx = xs[p] - x0
        dy = ys[p] - y0
        if QQ - ft2 * (dx * dx + dy * dy) <= lim:
            out += wt[p]
    return out > 0.0


@nb.njit(cache=True, nogil=True, error_model="numpy", _nrt=False, inline="always")
def awry(xs, ys, wt, lo0, lo1, hi0, hi1, x0, y0, t):  # pragma: no cover - compiled
    """Whether the fit (x0, y0, t) ends with its centre on the bound, leaves pixels outside its
    sphere or has one on its rim: there the cost of Eq. 21 is not smooth (at the rim the profile
    has a vertical tangent, where the iteration's steps shrink to nothing: a 5-pixel asperity
    stopped with a pixel at r^2 = 0.995 R^2 and 3.2 times the residual of the minimum beyond)
    and has several local minima."""
    if not (t > 0.0):
        return False
    if x0 <= lo0 or x0 >= hi0 or y0 <= lo1 or y0 >= hi1:
        return True
    # no pixel can be near the rim of a sphere wider than the box seen from its centre (most fits)
    ex = max(x0 - lo0, hi0 - x0)
    ey = max(y0 - lo1, hi1 - y0)
    R = (1.0 + t * t) / (2.0 * t)
    return (1.0 - _RIM) * R * R < ex * ex + ey * ey and outside(xs, ys, wt, x0, y0, t, _RIM)


@nb.njit(cache=True, nogil=True, error_model="numpy", _nrt=False)
def pattern_search(xs, ys, hs, wt, x0, y0, t, lo0, lo1, hi0, hi1):  # pragma: no cover - compiled
    """Compass search from (x0, y0, t), then the local iteration; returns ``(t, cost, x0, y0)``.

    Steps of 0.05 a_f along the axes and the planes' diagonals, halved when none lowers the cost,
    down to 1e-6: the first steps cross from one local minimum of Eq. 21 to a lower neighbour
    (where pixels leave the sphere the minima lie ~0.05-0.3 a_f apart), which the iteration,
    following the local gradient, cannot.
    """
    cost = cost_at(xs, ys, hs, wt, x0, y0, t)
    step = _PATTERN_STEP
    while step > _PATTERN_STOP:
        moved = False
        for k in range(len(_DIRECTIONS)):
            u = _DIRECTIONS[k]
            for sign in (1.0, -1.0):
                s = sign * step
                q0 = min(max(x0 + s * u[0], lo0), hi0)
                q1 = min(max(y0 + s * u[1], lo1), hi1)
                q2 = min(max(t + s * u[2], 0.0), 1.0)
                c = cost_at(xs, ys, hs, wt, q0, q1, q2)
                if c < cost:
                    x0, y0, t, cost = q0, q1, q2, c
                    moved = True
        if not moved:
            step *= 0.5
    t, cost, x0, y0, _s = lm(xs, ys, hs, wt, x0, y0, t, lo0, lo1, 0.0, hi0, hi1, 1.0, 0.0, 0.0, 0.0, False)
    return t, cost, x0, y0


@nb.njit(cache=True, nogil=True, error_model="numpy", _nrt=False)
def grid_search(xs, ys, hs, wt, lo0, lo1, hi0, hi1, t, cost, x0, y0, M, centres, caps, keep):  # pragma: no cover
    """Global search where a fit from the starts was awry (:func:`awry`).

    The cost is evaluated on a grid of ``centres x centres`` centres over the footprint's box and
    ``caps`` cap heights ``1/caps .. 1``; the ``keep`` best grid points (at most ``M.shape[1]``)
    and the given fit are polished by the local iteration and by :func:`pattern_search`; returns
    the best of all (never worse than the given fit).
    """
    nb_ = keep
    for k in range(nb_):
        M[0, k] = math.inf
    for i in range(centres):
        gx = lo0 + (hi0 - lo0) * i / (centres - 1)
        for j in range(centres):
            gy = lo1 + (hi1 - lo1) * j / (centres - 1)
            for m in range(caps):
                gt = (m + 1.0) / caps
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
    t2, cost2, x2, y2 = pattern_search(xs, ys, hs, wt, x0, y0, t, lo0, lo1, hi0, hi1)
    if cost2 < cost:
        t, cost, x0, y0 = t2, cost2, x2, y2
    for k in range(nb_):
        if not math.isfinite(M[0, k]):
            break
        t2, cost2, x2, y2, _s = lm(xs, ys, hs, wt, M[1, k], M[2, k], M[3, k], lo0, lo1, 0.0, hi0, hi1, 1.0,
                                   0.0, 0.0, 0.0, False)
        if cost2 < cost:
            t, cost, x0, y0 = t2, cost2, x2, y2
        M[0, k], M[1, k], M[2, k], M[3, k] = cost2, x2, y2, t2  # the minimum it reached
        seen = False  # grid points in one basin reach one minimum: searched on from once
        for j in range(k):
            if (abs(M[1, j] - x2) <= _SAME_MINIMUM and abs(M[2, j] - y2) <= _SAME_MINIMUM
                    and abs(M[3, j] - t2) <= _SAME_MINIMUM):
                seen = True
                break
        if not seen:
            t2, cost2, x2, y2 = pattern_search(xs, ys, hs, wt, x2, y2, t2, lo0, lo1, hi0, hi1)
            if cost2 < cost:
                t, cost, x0, y0 = t2, cost2, x2, y2
    return t, cost, x0, y0
