r"""Power spectral densities of height maps (paper §4.1, Eqs. 26-32).

Normalisation (docs/architecture.md): the 2D density :math:`s(q_x, q_y)` [m4]
integrates to the height variance,

.. math:: \iint s \, dq_x \, dq_y = m_0 ,

so for an :math:`N_y \times N_x` map of spacing :math:`\Delta`,
``psd = abs(fft2(z))**2 * dx**2 * dy**2 / ((2π)**2 * Lx * Ly)`` with :math:`L = N\Delta`.
An isotropic PSD ``(..., q)`` is the same 2D density on the ring :math:`|q| = q`. The moments of a
PSD are in :mod:`roughstick.surface.moments`, the self-affine PSD of Eq. 37 in
:mod:`roughstick.surface.self_affine`.
"""

from __future__ import annotations

import dask.array.fft
import numpy as np
import xarray as xr
from scipy import sparse
from scipy.interpolate import RegularGridInterpolator
from scipy.signal import get_window

from .._core import units as _units
from .._core.arguments import check_numbers
from .._core.conventions import append_history, dataset_attrs, set_attrs
from .._core.dask import is_lazy
from .._core.references import PAPER, cite
from .._core.validate import MIN_MAP_PIXELS, check_core_not_chunked
from .topography import _refuse_constant_or_nan, validate_height

__all__ = [
    "power_spectrum",
    "psd_isotropic",
    "average_psd",
    "submap_psd",
    "submap_variance_check",
    "interpolate_psd",
    "isotropic_to_2d",
]


def _wavevector(value, *, name: str):
    return _units.as_si(value, "wavevector", name=name)


def _keep(attrs, *keys):
    return {k: attrs[k] for k in keys if k in attrs}


def _units_psd(psd):
    return _units.require(psd, "length4", name=psd.name or "psd")


def _dq(c):
    return float(np.mean(np.diff(np.asarray(c, dtype=float))))


# --------------------------------------------------------------------------------------------
# PSD estimation (Eqs. 26-30), averaging (Eq. 31), sub-maps (Eq. 32)
# --------------------------------------------------------------------------------------------


def _fft_module(data):
    return dask.array.fft if is_lazy(data) else np.fft


def _get_window(name, n):
    try:
        return get_window(name, n, fftbins=True)
    except (ValueError, TypeError) as err:
        raise ValueError(
            f"unknown FFT window {name!r} ({err}); use 'auto' (Hann unless the map is periodic), "
            "'none', or a scipy.signal.get_window name such as 'hann' or 'blackman'."
        ) from None


def _window_2d(name, ny, nx):
    wy = _get_window(name, ny)
    wx = _get_window(name, nx)
    w = np.outer(wy, wx)
    return w / np.sqrt(np.mean(w**2))


def _resolve_window(window, height):
    """``"auto"``: Hann unless the map is periodic (attribute ``periodic = 1``); ``"none"``: None."""
    if window is None or (isinstance(window, str) and window == "none"):
        return None
    if isinstance(window, str) and window == "auto":
        return None if int(height.attrs.get("periodic", 0)) == 1 else "hann"
    return window


