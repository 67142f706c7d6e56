r"""Power spectral densities of height maps and the self-affine PSD of Eq. 37.

Normalisation (DESIGN.md §3, docs/architecture.md): the 2D density :math:`s(q_x, q_y)` [m4]
integrates to the height variance,

.. math:: \iint s \, dq_x \, dq_y = m_0 ,

so for an :math:`N_y \times N_x` map of spacing :math:`\Delta`,
``psd = abs(fft2(z))**2 * dx**2 * dy**2 / ((2π)**2 * Lx * Ly)`` with :math:`L = N\Delta`.
Nayak's one-direction moments are :math:`m_2 = \iint q_x^2 s`, :math:`m_4 = \iint q_x^4 s`; for an
isotropic :math:`s(q)`: :math:`m_0 = 2\pi\int s q\,dq`, :math:`m_2 = \pi\int s q^3 dq`,
:math:`m_4 = \tfrac{3\pi}{4}\int s q^5 dq`.

References
----------
Nayak, P. R. (1971). Random process model of rough surfaces. J. Lubr. Technol. 93, 398-407.
https://doi.org/10.1115/1.3451608
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ._core import units as _units
from ._core.conventions import append_history, dataset_attrs, set_attrs
from ._core.dask import check_core_not_chunked, is_lazy
from ._core.references import PAPER, cite

__all__ = [
    "power_spectrum",
    "psd_isotropic",
    "psd_moments",
    "average_psd",
    "submap_psd",
    "submap_variance_check",
    "choose_cutoff",
    "interpolate_psd",
    "psd_summary",
    "isotropic_to_2d",
    "self_affine_psd",
    "self_affine_moments",
    "fit_self_affine",
    "moments_from_asperities",
]

NAYAK_REFERENCE = cite("nayak1971")

# --------------------------------------------------------------------------------------------
# small unit helpers for quantities _units has no kind for (m4, m2, m-2)
# --------------------------------------------------------------------------------------------

def _wavevector(value, *, name: str):
    return _units.as_si(value, "wavevector", name=name)


def _positive(value, name: str, unit: str):
    if isinstance(value, xr.DataArray):
        return  # lazy or labelled inputs are checked where they are used
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0):
        raise ValueError(f"{name} must be finite and positive ({unit}), got {value!r}.")


# --------------------------------------------------------------------------------------------
# Eq. 37: the self-affine isotropic PSD and its moments in closed form
# --------------------------------------------------------------------------------------------


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
    >>> s = rs.self_affine_psd([0.0, 1e7, 2e7, 3e8], s0=1e-32, s1=1e-38, q0=2e7, qmax=2e8)
    >>> s.values
    array([1.e-32, 1.e-32, 1.e-32, 0.e+00])
    """
    s0 = _units.as_si(s0, "length4", name="s0")
    s1 = _units.as_si(s1, "length4", name="s1")
    q0 = _wavevector(q0, name="q0")
    qmax = _wavevector(qmax, name="qmax")
    for v, n, u in ((s0, "s0", "m4"), (s1, "s1", "m4"), (q0, "q0", "rad m-1"),
                    (qmax, "qmax", "rad m-1")):
        _positive(v, n, u)
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


def isotropic_to_2d(psd, qx, qy) -> xr.DataArray:
    r"""Evaluate an isotropic PSD ``s(q)`` on a 2D ``(qy, qx)`` grid at :math:`|q|`.

    Linear interpolation in :math:`\log s` between the ``q`` samples (exact for a power law
    between samples; zeros stay zero); zero beyond the largest ``q`` sample.

    Parameters
    ----------
    psd : xarray.DataArray
        Isotropic density [m4] with dim ``q`` (ascending, rad m-1), e.g. from
        :func:`self_affine_psd` or :func:`psd_isotropic`. Other dims are kept.
    qx, qy : array_like or xarray.DataArray
        1-D wave-vector components [rad m-1].

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4] over ``(..., qy, qx)``.
    """
    if "q" not in psd.dims:
        raise ValueError(f"psd must have a 'q' dimension (isotropic PSD), got dims {psd.dims}.")
    attrs = psd.attrs
    psd = _units_psd(psd)
    check_core_not_chunked(psd, ["q"])
    qx = np.asarray(qx.values if isinstance(qx, xr.DataArray) else qx, dtype=float)
    qy = np.asarray(qy.values if isinstance(qy, xr.DataArray) else qy, dtype=float)
    qgrid = psd["q"].values
    if np.any(np.diff(qgrid) <= 0):
        raise ValueError("the 'q' coordinate of psd must be strictly ascending; use psd.sortby('q').")
    qmag = np.hypot(qx[None, :], qy[:, None])

    def kern(s):
        tiny = np.finfo(float).tiny
        flat = s.reshape(-1, s.shape[-1])
        out = np.empty(flat.shape[:1] + qmag.shape)
        for i, row in enumerate(flat):
            logs = np.log(np.maximum(row, tiny))
            v = np.exp(np.interp(qmag, qgrid, logs, right=np.log(tiny)))
            out[i] = np.where(v <= tiny * 1.0001, 0.0, v)
        return out.reshape(s.shape[:-1] + qmag.shape)

    out = xr.apply_ufunc(
        kern, psd, input_core_dims=[["q"]], output_core_dims=[["qy", "qx"]],
        dask="parallelized", output_dtypes=[float],
        dask_gufunc_kwargs={"output_sizes": {"qy": qy.size, "qx": qx.size}},
    )
    out = out.assign_coords(qy=qy, qx=qx)
    return set_attrs(out.rename("psd"), "psd", **_keep(attrs, "references"))


