"""What every ``roughstick`` sub-command shares: logging, output folders, user-facing errors.

* ``--quiet`` / ``--verbose`` set the level of the standard ``logging`` logger ``roughstick``;
  INFO lines go to stdout, warnings and errors to stderr, one flushed line each, so batch jobs
  (SLURM, CI, ``nohup``) see progress as it happens, not at the end.
* Python warnings raised during a command are logged as one line ``warning: Category: text``
  (not the source line inside dask or the console script).
* :func:`claim_folder` records which command (and parsed parameters) wrote an output folder,
  before any work. Re-running the same command resumes or rewrites it; another command's (or
  other parameters') complete results are replaced only with ``--overwrite``, and their files
  are removed first; an unfinished (failed or killed) run never blocks the next.
* :func:`claim_folder` also locks the folder until the command ends (:mod:`._process`): a second
  run into a folder another live run is writing to is refused before it touches anything.
* :func:`check_scheduler` refuses a dask scheduler name before any work, naming the flag or key.
* :func:`add_figure_options` gives every command that draws figures the same ``--format`` and
  ``--dpi`` (:func:`figure_options` reads them back for :func:`roughstick.plotting.save_figure`).
* :func:`user_message` turns the errors a user can fix (bad configuration, missing or damaged
  file, read-only folder, unreachable scheduler) into one line naming the fix; anything else is
  a bug and keeps its traceback.
"""

from __future__ import annotations

import calendar
import contextlib
import errno
import json
import logging
import os
import pathlib
import re
import shutil
import sys
import time
import warnings

from .._core.remedy import config_key
from .._core.units import parse_quantity
from .._core.validate import figure_dpi, figure_format
from ..io.netcdf import WRITTEN_LOG, remove_partial_files, write_text_atomic, written_names
from ..plotting.save import DEFAULT_DPI, DEFAULT_FORMAT
from ._process import lock_folder, release_folders
from ._schema import SCHEMAS

__all__ = ["LOG", "positive_int", "add_common_options", "add_figure_options", "figure_options", "setup_logging", "teardown_logging", "claim_folder", "finish_folder", "run_status",
           "user_message", "MARKER", "small_p_problems", "canonical_params", "check_scheduler",
           "check_output_file", "NETCDF_SUFFIXES", "config_spellings", "fixed_spellings"]

LOG = logging.getLogger("roughstick")

#: File recording which command wrote an output folder, and whether it finished.
MARKER = ".roughstick-run.json"


def positive_int(text: str) -> int:
    """argparse type: an integer >= 1 (``--n 0`` is refused, not silently replaced)."""
    import argparse

    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {v}")
    return v


def refuse_bare_number(text: str, unit: str) -> None:
    """argparse check: a value without its unit is refused, naming an example ``unit``."""
    import argparse

    try:
        float(text)
    except ValueError:
        return
    raise argparse.ArgumentTypeError(f"{text!r} has no unit; write it with one, e.g. '{text} {unit}'")


def length_with_unit(text: str) -> str:
    """argparse type: a length with its unit (``--spacing 5`` is refused: read as m it made a
    5 m pixel and a nonsense Γ; the config files refuse a bare number the same way)."""
    import argparse

    refuse_bare_number(text, "nm")
    try:
        parse_quantity(text, "length", name="the length")
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"{text!r}: {exc}") from None
    return text


def add_common_options(p, *, overwrite: bool = True) -> None:
    """``--quiet``, ``--verbose`` (and ``--overwrite``) on a sub-command parser."""
    g = p.add_mutually_exclusive_group()
    g.add_argument("-q", "--quiet", action="store_true", help="print warnings and errors only")
    g.add_argument("-v", "--verbose", action="store_true", help="print debugging details too")
    if overwrite:
        p.add_argument("--overwrite", action="store_true",
                       help="replace results of another run in the output folder")


