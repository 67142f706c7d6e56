"""Issue 16 item 2: long boundary-element work announces its cost before it starts and reports its
progress (log lines without a terminal, tqdm on a terminal, a widget in Jupyter)."""

from __future__ import annotations

import logging
import re
import sys

import numpy as np
import pytest

import roughstick as rs
from roughstick._core import progress as prog


def _map(n=32, family="rough"):
    return rs.datasets.surface_family(family, shape=(n, n), seed=3)


def _messages(caplog):
    return [r.getMessage() for r in caplog.records if r.name == "roughstick"]


def test_bem_estimate_comes_first_then_progress_lines(caplog):
    pytest.importorskip("tamaas")
    caplog.set_level(logging.INFO, logger="roughstick")
    h = _map()
    ds = rs.contact.curves(h, relative_humidity=[0.5, 0.9], model="bem", n_distance=6,
                                 progress=True)
    msgs = _messages(caplog)
    # one estimate for both humidities, each on its own automatic grid (``solved``)
    assert msgs[0].startswith(f"bem: 1 map(s) of 32 x 32 pixels x 2 humidities x "
                              f"{ds.sizes['distance']} distances")
    assert sum(m.startswith("bem: 1 map(s)") for m in msgs) == 1
    assert "estimated about" in msgs[0] and "bench_bem_cost.py" in msgs[0]
    # progress counts Tamaas solves, the cost (states without contact cost a few FFTs): those
    # announced are fft_bem's states in contact on the same grid, close to the BEM's own count
    announced = int(re.search(r": (\d+) Tamaas solves to compute", msgs[0]).group(1))
    solves = ds.attrs["bem_solves"] + ds.attrs["bem_retries"]
    assert 0.5 * solves <= announced <= 1.5 * solves + 2, (announced, solves)
    assert re.match(rf"bem: {solves}/{solves} done \(100 %\)", msgs[-1]), msgs[-1]


def test_time_left_follows_the_measured_rate_not_the_estimate(caplog, monkeypatch):
    """A run estimated short but measured long says so with the time left at the measured rate
    (once), and from then on shows its progress lines; a run within the estimate says nothing."""
    caplog.set_level(logging.INFO, logger="roughstick")
    clock = {"t": 0.0}
    monkeypatch.setattr(prog, "time", type(sys)("fake_time"))
    prog.time.monotonic = lambda: clock["t"]
    with prog.WorkProgress(20, what="bem: x", estimate=4.0, unit="Tamaas solves") as p:
        assert not p.lines  # estimated under 5 s: no progress lines
        for _ in range(4):
            clock["t"] += 10.0  # 10 s per solve, not the 0.2 s estimated
            p.update()
    msgs = _messages(caplog)
    slower = [m for m in msgs if "slower than estimated" in m]
    assert len(slower) == 1 and "2 of 20 Tamaas solves took 20 s" in slower[0]
    assert "about 3 min left at the measured rate" in slower[0]  # 18 solves x 10 s
    assert any(m.startswith("bem: 4/20 done (20 %), 40 s elapsed, about 3 min left") for m in msgs)
    assert msgs[-1].startswith("bem: 4/4 done (100 %)")  # stopped early: the end is said
    caplog.clear()
    clock["t"] = 0.0
    with prog.WorkProgress(20, what="bem: y", estimate=100.0, progress=True) as p:
        for _ in range(20):
            clock["t"] += 6.0  # 120 s in all: within the factor 3
            p.update()
    assert not [m for m in _messages(caplog) if "than estimated" in m]


def test_fft_bem_progress_per_humidity_and_map(caplog):
    caplog.set_level(logging.INFO, logger="roughstick")
    stack = rs.datasets.surface_family("smooth", shape=(32, 32), seed=2, n=3).compute()
    dist = np.linspace(float(stack.max()) - 1e-9, float(stack.max()) + 3e-9, 5)
    rs.contact.curves(stack, relative_humidity=[0.4, 0.8], distance=dist, model="fft_bem",
                            progress=True)
    msgs = _messages(caplog)
    assert msgs[0].startswith("fft_bem: 3 map(s) of 32 x 32 pixels x 2 humidities (about 30 states): 6 curves")
    assert msgs[-1].startswith("fft_bem: 6/6 done (100 %)")


