r"""THE home of Nayak's moments :math:`m_0, m_2, m_4` and of the statistics derived from them.

One estimator of each kind, by name:

- of a height map, :func:`roughness_moments` with ``method="spline"`` (the paper's Table 2:
  variances of cubic-spline derivatives, not-a-knot) or ``method="spectral"`` (Table 3: integrals
  of the periodogram, optionally cut at ``qmax``);
- of a PSD (2D or isotropic), :func:`psd_moments`;
- of the self-affine PSD of Eq. 37 in closed form, :func:`self_affine_moments`;
- from roughness, summit radius and summit density (Table 4), :func:`moments_from_asperities`;
- the cutoff at which a PSD's moments match a map's, :func:`choose_cutoff` (Table 3).

Conventions (docs/architecture.md): :math:`m_0` is the height variance, :math:`m_2` and :math:`m_4` the
variances of the first and second derivatives along one direction; for a 2D density
:math:`m_2 = \iint q_x^2 s`, :math:`m_4 = \iint q_x^4 s`; for an isotropic :math:`s(q)`:
:math:`m_0 = 2\pi\int s q\,dq`, :math:`m_2 = \pi\int s q^3 dq`,
:math:`m_4 = \tfrac{3\pi}{4}\int s q^5 dq`. :func:`asperity_statistics` and
:func:`plasticity_index` turn moments into Nayak's summit statistics and GW's Eq. 15.

References
----------
Nayak (1971), doi:10.1115/1.3451608; Greenwood and Williamson (1966), doi:10.1098/rspa.1966.0242.
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from scipy.interpolate import CubicSpline

from .._core import units as _units
from .._core.conventions import append_history, dataset_attrs, set_attrs
from .._core.dask import is_lazy
from .._core.materials import POLYSILICON, Material, as_material
from .._core.references import cite
from .._core.validate import check_core_not_chunked, check_moments, check_positive_block, moments_si
from .spectrum import _check_psd2d, _dq, _units_psd, _wavevector, power_spectrum
from .topography import _refuse_constant_or_nan, validate_height

__all__ = [
    "summit_density",
    "roughness_moments",
    "psd_moments",
    "self_affine_moments",
    "moments_from_asperities",
    "choose_cutoff",
    "asperity_statistics",
    "plasticity_index",
]

NAYAK_REFERENCE = cite("nayak1971")

GW_REFERENCE = cite("greenwood1966")


def _moments_dataset(m0, m2, m4, *, title: str, **extra_vars) -> xr.Dataset:
    def wrap(v, key):
        da = v if isinstance(v, xr.DataArray) else xr.DataArray(v)
        return set_attrs(da.rename(key), key)

    ds = xr.Dataset({"m0": wrap(m0, "m0"), "m2": wrap(m2, "m2"), "m4": wrap(m4, "m4")})
    for k, v in extra_vars.items():
        ds[k] = v
    ds.attrs = dataset_attrs(title, references=NAYAK_REFERENCE)
    return ds


def _show_q(qmax) -> str:
    return f"{float(qmax):.4g}" if np.ndim(qmax) == 0 and not is_lazy(qmax) else "(given)"


def summit_density(moments: xr.Dataset) -> xr.DataArray:
    r"""Number of summits per unit area, :math:`N = m_4 / (6\pi\sqrt3\, m_2)` (Nayak 1971).

    Parameters
    ----------
    moments : xarray.Dataset
        ``m0`` (m2), ``m2`` (1), ``m4`` (m-2), any dims (docs/architecture.md).

    Returns
    -------
    xarray.DataArray
        :math:`N` [m-2].

    References
    ----------
    Nayak (1971), https://doi.org/10.1115/1.3451608

    Examples
    --------
    >>> ds = xr.Dataset({"m0": ((), 15.7e-18, {"units": "m2"}), "m2": ((), 0.040, {"units": "1"}),
    ...                  "m4": ((), 5.08e-4, {"units": "nm-2"})})
    >>> round(float(rs.surface.summit_density(ds)) * 1e-12, 2)  # per square micrometre
    388.99
    """
    _, m2, m4 = moments_si(moments)
    out = m4 / (6.0 * np.pi * np.sqrt(3.0) * m2)
    return set_attrs(out.rename("summit_density"), "summit_density", references=NAYAK_REFERENCE)



# ------------------------------------------------------------------------ moments of a map


def _spline_moments_kernel(z, *, x, y, direction):
    """(m0, m2, m4) over the last two axes by cubic-spline derivatives (not-a-knot)."""
    z = np.asarray(z, dtype=float)
    zc = z - z.mean(axis=(-2, -1), keepdims=True)
    m0 = (zc**2).mean(axis=(-2, -1))
    res2, res4 = [], []
    if direction in ("x", "mean"):
        cs = CubicSpline(x, z, axis=-1)
        d1, d2 = cs(x, 1), cs(x, 2)
        res2.append(d1.var(axis=(-2, -1)))
        res4.append(d2.var(axis=(-2, -1)))
    if direction in ("y", "mean"):
        cs = CubicSpline(y, z, axis=-2)
        d1, d2 = cs(y, 1), cs(y, 2)
        res2.append(d1.var(axis=(-2, -1)))
        res4.append(d2.var(axis=(-2, -1)))
    return m0, np.mean(res2, axis=0), np.mean(res4, axis=0)


def roughness_moments(
    height: xr.DataArray,
    *,
    method: str = "spline",
    direction: str = "mean",
    qmax=None,
    window="auto",
) -> xr.Dataset:
    r"""Nayak moments :math:`m_0, m_2, m_4` of a height map (Table 2).

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, units length; no NaN (use :func:`level` with
        ``nan="fill"``).
    method : {"spline", "spectral"}
        ``"spline"``: the paper's method, derivatives of a cubic-spline interpolant
        (not-a-knot) along each scan line, :math:`m_2 = \mathrm{var}(\partial z/\partial x)`,
        :math:`m_4 = \mathrm{var}(\partial^2 z/\partial x^2)`. ``"spectral"``:
        :math:`m_2 = \iint q_x^2 s`, :math:`m_4 = \iint q_x^4 s` over the 2D PSD
        (:func:`roughstick.surface.psd_moments`), optionally cut at ``qmax``.
    direction : {"mean", "x", "y"}
        One-direction moments along ``x``, ``y``, or their mean (isotropic estimate).
    qmax : float, optional
        Spectral only: cutoff wave number [rad m-1].
    window : str or None, default "auto"
        Spectral only: window of :func:`roughstick.surface.power_spectrum` (``"auto"``: Hann unless the
        map is periodic).

    Returns
    -------
    xarray.Dataset
        ``m0`` [m2], ``m2`` [1], ``m4`` [m-2] over the leading dims of ``height``.

    Notes
    -----
    The two methods agree on smooth maps (tests). On rough maps sampled near their smallest
    features the spline derivatives and the periodic spectral derivatives differ, which is
    why the paper introduces the cutoff :math:`\xi_{max}` (Table 3, :func:`roughstick.surface.choose_cutoff`).
    """
    if direction not in ("mean", "x", "y"):
        raise ValueError(f"direction must be 'mean', 'x' or 'y', got {direction!r}.")
    if method == "spectral":
        return psd_moments(power_spectrum(height, window=window), qmax=qmax, direction=direction)
    if method != "spline":
        raise ValueError(f"method must be 'spline' or 'spectral', got {method!r}.")
    if qmax is not None or window not in (None, "auto"):
        raise ValueError(
            "qmax and window apply to method='spectral' only (the spline moments use every "
            "pixel); pass method='spectral' to cut the periodogram at qmax."
        )
    h = validate_height(height)
    _refuse_constant_or_nan(h)
    m0, m2, m4 = xr.apply_ufunc(
        _spline_moments_kernel, h, input_core_dims=[["y", "x"]], output_core_dims=[[], [], []],
        dask="parallelized", output_dtypes=[float] * 3,
        kwargs=dict(x=h["x"].values, y=h["y"].values, direction=direction),
    )
    ds = xr.Dataset({
        "m0": set_attrs(m0.rename("m0"), "m0"),
        "m2": set_attrs(m2.rename("m2"), "m2"),
        "m4": set_attrs(m4.rename("m4"), "m4"),
    })
    ds.attrs = dataset_attrs("roughness moments (cubic-spline derivatives)",
                             references=NAYAK_REFERENCE, direction=direction)
    append_history(ds, f"roughness_moments: method='spline', direction={direction!r}")
    return ds


# ------------------------------------------------------------------------ moments of a PSD


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

    Raises
    ------
    ValueError
        A q grid that is not ascending, negative PSD values, or (eager PSDs) a moment that comes
        out zero (no power, or none below ``qmax``) or not finite (NaN or inf values): the
        message names which.
    """
    if direction not in ("mean", "x", "y"):
        raise ValueError(f"direction must be 'mean', 'x' or 'y', got {direction!r}.")
    if qmax is not None:
        qmax = _wavevector(qmax, name="qmax")
    if "qx" in psd.dims and "qy" not in psd.dims:
        raise ValueError("this is a profile (1-D) PSD over qx; its moments are "
                         "roughstick.surface.profile_moments(psd) (m_n = sum qx^n C dqx).")
    if "q" in psd.dims:
        s = _units_psd(psd)
        check_core_not_chunked(s, ["q"])
        q = s["q"]
        qv = np.asarray(q.values, dtype=float)
        if qv.size < 2 or np.any(np.diff(qv) <= 0) or qv[0] < 0:
            raise ValueError(
                "the isotropic PSD's coordinate 'q' must be >= 0 and strictly ascending with at "
                "least 2 points (a descending grid gives negative moments); use psd.sortby('q')."
            )
        if not is_lazy(s) and np.any(np.asarray(s.values) < 0):
            raise ValueError(
                "the PSD has negative values; a power spectral density is non-negative. Clip "
                "round-off with psd.clip(min=0)."
            )
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
    cut = "" if qmax is None else f"; qmax={_show_q(qmax)} rad m-1 (289 rad/um is 2.89e8)"
    if qmax is not None and "q" in psd.dims:
        cut += f", the PSD's q start at {float(np.min(qv[qv > 0], initial=np.inf)):.4g}"
    check_moments(m0, m2, m4, what="psd_moments", fix=(
        "Check the PSD's values (non-zero, finite: drop or fill NaN with psd.dropna or "
        f"psd.fillna(0)) and its q coordinate in rad m-1{cut}."))
    ds = _moments_dataset(m0, m2, m4, title="PSD moments")
    if qmax is not None:
        qm = qmax if isinstance(qmax, xr.DataArray) else xr.DataArray(qmax)
        ds["qmax"] = qm.assign_attrs(units="rad m-1", long_name="cutoff wave number")
    append_history(ds, f"psd_moments: qmax={'none' if qmax is None else 'set'}, direction={direction!r}")
    return ds


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
    >>> m = rs.surface.self_affine_moments(s0=6.46e-33, s1=6.29e-39, q0=19.4e6, qmax=289e6)
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


