r"""Height maps: validation, levelling, NaN dropouts and roughness statistics (paper §3.1).

Roughness statistics follow Nayak's one-direction convention (Table 2): :math:`m_0` is the
height variance, :math:`m_2` the variance of the first derivative and :math:`m_4` that of the
second derivative along one direction. They are measured either from cubic-spline derivatives,
as the paper does, or spectrally from the PSD (:func:`roughstick.psd_moments`).

References
----------
Nayak, P. R. (1971). Random process model of rough surfaces. J. Lubr. Technol. 93, 398-407.
https://doi.org/10.1115/1.3451608

Greenwood, J. A., Williamson, J. B. P. (1966). Contact of nominally flat surfaces.
Proc. R. Soc. Lond. A 295, 300-319. https://doi.org/10.1098/rspa.1966.0242
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ._core import units as _units
from ._core.conventions import append_history, dataset_attrs, set_attrs
from ._core.dask import check_core_not_chunked, is_lazy
from ._core.materials import POLYSILICON, Material
from ._core.references import cite

__all__ = [
    "validate_height",
    "level",
    "roughness_moments",
    "asperity_statistics",
    "plasticity_index",
    "roughness_statistics",
]

MIN_PIXELS = 8
NAYAK_REFERENCE = cite("nayak1971")
GW_REFERENCE = cite("greenwood1966")


def _check_axis(da: xr.DataArray, dim: str) -> float:
    if dim not in da.dims:
        raise ValueError(
            f"height must have dims (..., 'y', 'x'); got {da.dims}. Rename with "
            f".rename({{'<row dim>': 'y', '<column dim>': 'x'}})."
        )
    n = da.sizes[dim]
    if n < MIN_PIXELS:
        raise ValueError(
            f"the map has {n} pixels along {dim!r}; roughness statistics and spectra need at least "
            f"{MIN_PIXELS} x {MIN_PIXELS} pixels."
        )
    if dim not in da.coords:
        raise ValueError(
            f"height has no {dim!r} coordinate, so its pixel size is unknown. Assign pixel centres "
            f"in m, e.g. height.assign_coords({dim}=(np.arange(n) + 0.5) * spacing), or build it "
            "with roughstick.testing.make_topography(values, spacing=...)."
        )
    c = da[dim]
    cu = c.attrs.get("units", "m")
    cvals = np.asarray(c.values, dtype=float) * _units.factor(cu, "length", name=f"coordinate {dim}")
    d = np.diff(cvals)
    if np.any(d <= 0):
        if np.all(d < 0):
            raise ValueError(
                f"coordinate {dim!r} is descending; roughstick expects ascending pixel centres. "
                f"Use height.sortby({dim!r}) (or height.isel({dim}=slice(None, None, -1)))."
            )
        raise ValueError(f"coordinate {dim!r} is not monotonic: sort it with height.sortby({dim!r}).")
    step = d.mean()
    if np.max(np.abs(d - step)) > 1e-6 * step:
        raise ValueError(
            f"coordinate {dim!r} is not uniformly spaced (steps from {d.min():.6g} to {d.max():.6g} m); "
            f"FFT spectra need a uniform grid. Interpolate first, e.g. "
            f"height.interp({dim}=np.linspace(first, last, n))."
        )
    return float(step)


def validate_height(height: xr.DataArray) -> xr.DataArray:
    """Check a height map and return it in SI with canonical attributes.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, units length (converted to m); coordinates ``x``, ``y``
        uniform and ascending; at least 8 x 8 pixels; ``x`` and ``y`` single-chunk.

    Returns
    -------
    xarray.DataArray
        ``height`` transposed to ``(..., y, x)`` in m with coordinates in m; attributes
        ``spacing_x``, ``spacing_y`` [m] added.

    Raises
    ------
    roughstick._core.units.UnitsError
        Missing or non-length ``units``.
    ValueError
        Missing, descending, non-monotonic or non-uniform coordinates; fewer than 8 pixels;
        chunked ``x``/``y``.
    """
    if not isinstance(height, xr.DataArray):
        raise TypeError(
            f"height must be an xarray.DataArray, got {type(height).__name__}; wrap arrays with "
            "roughstick.testing.make_topography(values, spacing=...) or read them with read_afm."
        )
    h = _units.require(height, "length", name=height.name or "height")
    dx = _check_axis(h, "x")
    dy = _check_axis(h, "y")
    check_core_not_chunked(h, ["x", "y"])
    h = h.transpose(..., "y", "x")
    for dim in ("x", "y"):
        cu = h[dim].attrs.get("units", "m")
        f = _units.factor(cu, "length", name=f"coordinate {dim}")
        if f != 1.0:
            h = h.assign_coords({dim: h[dim].values * f})
    attrs = dict(h.attrs)
    h = set_attrs(h.rename("height"), "height")
    h.attrs.update({k: v for k, v in attrs.items() if k not in h.attrs})
    h.attrs["units"] = "m"
    h.attrs["spacing_x"] = dx
    h.attrs["spacing_y"] = dy
    return h


# ------------------------------------------------------------------------------ levelling


def _nearest_fill(z, mask):
    from scipy.ndimage import distance_transform_edt

    idx = distance_transform_edt(mask, return_distances=False, return_indices=True)
    return z[tuple(idx)]


def _level_kernel(z, *, method, nan, max_nan_fraction, x, y):
    """Level maps over the last two axes (y, x). Returns a float array of the same shape."""
    out = np.array(z, dtype=float, copy=True)
    flat = out.reshape((-1,) + out.shape[-2:])
    X, Y = np.meshgrid(x - x.mean(), y - y.mean())
    for k in range(flat.shape[0]):
        zz = flat[k]
        bad = ~np.isfinite(zz)
        frac = bad.mean()
        if frac > max_nan_fraction:
            raise ValueError(
                f"{100 * frac:.1f} % of the map is NaN (more than max_nan_fraction="
                f"{max_nan_fraction}); it cannot be levelled reliably. Crop the valid region "
                "(height.isel(x=..., y=...)) or raise max_nan_fraction."
            )
        if bad.any() and nan == "raise":
            raise ValueError(
                f"the map has {int(bad.sum())} NaN pixels (dropouts); pass nan='fill' (nearest valid "
                "value after levelling) or nan='mask' (keep NaN; spectra then refuse the map)."
            )
        good = ~bad
        if method == "mean":
            zz = zz - zz[good].mean()
        elif method == "plane":
            A = np.column_stack([np.ones(good.sum()), X[good], Y[good]])
            coef, *_ = np.linalg.lstsq(A, zz[good], rcond=None)
            zz = zz - (coef[0] + coef[1] * X + coef[2] * Y)
        elif method == "line":
            # scan lines run along x (rows): remove a least-squares line from each row,
            # then the mean plane of the result
            xs = X[0]
            for j in range(zz.shape[0]):
                g = good[j]
                if g.sum() >= 2:
                    p = np.polyfit(xs[g], zz[j, g], 1)
                    zz[j] = zz[j] - np.polyval(p, xs)
                elif g.sum() == 1:
                    zz[j] = zz[j] - zz[j, g][0]
            zz = zz - zz[good].mean()
        if bad.any() and nan == "fill":
            zz = _nearest_fill(zz, bad)
        flat[k] = zz
    return out


def level(
    height: xr.DataArray,
    *,
    method: str = "plane",
    nan: str = "raise",
    max_nan_fraction: float = 0.5,
) -> xr.DataArray:
    """Level a height map: remove its mean, mean plane, or a line per scan line.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, units length (converted to m). Scan lines run along
        ``x``.
    method : {"plane", "mean", "line", "none"}
        ``"mean"`` subtracts the mean height; ``"plane"`` the least-squares plane; ``"line"``
        a least-squares line from each scan line (row) and then the mean (scan-line alignment,
        removes line-to-line offsets and tilts of AFM images); ``"none"`` only handles NaN.
    nan : {"raise", "fill", "mask"}
        What to do with NaN pixels (AFM dropouts). ``"fill"`` replaces them, after levelling,
        by the nearest valid pixel; ``"mask"`` keeps them as NaN (levelling ignores them; spectra
        refuse such maps). The choice and the number of NaN pixels are appended to ``history``.
    max_nan_fraction : float
        A map with a larger NaN fraction raises ``ValueError`` whatever ``nan`` says.

    Returns
    -------
    xarray.DataArray
        Levelled ``height`` [m], same dims; lazy input stays lazy (errors then surface when the
        result is computed).

    Examples
    --------
    >>> x = (np.arange(16) + 0.5) * 1e-9
    >>> tilt = rs.testing.make_topography(2e-3 * x[None, :] + 1e-3 * x[:, None], spacing=1e-9)
    >>> float(abs(rs.level(tilt)).max()) < 1e-20
    True
    """
    if method not in ("plane", "mean", "line", "none"):
        raise ValueError(f"method must be 'plane', 'mean', 'line' or 'none', got {method!r}.")
    if nan not in ("raise", "fill", "mask"):
        raise ValueError(f"nan must be 'raise', 'fill' or 'mask', got {nan!r}.")
    h = validate_height(height)
    x = h["x"].values
    y = h["y"].values
    out = xr.apply_ufunc(
        _level_kernel, h, input_core_dims=[["y", "x"]], output_core_dims=[["y", "x"]],
        dask="parallelized", output_dtypes=[float],
        kwargs=dict(method=method, nan=nan, max_nan_fraction=max_nan_fraction, x=x, y=y),
    )
    out.attrs = dict(h.attrs)
    out = out.rename("height")
    line = f"level: method={method!r}"
    if not is_lazy(h):
        n_nan = int(np.count_nonzero(~np.isfinite(h.data)))
        frac = n_nan / h.size
        if n_nan:
            what = "filled with the nearest valid pixel" if nan == "fill" else "kept as NaN (masked)"
            line += f"; {n_nan} NaN pixels ({100 * frac:.3g} %) {what}"
    else:
        line += f"; NaN pixels (counted at compute time) handled with nan={nan!r}"
    append_history(out, line)
    return out


# ------------------------------------------------------------------------ roughness moments


def _spline_moments_kernel(z, *, x, y, direction):
    """(m0, m2, m4) over the last two axes by cubic-spline derivatives (not-a-knot)."""
    from scipy.interpolate import CubicSpline

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
    window=None,
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
        (:func:`roughstick.psd_moments`), optionally cut at ``qmax``.
    direction : {"mean", "x", "y"}
        One-direction moments along ``x``, ``y``, or their mean (isotropic estimate).
    qmax : float, optional
        Spectral only: cutoff wave number [rad m-1].
    window : str, optional
        Spectral only: window of :func:`roughstick.power_spectrum`.

    Returns
    -------
    xarray.Dataset
        ``m0`` [m2], ``m2`` [1], ``m4`` [m-2] over the leading dims of ``height``.

    Notes
    -----
    The two methods agree on smooth maps (tests). On rough maps sampled near their smallest
    features the spline derivatives and the periodic spectral derivatives differ, which is
    why the paper introduces the cutoff :math:`\xi_{max}` (Table 3, :func:`roughstick.choose_cutoff`).
    """
    if direction not in ("mean", "x", "y"):
        raise ValueError(f"direction must be 'mean', 'x' or 'y', got {direction!r}.")
    if method == "spectral":
        from .psd import power_spectrum, psd_moments

        return psd_moments(power_spectrum(height, window=window), qmax=qmax, direction=direction)
    if method != "spline":
        raise ValueError(f"method must be 'spline' or 'spectral', got {method!r}.")
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


