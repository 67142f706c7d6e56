"""Sphere fit of Eq. 21 for one asperity footprint: the compiled core of the rough-surface DMT.

Unknowns ``(x0, y0, t)``, ``t = delta / a_f`` in ``[0, 1]`` (see :mod:`._controller` for the
conventions shared with the literal reference of the tests). A projected Levenberg-Marquardt
iteration with the exact Hessian (:mod:`._lm`) from the reference's starts: the centroid with
twice the mean height, the least-squares paraboloid of the footprint (five pixels or more),
keeping the better, and the h-weighted centroid (:func:`plateau_escape`) where the fit stopped on
the plateau ``t = 0`` (or below ``t = 1e-6``, where the cost cannot tell them apart) or is
steeper than ``t = 0.3``.

Where a fit from a start leaves pixels outside its sphere, has one on its rim or ends with its
centre on the bound (:func:`._search.awry`), Eq. 21's cost is not smooth and has several
local minima, and the literal reference's ``least_squares`` can end in a lower one than LM from
the same start. There every awry fit is searched on from by compass steps, and three grids of
centres and caps (the reference's 7 x 7 x 8 and finer 11 x 11 x 12 and 15 x 15 x 16) are
polished the same way (:mod:`._search`); how often, and against the reference:
docs/rough_contact.md. The plateau is always a candidate. Per-pixel sums are vectorised over blocks of ``_SIMD`` pixels
(the footprint arrays are zero-padded with zero weight to a multiple of it).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ._lm import cost_at, lm, over_plateau
from ._search import GRID_KEEP, awry, grid_search, pattern_search

__all__ = ["fit_footprint", "fit_sphere", "small_fit", "paraboloid_start", "plateau_escape"]


_FASTMATH = {"reassoc", "contract"}
_SIMD = 8

_T_MAX_START = 0.999
_PARABOLOID_MIN_PIXELS = 5
_PARABOLOID_RCOND = 1e-10
_PARABOLOID_FLAT = 1e-9  # a paraboloid with q below this times the mean height is flat
_T_PLATEAU = 1e-6  # below this cap height the fit has stopped on the plateau (its centre free)
_T_STEEP = 0.3  # above this cap height (R < 1.8 a_f) the plateau-escape start is tried too


@nb.njit(cache=True, nogil=True, error_model="numpy", _nrt=False)
def small_fit(h, rho):  # pragma: no cover - compiled
    """Cap height for one- and two-pixel footprints (same rule as the base kernel)."""
    H = 0.0
    for v in h:
        H += v
    H /= h.size
    if H <= 0.0:
        return 0.0
    c = (1.0 - rho * rho - H * H) / (2.0 * H)
    if c <= 0.0:
        return 1.0
    return 1.0 / (math.sqrt(1.0 + c * c) + c)


@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH, error_model="numpy", _nrt=False)
def _para_sums(xs, ys, hs):  # pragma: no cover - compiled
    s1 = sx = sy = sq = sxx = sxy = syy = sxq = syq = sqq = 0.0
    sh = sxh = syh = sqh = 0.0
    for p in range(xs.size):
        x = xs[p]
        y = ys[p]
        h = hs[p]
        q = -(x * x + y * y)
        s1 += 1.0
        sx += x
        sy += y
        sq += q
        sxx += x * x
        sxy += x * y
        syy += y * y
        sxq += x * q
        syq += y * q
        sqq += q * q
        sh += h
        sxh += x * h
        syh += y * h
        sqh += q * h
    return s1, sx, sy, sq, sxx, sxy, syy, sxq, syq, sqq, sh, sxh, syh, sqh


@nb.njit(cache=True, nogil=True, error_model="numpy", _nrt=False)
def paraboloid_start(xs, ys, hs, M):  # pragma: no cover - compiled
    """Apex and cap height of the least-squares paraboloid ``h = w + u x + v y - q r^2``.

    Same rule as the base kernel (normal equations, partial pivoting, ``rcond`` test, ``q > 0``);
    the normal matrix from 14 vectorised sums. ``M`` is a (4, 5) work array.
    """
    s1, sx, sy, sq, sxx, sxy, syy, sxq, syq, sqq, sh, sxh, syh, sqh = _para_sums(xs, ys, hs)
    M[0, 0] = s1
    M[0, 1] = M[1, 0] = sx
    M[0, 2] = M[2, 0] = sy
    M[0, 3] = M[3, 0] = sq
    M[1, 1] = sxx
    M[1, 2] = M[2, 1] = sxy
    M[1, 3] = M[3, 1] = sxq
    M[2, 2] = syy
    M[2, 3] = M[3, 2] = syq
    M[3, 3] = sqq
    M[0, 4] = sh
    M[1, 4] = sxh
    M[2, 4] = syh
    M[3, 4] = sqh
    scale = max(max(M[0, 0], M[1, 1]), max(M[2, 2], M[3, 3]))
    for c in range(4):
        piv = c
        for r in range(c + 1, 4):
            if abs(M[r, c]) > abs(M[piv, c]):
                piv = r
        if abs(M[piv, c]) <= _PARABOLOID_RCOND * scale:
            return False, 0.0, 0.0, 0.0
        if piv != c:
            for j in range(5):
                tmp = M[c, j]
                M[c, j] = M[piv, j]
                M[piv, j] = tmp
        for r in range(c + 1, 4):
            f = M[r, c] / M[c, c]
            for j in range(c, 5):
                M[r, j] -= f * M[c, j]
    s3 = M[3, 4] / M[3, 3]
    s2 = (M[2, 4] - M[2, 3] * s3) / M[2, 2]
    s1_ = (M[1, 4] - M[1, 2] * s2 - M[1, 3] * s3) / M[1, 1]
    q = s3
    # a curvature at rounding level is no curvature: the footprint is flat (ties of quantised heights),
    # where the sign of q (and the start) would otherwise follow the rounding
    if not (q > _PARABOLOID_FLAT * abs(sh) / s1) or not math.isfinite(q):
        return False, 0.0, 0.0, 0.0
    x0 = s1_ / (2.0 * q)
    y0 = s2 / (2.0 * q)
    R = 1.0 / (2.0 * q)
    t0 = 1.0 if R <= 1.0 else 1.0 / (R + math.sqrt(R * R - 1.0))
    return True, x0, y0, min(t0, _T_MAX_START)



@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH, error_model="numpy", _nrt=False)
def plateau_escape(xs, ys, hs, wt):  # pragma: no cover - compiled
    """Start leaving the plateau ``t = 0`` if the plateau is not a minimum of Eq. 21.

    At ``t = 0`` the profile is the plane ``h = 0`` whatever the centre, so the iteration has no
    gradient in (x0, y0) there and can stop on the plateau with its centre where a cap would fit
    worse, while a cap centred elsewhere fits better. Near the plateau the cost is
    ``sum h^2 - 2 t g(c) + O(t^2)`` with ``g(c) = sum h (1 - |x - c|^2)``, largest at the
    h-weighted centroid ``c`` (inside the footprint's box, as ``h >= 0``). If ``g(c) > 0`` the
    plateau is not a minimum: returns ``(True, cx, cy, t)`` with the Gauss-Newton cap height
    ``t = g(c) / sum (1 - |x - c|^2)^2`` (at most the start cap limit); ``(False, ...)`` otherwise.
    """
    s = sx = sy = 0.0
    for p in range(xs.size):
        h = hs[p] * wt[p]
        s += h
        sx += h * xs[p]
        sy += h * ys[p]
    if not (s > 0.0):
        return False, 0.0, 0.0, 0.0
    cx = sx / s
    cy = sy / s
    g = 0.0
    a = 0.0
    for p in range(xs.size):
        ex = xs[p] - cx
        ey = ys[p] - cy
        j = (1.0 - ex * ex - ey * ey) * wt[p]
        g += j * hs[p]
        a += j * j
    if not (g > 0.0) or not (a > 0.0):
        return False, 0.0, 0.0, 0.0
    return True, cx, cy, min(g / a, _T_MAX_START)


@nb.njit(cache=True, nogil=True, error_model="numpy", _nrt=False)
def _search_on(xs, ys, hs, wt, lo0, lo1, hi0, hi1, t, cost, x0, y0, M, escaped, tA, xA, yA, awry_A, tB, xB, yB,
               awry_B, tE, xE, yE, awry_E):  # pragma: no cover - compiled
    """Where a fit from the starts is awry: the searches between Eq. 21's minima (fit_sphere)."""
    # Eq. 21 has several minima here: the plateau-escape start too, and every fit that is
    # awry searched on from by compass steps
    if not escaped:
        ok, px, py, pt = plateau_escape(xs, ys, hs, wt)
        if ok:
            tE, cE, xE, yE, _s = lm(xs, ys, hs, wt, px, py, pt, lo0, lo1, 0.0, hi0, hi1, 1.0, 0.0, 0.0, 0.0,
                                    False)
            awry_E = awry(xs, ys, wt, lo0, lo1, hi0, hi1, xE, yE, tE)
            if cE < cost:
                t, cost, x0, y0 = tE, cE, xE, yE
    for awry_k, tk, xk, yk in ((awry_E, tE, xE, yE), (awry_A, tA, xA, yA), (awry_B, tB, xB, yB)):
        if awry_k:
            t2, cost2, x2, y2 = pattern_search(xs, ys, hs, wt, xk, yk, tk, lo0, lo1, hi0, hi1)
            if cost2 < cost:
                t, cost, x0, y0 = t2, cost2, x2, y2
    # and a global search: the reference's grid (7 x 7 centres, 8 caps, its 5 best points), so
    # the fast path has every start the reference has, and finer ones (11 x 11 x 12 and
    # 15 x 15 x 16, 20 best points each) for minima in basins narrower than its spacing
    t, cost, x0, y0 = grid_search(xs, ys, hs, wt, lo0, lo1, hi0, hi1, t, cost, x0, y0, M, 7, 8, 5)
    t, cost, x0, y0 = grid_search(xs, ys, hs, wt, lo0, lo1, hi0, hi1, t, cost, x0, y0, M, 11, 12, GRID_KEEP)
    t, cost, x0, y0 = grid_search(xs, ys, hs, wt, lo0, lo1, hi0, hi1, t, cost, x0, y0, M, 15, 16, GRID_KEEP)
    return t, cost, x0, y0


@nb.njit(cache=True, nogil=True, error_model="numpy", _nrt=False)
def fit_sphere(xs, ys, hs, wt, n, hx, hy, M):  # pragma: no cover - compiled
    """Eq. 21 fit of one asperity (dimensionless data, as the base kernel's ``_fit_sphere``).

    ``xs, ys, hs, wt`` hold the ``n`` pixels (weight 1) followed by padding pixels of weight 0
    (and x = y = h = 0) up to a multiple of the SIMD width, so the per-pixel sums run as whole
    vectors (a scalar remainder loop cost ~20 ns per pixel, a full vector ~1 ns).
    Returns ``(t, cost, x0, y0)``. ``M`` is a (4, GRID_KEEP) work array.
    """
    if n <= 2:
        rho = 0.0
        if n == 2:
            rho = 0.5 * math.sqrt((xs[1] - xs[0]) ** 2 + (ys[1] - ys[0]) ** 2)
        t = small_fit(hs[:n], rho)
        return t, cost_at(xs, ys, hs, wt, 0.0, 0.0, t), 0.0, 0.0
    H = 0.0
    plateau = 0.0  # the cost of the plateau t = 0
    xmin = xmax = xs[0]
    ymin = ymax = ys[0]
    for p in range(n):
        H += hs[p]
        plateau += hs[p] * hs[p]
        v = xs[p]
        if v < xmin:
            xmin = v
        if v > xmax:
            xmax = v
        v = ys[p]
        if v < ymin:
            ymin = v
        if v > ymax:
            ymax = v
    H = 2.0 * H / n
    if H <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    lo0 = xmin - hx
    lo1 = ymin - hy
    hi0 = xmax + hx
    hi1 = ymax + hy
    t, cost, x0, y0, _s = lm(xs, ys, hs, wt, 0.0, 0.0, min(H, _T_MAX_START), lo0, lo1, 0.0, hi0, hi1, 1.0,
                             0.0, 0.0, 0.0, False)
    tA, xA, yA = t, x0, y0  # the fit from each start is kept to search on from, if awry
    awry_A = awry(xs, ys, wt, lo0, lo1, hi0, hi1, xA, yA, tA)
    awry_B = False
    tB = cB = xB = yB = 0.0
    if n >= _PARABOLOID_MIN_PIXELS:
        ok, px, py, pt = paraboloid_start(xs[:n], ys[:n], hs[:n], M)
        if ok:
            tB, cB, xB, yB, st = lm(xs, ys, hs, wt, px, py, pt, lo0, lo1, 0.0, hi0, hi1, 1.0, x0, y0, t, True)
            if st != 1:
                awry_B = awry(xs, ys, wt, lo0, lo1, hi0, hi1, xB, yB, tB)
                if cB < cost:
                    t, cost, x0, y0 = tB, cB, xB, yB
    # the plateau-escape start (the reference's third): where the fit stopped on (or
    # indistinguishably near) the plateau, where the centre is free; and where the sphere is steep
    # enough for other minima, with pixels outside it, to lie near (0.2 % of the families' fits)
    awry_E = escaped = False
    tE = xE = yE = 0.0
    if t < _T_PLATEAU or t > _T_STEEP:
        escaped = True
        ok, px, py, pt = plateau_escape(xs, ys, hs, wt)
        if ok:
            tE, cE, xE, yE, _s = lm(xs, ys, hs, wt, px, py, pt, lo0, lo1, 0.0, hi0, hi1, 1.0, 0.0, 0.0, 0.0, False)
            awry_E = awry(xs, ys, wt, lo0, lo1, hi0, hi1, xE, yE, tE)
            if t < _T_PLATEAU:
                here = over_plateau(xs, ys, hs, wt, x0, y0, t) if t > 0.0 else 0.0
                if tE > 0.0 and over_plateau(xs, ys, hs, wt, xE, yE, tE) < here:
                    t, cost, x0, y0 = tE, cE, xE, yE
            elif cE < cost:
                t, cost, x0, y0 = tE, cE, xE, yE
    if awry_A or awry_B or awry_E:  # (the best is one of these fits)
        t, cost, x0, y0 = _search_on(xs, ys, hs, wt, lo0, lo1, hi0, hi1, t, cost, x0, y0, M, escaped, tA, xA, yA,
                                     awry_A, tB, xB, yB, awry_B, tE, xE, yE, awry_E)
    # the plateau is always admissible; near it the two costs differ by less than their rounding,
    # so the difference is summed directly
    if t > 0.0 and plateau <= cost * (1.0 + 1e-9) and not over_plateau(xs, ys, hs, wt, x0, y0, t) < 0.0:
        return 0.0, cost_at(xs, ys, hs, wt, 0.0, 0.0, 0.0), 0.0, 0.0
    return t, cost, x0, y0



def fit_footprint(x, y, z, d, dx, dy):
    """The fast fit of one footprint in physical units, as the kernel fits it (tests, benchmarks).

    Same contract as ``fit_asperity`` of the literal reference (tests/contact/modified_dmt): ``x, y`` unwrapped
    pixel centres [m], ``z`` heights [m] (all ``>= d``), ``d`` the level, ``dx, dy`` the pixel
    size; returns ``(R, E)`` [m] (radius, inf for the plateau, and Eq. 23's rms fit error).
    """
    n = len(x)
    af = math.sqrt(n * dx * dy / math.pi)
    m = (n + _SIMD - 1) // _SIMD * _SIMD
    xs, ys, hs, wt = (np.zeros(m) for _ in range(4))
    xs[:n] = (x - np.mean(x)) / af
    ys[:n] = (y - np.mean(y)) / af
    hs[:n] = (np.asarray(z) - d) / af
    wt[:n] = 1.0
    t, cost, _x0, _y0 = fit_sphere(xs, ys, hs, wt, n, 0.5 * dx / af, 0.5 * dy / af, np.zeros((4, GRID_KEEP)))
    R = af * (1.0 + t * t) / (2.0 * t) if t > 0 else math.inf
    return R, math.sqrt(cost / n) * af