def _keep(attrs, *keys):
    return {k: attrs[k] for k in keys if k in attrs}


def _units_psd(psd):
    return _units.require(psd, "length4", name=psd.name or "psd")


def _J(a, t):
    """(exp(a t) - 1) / a, smooth through a = 0 (t = ln(qmax/q0))."""
    x = a * t
    small = np.abs(x) < 1e-8
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        big = np.expm1(x) / np.where(small, 1.0, a)
    return np.where(small, t * (1 + x / 2), big)


def _self_affine_moments_np(s0, beta, q0, qmax):
    """Closed-form (m0, m2, m4) of Eq. 37 for exponent ``beta``."""
    t = np.log(qmax / q0)
    i1 = q0**2 * (0.5 + _J(2 + beta, t))
    i3 = q0**4 * (0.25 + _J(4 + beta, t))
    i5 = q0**6 * (1 / 6 + _J(6 + beta, t))
    return 2 * np.pi * s0 * i1, np.pi * s0 * i3, 0.75 * np.pi * s0 * i5


def self_affine_moments(*, s0, s1, q0, qmax) -> xr.Dataset:
    r"""Moments :math:`m_0, m_2, m_4` of the Eq. 37 PSD in closed form.

    With :math:`\beta` the exponent of Eq. 37, :math:`t = \ln(q_{max}/q_0)` and
    :math:`J(a) = (e^{a t}-1)/a`:

    .. math::

        m_0 = 2\pi s_0 q_0^2 [1/2 + J(2+\beta)],\quad
        m_2 = \pi s_0 q_0^4 [1/4 + J(4+\beta)],\quad
        m_4 = \tfrac{3\pi}{4} s_0 q_0^6 [1/6 + J(6+\beta)].

    Parameters
    ----------
    s0, s1 : float or xarray.DataArray
        Plateau and cutoff values [m4].
    q0, qmax : float or xarray.DataArray
        Roll-off and cutoff wave numbers [rad m-1].

    Returns
    -------
    xarray.Dataset
        ``m0`` [m2], ``m2`` [1], ``m4`` [m-2] (Nayak one-direction convention).

    Examples
    --------
    >>> m = rs.self_affine_moments(s0=6.46e-33, s1=6.29e-39, q0=19.4e6, qmax=289e6)
    >>> round(float(m.m0) * 1e18, 1), round(float(m.m2), 4), round(float(m.m4) * 1e-12, 2)
    (12.5, 0.0032, 9.07)
    """
    s0 = _units.as_si(s0, "length4", name="s0")
    s1 = _units.as_si(s1, "length4", name="s1")
    q0 = _wavevector(q0, name="q0")
    qmax = _wavevector(qmax, name="qmax")
    beta = np.log(s1 / s0) / np.log(qmax / q0)
    m0, m2, m4 = _self_affine_moments_np(s0, beta, q0, qmax)
    return _moments_dataset(m0, m2, m4, title="moments of the self-affine PSD (Eq. 37)")


def _moments_dataset(m0, m2, m4, *, title: str, **extra_vars) -> xr.Dataset:
    def wrap(v, key):
        da = v if isinstance(v, xr.DataArray) else xr.DataArray(v)
        return set_attrs(da.rename(key), key)

    ds = xr.Dataset({"m0": wrap(m0, "m0"), "m2": wrap(m2, "m2"), "m4": wrap(m4, "m4")})
    for k, v in extra_vars.items():
        ds[k] = v
    ds.attrs = dataset_attrs(title, references=NAYAK_REFERENCE)
    return ds


def _fit_kernel(m0, m2, m4, qmax):
    """Solve Eq. 37 for (q0, s0, s1) from (m0, m2, m4, qmax). Returns 6 floats."""
    from scipy.optimize import least_squares

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


def fit_self_affine(*, m0, m2, m4, qmax, tolerance: float = 1e-6) -> xr.Dataset:
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
    tolerance : float
        Largest accepted relative moment residual; above it a ``ValueError`` says that Eq. 37
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
        Non-positive inputs, or no Eq. 37 PSD matches within ``tolerance``.

    Notes
    -----
    Table 4 of the paper (√m0 = 3.54 nm, R = 220 nm, N = 80.1 µm⁻², ξmax = 289 rad/µm; see
    :func:`moments_from_asperities`) gives q0 ≈ 21.2 rad/µm, s0 ≈ 5.5e3 nm⁴, s1 ≈ 5.5e-3 nm⁴.
    The printed 19.4 rad/µm, 6.46e3 nm⁴, 6.29e-3 nm⁴ are reproduced with N = 88.1 µm⁻²
    (DESIGN.md §3; tests/test_psd.py holds both).

    Examples
    --------
    >>> m = rs.moments_from_asperities(roughness=[2.6e-9, 2.4e-9], radius=220e-9, density=88.1e12)
    >>> fit = rs.fit_self_affine(m0=m.m0, m2=m.m2, m4=m.m4, qmax=289e6)
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
        _positive(v, k, "SI")
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
        if not worst <= tolerance:
            raise ValueError(
                f"no Eq. 37 PSD with qmax={float(qm):.4g} rad m-1 reaches m0={vals['m0']:.4g}, "
                f"m2={vals['m2']:.4g}, m4={vals['m4']:.4g} (worst relative residual {worst:.3g}). "
                "The bandwidth m0*m4/m2**2 may be out of reach for this cutoff: raise qmax, or "
                "pass tolerance=numpy.inf to get the closest PSD."
            )
    return ds


