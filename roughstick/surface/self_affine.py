r"""The isotropic self-affine PSD of Eq. 37 and its fit to the moments (paper §5.2, Fig. 19).

Its moments in closed form are :func:`roughstick.surface.moments.self_affine_moments`.
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from scipy.optimize import least_squares

from .._core import units as _units
from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.conventions import append_history, dataset_attrs, set_attrs
from .._core.dask import is_lazy
from .._core.references import PAPER, cite
from .._core.validate import check_positive_block
from .moments import _J, _self_affine_moments_np
from .spectrum import _wavevector

__all__ = ["self_affine_psd", "fit_self_affine"]


def _exponent(s0, s1, q0, qmax):
    return np.log(s1 / s0) / np.log(qmax / q0)


def _self_affine_kernel(q, s0, s1, q0, qmax):
    q = np.abs(q)
    beta = _exponent(s0, s1, q0, qmax)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        mid = s0 * (q / q0) ** beta
    return np.where(q < q0, s0, np.where(q <= qmax, mid, 0.0))


def self_affine_psd(q, *, s0, s1, q0, qmax) -> xr.DataArray:
    r"""The isotropic self-affine PSD of Eq. 37.

    .. math::

        s(q) = \begin{cases} s_0 & q < q_0 \\
        s_0 (q/q_0)^{\log_{10}(s_1/s_0)/\log_{10}(q_{max}/q_0)} & q_0 \le q \le q_{max} \\
        0 & q > q_{max} \end{cases}

    so that :math:`s(q_{max}) = s_1`.

    Parameters
    ----------
    q : array_like or xarray.DataArray
        Wave-vector magnitudes [rad m-1]. A 1-D array gives dims ``(q,)``; a DataArray keeps its
        own dims, so ``np.hypot(qx, qy)`` over ``(qy, qx)`` gives a 2D density on that grid.
        Negative values are taken by magnitude.
    s0, s1 : float or xarray.DataArray
        Plateau value and value at ``qmax`` [m4] (DataArrays: units ``m4``/``nm4``), > 0.
    q0, qmax : float or xarray.DataArray
        Roll-off and cutoff wave numbers [rad m-1], ``0 < q0 < qmax``.

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4], the 2D density evaluated at ``|q|`` (architecture: isotropic PSD).

    See Also
    --------
    fit_self_affine, self_affine_moments, isotropic_to_2d

    Examples
    --------
    >>> s = rs.surface.self_affine_psd([0.0, 1e7, 2e7, 3e8], s0=1e-32, s1=1e-38, q0=2e7, qmax=2e8)
    >>> s.values
    array([1.e-32, 1.e-32, 1.e-32, 0.e+00])
    """
    s0 = _units.as_si(s0, "length4", name="s0")
    s1 = _units.as_si(s1, "length4", name="s1")
    q0 = _wavevector(q0, name="q0")
    qmax = _wavevector(qmax, name="qmax")
    for v, n, u in ((s0, "s0", "m4"), (s1, "s1", "m4"), (q0, "q0", "rad m-1"),
                    (qmax, "qmax", "rad m-1")):
        if not isinstance(v, xr.DataArray):  # labelled sweeps are checked where they are used
            check_positive_block(v, n, f"Units: {u}.", finite=True)
    if not isinstance(q0, xr.DataArray) and not isinstance(qmax, xr.DataArray) and q0 >= qmax:
        raise ValueError(f"q0 must be smaller than qmax, got q0={q0!r}, qmax={qmax!r} (rad m-1).")
    if isinstance(q, xr.DataArray):
        qq = _units.require(q, "wavevector", name=q.name or "q")
    else:
        arr = np.asarray(q, dtype=float)
        if arr.ndim != 1:
            raise ValueError(
                "q must be 1-D (or a DataArray with its own dims, e.g. np.hypot(qx, qy)); "
                f"got shape {arr.shape}."
            )
        qq = xr.DataArray(arr, dims=("q",), coords={"q": arr})
    out = xr.apply_ufunc(_self_affine_kernel, qq, s0, s1, q0, qmax, dask="allowed")
    out = set_attrs(out.rename("psd"), "psd_isotropic", references=cite((PAPER, "Eq. 37")))
    return out


def _fit_kernel(m0, m2, m4, qmax):
    """Solve Eq. 37 for (q0, s0, s1) from (m0, m2, m4, qmax). Returns 6 floats."""
    nan6 = (np.nan,) * 6
    if not all(np.isfinite(v) and v > 0 for v in (m0, m2, m4, qmax)):
        return nan6
    r2, r4 = m2 / m0, m4 / m0

    def ratios(t, beta):
        q0 = qmax * np.exp(-t)
        a1 = 0.5 + _J(2 + beta, t)
        a3 = 0.25 + _J(4 + beta, t)
        a5 = 1 / 6 + _J(6 + beta, t)
        return q0**2 * a3 / (2 * a1), 0.375 * q0**4 * a5 / a1

    def resid(p):
        g2, g4 = ratios(*p)
        return np.array([np.log(g2 / r2), np.log(g4 / r4)])

    # coarse grid search (vectorised) for a start, then least squares
    tt, bb = np.meshgrid(np.linspace(0.02, 12.0, 300), np.linspace(-24.0, 6.0, 301))
    with np.errstate(all="ignore"):
        g2, g4 = ratios(tt, bb)
        cost = np.log(g2 / r2) ** 2 + np.log(g4 / r4) ** 2
    cost = np.where(np.isfinite(cost), cost, np.inf)
    k = np.unravel_index(np.argmin(cost), cost.shape)
    sol = least_squares(resid, x0=[tt[k], bb[k]], bounds=([1e-9, -60.0], [40.0, 20.0]),
                        xtol=1e-15, ftol=1e-15, gtol=1e-15, method="trf")
    t, beta = sol.x
    q0 = qmax * np.exp(-t)
    a1 = 0.5 + _J(2 + beta, t)
    s0 = m0 / (2 * np.pi * q0**2 * a1)
    s1 = s0 * np.exp(beta * t)
    f0, f2, f4 = _self_affine_moments_np(s0, beta, q0, qmax)
    return q0, s0, s1, f0 / m0 - 1, f2 / m2 - 1, f4 / m4 - 1


@renamed_keywords(tolerance="solver_tolerance")
@check_numbers(solver_tolerance="limit")
def fit_self_affine(*, m0, m2, m4, qmax, solver_tolerance: float = 1e-6) -> xr.Dataset:
    r"""Solve Eq. 37 for :math:`(q_0, s_0, s_1)` from the moments and the cutoff (paper §5.2).

    The moments of Eq. 37 are known in closed form (:func:`self_affine_moments`). ``s0`` scales
    all three, so the ratios :math:`m_2/m_0` and :math:`m_4/m_0` fix :math:`q_0` and the exponent;
    they are solved by least squares in :math:`(\ln(q_{max}/q_0), \beta)` from the best point of
    a coarse grid, then ``s0`` follows from :math:`m_0` and :math:`s_1 = s(q_{max})`.

    Parameters
    ----------
    m0 : float or xarray.DataArray
        Height variance [m2] (DataArray units ``m2``/``nm2``).
    m2 : float or xarray.DataArray
        One-direction slope variance [1].
    m4 : float or xarray.DataArray
        One-direction curvature variance [m-2] (DataArray units ``m-2``/``um-2``/``nm-2``).
    qmax : float or xarray.DataArray
        Cutoff wave number [rad m-1] (the paper takes 289 rad/µm).
    solver_tolerance : float
        Largest accepted relative moment residual of the fit; above it a ``ValueError`` says that Eq. 37
        cannot reach these moments with this ``qmax`` (only for eager inputs; NaN rows are kept
        for DataArray sweeps). Pass ``numpy.inf`` to always return.

    Returns
    -------
    xarray.Dataset
        ``q0`` [rad m-1], ``s0`` and ``s1`` [m4], ``qmax``, ``exponent`` (the Eq. 37 power,
        :math:`-2(1+H)` for a Hurst exponent H), and ``residual_m0``, ``residual_m2``,
        ``residual_m4`` (relative moment errors of the fitted PSD).

    Raises
    ------
    ValueError
        Non-positive inputs, or no Eq. 37 PSD matches within ``solver_tolerance``.

    Notes
    -----
    Table 4 of the paper (√m0 = 3.54 nm, R = 220 nm, N = 80.1 µm⁻², ξmax = 289 rad/µm; see
    :func:`moments_from_asperities`) gives q0 ≈ 21.2 rad/µm, s0 ≈ 5.5e3 nm⁴, s1 ≈ 5.5e-3 nm⁴.
    The printed 19.4 rad/µm, 6.46e3 nm⁴, 6.29e-3 nm⁴ are reproduced with N = 88.1 µm⁻²
    (tests/surface/test_self_affine.py holds both).

    Examples
    --------
    >>> m = rs.surface.moments_from_asperities(roughness=[2.6e-9, 2.4e-9], radius=220e-9, density=88.1e12)
    >>> fit = rs.surface.fit_self_affine(m0=m.m0, m2=m.m2, m4=m.m4, qmax=289e6)
    >>> round(float(fit.q0) / 1e6, 1), round(float(fit.s0) * 1e36), round(float(fit.s1) * 1e39, 2)
    (19.5, 6400, 6.31)
    """
    vals = {
        "m0": _units.as_si(m0, "area", name="m0"),
        "m2": _units.as_si(m2, "dimensionless", name="m2"),
        "m4": _units.as_si(m4, "inverse_area", name="m4"),
        "qmax": _wavevector(qmax, name="qmax"),
    }
    labelled = any(isinstance(v, xr.DataArray) for v in vals.values())
    for k, v in vals.items():
        if not isinstance(v, xr.DataArray):  # a sweep keeps NaN rows for impossible points
            check_positive_block(v, k, "SI units.", finite=True)
    outs = xr.apply_ufunc(
        _fit_kernel, vals["m0"], vals["m2"], vals["m4"], vals["qmax"],
        vectorize=True, dask="parallelized", output_core_dims=[[]] * 6,
        output_dtypes=[float] * 6,
    )
    q0, s0, s1, e0, e2, e4 = (o if isinstance(o, xr.DataArray) else xr.DataArray(o) for o in outs)
    qm = vals["qmax"] if isinstance(vals["qmax"], xr.DataArray) else xr.DataArray(vals["qmax"])
    beta = np.log(s1 / s0) / np.log(qm / q0)
    ds = xr.Dataset(
        {
            "q0": q0.assign_attrs(units="rad m-1", long_name="roll-off wave number of Eq. 37"),
            "s0": s0.assign_attrs(units="m4", long_name="plateau PSD value of Eq. 37"),
            "s1": s1.assign_attrs(units="m4", long_name="PSD value at the cutoff qmax (Eq. 37)"),
            "qmax": qm.assign_attrs(units="rad m-1", long_name="cutoff wave number of Eq. 37"),
            "exponent": beta.assign_attrs(units="1", long_name="power of the Eq. 37 self-affine branch"),
        }
    )
    for k, e in (("m0", e0), ("m2", e2), ("m4", e4)):
        ds[f"residual_{k}"] = e.assign_attrs(
            units="1", long_name=f"relative error of {k} of the fitted PSD"
        )
    ds.attrs = dataset_attrs(
        "self-affine PSD (Eq. 37) fitted to moments", references=cite((PAPER, "Eq. 37"))
    )
    append_history(ds, "fit_self_affine: Eq. 37 solved for (q0, s0, s1) from (m0, m2, m4, qmax)")
    if not labelled and not is_lazy(ds):
        worst = max(abs(float(ds[f"residual_{k}"])) for k in ("m0", "m2", "m4"))
        if not worst <= solver_tolerance:
            raise ValueError(
                f"no Eq. 37 PSD with qmax={float(qm):.4g} rad m-1 reaches m0={vals['m0']:.4g}, "
                f"m2={vals['m2']:.4g}, m4={vals['m4']:.4g} (worst relative residual {worst:.3g}). "
                "The bandwidth m0*m4/m2**2 may be out of reach for this cutoff: raise qmax, or "
                "pass solver_tolerance=numpy.inf to get the closest PSD."
            )
    return ds
