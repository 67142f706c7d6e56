"""Cost estimate and progress of long computations (the boundary-element models, ensembles).

Before a boundary-element run starts, :class:`WorkProgress` logs (logger ``roughstick``, INFO) what
it is about to compute and an estimate of the time it will take; while it runs it shows a tqdm bar
when interactive (a terminal, or a Jupyter widget when ``ipywidgets`` is installed) and otherwise
INFO lines at most every 30 s and at each tenth of the work (what the ``roughstick`` command prints
line by line, for batch jobs without a terminal). :func:`progress_bar` is the dask callback of the
same bar.

The estimate is ``constant x (one numpy rfft2 + irfft2 pair of the map, timed now) x solves``: the
FFT pair measures this machine's speed on this map size, :data:`BEM_SOLVE_FFT_PAIRS` and
:data:`FFT_BEM_STATE_FFT_PAIRS` the cost of one solve in FFT pairs, within a factor of about 3
(docs/performance.md, "Cost estimates").
"""

from __future__ import annotations

import contextlib
import contextvars
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
    "estimate_model_seconds",
    "format_seconds",
    "duration",
    "interactive",
    "tqdm_class",
    "progress_bar",
    "WorkProgress",
    "StagedProgress",
    "staged_progress",
    "current_staged_progress",
]

_LOG = logging.getLogger("roughstick")

#: One Tamaas solve in FFT pairs of the same map at 64 x 64 pixels; scales as (pixels / 64^2)^0.3.
BEM_SOLVE_FFT_PAIRS = 1500.0
#: One fft_bem state (one distance) in FFT pairs of the same map at 64 x 64 pixels; scales as
#: (pixels / 64^2)^-0.25.
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


#: Seconds of one modified-DMT or GW curve of a 256 x 256 map, scaled with the pixels: whole
#: six-humidity calls (checks included) on Table 4, S2 and smooth maps of 256² and 1024² took
#: 0.001-0.015 s per curve so scaled (docs/evidence/rough_contact.md, "Speed of the default call").
DMT_CURVE_SECONDS_256 = 0.005


def estimate_model_seconds(model: str, shape, curves: int, points: int = 47) -> float:
    """Estimated wall time [s] of ``curves`` curves (maps x humidities) of ``points`` distances
    by a contact model of :func:`roughstick.contact.curves` on maps of ``shape``.

    ``"bem"`` and ``"fft_bem"``: :func:`estimate_seconds` for every point solved (the BEM's
    default grid is fft_bem's, which it computes first); ``"modified_dmt"`` and ``"gw"``:
    :data:`DMT_CURVE_SECONDS_256` per curve, scaled with the pixels (these are rarely long).

    Examples
    --------
    >>> from roughstick._core.progress import estimate_model_seconds
    >>> estimate_model_seconds("modified_dmt", (512, 512), 2)
    0.04
    """
    if model in ("modified_dmt", "gw"):
        return DMT_CURVE_SECONDS_256 * float(np.prod(shape)) / 256**2 * int(curves)
    fft = estimate_seconds("fft_bem", shape, int(curves) * int(points))
    return fft if model == "fft_bem" else fft + estimate_seconds("bem", shape, int(curves) * int(points))


def format_seconds(seconds: float) -> str:
    """``"about 40 s"``, ``"about 3 min"``, ``"about 1.5 h"``."""
    if not np.isfinite(seconds):
        return "unknown"
    return f"about {duration(seconds)}"


def duration(seconds: float) -> str:
    """``"40 s"``, ``"3 min"``, ``"1.5 h"``."""
    if seconds < 90:
        return f"{max(seconds, 1):.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


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