def moments_from_asperities(*, roughness, radius, density) -> xr.Dataset:
    r"""PSD moments from roughness, mean summit radius and summit density (Table 4, Nayak).

    .. math::

        m_0 = \sum_i \sigma_i^2,\qquad
        m_4 = \left(\frac{3\sqrt{\pi}}{8R}\right)^2,\qquad
        m_2 = \frac{m_4}{6\sqrt{3}\,\pi N}.

    The summit relations are Nayak's for a Gaussian surface (mean summit curvature
    :math:`8\sqrt{m_4}/(3\sqrt\pi)` at high bandwidth; summit density
    :math:`N = m_4/(6\pi\sqrt{3} m_2)`). Table 4 prints :math:`\mu_4 = 3\sqrt\pi/(8R)` without
    the square; the square is what gives its 9.1 µm⁻².

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
    >>> m = rs.surface.moments_from_asperities(roughness=[2.6e-9, 2.4e-9], radius=220e-9, density=80.1e12)
    >>> round(float(m.m0) ** 0.5 * 1e9, 2), round(float(m.m2), 5), round(float(m.m4) * 1e-12, 2)
    (3.54, 0.00349, 9.13)
    """
    r = np.atleast_1d(np.asarray(roughness, dtype=float))
    if r.size == 0:
        raise ValueError("roughness is empty: give one RMS roughness [m] per surface, e.g. [2.6e-9, 2.4e-9].")
    check_positive_block(r, "roughness", "Lengths in m.", finite=True)
    check_positive_block(radius, "radius", "A length in m.", finite=True)
    check_positive_block(density, "density", "Summits per m2.", finite=True)
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


