"""Read AFM height maps into ``height`` DataArrays (y, x) in metres.

Built in: the project's own CF NetCDF, ``.npy`` arrays and plain-text grids. Vendor formats
(NanoScope/DI, Park TIFF, Gwyddion, Igor, ... 40+) go through SurfaceTopography's readers,
an optional extra: ``pip install roughstick[afm]``.

The sample maps shipped inside the package (``roughstick/data/S1A.nc`` ... ``S2C.nc``,
:mod:`roughstick.datasets`) are named ``bundled:S1A`` ... ``bundled:S2C`` wherever a map path is
accepted (:func:`read_afm`, ``roughstick psd``, ``roughstick curves``, a ``roughstick run``
config's ``[psd] files``): :func:`resolve_map_path`. A real file of that name always wins.
"""

from __future__ import annotations

import logging
import pathlib
import warnings
from importlib import resources

import numpy as np
import xarray as xr

from .._core import units as _units
from .._core.conventions import ATTRS, append_history, set_coord_attrs
from .._core.levelling import METHODS, level_kernel
from .._core.memory import physical_memory
from .._core.remedy import spell
from .._core.validate import as_length

__all__ = ["read_afm"]

#: The prefix naming a map shipped inside the package: ``bundled:S1A``.
BUNDLED_PREFIX = "bundled:"
#: Names of the bundled sample maps (synthetic stand-ins of the paper's S1 and S2 measurements).
BUNDLED_MAPS = ("S1A", "S1B", "S1C", "S2A", "S2B", "S2C")


def bundled_map_names() -> str:
    """The bundled map names as a user writes them: ``bundled:S1A, ..., bundled:S2C``."""
    return ", ".join(BUNDLED_PREFIX + n for n in BUNDLED_MAPS)


def bundled_map_file(name: str) -> pathlib.Path:
    """Path inside the installed package of the bundled map ``name`` (one of :data:`BUNDLED_MAPS`,
    e.g. ``"S1A"``; case and a ``.nc`` suffix are ignored)."""
    key = str(name).removesuffix(".nc").upper()
    if key not in BUNDLED_MAPS:
        raise ValueError(f"unknown bundled map {BUNDLED_PREFIX + str(name)!r}; the bundled maps are "
                         f"{bundled_map_names()}.")
    path = resources.files("roughstick").joinpath("data", f"{key}.nc")
    if not path.is_file():
        raise FileNotFoundError(
            f"the bundled map {key}.nc is missing from {path}: the installation is incomplete "
            "(reinstall roughstick; from a checkout, `pip install .`).")
    return pathlib.Path(str(path))


def resolve_map_path(path, *, base=None) -> pathlib.Path:
    """The file a map path names: ``path`` itself (``~`` expanded; a relative path taken from
    the folder ``base`` when given, e.g. a config file's) when such a file or folder exists, else,
    for ``bundled:NAME``, the bundled map ``NAME`` inside the package.

    Raises
    ------
    ValueError
        ``bundled:NAME`` with an unknown ``NAME`` (the message lists the bundled names).

    Examples
    --------
    >>> resolve_map_path("bundled:S2C").name
    'S2C.nc'
    """
    text = str(path)
    p = pathlib.Path(path).expanduser()
    if base is not None and not p.is_absolute():
        p = (pathlib.Path(base) / p).resolve()
    if p.exists() or not text.lower().startswith(BUNDLED_PREFIX):
        return p
    return bundled_map_file(text[len(BUNDLED_PREFIX):])


def _not_found(path: pathlib.Path) -> str:
    """'no such AFM file', with the bundled name when ``path`` looks like one without its prefix."""
    stem = path.name.removesuffix(".nc").upper()
    hint = (f" (the bundled sample map is named {BUNDLED_PREFIX}{stem})" if stem in BUNDLED_MAPS
            and not path.parent.parts else "")
    return f"no such AFM file: {path}{hint}"


_TEXT = {".txt", ".csv", ".asc", ".dat", ".xyz"}
_NETCDF = {".nc", ".nc4", ".netcdf", ".cdf"}


def _length(value, name: str) -> float:
    """A length as float m: a number (m) or a string such as ``"5 nm"``."""
    return as_length(value, name=name)


