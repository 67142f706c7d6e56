"""Sphere fit of Eq. 21 for one asperity footprint: the compiled core of the rough-surface DMT.

Unknowns ``(x0, y0, t)``, ``t = delta / a_f`` in ``[0, 1]`` (see :mod:`._rough_kernels` for the
conventions shared with :mod:`._rough_reference`); a projected Levenberg-Marquardt iteration with
an analytic Jacobian, started from the least-squares paraboloid of the footprint (five pixels or
more) and the centroid, keeping the better. Two safeguards keep it from stopping where the
literal reference finds a better fit: a fit ending on the plateau ``t = 0`` (or below
``t = 1e-6``, where the cost cannot tell them apart) is restarted from
the h-weighted centroid when a cap there fits better (:func:`plateau_escape`; without it 2.0e-2
relative pressure differences on S2A crops, issue 12), and a fit leaving pixels outside its
sphere or its centre on the bound, where Eq. 21's cost is not smooth and has several minima, is
compared with a grid search (:func:`grid_search`; never triggered on the five surface families,
it is for steep asperities cut by the edge of a measured map). The plateau is always a
candidate. Per-pixel sums are vectorised over blocks of ``_SIMD`` pixels (the
footprint arrays are zero-padded with zero weight to a multiple of it).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

__all__ = ["fit_footprint", "fit_sphere", "small_fit", "cost_at", "derivs_at", "paraboloid_start", "plateau_escape", "over_plateau", "outside", "grid_search", "lm"]


_FASTMATH = {"reassoc", "contract"}
_SIMD = 8

_MAX_ITER = 200
_T_MAX_START = 0.999
_PARABOLOID_MIN_PIXELS = 5
_PARABOLOID_RCOND = 1e-10
_STOP = 1e-9
_STOP_LAMBDA = 1e-2
_SAME = 1e-7
_T_PLATEAU = 1e-6  # below this cap height the fit has stopped on the plateau (its centre free)
_GRID_CENTRES = 7  # the search where a fit leaves pixels outside its sphere: 7 x 7 centres,
_GRID_CAPS = 8  # 8 cap heights, the 5 best polished (M's 4 x 5 entries hold them)


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


@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH, error_model="numpy", _nrt=False, inline="always")
def _cap_height(rho2, QQ, ft2, t2, omt2, out):  # pragma: no cover - compiled
    """Height of the Eq. 21 cap at squared distance ``rho2`` from its centre (dimensionless,
    constants of the cap height t precomputed: Q^2, 4t^2, 2t, 1 - t^2); ``out`` outside it."""
    W2 = QQ - ft2 * rho2
    if W2 > 0.0:
        return t2 * (1.0 - rho2) / (math.sqrt(W2) + omt2)
    return out


@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH, error_model="numpy", _nrt=False)
def cost_at(xs, ys, hs, wt, x0, y0, t):  # pragma: no cover - compiled
    """Sum of squared residuals of Eq. 21 (dimensionless), the base kernel's profile."""
    Q = 1.0 + t * t
    QQ = Q * Q
    ft2 = 4.0 * t * t
    t2 = 2.0 * t
    omt2 = 1.0 - t * t
    out = -omt2 / t2 if t > 0.0 else 0.0
    cost = 0.0
    for p in range(xs.size):
        dx = xs[p] - x0
        dy = ys[p] - y0
        rho2 = dx * dx + dy * dy
        Hm = _cap_height(rho2, QQ, ft2, t2, omt2, out)
        r = (hs[p] - Hm) * wt[p]
        cost += r * r
    return cost


