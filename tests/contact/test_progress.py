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
    ds = rs.rough_contact_curves(h, relative_humidity=[0.5, 0.9], model="bem", n_distance=6,
                                 progress=True)
    msgs = _messages(caplog)
    # one estimate for both humidities, each on its own automatic grid (``solved``)
    assert msgs[0].startswith(f"bem: 1 map(s) of 32 x 32 pixels x 2 humidities x "
                              f"{ds.sizes['distance']} distances")
    assert sum(m.startswith("bem: 1 map(s)") for m in msgs) == 1
    assert "estimated about" in msgs[0] and "bench_bem_cost.py" in msgs[0]
    # the solves announced are the points below the highest summit (measured: bem_solves); a
    # state Tamaas stalled on is on its grid but not ``solved`` (interpolated, bem_unconverged)
    solved = ds.solved.values > 0
    stalled = ds.attrs["bem_unconverged"]
    n_below = int(np.sum(solved & (ds.distance.values < float(h.max()))[None, :]))
    announced = int(re.search(r"\((\d+) Tamaas solves\)", msgs[0]).group(1))
    assert n_below <= announced <= n_below + stalled
    assert ds.attrs["bem_solves"] >= announced
    n_grid = int(solved.sum()) + stalled
    assert msgs[-1].startswith(f"bem: {n_grid}/{n_grid} done (100 %)")


def test_fft_bem_progress_per_humidity_and_map(caplog):
    caplog.set_level(logging.INFO, logger="roughstick")
    stack = rs.datasets.surface_family("smooth", shape=(32, 32), seed=2, n=3).compute()
    dist = np.linspace(float(stack.max()) - 1e-9, float(stack.max()) + 3e-9, 5)
    rs.rough_contact_curves(stack, relative_humidity=[0.4, 0.8], distance=dist, model="fft_bem",
                            progress=True)
    msgs = _messages(caplog)
    assert msgs[0].startswith("fft_bem: 3 map(s) of 32 x 32 pixels x 2 humidities (about 30 states): 6 curves")
    assert msgs[-1].startswith("fft_bem: 6/6 done (100 %)")


def test_short_runs_stay_quiet_by_default_long_ones_announce(caplog, monkeypatch):
    caplog.set_level(logging.INFO, logger="roughstick")
    h = _map(family="smooth")
    rs.fft_bem_contact_curves(h, relative_humidity=0.5)
    assert _messages(caplog) == []  # estimated well under 5 s: no noise in ensembles
    monkeypatch.setattr(prog, "PROGRESS_THRESHOLD", 0.0)  # as if it were a long run
    rs.fft_bem_contact_curves(h, relative_humidity=0.5)
    msgs = _messages(caplog)
    assert "estimated" in msgs[0] and msgs[-1].startswith("fft_bem: 1/1 done")


def test_resolution_study_announces_every_pixel_size(caplog):
    caplog.set_level(logging.INFO, logger="roughstick")
    rs.resolution_study(_map(family="smooth"), relative_humidity=0.5, factors=(1, 2),
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
    n = int(out[first].split(" humidities x ")[1].split()[0])
    assert "estimated about" in out[first] and any(line.startswith(f"bem: {n}/{n} done") for line in out)


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
