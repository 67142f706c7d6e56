"""CF NetCDF output: checked, zlib-compressed, atomic writes; ensemble folders written chunk by chunk.

Every write goes to a temporary name in the destination folder and is renamed into place only
after the file is closed and flushed, so a file under its final name is always complete: a killed
run leaves at most a ``*.tmp-*`` file, which :func:`open_ensemble` ignores and a resumed run
deletes. An ensemble folder (written by :func:`roughstick.run_ensemble` with ``output=``) holds

``manifest.json``
    the run's parameters, their hash, the block layout and the blocks completed so far;
``block-r<i>-h<j>.nc``
    one CF NetCDF file per (realization chunk ``i``, humidity chunk ``j``), each carrying the
    parameters hash and its block index in its attributes.
"""

from __future__ import annotations

import contextlib
import json
import os
import pathlib
import threading

import numpy as np
import xarray as xr

__all__ = ["write", "open_dataset", "open_ensemble", "check_cf"]

#: Name of the manifest of an ensemble folder.
MANIFEST = "manifest.json"
#: Format tag written into every manifest.
MANIFEST_FORMAT = "roughstick-ensemble/1"
_TMP_TAG = ".tmp-"
_LOCK = threading.Lock()


# ----------------------------------------------------------------------------- CF checks
def check_cf(ds: xr.Dataset) -> None:
    """Raise ``ValueError`` unless every variable and coordinate has ``units`` and ``long_name``.

    Parameters
    ----------
    ds : xarray.Dataset or xarray.DataArray
        Object about to be written.

    Raises
    ------
    ValueError
        Naming each variable that lacks an attribute and how to add it.

    Examples
    --------
    >>> ds = xr.Dataset({"a": ("x", [1.0])})
    >>> rs.io.netcdf.check_cf(ds)
    Traceback (most recent call last):
    ...
    ValueError: not CF-complete: 'a' lacks units, long_name; ...
    """
    if isinstance(ds, xr.DataArray):
        ds = ds.to_dataset(name=ds.name or "data")
    missing = []
    for name, var in list(ds.data_vars.items()) + list(ds.coords.items()):
        lack = [k for k in ("units", "long_name") if k not in var.attrs and k not in var.encoding]
        if lack:
            missing.append(f"{name!r} lacks {', '.join(lack)}")
    if missing:
        raise ValueError(
            "not CF-complete: " + "; ".join(missing) + "; set them before writing, e.g. "
            "roughstick._core.conventions.set_attrs(da, key) or da.attrs.update(units='m', long_name='...')."
        )


def _netcdf_attrs(attrs: dict, where: str) -> dict:
    out = {}
    for k, v in attrs.items():
        if isinstance(v, (bool, np.bool_)):
            v = int(v)
        elif v is None:
            raise ValueError(f"attribute {k!r} of {where} is None, which NetCDF cannot store; drop it.")
        elif isinstance(v, dict):
            v = json.dumps(v, sort_keys=True)
        elif isinstance(v, (list, tuple)) and v and all(isinstance(e, str) for e in v):
            v = ", ".join(v)
        out[k] = v
    return out


def _prepare(ds: xr.Dataset) -> tuple[xr.Dataset, dict]:
    if isinstance(ds, xr.DataArray):
        ds = ds.to_dataset(name=ds.name or "data")
    check_cf(ds)
    ds = ds.copy(deep=False)
    ds.attrs = _netcdf_attrs(ds.attrs, "the Dataset")
    for name in list(ds.variables):
        ds[name].attrs = _netcdf_attrs(ds[name].attrs, repr(name))
    encoding = {}
    for name, var in ds.data_vars.items():
        enc = {}
        if var.dtype.kind in "fiu":
            enc = {"zlib": True, "complevel": 4, "shuffle": True}
        if var.dtype.kind == "f":
            enc["_FillValue"] = np.nan if var.dtype.itemsize >= 4 else None
        if var.chunks is not None:
            # one NetCDF chunk per dask block along each dim, capped to keep chunks modest
            enc["chunksizes"] = tuple(max(1, min(c[0], 4096)) for c in var.chunks)
        encoding[name] = enc
    return ds, encoding


