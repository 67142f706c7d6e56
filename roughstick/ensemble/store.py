"""Streamed ensembles: one CF NetCDF file per block, a manifest, resume after an interruption.

An ensemble folder (written by :func:`roughstick.ensemble.run` with ``output=``) holds

``manifest.json``
    the run's parameters, their hash, the block layout and the blocks completed so far;
``block-r<i>-h<j>.nc``
    one CF NetCDF file per (realization chunk ``i``, humidity chunk ``j``), each carrying the
    parameters hash and its block index in its attributes.

Every file is written atomically (:func:`roughstick.io.netcdf.write`), so a file under its final
name is complete: a killed run leaves at most a temporary file, which :func:`open_ensemble`
ignores and a resumed run deletes. A resumed run recomputes only the blocks that are not complete
(:func:`pending_blocks`), and refuses a folder that holds a run with other parameters.
"""

from __future__ import annotations

import json
import pathlib
import shutil

import xarray as xr

from .._core.conventions import append_history
from ..io.netcdf import remove_partial_files, write, write_text_atomic
from .pipeline import Spec

__all__ = ["open_ensemble"]

#: Name of the manifest of an ensemble folder.
MANIFEST = "manifest.json"

#: Format tag written into every manifest.
MANIFEST_FORMAT = "roughstick-ensemble/1"


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
    write_text_atomic(pathlib.Path(folder) / MANIFEST, json.dumps(manifest, indent=1, sort_keys=True))


def valid_block(path, *, params_hash: str, block: tuple[int, int]) -> bool:
    """True if ``path`` is a complete block file of the run with ``params_hash``."""
    path = pathlib.Path(path)
    if not path.exists():
        return False
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return _block_attrs_ok(ds.attrs, params_hash, block)
    except (OSError, ValueError, KeyError, RuntimeError):
        return False


def _block_attrs_ok(attrs, params_hash, block) -> bool:
    return (
        attrs.get("roughstick_params_hash") == params_hash
        and int(attrs.get("roughstick_block_realization", -1)) == block[0]
        and int(attrs.get("roughstick_block_rh", -1)) == block[1]
        and int(attrs.get("roughstick_block_complete", 0)) == 1
    )


def _open_block(path, params_hash, block, chunks):
    """The block opened once and checked on its own attributes (None: missing or not a complete
    block of this run)."""
    if not path.exists():
        return None
    try:
        ds = xr.open_dataset(path, engine="netcdf4", chunks=chunks)
    except (OSError, ValueError, KeyError, RuntimeError):
        return None
    try:
        if _block_attrs_ok(ds.attrs, params_hash, block):
            return ds
    except (ValueError, KeyError):
        pass
    ds.close()
    return None


