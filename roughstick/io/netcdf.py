"""CF NetCDF output: checked, zlib-compressed, atomic writes.

Every write goes to a temporary name in the destination folder and is renamed into place only
after the file is closed and flushed, so a file under its final name is always complete: a killed
run leaves at most a ``*.tmp-*`` file, which :func:`open_dataset` refuses and
:func:`remove_partial_files` deletes. Every file renamed into place (:func:`publish`, also used for
figures and caches) is noted in the written-files log (:data:`WRITTEN_LOG`) of the run folder
holding it, if any, so that a run folder knows its own results from files a user saved there. The
ensemble folders built on these files (one file per
block plus a manifest, resumable) are :mod:`roughstick.ensemble.store`.
"""

from __future__ import annotations

import contextlib
import json
import os
import pathlib
import threading

import dask
import numpy as np
import xarray as xr

__all__ = ["write", "open_dataset", "check_cf"]

_TMP_TAG = ".tmp-"
_LOCK = threading.Lock()

#: the log, in a command's output folder while its run is unfinished, of the result files (and
#: folders) written into it: one name per line, appended by :func:`publish` from any process
WRITTEN_LOG = ".roughstick-written"
_LOG_DEPTH = 4  # a result up to three folders below the run folder (subset-*/rh-0.5000/level.nc)
#: the temporary files this process has named and not yet renamed into place or deleted; no new
#: one once the process is ending (:func:`remove_own_partial_files`)
_PARTIAL: set[pathlib.Path] = set()
_PARTIAL_CHANGED = threading.Condition()
_ENDING = False


# ----------------------------------------------------------------------------- CF checks
def check_cf(ds: xr.Dataset) -> None:
    """Raise ``ValueError`` unless every variable and coordinate has ``units`` and ``long_name``
    (string labels: ``long_name`` only; :func:`write` drops their ``units``).

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
        need = ("long_name",) if var.dtype.kind in "OSU" else ("units", "long_name")  # labels: no units
        lack = [k for k in need if k not in var.attrs and k not in var.encoding]
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
        attrs = _netcdf_attrs(ds[name].attrs, repr(name))
        if ds[name].dtype.kind in "OSU":  # labels such as adsorbed_layer = "none"/"paper": no units
            attrs.pop("units", None)
        ds[name].attrs = attrs
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
    for name in ds.coords:  # CF: coordinate variables carry no _FillValue (they may not be missing)
        if name not in encoding and ds[name].dtype.kind in "fiu":
            encoding[name] = {"_FillValue": None}
    return ds, encoding


def _tmp_name(path: pathlib.Path) -> pathlib.Path:
    return partial_file(path.with_name(f".{path.name}{_TMP_TAG}{os.getpid()}-{threading.get_ident()}"))


def partial_file(tmp) -> pathlib.Path:
    """Note ``tmp`` as a temporary file this process is writing (until :func:`publish` renames it
    or it is deleted), so that :func:`remove_own_partial_files` can delete it; return it. Once the
    process is ending, no new one is started: the calling thread waits for the end."""
    tmp = pathlib.Path(tmp).absolute()
    with _PARTIAL_CHANGED:
        while _ENDING:
            _PARTIAL_CHANGED.wait()
        _PARTIAL.add(tmp)
    return tmp


def _forget(tmp: pathlib.Path) -> None:
    with _PARTIAL_CHANGED:
        _PARTIAL.discard(tmp)
        _PARTIAL_CHANGED.notify_all()


def discard_partial_file(tmp) -> None:
    """Delete the temporary file ``tmp`` of a failed or interrupted write (if it exists)."""
    tmp = pathlib.Path(tmp).absolute()
    with contextlib.suppress(OSError):
        tmp.unlink()
    _forget(tmp)


def remove_own_partial_files(wait: float = 1.0) -> None:
    """What a process about to end (an interrupted command) does to leave no partial file behind:
    start no new temporary file (:func:`partial_file`), give the writes under way up to ``wait``
    seconds to finish (their files are then complete under their final names), and delete the
    temporary files still there."""
    global _ENDING
    if not _PARTIAL_CHANGED.acquire(timeout=wait):
        return
    try:
        _ENDING = True
        _PARTIAL_CHANGED.wait_for(lambda: not _PARTIAL, timeout=wait)
        left = list(_PARTIAL)
    finally:
        _PARTIAL_CHANGED.release()
    for tmp in left:
        with contextlib.suppress(OSError):
            tmp.unlink()


def _fsync(path: pathlib.Path) -> None:
    with contextlib.suppress(OSError), open(path, "rb") as fh:
        os.fsync(fh.fileno())


def _finish(_, tmp: pathlib.Path, path: pathlib.Path) -> str:
    publish(tmp, path)
    return str(path)


def publish(tmp, path) -> None:
    """Flush the finished temporary file ``tmp`` and rename it to ``path``; note ``path`` in the
    written-files log (:data:`WRITTEN_LOG`) of the nearest folder above it that keeps one.

    The log is appended with one ``write`` in append mode, so writers in several threads or
    processes do not mix their lines; the name noted is the entry of the run folder that holds
    ``path`` (``subset-x`` for ``subset-x/rh-0.5000/run000-level00.nc``).
    """
    tmp, path = pathlib.Path(tmp), pathlib.Path(path)
    _fsync(tmp)
    os.replace(tmp, path)
    _forget(tmp.absolute())
    path = path.absolute()
    folder = path.parent
    for _ in range(_LOG_DEPTH):
        log = folder / WRITTEN_LOG
        if log.is_file():
            entry = path.relative_to(folder).parts[0]
            if entry.startswith("."):  # the run's own bookkeeping (its marker, this log)
                return
            line = (entry + "\n").encode()
            with contextlib.suppress(OSError):
                fd = os.open(log, os.O_WRONLY | os.O_APPEND)
                try:
                    os.write(fd, line)
                finally:
                    os.close(fd)
            return
        folder = folder.parent


def written_names(folder) -> set[str] | None:
    """The names noted in ``folder``'s written-files log (see :func:`publish`), or None if it has none."""
    try:
        text = (pathlib.Path(folder) / WRITTEN_LOG).read_text()
    except OSError:
        return None
    return {line for line in text.splitlines() if line}


