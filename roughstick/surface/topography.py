r"""Height maps: validation, levelling and NaN dropouts (paper §3.1).

A height map is a DataArray ``height`` over ``(..., y, x)`` in m with uniform ascending pixel-centre
coordinates (docs/architecture.md). :func:`validate_height` checks one and returns it in SI;
:func:`level` removes its mean, mean plane or scan-line offsets and handles NaN pixels. Roughness
statistics of a map are in :mod:`roughstick.surface.moments`.
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from .._core import units as _units
from .._core.arguments import check_numbers
from .._core.conventions import append_history, set_attrs
from .._core.dask import is_lazy
from .._core.levelling import level_kernel as _level_kernel
from .._core.validate import (
    MIN_MAP_PIXELS,
    check_core_not_chunked,
    check_has_roughness,
    check_height_dtype,
    check_plausible_height,
    external_stacklevel,
    grid_spacing,
)

__all__ = ["validate_height", "level"]


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
        chunked ``x``/``y``; values implausible in SI for a MEMS map (pixels over 1 mm, e.g.
        coordinates in nm or pixel indices without ``units``; rms height over 1 mm, e.g. nm
        labelled m): the message names the fix.
    TypeError
        Not a DataArray; a dtype a height map cannot have (bool, complex, object, text).
    """
    if not isinstance(height, xr.DataArray):
        raise TypeError(
            f"height must be an xarray.DataArray, got {type(height).__name__}; wrap arrays with "
            "roughstick.testing.make_topography(values, spacing=...) or read them with read_afm."
        )
    check_height_dtype(height)
    h = _units.require(height, "length", name=height.name or "height")
    dx = grid_spacing(h, "x", min_pixels=MIN_MAP_PIXELS)
    dy = grid_spacing(h, "y", min_pixels=MIN_MAP_PIXELS)
    check_plausible_height(h, dx, dy)
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


@check_numbers(max_nan_fraction="fraction01")
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
    >>> float(abs(rs.surface.level(tilt)).max()) < 1e-20
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
    if method != "none":
        out.attrs["levelling"] = method
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


def is_periodic(height: xr.DataArray) -> bool:
    """Whether a map wraps around (``attrs['periodic']`` 1, as generated surfaces are)."""
    return str(height.attrs.get("periodic", 0)).strip().lower() in ("1", "true")


def level_unless_periodic(height: xr.DataArray) -> xr.DataArray:
    """A measured map levelled by its least-squares plane; a periodic map (a generated surface,
    which has no instrument tilt and whose long waves are its roughness) or a map levelled
    already (``attrs['levelling']``, e.g. by :func:`roughstick.io.read_afm`) as it is: the rule
    of ``read_afm(levelling="auto")``."""
    h = validate_height(height)
    done = str(h.attrs.get("levelling", "none")) != "none"
    return h if is_periodic(h) or done else level(h, method="plane")


def _refuse_constant_or_nan(h: xr.DataArray) -> None:
    """Eager inputs only: NaN pixels and constant maps raise (lazy ones are not computed)."""
    if is_lazy(h):
        return
    z = h.data
    check_has_roughness(z)  # first: levelling cannot rescue a map without roughness
    if not np.all(np.isfinite(z)):
        raise ValueError(
            "the height map has NaN/inf pixels; level it first with "
            "roughstick.surface.level(height, nan='fill') (or crop the dropouts)."
        )


#: Maps whose rms heights or correlation lengths differ by more than this factor are not said to
#: be of one surface when they are averaged (:func:`warn_if_incompatible`).
COMPATIBLE_RATIO = 2.0


class IncompatibleMapsWarning(UserWarning):
    """Maps averaged into one PSD differ more than maps of one surface do."""