def moments_from_asperities(*, roughness, radius, density) -> xr.Dataset:
    r"""PSD moments from roughness, mean summit radius and summit density (Table 4, Nayak).

    .. math::

        m_0 = \sum_i \sigma_i^2,\qquad
        m_4 = \left(\frac{3\sqrt{\pi}}{8R}\right)^2,\qquad
        m_2 = \frac{m_4}{6\sqrt{3}\,\pi N}.

    The summit relations are Nayak's for a Gaussian surface (mean summit curvature
    :math:`8\sqrt{m_4}/(3\sqrt\pi)` at high bandwidth; summit density
    :math:`N = m_4/(6\pi\sqrt{3} m_2)`). Table 4 prints :math:`\mu_4 = 3\sqrt\pi/(8R)` without
    the square; the square is what gives its 9.1 µm⁻² (DESIGN.md §3).

    Parameters
    ----------
    roughness : float or sequence of float
        RMS roughness [m]; several values (two surfaces in contact) are summed in variance,
        :math:`\sqrt{2.6^2+2.4^2} = 3.54` nm as in Table 4.
    radius : float
        Mean summit radius of the (equivalent) surface [m].
    density : float
        Summit density N [m-2].

    Returns
    -------
    xarray.Dataset
        ``m0`` [m2], ``m2`` [1], ``m4`` [m-2].

    References
    ----------
    Nayak (1971), https://doi.org/10.1115/1.3451608

    Examples
    --------
    >>> m = rs.moments_from_asperities(roughness=[2.6e-9, 2.4e-9], radius=220e-9, density=80.1e12)
    >>> round(float(m.m0) ** 0.5 * 1e9, 2), round(float(m.m2), 5), round(float(m.m4) * 1e-12, 2)
    (3.54, 0.00349, 9.13)
    """
    r = np.atleast_1d(np.asarray(roughness, dtype=float))
    if r.size == 0 or not np.all(np.isfinite(r)) or np.any(r <= 0):
        raise ValueError(f"roughness must be positive lengths in m, got {roughness!r}.")
    _positive(radius, "radius", "m")
    _positive(density, "density", "m-2")
    m0 = float(np.sum(r**2))
    m4 = (3 * np.sqrt(np.pi) / (8 * float(radius))) ** 2
    m2 = m4 / (6 * np.sqrt(3) * np.pi * float(density))
    ds = _moments_dataset(m0, m2, m4, title="PSD moments from asperity statistics (Table 4)")
    append_history(
        ds,
        f"moments_from_asperities: roughness={list(r)} m, radius={float(radius)} m, "
        f"density={float(density)} m-2",
    )
    return ds


# --------------------------------------------------------------------------------------------
# PSD estimation (Eqs. 26-30), averaging (Eq. 31), sub-maps (Eq. 32)
# --------------------------------------------------------------------------------------------


def _fft_module(data):
    if type(data).__module__.startswith("dask"):
        import dask.array.fft as fft

        return fft
    return np.fft


def _window_2d(name, ny, nx):
    from scipy.signal import get_window

    wy = get_window(name, ny, fftbins=True)
    wx = get_window(name, nx, fftbins=True)
    w = np.outer(wy, wx)
    return w / np.sqrt(np.mean(w**2))


