r"""The quadrature kernels of Greenwood-Williamson (Eq. 14): plain numpy on SI floats.

The joint density of summit height and curvature (:func:`_log_density`, derived in
docs/greenwood_williamson.md) and the vectorised quadrature over (distance x height x curvature)
that :func:`roughstick.contact.gw_curves` wraps with one ``xarray.apply_ufunc``.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy import interpolate, special

from ..._core.conventions import CURVE_VARIABLES
from ..sphere import force_kernel

__all__: list[str] = []

#: Curvature measures of a summit used for its sphere radius.
CURVATURE_MEASURES = ("geometric", "mean")

# Quadrature range of the summit height in units of sqrt(m0) when no cutoff is given. Summit
# heights have a standard deviation <= sqrt(m0) and a mean <= 1.85 sqrt(m0) (alpha >= 1.5), so
# the density at 10 sqrt(m0) is below 1e-16 of its peak.
_XI_TOP = 10.0


_XI_BOTTOM = -10.0


# order of the variables in the kernel output
_VARS = tuple(v for v in CURVE_VARIABLES if v != "fit_error")


def _check_moments_np(m0, m2, m4):
    """Raise a clear ValueError for impossible moments (numpy values)."""
    m0, m2, m4 = (np.asarray(v, dtype=float) for v in (m0, m2, m4))
    for name, v, unit in (("m0", m0, "m2"), ("m2", m2, "1"), ("m4", m4, "m-2")):
        bad = ~(np.isfinite(v) & (v > 0))
        if np.any(bad):
            raise ValueError(
                f"moment {name} must be positive and finite ({unit}), got {v[bad].ravel()[0]!r}. "
                "Spectral moments are integrals of a non-negative PSD."
            )
    alpha = m0 * m4 / m2**2
    bad = ~(alpha > 1.5)
    if np.any(bad):
        raise ValueError(
            f"bandwidth alpha = m0*m4/m2**2 = {alpha[bad].ravel()[0]!r} is below 1.5, which no "
            "isotropic Gaussian surface can have (Nayak 1971: alpha >= 1.5, equality for a single "
            "ring of wavevectors). Check the moments' units (m0 in m2, m2 in 1, m4 in m-2) and "
            "that m2, m4 are one-direction moments."
        )
    return alpha


_LOG_9SQRT3 = float(np.log(9.0 * np.sqrt(3.0)))


_LOG_3SQRT3 = float(np.log(3.0 * np.sqrt(3.0)))


_LOG_2PI = float(np.log(2.0 * np.pi))


def _log_density(xi, t, alpha, measure="geometric"):
    r"""Log of the dimensionless joint density of summit height and curvature.

    ``xi = h / sqrt(m0)``, ``t = kappa / sqrt(m4)``; the density integrates to one over
    ``xi`` in R and ``t`` > 0 for any ``alpha`` > 1.5. Arrays broadcast.

    Derivation (Kac–Rice, as Nayak 1971): at a point, write the negative Hessian as
    :math:`u \pm \sqrt{v^2+w^2}` with :math:`u = -(z_{xx}+z_{yy})/2`, :math:`v = (z_{xx}-z_{yy})/2`,
    :math:`w = z_{xy}`. For an isotropic Gaussian field, :math:`v, w` are independent
    :math:`N(0, m_4/3)`, independent of :math:`(z, u)`, which are bivariate normal with
    variances :math:`m_0, 2m_4/3` and covariance :math:`m_2`; the gradient is independent of all
    of them with density :math:`1/(2\pi m_2)` at zero. Summits per unit area:
    :math:`n = (u^2 - r^2)\,p(z, u)\,p_r(r)/(2\pi m_2)` for :math:`0 \le r = \sqrt{v^2+w^2} < u`.

    * ``measure="mean"`` (Nayak's mean curvature :math:`\kappa_m = u`): integrating over
      :math:`r` gives
      :math:`\rho(\xi, t) = 3\sqrt3\,(t^2 - \tfrac23 + \tfrac23 e^{-3t^2/2})\,\phi_2(\xi, t)` with
      :math:`\phi_2` the bivariate normal density of variances 1, 2/3 and covariance
      :math:`1/\sqrt\alpha`.
    * ``measure="geometric"`` (:math:`\kappa_g = \sqrt{\kappa_1\kappa_2} = \sqrt{u^2-r^2}`, the
      radius of Greenwood 2006): changing :math:`r \to \kappa_g` and integrating over :math:`u`,
      :math:`\rho(\xi, t) = 9\sqrt3\,t^3\,\phi(\xi)\,I(\xi, t)` with
      :math:`I = \int_t^\infty \phi(v; \xi/\sqrt\alpha, \tfrac23 - \tfrac1\alpha)\,
      e^{-3(v^2 - t^2)/2}\,dv`, which is a normal tail probability:
      :math:`I = (3 - 3/\alpha)^{-1/2}\exp[3t^2/2 - \xi^2/(2(\alpha - 1))]\,
      \Phi((\mu' - t)\sqrt{P})`, :math:`P = 3 + 1/\tau^2`, :math:`\mu' = \xi/(\sqrt\alpha\,\tau^2 P)`,
      :math:`\tau^2 = 2/3 - 1/\alpha`.
    """
    xi = np.asarray(xi, dtype=float)
    t = np.asarray(t, dtype=float)
    alpha = float(alpha)
    tau2 = 2.0 / 3.0 - 1.0 / alpha
    with np.errstate(divide="ignore"):
        log_t = np.log(t)
    if measure == "mean":
        # bivariate normal (xi, t): var 1, 2/3, cov c = 1/sqrt(alpha); det = tau2
        c = 1.0 / np.sqrt(alpha)
        q = (xi**2 * (2.0 / 3.0) - 2.0 * c * xi * t + t**2) / tau2
        log_phi2 = -0.5 * q - _LOG_2PI - 0.5 * np.log(tau2)
        # t^2 - 2/3 + 2/3 exp(-3 t^2/2) = 2/3 * (x - 1 + exp(-x)), x = 3 t^2 / 2 (>= 0, ~x^2/2)
        x = 1.5 * t**2
        g = np.where(x > 1e-4, x - 1.0 + np.exp(-x), 0.5 * x**2 * (1.0 - x / 3.0))
        with np.errstate(divide="ignore"):
            out = _LOG_3SQRT3 + np.log(2.0 / 3.0 * g) + log_phi2
        return np.where(t > 0, out, -np.inf)
    if measure != "geometric":
        raise ValueError(f"curvature_measure must be one of {CURVATURE_MEASURES}, got {measure!r}.")
    P = 3.0 + 1.0 / tau2
    mu_p = xi / (np.sqrt(alpha) * tau2 * P)
    log_I = (
        -0.5 * np.log(3.0 - 3.0 / alpha)
        + 1.5 * t**2
        - xi**2 / (2.0 * (alpha - 1.0))
        + special.log_ndtr((mu_p - t) * np.sqrt(P))
    )
    out = _LOG_9SQRT3 + 3.0 * log_t - 0.5 * xi**2 - 0.5 * _LOG_2PI + log_I
    return np.where(t > 0, out, -np.inf)


@functools.lru_cache(maxsize=32)
def _gauss(n: int):
    x, w = np.polynomial.legendre.leggauss(n)
    return (x + 1.0) / 2.0, w / 2.0  # on [0, 1]


def _sphere_force(model, delta, radius, K, sigma0, h0):
    delta, radius = np.broadcast_arrays(np.asarray(delta, float), np.asarray(radius, float))
    f = force_kernel(model, delta.ravel(), radius.ravel(), K, sigma0, h0)
    return np.reshape(f, delta.shape)


def _wet_and_contact(delta, radius, h_water):
    """Geometric wetted annulus (Eq. 8 minus Hertz contact, Eqs. 10-11) and contact area [m2]."""
    a2 = radius * np.clip(delta, 0.0, None)
    x = np.clip(delta + h_water, 0.0, radius)  # the meniscus cannot pass the sphere's equator
    c2 = x * (2.0 * radius - x)
    return np.pi * np.clip(c2 - a2, 0.0, None), np.pi * a2


def _tabulated(model, grid_delta, grid_x, radius, K, sigma0, h0):
    """Cubic spline in ``grid_x`` of the sphere force on ``grid_delta`` for every radius."""
    table = _sphere_force(model, grid_delta[:, None], radius[None, :], K, sigma0, h0)
    return interpolate.CubicSpline(grid_x, table, axis=0)


def _gw_point(
    m0, m2, m4, dP, h_water, distance, *, model, K, t_nodes, t_weights, xi_top, n_height, measure,
    table, cache,
):
    """All six curves for one set of moments and one humidity: array (n_distance, 6)."""
    alpha = float(_check_moments_np(m0, m2, m4))
    sigma, sq4 = np.sqrt(m0), np.sqrt(m4)
    N = m4 / (6.0 * np.pi * np.sqrt(3.0) * m2)
    s, ws = _gauss(n_height)
    radius = 1.0 / (t_nodes * sq4)  # (n_t,)
    R3 = radius[None, None, :]
    d = np.asarray(distance, dtype=float)
    xi_d = d / sigma
    lo = np.clip(xi_d - h_water / sigma, _XI_BOTTOM, xi_top)  # start of the wet interval
    mid = np.clip(xi_d, _XI_BOTTOM, xi_top)  # first contact
    sigma0 = abs(dP)
    capillary = model != "hertz" and h_water > 0 and sigma0 > 0
    out = np.zeros((d.size, len(_VARS)))

    # contact interval xi in [mid, xi_top], xi = mid + L s^2 (smooths delta^(3/2) at first contact)
    key = (m0, m2, m4)
    if key not in cache:
        L = xi_top - mid
        xi = mid[:, None] + L[:, None] * s[None, :] ** 2  # (n_d, n_h)
        wxi = (2.0 * L[:, None] * s[None, :]) * ws[None, :]
        rho = np.exp(_log_density(xi[:, :, None], t_nodes[None, None, :], alpha, measure))
        weight = N * rho * wxi[:, :, None] * t_weights[None, None, :]  # summits per m2 at each node
        delta = np.clip(sigma * xi - d[:, None], 0.0, None)  # (n_d, n_h)
        f_hertz = _sphere_force("hertz", delta[:, :, None], R3, K, 0.0, 0.0)
        cache.clear()
        cache[key] = (weight, delta, (weight * f_hertz).sum(axis=(1, 2)), weight.sum(axis=(1, 2)))
    weight, delta, p_rep, n_cont = cache[key]
    out[:, 1] = p_rep
    out[:, 4] = n_cont
    wet, contact = _wet_and_contact(delta[:, :, None], R3, h_water)
    out[:, 3] = (weight * contact).sum(axis=(1, 2))
    out[:, 5] = xi_top * sigma - d
    if model == "hertz":
        out[:, 0] = p_rep
        return out
    dmax = float(delta.max())
    if table and dmax > 0:
        # splines in sqrt(delta / dmax): Hertz's delta^(3/2) becomes a cubic
        g = np.linspace(0.0, 1.0, table)
        spl = _tabulated(model, dmax * g**2, g, radius, K, sigma0, h_water)
        f = spl(np.sqrt(delta / dmax))
    else:
        f = _sphere_force(model, delta[:, :, None], R3, K, sigma0, h_water)
    out[:, 0] = (weight * f).sum(axis=(1, 2))
    if not capillary:  # no water (sigma0 or h_water is zero): the model reduces to its dry contact
        return out
    out[:, 2] = (weight * wet).sum(axis=(1, 2))
    # wet interval xi in [lo, mid]: -h_water < delta <= 0 (meniscus, no contact)
    Lw = mid - lo
    xi = lo[:, None] + Lw[:, None] * s[None, :]
    wxi = Lw[:, None] * ws[None, :]
    rho = np.exp(_log_density(xi[:, :, None], t_nodes[None, None, :], alpha, measure))
    wgt = N * rho * wxi[:, :, None] * t_weights[None, None, :]
    dl = np.clip(sigma * xi - d[:, None], -h_water, 0.0)  # (n_d, n_h)
    if table:
        g = np.linspace(-h_water, 0.0, max(table // 4, 8))
        f = _tabulated(model, g, g, radius, K, sigma0, h_water)(dl)
    else:
        f = _sphere_force(model, dl[:, :, None], R3, K, sigma0, h_water)
    wet, _ = _wet_and_contact(dl[:, :, None], R3, h_water)
    out[:, 0] += (wgt * f).sum(axis=(1, 2))
    out[:, 2] += (wgt * wet).sum(axis=(1, 2))
    return out


def _gw_block(m0, m2, m4, dP, hw, distance, **kw):
    shape = np.broadcast(m0, m2, m4, dP, hw).shape
    b = [np.broadcast_to(np.asarray(v, dtype=float), shape) for v in (m0, m2, m4, dP, hw)]
    out = np.empty(shape + (np.size(distance), len(_VARS)))
    cache: dict = {}
    # visit humidities of one moment set together so the RH-independent part is reused
    order = sorted(np.ndindex(shape), key=lambda i: (b[0][i], b[1][i], b[2][i]))
    for idx in order:
        out[idx] = _gw_point(*(float(v[idx]) for v in b), distance, cache=cache, **kw)
    return out
