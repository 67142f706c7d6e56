"""What every ``roughstick`` sub-command shares: logging, output folders, user-facing errors.

* ``--quiet`` / ``--verbose`` set the level of the standard ``logging`` logger ``roughstick``;
  INFO lines go to stdout, warnings and errors to stderr, one flushed line each, so batch jobs
  (SLURM, CI, ``nohup``) see progress as it happens, not at the end.
* Python warnings raised during a command are logged as one line ``warning: Category: text``
  (not the source line inside dask or the console script).
* :func:`claim_folder` records which command (and arguments) wrote an output folder. Re-running
  the same command resumes or rewrites it; another command's complete results are replaced only
  with ``--overwrite``; an unfinished (failed or killed) run never blocks the next.
* :func:`user_message` turns the errors a user can fix (bad configuration, missing or damaged
  file, read-only folder, unreachable scheduler) into one line naming the fix; anything else is
  a bug and keeps its traceback.
"""

from __future__ import annotations

import errno
import json
import logging
import pathlib
import sys
import time
import warnings

from .._core.units import parse_quantity
from ..io.netcdf import remove_partial_files, write_text_atomic

__all__ = ["LOG", "positive_int", "add_common_options", "setup_logging", "teardown_logging", "claim_folder", "finish_folder", "run_status",
           "user_message", "MARKER", "small_p_problems"]

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


def length_with_unit(text: str) -> str:
    """argparse type: a length with its unit (``--spacing 5`` is refused: read as m it made a
    5 m pixel and a nonsense Γ; the config files refuse a bare number the same way)."""
    import argparse

    try:
        float(text)
    except ValueError:
        pass
    else:
        raise argparse.ArgumentTypeError(f"{text!r} has no unit; write it with one, e.g. '{text} nm'")
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


def claim_folder(folder, *, command: str, params: dict, overwrite: bool) -> pathlib.Path:
    """Create ``folder`` (parents too) for ``command``; refuse to mix it with another run's results.

    Raises
    ------
    FileExistsError
        ``folder`` holds the complete results of a different command or arguments and
        ``overwrite`` is False (the message names ``--overwrite`` and ``--out``), or is a file.
    """
    folder = pathlib.Path(folder)
    if folder.exists() and not folder.is_dir():
        raise FileExistsError(f"output {str(folder)!r} exists and is not a folder; choose another with --out.")
    folder.mkdir(parents=True, exist_ok=True)
    marker = folder / MARKER
    old = None
    if marker.is_file():
        try:
            old = json.loads(marker.read_text())
        except (OSError, ValueError):
            old = None
    record = {"command": command, "params": params}
    if old is not None and old.get("status") == "complete" and \
            {k: old.get(k) for k in record} != record and not overwrite:
        raise FileExistsError(
            f"output folder {str(folder)!r} holds the complete results of `roughstick {old.get('command')}` "
            f"with other arguments ({_diff(old.get('params') or {}, params)}); pass --overwrite to "
            "replace them or --out to write elsewhere.")
    if old is not None and old.get("status") != "complete" and {k: old.get(k) for k in record} != record:
        LOG.info("replacing the unfinished run left in %s", folder)
    removed = remove_partial_files(folder)
    if removed:
        LOG.debug("removed %d partial file(s) of an interrupted run", len(removed))
    write_text_atomic(marker, json.dumps({**record, "status": "running",
                                          "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())},
                                         indent=1, default=str))
    return folder


def run_status(folder) -> str | None:
    """"complete", "running" (unfinished: failed or killed), or None (no roughstick run there)."""
    marker = pathlib.Path(folder) / MARKER
    try:
        return json.loads(marker.read_text()).get("status")
    except (OSError, ValueError):
        return None


def finish_folder(folder) -> None:
    """Mark the run in ``folder`` complete (see :func:`claim_folder`)."""
    marker = pathlib.Path(folder) / MARKER
    rec = json.loads(marker.read_text())
    rec.update(status="complete", finished=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()))
    write_text_atomic(marker, json.dumps(rec, indent=1, default=str))


def _diff(a: dict, b: dict) -> str:
    keys = sorted(set(a) | set(b))
    d = [f"{k}: {a.get(k)!r} -> {b.get(k)!r}" for k in keys if a.get(k) != b.get(k)]
    return "; ".join(d) or "another command"


#: Python argument names that a message may mention, and the CLI flag to name instead.
_FLAGS = {"overwrite=True": "--overwrite", "output=": "--out ",
          "a smaller lower= to ensemble_distance_grid": "a smaller [ensemble] distance_lower (roughstick run)"}


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
    if isinstance(exc, ValueError):  # our validation errors (ConfigError, UnitsError ...)
        msg = str(exc)
        for py, flag in _FLAGS.items():
            msg = msg.replace(py, flag)
        return msg
    return None


def small_p_problems(section: str, settings: dict) -> list[str]:
    """What is wrong with the subset-simulation stopping rule of ``[section]`` (the keys
    ``method``, ``samples_per_level``, ``max_evaluations``), shared by ``risk`` and ``beam``."""
    problems = []
    if settings["method"] == "subset" and settings["samples_per_level"] % 5:
        problems.append(f"[{section}] samples_per_level = {settings['samples_per_level']}: must be a "
                        "multiple of 5 (20 % of each level seed the chains), e.g. 1000")
    if settings["max_evaluations"] < settings["samples_per_level"]:
        problems.append(f"[{section}] max_evaluations = {settings['max_evaluations']} is below "
                        f"samples_per_level = {settings['samples_per_level']}: raise it (e.g. 20000)")
    return problems