def _figure_format(text: str) -> str:
    import argparse

    try:
        return figure_format(text, name="--format")
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _figure_dpi(text: str) -> int:
    import argparse

    try:
        return figure_dpi(text, name="--dpi")
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def add_figure_options(p) -> None:
    """``--format png|pdf|svg`` and ``--dpi N`` on a sub-command that writes figures: one
    definition for every command, checked by argparse before any work."""
    p.add_argument("--format", dest="figure_format", type=_figure_format, default=DEFAULT_FORMAT,
                   metavar="{png,pdf,svg}",
                   help=f"file format of the figures (default {DEFAULT_FORMAT}; pdf and svg are vector "
                        "formats for reports)")
    p.add_argument("--dpi", type=_figure_dpi, default=DEFAULT_DPI,
                   help=f"resolution of the figures in dots per inch, 50-1200 (default {DEFAULT_DPI}; "
                        "for pdf/svg it applies to embedded images such as height maps)")


def figure_options(args) -> dict:
    """The figure options :func:`add_figure_options` parsed, as keyword arguments of
    :func:`roughstick.plotting.save_figure` (``format``, ``dpi``)."""
    return {"format": args.figure_format, "dpi": args.dpi}


class _Below(logging.Filter):
    def __init__(self, level):
        super().__init__()
        self.level = level

    def filter(self, record):
        return record.levelno < self.level


def setup_logging(*, quiet: bool = False, verbose: bool = False) -> None:
    """Route the ``roughstick`` logger to stdout (INFO) and stderr (WARNING and above)."""
    for h in list(LOG.handlers):
        LOG.removeHandler(h)
    out = logging.StreamHandler(sys.stdout)
    out.addFilter(_Below(logging.WARNING))
    err = logging.StreamHandler(sys.stderr)
    err.setLevel(logging.WARNING)
    fmt = logging.Formatter("%(message)s")
    for h in (out, err):
        h.setFormatter(fmt)
        LOG.addHandler(h)
    LOG.setLevel(logging.WARNING if quiet else logging.DEBUG if verbose else logging.INFO)
    LOG.propagate = False

    shown = set()

    def show(message, category, filename, lineno, file=None, line=None):
        text = f"warning: {category.__name__}: {message}"
        if text not in shown:  # the same advice once per command, not once per call site
            shown.add(text)
            LOG.warning("%s", text)

    warnings.showwarning = show


def teardown_logging() -> None:
    """Remove the handlers :func:`setup_logging` installed (a library user's logging is theirs)."""
    for h in list(LOG.handlers):
        LOG.removeHandler(h)
    LOG.setLevel(logging.NOTSET)
    LOG.propagate = True


#: What a roughstick command writes into its folder (figures, NetCDF, tables, manifests): the
#: only kinds of entry a replacement removes (a user's notes or config beside them stay).
_RESULT_SUFFIXES = frozenset({".nc", ".png", ".csv", ".json", ".npy", ".pdf", ".svg"})
_FILE_SUFFIXES = frozenset({".nc", ".png", ".csv", ".json", ".toml", ".npy", ".pdf", ".svg", ".txt"})
#: Slack on file times (coarse file-system clocks) when telling a run's files by their time.
_SLACK = 1.0


def canonical_params(params):
    """``params`` as plain JSON values: keys sorted, paths as text, arrays as lists, floats to 12
    significant digits, so the same parameters compare equal however the file spelled them
    (comments, whitespace, key order, "5 nm" or "5.0 nm")."""
    import numpy as np

    if isinstance(params, dict):
        return {str(k): canonical_params(params[k]) for k in sorted(params, key=str)}
    if isinstance(params, (list, tuple)):
        return [canonical_params(v) for v in params]
    if isinstance(params, np.ndarray):
        return canonical_params(params.tolist())
    if isinstance(params, np.generic):
        params = params.item()
    if params is None or isinstance(params, (bool, int, str)):
        return params
    if isinstance(params, float):
        return float(f"{params:.12g}")
    return str(params)


def check_scheduler(value, *, where: str) -> None:
    """Refuse a dask scheduler name before any work starts; ``where`` names the flag or key."""
    if value is None or value in ("threads", "threading", "sync", "synchronous", "processes") or (
            isinstance(value, str) and re.fullmatch(r"(tcp|tls|inproc|ucx)://\S+", value)):
        return
    raise ValueError(f"{where}{' ' if where.startswith('--') else ' = '}{value!r}: not a dask scheduler; use 'threads', 'sync', 'processes' "
                     "or the address of a running dask scheduler, tcp://host:port.")