_LINE_SCAN = ("roughstick's contact, ensemble and generation analyses need a 2-D height map; "
              "for a line scan's PSD and moments read it with read_afm(path, line_scan=True) and "
              "use roughstick.surface.profile_psd / profile_moments (CLI: roughstick psd reads line scans).")


def _line_scan_shape(shape) -> bool:
    """A 1-D array, or one row or one column of at least 2 points."""
    return len(shape) == 1 or (len(shape) == 2 and min(shape) == 1 and max(shape) >= 2)


def _grid(values, dx, dy, *, units, source, periodic=0, line_scan=False):
    raw = np.asarray(values)
    if raw.dtype.kind not in "fiu":
        what = {"c": "complex numbers", "b": "booleans", "O": "Python objects", "U": "text",
                "S": "bytes", "M": "dates", "m": "time spans", "V": "records"}.get(raw.dtype.kind, str(raw.dtype))
        raise ValueError(f"{source} holds {what} (dtype {raw.dtype}), which a height map cannot be; "
                         "give real heights (float or integer).")
    z = raw.astype(float)
    if _line_scan_shape(z.shape) and z.size:
        if not line_scan:
            raise ValueError(f"{source} is a line scan (1-D profile of {z.size} points, shape "
                             f"{z.shape}). " + _LINE_SCAN)
        z = z.reshape(1, -1)
    if z.ndim != 2:
        raise ValueError(f"a height map must be 2-D, got an array of shape {z.shape} from {source}.")
    if z.size == 0 or min(z.shape) < 2 and not line_scan:
        raise ValueError(f"{source} is empty or a single line of pixels (shape {z.shape}); a height "
                         "map needs at least 2 x 2 pixels.")
    if z.shape[-1] < 2:
        raise ValueError(f"{source} has fewer than 2 points (shape {z.shape}).")
    if np.isinf(z).any():
        raise ValueError(f"{source} has {int(np.isinf(z).sum())} infinite pixel(s); mark missing "
                         "pixels as NaN (roughstick.surface.level(..., nan='fill') handles them).")
    finite = z[np.isfinite(z)]
    if finite.size == 0:
        raise ValueError(f"{source} has no finite pixel (all NaN).")
    if np.ptp(finite) == 0:
        warnings.warn(f"{source}: every pixel has the same height ({finite[0]:g}): a flat map. "
                      "Is it the right channel or file?", UserWarning, stacklevel=4)
    f = _units.factor(units, "length", name="height")
    span = float(np.ptp(finite)) * f
    if span > 1e-3:
        warnings.warn(f"{source}: heights span {span:g} m (units {units!r}), more than 1 mm, "
                      "implausible for an AFM map; if the values are nanometres, pass units='nm' "
                      "(--units nm).", UserWarning, stacklevel=4)
    ny, nx = z.shape
    if ny == 1 and line_scan:  # a profile: height over x only
        da = xr.DataArray(z[0] * f, dims=("x",), coords={"x": (np.arange(nx) + 0.5) * dx},
                          name="height", attrs={**ATTRS["height"], "periodic": int(periodic),
                                                "source": str(source), "line_scan": 1})
        set_coord_attrs(da)
        return da
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


def _metadata(info: dict) -> dict:
    """Instrument metadata of SurfaceTopography's ``info`` (or contact.engineering's ``json``)
    as flat NetCDF-storable attributes: ``instrument_name``, ``acquisition_time`` ..."""
    out = {}

    def walk(prefix, v):
        if isinstance(v, dict):
            for k, x in v.items():
                if k != "raw_metadata":
                    walk(f"{prefix}_{k}" if prefix else str(k), x)
        elif isinstance(v, (str, int, float, np.integer, np.floating)) and not isinstance(v, bool):
            out[prefix] = v.item() if hasattr(v, "item") else v
        elif v is not None and not isinstance(v, (list, tuple)):
            out[prefix] = str(v)

    walk("", info or {})
    return out


def _is_height_name(name: str) -> bool:
    return "height" in str(name).lower().replace("_", " ")