def progress_bar(progress: bool | None = None, **kwargs):
    """A dask callback showing a tqdm progress bar (terminal or Jupyter), or a no-op.

    ``progress=None`` shows it only when interactive: stderr is a terminal or the code runs in a
    Jupyter kernel, and the ``CI`` environment variable is not set.

    Examples
    --------
    >>> from roughstick._core.progress import progress_bar
    >>> with progress_bar(False):
    ...     pass
    """
    if progress is None:
        progress = interactive()
    if not progress:
        return contextlib.nullcontext()
    from tqdm.dask import TqdmCallback

    return TqdmCallback(tqdm_class=tqdm_class(), **kwargs)


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
        self.estimate, self.unit, self.progress, self.rechecked = estimate, unit, progress, False
        long = estimate is None or estimate >= PROGRESS_THRESHOLD
        self.task = progress is None and not foreground()
        if self.task:
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
            if self.done > self.total:  # more work than announced (solver retries): total follows
                self.total = self.done
                if self.bar is not None:
                    self.bar.total = self.total
            if self.bar is not None:
                self.bar.update(k)
            now = time.monotonic()
            self._recheck(now)
            if not self.lines:
                return
            if self.done >= self.total or self.done % self.step == 0 or now - self.last >= self.every:
                self.last = now
                el = now - self.t0
                eta = el / self.done * (self.total - self.done) if self.done else float("nan")
                _LOG.info(f"{self.what.split(':')[0]}: {self.done}/{self.total} done "
                          f"({100 * self.done / self.total:.0f} %), {duration(el)} elapsed, "
                          f"about {duration(eta) if np.isfinite(eta) else '? s'} left at the measured rate")

    def _recheck(self, now: float) -> None:
        """Once the measured time per unit puts the whole run outside a factor 3 of the estimate,
        say so with the time left at the measured rate; a run found long shows its progress
        lines from then on (unless ``progress=False``, or a task of a larger computation)."""
        if self.rechecked or self.estimate is None or self.done < min(2, self.total):
            return
        el = now - self.t0
        projected = el / self.done * self.total
        if max(projected, self.estimate) < PROGRESS_THRESHOLD:
            return  # short either way: nothing worth a line
        if self.estimate / 3 <= projected <= 3 * self.estimate:
            return
        self.rechecked = True
        if self.task or self.progress is False:
            return
        word = "slower" if projected > self.estimate else "faster"
        _LOG.info(f"{self.what.split(':')[0]}: {word} than estimated: {self.done} of {self.total} "
                  f"{self.unit} took {duration(el)} ({el / self.done:.3g} s each, against "
                  f"{self.estimate / self.total:.3g} s estimated): about "
                  f"{duration(projected - el)} left at the measured rate, "
                  f"{duration(projected)} in all")
        if word == "slower" and self.bar is None and not self.lines:
            self.lines = True  # estimated short, measured long: follow it

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None
        if self.lines and 0 < self.done < self.total:  # less work than announced: say it ended
            self.lines = False
            _LOG.info(f"{self.what.split(':')[0]}: {self.done}/{self.done} done (100 %), "
                      f"{duration(time.monotonic() - self.t0)} elapsed ({self.total} {self.unit} "
                      "were estimated)")

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


_STAGED: contextvars.ContextVar[StagedProgress | None] = contextvars.ContextVar(
    "roughstick_staged_progress", default=None)