def power_spectrum(height: xr.DataArray, *, window: str | None = None) -> xr.DataArray:
    r"""2D power spectral density of height maps by FFT (Eqs. 26-30).

    .. math::

        s(q_x, q_y) = \frac{|\mathrm{FFT}(z - \bar z)|^2 \, \Delta x^2 \Delta y^2}
                           {(2\pi)^2 L_x L_y},\qquad
        \sum s \, \Delta q_x \Delta q_y = \overline{(z - \bar z)^2} = m_0

    (Parseval, exact without a window). The paper's Eq. 26 omits the :math:`(2\pi)^2`; this
    normalisation makes :math:`\iint s = m_0` as in its Tables 3 and 4 (DESIGN.md §3).

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, units length (converted to m), uniform ascending
        coords, at least 8 x 8, odd and non-square sizes allowed, no NaN. A stack ``(..., y, x)``
        backed by dask stays lazy (``x`` and ``y`` must each be one chunk).
    window : str, optional
        A :func:`scipy.signal.get_window` name (e.g. ``"hann"``) applied separably; it is
        normalised to unit mean square so that the expected variance is kept (Parseval then
        holds only on average).

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4] over ``(..., qy, qx)``, ascending centred coords [rad m-1] including 0;
        attrs ``spacing_x``, ``spacing_y`` [m] and ``window``.

    Raises
    ------
    ValueError
        Bad coordinates or sizes (see :func:`roughstick.validate_height`), chunked x/y, and, for
        eager input, NaN pixels or a constant map.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> h = rs.testing.make_topography(rng.normal(size=(12, 10)) * 1e-9, spacing=5e-9)
    >>> s = rs.power_spectrum(h)
    >>> dqx, dqy = 2 * np.pi / (10 * 5e-9), 2 * np.pi / (12 * 5e-9)
    >>> s.dims, bool(np.isclose(float(s.sum()) * dqx * dqy, float(h.var())))
    (('qy', 'qx'), True)
    """
    from .topography import _refuse_constant_or_nan, validate_height

    h = validate_height(height)
    _refuse_constant_or_nan(h)
    dx, dy = h.attrs["spacing_x"], h.attrs["spacing_y"]
    ny, nx = h.sizes["y"], h.sizes["x"]
    data = h.data
    fft = _fft_module(data)
    z = data - data.mean(axis=(-2, -1), keepdims=True)
    if window is not None:
        z = z * _window_2d(window, ny, nx)
    Z = fft.fftshift(fft.fft2(z, axes=(-2, -1)), axes=(-2, -1))
    s = (Z.real**2 + Z.imag**2) * (dx * dy) / ((2 * np.pi) ** 2 * nx * ny)
    qx = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(nx, dx))
    qy = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(ny, dy))
    lead = {d: h[d] for d in h.dims[:-2] if d in h.coords}
    out = xr.DataArray(s, dims=h.dims[:-2] + ("qy", "qx"),
                       coords={**lead, "qy": qy, "qx": qx}, name="psd")
    out = set_attrs(out, "psd", spacing_x=dx, spacing_y=dy, window=str(window),
                    references=cite((PAPER, "Eqs. 26-30")))
    return out


def _check_psd2d(psd):
    if not ({"qx", "qy"} <= set(psd.dims)):
        raise ValueError(f"expected a 2D PSD with dims (..., 'qy', 'qx'), got {psd.dims}.")
    psd = _units_psd(psd)
    check_core_not_chunked(psd, ["qx", "qy"])
    if not is_lazy(psd) and np.any(psd.data < 0):
        raise ValueError(
            "the PSD has negative values; a power spectral density is non-negative. Clip "
            "interpolation artefacts with psd.clip(min=0) if they are round-off."
        )
    for d in ("qx", "qy"):
        c = psd[d].values
        if np.any(np.diff(c) <= 0):
            raise ValueError(f"coordinate {d!r} must be ascending (fftshift order); use psd.sortby({d!r}).")
    return psd.transpose(..., "qy", "qx")


def _dq(c):
    return float(np.mean(np.diff(np.asarray(c, dtype=float))))


def psd_isotropic(psd: xr.DataArray, *, full: bool = False) -> xr.DataArray:
    r"""Radial (isotropic) average of a 2D PSD.

    Rings of width :math:`\Delta q = \min(\Delta q_x, \Delta q_y)` centred on
    :math:`q_k = k\Delta q`; each value is the mean of the 2D density over the ring, so
    :math:`m_0 \approx 2\pi\sum_k s_k q_k \Delta q`.

    Parameters
    ----------
    psd : xarray.DataArray
        2D ``psd`` [m4] over ``(..., qy, qx)`` (:func:`power_spectrum`).
    full : bool
        Keep rings out to the corners of the grid (partly sampled). Default: up to the
        smaller Nyquist wave number.

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4] over ``(..., q)``; coordinate ``n_samples`` (pixels per ring).
    """
    from scipy import sparse

    s = _check_psd2d(psd)
    qx, qy = s["qx"].values, s["qy"].values
    dq = min(_dq(qx), _dq(qy))
    qmag = np.hypot(qx[None, :], qy[:, None]).ravel()
    k = np.rint(qmag / dq).astype(int)
    kmax = int(np.floor(min(np.abs(qx).max(), np.abs(qy).max()) / dq)) if not full else k.max()
    keep = k <= kmax
    counts = np.bincount(k[keep], minlength=kmax + 1)
    rows = np.flatnonzero(keep)
    cols = k[keep]
    nb = kmax + 1
    w = sparse.csr_matrix((1.0 / counts[cols], (rows, cols)), shape=(qmag.size, nb))

    def kern(a):
        flat = a.reshape(-1, a.shape[-2] * a.shape[-1])
        return np.asarray(flat @ w).reshape(a.shape[:-2] + (nb,))

    out = xr.apply_ufunc(
        kern, s, input_core_dims=[["qy", "qx"]], output_core_dims=[["q"]],
        dask="parallelized", output_dtypes=[float], dask_gufunc_kwargs={"output_sizes": {"q": nb}},
    )
    out = out.assign_coords(q=np.arange(nb) * dq, n_samples=("q", counts))
    out["n_samples"].attrs = {"units": "1", "long_name": "number of 2D PSD samples in the ring"}
    return set_attrs(out.rename("psd"), "psd_isotropic", **_keep(psd.attrs, "spacing_x", "spacing_y"))