def autocorrelation_length(height: xr.DataArray, *, threshold: float = 0.2) -> float:
    r"""The autocorrelation length :math:`S_{al}` [m] of one map (ISO 25178-2): the shortest
    horizontal distance at which its areal autocorrelation falls to ``threshold``.

    The autocorrelation is that of the map padded with zeros to twice its size (no wrap-round),
    normalised by the overlap, on the pixel grid.

    Examples
    --------
    >>> y, x = np.meshgrid(np.arange(64), np.arange(64), indexing="ij")
    >>> h = rs.testing.make_topography(np.cos(2 * np.pi * x / 32) * 1e-9, spacing=1e-9)
    >>> round(rs.surface.topography.autocorrelation_length(h) * 1e9)  # cos(2 pi r/32) = 0.2: 6.97
    7
    """
    h = validate_height(height)
    z = np.asarray(h.values, dtype=float)
    z = np.where(np.isfinite(z), z - np.nanmean(z), 0.0)
    ny, nx = z.shape
    f = np.fft.rfft2(z, s=(2 * ny, 2 * nx))
    acf = np.fft.irfft2(np.abs(f) ** 2, s=(2 * ny, 2 * nx))
    ones = np.fft.rfft2(np.ones_like(z), s=(2 * ny, 2 * nx))
    overlap = np.maximum(np.fft.irfft2(np.abs(ones) ** 2, s=(2 * ny, 2 * nx)), 1.0)
    acf = np.fft.fftshift(acf / overlap)
    acf /= acf[ny, nx]
    dy, dx = grid_spacing(h, "y"), grid_spacing(h, "x")
    yy, xx = np.meshgrid((np.arange(2 * ny) - ny) * dy, (np.arange(2 * nx) - nx) * dx, indexing="ij")
    r = np.hypot(yy, xx)
    # only lags with at least half the map overlapping are trusted
    trusted = (abs(yy) <= ny * dy / 2) & (abs(xx) <= nx * dx / 2)
    below = trusted & (acf <= threshold)
    return float(r[below].min()) if below.any() else float(r[trusted].max())


def warn_if_incompatible(maps, names=None) -> dict:
    """An :class:`IncompatibleMapsWarning` when maps about to be averaged into one PSD differ in
    rms height or autocorrelation length by more than :data:`COMPATIBLE_RATIO` (maps of different
    samples, or of one sample at scales where it is not stationary); returns each map's
    ``{"rms_height": ..., "autocorrelation_length": ...}`` [m] by name.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> a = rs.testing.make_topography(rng.normal(size=(32, 32)) * 1e-9, spacing=1e-9)
    >>> b = rs.testing.make_topography(rng.normal(size=(32, 32)) * 5e-9, spacing=1e-9)
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     _ = rs.surface.topography.warn_if_incompatible([a, b], ["a", "b"])
    >>> [w.category.__name__ for w in caught]
    ['IncompatibleMapsWarning']
    """
    maps = list(maps)
    names = [str(n) for n in (names or range(len(maps)))]
    stats = {n: {"rms_height": float(np.nanstd(np.asarray(m.values, dtype=float))),
                 "autocorrelation_length": autocorrelation_length(m)} for n, m in zip(names, maps)}
    if len(maps) < 2:
        return stats
    bad = []
    for key, label in (("rms_height", "rms height Sq"), ("autocorrelation_length", "autocorrelation length Sal")):
        v = np.array([s[key] for s in stats.values()])
        if v.min() > 0 and v.max() / v.min() > COMPATIBLE_RATIO:
            bad.append(f"{label} {v.min() * 1e9:.3g}-{v.max() * 1e9:.3g} nm ({v.max() / v.min():.3g}x)")
    if bad:
        each = "; ".join(f"{n}: Sq {s['rms_height'] * 1e9:.3g} nm, Sal {s['autocorrelation_length'] * 1e9:.3g} nm"
                         for n, s in stats.items())
        warnings.warn(
            f"the {len(maps)} maps averaged into one PSD differ more than maps of one surface do "
            f"({' and '.join(bad)}, more than {COMPATIBLE_RATIO:g}x; {each}): their average is the "
            "PSD of none of them. Average only maps of one sample (give each sample's maps to a "
            "command or run of their own), or crop the maps to a common scan size.",
            IncompatibleMapsWarning, stacklevel=external_stacklevel())
    return stats
