"""Ctrl-C (SIGINT) sent to real `roughstick` processes at varied moments (fault injection).

A KeyboardInterrupt raised wherever the main thread happened to be could land inside netCDF's
file lock while a finished block was being written: the clean-up then waited for that lock
forever, and the command printed "interrupted" but never exited (a quarter of the interrupts
sent while a block was written). Every interrupted process here must exit within BOUND seconds
with status 130 and the one line, leave no partial file and no folder lock, and its re-run
must compute only the blocks still missing.
"""

from __future__ import annotations

import os
import pathlib
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import psutil
import pytest
import xarray as xr
from _configs import MOMENTS_PSD

import roughstick as rs
from roughstick.cli import main
from roughstick.cli._common import MARKER
from roughstick.cli._process import LOCK, interrupted_message

#: A run of many small blocks (one realization of 16 x 16 pixels each), so that the main work is
#: a stream of block writes; no trial below gets near its end.
CONFIG = """
title = "interrupted"
""" + MOMENTS_PSD.lstrip("\n") + """[surface]
shape = [16, 16]
spacing = "5 nm"
[ensemble]
n = {n}
relative_humidity = [0.5]
seed = 11
chunks = 1
[output]
folder = "out"
figures = false
"""

#: Seconds an interrupted command may take to exit (it takes well under one; a generous bound for
#: a loaded machine: the failure it guards against is a process that never exits).
BOUND = 15.0


def _config(tmp_path, n):
    p = tmp_path / "c.toml"
    p.write_text(CONFIG.format(n=n))
    return p


class _Run:
    """`python -m roughstick.cli ARGS` in a subprocess, its output read as it comes."""

    def __init__(self, *args):
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "roughstick.cli", *map(str, args)],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
            env={**os.environ, "CI": "true"},  # progress as log lines, not a bar
            # a SIGINT ignored by the test runner's shell would be ignored by the child too
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
        self.out, self.err = [], []
        self._readers = [threading.Thread(target=self._read, args=(s, b), daemon=True)
                         for s, b in ((self.proc.stdout, self.out), (self.proc.stderr, self.err))]
        for t in self._readers:
            t.start()

    @staticmethod
    def _read(stream, lines):
        for line in stream:
            lines.append(line.rstrip("\n"))

    def wait_for(self, condition, what, limit=120.0):
        t0 = time.monotonic()
        while not condition():
            if self.proc.poll() is not None:
                raise AssertionError(f"exited ({self.proc.returncode}) before {what}: {self.err[-5:]}")
            if time.monotonic() - t0 > limit:
                self.proc.kill()
                raise AssertionError(f"no {what} within {limit} s")
            time.sleep(0.0005)

    def interrupt(self):
        """SIGINT now; the seconds until the process has exited (it is killed after BOUND)."""
        self.proc.send_signal(signal.SIGINT)
        t0 = time.monotonic()
        try:
            self.proc.wait(timeout=BOUND)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            raise AssertionError(f"still running {BOUND:g} s after one Ctrl-C; it printed "
                                 f"{self.err[-3:]}") from None
        for t in self._readers:
            t.join(5)
        return time.monotonic() - t0


def _blocks(ens: pathlib.Path) -> list[pathlib.Path]:
    return sorted(ens.glob("block-*.nc")) if ens.exists() else []


def _writing(ens: pathlib.Path) -> bool:
    """A block is being written now (its temporary file exists)."""
    try:
        return any(n.startswith(".block-") and ".tmp-" in n for n in os.listdir(ens))
    except FileNotFoundError:
        return False