def psd_moments(psd: xr.DataArray, *, qmax=None, direction: str = "mean") -> xr.Dataset:
    r"""Moments :math:`\mu_0, \mu_2, \mu_4` of a PSD (Nayak one-direction convention).

    2D: :math:`\mu_0 = \sum s\,\Delta q_x\Delta q_y`, :math:`\mu_2 = \sum q_x^2 s\,\Delta q^2`,
    :math:`\mu_4 = \sum q_x^4 s\,\Delta q^2` over :math:`|q| \le q_{max}` (``direction="y"`` uses
    :math:`q_y`; ``"mean"`` averages both). Isotropic ``(q)``: trapezoid rule for
    :math:`2\pi\int s q`, :math:`\pi\int s q^3`, :math:`\tfrac{3\pi}{4}\int s q^5`.

    Parameters
    ----------
    psd : xarray.DataArray
        ``psd`` [m4] over ``(..., qy, qx)`` or ``(..., q)``.
    qmax : float or xarray.DataArray, optional
        Cutoff wave number [rad m-1] (Table 3 uses 289 rad/µm); a DataArray adds its dims.
    direction : {"mean", "x", "y"}
        2D only.

    Returns
    -------
    xarray.Dataset
        ``m0`` [m2], ``m2`` [1], ``m4`` [m-2].
    """
    if direction not in ("mean", "x", "y"):
        raise ValueError(f"direction must be 'mean', 'x' or 'y', got {direction!r}.")
    if qmax is not None:
        qmax = _wavevector(qmax, name="qmax")
    if "q" in psd.dims:
        s = _units_psd(psd)
        check_core_not_chunked(s, ["q"])
        q = s["q"]
        if qmax is not None:
            s = s.where(q <= qmax, 0.0)
        m0 = 2 * np.pi * (s * q).integrate("q")
        m2 = np.pi * (s * q**3).integrate("q")
        m4 = 0.75 * np.pi * (s * q**5).integrate("q")
    else:
        s = _check_psd2d(psd)
        area = _dq(s["qx"].values) * _dq(s["qy"].values)
        qx, qy = s["qx"], s["qy"]
        if qmax is not None:
            s = s.where(np.hypot(qx, qy) <= qmax, 0.0)
        dims = ("qy", "qx")
        m0 = s.sum(dims) * area
        comp = {"x": [qx], "y": [qy], "mean": [qx, qy]}[direction]
        m2 = sum((s * c**2).sum(dims) for c in comp) * area / len(comp)
        m4 = sum((s * c**4).sum(dims) for c in comp) * area / len(comp)
    ds = _moments_dataset(m0, m2, m4, title="PSD moments")
    if qmax is not None:
        qm = qmax if isinstance(qmax, xr.DataArray) else xr.DataArray(qmax)
        ds["qmax"] = qm.assign_attrs(units="rad m-1", long_name="cutoff wave number")
    append_history(ds, f"psd_moments: qmax={'none' if qmax is None else 'set'}, direction={direction!r}")
    return ds


def average_psd(psd: xr.DataArray, dim) -> xr.DataArray:
    r"""Average PSDs of several maps, Eq. 31: :math:`s = \frac{1}{n}\sum_j s^{(j)}`.

    Parameters
    ----------
    psd : xarray.DataArray or sequence of xarray.DataArray
        PSDs with identical ``q`` coordinates (same map size and spacing); a sequence is stacked
        along ``dim``.
    dim : str or sequence of str
        Dimension(s) over which to average (e.g. ``"map"``, ``("map", "submap")``).

    Returns
    -------
    xarray.DataArray
        The averaged ``psd``; attr ``n_averaged``.
    """
    if isinstance(psd, (list, tuple)):
        name = dim if isinstance(dim, str) else dim[0]
        psd = xr.concat(list(psd), dim=name, join="exact", combine_attrs="drop_conflicts")
    dims = [dim] if isinstance(dim, str) else list(dim)
    missing = [d for d in dims if d not in psd.dims]
    if missing:
        raise ValueError(f"cannot average over {missing}: psd has dims {psd.dims}.")
    n = int(np.prod([psd.sizes[d] for d in dims]))
    key = "psd_isotropic" if "q" in psd.dims else "psd"
    out = set_attrs(psd.mean(dims).rename("psd"), key,
                    **_keep(psd.attrs, "spacing_x", "spacing_y", "window"), n_averaged=n)
    return append_history(out, f"average_psd: Eq. 31 mean of {n} spectra over {dims}")


def _split(height: xr.DataArray, n: int) -> xr.DataArray:
    k = int(round(np.sqrt(n)))
    if k * k != n or n < 1:
        raise ValueError(f"n (sub-maps per map) must be a perfect square (1, 4, 16, ...), got {n}.")
    ny, nx = height.sizes["y"] // k, height.sizes["x"] // k
    if min(ny, nx) < 8:
        raise ValueError(
            f"splitting a {height.sizes['y']} x {height.sizes['x']} map into {n} sub-maps leaves "
            f"{ny} x {nx} pixels; need at least 8 x 8. Use fewer sub-maps."
        )
    tiles = []
    for i in range(k):
        for j in range(k):
            t = height.isel(y=slice(i * ny, (i + 1) * ny), x=slice(j * nx, (j + 1) * nx))
            tiles.append(t.assign_coords(y=height["y"].values[:ny], x=height["x"].values[:nx]))
    out = xr.concat(tiles, dim="submap", combine_attrs="override")
    return out.assign_coords(submap=np.arange(n)).transpose(..., "submap", "y", "x")


