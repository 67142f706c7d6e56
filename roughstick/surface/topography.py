r"""Height maps: validation, levelling and NaN dropouts (paper §3.1).

A height map is a DataArray ``height`` over ``(..., y, x)`` in m with uniform ascending pixel-centre
coordinates (docs/architecture.md). :func:`validate_height` checks one and returns it in SI;
:func:`level` removes its mean, mean plane or scan-line offsets and handles NaN pixels. Roughness
statistics of a map are in :mod:`roughstick.surface.moments`.
"""

from __future__ import annotations

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