def _interrupt_at_moments(tmp_path, moments, n):
    """Interrupt `roughstick run` once per moment, each a re-run of the same command in the same
    folder; check each exit and each resume. Return the number of blocks of the run."""
    cfg = _config(tmp_path, n)
    out = tmp_path / "out"
    ens = out / "ensemble"
    for k, (kind, delay) in enumerate(moments):
        kept = len(_blocks(ens))
        run = _Run("run", cfg)
        run.wait_for(lambda r=run: any("ensemble blocks:" in x for x in r.out), "the start of the work")
        if kind == "writing":  # while the main work writes a finished block
            run.wait_for(lambda k=kept: len(_blocks(ens)) > k, "a new block")
            run.wait_for(lambda: _writing(ens), "the writing of a block")
        t_end = time.perf_counter() + delay
        while time.perf_counter() < t_end:
            pass
        took = run.interrupt()
        at = f"trial {k} ({kind} + {delay:g} s)"
        assert run.proc.returncode == 130, (at, run.proc.returncode, run.err[-5:])
        assert run.err[-1] == interrupted_message("run"), (at, run.err[-5:])
        assert took < BOUND, at
        # resumed: the re-run computed only what the earlier attempts had not written
        line = next(x for x in run.out if "ensemble blocks:" in x)
        assert f"ensemble blocks: {n - kept} to compute" in line, (at, line, kept)
        # nothing partial, no lock; what is there is complete
        assert not [p for p in out.rglob("*") if ".tmp-" in p.name], at
        assert not (out / LOCK).exists(), at
        assert '"status": "running"' in (out / MARKER).read_text()
        for p in _blocks(ens):
            with xr.open_dataset(p) as b:
                assert int(b.attrs["roughstick_block_complete"]) == 1, (at, p.name)
    assert len(_blocks(ens)) < n, "the trials must end before the run does"
    return cfg


def test_ctrl_c_while_run_writes_blocks_exits_at_once_and_resumes(tmp_path):
    """Three interrupts of `roughstick run` in the same folder, each while a block is written."""
    _interrupt_at_moments(tmp_path, [("writing", 0.0), ("writing", 0.004), ("writing", 0.008)],
                          n=400)


@pytest.mark.slow
def test_ctrl_c_at_many_moments_then_the_resumed_run_is_bit_identical(tmp_path):
    """Fourteen interrupts at varied moments (the start of the work, a block being written, its
    end), then the resumed run completes and equals an uninterrupted run bit for bit."""
    moments = [("started", 0.0), ("started", 0.3)] + [
        ("writing", d) for d in (0.0, 0.002, 0.004, 0.006, 0.008, 0.010, 0.012, 0.016, 0.020,
                                 0.030, 0.050, 0.100)]
    n = 100
    cfg = _interrupt_at_moments(tmp_path, moments, n=n)
    done = subprocess.run([sys.executable, "-m", "roughstick.cli", "run", str(cfg), "-q"],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert main(["run", str(cfg), "-q", "--out", str(tmp_path / "ref")]) == 0
    got = rs.ensemble.open_ensemble(tmp_path / "out" / "ensemble").load()
    ref = rs.ensemble.open_ensemble(tmp_path / "ref" / "ensemble").load()
    assert got.sizes["realization"] == n
    xr.testing.assert_equal(got, ref)
    assert np.array_equal(got["adhesive_energy"].values, ref["adhesive_energy"].values, equal_nan=True)


def test_ctrl_c_ends_the_workers_of_scheduler_processes(tmp_path):
    """The process ends at once, not waiting for its threads: the worker processes of
    `--scheduler processes` must not outlive it (they held its output pipes open, for ever)."""
    ens = tmp_path / "out" / "ensemble"
    run = _Run("run", _config(tmp_path, 400), "--scheduler", "processes")
    run.wait_for(lambda: len(_blocks(ens)) > 0, "a block")
    workers = psutil.Process(run.proc.pid).children(recursive=True)
    assert workers
    run.interrupt()
    assert run.proc.returncode == 130 and run.err[-1] == interrupted_message("run")
    _, alive = psutil.wait_procs(workers, timeout=5)
    for w in alive:  # not left running by a failure here
        w.kill()
    assert not alive
