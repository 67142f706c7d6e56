"""Cost estimate and progress of long computations (the boundary-element models, issue 16 item 2).

Before a boundary-element run starts, :class:`WorkProgress` logs (logger ``roughstick``, INFO) what
it is about to compute and an estimate of the time it will take; while it runs it shows a tqdm bar
when interactive (a terminal, or a Jupyter widget when ``ipywidgets`` is installed) and otherwise
INFO lines at most every 30 s and at each tenth of the work (what the ``roughstick`` command prints
line by line, for batch jobs without a terminal).

The estimate is ``constant x (one numpy rfft2 + irfft2 pair of the map, timed now) x solves``: the
FFT pair measures this machine's speed on this map size, the constants below the cost of one solve
in FFT pairs. They come from ``nice -n 19 python benchmarks/bench_bem_cost.py`` (three surface
families, 64^2-256^2, RH 0.5; ratios within one run): one Tamaas solve took 884-1173 FFT pairs at
64^2, 2301-2995 at 128^2 and 3111-4300 at 256^2; on a loaded machine, in one run, 8342 at 256^2
and 10916 at 512^2 (S1, 4 distances: the ratio grows 1.3x per 4x pixels there). The model
``1500 (N_pixels / 64^2)^0.3`` is within a factor 1.5 of all of them (4600 at 512^2 for the quiet
machine's FFT); one
fft_bem state 9-12 FFT pairs at 64^2, 6-10 at 128^2, 4-9 at 256^2 (after the first call, whose
numba compilation costs ~1 s) and 2.3 at 1024^2 (``roughstick curves data_samples/S1A.nc --rh 0.3
0.7 --model auto``: 92 states in 5 s), i.e. about ``12 (N_pixels / 64^2)^-0.25``. Expect the
estimate within a factor of ~3 (the solver's iterations depend on the surface and humidity, and
maps above 512^2 are extrapolated); the S1 256^2 BEM run at RH 0.5 (23 solves) took 18.6 s.
"""

from __future__ import annotations

import logging
import os
import sys
import threading
import time

import numpy as np

__all__ = [
    "BEM_SOLVE_FFT_PAIRS",
    "FFT_BEM_STATE_FFT_PAIRS",
    "fft_pair_seconds",
    "estimate_seconds",
    "format_seconds",
    "interactive",
    "tqdm_class",
    "WorkProgress",
]

_LOG = logging.getLogger("roughstick")

#: One Tamaas solve in FFT pairs of the same map at 64 x 64 pixels; scales as (pixels / 64^2)^0.3
#: (benchmarks/bench_bem_cost.py, see the module docstring).
BEM_SOLVE_FFT_PAIRS = 1500.0
#: One fft_bem state (one distance) in FFT pairs of the same map at 64 x 64 pixels; scales as
#: (pixels / 64^2)^-0.25 (benchmarks/bench_bem_cost.py; ~2.3 at 1024^2, S1A map, see docstring).
FFT_BEM_STATE_FFT_PAIRS = 12.0
#: Runs estimated at least this long [s] show a progress bar / lines by default.
PROGRESS_THRESHOLD = 5.0


def fft_pair_seconds(shape, *, repeats: int = 3) -> float:
    """Seconds of one numpy ``rfft2`` + ``irfft2`` pair on a map of ``shape`` (min of ``repeats``)."""
    shape = tuple(int(s) for s in shape)
    z = np.random.default_rng(0).standard_normal(shape)
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        np.fft.irfft2(np.fft.rfft2(z), s=shape)
        best = min(best, time.perf_counter() - t0)
    return float(best)


def estimate_seconds(model: str, shape, solves: int) -> float:
    """Estimated wall time [s] of ``solves`` solves of ``model`` ("bem" or "fft_bem") on ``shape``.

    Examples
    --------
    >>> from roughstick._core.progress import estimate_seconds
    >>> estimate_seconds("bem", (64, 64), 10) > estimate_seconds("fft_bem", (64, 64), 10)
    True
    """
    npix = float(np.prod(shape))
    if model == "bem":
        per = BEM_SOLVE_FFT_PAIRS * (npix / 64**2) ** 0.3
    elif model == "fft_bem":
        per = FFT_BEM_STATE_FFT_PAIRS * (npix / 64**2) ** -0.25
    else:
        raise ValueError(f"no cost model for {model!r}; known: 'bem', 'fft_bem'.")
    return float(per * fft_pair_seconds(shape) * max(int(solves), 0))