def _refuse_constant_or_nan(h: xr.DataArray) -> None:
    """Eager inputs only: NaN pixels and constant maps raise (lazy ones are not computed)."""
    if is_lazy(h):
        return
    z = h.data
    if not np.all(np.isfinite(z)):
        raise ValueError(
            "the height map has NaN/inf pixels; level it first with "
            "roughstick.level(height, nan='fill') (or crop the dropouts)."
        )
    zz = z.reshape((-1,) + z.shape[-2:])
    spread = zz.max(axis=(-2, -1)) - zz.min(axis=(-2, -1))
    scale = np.maximum(np.abs(zz).max(axis=(-2, -1)), np.finfo(float).tiny)
    if np.any(spread <= 1e-12 * scale):
        raise ValueError(
            "the height map is constant (zero variance): it has no roughness, so moments, "
            "summit statistics and spectra are undefined. Check the channel and the units."
        )


# ------------------------------------------------------------------------- asperity stats


def _as_moments(moments) -> tuple:
    if not isinstance(moments, xr.Dataset) or not {"m0", "m2", "m4"} <= set(moments.data_vars):
        raise TypeError("moments must be a Dataset with m0, m2, m4 (roughness_moments or psd_moments).")
    return moments["m0"], moments["m2"], moments["m4"]


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
        ``m0``, ``m2``, ``m4`` (e.g. :func:`roughness_moments`, :func:`roughstick.psd_moments`).

    Returns
    -------
    xarray.Dataset
        ``summit_density`` [m-2], ``summit_radius`` [m], ``bandwidth`` [1],
        ``summit_height_std`` [m], plus the moments.

    Examples
    --------
    >>> m = rs.moments_from_asperities(roughness=3.54e-9, radius=220e-9, density=80.1e12)
    >>> s = rs.asperity_statistics(m)
    >>> round(float(s.summit_density) * 1e-12, 1), round(float(s.summit_radius) * 1e9)
    (80.1, 220)
    """
    m0, m2, m4 = _as_moments(moments)
    n = m4 / (6 * np.pi * np.sqrt(3) * m2)
    r = 3 * np.sqrt(np.pi) / (8 * np.sqrt(m4))
    a = m0 * m4 / m2**2
    sig = np.sqrt(((1 - 0.8968 / a) * m0).where(a >= 0.8968))
    ds = xr.Dataset({
        "m0": m0, "m2": m2, "m4": m4,
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


def roughness_statistics(
    height: xr.DataArray,
    *,
    method: str = "spline",
    direction: str = "mean",
    qmax=None,
) -> xr.Dataset:
    """Table 2/3-style statistics of height maps: moments, rms values and summit statistics.

    Parameters
    ----------
    height : xarray.DataArray
        Levelled topography, dims ``(..., y, x)``, units length.
    method, direction, qmax
        As in :func:`roughness_moments`.

    Returns
    -------
    xarray.Dataset
        ``m0``, ``m2``, ``m4``, ``rms_height`` [m], ``rms_slope`` [1], ``skewness``,
        ``kurtosis`` [1], and the fields of :func:`asperity_statistics`.
    """
    m = roughness_moments(height, method=method, direction=direction, qmax=qmax)
    ds = asperity_statistics(m)
    h = validate_height(height)
    zc = h - h.mean(("y", "x"))
    sd = np.sqrt((zc**2).mean(("y", "x")))
    ds["rms_height"] = np.sqrt(ds.m0).assign_attrs(units="m", long_name="rms height sqrt(m0)")
    ds["rms_slope"] = np.sqrt(ds.m2).assign_attrs(units="1", long_name="rms slope sqrt(m2)")
    ds["skewness"] = ((zc**3).mean(("y", "x")) / sd**3).assign_attrs(
        units="1", long_name="height skewness")
    ds["kurtosis"] = ((zc**4).mean(("y", "x")) / sd**4).assign_attrs(
        units="1", long_name="height kurtosis")
    ds.attrs = dataset_attrs(f"roughness statistics ({method})", references=NAYAK_REFERENCE,
                             direction=direction)
    append_history(ds, f"roughness_statistics: method={method!r}, direction={direction!r}")
    return ds
