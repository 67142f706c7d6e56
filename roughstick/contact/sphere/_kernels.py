r"""Plain-numpy SI kernels of the sphere-on-flat contact models (no xarray).

Every kernel broadcasts its array arguments, works elementwise and returns float arrays.
Conventions: ``delta`` is the interference [m] (> 0 overlap of the undeformed profiles, < 0 a
gap between them), forces are in N and positive when repulsive, ``K`` is the paper's
:math:`K = \tfrac43 E^*` [Pa], ``sigma0`` >= 0 the Dugdale (Laplace) stress [Pa] and ``h0`` its
range [m] (capillarity: :math:`\sigma_0 = |\Delta P|`, :math:`h_0 = h_{water}`), so that the work of
adhesion is :math:`w = \sigma_0 h_0`.

Dimensionless variables of Maugis (1992) used below:

.. math::

    A = a\,(\pi w R^2/K)^{-1/3},\quad C = c\,(\pi w R^2/K)^{-1/3},\quad
    \Delta = \delta\,(\pi^2 w^2 R/K^2)^{-1/3},\quad \bar P = F/(\pi w R),\quad
    \lambda = 2\sigma_0 (\pi w K^2/R)^{-1/3}\ \text{(Eq. 7)},

and the contact branch is parametrised by :math:`\varphi = \arccos(a/c) \in (0, \pi/2)`
(:math:`m = c/a = \sec\varphi`), which turns Maugis' equations into closed forms of
:math:`\varphi`. Kim's non-contact branch (:math:`a = 0`) is parametrised by :math:`C`.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "MODELS",
    "sphere_force_kernel",
    "sphere_state_kernel",
    "transition_parameter_kernel",
]
# the adhesive-energy kernels (work to separate) are in _sphere_energy.py

MODELS = ("hertz", "jkr", "dmt", "maugis", "modified_dmt")
BRANCHES = ("retraction", "approach")

_HALF_PI = 0.5 * np.pi


# --------------------------------------------------------------------------------------------
# auxiliary functions of phi = arccos(1/m) (closed forms with series near 0)
# --------------------------------------------------------------------------------------------
def _sin_minus_xcos(x):
    """sin(x) - x cos(x) without cancellation (series for x < 1)."""
    x = np.asarray(x, dtype=float)
    x2 = x * x
    # sum_k (-1)^(k+1) 2k x^(2k+1) / (2k+1)!, k = 1..9 (error < 1e-17 relative for x < 1)
    series = np.zeros_like(x)
    for k in range(9, 0, -1):
        coef = (-1) ** (k + 1) * 2 * k / math.factorial(2 * k + 1)
        series = series * x2 + coef
    series = series * x2 * x
    with np.errstate(all="ignore"):
        full = np.sin(x) - x * np.cos(x)
    return np.where(x < 1.0, series, full)


def _X(phi):
    r""":math:`\sqrt{m^2-1} + (m^2-2)\arccos(1/m)` with :math:`m = \sec\varphi` (Hertz gap shape).

    Written as :math:`(\sin 2\varphi - 2\varphi\cos 2\varphi)/(2\cos^2\varphi)` to avoid the
    cancellation at small :math:`\varphi` (where it tends to :math:`4\varphi^3/3`).
    """
    phi = np.asarray(phi, dtype=float)
    with np.errstate(all="ignore"):
        c = np.cos(phi)
        return _sin_minus_xcos(2.0 * phi) / (2.0 * c * c)


def _Y(phi):
    r""":math:`\sqrt{m^2-1}\arccos(1/m) - m + 1` with :math:`m = \sec\varphi`.

    Written as :math:`(\varphi\sin\varphi - 2\sin^2(\varphi/2))/\cos\varphi` (no cancellation).
    """
    phi = np.asarray(phi, dtype=float)
    with np.errstate(all="ignore"):
        sh = np.sin(0.5 * phi)
        return (phi * np.sin(phi) - 2.0 * sh * sh) / np.cos(phi)


def _illinois(fun, lo, hi, flo, fhi, *, xtol=1e-14, maxiter=100):
    """Vectorised bracketed root finder (regula falsi with the Illinois modification).

    ``fun(x, idx)`` evaluates the function at ``x`` for the elements ``idx``; ``flo`` and
    ``fhi`` must have opposite signs (or be zero). Superlinear, never leaves the bracket; only
    unconverged elements are evaluated. Returns the root estimate.
    """
    lo = np.array(lo, dtype=float)
    hi = np.array(hi, dtype=float)
    flo = np.array(flo, dtype=float)
    fhi = np.array(fhi, dtype=float)
    x = np.where(flo == 0, lo, np.where(fhi == 0, hi, 0.5 * (lo + hi)))
    active = np.nonzero((flo != 0) & (fhi != 0) & np.isfinite(flo) & np.isfinite(fhi))[0]
    side = np.zeros(lo.shape, dtype=np.int8)
    for it in range(maxiter):
        if active.size == 0:
            break
        a, b, fa, fb = lo[active], hi[active], flo[active], fhi[active]
        with np.errstate(all="ignore"):
            xr = (a * fb - b * fa) / (fb - fa)
        # fall back to bisection when the secant misbehaves, and every 8th step
        bad = ~((xr > np.minimum(a, b)) & (xr < np.maximum(a, b)))
        if it % 8 == 7:
            bad[:] = True
        xr = np.where(bad, 0.5 * (a + b), xr)
        fr = fun(xr, active)
        x[active] = xr
        same_lo = np.sign(fr) == np.sign(fa)
        sd = side[active]
        # replace the end with the same sign; halve the other end's f if it was kept twice
        new_lo = np.where(same_lo, xr, a)
        new_hi = np.where(same_lo, b, xr)
        new_flo = np.where(same_lo, fr, np.where(sd == -1, 0.5 * fa, fa))
        new_fhi = np.where(same_lo, np.where(sd == 1, 0.5 * fb, fb), fr)
        side[active] = np.where(same_lo, 1, -1)
        lo[active], hi[active], flo[active], fhi[active] = new_lo, new_hi, new_flo, new_fhi
        done = (fr == 0) | (np.abs(new_hi - new_lo) <= xtol * (1.0 + np.abs(xr)))
        active = active[~done]
    return x


# --------------------------------------------------------------------------------------------
# Hertz and the modified DMT (closed forms)
# --------------------------------------------------------------------------------------------
def hertz_force(delta, radius, K):
    r"""Hertz force :math:`F = K\sqrt{R}\,\delta^{3/2}` for :math:`\delta > 0`, else 0 (Eqs. 10-11)."""
    delta = np.asarray(delta, dtype=float)
    dpos = np.where(delta > 0, delta, 0.0)
    out = K * np.sqrt(radius) * dpos * np.sqrt(dpos)
    return np.where(np.isnan(delta), np.nan, out)


def modified_dmt_force(delta, radius, K, sigma0, h0):
    r"""Modified DMT force of Eqs. 8-11 (sphere, exact cap geometry for the water radius).

    .. math::

        F = F_r - \sigma_0 \pi\,[R^2 - (R-\delta-h_0)^2 - a^2],\qquad a^2 = R\delta,\quad
        F_r = K\sqrt{R}\,\delta^{3/2}

    for :math:`\delta > 0`; for :math:`-h_0 < \delta \le 0` only the water term with
    :math:`a = 0`; zero below :math:`-h_0`. ``c`` is capped at ``R`` (water cannot wet beyond the
    sphere's equator).
    """
    delta = np.asarray(delta, dtype=float)
    s = np.minimum(delta + h0, radius)  # height of the wetted cap, at most R
    c2 = np.where(s > 0, 2.0 * radius * s - s * s, 0.0)
    a2 = np.where(delta > 0, radius * delta, 0.0)
    return hertz_force(delta, radius, K) - sigma0 * np.pi * np.maximum(c2 - a2, 0.0)


# --------------------------------------------------------------------------------------------
# DMT: Hertz + Dugdale stress on the Hertz-deformed gap
# --------------------------------------------------------------------------------------------
def _sigmoid(u):
    """Logistic function without overflow."""
    e = np.exp(-np.abs(u))
    return np.where(u >= 0, 1.0 / (1.0 + e), e / (1.0 + e))


def _solve_X(target):
    """Solve ``_X(phi) = target`` (target > 0) for phi in (0, pi/2).

    Newton on ``log X`` in the logit variable ``u = log(phi / (pi/2 - phi))``, in which
    ``log X`` is close to linear at both ends (3u for small phi, 2u near pi/2): 4-6 iterations
    from the asymptotic start. Relative accuracy of X about 1e-15 for targets in 1e-12..1e6.
    """
    target = np.asarray(target, dtype=float)
    shape = target.shape
    target = target.ravel()
    with np.errstate(all="ignore"):
        lt = np.log(target)
        # asymptotic starts: X ~ 4 phi^3 / 3 (small phi); X ~ pi / (2 eps^2) near pi/2
        phi_s = np.cbrt(0.75 * target)
        eps_b = np.sqrt(np.pi / (2.0 * target))
        phi0 = np.where(target < 1.0, np.minimum(phi_s, 1.0), _HALF_PI - np.minimum(eps_b, 0.5))
        u = np.log(phi0 / (_HALF_PI - phi0))
        u = np.where(np.isfinite(lt), u, np.nan)
        active = np.nonzero(np.isfinite(u))[0]
        for _ in range(40):
            if active.size == 0:
                break
            ua = u[active]
            sig = _sigmoid(ua)
            phi = _HALF_PI * sig
            X = _X(phi)
            t = np.tan(phi)
            dX = 2 * t * t + 2 * phi * t / np.cos(phi) ** 2
            step = (np.log(X) - lt[active]) / (dX / X * phi * (1.0 - sig))
            step = np.clip(step, -2.0, 2.0)
            u[active] = ua - step
            # quadratic convergence: once the step is below 1e-8 the error is ~1e-16
            active = active[~(np.abs(step) < 1e-8) & np.isfinite(step)]
        phi = _HALF_PI * _sigmoid(u)
        phi = np.where(target == np.inf, _HALF_PI, np.where(target == 0, 0.0, phi))
    return phi.reshape(shape)


def dmt_force(delta, radius, K, sigma0, h0, *, outer="sphere", return_state=False):
    r"""DMT force: Hertz plus the Dugdale stress :math:`\sigma_0` where the Hertz gap is below :math:`h_0`.

    In contact (:math:`\delta > 0`) the adhesive radius ``c`` follows from the gap of a
    Hertz-deformed paraboloid outside the contact (Johnson 1985, Eq. 3.42b),

    .. math::

        g(r) = \frac{a^2}{\pi R}\Big[\sqrt{m^2-1} + (m^2-2)\arccos\frac1m\Big] = h_0,
        \qquad m = c/a,\quad a^2 = R\delta,

    and :math:`F = K a^3/R - \sigma_0\pi(c^2 - a^2)`. Out of contact (:math:`-h_0<\delta\le0`) the
    bodies are undeformed: ``outer="sphere"`` uses the cap :math:`c^2 = 2R s - s^2`,
    :math:`s = \delta + h_0` (as Eq. 8), ``outer="paraboloid"`` uses :math:`c^2 = 2Rs`.
    """
    delta, radius, K, sigma0, h0 = np.broadcast_arrays(
        *(np.asarray(v, float) for v in (delta, radius, K, sigma0, h0))
    )
    with np.errstate(all="ignore"):
        dpos = np.where(delta > 0, delta, np.nan)
        phi = _solve_X(np.pi * h0 / dpos)
        a2 = radius * dpos
        c2_in = a2 / np.cos(phi) ** 2
        s = np.minimum(delta + h0, radius)
        if outer == "sphere":
            c2_out = np.where(s > 0, 2 * radius * s - s * s, 0.0)
        else:
            c2_out = np.where(s > 0, 2 * radius * s, 0.0)
        ann_in = a2 * np.tan(phi) ** 2
        inside = delta > 0
        annulus = np.where(inside, ann_in, c2_out)
        force = hertz_force(delta, radius, K) - sigma0 * np.pi * annulus
        force = np.where(np.isnan(delta), np.nan, force)
    if not return_state:
        return force
    a = np.where(inside, np.sqrt(np.where(inside, a2, 0.0)), 0.0)
    c = np.sqrt(np.where(inside, c2_in, c2_out))
    return force, np.where(np.isnan(delta), np.nan, a), np.where(np.isnan(delta), np.nan, c)


# --------------------------------------------------------------------------------------------
# JKR (given w)
# --------------------------------------------------------------------------------------------
_JKR_A_MIN = 6.0 ** (-1.0 / 3.0)  # dimensionless contact radius at the displacement-control jump-off
_JKR_D_MIN = -3.0 * 6.0 ** (-2.0 / 3.0)


def _jkr_dimless(Delta, branch):
    """Solve JKR Delta = A^2 - (2/3) sqrt(6 A) on the stable branch A >= 6^(-1/3)."""
    Delta = np.asarray(Delta, float)
    with np.errstate(all="ignore"):
        # s = sqrt(A): g(s) = s^4 - (2/3) sqrt(6) s - Delta, increasing for s >= s_min
        k = 2.0 / 3.0 * np.sqrt(6.0)
        s_min = np.sqrt(_JKR_A_MIN)
        ok = Delta >= _JKR_D_MIN
        # start above the root: s^4 >= Delta + k s  ->  guess from the dominant term
        s = np.maximum(np.power(np.maximum(Delta, 0) + k * 2.0, 0.25), np.cbrt(k) + 0.5)
        s = np.maximum(s, np.power(np.abs(Delta), 0.25) + 1.0)
        for _ in range(100):
            g = s**4 - k * s - Delta
            dg = 4 * s**3 - k
            new = np.maximum(s - g / dg, s_min)
            if np.all((np.abs(new - s) <= 1e-14 * s) | ~ok):
                s = new
                break
            s = new
        A = s * s
        P = A**3 - np.sqrt(6.0 * A**3)
        P = np.where(ok, P, 0.0)
        A = np.where(ok, A, 0.0)
        if branch == "approach":
            P = np.where(Delta < 0, 0.0, P)
            A = np.where(Delta < 0, 0.0, A)
    return P, A


def jkr_force(delta, radius, K, w, *, branch="retraction", return_state=False):
    r"""JKR force under displacement control (stable branch, Johnson-Kendall-Roberts 1971).

    .. math::

        F = \frac{K a^3}{R} - \sqrt{6\pi w K a^3},\qquad
        \delta = \frac{a^2}{R} - \frac23\sqrt{\frac{6\pi w a}{K}}

    Only the branch with :math:`d\delta/da > 0` is stable under displacement control. On
    ``branch="retraction"`` the sphere stays attached down to
    :math:`\delta_{min} = -3\cdot 6^{-2/3}(\pi^2w^2R/K^2)^{1/3}` and the force is zero below;
    on ``"approach"`` it is zero until :math:`\delta = 0`.
    """
    delta, radius = np.broadcast_arrays(np.asarray(delta, float), np.asarray(radius, float))
    w = np.asarray(w, float)
    with np.errstate(all="ignore"):
        ld = np.cbrt(np.pi**2 * w**2 * radius / K**2)
        la = np.cbrt(np.pi * w * radius**2 / K)
        P, A = _jkr_dimless(delta / ld, branch)
        force = P * np.pi * w * radius
        a = A * la
    hz = w <= 0
    if np.any(hz):
        force = np.where(hz, hertz_force(delta, radius, K), force)
        a = np.where(hz, np.sqrt(np.maximum(radius * delta, 0.0)), a)
    nan = np.isnan(delta)
    force = np.where(nan, np.nan, force)
    if return_state:
        return force, np.where(nan, np.nan, a), np.where(nan, np.nan, a)
    return force


# --------------------------------------------------------------------------------------------
# Maugis-Dugdale with Kim's non-contact extension
# --------------------------------------------------------------------------------------------
def _maugis_A(phi, lam):
    """Contact radius A solving Maugis' Eq. (1) for given phi (closed-form quadratic root)."""
    X = _X(phi)
    b = 4.0 / 3.0 * lam * lam * _Y(phi)
    return 2.0 / (b + np.sqrt(b * b + 2.0 * lam * X))


def _maugis_contact(phi, lam):
    """(Delta, P, A, C) on Maugis' contact branch at parameter phi."""
    with np.errstate(all="ignore"):
        A = _maugis_A(phi, lam)
        t = np.tan(phi)
        sec2 = 1.0 / np.cos(phi) ** 2
        Delta = A * A - 4.0 / 3.0 * lam * A * t
        P = A**3 - lam * A * A * (t + phi * sec2)
        C = A * np.sqrt(sec2)
    return Delta, P, A, C


def _kim_constants(lam):
    """Junction radius C_j (a = 0 on the contact branch), Kim's C*, Delta at C_j and at C*."""
    lam = np.asarray(lam, float)
    # pi lam C^2/4 + (4 lam^2/3)(pi/2 - 1) C - 1 = 0
    qa = np.pi * lam / 4.0
    qb = 4.0 / 3.0 * lam * lam * (_HALF_PI - 1.0)
    Cj = 2.0 / (qb + np.sqrt(qb * qb + 4.0 * qa))
    Cs = 8.0 * lam / (3.0 * np.pi)
    Dj = -4.0 / 3.0 * lam * Cj
    Dstar = -0.5 * Cs * Cs - 2.0 / (np.pi * lam)
    return Cj, Cs, Dj, Dstar


def _kim_delta(C, lam):
    """Kim's non-contact branch: Delta(C) = C^2/2 - 8 lam C/(3 pi) - 2/(pi lam)."""
    return 0.5 * C * C - 8.0 * lam * C / (3.0 * np.pi) - 2.0 / (np.pi * lam)


def _maugis_phi_min(lam, n_iter=80):
    """phi of the minimum of Delta on the contact branch (golden section in log phi).

    Only used where the minimum is on the contact branch (C* >= C_j, i.e. lam above ~0.94).
    """
    lam = np.asarray(lam, float)
    lo = np.log(np.full(lam.shape, 1e-9))
    hi = np.log(np.full(lam.shape, _HALF_PI * (1 - 1e-12)))
    g = (np.sqrt(5.0) - 1.0) / 2.0
    x1 = hi - g * (hi - lo)
    x2 = lo + g * (hi - lo)
    f1 = _maugis_contact(np.exp(x1), lam)[0]
    f2 = _maugis_contact(np.exp(x2), lam)[0]
    for _ in range(n_iter):
        left = f1 < f2
        hi = np.where(left, x2, hi)
        lo = np.where(left, lo, x1)
        x_keep = np.where(left, x1, x2)
        f_keep = np.where(left, f1, f2)
        x_new = np.where(left, hi - g * (hi - lo), lo + g * (hi - lo))
        f_new = _maugis_contact(np.exp(x_new), lam)[0]
        x1 = np.where(left, x_new, x_keep)
        f1 = np.where(left, f_new, f_keep)
        x2 = np.where(left, x_keep, x_new)
        f2 = np.where(left, f_keep, f_new)
    return np.exp(0.5 * (lo + hi))


def _maugis_dimless(Delta, lam, branch="retraction"):
    """Dimensionless Maugis-Kim solution (P, A, C) at interference Delta on the chosen branch.

    The curve Delta(s) along Kim's branch (C from 0 to C_j) then the contact branch (phi from
    pi/2 to 0) falls to one minimum and then rises. ``retraction`` returns the rising part for
    Delta above the minimum (P = 0 below: the sphere has jumped off); ``approach`` returns the
    same states but P = 0 below Delta = -2/(pi lam) (gap at the apex larger than h0).
    """
    Delta, lam = np.broadcast_arrays(np.asarray(Delta, float), np.asarray(lam, float))
    shape = Delta.shape
    Delta = Delta.ravel()
    lam = lam.ravel()
    P = np.zeros(Delta.shape)
    A = np.zeros(Delta.shape)
    C = np.zeros(Delta.shape)
    with np.errstate(all="ignore"):
        Cj, Cs, Dj, Dstar = _kim_constants(lam)
        kim_min = Cs < Cj  # minimum of Delta lies on Kim's branch
        # -- Kim's branch (stable root) ------------------------------------------------------
        on_kim = kim_min & (Delta >= Dstar) & (Delta <= Dj)
        Ck = Cs + np.sqrt(np.maximum(Cs * Cs + 2.0 * (Delta + 2.0 / (np.pi * lam)), 0.0))
        P = np.where(on_kim, -0.5 * np.pi * lam * Ck * Ck, P)
        C = np.where(on_kim, Ck, C)
        # -- contact branch ------------------------------------------------------------------
        phi_hi = np.full(Delta.shape, _HALF_PI)
        need_min = ~kim_min & np.isfinite(Delta) & np.isfinite(lam)
        D_floor = np.where(kim_min, Dj, np.nan)
        if np.any(need_min):
            idx = np.nonzero(need_min)[0]
            lam_u, inv = np.unique(lam[idx], return_inverse=True)
            pm = _maugis_phi_min(lam_u)
            phi_hi[idx] = pm[inv]
            D_floor[idx] = _maugis_contact(pm, lam_u)[0][inv]
        on_contact = Delta > D_floor
        idx = np.nonzero(on_contact)[0]
        if idx.size:
            d = Delta[idx]
            lm = lam[idx]
            hi = phi_hi[idx].copy()
            # lower bracket: deep Hertz-like contact Delta ~ A^2 ~ 3/(2 lam phi^3)
            lo = np.minimum(0.5 * np.cbrt(1.5 / (lm * np.maximum(d, 1e-300))), 0.5 * hi)
            for _ in range(200):
                bad = _maugis_contact(lo, lm)[0] < d
                if not np.any(bad):
                    break
                lo = np.where(bad, lo * 0.25, lo)
            # Illinois in log(phi): Delta decreases with phi on [lo, hi]
            llo = np.log(lo)
            lhi = np.log(hi)
            f_lo = _maugis_contact(lo, lm)[0] - d
            f_hi = _maugis_contact(hi, lm)[0] - d

            def fun(x, sel):
                return _maugis_contact(np.exp(x), lm[sel])[0] - d[sel]

            root = _illinois(fun, llo, lhi, f_lo, f_hi, xtol=1e-15)
            _, Pc, Ac, Cc = _maugis_contact(np.exp(root), lm)
            P[idx] = Pc
            A[idx] = Ac
            C[idx] = Cc
        if branch == "approach":
            off = Delta < -2.0 / (np.pi * lam)
            P = np.where(off, 0.0, P)
            A = np.where(off, 0.0, A)
            C = np.where(off, 0.0, C)
        nan = np.isnan(Delta) | np.isnan(lam)
        P = np.where(nan, np.nan, P)
        A = np.where(nan, np.nan, A)
        C = np.where(nan, np.nan, C)
    return P.reshape(shape), A.reshape(shape), C.reshape(shape)


def transition_parameter_kernel(radius, K, sigma0, h0):
    r"""Maugis' :math:`\lambda = 2\sigma_0/(\pi w K^2/R)^{1/3}` with :math:`w = \sigma_0 h_0` (Eq. 7)."""
    w = np.asarray(sigma0, float) * np.asarray(h0, float)
    with np.errstate(all="ignore"):
        return 2.0 * np.asarray(sigma0, float) / np.cbrt(np.pi * w * K**2 / np.asarray(radius, float))


def maugis_force(delta, radius, K, sigma0, h0, *, branch="retraction", return_state=False):
    r"""Maugis-Dugdale force with Kim's non-contact extension, under displacement control.

    See the module docstring for the dimensionless variables. Contact branch (Maugis 1992):

    .. math::

        \frac{\lambda A^2}{2}\Big[\sqrt{m^2-1} + (m^2-2)\arccos\frac1m\Big]
        + \frac{4\lambda^2 A}{3}\Big[\sqrt{m^2-1}\arccos\frac1m - m + 1\Big] = 1,

        \bar P = A^3 - \lambda A^2\Big[\sqrt{m^2-1} + m^2\arccos\frac1m\Big],\qquad
        \Delta = A^2 - \frac43 A\lambda\sqrt{m^2-1}.

    Non-contact branch (a = 0, Kim et al.): uniform tension :math:`\sigma_0` on :math:`r < c`,
    gap :math:`h_0` at :math:`r=c`:

    .. math:: \bar P = -\frac{\pi\lambda C^2}{2},\qquad
              \Delta = \frac{C^2}{2} - \frac{8\lambda C}{3\pi} - \frac{2}{\pi\lambda}.
    """
    delta, radius = np.broadcast_arrays(np.asarray(delta, float), np.asarray(radius, float))
    sigma0 = np.asarray(sigma0, float)
    h0 = np.asarray(h0, float)
    w = sigma0 * h0
    with np.errstate(all="ignore"):
        lam = transition_parameter_kernel(radius, K, sigma0, h0)
        ld = np.cbrt(np.pi**2 * w**2 * radius / K**2)
        la = np.cbrt(np.pi * w * radius**2 / K)
        P, A, C = _maugis_dimless(delta / ld, lam, branch)
        force = P * np.pi * w * radius
        a = A * la
        c = C * la
    hz = w <= 0
    if np.any(hz):
        force = np.where(hz, hertz_force(delta, radius, K), force)
        a = np.where(hz, np.sqrt(np.maximum(radius * delta, 0.0)), a)
        c = np.where(hz, a, c)
    nan = np.isnan(delta)
    force = np.where(nan, np.nan, force)
    if return_state:
        return force, np.where(nan, np.nan, a), np.where(nan, np.nan, c)
    return force


# --------------------------------------------------------------------------------------------
# dispatch
# --------------------------------------------------------------------------------------------
def _check_model(model):
    if model not in MODELS:
        raise ValueError(f"unknown contact model {model!r}; valid names are {', '.join(map(repr, MODELS))}.")


def sphere_state_kernel(model, delta, radius, K, sigma0=0.0, h0=0.0, *, branch="retraction", dmt_outer="sphere"):
    """Force [N], contact radius ``a`` [m] and adhesive radius ``c`` [m] of a sphere on a flat.

    Parameters as :func:`sphere_force_kernel`. ``c`` is the outer radius of the wetted (Dugdale)
    zone; it equals ``a`` for Hertz and JKR.
    """
    _check_model(model)
    if branch not in BRANCHES:
        raise ValueError(f"branch must be one of {BRANCHES}, got {branch!r}.")
    delta, radius = np.broadcast_arrays(np.asarray(delta, float), np.asarray(radius, float))
    if model == "hertz":
        f = hertz_force(delta, radius, K)
        a = np.sqrt(np.maximum(radius * np.where(np.isnan(delta), np.nan, delta), 0.0))
        a = np.where(np.isnan(delta), np.nan, a)
        return f, a, a
    if model == "modified_dmt":
        f = modified_dmt_force(delta, radius, K, sigma0, h0)
        nan = np.isnan(delta)
        a = np.where(delta > 0, np.sqrt(np.maximum(radius * delta, 0.0)), 0.0)
        s = np.minimum(delta + h0, radius)
        c = np.sqrt(np.where(s > 0, 2 * radius * s - s * s, 0.0))
        return f, np.where(nan, np.nan, a), np.where(nan, np.nan, c)
    if model == "dmt":
        return dmt_force(delta, radius, K, sigma0, h0, outer=dmt_outer, return_state=True)
    if model == "jkr":
        return jkr_force(delta, radius, K, np.asarray(sigma0) * np.asarray(h0), branch=branch, return_state=True)
    return maugis_force(delta, radius, K, sigma0, h0, branch=branch, return_state=True)


def sphere_force_kernel(model, delta, radius, K, sigma0=0.0, h0=0.0, *, branch="retraction", dmt_outer="sphere"):
    r"""Force [N] of a sphere on a flat for one of :data:`MODELS` (numpy, broadcasting).

    Parameters
    ----------
    model : {"hertz", "jkr", "dmt", "maugis", "modified_dmt"}
        Contact model.
    delta : array_like
        Interference [m]; > 0 overlap, < 0 separation. NaN gives NaN.
    radius : array_like
        Sphere radius R [m], broadcast against ``delta``.
    K : float or array_like
        :math:`K = \tfrac43 E^*` [Pa].
    sigma0, h0 : float or array_like
        Dugdale stress [Pa] (capillarity: :math:`|\Delta P|`) and its range [m]
        (:math:`h_{water}`); JKR uses only :math:`w = \sigma_0 h_0`.
    branch : {"retraction", "approach"}
        Branch of the displacement-controlled curve for JKR and Maugis (see their kernels).
    dmt_outer : {"sphere", "paraboloid"}
        Geometry of the non-contact water radius in DMT.

    Returns
    -------
    numpy.ndarray
        Force [N], positive repulsive.
    """
    _check_model(model)
    if model == "hertz":
        return hertz_force(delta, radius, K)
    if model == "modified_dmt":
        return modified_dmt_force(delta, radius, K, sigma0, h0)
    return sphere_state_kernel(model, delta, radius, K, sigma0, h0, branch=branch, dmt_outer=dmt_outer)[0]