def submap_psd(
    height: xr.DataArray, *, n: int = 16, average_dims=None, window: str | None = None
) -> xr.DataArray:
    r"""PSD averaged over maps and sub-maps (Eq. 31; the paper's schemes 1/4/16, Fig. 12).

    Each map is cut into ``n`` = k² equal tiles (remainder rows/columns dropped), the PSD of
    every tile is taken (:func:`power_spectrum`, each tile's mean removed) and all are averaged.

    Parameters
    ----------
    height : xarray.DataArray
        Topography ``(..., y, x)``, units length; leading dims are the measured maps.
    n : int
        Sub-maps per map: 1, 4, 16, ...
    average_dims : sequence of str, optional
        Leading dims to average over as well (default: all of them, i.e. one PSD per sample).
    window : str, optional
        Window passed to :func:`power_spectrum`.

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4] over ``(..., qy, qx)`` on the sub-map wave-number grid; attrs
        ``n_averaged``, ``n_submaps``.
    """
    from .topography import validate_height

    h = validate_height(height)
    tiles = _split(h, n)
    s = power_spectrum(tiles, window=window)
    if average_dims is None:
        lead = list(h.dims[:-2])
    elif isinstance(average_dims, str):
        lead = [average_dims]
    else:
        lead = list(average_dims)
    out = average_psd(s, ["submap", *lead])
    out.attrs["n_submaps"] = n
    return out


def submap_variance_check(
    height: xr.DataArray, *, n: int = 16, reference=None, threshold: float = 0.03
) -> xr.Dataset:
    r"""Representativeness of sub-maps, Eq. 32.

    .. math:: \epsilon = \frac{\sqrt{E\left([m_0^{(j)} - m_0]^2\right)}}{m_0} \ll 1

    over all sub-maps j of all maps; :math:`m_0` is the reference variance (default: mean of
    the whole maps' variances, as Table 2 does). The paper accepts its schemes at ε < 3 %.

    Parameters
    ----------
    height : xarray.DataArray
        Topography ``(..., y, x)``; all leading dims are pooled.
    n : int
        Sub-maps per map.
    reference : float, optional
        :math:`m_0` [m2].
    threshold : float
        Limit for ``representative``.

    Returns
    -------
    xarray.Dataset
        ``m0_submap`` (..., submap) [m2], ``m0`` [m2], ``relative_std`` ε [1],
        ``representative`` (bool, ε < threshold).
    """
    from .topography import validate_height

    h = validate_height(height)
    tiles = _split(h, n)
    tc = tiles - tiles.mean(("y", "x"))
    m0j = (tc**2).mean(("y", "x"))
    if reference is None:
        hc = h - h.mean(("y", "x"))
        m0 = (hc**2).mean(("y", "x")).mean()
    else:
        m0 = xr.DataArray(float(_units.as_si(reference, "area", name="reference")))
    eps = np.sqrt(((m0j - m0) ** 2).mean()) / m0
    ds = xr.Dataset({
        "m0_submap": m0j.assign_attrs(units="m2", long_name="height variance of each sub-map"),
        "m0": m0.assign_attrs(units="m2", long_name="reference height variance"),
        "relative_std": eps.assign_attrs(units="1", long_name="Eq. 32 relative std of sub-map variances"),
        "representative": (eps < threshold).assign_attrs(long_name=f"Eq. 32 below {threshold}"),
    })
    ds.attrs = dataset_attrs("Eq. 32 sub-map representativeness", references=cite((PAPER, "Eq. 32")),
                             n_submaps=n, threshold=threshold)
    return ds


# --------------------------------------------------------------------------------------------
# cutoff (Table 3) and interpolation onto a larger map (§4.2.1)
# --------------------------------------------------------------------------------------------


def _cumulative_moments(s2d, qx, qy, direction):
    qxx, qyy = np.meshgrid(qx, qy)
    qm = np.hypot(qxx, qyy).ravel()
    order = np.argsort(qm, kind="stable")
    qs = qm[order]
    ss = s2d.ravel()[order]
    if direction == "x":
        c2, c4 = qxx.ravel()[order] ** 2, qxx.ravel()[order] ** 4
    elif direction == "y":
        c2, c4 = qyy.ravel()[order] ** 2, qyy.ravel()[order] ** 4
    else:
        c2 = (qxx.ravel()[order] ** 2 + qyy.ravel()[order] ** 2) / 2
        c4 = (qxx.ravel()[order] ** 4 + qyy.ravel()[order] ** 4) / 2
    area = _dq(qx) * _dq(qy)
    m0 = np.cumsum(ss) * area
    m2 = np.cumsum(ss * c2) * area
    m4 = np.cumsum(ss * c4) * area
    last = np.r_[qs[1:] != qs[:-1], True]  # one entry per distinct |q|
    return qs[last], m0[last], m2[last], m4[last]


