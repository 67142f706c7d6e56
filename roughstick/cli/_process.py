"""What a ``roughstick`` command process does about other processes and about its own end.

* :func:`lock_folder`: one run writes into an output folder at a time. The lock file
  :data:`LOCK` names the process holding it; a second run is refused before it touches anything
  (naming the first and ``--out``); the lock of a run that is gone (killed, failed, its machine
  down) is taken over, so it never blocks the next run. :func:`release_folders` removes it.
* :func:`run_stoppable`: one Ctrl-C ends the command's process within moments, whatever it is
  computing or writing, leaving no partial file and no lock, and what was complete for the re-run
  to resume.
"""

from __future__ import annotations

import atexit
import contextlib
import contextvars
import json
import os
import pathlib
import signal
import socket
import sys
import threading
import time

import psutil

from ..io.netcdf import remove_own_partial_files

__all__ = ["LOCK", "LOCK_REFRESH", "LOCK_EXPIRES", "lock_folder", "release_folders", "run_stoppable",
           "interrupted_message"]

#: File saying which process is writing an output folder now (:func:`lock_folder`).
LOCK = ".roughstick-lock"
#: Seconds between two refreshes of the time stamp of a lock this process holds, and the age after
#: which the lock of a run on another machine (whose process cannot be looked up from here) counts
#: as abandoned.
LOCK_REFRESH = 30.0
LOCK_EXPIRES = 180.0
_HELD: dict[pathlib.Path, str] = {}  # lock file -> the text this process wrote into it
_HELD_LOCK = threading.Lock()
_REFRESHER: list[threading.Thread] = []


def lock_folder(folder, *, command: str) -> None:
    """Make this process the one writer of ``folder``: create its lock file :data:`LOCK` (pid,
    machine, process start time, command), or refuse if another live run holds it.

    A lock whose run is gone is taken over: on this machine, when no process of that pid and start
    time runs (the run was killed or failed); a lock written on another machine (a shared file
    system), when its time stamp, refreshed every :data:`LOCK_REFRESH` s while its run lives, is
    older than :data:`LOCK_EXPIRES` s. Locking a folder this process holds already does nothing.
    The lock is removed by :func:`release_folders`.

    Raises
    ------
    FileExistsError
        Another live run is writing to ``folder`` (the message names it, and ``--out``).
    """
    folder = pathlib.Path(folder)
    path = (folder / LOCK).absolute()
    if path in _HELD:
        return
    me = {"pid": os.getpid(), "host": socket.gethostname(), "created": _process_created(os.getpid()),
          "command": command, "started": time.strftime("%Y-%m-%d %H:%M:%S")}
    text = json.dumps(me)
    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline:
        try:
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            seen, other = _read_lock(path)
            if seen is None:  # removed since
                continue
            if other is None and _age(path) < 5.0:  # its writer is filling it in this instant
                time.sleep(0.05)
                continue
            if other is not None and _lock_alive(other, path):
                if (other.get("pid"), other.get("host"), other.get("created")) == (
                        me["pid"], me["host"], me["created"]):  # this process's, but not recorded
                    _hold(path, seen)
                    return
                raise FileExistsError(_busy(folder, other, path)) from None
            _take_over(path, seen)  # the run that wrote it is gone (or it is not a lock)
            continue
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        _hold(path, text)
        return
    raise FileExistsError(f"could not lock the output folder {str(folder)!r}: its {LOCK} keeps changing; "
                          "is another run starting there? Write elsewhere with --out.")


def release_folders(folder=None) -> None:
    """Remove the locks this process holds (only that of ``folder`` if given), each only if it is
    still this process's (:func:`lock_folder`)."""
    want = None if folder is None else (pathlib.Path(folder) / LOCK).absolute()
    got = _HELD_LOCK.acquire(timeout=2.0)  # bounded: also called from the Ctrl-C handler
    try:
        for path, text in list(_HELD.items()):
            if want is not None and path != want:
                continue
            _HELD.pop(path, None)
            if _read_lock(path)[0] == text:
                with contextlib.suppress(OSError):
                    path.unlink()
    finally:
        if got:
            _HELD_LOCK.release()


def _hold(path: pathlib.Path, text: str) -> None:
    with _HELD_LOCK:
        _HELD[path] = text
        if not _REFRESHER:  # one daemon thread per process keeps the held locks' time stamps fresh
            atexit.register(release_folders)
            t = threading.Thread(target=_refresh_locks, name="roughstick folder locks", daemon=True)
            _REFRESHER.append(t)
            t.start()


def _refresh_locks() -> None:
    while True:
        time.sleep(LOCK_REFRESH)
        for path in list(_HELD):
            with contextlib.suppress(OSError):
                os.utime(path)


def _read_lock(path: pathlib.Path) -> tuple[str | None, dict | None]:
    """The text of the lock file (None: there is none) and its record (None: not a lock record)."""
    try:
        text = path.read_text()
    except FileNotFoundError:
        return None, None
    except (OSError, UnicodeDecodeError):
        return "", None
    try:
        rec = json.loads(text)
    except ValueError:
        return text, None
    ok = isinstance(rec, dict) and isinstance(rec.get("pid"), int) and isinstance(rec.get("host"), str)
    return text, rec if ok else None


def _age(path: pathlib.Path) -> float:
    try:
        return time.time() - path.stat().st_mtime
    except OSError:
        return 0.0