@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH, error_model="numpy", _nrt=False)
def derivs_at(xs, ys, hs, wt, x0, y0, t):  # pragma: no cover - compiled
    """Cost, ``J^T r`` and the upper triangle of the exact Hessian / 2 (base kernel's formulas)."""
    n = xs.size
    tt2 = t * t
    Q = 1.0 + tt2
    QQ = Q * Q
    ft2 = 4.0 * tt2
    t2 = 2.0 * t
    e8t3 = 8.0 * tt2 * t
    omt4 = 1.0 - tt2 * tt2
    omt2 = 1.0 - tt2
    cost = 0.0
    g0 = g1 = g2 = 0.0
    a00 = a01 = a02 = a11 = a12 = a22 = 0.0
    for p in range(n):
        ex = xs[p] - x0
        ey = ys[p] - y0
        rho2 = ex * ex + ey * ey
        W2 = QQ - ft2 * rho2
        if W2 > 0.0:
            W = math.sqrt(W2)
            iW = 1.0 / W
            Den = W + omt2
            iD = 1.0 / Den
            omr = 1.0 - rho2
            Hm = t2 * omr * iD
            j0 = t2 * ex * iW
            j1 = t2 * ey * iW
            j2 = 2.0 * Q * omr * iW * iD
            iW3 = iW * iW * iW
            c8 = e8t3 * iW3
            tw = t2 * iW
            hxx = -tw - c8 * ex * ex
            hyy = -tw - c8 * ey * ey
            hxy = -c8 * ex * ey
            c2 = 2.0 * omt4 * iW3
            hxt = c2 * ex
            hyt = c2 * ey
            dW = t2 * (Q - 2.0 * rho2) * iW
            dDen = dW - t2
            iWD = iW * iD
            htt = 2.0 * omr * (t2 * iWD - Q * (dW * Den + W * dDen) * iWD * iWD)
        elif t > 0.0:
            Hm = -omt2 / t2
            j0 = 0.0
            j1 = 0.0
            j2 = Q / (2.0 * tt2)
            hxx = hyy = hxy = hxt = hyt = 0.0
            htt = -1.0 / (tt2 * t)
        else:
            Hm = 0.0
            j0 = j1 = 0.0
            j2 = 1.0 - rho2
            hxx = hyy = hxy = hxt = hyt = htt = 0.0
        w = wt[p]
        r = (hs[p] - Hm) * w
        j0 *= w
        j1 *= w
        j2 *= w
        cost += r * r
        g0 += j0 * r
        g1 += j1 * r
        g2 += j2 * r
        a00 += j0 * j0 - r * hxx
        a01 += j0 * j1 - r * hxy
        a02 += j0 * j2 - r * hxt
        a11 += j1 * j1 - r * hyy
        a12 += j1 * j2 - r * hyt
        a22 += j2 * j2 - r * htt
    return cost, g0, g1, g2, a00, a01, a02, a11, a12, a22


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
    if not (q > 0.0) or not math.isfinite(q):
        return False, 0.0, 0.0, 0.0
    x0 = s1_ / (2.0 * q)
    y0 = s2 / (2.0 * q)
    R = 1.0 / (2.0 * q)
    t0 = 1.0 if R <= 1.0 else 1.0 / (R + math.sqrt(R * R - 1.0))
    return True, x0, y0, min(t0, _T_MAX_START)