def _cutoff_kernel(s2d, t0, t2, t4, *, qx, qy, direction, weights):
    qs, m0, m2, m4 = _cumulative_moments(s2d, qx, qy, direction)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.stack([m0 / t0 - 1, m2 / t2 - 1, m4 / t4 - 1])
    cost = np.nansum(weights[:, None] * r**2, axis=0)
    cost[~np.isfinite(cost)] = np.inf
    i = int(np.argmin(cost))
    return qs[i], m0[i], m2[i], m4[i], r[0, i], r[1, i], r[2, i]


def choose_cutoff(
    psd: xr.DataArray, target: xr.Dataset, *, match=("m2", "m4"), direction: str = "mean"
) -> xr.Dataset:
    r"""Cutoff :math:`\xi_{max}` at which the PSD moments match the spatial variances (Table 3).

    Every distinct :math:`|q|` of the grid is a candidate; the one minimising the sum of
    squared relative errors of the moments in ``match`` is returned with all three residuals.

    Parameters
    ----------
    psd : xarray.DataArray
        2D ``psd`` [m4] over ``(..., qy, qx)`` (e.g. :func:`submap_psd`).
    target : xarray.Dataset
        Spatial ``m0``, ``m2``, ``m4`` (:func:`roughstick.roughness_moments`), broadcasting
        against the leading dims of ``psd``.
    match : sequence of {"m0", "m2", "m4"}
        Moments that drive the choice (default m2 and m4; m0 hardly depends on the cutoff).
    direction : {"mean", "x", "y"}
        One-direction convention, as in :func:`psd_moments`.

    Returns
    -------
    xarray.Dataset
        ``qmax`` [rad m-1], PSD moments ``m0``, ``m2``, ``m4`` at that cutoff, and
        ``residual_m0``, ``residual_m2``, ``residual_m4`` (PSD / spatial − 1).
    """
    s = _check_psd2d(psd)
    bad = [k for k in match if k not in ("m0", "m2", "m4")]
    if bad or not match:
        raise ValueError(f"match must name moments among 'm0', 'm2', 'm4', got {match!r}.")
    w = np.array([float(k in match) for k in ("m0", "m2", "m4")])
    outs = xr.apply_ufunc(
        _cutoff_kernel, s, target["m0"], target["m2"], target["m4"],
        input_core_dims=[["qy", "qx"], [], [], []], output_core_dims=[[]] * 7,
        vectorize=True, dask="parallelized", output_dtypes=[float] * 7,
        kwargs=dict(qx=s["qx"].values, qy=s["qy"].values, direction=direction, weights=w),
    )
    qmax, m0, m2, m4, r0, r2, r4 = outs
    ds = _moments_dataset(m0, m2, m4, title="PSD cutoff matching spatial variances (Table 3)")
    ds["qmax"] = qmax.assign_attrs(units="rad m-1", long_name="cutoff wave number xi_max")
    for k, r in (("m0", r0), ("m2", r2), ("m4", r4)):
        ds[f"residual_{k}"] = r.assign_attrs(units="1", long_name=f"relative error of PSD {k} vs spatial")
    append_history(ds, f"choose_cutoff: match={list(match)}, direction={direction!r}")
    return ds


def _interp_kernel(s, *, qx0, qy0, qx1, qy1):
    from scipy.interpolate import RegularGridInterpolator

    # periodic extension by one row/column: the DFT spectrum is periodic in q with period 2 q_N
    def ext(c):
        d = _dq(c)
        return np.r_[c, c[-1] + d]

    sx = np.concatenate([s, s[..., :, :1]], axis=-1)
    sx = np.concatenate([sx, sx[..., :1, :]], axis=-2)
    gy, gx = ext(qy0), ext(qx0)
    Y, X = np.meshgrid(qy1, qx1, indexing="ij")
    pts = np.column_stack([Y.ravel(), X.ravel()])
    flat = sx.reshape((-1,) + sx.shape[-2:])
    out = np.empty((flat.shape[0], qy1.size, qx1.size))
    for i, a in enumerate(flat):
        f = RegularGridInterpolator((gy, gx), a, bounds_error=False, fill_value=0.0)
        out[i] = f(pts).reshape(qy1.size, qx1.size)
    return out.reshape(s.shape[:-2] + (qy1.size, qx1.size))