def _read_netcdf(path: pathlib.Path, channel, units, spacing, line_scan=False):
    import json

    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            ds.load()
    except OSError as exc:  # "NetCDF: HDF error", "Unknown file format"
        raise ValueError(f"cannot read {path.name} as NetCDF ({exc}): the file is damaged, truncated "
                         "or not NetCDF despite its extension.") from exc
    names = list(ds.data_vars)
    if isinstance(channel, str):
        name = channel
    elif "height" in ds.data_vars:
        name = "height"
    elif "heights" in ds.data_vars:  # SurfaceTopography / contact.engineering
        name = "heights"
    elif len(names) == 1:
        name = names[0]
    elif [n for n in names if _is_height_name(n)]:
        name = [n for n in names if _is_height_name(n)][0]
    else:
        raise ValueError(f"{path} has variables {names} and none is a height; pass channel='<name>' "
                         "(roughstick psd/curves: --channel NAME).")
    if name not in ds.data_vars:
        raise ValueError(f"{path} has no variable {name!r}; it has {names}.")
    da = ds[name]
    foreign = "units" not in da.attrs or da.dims != ("y", "x") or units is not None or spacing is not None
    if not foreign:  # written by roughstick: returned exactly as stored
        if "periodic" not in da.attrs:
            da.attrs["periodic"] = 0
        if "source" not in da.attrs:
            da.attrs["source"] = str(path)
        return _units.require(da, "length", name=name)
    # another writer (SurfaceTopography, contact.engineering, Gwyddion export ...): 'unit' (not CF's
    # 'units') and dims (x, y) are common; the caller's units= / spacing= win over the file
    zunit = units or da.attrs.get("units") or da.attrs.get("unit")
    if zunit is None:
        raise ValueError(f"{path.name}: variable {name!r} has no 'units' (or 'unit') attribute; pass "
                         "units= (e.g. 'nm'; roughstick psd/curves: --units nm).")
    if da.ndim == 1:
        if not line_scan:
            raise ValueError(f"{path.name}: {name!r} is a line scan (1-D profile of {da.size} "
                             "points). " + _LINE_SCAN)
        da = da.rename({da.dims[0]: "x"})
    elif da.ndim != 2:
        raise ValueError(f"{path.name}: {name!r} has dims {da.dims}; a height map is 2-D.")
    if set(da.dims) == {"x", "y"}:
        da = da.transpose("y", "x")
    ydim, xdim = da.dims if da.ndim == 2 else (None, da.dims[0])
    if spacing is None:
        dxy = []
        for dim in (ydim, xdim):
            if dim is None:  # a line scan: no y
                dxy.append(None)
                continue
            c = da[dim] if dim in da.coords else None
            if c is None or c.size < 2:
                raise ValueError(f"{path.name}: no {dim} coordinate to tell the pixel size; pass "
                                 "spacing= (e.g. '5 nm'; roughstick psd/curves: --spacing '5 nm').")
            cu = c.attrs.get("units") or c.attrs.get("unit")
            if cu is None:
                raise ValueError(f"{path.name}: coordinate {dim!r} has no units; pass spacing= "
                                 "(e.g. '5 nm'; --spacing '5 nm').")
            dxy.append(float(c[1] - c[0]) * _units.factor(cu, "length", name=dim))
        spacing = tuple(dxy)
    out = _grid(da.values, spacing[1], spacing[0], units=zunit, source=str(path), line_scan=line_scan)
    out.attrs["channel"] = name
    meta = {}
    if "json" in ds.attrs:
        try:
            meta = json.loads(ds.attrs["json"])
        except ValueError:
            meta = {}
    out.attrs.update(_metadata(meta))
    return out


#: extensions that are surely not height maps (a config passed where a map is expected)
_NOT_MAPS = {
    ".toml": "a configuration file (roughstick run / risk / beam CONFIG.toml)",
    ".json": "a JSON file", ".yaml": "a YAML file", ".yml": "a YAML file", ".py": "a Python file",
    ".ipynb": "a notebook", ".md": "a text document",
}