#: Names a NetCDF output file may have.
NETCDF_SUFFIXES = (".nc", ".nc4", ".netcdf")


def check_output_file(path, *, flag: str = "--out", suffixes=NETCDF_SUFFIXES, overwrite: bool = False) -> pathlib.Path:
    """Refuse, before any work, an output file that would be written wrong or not at all: another
    extension than ``suffixes`` (a NetCDF file named ``.png``), a folder, an existing file without
    ``overwrite``, or a place that cannot be written. Creates the missing parent folders; every
    message names ``flag``."""
    path = pathlib.Path(path)
    if path.is_dir():
        raise FileExistsError(f"{flag} {str(path)!r} is a folder; give a file name, e.g. "
                              f"{str(path / ('result' + suffixes[0]))!r}.")
    if path.suffix.lower() not in suffixes:
        stem = path.with_suffix(suffixes[0]) if path.suffix else path.with_name(path.name + suffixes[0])
        kind = "a NetCDF file" if suffixes == NETCDF_SUFFIXES else f"written as {' or '.join(suffixes)}"
        raise ValueError(f"{flag} {str(path)!r}: the output is {kind}; give it the {suffixes[0]} extension, "
                         f"e.g. {flag} {stem}")
    if path.exists() and not overwrite:
        raise FileExistsError(f"{flag} {str(path)!r} exists; pass --overwrite to replace it or choose another name.")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        probe = path.parent / f".{path.name}.probe-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        raise FileExistsError(f"cannot write {flag} {str(path)!r} ({exc.strerror or exc}); choose a "
                              f"writable place with {flag}.") from None
    return path