def _tmp_name(path: pathlib.Path) -> pathlib.Path:
    return path.with_name(f".{path.name}{_TMP_TAG}{os.getpid()}-{threading.get_ident()}")


def _fsync(path: pathlib.Path) -> None:
    with contextlib.suppress(OSError), open(path, "rb") as fh:
        os.fsync(fh.fileno())


def _finish(_, tmp: pathlib.Path, path: pathlib.Path) -> str:
    _fsync(tmp)
    os.replace(tmp, path)
    return str(path)


def write(ds: xr.Dataset, path, *, compute: bool = False):
    """Write ``ds`` to CF NetCDF (netCDF4 engine, zlib level 4) atomically.

    Checks that every variable and coordinate carries ``units`` and ``long_name`` first. The data
    go to a temporary file in the same folder that is renamed to ``path`` only once fully written,
    so ``path`` never holds a partial file.

    Parameters
    ----------
    ds : xarray.Dataset or xarray.DataArray
        Data to write; lazy (dask) data are computed chunk by chunk during the write.
    path : str or pathlib.Path
        Destination file.
    compute : bool, default False
        If False, return a :class:`dask.delayed.Delayed` that performs the write (and the rename)
        when computed; if True, write now and return the path.

    Returns
    -------
    dask.delayed.Delayed or pathlib.Path

    Raises
    ------
    ValueError
        If a variable lacks ``units`` or ``long_name`` (see :func:`check_cf`).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> ds = xr.Dataset({"a": ("x", [1.0, 2.0], {"units": "m", "long_name": "a length"})})
    >>> ds["x"] = ("x", [0, 1], {"units": "1", "long_name": "index"})
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "a.nc"
    >>> rs.io.netcdf.write(ds, p, compute=True).name
    'a.nc'
    >>> float(rs.open_dataset(p)["a"].sum())
    3.0
    """
    import dask

    path = pathlib.Path(path)
    if not path.parent.exists():
        raise FileNotFoundError(f"folder {str(path.parent)!r} does not exist; create it first.")
    ds, encoding = _prepare(ds)
    tmp = _tmp_name(path)
    if compute:
        ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding)
        _finish(None, tmp, path)
        return path
    delayed_write = ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding, compute=False)
    return dask.delayed(_finish, pure=False)(delayed_write, tmp, path)


def open_dataset(path, *, chunks=None) -> xr.Dataset:
    """Open a NetCDF file written by roughstick (or a whole ensemble folder).

    Parameters
    ----------
    path : str or pathlib.Path
        A ``.nc`` file, or an ensemble folder (then :func:`open_ensemble` is used).
    chunks : dict, optional
        Passed to :func:`xarray.open_dataset` to get lazy dask arrays.

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If ``path`` is a temporary (partial) file left by an interrupted write.
    """
    path = pathlib.Path(path)
    if path.is_dir():
        return open_ensemble(path, chunks=chunks)
    if not path.exists():
        raise FileNotFoundError(f"no such file: {str(path)!r}")
    if _TMP_TAG in path.name:
        raise ValueError(
            f"{str(path)!r} is a temporary file left by an interrupted write, not a complete result; "
            "delete it (a resumed run recomputes that block)."
        )
    return xr.open_dataset(path, engine="netcdf4", chunks=chunks)


# ----------------------------------------------------------------------------- ensemble folders
def block_name(i: int, j: int) -> str:
    """File name of block (realization chunk ``i``, humidity chunk ``j``)."""
    return f"block-r{i:05d}-h{j:03d}.nc"


def read_manifest(folder) -> dict | None:
    """The manifest of an ensemble folder, or None if there is none."""
    p = pathlib.Path(folder) / MANIFEST
    if not p.exists():
        return None
    try:
        m = json.loads(p.read_text())
    except json.JSONDecodeError as exc:  # pragma: no cover - atomic writes make this unlikely
        raise ValueError(f"{str(p)!r} is not valid JSON ({exc}); delete the folder or pass overwrite=True.") from exc
    if m.get("format") != MANIFEST_FORMAT:
        raise ValueError(f"{str(p)!r} is not a roughstick ensemble manifest (format {m.get('format')!r}).")
    return m