def _read_vendor(path: pathlib.Path, channel, spacing, line_scan=False):
    try:
        from SurfaceTopography import open_topography
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(
            f"reading {path.suffix or 'this'} files needs SurfaceTopography: "
            "pip install roughstick[afm] (or pip install SurfaceTopography). Built-in formats: "
            ".nc (NetCDF), .npy, plain-text grids."
        ) from exc
    try:
        reader = open_topography(str(path))
    except Exception as exc:  # SurfaceTopography raises many types for a file it cannot parse
        raise ValueError(f"cannot read {path.name}: SurfaceTopography recognises no AFM format in it "
                         f"({type(exc).__name__}: {exc}). Is it what its extension says?") from exc
    channels = reader.channels
    listing = [(c.index, c.name) for c in channels]

    def is_height(c):  # a height channel has a (string) length unit for its data
        return isinstance(c.unit, str)

    if channel is None:  # the channel named height, not the file's first (e.g. ZSensor)
        named = [c for c in channels if is_height(c) and _is_height_name(c.name)]
        idx = named[0].index if named else reader.default_channel.index
    elif isinstance(channel, (int, np.integer)):
        idx = int(channel)
        if not 0 <= idx < len(channels):
            raise ValueError(f"{path.name} has channels {listing}, not {idx}.")
    else:
        names = [c.name for c in channels]
        if channel not in names:
            raise ValueError(f"{path.name} has no channel {channel!r}; channels: {listing}.")
        idx = names.index(channel)
    info = channels[idx]
    if info.dim == 1 and not line_scan:
        raise ValueError(f"channel {idx} ({info.name!r}) of {path.name} is a line scan (1-D profile). "
                         + _LINE_SCAN)
    if not is_height(info):
        raise ValueError(
            f"channel {idx} ({info.name!r}) of {path.name} is not a height channel (no length unit); "
            f"choose a height channel: {listing}."
        )
    t = reader.topography(channel_index=idx)
    unit = t.unit
    h = t.heights()
    if np.ma.isMaskedArray(h):
        h = h.filled(np.nan)
    # SurfaceTopography indexes heights[x, y]: transpose to (y, x) with scan lines along x
    z = np.asarray(h, dtype=float).T
    f = _units.factor(unit, "length", name="SurfaceTopography unit")
    if z.ndim == 1:  # a line scan (UniformLineScan)
        (sx,), (nx,) = np.atleast_1d(t.physical_sizes), np.atleast_1d(t.nb_grid_pts)
        sy, ny = sx, 1
    else:
        sx, sy = t.physical_sizes
        nx, ny = t.nb_grid_pts
    dx, dy = (sx * f / nx, sy * f / ny) if spacing is None else (spacing[1], spacing[0])
    da = _grid(z, dx, dy, units=unit, source=str(path), line_scan=line_scan)
    da.attrs["channel"] = f"{idx}: {info.name}"
    da.attrs["channels_in_file"] = ", ".join(f"{i}: {n}" for i, n in listing)
    da.attrs.update(_metadata(dict(info.info)))
    return da


def _check_npy_fits(path) -> None:
    """Refuse, from its header and before reading the data, a .npy larger than the memory."""
    try:
        with open(path, "rb") as fh:
            version = np.lib.format.read_magic(fh)
            read = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                    else np.lib.format.read_array_header_2_0)
            shape, _, dtype = read(fh)
    except (ValueError, OSError):
        return  # np.load reports a damaged header
    need = float(np.prod(shape, dtype=float)) * max(dtype.itemsize, 8)  # read, then as float64
    have = physical_memory()
    if have is not None and need > have:
        raise MemoryError(
            f"{pathlib.Path(path).name} holds a {' x '.join(map(str, shape))} {dtype} array "
            f"(about {need / 2**30:.3g} GiB as float64), more than this machine's "
            f"{have / 2**30:.3g} GiB; crop it first (np.load(..., mmap_mode='r')[rows, cols])."
        )