class StagedProgress:
    """Progress of work made of points whose cost is not known in advance (the levels of a
    subset simulation run until a target is met): one INFO line per completed stage, each with
    the time left re-estimated from what has run.

    The time left is the evaluations still expected times the measured seconds per evaluation:
    once a point is done, each remaining point is expected to need as many evaluations as the
    points done did on average; before that, only the evaluation ``budget`` of each point bounds
    it ("at most").

    Parameters
    ----------
    points : int
        Points of work (e.g. humidities x lengths x layers).
    what : str
        Name of the work in each line (``"subset"``).
    budget : int, optional
        Evaluations allowed per point (``max_evaluations``).
    clock : callable
        Seconds (``time.monotonic``; a test may pass its own).

    Examples
    --------
    >>> from roughstick._core.progress import StagedProgress
    >>> t = iter(range(0, 100, 10))
    >>> p = StagedProgress(2, what="subset", budget=400, clock=lambda: next(t))
    >>> p.start_point("RH 0.5")
    >>> p.stage("level 0", evaluations=100)
    'subset RH 0.5 (point 1 of 2): level 0, 100 evaluations (0.1 s each); 20 s elapsed, at most 70 s left (at most 400 evaluations per point)'
    >>> p.start_point("RH 0.7")
    >>> p.stage("level 0", evaluations=300)
    'subset RH 0.7 (point 2 of 2): level 0, 300 evaluations (0.05 s each); 40 s elapsed, about 1 s left (as the 1 point done); at most 5 s left (at most 400 evaluations per point)'
    """

    def __init__(self, points: int, *, what: str, budget: int | None = None, clock=time.monotonic):
        self.points, self.what, self.budget, self.clock = max(int(points), 1), what, budget, clock
        self.t0 = clock()
        self.context = ""  # set by the caller: what the current point is (e.g. a beam length)
        self.point = 0  # points started
        self.done_evaluations: list[int] = []  # evaluations of each finished point
        self.spent = 0  # evaluations of the current point
        self.measured = [0, 0.0]  # evaluations computed here and their seconds (resumed ones: none)
        self.label = ""
        self.cap = budget  # evaluations a point may take at most (set_cap)

    def set_cap(self, evaluations: int) -> None:
        """The most evaluations a point may take: the budget, or more where one run of the
        estimator may overshoot it (subset simulation completes the run it started)."""
        self.cap = max(int(evaluations), self.budget or 0)

    def start_point(self, label: str = "") -> None:
        """A new point starts (the previous one, if any, is done)."""
        if self.point:
            self.done_evaluations.append(self.spent)
        self.point += 1
        self.spent = 0
        self.label = " ".join(v for v in (self.context, label) if v)
        self._t = self.clock()

    def stage(self, text: str, *, evaluations: int, computed: bool = True) -> str:
        """Log (and return) the line of a completed stage of ``evaluations`` model evaluations
        (``computed=False``: read back from a previous run, so not timed)."""
        now = self.clock()
        self.spent += int(evaluations)
        if computed:
            self.measured[0] += int(evaluations)
            self.measured[1] += now - self._t
        self._t = now
        per = self.measured[1] / self.measured[0] if self.measured[0] else float("nan")
        left_points = self.points - self.point
        line = (f"{self.what} {self.label} (point {min(self.point, self.points)} of {self.points}): "
                f"{text}, {self.spent} evaluations ({per:.2g} s each); "
                f"{duration(now - self.t0)} elapsed, {self._left(per, left_points)}")
        _LOG.info(line)
        return line

    def _left(self, per: float, left_points: int) -> str:
        if not np.isfinite(per):
            return "time left unknown until an evaluation is timed"
        bound = (None if self.cap is None else
                 (max(self.cap - self.spent, 0) + self.cap * left_points) * per)
        at_most = ("" if bound is None else
                   f"at most {duration(bound)} left (at most {self.cap} evaluations per point)")
        if not self.done_evaluations:
            return at_most or "time left unknown until a point is done"
        mean = float(np.mean(self.done_evaluations))
        left = (max(mean - self.spent, 0.0) + mean * left_points) * per
        n = len(self.done_evaluations)
        return (f"about {duration(left)} left (as the {n} point{'s' * (n > 1)} done)"
                + (f"; {at_most}" if at_most else ""))


@contextlib.contextmanager
def staged_progress(points: int, *, what: str, budget: int | None = None):
    """The :class:`StagedProgress` stages report to within the block: a new one of ``points``
    points, or the one an outer block already set (it counts the points of the whole command).
    """
    outer = _STAGED.get()
    if outer is not None:
        yield outer
        return
    prog = StagedProgress(points, what=what, budget=budget)
    token = _STAGED.set(prog)
    try:
        yield prog
    finally:
        _STAGED.reset(token)


def current_staged_progress() -> StagedProgress | None:
    """The :class:`StagedProgress` set by the calling code, if any."""
    return _STAGED.get()