def power_spectrum(height: xr.DataArray, *, window: str | None = "auto") -> xr.DataArray:
    r"""2D power spectral density of height maps by FFT (Eqs. 26-30).

    .. math::

        s(q_x, q_y) = \frac{|\mathrm{FFT}(z - \bar z)|^2 \, \Delta x^2 \Delta y^2}
                           {(2\pi)^2 L_x L_y},\qquad
        \sum s \, \Delta q_x \Delta q_y = \overline{(z - \bar z)^2} = m_0

    (Parseval, exact without a window). The paper's Eq. 26 omits the :math:`(2\pi)^2`; this
    normalisation makes :math:`\iint s = m_0` as in its Tables 3 and 4.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, units length (converted to m), uniform ascending
        coords, at least 8 x 8, odd and non-square sizes allowed, no NaN. A stack ``(..., y, x)``
        backed by dask stays lazy (``x`` and ``y`` must each be one chunk).
    window : str or None, default "auto"
        A :func:`scipy.signal.get_window` name (e.g. ``"hann"``) applied separably; it is
        normalised to unit mean square so that the expected variance is kept (Parseval then
        holds only on average). ``"auto"``: no window on a periodic map (attribute
        ``periodic = 1``, e.g. generated surfaces: Parseval exact), Hann otherwise (measured
        scans, whose opposite edges do not match: without a window the edge step leaks power to
        high q and inflates m2 and m4, by up to +112 % and +1368 % on 128² crops of the five
        surface families at qmax = 289 rad/µm; Hann keeps them within 11 % and 6 %,
        docs/topography_psd.md). ``None`` or ``"none"``: no window (the paper's Table 3).

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4] over ``(..., qy, qx)``, ascending centred coords [rad m-1] including 0;
        attrs ``spacing_x``, ``spacing_y`` [m] and ``window``.

    Raises
    ------
    ValueError
        Bad coordinates or sizes (see :func:`roughstick.surface.validate_height`), chunked x/y, and, for
        eager input, NaN pixels or a constant map.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> h = rs.testing.make_topography(rng.normal(size=(12, 10)) * 1e-9, spacing=5e-9)
    >>> s = rs.surface.power_spectrum(h)
    >>> dqx, dqy = 2 * np.pi / (10 * 5e-9), 2 * np.pi / (12 * 5e-9)
    >>> s.dims, bool(np.isclose(float(s.sum()) * dqx * dqy, float(h.var())))
    (('qy', 'qx'), True)
    """
    h = validate_height(height)
    _refuse_constant_or_nan(h)
    window = _resolve_window(window, h)
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
        try:
            psd = xr.concat(list(psd), dim=name, join="exact", combine_attrs="drop_conflicts")
        except ValueError as exc:
            raise ValueError(f"the PSDs have different q grids ({exc}); maps of different sizes "
                             "or spacings are averaged by roughstick.surface.average_psd_common(psds) on a "
                             "common log-spaced q grid.") from exc
    dims = [dim] if isinstance(dim, str) else list(dim)
    missing = [d for d in dims if d not in psd.dims]
    if missing:
        raise ValueError(f"cannot average over {missing}: psd has dims {psd.dims}.")
    n = int(np.prod([psd.sizes[d] for d in dims]))
    key = ("psd_isotropic" if "q" in psd.dims else "psd_1d" if "qy" not in psd.dims and "qx" in psd.dims
           else "psd")
    out = set_attrs(psd.mean(dims).rename("psd"), key,
                    **_keep(psd.attrs, "spacing_x", "spacing_y", "window", "kind"), n_averaged=n)
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


@check_numbers(n="count")
def submap_psd(
    height: xr.DataArray, *, n: int = 16, average_dims=None, window: str | None = "auto"
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
    window : str or None, default "auto"
        Window passed to :func:`power_spectrum`; ``"auto"`` is Hann whenever ``n > 1`` (tiles
        are never periodic) or the map is not periodic.

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4] over ``(..., qy, qx)`` on the sub-map wave-number grid; attrs
        ``n_averaged``, ``n_submaps``.
    """
    h = validate_height(height)
    if isinstance(window, str) and window == "auto" and n > 1:
        window = "hann"  # a tile of a periodic map is not periodic
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


@check_numbers(n="count", threshold="positive")
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
# interpolation onto a larger map (§4.2.1) and isotropic -> 2D
# --------------------------------------------------------------------------------------------


def _interp_kernel(s, *, qx0, qy0, qx1, qy1):
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
    if min(ny, nx) < MIN_MAP_PIXELS:
        raise ValueError(f"shape must be at least {MIN_MAP_PIXELS} x {MIN_MAP_PIXELS}, got {shape}.")
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