def read_afm(path, *, spacing=None, channel=None, units=None, line_scan: bool = False,
             levelling: str = "auto") -> xr.DataArray:
    """Read an AFM height map as ``height`` (y, x) in metres.

    Parameters
    ----------
    path : str or pathlib.Path
        A file, or ``"bundled:S1A"`` ... ``"bundled:S2C"`` for a sample map shipped with
        roughstick (:func:`resolve_map_path`; a real file of that name wins). ``.nc`` (NetCDF; a Dataset with ``height`` or a single variable, as written by
        roughstick: read back exactly), ``.npy`` (2-D array, rows = y), plain text (``.txt``,
        ``.csv``, ``.asc``, ``.dat``: whitespace- or comma-separated grid, ``#`` comments), or
        any format SurfaceTopography reads (DI/NanoScope ``.di``/``.spm``, Park ``.tiff``,
        Gwyddion ``.gwy``, Igor ``.ibw``, ...).
    spacing : float or str or (dy, dx), optional
        Pixel size: a number in m or a string such as ``"5 nm"``. Required for ``.npy`` and
        text; overrides the file's scan size for vendor formats.
    channel : int or str, optional
        Channel index or name (vendor formats; e.g. ``"Height"``, ``3``) or variable name
        (NetCDF). Default: the channel named height (not the file's first channel, which is
        often ZSensor), else the file's default; NetCDF: ``height``, SurfaceTopography's
        ``heights``, or the only variable. The channel used is in ``attrs['channel']`` (and the
        others in ``attrs['channels_in_file']``).
    units : str, optional
        Units of the height values of ``.npy`` and text files (``"m"``, ``"nm"``, ``"um"``, ...);
        required for them, since nothing in the file says. For NetCDF from other writers
        (SurfaceTopography, contact.engineering: attribute ``unit``, dims ``(x, y)``) it
        overrides the file's unit.
    line_scan : bool
        Accept a line scan (a 1-D profile: a 1-D array, one row or one column of numbers, a
        1-D NetCDF variable, a vendor line-scan channel) and return it as ``height`` over
        ``("x",)`` with attr ``line_scan = 1``, for :func:`roughstick.surface.profile_psd` and
        :func:`roughstick.surface.profile_moments`. Default ``False``: a line scan is refused, since
        contact, ensembles and generation need a 2-D map. 2-D maps are read either way.
    levelling : {"auto", "plane", "mean", "line", "none"}, default "auto"
        What is removed from a 2-D map as it is read (:func:`roughstick.surface.level`):
        ``"auto"`` removes the least-squares plane of a measured map (an instrument's tilt and
        offset; the contact models measure distances from the mean plane) and leaves a map
        marked periodic (a generated surface) or already levelled (``attrs['levelling']``) as it
        is; ``"none"`` keeps the raw heights. Every command that reads a map (``roughstick psd``,
        ``curves``, ``run``) levels it by this function, the same way by default (``--level``).
        NaN pixels are kept (levelling ignores them). Line scans are not levelled here
        (:func:`roughstick.surface.level_profile`).

    Returns
    -------
    xarray.DataArray
        ``height`` [m] over ``(y, x)``, pixel-centre coords in m, attrs ``periodic`` (0: measured),
        ``source`` (the file), ``channel``, the instrument metadata SurfaceTopography reports
        (``instrument_name``, ``instrument_vendor``, ``acquisition_time`` ...), ``levelling``
        (what was removed) and ``history`` (which says it, with the span of the removed plane).

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
    >>> np.save(p, np.arange(80.0).reshape(8, 10))
    >>> h = rs.io.read_afm(p, spacing="5 nm", units="nm")
    >>> h.dims, h.sizes["x"], float(h.x[1] - h.x[0]), h.attrs["levelling"]
    (('y', 'x'), 10, 5e-09, 'plane')
    >>> float(abs(h).max()) < 1e-20  # the heights 0 ... 79 nm are a plane
    True
    """
    if levelling not in LEVELLINGS:
        raise ValueError(f"levelling must be one of {LEVELLINGS}, got {levelling!r}.")
    return _level_on_read(_read(path, spacing, channel, units, line_scan), levelling)


#: The values of ``read_afm(levelling=...)``.
LEVELLINGS = ("auto", *METHODS)


