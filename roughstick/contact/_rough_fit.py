"""The constrained sphere fit of Eqs. 19-21 for the rough-surface kernels (numba), by a projected
Levenberg-Marquardt iteration with an analytic Jacobian.

Split out of :mod:`roughstick.contact._rough_kernels` (whose docstring states the fit's
conventions) only to keep modules under 600 lines; the code is unchanged.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

__all__: list[str] = []

# Levenberg-Marquardt controls of the sphere fit (shared with nothing: the reference uses scipy).
_MAX_ITER = 200
_T_MAX_START = 0.999
_PARABOLOID_MIN_PIXELS = 5
_PARABOLOID_RCOND = 1e-10
# a rejected step below this (relative) ends the iteration: the cost differences are rounding
_STEP_NOISE = 1e-10
# the per-pixel sums of the fit may be reassociated (SIMD) and fused (FMA): about twice faster,
# the values change at rounding level only (no 'nnan'/'ninf'/'afn': NaN, inf and libm kept exact)
_FASTMATH = {"reassoc", "contract"}
# rows of the fit's work array (see fit_workspace): vectors of 3, matrices of 3 rows, paraboloid 4 x 5
_WS_P, _WS_G, _WS_Q, _WS_S, _WS_Y, _WS_SR, _WS_LO, _WS_HI, _WS_SOL = range(9)
_WS_A = 9
_WS_B = 12
_WS_L = 15
_WS_PARA = 18
_WS_ROWS = 22


@nb.njit(cache=True, nogil=True)
def _small_fit(h, rho):  # pragma: no cover - compiled
    """Cap height ``t`` for one- and two-pixel footprints (see module docstring).

    The sphere through the footprint circle whose height at distance ``rho`` from the centre
    equals the mean of ``h`` (all lengths in units of a_f), capped at the hemisphere ``t = 1``.
    """
    H = 0.0
    for v in h:
        H += v
    H /= h.size
    if H <= 0.0:
        return 0.0
    c = (1.0 - rho * rho - H * H) / (2.0 * H)  # depth of the sphere centre below the plane
    if c <= 0.0:
        return 1.0
    return 1.0 / (math.sqrt(1.0 + c * c) + c)  # t = R - c


@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH)
def _profile(rho2, t):  # pragma: no cover - compiled
    """Height above the contact plane of the constrained sphere of cap height ``t`` (Eq. 21).

    Dimensionless (lengths over a_f): ``R = (1 + t^2) / (2 t)``, centre ``c = (1 - t^2) / (2 t)``
    below the plane, height ``sqrt(R^2 - rho^2) - c`` written without cancellation; outside the
    sphere's projection (``rho > R``) the profile is taken at ``rho = R``, i.e. ``-c``.
    Returns ``(H, W)`` with ``W = 2 t sqrt(R^2 - rho^2)`` (0 outside the projection).
    """
    Q = 1.0 + t * t
    W2 = Q * Q - 4.0 * t * t * rho2
    if W2 > 0.0:
        W = math.sqrt(W2)
        return 2.0 * t * (1.0 - rho2) / (W + 1.0 - t * t), W
    if t > 0.0:
        return -(1.0 - t * t) / (2.0 * t), 0.0
    return 0.0, 0.0


@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH)
def _model_and_cost(xs, ys, hs, x0, y0, t):  # pragma: no cover - compiled
    """Sum of squared residuals of Eq. 21 (dimensionless, lengths in units of a_f)."""
    cost = 0.0
    for p in range(xs.size):
        dx = xs[p] - x0
        dy = ys[p] - y0
        Hm, _W = _profile(dx * dx + dy * dy, t)
        r = hs[p] - Hm
        cost += r * r
    return cost


@nb.njit(cache=True, nogil=True)
def _paraboloid_start(xs, ys, hs, M, sol):  # pragma: no cover - compiled
    """Second start of the fit: linear least squares ``h = w + u x + v y - q (x^2 + y^2)``.

    Returns ``(ok, x0, y0, t0)``: the paraboloid's apex and the cap height of the sphere of
    radius ``1 / (2 q)`` through the footprint circle (clipped to [0, 0.999]; the caller clips
    the apex to the footprint box); ``ok`` is False when the system is singular or the
    paraboloid is not a cap. ``M`` (4, 5) and ``sol`` (4,) are work arrays (no allocation).
    """
    n = xs.size
    M[:, :] = 0.0
    for p in range(n):
        g0 = 1.0
        g1 = xs[p]
        g2 = ys[p]
        g3 = -(xs[p] * xs[p] + ys[p] * ys[p])
        g = (g0, g1, g2, g3)
        for i in range(4):
            for j in range(4):
                M[i, j] += g[i] * g[j]
            M[i, 4] += g[i] * hs[p]
    scale = 0.0
    for i in range(4):
        scale = max(scale, M[i, i])
    # Gaussian elimination with partial pivoting
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
    sol[:] = 0.0
    for r in range(3, -1, -1):
        acc = M[r, 4]
        for j in range(r + 1, 4):
            acc -= M[r, j] * sol[j]
        sol[r] = acc / M[r, r]
    q = sol[3]
    if not (q > 0.0) or not math.isfinite(q):
        return False, 0.0, 0.0, 0.0
    x0 = sol[1] / (2.0 * q)
    y0 = sol[2] / (2.0 * q)
    R = 1.0 / (2.0 * q)
    t0 = 1.0 if R <= 1.0 else 1.0 / (R + math.sqrt(R * R - 1.0))
    return True, x0, y0, min(t0, _T_MAX_START)


def fit_workspace():
    """Work arrays of :func:`_fit_sphere` (allocated once per map, reused by every fit)."""
    return np.empty((_WS_ROWS, 5)), np.empty(3, np.int64), np.empty(3, np.bool_)



@nb.njit(cache=True, nogil=True)
def _search_box(xs, ys, hx, hy, ws):
    """Bounds of (x0, y0, t) for the fit: the centre within the footprint's bounding box grown by
    half a pixel (Eq. 21 asks for a centre inside the footprint), the cap height t in [0, 1]."""
    lo = ws[_WS_LO, :3]
    hi = ws[_WS_HI, :3]
    lo[0] = xs.min() - hx
    lo[1] = ys.min() - hy
    lo[2] = 0.0
    hi[0] = xs.max() + hx
    hi[1] = ys.max() + hy
    hi[2] = 1.0
    return lo, hi


@nb.njit(cache=True, nogil=True)
def _fit_sphere(xs, ys, hs, hx, hy, ws, iw, free):  # pragma: no cover - compiled
    """Constrained sphere fit of Eq. 21 on dimensionless data (lengths in units of a_f).

    ``xs, ys`` are pixel centres relative to the footprint centroid and ``hs`` the heights above
    the contact plane, all divided by the footprint radius a_f; ``hx, hy`` are half a pixel in
    the same unit. The unknowns are the centre ``(x0, y0)``, kept inside the footprint as Eq. 21
    asks (``X in Omega``; here its bounding box, half a pixel beyond the outer pixel centres),
    and the cap height ``t = delta / a_f`` in [0, 1] (the Hertz interference over the footprint
    radius; ``R = a_f (1 + t^2) / (2 t)``), a smooth parametrisation of Eq. 20 from the plateau
    (t = 0, R infinite) to the hemisphere (t = 1). Eq. 21 is not convex (steep asperities cut
    by the edge of a measured map especially), so two starts are refined and the better kept:
    the footprint centroid with the cap of twice the mean height, and the apex and curvature of
    the least-squares paraboloid. Returns ``(t, cost, x0, y0)``
    with ``cost`` the sum of squared dimensionless residuals. ``ws, iw, free`` come from
    :func:`fit_workspace` (no allocation inside the fit).
    """
    n = xs.size
    if n <= 2:
        rho = 0.0
        if n == 2:
            rho = 0.5 * math.sqrt((xs[1] - xs[0]) ** 2 + (ys[1] - ys[0]) ** 2)
        t = _small_fit(hs, rho)
        return t, _model_and_cost(xs, ys, hs, 0.0, 0.0, t), 0.0, 0.0
    H = 0.0
    for v in hs:
        H += v
    H = 2.0 * H / n
    if H <= 0.0:
        return 0.0, 0.0, 0.0, 0.0  # plateau exactly at the contact plane: t = 0 fits exactly
    lo, hi = _search_box(xs, ys, hx, hy, ws)
    t, cost, x0, y0, _c = _lm(xs, ys, hs, 0.0, 0.0, min(H, _T_MAX_START), lo, hi, ws, iw, free)
    if n >= _PARABOLOID_MIN_PIXELS:
        ok, px, py, pt = _paraboloid_start(xs, ys, hs, ws[_WS_PARA:_WS_PARA + 4, :], ws[_WS_SOL, :4])
        if ok:
            t2, cost2, x2, y2, _c = _lm(xs, ys, hs, px, py, pt, lo, hi, ws, iw, free)
            if cost2 < cost:
                return t2, cost2, x2, y2
    return t, cost, x0, y0


@nb.njit(cache=True, nogil=True)
def _fit_sphere_warm(xs, ys, hs, hx, hy, ws, iw, free, x0, y0, t0):  # pragma: no cover - compiled
    """The fit of :func:`_fit_sphere` refined from one given start ``(x0, y0, t0)`` (a warm start).

    Used for an asperity whose pixels are those of its fit at the previous (higher) distance:
    only the heights moved, by the change of d, so that fit's solution is a close start and
    the damped Newton iteration needs a few steps. Falls back to the two cold starts of
    :func:`_fit_sphere` for one- and two-pixel footprints, a plateau at the plane, or when the
    iteration does not converge. Eq. 21 is not convex: the warm start follows the local
    minimum of the previous level, which can differ from the better of the two cold starts
    (see docs/rough_contact.md).
    """
    n = xs.size
    if n <= 2:
        return _fit_sphere(xs, ys, hs, hx, hy, ws, iw, free)
    H = 0.0
    for v in hs:
        H += v
    if H <= 0.0:
        return _fit_sphere(xs, ys, hs, hx, hy, ws, iw, free)
    lo, hi = _search_box(xs, ys, hx, hy, ws)
    t, cost, x, y, conv = _lm(xs, ys, hs, x0, y0, t0, lo, hi, ws, iw, free)
    if conv:
        return t, cost, x, y
    return _fit_sphere(xs, ys, hs, hx, hy, ws, iw, free)


@nb.njit(cache=True, nogil=True, fastmath=_FASTMATH)
def _derivatives(xs, ys, hs, x0, y0, t):  # pragma: no cover - compiled
    """Cost, gradient and exact Hessian of ``sum (h - H)^2`` in ``(x0, y0, t)`` (Eq. 21).

    The residuals of Eq. 21 are not small where a sphere fits an asperity badly, so the
    Gauss-Newton matrix ``J^T J`` misses a large ``sum r d2H`` term (the centre of a flat cap is
    set by it); the full Hessian makes the Newton iteration converge quadratically. All
    expressions are written without cancellation for small ``t``. Returns
    ``(cost, g0, g1, g2, a00, a01, a02, a11, a12, a22)``: ``g = J^T r = -grad(cost) / 2`` and
    the upper triangle of ``Hessian(cost) / 2`` (scalars, so the caller keeps them in registers).
    """
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
            # outside the projection of the sphere: H = -c(t)
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
        r = hs[p] - Hm
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


@nb.njit(cache=True, nogil=True)
def _lm(xs, ys, hs, x0, y0, t, lo, hi, ws, iw, free):  # pragma: no cover - compiled
    """Damped Newton (Levenberg-Marquardt on the exact Hessian) within the box ``lo <= p <= hi``.

    ``p = (x0, y0, t)``. Active set: an unknown sitting on a bound with the descent direction
    pointing out stays there while the others move (its row and column of the damped matrix
    become the identity's and its right-hand side 0, which is the Cholesky solve of the free
    block exactly). The damping grows until the matrix is positive definite and the cost
    decreases, and shrinks after each success. Stops when the step is at rounding level.
    The state lives in scalars and the 3 x 3 Cholesky is unrolled (about 15 % of the S2A time
    went to the bookkeeping of work arrays); the arithmetic is that of the generic version
    operation for operation, so the results are the same bits. ``ws, iw, free`` are unused
    (kept for the callers' signature).
    """
    lam = 1e-3
    lo0 = lo[0]
    lo1 = lo[1]
    lo2 = lo[2]
    hi0 = hi[0]
    hi1 = hi[1]
    hi2 = hi[2]
    p0 = min(max(x0, lo0), hi0)
    p1 = min(max(y0, lo1), hi1)
    p2 = min(max(t, lo2), hi2)
    cost, g0, g1, g2, a00, a01, a02, a11, a12, a22 = _derivatives(xs, ys, hs, p0, p1, p2)
    small = False
    for _ in range(_MAX_ITER):
        f0 = not ((p0 <= lo0 and g0 < 0.0) or (p0 >= hi0 and g0 > 0.0))
        f1 = not ((p1 <= lo1 and g1 < 0.0) or (p1 >= hi1 and g1 > 0.0))
        f2 = not ((p2 <= lo2 and g2 < 0.0) or (p2 >= hi2 and g2 > 0.0))
        scale = max(abs(a00), abs(a11), abs(a22), 1e-300)
        improved = False
        small = False
        for _inner in range(80):
            # damped matrix restricted to the free unknowns (fixed ones: identity row, rhs 0)
            b00 = a00 + lam * max(abs(a00), 1e-12 * scale) if f0 else 1.0
            b11 = a11 + lam * max(abs(a11), 1e-12 * scale) if f1 else 1.0
            b22 = a22 + lam * max(abs(a22), 1e-12 * scale) if f2 else 1.0
            b01 = a01 if (f0 and f1) else 0.0
            b02 = a02 if (f0 and f2) else 0.0
            b12 = a12 if (f1 and f2) else 0.0
            r0 = g0 if f0 else 0.0
            r1 = g1 if f1 else 0.0
            r2 = g2 if f2 else 0.0
            # Cholesky, same operation order as a generic row-by-row factorisation
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
            step = abs(q0 - p0)
            step += abs(q1 - p1)
            step += abs(q2 - p2)
            rel = 1.0 + abs(p0) + abs(p1)
            if step <= 1e-14 * rel:
                small = True
                break
            nc = _model_and_cost(xs, ys, hs, q0, q1, q2)
            if nc > cost and step <= _STEP_NOISE * rel:
                small = True
                break
            if nc <= cost:
                p0 = q0
                p1 = q1
                p2 = q2
                cost, g0, g1, g2, a00, a01, a02, a11, a12, a22 = _derivatives(xs, ys, hs, p0, p1, p2)
                lam = lam / 10.0 if lam > 1e-15 else 0.0
                improved = True
                small = step <= 1e-13 * (1.0 + abs(p0) + abs(p1))
                break
            lam = max(lam * 10.0, 1e-12)
            if lam > 1e25:
                break
        if small or not improved:
            break
    return p2, cost, p0, p1, small


@nb.njit(cache=True, nogil=True)
def _fit_level(
    roots, start, members, vx, vy, zflat, order, d, dx, dy, xs, ys, hs, warm, pm, sol, fit, ws, iw,
    free,
):  # pragma: no cover - compiled
    """Fit every asperity of one level (Eqs. 19-21); ``fit[c] = (t, cost)`` for ``roots[c]``.

    Asperity ``c`` uses the slice ``start[r]:start[r + 1]`` of ``xs, ys, hs`` (disjoint slices:
    the fits are independent). A numba ``prange`` over them with per-thread work arrays gave
    bit-identical results but was 2.6x slower on S2A on this shared 2-core machine (thread
    wake-up at each of the 200 levels), so the fits run serially; maps run in parallel instead
    (dask, :mod:`roughstick.ensemble`).
    """
    nr = roots.size
    for c in range(nr):
        r = roots[c]
        a = start[r]
        m = start[r + 1] - a
        af = math.sqrt(m * (dx * dy) / math.pi)  # as in _hertz_levels, bit for bit
        mx = 0.0
        my = 0.0
        for t in range(m):
            j = members[a + t]
            ux = vx[j] if j != r else 0
            uy = vy[j] if j != r else 0
            xs[a + t] = ux * dx
            ys[a + t] = uy * dy
            hs[a + t] = zflat[order[j]] - d
            mx += xs[a + t]
            my += ys[a + t]
        mx /= m
        my /= m
        for t in range(a, a + m):
            xs[t] = (xs[t] - mx) / af
            ys[t] = (ys[t] - my) / af
            hs[t] = hs[t] / af
        hx = 0.5 * dx / af
        hy = 0.5 * dy / af
        X = xs[a : a + m]
        Y = ys[a : a + m]
        Z = hs[a : a + m]
        if warm and pm[r] == m:
            # same pixels as at the last fit (sets only grow): same centroid and a_f, the
            # data only shifted by the change of d; start from that fit's solution
            tt, cost, x0, y0 = _fit_sphere_warm(
                X, Y, Z, hx, hy, ws, iw, free, sol[r, 0], sol[r, 1], sol[r, 2]
            )
        else:
            tt, cost, x0, y0 = _fit_sphere(X, Y, Z, hx, hy, ws, iw, free)
        pm[r] = m
        sol[r, 0] = x0
        sol[r, 1] = y0
        sol[r, 2] = tt
        fit[c, 0] = tt
        fit[c, 1] = cost
