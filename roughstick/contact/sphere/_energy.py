r"""Plain-numpy SI kernels of the work to separate a sphere from a flat (Table 1), no xarray.

The integral of the attractive force along the retraction path of each model of
:mod:`._kernels` (same conventions and dimensionless variables).
"""

from __future__ import annotations

import numpy as np

from ._kernels import (
    _HALF_PI,
    _JKR_A_MIN,
    _check_model,
    _illinois,
    _kim_constants,
    _maugis_contact,
    _maugis_phi_min,
    dmt_force,
    modified_dmt_force,
    transition_parameter_kernel,
)

__all__ = ["adhesive_energy_kernel"]


# --------------------------------------------------------------------------------------------
# adhesive energy: work to separate = integral of the attractive force along the retraction path
# --------------------------------------------------------------------------------------------
_GL_T, _GL_W = np.polynomial.legendre.leggauss(64)
_GL_T = 0.5 * (_GL_T + 1.0)  # nodes on [0, 1]
_GL_W = 0.5 * _GL_W


def _cap_area_integral(S, R):
    """int_0^S (2 R s - s^2) ds with s capped at R (the wetted cap cannot pass the equator)."""
    Sm = np.minimum(S, R)
    return R * Sm * Sm - Sm**3 / 3.0 + np.maximum(S - R, 0.0) * R * R


def _positive_root(fun, hi0, shape):
    """Smallest-bracket root of an increasing ``fun`` on (0, hi]: expand hi until fun(hi) > 0."""
    hi = np.array(np.broadcast_to(hi0, shape), dtype=float)
    for _ in range(200):
        bad = ~(fun(hi, np.arange(hi.size).reshape(shape)) > 0) & np.isfinite(hi)
        if not np.any(bad):
            break
        hi = np.where(bad, hi * 4.0, hi)
    lo = np.zeros(shape)
    flat = np.arange(hi.size)

    def f(x, sel):
        return fun(x, sel)

    flo = f(lo.ravel(), flat)
    fhi = f(hi.ravel(), flat)
    return _illinois(f, lo.ravel(), hi.ravel(), flo, fhi, xtol=1e-15).reshape(shape)


def _energy_modified_dmt(R, K, s0, h0):
    shape = R.shape
    Rf, Kf, sf, hf = (np.broadcast_to(v, shape).ravel() for v in (R, K, s0, h0))

    def F(d, sel):
        d = np.asarray(d).ravel()
        return modified_dmt_force(d, Rf[sel.ravel()], Kf[sel.ravel()], sf[sel.ravel()], hf[sel.ravel()])

    scale = (sf * np.pi * np.sqrt(Rf) / Kf) ** 2 + 2.0 * hf
    deq = _positive_root(F, scale.reshape(shape), shape).ravel()
    W = sf * np.pi * (_cap_area_integral(hf + deq, Rf) - 0.5 * Rf * deq * deq)
    W = W - 0.4 * Kf * np.sqrt(Rf) * deq**2 * np.sqrt(deq)
    return W.reshape(shape)


def _energy_dmt(R, K, s0, h0, outer):
    shape = R.shape
    Rf, Kf, sf, hf = (np.broadcast_to(v, shape).ravel() for v in (R, K, s0, h0))

    def F(d, sel):
        d = np.asarray(d).ravel()
        s = sel.ravel()
        return dmt_force(d, Rf[s], Kf[s], sf[s], hf[s], outer=outer)

    # at delta -> 0+ the DMT force is -2 pi R w; Hertz wins once K sqrt(R) d^1.5 > sigma0 pi (c^2-a^2)
    scale = (sf * np.pi * np.sqrt(Rf) / Kf) ** 2 + np.cbrt((2 * np.pi * Rf * sf * hf / (Kf * np.sqrt(Rf))) ** 2)
    deq = _positive_root(F, scale.reshape(shape), shape).ravel()
    if outer == "sphere":
        W_out = sf * np.pi * _cap_area_integral(hf, Rf)
    else:
        W_out = sf * np.pi * Rf * hf * hf
    # contact part: int_0^deq -F d(delta), delta = deq t^2 (F has sqrt-type behaviour at 0)
    t = _GL_T[:, None]
    d = deq[None, :] * t * t
    Fn = dmt_force(d, Rf[None, :], Kf[None, :], sf[None, :], hf[None, :], outer=outer)
    W_in = np.sum(_GL_W[:, None] * (-Fn) * 2.0 * deq[None, :] * t, axis=0)
    return (W_out + W_in).reshape(shape)


_JKR_A_EQ = 6.0 ** (1.0 / 3.0)


def _jkr_energy_dimless():
    def G(A):
        return -0.4 * A**5 + 2.0 * np.sqrt(6.0) / 3.0 * A**3.5 - A * A

    return G(_JKR_A_EQ) - G(_JKR_A_MIN)


