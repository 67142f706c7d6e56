"""The cost of Eq. 21 for one asperity footprint and its local minimiser (compiled).

Unknowns ``(x0, y0, t)``, ``t = delta / a_f`` in ``[0, 1]`` (see :mod:`._controller` for the
conventions shared with the literal reference of the tests). :func:`lm` is a projected Levenberg-Marquardt
iteration (damped Newton with the exact Hessian: the residuals of Eq. 21 are not small, so
Gauss-Newton's ``J^T J`` misses a large ``sum r grad^2 H`` term and crawls), bounds by an active
set. The starts and the search between local minima are in :mod:`._fit` and
:mod:`._search`. Per-pixel sums are vectorised over blocks of SIMD pixels (the footprint
arrays are zero-padded with zero weight to a multiple of the width).
"""

from __future__ import annotations

import math

import numba as nb

__all__ = ["cost_at", "derivs_at", "lm", "over_plateau"]


_FASTMATH = {"reassoc", "contract"}
_MAX_ITER = 200
_STOP = 1e-9
_STOP_LAMBDA = 1e-2
_SAME = 1e-7


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