# ------------------------------------------------------------------------ cutoff (Table 3)


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
        Spatial ``m0``, ``m2``, ``m4`` (:func:`roughstick.surface.roughness_moments`), broadcasting
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


# ------------------------------------------------------------------------ summit statistics


def asperity_statistics(moments: xr.Dataset) -> xr.Dataset:
    r"""Nayak summit statistics from the moments.

    .. math::

        N = \frac{m_4}{6\pi\sqrt{3}\,m_2},\qquad
        R = \frac{3\sqrt{\pi}}{8\sqrt{m_4}},\qquad
        \alpha = \frac{m_0 m_4}{m_2^2},\qquad
        \sigma_s = \sqrt{(1 - 0.8968/\alpha)\, m_0}.

    :math:`R` is the inverse mean summit curvature in the high-bandwidth limit, the relation
    Table 4 uses; :math:`\sigma_s` is the standard deviation of summit heights (Nayak's
    large-α result as used by McCool, 1986; NaN when α < 0.8968).

    Parameters
    ----------
    moments : xarray.Dataset
        ``m0``, ``m2``, ``m4`` (e.g. :func:`roughness_moments`, :func:`roughstick.surface.psd_moments`).

    Returns
    -------
    xarray.Dataset
        ``summit_density`` [m-2], ``summit_radius`` [m], ``bandwidth`` [1],
        ``summit_height_std`` [m], plus the moments.

    Examples
    --------
    >>> m = rs.surface.moments_from_asperities(roughness=3.54e-9, radius=220e-9, density=80.1e12)
    >>> s = rs.surface.asperity_statistics(m)
    >>> round(float(s.summit_density) * 1e-12, 1), round(float(s.summit_radius) * 1e9)
    (80.1, 220)
    """
    m0, m2, m4 = moments_si(moments)
    n = summit_density(moments)
    r = 3 * np.sqrt(np.pi) / (8 * np.sqrt(m4))
    a = m0 * m4 / m2**2
    sig = np.sqrt(((1 - 0.8968 / a) * m0).where(a >= 0.8968))
    ds = xr.Dataset({
        "m0": set_attrs(m0, "m0"), "m2": set_attrs(m2, "m2"), "m4": set_attrs(m4, "m4"),
        "summit_density": set_attrs(n.rename("summit_density"), "summit_density"),
        "summit_radius": set_attrs(r.rename("summit_radius"), "summit_radius"),
        "bandwidth": set_attrs(a.rename("bandwidth"), "bandwidth"),
        "summit_height_std": sig.rename("summit_height_std").assign_attrs(
            units="m", long_name="standard deviation of summit heights"),
    })
    ds.attrs = dataset_attrs("Nayak summit statistics", references=NAYAK_REFERENCE)
    return ds