def interpolate_psd(psd: xr.DataArray, *, shape, spacing=None) -> xr.DataArray:
    r"""A PSD estimated on a small map, on the finer wave-number grid of a larger map (§4.2.1).

    The paper estimates :math:`s` on 1.28 µm sub-maps (256², Δq⁰) and generates 5.12 or
    10.24 µm surfaces (Δq = Δq⁰/4 or /8) "by an interpolation process". The density is
    interpolated bilinearly in :math:`(q_y, q_x)`; the grid is extended periodically by one
    row/column (a DFT spectrum has period :math:`2q_N`), and is zero beyond the source's
    Nyquist wave number when the new ``spacing`` is finer. Moments are preserved up to the
    interpolation error of the density (tests: < 1 % on a 256² estimate → 2048²).

    Parameters
    ----------
    psd : xarray.DataArray
        2D ``psd`` [m4] ``(..., qy, qx)`` from :func:`power_spectrum`/:func:`submap_psd`, or an
        isotropic ``(..., q)`` PSD (then evaluated at :math:`|q|`, :func:`isotropic_to_2d`).
    shape : tuple of int
        ``(ny, nx)`` of the target map.
    spacing : float, optional
        Pixel size of the target map [m]; default the source's ``spacing_x``.

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4] over ``(..., qy, qx)`` of the target grid, attrs ``spacing_x``,
        ``spacing_y`` of the target.
    """
    ny, nx = (int(v) for v in shape)
    if min(ny, nx) < MIN_SIDE:
        raise ValueError(f"shape must be at least {MIN_SIDE} x {MIN_SIDE}, got {shape}.")
    if spacing is None:
        if "spacing_x" not in psd.attrs:
            raise ValueError("psd has no 'spacing_x' attribute: pass spacing= (m) of the target map.")
        dx = float(psd.attrs["spacing_x"])
        dy = float(psd.attrs.get("spacing_y", dx))
    else:
        dx = dy = float(_units.as_si(spacing, "length", name="spacing"))
    qx1 = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(nx, dx))
    qy1 = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(ny, dy))
    if "q" in psd.dims:
        out = isotropic_to_2d(psd, qx1, qy1)
    else:
        s = _check_psd2d(psd)
        out = xr.apply_ufunc(
            _interp_kernel, s, input_core_dims=[["qy", "qx"]], output_core_dims=[["qy", "qx"]],
            exclude_dims={"qy", "qx"}, dask="parallelized", output_dtypes=[float],
            dask_gufunc_kwargs={"output_sizes": {"qy": ny, "qx": nx}},
            kwargs=dict(qx0=s["qx"].values, qy0=s["qy"].values, qx1=qx1, qy1=qy1),
        )
        out = out.assign_coords(qy=qy1, qx=qx1)
    out = set_attrs(out.rename("psd"), "psd", spacing_x=dx, spacing_y=dy,
                    **_keep(psd.attrs, "references"))
    return append_history(out, f"interpolate_psd: onto the {ny} x {nx} grid of spacing {dx:.4g} m (§4.2.1)")


MIN_SIDE = 8


def psd_summary(
    height: xr.DataArray,
    *,
    n: int = 16,
    qmax=None,
    window: str | None = None,
    match=("m2", "m4"),
) -> xr.Dataset:
    r"""The paper's §4.1 chain on a set of maps: spatial variances, averaged PSD, cutoff, Eq. 32.

    Parameters
    ----------
    height : xarray.DataArray
        Levelled maps ``(..., y, x)`` of one sample (leading dims are the measurements).
    n : int
        Sub-maps per map for the PSD (Eq. 31; 16 is the paper's scheme 3).
    qmax : float, optional
        Fixed cutoff [rad m-1] (Table 3: 289 rad/µm); default: chosen by :func:`choose_cutoff`.
    window : str, optional
        Window for :func:`power_spectrum`.
    match : sequence of str
        Moments matched by :func:`choose_cutoff`.

    Returns
    -------
    xarray.Dataset
        ``psd`` (qy, qx) and ``psd_isotropic`` (q) [m4]; ``spatial_m0/m2/m4`` (mean over maps of
        the cubic-spline variances, as Table 2); ``m0/m2/m4`` PSD moments at ``qmax``;
        ``residual_*`` (PSD / spatial − 1); ``relative_std`` (Eq. 32) and ``n_maps``.
    """
    from .topography import roughness_moments, validate_height

    h = validate_height(height)
    lead = list(h.dims[:-2])
    spatial = roughness_moments(h)
    spatial = spatial.mean(lead, keep_attrs=True) if lead else spatial
    s = submap_psd(h, n=n, window=window)
    if qmax is None:
        cut = choose_cutoff(s, spatial, match=match)
    else:
        cut = psd_moments(s, qmax=qmax)
        for k in ("m0", "m2", "m4"):
            cut[f"residual_{k}"] = (cut[k] / spatial[k] - 1).assign_attrs(
                units="1", long_name=f"relative error of PSD {k} vs spatial")
    chk = submap_variance_check(h, n=n)
    ds = xr.Dataset({"psd": s, "psd_isotropic": psd_isotropic(s).rename({"n_samples": "n_ring"})})
    ds["n_ring"].attrs = {"units": "1", "long_name": "number of 2D PSD samples in the ring"}
    for k in ("m0", "m2", "m4"):
        ds[f"spatial_{k}"] = spatial[k].assign_attrs(
            long_name=f"spatial {spatial[k].attrs['long_name']} (cubic splines, mean over maps)")
        ds[k] = cut[k].assign_attrs(long_name=f"PSD moment {k} up to qmax")
        ds[f"residual_{k}"] = cut[f"residual_{k}"]
    ds["qmax"] = xr.DataArray(cut["qmax"]).assign_attrs(units="rad m-1", long_name="cutoff wave number")
    ds["relative_std"] = chk["relative_std"]
    ds.attrs = dataset_attrs(
        "PSD and roughness statistics of AFM maps (paper §4.1, Tables 2-3, Fig. 12)",
        references=cite((PAPER, "section 4.1, Eqs. 26-32"), "nayak1971"),
        n_submaps=n, n_maps=int(np.prod([h.sizes[d] for d in lead])) if lead else 1,
        window=str(window),
    )
    append_history(ds, f"psd_summary: n={n}, qmax={'chosen' if qmax is None else qmax}")
    return ds
