r"""Line scans (1-D height profiles): their PSD and their Nayak moments.

A profile is a DataArray ``height`` over ``(..., x)`` in m (no ``y``; any leading dims, e.g. the
rows ``y`` of a map, are kept). The 1-D counterpart of the windowed periodogram of Eqs. 26-31 is

.. math::

    C(q_x) = \frac{|\mathrm{FFT}(z - \bar z)|^2\,\Delta x^2}{2\pi L},\qquad
    \sum C\,\Delta q_x = \overline{(z - \bar z)^2} = m_0 ,

two-sided over :math:`q_x \in [-\pi/\Delta x, \pi/\Delta x)` (``psd_1d`` [m3]). For a surface
with 2D density :math:`s(q_x, q_y)`, every profile along :math:`x` has on average the projection

.. math::

    C(q_x) = \int s(q_x, q_y)\,dq_y
           \overset{\text{isotropic}}{=} 2\int_0^\infty s\big(\sqrt{q_x^2 + u^2}\big)\,du
           = 2\int_{|q_x|}^\infty \frac{s(q)\,q}{\sqrt{q^2 - q_x^2}}\,dq

(:func:`project_psd`), so a profile's moments :math:`m_n = \int q_x^n C\,dq_x` equal the
surface's one-direction Nayak moments (:mod:`roughstick.surface.moments`): :math:`m_0` the height
variance, :math:`m_2` the mean squared slope, :math:`m_4` the mean squared curvature of the
profile. The reverse (an isotropic 2D PSD from profiles) is an inverse Abel transform that
assumes isotropy; roughstick does not do it: contact and surface generation need a 2D map.
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from scipy.interpolate import CubicSpline

from .._core import units as _units
from .._core.conventions import append_history, dataset_attrs, set_attrs
from .._core.dask import is_lazy
from .._core.references import PAPER, cite
from .._core.validate import check_core_not_chunked, grid_spacing
from .spectrum import _check_psd2d, _dq, _get_window, _units_psd, isotropic_to_2d

__all__ = ["validate_profile", "level_profile", "profile_psd", "project_psd", "profile_moments"]

#: Smallest profile length (points) a spectrum or moments are estimated on.
MIN_POINTS = 8

_LINE_SCAN_HINT = (
    "roughstick estimates the PSD and moments of a line scan (profile_psd, profile_moments; "
    "CLI: roughstick psd); contact, ensembles and surface generation need a 2-D height map."
)


def validate_profile(profile: xr.DataArray) -> xr.DataArray:
    """Check a line scan and return it in SI.

    Parameters
    ----------
    profile : xarray.DataArray
        Heights over ``(..., x)``, units length (converted to m), uniform ascending ``x`` [m],
        at least 8 points, ``x`` in one chunk. Leading dims (a stack of profiles, or the rows
        ``y`` of a map) are kept.

    Returns
    -------
    xarray.DataArray
        ``height`` over ``(..., x)`` in m; attr ``spacing_x`` [m].
    """
    if not isinstance(profile, xr.DataArray):
        raise TypeError(f"a profile must be an xarray.DataArray over (..., 'x'), got "
                        f"{type(profile).__name__}; read a line scan with read_afm(path, line_scan=True).")
    if "x" not in profile.dims:
        raise ValueError(f"a profile must have a dim 'x' (the scan direction); got {profile.dims}. "
                         "Rename it with .rename({'<dim>': 'x'}).")
    if profile.sizes["x"] < MIN_POINTS:
        raise ValueError(f"the profile has {profile.sizes['x']} point(s); its PSD and moments need at "
                         f"least {MIN_POINTS} points.")
    p = _units.require(profile, "length", name=profile.name or "height")
    dx = grid_spacing(p, "x", min_pixels=MIN_POINTS, purpose="a profile's PSD and moments")
    check_core_not_chunked(p, ["x"])
    p = p.transpose(..., "x")
    f = _units.factor(p["x"].attrs.get("units", "m"), "length", name="coordinate x")
    if f != 1.0:
        p = p.assign_coords(x=p["x"].values * f)
    attrs = dict(p.attrs)
    p = set_attrs(p.rename("height"), "height")
    p.attrs.update({k: v for k, v in attrs.items() if k not in p.attrs})
    p.attrs.update(units="m", spacing_x=dx)
    return p


def _refuse_bad(z):
    if not np.all(np.isfinite(z)):
        raise ValueError("the profile has NaN/inf points; level it first with "
                         "level_profile(profile, nan='fill') (or crop the dropouts).")
    zz = z.reshape(-1, z.shape[-1])
    if np.any(np.ptp(zz, axis=-1) <= 1e-12 * np.maximum(np.abs(zz).max(axis=-1), np.finfo(float).tiny)):
        raise ValueError("the profile is constant (zero variance): its PSD and moments are undefined. "
                         "Check the channel and the units.")


def level_profile(profile: xr.DataArray, *, method: str = "line", nan: str = "raise") -> xr.DataArray:
    """Remove a line scan's mean (``"mean"``) or least-squares line (``"line"``, ``"plane"``).

    Parameters
    ----------
    profile : xarray.DataArray
        Heights over ``(..., x)`` (:func:`validate_profile`).
    method : {"line", "plane", "mean", "none"}
        ``"plane"`` is ``"line"`` (the CLI's default ``--level plane`` works on line scans).
    nan : {"raise", "fill"}
        NaN points: refuse, or fill by linear interpolation along ``x`` before levelling.

    Returns
    -------
    xarray.DataArray
        The levelled ``height`` [m], same dims.
    """
    if method not in ("line", "plane", "mean", "none"):
        raise ValueError(f"method must be 'line', 'plane', 'mean' or 'none', got {method!r}.")
    if nan not in ("raise", "fill"):
        raise ValueError(f"nan must be 'raise' or 'fill', got {nan!r}.")
    p = validate_profile(profile)
    z = np.array(p.values, dtype=float)
    x = p["x"].values
    flat = z.reshape(-1, z.shape[-1])
    for row in flat:
        bad = ~np.isfinite(row)
        if bad.any():
            if nan == "raise":
                raise ValueError(f"the profile has {int(bad.sum())} NaN/inf point(s); pass nan='fill' "
                                 "(CLI: --nan fill) to interpolate across them, or crop them.")
            if bad.sum() > row.size - 2:
                raise ValueError("the profile has fewer than 2 finite points; nothing to fill from.")
            row[bad] = np.interp(x[bad], x[~bad], row[~bad])
        if method in ("line", "plane"):
            row -= np.polyval(np.polyfit(x, row, 1), x)
        elif method == "mean":
            row -= row.mean()
    out = p.copy(data=z)
    return append_history(out, f"level_profile: method={method!r}, nan={nan!r}")


def profile_psd(profile: xr.DataArray, *, window: str | None = "auto") -> xr.DataArray:
    r"""1-D PSD of line scans by FFT: the 1-D counterpart of Eqs. 26-30.

    :math:`C(q_x) = |\mathrm{FFT}(z - \bar z)|^2 \Delta x^2 / (2\pi L)`, two-sided, with
    :math:`\sum C\,\Delta q_x = m_0` (Parseval, exact without a window). Average profiles (Eq. 31)
    with ``.mean(dim)``; for an isotropic surface the average is :func:`project_psd` of its 2D PSD.

    Parameters
    ----------
    profile : xarray.DataArray
        Heights over ``(..., x)`` (a line scan, a stack of them, or a map whose rows ``y`` are
        then profiles), units length, at least 8 points, no NaN. Dask-backed input stays lazy
        (``x`` in one chunk).
    window : str or None, default "auto"
        A :func:`scipy.signal.get_window` name, normalised to unit mean square. ``"auto"``: Hann
        unless the profile is marked periodic (attribute ``periodic = 1``); ``None``/``"none"``:
        no window (Parseval exact).

    Returns
    -------
    xarray.DataArray
        ``psd`` [m3] over ``(..., qx)``, ascending centred ``qx`` [rad m-1] including 0; attrs
        ``spacing_x`` [m], ``window``, ``kind = "profile"``.

    Examples
    --------
    >>> x = (np.arange(64) + 0.5) * 5e-9
    >>> z = xr.DataArray(np.sin(2 * np.pi * 3 * x / x.size / 5e-9) * 1e-9, dims="x",
    ...                  coords={"x": ("x", x, {"units": "m"})}, attrs={"units": "m"})
    >>> c = rs.surface.profile_psd(z)
    >>> bool(np.isclose(float(c.sum()) * 2 * np.pi / (64 * 5e-9), float(z.var())))
    True
    """
    p = validate_profile(profile)
    if not is_lazy(p):
        _refuse_bad(np.asarray(p.values, dtype=float))
    dx, n = p.attrs["spacing_x"], p.sizes["x"]
    if window is None or window == "none":
        window = None
    elif window == "auto":  # line scans are rarely periodic: Hann unless marked periodic
        window = None if int(p.attrs.get("periodic", 0)) == 1 else "hann"
    w = None
    if window is not None:
        w = _get_window(window, n)
        w = w / np.sqrt(np.mean(w**2))

    def kern(z):
        zc = z - z.mean(axis=-1, keepdims=True)
        if w is not None:
            zc = zc * w
        Z = np.fft.fftshift(np.fft.fft(zc, axis=-1), axes=-1)
        return (Z.real**2 + Z.imag**2) * dx / (2 * np.pi * n)

    out = xr.apply_ufunc(kern, p.astype(float), input_core_dims=[["x"]], output_core_dims=[["qx"]],
                         exclude_dims={"x"}, dask="parallelized", output_dtypes=[float],
                         dask_gufunc_kwargs={"output_sizes": {"qx": n}})
    qx = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(n, dx))
    out = out.assign_coords(qx=qx).rename("psd")
    out.attrs = {}
    out["qx"].attrs = {"units": "rad m-1", "long_name": "wave number along the profile"}
    return set_attrs(out, "psd_1d", spacing_x=dx, window=str(window), kind="profile",
                     references=cite((PAPER, "Eqs. 26-31, 1-D counterpart")))


def _check_profile_psd(psd):
    if "qx" not in psd.dims or "qy" in psd.dims:
        raise ValueError(f"expected a profile PSD over (..., 'qx') (profile_psd), got dims {psd.dims}.")
    if psd.attrs.get("units") != "m3":
        raise ValueError(f"a profile PSD has units 'm3', got {psd.attrs.get('units')!r}; convert it "
                         "to m3 (1 nm3 = 1e-27 m3).")
    check_core_not_chunked(psd, ["qx"])
    if np.any(np.diff(psd["qx"].values) <= 0):
        raise ValueError("coordinate 'qx' must be ascending (fftshift order); use psd.sortby('qx').")
    return psd.transpose(..., "qx")


def project_psd(psd: xr.DataArray, *, qx=None, direction: str = "x") -> xr.DataArray:
    r"""The profile PSD a surface's profiles have on average: :math:`C(q_x) = \int s\,dq_y`.

    Parameters
    ----------
    psd : xarray.DataArray
        2D ``psd`` [m4] over ``(..., qy, qx)`` (summed over the other axis:
        :math:`C = \sum s\,\Delta q`), or isotropic over ``(..., q)`` (integrated numerically,
        :math:`C(q_x) = 2\int_0^{u_{max}} s(\sqrt{q_x^2+u^2})\,du` with ``s`` interpolated
        log-linearly by :func:`roughstick.surface.isotropic_to_2d` and zero beyond its last ``q``).
    qx : array_like, optional
        Isotropic input only: wave numbers [rad m-1] to evaluate at (default ``±q``).
    direction : {"x", "y"}
        2D input only: profiles along x (sum over qy) or along y (sum over qx, renamed qx).

    Returns
    -------
    xarray.DataArray
        ``psd`` [m3] over ``(..., qx)``.
    """
    if direction not in ("x", "y"):
        raise ValueError(f"direction must be 'x' or 'y', got {direction!r}.")
    if "q" in psd.dims:
        s = _units_psd(psd)
        q = s["q"].values
        if np.any(np.diff(q) <= 0):
            raise ValueError("coordinate 'q' must be ascending; use psd.sortby('q').")
        qmax = float(q[-1])
        if qx is None:
            qx = np.concatenate([-q[:0:-1], q])
        qx = np.asarray(_units.as_si(qx, "wavevector", name="qx"), dtype=float).ravel()
        dq = float(np.min(np.diff(q))) / 4
        u = np.arange(0.0, qmax + dq, dq)
        two_d = isotropic_to_2d(s, qx, u)  # (..., qy=u, qx)
        w = np.full(u.size, dq)
        w[0] = dq / 2  # trapezoid on [0, umax]; s = 0 beyond qmax
        c = 2 * (two_d * xr.DataArray(w, dims="qy")).sum("qy")
        c = c.assign_coords(qx=qx)
    else:
        s = _check_psd2d(psd)
        other = "qy" if direction == "x" else "qx"
        c = s.sum(other) * _dq(s[other].values)
        if direction == "y":
            c = c.rename(qy="qx")
    c["qx"].attrs = {"units": "rad m-1", "long_name": "wave number along the profile"}
    out = set_attrs(c.rename("psd"), "psd_1d", kind="profile")
    return append_history(out, f"project_psd: profiles along {direction} of a {'isotropic' if 'q' in psd.dims else '2D'} PSD")


def _spline_moments(z, x):
    zc = z - z.mean(axis=-1, keepdims=True)
    cs = CubicSpline(x, z, axis=-1)
    return (zc**2).mean(axis=-1), cs(x, 1).var(axis=-1), cs(x, 2).var(axis=-1)


def profile_moments(data: xr.DataArray, *, method: str = "spline", qmax=None) -> xr.Dataset:
    r"""Nayak moments of line scans: :math:`m_0` (height variance), :math:`m_2` (mean squared
    slope), :math:`m_4` (mean squared curvature).

    Parameters
    ----------
    data : xarray.DataArray
        A profile ``height`` over ``(..., x)`` or its PSD ``psd`` [m3] over ``(..., qx)``:
        two-sided on a uniform grid (:func:`profile_psd`, :func:`project_psd`; summed) or
        one-sided, ``qx > 0`` only (:func:`roughstick.surface.average_psd_common`; :math:`m_n =
        2\int q_x^n C\,dq_x` by the trapezoid rule over its band).
    method : {"spline", "spectral"}
        Profile input: variances of the cubic-spline (not-a-knot) derivatives, as the paper's
        Table 2 does for maps, or :math:`m_n = \sum q_x^n C\,\Delta q_x` of its periodogram. A
        PSD is always integrated (``"spectral"``).
    qmax : float or str, optional
        Spectral only: keep :math:`|q_x| \le q_{max}` [rad m-1].

    Returns
    -------
    xarray.Dataset
        ``m0`` [m2], ``m2`` [1], ``m4`` [m-2] over the leading dims.
    """
    if method not in ("spline", "spectral"):
        raise ValueError(f"method must be 'spline' or 'spectral', got {method!r}.")
    if qmax is not None:
        qmax = float(_units.as_si(qmax, "wavevector", name="qmax"))
    if "qx" in data.dims:
        c, method = _check_profile_psd(data), "spectral"
    elif method == "spectral":
        c = profile_psd(data)
    else:
        if qmax is not None:
            raise ValueError("qmax applies to method='spectral'; the spline moments use every point.")
        p = validate_profile(data)
        z = np.asarray(p.values, dtype=float)
        _refuse_bad(z)
        m0, m2, m4 = _spline_moments(z, p["x"].values)
        lead = {d: p[d] for d in p.dims[:-1] if d in p.coords}
        m0, m2, m4 = (xr.DataArray(v, dims=p.dims[:-1], coords=lead) for v in (m0, m2, m4))
        c = None
    if c is not None:
        qx = c["qx"]
        if qmax is not None:
            c = c.where(np.abs(qx) <= qmax, 0.0)
        if np.all(qx.values > 0):  # one-sided, e.g. averaged on a log grid (average_psd_common)
            m0, m2, m4 = (2 * (c * qx**k).integrate("qx") for k in (0, 2, 4))
        else:
            steps = np.diff(qx.values)
            if np.ptp(steps) > 1e-6 * steps.mean():
                raise ValueError("a two-sided profile PSD needs a uniform qx grid (profile_psd); a "
                                 "one-sided one (qx > 0 only) is integrated by the trapezoid rule.")
            m0, m2, m4 = ((c * qx**k).sum("qx") * steps.mean() for k in (0, 2, 4))
    ds = xr.Dataset({k: set_attrs(v.rename(k), k) for k, v in (("m0", m0), ("m2", m2), ("m4", m4))})
    ds.attrs = dataset_attrs(title="profile moments")
    append_history(ds, f"profile_moments: method={method!r}, qmax={'none' if qmax is None else qmax}")
    return ds