def _process_created(pid: int) -> float | None:
    """Start time of process ``pid`` (with the pid, it names one process: pids are reused)."""
    try:
        return round(psutil.Process(pid).create_time(), 2)
    except psutil.Error:
        return None


def _lock_alive(rec: dict, path: pathlib.Path) -> bool:
    """Whether the run that wrote the lock record ``rec`` may still be writing."""
    if rec["host"] != socket.gethostname():  # its process cannot be looked up from here
        return _age(path) < LOCK_EXPIRES
    try:
        proc = psutil.Process(rec["pid"])
        if proc.status() == psutil.STATUS_ZOMBIE:  # ended, not yet waited for by its parent
            return False
        created = round(proc.create_time(), 2)
    except psutil.NoSuchProcess:
        return False
    except psutil.Error:  # exists, but is not ours to look at: take it for the run
        return True
    return rec.get("created") is None or abs(created - float(rec["created"])) < 1.0


def _take_over(path: pathlib.Path, seen: str) -> None:
    """Remove the abandoned lock ``path`` whose text was ``seen``, unless another process replaced
    it in the meantime (then it is put back)."""
    aside = path.with_name(f"{LOCK}.stale-{os.getpid()}-{threading.get_ident()}")
    try:
        os.replace(path, aside)
    except FileNotFoundError:  # another process took it over first
        return
    try:
        if aside.read_text() != seen:  # a new lock was made in between: not ours to remove
            with contextlib.suppress(OSError):
                os.link(aside, path)  # no-op if yet another one is there
    finally:
        with contextlib.suppress(OSError):
            aside.unlink()


def _busy(folder: pathlib.Path, rec: dict, path: pathlib.Path) -> str:
    where = f"pid {rec['pid']}" if rec["host"] == socket.gethostname() else (
        f"pid {rec['pid']} on {rec['host']}; if that run was stopped, its lock expires at "
        f"{time.strftime('%H:%M:%S', time.localtime(time.time() - _age(path) + LOCK_EXPIRES))}")
    return (f"another roughstick run is writing to {str(folder)!r} (`roughstick {rec.get('command', '?')}`, "
            f"{where}, started {rec.get('started', '?')}); wait for it to finish or write elsewhere "
            "with --out OTHER_FOLDER.")


# ----------------------------------------------------------------------------- Ctrl-C
def _end_children(wait: float = 0.5) -> None:
    """Terminate the processes this one started (and theirs), killing those still there after
    ``wait`` seconds."""
    try:
        children = psutil.Process().children(recursive=True)
    except psutil.Error:
        return
    for c in children:
        with contextlib.suppress(psutil.Error):
            c.terminate()
    _, alive = psutil.wait_procs(children, timeout=wait)
    for c in alive:
        with contextlib.suppress(psutil.Error):
            c.kill()


def interrupted_message(command: str) -> str:
    """The line an interrupted command prints."""
    return (f"roughstick {command}: interrupted; completed results are kept: re-run the same "
            "command to resume.")


def run_stoppable(func, args, *, command: str):
    """Run ``func(args)`` so that one Ctrl-C (SIGINT) ends the process within moments, whatever
    the work is doing; return what ``func`` returns, or raise what it raised.

    The work runs in a thread of its own (marked as the caller's for
    :func:`roughstick._core.progress.foreground`) while the main thread only waits for it, so the
    signal is handled at once and never inside the work: a ``KeyboardInterrupt`` raised in the
    work could land in a library between taking and releasing a lock (netCDF's file lock), which
    its clean-up, or a thread the interpreter waits for on exit, then waited for forever. The
    handler ends the processes this one started (the workers of ``--scheduler processes``, which
    would outlive it), lets a file being written finish (up to a second; no new one is started)
    and deletes the temporary files left (:func:`roughstick.io.netcdf.remove_own_partial_files`),
    removes its folder locks, prints :func:`interrupted_message` and ends the process with status
    130 without waiting for the work's threads. What was written is complete under its final name
    (files are renamed into place once written), so re-running the same command resumes, as after
    a kill.
    Outside the main thread (where signals cannot be handled), ``func(args)`` is called directly.
    """
    if threading.current_thread() is not threading.main_thread():
        return func(args)
    outcome = {}

    def work():
        try:
            outcome["value"] = func(args)
        except BaseException as exc:  # noqa: BLE001 - raised again in the main thread
            outcome["error"] = exc

    def stop(signum, frame):
        _end_children()
        remove_own_partial_files()
        release_folders()
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        lead = "\n" if sys.stderr is not None and sys.stderr.isatty() else ""  # after a progress bar
        with contextlib.suppress(OSError):
            os.write(2, (lead + interrupted_message(command) + "\n").encode())
        os._exit(130)

    # the command's thread sees the caller's context (e.g. how its warnings spell their remedies)
    worker = threading.Thread(target=contextvars.copy_context().run, args=(work,),
                              name=f"roughstick {command}", daemon=True)
    worker.roughstick_foreground = True
    previous = signal.signal(signal.SIGINT, stop)
    try:
        worker.start()
        while worker.is_alive():
            worker.join(0.5)  # a timed wait: the handler runs within moments on every platform
    finally:
        signal.signal(signal.SIGINT, previous)
    if "error" in outcome:
        raise outcome.pop("error")
    return outcome.get("value")