def plasticity_index(
    moments: xr.Dataset,
    *,
    material: Material = POLYSILICON,
    hardness: float | None = None,
    summit_height_std=None,
) -> xr.DataArray:
    r"""Greenwood–Williamson plasticity index, Eq. 15.

    .. math:: \Psi = \frac{E}{2(1-\nu^2) H}\sqrt{\frac{\sigma_s}{R}}

    with :math:`R` the mean summit radius and :math:`\sigma_s` the standard deviation of the
    summit heights (:func:`asperity_statistics`). :math:`\Psi < 0.6`: elastic; > 1: plastic.

    Parameters
    ----------
    moments : xarray.Dataset
        ``m0``, ``m2``, ``m4``.
    material : roughstick.Material
        Young's modulus and Poisson ratio (default poly-silicon, 164 GPa, 0.23).
    hardness : float, optional
        Hardness H [Pa]; defaults to ``material.hardness`` (required one way or the other).
    summit_height_std : float, optional
        :math:`\sigma_s` [m]; default from Nayak's bandwidth formula.

    Returns
    -------
    xarray.DataArray
        ``plasticity_index`` [1].

    References
    ----------
    Greenwood and Williamson (1966), https://doi.org/10.1098/rspa.1966.0242
    """
    material = as_material(material)
    H = hardness if hardness is not None else material.hardness
    if H is None or not H > 0:
        raise ValueError(
            "plasticity_index needs a positive hardness in Pa: pass hardness=... or a Material "
            "with hardness set (e.g. roughstick.Material(hardness=10e9))."
        )
    st = asperity_statistics(moments)
    sig = st.summit_height_std if summit_height_std is None else summit_height_std
    e = material.youngs_modulus / (2 * (1 - material.poisson_ratio**2))
    psi = e / H * np.sqrt(sig / st.summit_radius)
    out = set_attrs(xr.DataArray(psi).rename("plasticity_index"), "plasticity_index",
                    references=GW_REFERENCE)
    return out