def test_short_runs_stay_quiet_by_default_long_ones_announce(caplog, monkeypatch):
    caplog.set_level(logging.INFO, logger="roughstick")
    h = _map(family="smooth")
    rs.contact.fft_bem_curves(h, relative_humidity=0.5)
    assert _messages(caplog) == []  # estimated well under 5 s: no noise in ensembles
    monkeypatch.setattr(prog, "PROGRESS_THRESHOLD", 0.0)  # as if it were a long run
    rs.contact.fft_bem_curves(h, relative_humidity=0.5)
    msgs = _messages(caplog)
    assert "estimated" in msgs[0] and msgs[-1].startswith("fft_bem: 1/1 done")


def test_resolution_study_announces_every_pixel_size(caplog):
    caplog.set_level(logging.INFO, logger="roughstick")
    rs.contact.resolution_study(_map(family="smooth"), relative_humidity=0.5, factors=(1, 2),
                        model="fft_bem", progress=True)
    starts = [m for m in _messages(caplog) if "estimated" in m]
    assert [m.split(" pixels")[0] for m in starts] == ["fft_bem: 1 map(s) of 32 x 32",
                                                       "fft_bem: 1 map(s) of 16 x 16"]


def test_terminal_gets_a_tqdm_bar_and_jupyter_a_widget(monkeypatch):
    import tqdm

    monkeypatch.setattr(prog, "interactive", lambda: True)
    with prog.WorkProgress(4, what="bem: x", estimate=100.0) as p:
        assert isinstance(p.bar, tqdm.tqdm) and not p.lines
        p.update(4)
        assert p.bar.n == 4
    monkeypatch.setitem(sys.modules, "ipywidgets", type(sys)("ipywidgets"))
    import tqdm.auto

    assert prog.tqdm_class() is tqdm.auto.tqdm


def test_estimate_scales_with_pixels_and_solves():
    # one Tamaas solve costs ~1500 (N/64^2)^0.3 FFT pairs (benchmarks/bench_bem_cost.py)
    a = prog.estimate_seconds("bem", (64, 64), 10)
    b = prog.estimate_seconds("bem", (64, 64), 20)
    assert 1.2 < b / a < 3.5  # twice the solves (FFT timings jitter)
    with pytest.raises(ValueError, match="no cost model"):
        prog.estimate_seconds("gw", (64, 64), 1)
    assert prog.format_seconds(30) == "about 30 s" and prog.format_seconds(600) == "about 10 min"


def test_cli_curves_bem_prints_the_estimate(tmp_path, capsys, monkeypatch):
    pytest.importorskip("tamaas")
    from roughstick.cli import main

    monkeypatch.setattr(prog, "PROGRESS_THRESHOLD", 0.0)
    np.save(tmp_path / "m.npy", _map(n=16).values * 1e9)
    assert main(["curves", str(tmp_path / "m.npy"), "--spacing", "5 nm", "--units", "nm",
                 "--rh", "0.9", "--model", "bem", "--n-distance", "5",
                 "--out", str(tmp_path / "b.nc")]) == 0
    out = capsys.readouterr().out.splitlines()
    # the grid comes from fft_bem's automatic march (its own short line may come first); the
    # BEM's estimate comes before any of its progress lines
    first = next(i for i, line in enumerate(out) if line.startswith("bem:"))
    assert out[first].startswith("bem: 1 map(s) of 16 x 16 pixels x 1 humidities x ")
    assert "Tamaas solves to compute, estimated about" in out[first]
    assert any(re.match(r"bem: (\d+)/\1 done \(100 %\)", line) for line in out[first:])


def test_tasks_of_a_larger_computation_stay_quiet(caplog, monkeypatch):
    """Inside an ensemble block (a worker thread) the ensemble's own progress is shown instead."""
    import threading

    caplog.set_level(logging.INFO, logger="roughstick")
    monkeypatch.setattr(prog, "interactive", lambda: True)
    seen = {}

    def task():
        seen["p"] = prog.WorkProgress(10, what="fft_bem: x", estimate=100.0)

    t = threading.Thread(target=task)
    t.start()
    t.join()
    assert seen["p"].bar is None and not seen["p"].lines and _messages(caplog) == []
