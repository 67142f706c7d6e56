"""Read AFM height maps into ``height`` DataArrays (y, x) in metres.

Built in: the project's own CF NetCDF, ``.npy`` arrays and plain-text grids. Vendor formats
(NanoScope/DI, Park TIFF, Gwyddion, Igor, ... 40+) go through SurfaceTopography's readers,
an optional extra: ``pip install roughstick[afm]``.
"""

from __future__ import annotations

import pathlib

import numpy as np
import xarray as xr

from .._core import units as _units
from .._core.conventions import ATTRS, append_history, set_coord_attrs
from .._core.validate import check_positive_block

__all__ = ["read_afm"]

_TEXT = {".txt", ".csv", ".asc", ".dat", ".xyz"}
_NETCDF = {".nc", ".nc4", ".netcdf", ".cdf"}


def _length(value, name: str) -> float:
    """A length as float m: a number (m) or a string such as ``"5 nm"``."""
    v = _units.parse_quantity(value, "length", name=name)
    check_positive_block(v, name, "Pass a positive length, e.g. '5 nm' or 5e-9 (m).", finite=True)
    return v


def _grid(values, dx, dy, *, units, source, periodic=0):
    z = np.asarray(values, dtype=float)
    if z.ndim != 2:
        raise ValueError(f"a height map must be 2-D, got an array of shape {z.shape} from {source}.")
    f = _units.factor(units, "length", name="height")
    ny, nx = z.shape
    da = xr.DataArray(
        z * f,
        dims=("y", "x"),
        coords={"y": (np.arange(ny) + 0.5) * dy, "x": (np.arange(nx) + 0.5) * dx},
        name="height",
        attrs={**ATTRS["height"], "periodic": int(periodic), "source": str(source)},
    )
    set_coord_attrs(da)
    return da


def _spacing_pair(spacing):
    if spacing is None:
        return None
    if isinstance(spacing, (tuple, list)):
        if len(spacing) != 2:
            raise ValueError(f"spacing must be one length or (dy, dx), got {spacing!r}.")
        return _length(spacing[0], "spacing"), _length(spacing[1], "spacing")
    v = _length(spacing, "spacing")
    return v, v


def _read_netcdf(path: pathlib.Path, channel):
    with xr.open_dataset(path, engine="netcdf4") as ds:
        ds.load()
    if isinstance(channel, str):
        name = channel
    elif "height" in ds.data_vars:
        name = "height"
    elif len(ds.data_vars) == 1:
        name = next(iter(ds.data_vars))
    else:
        raise ValueError(
            f"{path} has variables {list(ds.data_vars)} and none is 'height'; pass channel='<name>'."
        )
    if name not in ds.data_vars:
        raise ValueError(f"{path} has no variable {name!r}; it has {list(ds.data_vars)}.")
    da = ds[name]
    # written by roughstick: returned exactly as stored; other NetCDF files get the defaults
    if "periodic" not in da.attrs:
        da.attrs["periodic"] = 0
    if "source" not in da.attrs:
        da.attrs["source"] = str(path)
    return _units.require(da, "length", name=name) if "units" in da.attrs else da


def _read_vendor(path: pathlib.Path, channel, spacing):
    try:
        from SurfaceTopography import open_topography
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(
            f"reading {path.suffix or 'this'} files needs SurfaceTopography: "
            "pip install roughstick[afm] (or pip install SurfaceTopography). Built-in formats: "
            ".nc (NetCDF), .npy, plain-text grids."
        ) from exc
    reader = open_topography(str(path))
    channels = reader.channels
    if channel is None:
        idx = reader.default_channel.index
    elif isinstance(channel, (int, np.integer)):
        idx = int(channel)
        if not 0 <= idx < len(channels):
            raise ValueError(f"{path.name} has channels 0..{len(channels) - 1}, not {idx}.")
    else:
        names = [c.name for c in channels]
        if channel not in names:
            raise ValueError(f"{path.name} has no channel {channel!r}; channels: {names}.")
        idx = names.index(channel)
    info = channels[idx]
    unit = info.unit
    if isinstance(unit, tuple):
        unit = unit[1] if len(unit) > 1 else unit[0]
    if unit is None:
        raise ValueError(
            f"channel {idx} ({info.name!r}) of {path.name} is not a height channel (no length unit); "
            f"choose a height channel: {[(c.index, c.name) for c in channels]}."
        )
    t = reader.topography(channel_index=idx)
    unit = t.unit
    h = t.heights()
    if np.ma.isMaskedArray(h):
        h = h.filled(np.nan)
    # SurfaceTopography indexes heights[x, y]: transpose to (y, x) with scan lines along x
    z = np.asarray(h, dtype=float).T
    f = _units.factor(unit, "length", name="SurfaceTopography unit")
    sx, sy = t.physical_sizes
    nx, ny = t.nb_grid_pts
    dx, dy = (sx * f / nx, sy * f / ny) if spacing is None else (spacing[1], spacing[0])
    da = _grid(z, dx, dy, units=unit, source=str(path))
    da.attrs["channel"] = f"{idx}: {info.name}"
    return da