def claim_folder(folder, *, command: str, params: dict, overwrite: bool, keep=(),
                 legacy_params: dict | None = None) -> pathlib.Path:
    """Create ``folder`` (parents too) for ``command``; refuse to mix it with another run's results.

    The marker file :data:`MARKER` records ``command`` and ``params`` (compared as
    :func:`canonical_params`, so a comment added to a config file changes nothing) and says
    "running" until :func:`finish_folder`. When this run replaces another one (other command or
    parameters: a complete run with ``overwrite``, or an unfinished run), the other run's result
    files are removed first, so a run killed midway never leaves the old results beside the new
    marker. A rerun with the same parameters keeps them (it resumes or rewrites the same results).
    A run's results are the files roughstick wrote for it: while it runs, every file renamed into
    place there is noted in the folder's written-files log (``io.netcdf.WRITTEN_LOG``); when it
    finishes, the marker lists them. Never removed: what is not a result file (``.nc``, ``.png``,
    ``.csv``, ``.json``, ``.npy`` or a folder of them), what the run did not write (what was there
    before, a figure the user saved there while it ran), files named in ``params`` and the paths in
    ``keep`` (the config file). ``legacy_params``: what a marker
    written by an earlier roughstick recorded for these parameters (the raw config text).

    First of all the folder is locked for this process (:func:`lock_folder`, released by
    :func:`finish_folder` or when the command ends, however it ends).

    Raises
    ------
    FileExistsError
        ``folder`` holds the complete results of a different command or parameters and
        ``overwrite`` is False (the message names ``--overwrite`` and ``--out``), or is a file,
        or names a file (``--out result.nc``), or another live run is writing to it.
    """
    folder = pathlib.Path(folder)
    if folder.exists() and not folder.is_dir():
        raise FileExistsError(f"output {str(folder)!r} exists and is not a folder; choose another with --out.")
    if not folder.exists() and folder.suffix.lower() in _FILE_SUFFIXES:
        raise FileExistsError(f"--out {str(folder)!r} names a file, but `roughstick {command}` writes a "
                              f"folder of results; give a folder, e.g. --out {str(folder.with_suffix(''))!r}.")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise FileExistsError(f"cannot create the output folder {str(folder)!r} ({exc.strerror or exc}); "
                              "choose a writable folder with --out.") from None
    lock_folder(folder, command=command)  # before anything in it is read or removed
    marker = folder / MARKER
    old = _read_marker(marker)
    record = {"command": command, "params": canonical_params(params)}
    same = old is not None and (_same_record(old, record) or (
        legacy_params is not None and old.get("command") == command and old.get("params") == legacy_params))
    if old is not None and old.get("status") == "complete" and not same and not overwrite:
        what = (f"with different parameters ({_diff(old.get('params'), record['params'])})"
                if old.get("command") == command else "(another command)")
        raise FileExistsError(
            f"output folder {str(folder)!r} holds the complete results of `roughstick {old.get('command')}` "
            f"{what}; pass --overwrite to replace them or --out to write elsewhere.")
    removed = remove_partial_files(folder)
    if removed:
        LOG.debug("removed %d partial file(s) of an interrupted run", len(removed))
    since = time.time()
    if old is not None and not same:
        if old.get("status") == "complete":  # first un-complete it: a kill below leaves no "complete"
            write_text_atomic(marker, json.dumps({**old, "status": "running"}, indent=1, default=str))
        protected = ({pathlib.Path(k).resolve() for k in keep} | _named_paths(record["params"])
                     | _named_paths(old.get("params")))
        stale = [p for p in _results_of(folder, old) if p.resolve() not in protected]
        for p in stale:
            if p.is_dir() and not p.is_symlink():
                shutil.rmtree(p, ignore_errors=True)
            else:
                with contextlib.suppress(FileNotFoundError):
                    p.unlink()
        LOG.info(f"replacing the {'complete' if old.get('status') == 'complete' else 'unfinished'} run of "
                 f"`roughstick {old.get('command')}` in {folder}: removed its {len(stale)} result file(s) and folder(s)")
    carried = {}
    log = folder / WRITTEN_LOG
    earlier = written_names(folder) if same else None
    if same:  # resuming or rewriting: the files of the earlier attempts are this run's too
        since = min(since, _since(old))
        carried = {"outputs": old["outputs"]} if old.get("outputs") else {}
        if earlier is None and old.get("status") != "complete":  # a marker from before the log
            earlier = {p.name for p in _results_of(folder, old)}
    # the log of what this run writes (io.netcdf.publish appends to it): written before the marker
    # says "running", so an unfinished run always has one
    write_text_atomic(log, "".join(f"{n}\n" for n in sorted(earlier or ())))
    write_text_atomic(marker, json.dumps({**record, **carried, "status": "running", "since": since,
                                          "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(since))},
                                         indent=1, default=str))
    return folder


def _read_marker(marker: pathlib.Path) -> dict | None:
    try:
        old = json.loads(marker.read_text())
    except (OSError, ValueError):
        return None
    return old if isinstance(old, dict) else None


def _same_record(old: dict, record: dict) -> bool:
    return old.get("command") == record["command"] and json.dumps(
        canonical_params(old.get("params")), sort_keys=True) == json.dumps(record["params"], sort_keys=True)


def _named_paths(params) -> set:
    """Every text value of ``params`` that names an existing path (inputs: never removed)."""
    out = set()
    if isinstance(params, dict):
        params = list(params.values())
    if isinstance(params, list):
        for v in params:
            out |= _named_paths(v)
    elif isinstance(params, str) and ("/" in params or "\\" in params):
        with contextlib.suppress(OSError, ValueError):
            out.add(pathlib.Path(params).resolve())
    return out


def _is_result(p: pathlib.Path, depth: int = 3) -> bool:
    """A result file, or a folder holding one within ``depth`` levels (``subset-*/rh-0.5000/``)."""
    if p.is_dir() and not p.is_symlink():
        return depth > 0 and any(_is_result(c, depth - 1) for c in p.iterdir())
    return p.suffix.lower() in _RESULT_SUFFIXES


def _since(rec: dict) -> float:
    if "since" in rec:
        return float(rec["since"])
    try:  # markers written before "since" existed
        return calendar.timegm(time.strptime(rec["started"], "%Y-%m-%dT%H:%M:%SZ"))
    except (KeyError, TypeError, ValueError):
        return 0.0  # unknown start: every result file may be that run's


def _results_of(folder: pathlib.Path, rec: dict) -> list[pathlib.Path]:
    """The result files (and folders) the run recorded in ``rec`` wrote into ``folder``: the list
    it recorded when it finished, and, if it never finished, those its written-files log names
    (``io.netcdf.publish``), so a figure the user saved there meanwhile is not taken for one. A
    marker from before the list or the log: every result written while the run ran."""
    entries = [p for p in folder.iterdir() if p.name != MARKER and _is_result(p)]
    listed = set(rec.get("outputs") or [])
    if rec.get("status") == "complete" and "outputs" in rec:
        return [p for p in entries if p.name in listed]
    logged = written_names(folder) if rec.get("status") != "complete" else None
    if logged is not None:
        return [p for p in entries if p.name in listed | logged]
    t0 = _since(rec) - _SLACK
    t1 = _finished(rec) + _SLACK  # a run that finished without a list (older markers): not after
    return [p for p in entries if p.name in listed or t0 <= p.stat().st_mtime <= t1]


def _finished(rec: dict) -> float:
    try:
        return calendar.timegm(time.strptime(rec["finished"], "%Y-%m-%dT%H:%M:%SZ"))
    except (KeyError, TypeError, ValueError):
        return float("inf")  # unfinished: everything since it started may be its


def run_status(folder) -> str | None:
    """"complete", "running" (unfinished: failed or killed), or None (no roughstick run there)."""
    rec = _read_marker(pathlib.Path(folder) / MARKER)
    return None if rec is None else rec.get("status")


def finish_folder(folder) -> None:
    """Mark the run in ``folder`` complete (see :func:`claim_folder`), listing the result files
    it wrote (those a later run with other parameters removes)."""
    folder = pathlib.Path(folder)
    marker = folder / MARKER
    rec = json.loads(marker.read_text())
    rec.update(status="complete", finished=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
               outputs=sorted(p.name for p in _results_of(folder, {**rec, "status": "running"})
                              if p.resolve() not in _named_paths(rec.get("params"))))
    write_text_atomic(marker, json.dumps(rec, indent=1, default=str))
    with contextlib.suppress(FileNotFoundError):  # complete: the list above says what is the run's
        (folder / WRITTEN_LOG).unlink()
    release_folders(folder)


def _flat(params, prefix="") -> dict:
    if not isinstance(params, dict):
        return {prefix or "parameters": params}
    out = {}
    for k, v in params.items():
        out.update(_flat(v, f"{prefix}.{k}" if prefix else str(k)) if isinstance(v, dict) else
                   {f"{prefix}.{k}" if prefix else str(k): v})
    return out


def _short(v, width: int = 40) -> str:
    text = "(none)" if v is _MISSING else repr(v)
    return text if len(text) <= width else text[:width - 3] + "..."


_MISSING = object()


def _diff(a, b, *, most: int = 3) -> str:
    """The keys that differ between two parameter sets: at most ``most``, values shortened."""
    a, b = _flat(a or {}), _flat(b or {})
    keys = [k for k in sorted(set(a) | set(b)) if a.get(k, _MISSING) != b.get(k, _MISSING)]
    d = [f"{k}: {_short(a.get(k, _MISSING))} -> {_short(b.get(k, _MISSING))}" for k in keys[:most]]
    if len(keys) > most:
        d.append(f"and {len(keys) - most} more")
    return "; ".join(d) or "the same parameters"


#: Python argument names that a message may mention, and the CLI flag to name instead.
_FLAGS = {"overwrite=True": "--overwrite", "output=": "--out ",
          "a smaller lower= to distance_grid": "a smaller [ensemble] distance_lower (roughstick run)"}


def user_message(exc: BaseException) -> str | None:
    """One line for an error the user can fix, or None for a bug (which keeps its traceback)."""
    if isinstance(exc, ConnectionError):
        return str(exc)
    if isinstance(exc, ImportError) and "pip install" in str(exc):
        return str(exc)  # an optional dependency, named with its install command
    if isinstance(exc, (FileNotFoundError, FileExistsError)) and exc.filename is None:
        return str(exc)  # our own messages
    if isinstance(exc, PermissionError) or getattr(exc, "errno", None) in (errno.EROFS, errno.EACCES):
        return (f"cannot write {exc.filename!r}: {exc.strerror.lower() if exc.strerror else exc}; "
                "choose a writable folder with --out.")
    if isinstance(exc, IsADirectoryError):
        return f"{exc.filename!r} is a folder, not a file; give a file."
    if isinstance(exc, NotADirectoryError):
        return f"{exc.filename!r}: a path component is a file, not a folder; choose another path with --out."
    if isinstance(exc, FileNotFoundError):
        return f"no such file or folder: {exc.filename!r}."
    if isinstance(exc, OSError) and getattr(exc, "errno", None) == errno.ENOSPC:
        return f"the disk is full while writing {exc.filename!r}; free space or choose another --out."
    if isinstance(exc, OSError):
        return f"{exc.filename or 'a file'}: {exc.strerror or exc}."
    if isinstance(exc, MemoryError) and str(exc):  # sized before allocating (or numpy's own)
        return str(exc)
    if isinstance(exc, ValueError):  # our validation errors (ConfigError, UnitsError ...)
        msg = str(exc)
        for py, flag in _FLAGS.items():
            msg = msg.replace(py, flag)
        return msg
    return None


def small_p_problems(section: str, settings: dict) -> list[str]:
    """What is wrong with the subset-simulation stopping rule of ``[section]`` (the keys
    ``method``, ``n_per_level``, ``max_evaluations``), shared by ``risk`` and ``beam``."""
    problems = []
    if settings["method"] == "subset" and settings["n_per_level"] % 5:
        problems.append(f"[{section}] n_per_level = {settings['n_per_level']}: must be a "
                        "multiple of 5 (20 % of each level seed the chains), e.g. 1000")
    if settings["max_evaluations"] < settings["n_per_level"]:
        problems.append(f"[{section}] max_evaluations = {settings['max_evaluations']} is below "
                        f"n_per_level = {settings['n_per_level']}: raise it (e.g. 20000)")
    return problems


def _model_key(table: str) -> str:
    """The key of the contact model in ``[table]``: ``model`` (``contact_model`` in a table whose
    schema still spells it so)."""
    old = any("contact_model" in tables.get(table, {}) for tables in SCHEMAS.values())
    return "contact_model" if old else "model"


def config_spellings(*, contact_model: str, surface: str = "surface", key: str | None = None,
                     samples: str | None = None) -> dict:
    """How the warnings of a command read from a configuration file spell their remedies
    (:mod:`roughstick._core.remedy`): keys of its tables, the contact model as ``key`` (default:
    the key the schema gives it) in ``[contact_model]``, the pixel in ``[surface]``, the samples
    per level of subset simulation as ``n_per_level`` in ``[samples]``."""
    more = {"samples_per_level": config_key(samples, "n_per_level", fmt=str)} if samples else {}
    return {**more,
        "contact_model": config_key(contact_model, key or _model_key(contact_model)),
        "spacing": config_key(surface, "spacing", fmt=lambda v: f'"{v * 1e9:.2g} nm"'),
        "resolution": lambda v=None, **kw: (f"the same run with [{surface}] spacing doubled (its size "
                                            "kept), compared with this one"),
        "height_distribution": config_key(surface, "height_distribution"),
        "surface_size": config_key(surface, "size", fmt=lambda v: f'"{v * 1e6:.4g} um"'),
        "levelling": config_key("psd", "level"),
    }


def fixed_spellings(command: str) -> dict:
    """How the warnings of a command whose settings are fixed (``demo``, ``reproduce``) spell
    their remedies: the key of a ``roughstick run`` configuration, where the user's own run
    can change it."""
    own = (f"in a `roughstick run` configuration (the settings of `roughstick {command}` are fixed: "
           "`roughstick examples --out examples` writes configurations to start from)")
    return {"contact_model": lambda v, **kw: f'[ensemble] model = "{v}" {own}',
            "spacing": lambda v, **kw: f'[surface] spacing = "{v * 1e9:.2g} nm" {own}',
            "resolution": lambda v=None, **kw: "`roughstick curves MAP --rh ... --resolution`"}