def _level_on_read(da: xr.DataArray, levelling: str) -> xr.DataArray:
    """``da`` levelled as ``read_afm(levelling=...)`` says, the removed part said in ``history``
    (and to the logger ``roughstick``)."""
    if "y" not in da.dims:  # a line scan
        return da
    done = str(da.attrs.get("levelling", "none"))
    periodic = str(da.attrs.get("periodic", 0)).strip().lower() in ("1", "true")
    name = pathlib.Path(str(da.attrs.get("source", "map"))).name
    if levelling == "auto":
        if periodic or done != "none":  # read back exactly
            why = "a periodic map" if periodic else f"levelled already ({done})"
            logging.getLogger("roughstick").info(f"read_afm: {name} not levelled ({why})")
            return da
        levelling = "plane"
    if levelling == "none":  # the raw heights, as the file holds them
        logging.getLogger("roughstick").info(f"read_afm: {name} not levelled (raw heights, "
                                             f"{spell('levelling', 'none')})")
        return da
    raw = np.asarray(da.values, dtype=float)
    x, y = (np.asarray(da[d].values, dtype=float) for d in ("x", "y"))
    if np.count_nonzero(~np.isfinite(raw)) > 0.5 * raw.size:  # level() refuses it, naming the fix
        return da
    z = level_kernel(raw, method=levelling, nan="mask", max_nan_fraction=1.0, x=x, y=y)
    removed = raw - z
    span = float(np.nanmax(removed) - np.nanmin(removed)) if np.isfinite(removed).any() else 0.0
    out = da.copy(data=z)
    out.attrs["levelling"] = levelling
    line = (f"read_afm: {name} levelled: removed {METHODS[levelling]} (spanning {span * 1e9:.3g} nm; "
            f"rms height {float(np.nanstd(z)) * 1e9:.3g} nm after; raw heights: "
            f"{spell('levelling', 'none')})")
    append_history(out, line)
    logging.getLogger("roughstick").info(line)
    return out


def _read(path, spacing, channel, units, line_scan) -> xr.DataArray:
    """The map of :func:`read_afm` as the file holds it."""
    path = resolve_map_path(path)
    if not path.exists():
        raise FileNotFoundError(_not_found(path))
    if path.is_dir():
        raise ValueError(f"{str(path)!r} is a folder, not an AFM file; give one of the files in it.")
    suffix = path.suffix.lower()
    if suffix in _NOT_MAPS:
        raise ValueError(
            f"{path.name} is {_NOT_MAPS[suffix]}, not a height map. Height maps: .nc, .npy, text "
            "grids, or an AFM vendor format (SurfaceTopography).")
    sp = _spacing_pair(spacing)
    if suffix in _NETCDF:
        da = _read_netcdf(path, channel, units, sp, line_scan)
        if "channel" in da.attrs:  # another writer's file (a roughstick file reads back exactly)
            append_history(da, f"read_afm: {path.name} variable {da.attrs['channel']!r}")
        return da
    if suffix == ".npy" or suffix in _TEXT:
        if sp is None or units is None:
            raise ValueError(
                f"{path.name} holds bare numbers: pass spacing= (pixel size, e.g. '5 nm' or 5e-9) "
                "and units= (of the heights, e.g. 'nm')."
            )
        with open(path, "rb") as fh:
            head = fh.read(8)
        is_npy = head.startswith(b"\x93NUMPY")
        if suffix == ".npy":
            if not is_npy:
                raise ValueError(
                    f"{path.name} is not a NumPy .npy file despite its extension (it does not start "
                    f"with the .npy signature: {head[:6]!r}); save it with np.save, or give the "
                    "file its true extension (.txt/.csv for text, .nc, a vendor format)."
                )
            _check_npy_fits(path)
            try:
                z = np.load(path, allow_pickle=False)
            except ValueError as err:
                raise ValueError(
                    f"{path.name}: cannot read it as a numeric .npy array ({err}); roughstick "
                    "never loads pickled objects: save the heights with np.save(path, "
                    "np.asarray(z, dtype=float))."
                ) from None
        else:
            if is_npy:
                raise ValueError(
                    f"{path.name} is a NumPy .npy file, not text as its extension says; rename it "
                    "to .npy."
                )
            delim = "," if suffix == ".csv" else None
            try:
                z = np.loadtxt(path, comments="#", delimiter=delim, ndmin=2)
            except (ValueError, UnicodeDecodeError) as err:
                raise ValueError(
                    f"{path.name} is not a table of numbers as its extension says "
                    f"({type(err).__name__}: {str(err)[:120]}); give one row of heights per "
                    "line (comments start with #), or the file's true extension."
                ) from None
        da = _grid(z, sp[1], sp[0], units=units, source=str(path), line_scan=line_scan)
    else:
        da = _read_vendor(path, channel, sp, line_scan)
    append_history(da, f"read_afm: {path.name}" + (f" channel {channel!r}" if channel is not None else ""))
    return da