def read_afm(path, *, spacing=None, channel=None, units=None) -> xr.DataArray:
    """Read an AFM height map as ``height`` (y, x) in metres.

    Parameters
    ----------
    path : str or pathlib.Path
        ``.nc`` (NetCDF; a Dataset with ``height`` or a single variable, as written by
        roughstick: read back exactly), ``.npy`` (2-D array, rows = y), plain text (``.txt``,
        ``.csv``, ``.asc``, ``.dat``: whitespace- or comma-separated grid, ``#`` comments), or
        any format SurfaceTopography reads (DI/NanoScope ``.di``/``.spm``, Park ``.tiff``,
        Gwyddion ``.gwy``, Igor ``.ibw``, ...).
    spacing : float or str or (dy, dx), optional
        Pixel size: a number in m or a string such as ``"5 nm"``. Required for ``.npy`` and
        text; overrides the file's scan size for vendor formats.
    channel : int or str, optional
        Channel index or name (vendor formats; e.g. ``"Z Height"``, ``3``) or variable name
        (NetCDF). Default: the file's default channel / ``height``.
    units : str, optional
        Units of the height values of ``.npy`` and text files (``"m"``, ``"nm"``, ``"um"``, ...);
        required for them, since nothing in the file says.

    Returns
    -------
    xarray.DataArray
        ``height`` [m] over ``(y, x)``, pixel-centre coords in m, attrs ``periodic`` (0: measured),
        ``source`` (the file) and ``history``. Not levelled: use :func:`roughstick.level`.

    Raises
    ------
    FileNotFoundError
        No such file.
    ImportError
        A vendor format without SurfaceTopography (``pip install roughstick[afm]``).
    ValueError
        Missing ``spacing``/``units`` for arrays, a non-height channel, a non-2-D array.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "map.npy"
    >>> np.save(p, np.zeros((8, 10)))
    >>> h = rs.read_afm(p, spacing="5 nm", units="nm")
    >>> h.dims, h.sizes["x"], float(h.x[1] - h.x[0])
    (('y', 'x'), 10, 5e-09)
    """
    path = pathlib.Path(path)
    if not path.exists():
        raise FileNotFoundError(f"no such AFM file: {path}")
    suffix = path.suffix.lower()
    sp = _spacing_pair(spacing)
    if suffix in _NETCDF:
        return _read_netcdf(path, channel)
    if suffix == ".npy" or suffix in _TEXT:
        if sp is None or units is None:
            raise ValueError(
                f"{path.name} holds bare numbers: pass spacing= (pixel size, e.g. '5 nm' or 5e-9) "
                "and units= (of the heights, e.g. 'nm')."
            )
        if suffix == ".npy":
            z = np.load(path, allow_pickle=False)
        else:
            delim = "," if suffix == ".csv" else None
            z = np.loadtxt(path, comments="#", delimiter=delim, ndmin=2)
        da = _grid(z, sp[1], sp[0], units=units, source=str(path))
    else:
        da = _read_vendor(path, channel, sp)
    append_history(da, f"read_afm: {path.name}" + (f" channel {channel!r}" if channel is not None else ""))
    return da