@nb.njit(cache=True, nogil=True, error_model="numpy", _nrt=False)
def lm(xs, ys, hs, wt, x0, y0, t, lo0, lo1, lo2, hi0, hi1, hi2, r0_, r1_, r2_, use_ref):  # pragma: no cover
    """Damped Newton in the box (the base kernel's iteration; see the module docstring).

    Returns ``(t, cost, x0, y0, status)``; status 0 converged, 1 reached the reference point
    ``(r0_, r1_, r2_)`` (when ``use_ref``), 2 stopped without convergence.
    """
    lam = 1e-3
    p0 = min(max(x0, lo0), hi0)
    p1 = min(max(y0, lo1), hi1)
    p2 = min(max(t, lo2), hi2)
    cost, g0, g1, g2, a00, a01, a02, a11, a12, a22 = derivs_at(xs, ys, hs, wt, p0, p1, p2)
    for _ in range(_MAX_ITER):
        f0 = not ((p0 <= lo0 and g0 < 0.0) or (p0 >= hi0 and g0 > 0.0))
        f1 = not ((p1 <= lo1 and g1 < 0.0) or (p1 >= hi1 and g1 > 0.0))
        f2 = not ((p2 <= lo2 and g2 < 0.0) or (p2 >= hi2 and g2 > 0.0))
        scale = max(abs(a00), abs(a11), abs(a22), 1e-300)
        improved = False
        done = False
        for _inner in range(80):
            b00 = a00 + lam * max(abs(a00), 1e-12 * scale) if f0 else 1.0
            b11 = a11 + lam * max(abs(a11), 1e-12 * scale) if f1 else 1.0
            b22 = a22 + lam * max(abs(a22), 1e-12 * scale) if f2 else 1.0
            b01 = a01 if (f0 and f1) else 0.0
            b02 = a02 if (f0 and f2) else 0.0
            b12 = a12 if (f1 and f2) else 0.0
            r0 = g0 if f0 else 0.0
            r1 = g1 if f1 else 0.0
            r2 = g2 if f2 else 0.0
            if not (b00 > 0.0):
                lam = max(lam * 10.0, 1e-12)
                continue
            l00 = math.sqrt(b00)
            l10 = b01 / l00
            l20 = b02 / l00
            d11 = b11 - l10 * l10
            if not (d11 > 0.0):
                lam = max(lam * 10.0, 1e-12)
                continue
            l11 = math.sqrt(d11)
            l21 = (b12 - l20 * l10) / l11
            d22 = b22 - l20 * l20
            d22 = d22 - l21 * l21
            if not (d22 > 0.0):
                lam = max(lam * 10.0, 1e-12)
                continue
            l22 = math.sqrt(d22)
            y0_ = r0 / l00
            y1_ = (r1 - l10 * y0_) / l11
            y2_ = r2 - l20 * y0_
            y2_ = (y2_ - l21 * y1_) / l22
            s2 = y2_ / l22
            s1 = (y1_ - l21 * s2) / l11
            s0 = y0_ - l10 * s1
            s0 = (s0 - l20 * s2) / l00
            q0 = min(max(p0 + s0, lo0), hi0)
            q1 = min(max(p1 + s1, lo1), hi1)
            q2 = min(max(p2 + s2, lo2), hi2)
            step = abs(q0 - p0) + abs(q1 - p1) + abs(q2 - p2)
            rel = 1.0 + abs(p0) + abs(p1)
            if step <= 1e-14 * rel:
                done = True
                break
            if lam <= _STOP_LAMBDA and step <= _STOP * rel:
                # a (nearly) Newton step this small: the last one; its cost decides
                nc = cost_at(xs, ys, hs, wt, q0, q1, q2)
                if nc <= cost:
                    p0 = q0
                    p1 = q1
                    p2 = q2
                    cost = nc
                done = True
                break
            nc, h0, h1, h2, c00, c01, c02, c11, c12, c22 = derivs_at(xs, ys, hs, wt, q0, q1, q2)
            if nc <= cost:
                p0 = q0
                p1 = q1
                p2 = q2
                cost = nc
                g0 = h0
                g1 = h1
                g2 = h2
                a00 = c00
                a01 = c01
                a02 = c02
                a11 = c11
                a12 = c12
                a22 = c22
                lam = lam / 10.0 if lam > 1e-15 else 0.0
                improved = True
                break
            if step <= 1e-10 * rel:  # rejected at rounding level: converged
                done = True
                break
            lam = max(lam * 10.0, 1e-12)
            if lam > 1e25:
                break
        if done:
            return p2, cost, p0, p1, 0
        if not improved:
            return p2, cost, p0, p1, 2
        if use_ref and lam <= _STOP_LAMBDA:
            tol = _SAME * (1.0 + abs(r0_) + abs(r1_))
            if abs(p0 - r0_) <= tol and abs(p1 - r1_) <= tol and abs(p2 - r2_) <= tol:
                return p2, cost, p0, p1, 1
    return p2, cost, p0, p1, 2


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
def fit_sphere(xs, ys, hs, wt, n, hx, hy, M):  # pragma: no cover - compiled
    """Eq. 21 fit of one asperity (dimensionless data, as the base kernel's ``_fit_sphere``).

    ``xs, ys, hs, wt`` hold the ``n`` pixels (weight 1) followed by padding pixels of weight 0
    (and x = y = h = 0) up to a multiple of the SIMD width, so the per-pixel sums run as whole
    vectors (a scalar remainder loop cost ~20 ns per pixel, a full vector ~1 ns).
    Returns ``(t, cost, x0, y0)``. ``M`` is a (4, 5) work array.
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
    if n >= _PARABOLOID_MIN_PIXELS:
        ok, px, py, pt = paraboloid_start(xs[:n], ys[:n], hs[:n], M)
        if ok:
            t2, cost2, x2, y2, st = lm(xs, ys, hs, wt, px, py, pt, lo0, lo1, 0.0, hi0, hi1, 1.0, x0, y0, t, True)
            if st != 1 and cost2 < cost:
                t, cost, x0, y0 = t2, cost2, x2, y2
    if t < _T_PLATEAU:  # on (or indistinguishably near) the plateau, where the centre is free
        ok, px, py, pt = plateau_escape(xs, ys, hs, wt)
        if ok:
            t2, cost2, x2, y2, _s = lm(xs, ys, hs, wt, px, py, pt, lo0, lo1, 0.0, hi0, hi1, 1.0, 0.0, 0.0, 0.0,
                                       False)
            here = over_plateau(xs, ys, hs, wt, x0, y0, t) if t > 0.0 else 0.0
            if t2 > 0.0 and over_plateau(xs, ys, hs, wt, x2, y2, t2) < here:
                t, cost, x0, y0 = t2, cost2, x2, y2
    if t > 0.0:
        on_bound = x0 <= lo0 or x0 >= hi0 or y0 <= lo1 or y0 >= hi1
        # no pixel can be outside a sphere wider than the box seen from its centre (most fits)
        ex = max(x0 - lo0, hi0 - x0)
        ey = max(y0 - lo1, hi1 - y0)
        R = (1.0 + t * t) / (2.0 * t)
        if on_bound or (R * R < ex * ex + ey * ey and outside(xs, ys, wt, x0, y0, t)):
            t, cost, x0, y0 = grid_search(xs, ys, hs, wt, lo0, lo1, hi0, hi1, t, cost, x0, y0, M)
    # the plateau is always admissible; near it the two costs differ by less than their rounding,
    # so the difference is summed directly
    if t > 0.0 and plateau <= cost * (1.0 + 1e-9) and not over_plateau(xs, ys, hs, wt, x0, y0, t) < 0.0:
        return 0.0, cost_at(xs, ys, hs, wt, 0.0, 0.0, 0.0), 0.0, 0.0
    return t, cost, x0, y0


@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH, error_model="numpy", _nrt=False)
def over_plateau(xs, ys, hs, wt, x0, y0, t):  # pragma: no cover - compiled
    """Cost of the cap (x0, y0, t) minus the plateau's, ``sum Hm (Hm - 2 h)``, without the
    cancellation of two nearly equal sums of squares (a cap of t ~ 1e-6 gains ~1e-12 of them)."""
    Q = 1.0 + t * t
    QQ = Q * Q
    ft2 = 4.0 * t * t
    t2 = 2.0 * t
    omt2 = 1.0 - t * t
    out = -omt2 / t2
    diff = 0.0
    for p in range(xs.size):
        dx = xs[p] - x0
        dy = ys[p] - y0
        rho2 = dx * dx + dy * dy
        Hm = _cap_height(rho2, QQ, ft2, t2, omt2, out)
        diff += Hm * (Hm - 2.0 * hs[p]) * wt[p]
    return diff


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



def fit_footprint(x, y, z, d, dx, dy):
    """The fast fit of one footprint in physical units, as the kernel fits it (tests, benchmarks).

    Same contract as :func:`roughstick.contact._rough_reference.fit_asperity`: ``x, y`` unwrapped
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
    t, cost, _x0, _y0 = fit_sphere(xs, ys, hs, wt, n, 0.5 * dx / af, 0.5 * dy / af, np.zeros((4, 5)))
    R = af * (1.0 + t * t) / (2.0 * t) if t > 0 else math.inf
    return R, math.sqrt(cost / n) * af