def write_manifest(folder, manifest: dict) -> None:
    """Write ``manifest.json`` atomically (temporary file + rename)."""
    folder = pathlib.Path(folder)
    p = folder / MANIFEST
    tmp = _tmp_name(p)
    with _LOCK:
        tmp.write_text(json.dumps(manifest, indent=1, sort_keys=True))
        _finish(None, tmp, p)


def remove_partial_files(folder) -> list[pathlib.Path]:
    """Delete temporary files left by interrupted writes in ``folder``; return their paths."""
    removed = []
    for p in pathlib.Path(folder).iterdir():
        if _TMP_TAG in p.name:
            with contextlib.suppress(FileNotFoundError):
                p.unlink()
            removed.append(p)
    return removed


def valid_block(path, *, params_hash: str, block: tuple[int, int]) -> bool:
    """True if ``path`` is a complete block file of the run with ``params_hash``."""
    path = pathlib.Path(path)
    if not path.exists():
        return False
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return (
                ds.attrs.get("roughstick_params_hash") == params_hash
                and int(ds.attrs.get("roughstick_block_realization", -1)) == block[0]
                and int(ds.attrs.get("roughstick_block_rh", -1)) == block[1]
                and int(ds.attrs.get("roughstick_block_complete", 0)) == 1
            )
    except (OSError, ValueError, KeyError, RuntimeError):
        return False


def open_ensemble(folder, *, chunks=None, allow_incomplete: bool = False) -> xr.Dataset:
    """Open an ensemble folder as one Dataset over (realization, rh[, distance]).

    Parameters
    ----------
    folder : str or pathlib.Path
        Folder written by :func:`roughstick.run_ensemble` with ``output=folder``.
    chunks : dict, optional
        Passed to :func:`xarray.open_dataset` for each block (``{}`` gives one dask chunk per block).
    allow_incomplete : bool, default False
        Return the completed realization chunks only (those with every humidity chunk written)
        instead of raising when the run is unfinished.

    Returns
    -------
    xarray.Dataset
        With the run's global attributes from the manifest.

    Raises
    ------
    FileNotFoundError
        If ``folder`` holds no manifest.
    ValueError
        If blocks are missing (an interrupted run: the message says how to resume).
    """
    folder = pathlib.Path(folder)
    m = read_manifest(folder)
    if m is None:
        raise FileNotFoundError(
            f"{str(folder)!r} holds no {MANIFEST}: it is not an ensemble folder written by "
            "roughstick.run_ensemble(output=...) or `roughstick run`."
        )
    n_r = len(m["realization_chunks"])
    n_h = len(m["rh_chunks"])
    rows, missing = [], []
    for i in range(n_r):
        row = []
        for j in range(n_h):
            p = folder / block_name(i, j)
            if valid_block(p, params_hash=m["params_hash"], block=(i, j)):
                row.append(p)
            else:  # missing, or not a complete block of this run: never used
                missing.append(p.name)
                row = None
                break
        if row is not None:
            rows.append(row)
    if missing and not allow_incomplete:
        raise ValueError(
            f"ensemble in {str(folder)!r} is incomplete: {len(missing)} block(s) missing "
            f"(e.g. {missing[0]}). Resume it by running the same command or call again "
            "(run_ensemble(..., output=folder) / `roughstick run CONFIG`), or pass allow_incomplete=True."
        )
    if not rows:
        raise ValueError(f"ensemble in {str(folder)!r} has no completed realization chunk yet.")
    grid = [[xr.open_dataset(p, engine="netcdf4", chunks=chunks) for p in row] for row in rows]
    ds = xr.combine_nested(
        grid,
        concat_dim=["realization", "rh"],
        data_vars="minimal",
        coords="minimal",
        compat="override",
        join="exact",
        combine_attrs="override",
    )
    ds.attrs = dict(m.get("attrs", {}))
    if missing:
        ds.attrs["incomplete"] = f"{len(rows)} of {n_r} realization chunks"
    return ds