def format_seconds(seconds: float) -> str:
    """``"about 40 s"``, ``"about 3 min"``, ``"about 1.5 h"``."""
    if not np.isfinite(seconds):
        return "unknown"
    if seconds < 90:
        return f"about {max(seconds, 1):.0f} s"
    if seconds < 5400:
        return f"about {seconds / 60:.0f} min"
    return f"about {seconds / 3600:.1f} h"


def interactive() -> bool:
    """True on a terminal or in a Jupyter kernel (and the ``CI`` environment variable unset)."""
    if os.environ.get("CI", "").lower() not in ("", "0", "false", "no"):
        return False
    try:  # Jupyter kernels have no tty but do show widgets
        from IPython import get_ipython

        ip = get_ipython()
        if ip is not None and "IPKernelApp" in getattr(ip, "config", {}):
            return True
    except ImportError:  # pragma: no cover
        pass
    return bool(getattr(sys.stderr, "isatty", lambda: False)())


def tqdm_class():
    """tqdm.auto (a Jupyter widget) when ipywidgets is there, else the text bar."""
    try:
        import ipywidgets  # noqa: F401
        from tqdm.auto import tqdm
    except ImportError:
        from tqdm import tqdm
    return tqdm


def foreground() -> bool:
    """True in the thread that runs the caller's work: the main thread, or the thread a
    ``roughstick`` command runs in (marked ``roughstick_foreground``), not a pool's worker."""
    t = threading.current_thread()
    return t is threading.main_thread() or getattr(t, "roughstick_foreground", False)


class WorkProgress:
    """Announce a long computation with its estimated cost, then report its progress.

    Parameters
    ----------
    total : int
        Units of work (e.g. humidity x distance points).
    what : str
        What is computed, e.g. ``"bem: 2 humidities x 40 distances on a 256 x 256 map"``.
    unit : str
        Name of one unit of work in the messages (``"points"``).
    estimate : float, optional
        Estimated seconds (:func:`estimate_seconds`).
    progress : bool or None
        ``True``: always show progress; ``False``: only the start line (INFO); ``None``: show it
        when the estimate is at least 5 s and this is the caller's own thread (the main thread, or
        the thread a ``roughstick`` command runs in; not a task of an ensemble, whose own progress
        is shown). Shown as a tqdm bar when :func:`interactive` (a
        widget in Jupyter with ipywidgets), else as INFO log lines.
    every : float
        Seconds between log lines (non-interactive).

    Examples
    --------
    >>> from roughstick._core.progress import WorkProgress
    >>> with WorkProgress(3, what="demo", estimate=0.1, progress=False) as p:
    ...     p.update(3)
    """

    def __init__(self, total: int, *, what: str, estimate: float | None = None,
                 progress: bool | None = None, every: float = 30.0, unit: str = "points"):
        self.total, self.what, self.every = max(int(total), 1), what, float(every)
        self.done = 0
        self.bar = None
        self.lines = False
        self._lock = threading.Lock()
        long = estimate is None or estimate >= PROGRESS_THRESHOLD
        if progress is None and not foreground():
            long = False  # a task of a larger computation (an ensemble block): it has its own
        show = progress if progress is not None else long
        est = "" if estimate is None else (
            f", estimated {format_seconds(estimate)} (cost model of "
            "benchmarks/bench_bem_cost.py, within a factor ~3)")
        _LOG.log(logging.INFO if (long or progress) else logging.DEBUG,
                 f"{what}: {self.total} {unit} to compute{est}")
        if show:
            if interactive():
                self.bar = tqdm_class()(total=self.total, desc=what.split(":")[0],
                                         leave=False, file=sys.stderr)
            else:
                self.lines = True
        self.t0 = self.last = time.monotonic()
        self.step = max(1, self.total // 10)

    def update(self, k: int = 1) -> None:
        with self._lock:
            self.done += k
            if self.bar is not None:
                self.bar.update(k)
            if not self.lines:
                return
            now = time.monotonic()
            if self.done >= self.total or self.done % self.step == 0 or now - self.last >= self.every:
                self.last = now
                el = now - self.t0
                eta = el / self.done * (self.total - self.done) if self.done else float("nan")
                _LOG.info(f"{self.what.split(':')[0]}: {self.done}/{self.total} done "
                          f"({100 * self.done / self.total:.0f} %), {el:.0f} s elapsed, "
                          f"about {eta:.0f} s left")

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