def open_ensemble(folder, *, chunks=None, allow_incomplete: bool = False) -> xr.Dataset:
    """Open an ensemble folder as one Dataset over (realization, rh[, distance]).

    Parameters
    ----------
    folder : str or pathlib.Path
        Folder written by :func:`roughstick.ensemble.run` with ``output=folder``.
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
            "roughstick.ensemble.run(output=...) or `roughstick run`."
        )
    n_r = len(m["realization_chunks"])
    n_h = len(m["rh_chunks"])
    rows, missing = [], []
    for i in range(n_r):
        row = []
        for j in range(n_h):
            p = folder / block_name(i, j)
            ds = _open_block(p, m["params_hash"], (i, j), chunks)
            if ds is None:  # missing, or not a complete block of this run: never used
                missing.append(p.name)
                for other in row:
                    other.close()
                row = None
                break
            row.append(ds)
        if row is not None:
            rows.append(row)
    if missing and not allow_incomplete:
        raise ValueError(
            f"ensemble in {str(folder)!r} is incomplete: {len(missing)} block(s) missing "
            f"(e.g. {missing[0]}). Resume it by running the same command or call again "
            "(roughstick.ensemble.run(..., output=folder) / `roughstick run CONFIG`), or pass allow_incomplete=True."
        )
    if not rows:
        raise ValueError(f"ensemble in {str(folder)!r} has no completed realization chunk yet.")
    ds = xr.combine_nested(
        rows,
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


def _manifest_for(spec: Spec, n, attrs) -> dict:
    rblocks = spec.realization_blocks(0, n)
    return {
        "format": MANIFEST_FORMAT,
        "params_hash": spec.token,
        "n": int(n),
        "realization_chunks": [[a, b] for _, a, b in rblocks],
        "rh_chunks": [[lo, hi] for _, lo, hi in spec.rh_blocks()],
        "relative_humidity": spec.rh.tolist(),
        "shape": list(spec.shape),
        "spacing": spec.spacing,
        "seed": str(spec.seed.entropy),
        "attrs": {k: v for k, v in attrs.items() if isinstance(v, (str, int, float))},
        "completed": [],
        "complete": False,
    }


def prepare_folder(folder: pathlib.Path, spec: Spec, n: int, attrs: dict, overwrite: bool) -> dict:
    """Make ``folder`` ready to receive the blocks of ``spec`` (``n`` realizations); return its
    manifest, keeping the completed blocks of the same run and refusing to mix runs."""
    if folder.exists() and not folder.is_dir():
        raise FileExistsError(f"output {str(folder)!r} exists and is not a folder; choose another path.")
    m = read_manifest(folder) if folder.exists() else None
    if m is not None and m["params_hash"] != spec.token:
        if not overwrite:
            raise FileExistsError(
                f"output folder {str(folder)!r} holds a run with different parameters "
                f"(hash {m['params_hash']} != {spec.token}); refusing to mix them. To resume that run, "
                "use its original parameters/config; to replace it, pass overwrite=True "
                "(`roughstick run CONFIG --overwrite`); or choose another output folder."
            )
        shutil.rmtree(folder)
        m = None
    if m is None and folder.exists() and any(folder.iterdir()):
        if not overwrite:
            raise FileExistsError(
                f"output folder {str(folder)!r} is not empty and holds no roughstick manifest; "
                "choose an empty or new folder, or pass overwrite=True (`--overwrite`) to clear it."
            )
        shutil.rmtree(folder)
    folder.mkdir(parents=True, exist_ok=True)
    remove_partial_files(folder)
    new = _manifest_for(spec, n, attrs)
    if m is not None:
        new["completed"] = [c for c in m.get("completed", []) if (folder / c).exists()]
    write_manifest(folder, new)
    return new


def pending_blocks(folder: pathlib.Path, spec: Spec, manifest: dict, start: int, n: int) -> list:
    """Blocks ``(i, a, b, j, lo, hi)`` of realizations ``[start, n)`` still to compute; blocks found
    complete on disk but not yet in the manifest (killed between the two writes) are recorded."""
    todo = []
    done = set(manifest["completed"])
    for i, a, b in spec.realization_blocks(start, n):
        for j, lo, hi in spec.rh_blocks():
            name = block_name(i, j)
            if name in done and valid_block(folder / name, params_hash=spec.token, block=(i, j)):
                continue
            if (folder / name).exists() and valid_block(folder / name, params_hash=spec.token, block=(i, j)):
                manifest["completed"].append(name)  # written but not yet recorded when killed
                continue
            todo.append((i, a, b, j, lo, hi))
    return todo


def write_block(folder: pathlib.Path, spec: Spec, manifest: dict, attrs: dict, i: int, j: int,
                ds: xr.Dataset) -> None:
    """Write block ``(i, j)`` of the run and record it in the manifest (in that order)."""
    ds = ds.copy()
    ds.attrs = {**attrs, "roughstick_params_hash": spec.token, "roughstick_block_realization": i,
                "roughstick_block_rh": j, "roughstick_block_complete": 1}
    append_history(ds, f"ensemble.run block {i} (realizations), {j} (humidities) of run "
                       f"{spec.token}")
    name = block_name(i, j)
    write(ds, folder / name, compute=True, overwrite=True)
    manifest["completed"].append(name)
    write_manifest(folder, manifest)


def record_attrs(folder, attrs: dict) -> None:
    """Add ``attrs`` (str/int/float values) to the run's global attributes in the manifest, so that
    :func:`open_ensemble` (and the band written from it) carries them, e.g. ``auto_converged``."""
    m = read_manifest(folder)
    if m is None:
        raise FileNotFoundError(f"{str(folder)!r} holds no {MANIFEST}; nothing to record into.")
    m["attrs"] = {**m.get("attrs", {}),
                  **{k: v for k, v in attrs.items() if isinstance(v, (str, int, float))}}
    write_manifest(folder, m)


def finish_manifest(folder: pathlib.Path, spec: Spec, manifest: dict, n: int) -> None:
    """Record whether every block of ``n`` realizations is written."""
    manifest["completed"] = sorted(set(manifest["completed"]))
    total = len(spec.realization_blocks(0, n)) * len(spec.rh_blocks())
    manifest["complete"] = len(manifest["completed"]) >= total
    write_manifest(folder, manifest)