def _energy_jkr(R, K, w):
    with np.errstate(all="ignore"):
        scale = np.pi * w * R * np.cbrt(np.pi**2 * w**2 * R / K**2)
    return _jkr_energy_dimless() * scale


def _maugis_energy_dimless(lam):
    """Dimensionless work to separate, int -P dDelta along the retraction branch."""
    lam = np.asarray(lam, float).ravel()
    W = np.zeros(lam.shape)
    Cj, Cs, Dj, Dstar = _kim_constants(lam)
    kim_min = Cs < Cj
    # Kim part: int_{C*}^{Cj} (pi lam C^2 / 2) (C - C*) dC
    Wk = 0.5 * np.pi * lam * ((Cj**4 - Cs**4) / 4.0 - Cs * (Cj**3 - Cs**3) / 3.0)
    W = np.where(kim_min, Wk, 0.0)
    # contact part from phi_start (junction or jump-off) down to phi_eq where P = 0
    phi_start = np.full(lam.shape, _HALF_PI)
    if np.any(~kim_min):
        idx = np.nonzero(~kim_min)[0]
        phi_start[idx] = _maugis_phi_min(lam[idx])
    # P(phi) increases as phi decreases (A grows); find P = 0 in log(phi)
    lo = np.log(phi_start) - 1.0
    for _ in range(200):
        bad = _maugis_contact(np.exp(lo), lam)[1] <= 0
        if not np.any(bad):
            break
        lo = np.where(bad, lo - 2.0, lo)
    hi = np.log(phi_start)

    def fun(x, sel):
        return _maugis_contact(np.exp(x), lam[sel])[1]

    with np.errstate(all="ignore"):
        x_eq = _illinois(fun, lo, hi, fun(lo, np.arange(lam.size)), fun(hi, np.arange(lam.size)))
        # Gauss-Legendre in x = log(phi) on [x_eq, x_start]; dDelta/dx by central differences
        xs = x_eq[None, :] + _GL_T[:, None] * (hi - x_eq)[None, :]
        lam2 = lam[None, :]
        hstep = 1e-6
        Dp = _maugis_contact(np.exp(xs + hstep), lam2)[0]
        Dm = _maugis_contact(np.exp(xs - hstep), lam2)[0]
        P = _maugis_contact(np.exp(xs), lam2)[1]
        dD = (Dp - Dm) / (2 * hstep)
        Wc = np.sum(_GL_W[:, None] * P * dD, axis=0) * (hi - x_eq)
    return W + Wc


def _energy_maugis(R, K, s0, h0):
    w = s0 * h0
    lam = transition_parameter_kernel(R, K, s0, h0)
    shape = lam.shape
    lam_u, inv = np.unique(lam.ravel(), return_inverse=True)
    ok = np.isfinite(lam_u) & (lam_u > 0)
    Wd = np.full(lam_u.shape, np.nan)
    if np.any(ok):
        Wd[ok] = _maugis_energy_dimless(lam_u[ok])
    with np.errstate(all="ignore"):
        scale = np.pi * w * R * np.cbrt(np.pi**2 * w**2 * R / K**2)
    return Wd[inv].reshape(shape) * scale


def adhesive_energy_kernel(model, radius, K, sigma0=0.0, h0=0.0, *, dmt_outer="sphere"):
    r"""Work [J] to separate a sphere from a flat: :math:`\int -F\,\mathbf 1(F<0)\,d\delta`.

    The integral runs along the displacement-controlled retraction path, from the equilibrium
    interference (F = 0) out to the last attached state (:math:`\delta = -h_0` for DMT and the
    modified DMT; the jump-off point for JKR and Maugis). Closed forms for the modified DMT and
    JKR; 64-point Gauss-Legendre for the contact part of DMT and Maugis (relative accuracy
    better than 1e-6, checked against dense trapezoidal integration in the tests).
    """
    _check_model(model)
    R, K, s0, h0 = np.broadcast_arrays(*(np.asarray(v, float) for v in (radius, K, sigma0, h0)))
    w = s0 * h0
    if model == "hertz":
        out = np.zeros(R.shape)
    elif model == "jkr":
        out = _energy_jkr(R, K, w)
    else:
        out = np.full(R.shape, np.nan)
        good = np.isfinite(R + K + s0 + h0) & (w > 0)
        if np.any(good):
            args = (R[good], K[good], s0[good], h0[good])
            if model == "modified_dmt":
                out[good] = _energy_modified_dmt(*args)
            elif model == "dmt":
                out[good] = _energy_dmt(*args, dmt_outer)
            else:
                out[good] = _energy_maugis(*args)
        out = np.where(np.isfinite(R + K + s0 + h0) & (w <= 0), 0.0, out)
    return out