def write(ds: xr.Dataset, path, *, compute: bool = True, overwrite: bool = False):
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
    compute : bool, default True
        If True, write now and return the path (as xarray's ``to_netcdf``); if False, return a
        :class:`dask.delayed.Delayed` that performs the write (and the rename) when computed.
    overwrite : bool, default False
        Replace an existing ``path``; without it an existing file is refused before anything is
        written (as the command line refuses it without ``--overwrite``).

    Returns
    -------
    dask.delayed.Delayed or pathlib.Path

    Raises
    ------
    ValueError
        If a variable lacks ``units`` or ``long_name`` (see :func:`check_cf`).
    FileExistsError
        If ``path`` exists and ``overwrite`` is False.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> ds = xr.Dataset({"a": ("x", [1.0, 2.0], {"units": "m", "long_name": "a length"})})
    >>> ds["x"] = ("x", [0, 1], {"units": "1", "long_name": "index"})
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "a.nc"
    >>> rs.io.netcdf.write(ds, p, compute=True).name
    'a.nc'
    >>> float(rs.io.open_dataset(p)["a"].sum())
    3.0
    """

    path = pathlib.Path(path)
    if not path.parent.exists():
        raise FileNotFoundError(f"folder {str(path.parent)!r} does not exist; create it first.")
    if path.exists() and not overwrite:
        raise FileExistsError(
            f"{str(path)!r} exists ({'a folder' if path.is_dir() else 'a file'}); write refuses to "
            "replace it: pass overwrite=True to replace it, or choose another path."
        )
    ds, encoding = _prepare(ds)
    tmp = _tmp_name(path)
    if compute:
        try:
            ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding)
            _finish(None, tmp, path)
        except BaseException:  # a failed or interrupted write leaves nothing behind
            discard_partial_file(tmp)
            raise
        return path
    delayed_write = ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding, compute=False)
    return dask.delayed(_finish, pure=False)(delayed_write, tmp, path)


def open_dataset(path, *, chunks=None) -> xr.Dataset:
    """Open a NetCDF file written by roughstick.

    Parameters
    ----------
    path : str or pathlib.Path
        A ``.nc`` file. An ensemble folder (``roughstick.ensemble.run(output=...)``) is opened with
        :func:`roughstick.ensemble.open_ensemble`.
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
        If ``path`` is a folder, or a temporary (partial) file left by an interrupted write.
    """
    path = pathlib.Path(path)
    if path.is_dir():
        raise ValueError(
            f"{str(path)!r} is a folder; an ensemble folder written by roughstick.ensemble.run(output=...) "
            "opens with roughstick.ensemble.open_ensemble(path)."
        )
    if not path.exists():
        raise FileNotFoundError(f"no such file: {str(path)!r}")
    if _TMP_TAG in path.name:
        raise ValueError(
            f"{str(path)!r} is a temporary file left by an interrupted write, not a complete result; "
            "delete it (a resumed run recomputes that block)."
        )
    try:
        return xr.open_dataset(path, engine="netcdf4", chunks=chunks)
    except OSError as exc:  # netCDF4 says "NetCDF: HDF error" / "Unknown file format"
        raise ValueError(
            f"cannot read {str(path)!r} as NetCDF ({exc}): the file is damaged, truncated or not "
            "a NetCDF file; re-create it (a roughstick run re-writes missing blocks) or give another file."
        ) from exc


# ----------------------------------------------------------------------------- other files
def write_text_atomic(path, text: str) -> None:
    """Write ``text`` to ``path`` atomically (temporary file in the same folder, then rename)."""
    path = pathlib.Path(path)
    tmp = _tmp_name(path)
    with _LOCK:
        try:
            tmp.write_text(text)
            _finish(None, tmp, path)
        except BaseException:
            discard_partial_file(tmp)
            raise


def remove_partial_files(folder) -> list[pathlib.Path]:
    """Delete temporary files left by interrupted writes in ``folder``; return their paths."""
    removed = []
    for p in pathlib.Path(folder).iterdir():
        if _TMP_TAG in p.name:
            with contextlib.suppress(FileNotFoundError):
                p.unlink()
            removed.append(p)
    return removed
