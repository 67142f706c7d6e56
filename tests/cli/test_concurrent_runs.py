"""Two runs into one output folder: the second is refused before it touches anything, naming the
first and --out; a run that failed or was killed never blocks the next one.

Two `roughstick risk` runs into one folder used to run side by side, and the cleanup of one
deleted the other's temporary files ("No such file or directory: '.../.roughstick-run.json.tmp-…'").
"""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import subprocess
import sys
import time

import pytest
from _configs import MOMENTS_PSD, SMALL_BEAM

import roughstick as rs
from roughstick.cli import main
from roughstick.cli import run as run_cmd
from roughstick.cli._common import MARKER
from roughstick.cli._process import LOCK, LOCK_EXPIRES, lock_folder, release_folders

#: A subset-simulation risk run of about 10 s of work after it has claimed its folder.
RISK = """
[output]
folder = "out"
[beam]
lengths = ["400 um"]
[surface]
shape = [16, 16]
[ensemble]
relative_humidity = [0.5, 0.55, 0.6, 0.65, 0.7, 0.75]
adsorbed_layer = ["paper"]
seed = 3
[risk]
method = "subset"
n_per_level = 50
target_cv = 0.5
max_evaluations = 400
levels = [0.01]
"""


def _cli(*args, **kw):
    return subprocess.Popen([sys.executable, "-m", "roughstick.cli", *map(str, args)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def test_two_risk_runs_started_together_into_one_folder_one_is_refused_up_front(tmp_path):
    cfg = tmp_path / "r.toml"
    cfg.write_text(RISK)
    out = tmp_path / "out"
    runs = [_cli("risk", cfg, "-q") for _ in range(2)]
    t0 = time.monotonic()
    while all(r.poll() is None for r in runs):
        assert time.monotonic() - t0 < 300, "neither run ended"
        time.sleep(0.01)
    loser, winner = runs if runs[0].poll() is not None else runs[::-1]
    overlapped = winner.poll() is None
    _, err_loser = loser.communicate(timeout=300)
    _, err_winner = winner.communicate(timeout=300)
    assert (winner.returncode, loser.returncode) == (0, 1), (err_winner[-600:], err_loser[-600:])
    assert overlapped, "the first run to end was refused only once the other had finished"
    assert re.fullmatch(
        re.escape(f"roughstick risk: error: another roughstick run is writing to {str(out)!r} "
                  f"(`roughstick risk`, pid {winner.pid}, started ") + r"[-\d: ]+" + re.escape(
            "); wait for it to finish or write elsewhere with --out OTHER_FOLDER."),
        err_loser.strip().splitlines()[-1]), err_loser
    # the results of the run that wrote are whole, and no lock or partial file is left
    assert json.loads((out / MARKER).read_text())["status"] == "complete"
    assert rs.open_dataset(out / "risk.nc").sizes["rh"] == 6
    assert not (out / LOCK).exists()
    assert not [p for p in out.rglob("*") if ".tmp-" in p.name]


@pytest.fixture
def held(tmp_path):
    """A folder locked by another live process (as a run writing there holds it)."""
    busy = tmp_path / "busy"
    busy.mkdir()
    holder = subprocess.Popen(
        [sys.executable, "-c", "import sys; from roughstick.cli._common import lock_folder; "
         "lock_folder(sys.argv[1], command='risk'); print('locked', flush=True); sys.stdin.read()",
         str(busy)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    assert holder.stdout.readline().strip() == "locked"
    yield busy, holder
    holder.kill()
    holder.wait()


def _configs(tmp_path):
    (tmp_path / "run.toml").write_text('title = "t"\n' + MOMENTS_PSD + '[surface]\nshape = [32, 32]\n'
                                      'spacing = "5 nm"\n[ensemble]\nn = 2\nrelative_humidity = [0.5]\n')
    (tmp_path / "beam.toml").write_text(SMALL_BEAM)
    (tmp_path / "risk.toml").write_text(RISK)
    return {"run": ["run", tmp_path / "run.toml"], "beam": ["beam", tmp_path / "beam.toml"],
            "risk": ["risk", tmp_path / "risk.toml"], "demo": ["demo", "--quick", "--only", "sphere"],
            "reproduce": ["reproduce", "--quick"]}


def test_every_command_refuses_a_folder_another_run_writes_to(tmp_path, held, capsys):
    busy, holder = held
    before = sorted(p.name for p in busy.iterdir())
    for name, args in _configs(tmp_path).items():
        assert main([*map(str, args), "--out", str(busy), "-q"]) == 1, name
        err = capsys.readouterr().err
        assert f"another roughstick run is writing to {str(busy)!r} (`roughstick risk`, pid {holder.pid}," in err
        assert "--out OTHER_FOLDER" in err, err
        assert sorted(p.name for p in busy.iterdir()) == before, name  # untouched


def test_a_killed_run_does_not_block_the_next(tmp_path, held, capsys):
    busy, holder = held
    holder.send_signal(signal.SIGKILL)
    holder.wait()
    assert (busy / LOCK).exists()  # left behind by the killed process
    assert main(["demo", "--quick", "--only", "sphere", "--out", str(busy), "-q"]) == 0
    assert json.loads((busy / MARKER).read_text())["status"] == "complete"
    assert not (busy / LOCK).exists()


def test_a_failed_run_does_not_block_the_next(tmp_path, monkeypatch, capsys):
    (tmp_path / "run.toml").write_text('title = "t"\n' + MOMENTS_PSD + '[surface]\nshape = [32, 32]\n'
                                      'spacing = "5 nm"\n[ensemble]\nn = 2\nrelative_humidity = [0.5]\n'
                                      '[output]\nfolder = "out"\n')

    def broken(*a, **kw):
        raise OSError(28, "No space left on device", "x.nc")

    monkeypatch.setattr(run_cmd.rs.ensemble, "run", broken)
    assert main(["run", str(tmp_path / "run.toml"), "-q"]) == 1
    assert not (tmp_path / "out" / LOCK).exists()


def _write_lock(folder, **rec):
    folder.mkdir(exist_ok=True)
    (folder / LOCK).write_text(json.dumps({"command": "risk", "started": "2026-01-01 00:00:00", **rec}))


def test_stale_locks_are_taken_over_and_live_ones_named(tmp_path):
    f = tmp_path / "f"
    try:
        # this machine, a pid that runs but was started at another time: a reused pid
        _write_lock(f, pid=os.getpid(), host=socket.gethostname(), created=1.0)
        lock_folder(f, command="run")
        assert json.loads((f / LOCK).read_text())["command"] == "run"
        release_folders(f)
        assert not (f / LOCK).exists()
        # another machine (a shared file system), refreshed recently: refused, its expiry said
        _write_lock(f, pid=1, host="elsewhere.invalid", created=1.0)
        with pytest.raises(FileExistsError, match=r"pid 1 on elsewhere.invalid; if that run was "
                                                  r"stopped, its lock expires at \d\d:\d\d:\d\d"):
            lock_folder(f, command="run")
        # ... and not refreshed for longer than LOCK_EXPIRES: abandoned
        old = time.time() - LOCK_EXPIRES - 10
        os.utime(f / LOCK, (old, old))
        lock_folder(f, command="run")
        release_folders(f)
        # an empty or damaged lock file, not just being written
        (f / LOCK).write_text("")
        os.utime(f / LOCK, (old, old))
        lock_folder(f, command="run")
        assert json.loads((f / LOCK).read_text())["pid"] == os.getpid()
    finally:
        release_folders()
