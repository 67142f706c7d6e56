"""The output folders of `run`, `demo`, `beam` and `risk`: who wrote them, replacing another run's
results, checks made before any work, and what the terminal and the files say about a result."""

from __future__ import annotations

import json
import os
import time
import types
import warnings

import numpy as np
import pytest
import xarray as xr
from _configs import MOMENTS_PSD, SMALL_BEAM

import roughstick as rs
from roughstick.cli import main
from roughstick.cli import run as run_cmd
from roughstick.cli._common import MARKER
from roughstick.cli._process import LOCK
from roughstick.cli.risk import _confirmed
from roughstick.io.netcdf import WRITTEN_LOG, write_text_atomic

RUN = """
title = "t"
""" + MOMENTS_PSD.lstrip("\n") + """[surface]
shape = [32, 32]
spacing = "5 nm"
[ensemble]
n = {n}
relative_humidity = {rh}
seed = 7
[output]
folder = "out"
figures = {figures}
"""

# the same parameters as RUN(n=4, rh=[0.3, 0.9]): comments, blank lines, other key order and spelling
RUN_REWRITTEN = """
# a comment added after the run
title = "t"

[surface]
spacing = "5.0 nm"     # same pixel
shape = [32, 32]
[psd]
qmax = "0.289 rad/nm"
m4 = "5.08e-4 nm-2"
m2 = 0.04
m0 = "15.7 nm2"
source = "moments"
[ensemble]
seed = 7
relative_humidity = [0.30, 0.9]
n = 4
[output]
figures = false
folder = "out"
"""


def _cfg(tmp_path, name="c.toml", n=4, rh="[0.3, 0.9]", figures="false", extra=""):
    p = tmp_path / name
    p.write_text(RUN.format(n=n, rh=rh, figures=figures) + extra)
    return p


def _marker(folder):
    return json.loads((folder / MARKER).read_text())


def _fake_steps(monkeypatch, plan):
    """demo with steps that write the given files (None: the step raises KeyboardInterrupt)."""
    from roughstick.cli import demo

    def make(name, files):
        def run(out, *, quick, **figure_options):
            if files is None:
                raise KeyboardInterrupt
            for f in files:  # as the real steps write (io.netcdf.publish notes them as the run's)
                write_text_atomic(out / f, name)
            return [out / f for f in files]
        return types.SimpleNamespace(__name__=f"x.{name}", run=run)

    monkeypatch.setattr(demo, "steps", lambda: [make(n, f) for n, f in plan])


def test_run_killed_after_overwrite_leaves_no_old_result(tmp_path, monkeypatch, capsys):
    """Audit item 1: `run --overwrite` killed midway left the old band.nc and PNGs beside the new
    run's marker, a complete-looking folder of two runs."""
    assert main(["run", str(_cfg(tmp_path, figures="true")), "-q"]) == 0
    out = tmp_path / "out"
    (out / "notes.txt").write_text("mine")  # the user's, written after the run: kept
    other = _cfg(tmp_path, "other.toml", rh="[0.3, 0.8]", figures="false")

    def killed(*a, **kw):
        raise KeyboardInterrupt

    monkeypatch.setattr(run_cmd.rs.ensemble, "run", killed)
    assert main(["run", str(other), "--overwrite", "-q"]) == 130
    left = sorted(p.name for p in out.iterdir())
    assert left == [MARKER, WRITTEN_LOG, "notes.txt"], left  # no band.nc, PNG or ensemble of the old run
    assert _marker(out)["status"] == "running" and _marker(out)["params"]["relative_humidity"] == [0.3, 0.8]
    monkeypatch.undo()
    capsys.readouterr()
    assert main(["run", str(other), "-q"]) == 0  # the retry needs no --overwrite: nothing complete to lose
    assert _marker(out)["status"] == "complete"
    assert rs.io.open_dataset(out / "band.nc").rh.values.tolist() == [0.3, 0.8]
    assert (out / "notes.txt").read_text() == "mine"


def test_demo_killed_after_overwrite_then_other_options(tmp_path, monkeypatch, capsys):
    out = tmp_path / "d"
    _fake_steps(monkeypatch, [("s10_sphere", ["a.png", "a.nc"]), ("s20_topo", ["b.csv"])])
    assert main(["demo", "--quick", "-q", "--out", str(out)]) == 0
    # other options, --overwrite, killed after the first step wrote its file
    _fake_steps(monkeypatch, [("s10_sphere", ["c.png"]), ("s20_topo", None)])
    assert main(["demo", "-q", "--overwrite", "--out", str(out)]) == 130
    assert sorted(p.name for p in out.iterdir()) == [MARKER, WRITTEN_LOG, "c.png"]
    # a third set of options replaces that unfinished run: its c.png goes too
    _fake_steps(monkeypatch, [("s10_sphere", ["e.png"])])
    assert main(["demo", "-q", "--only", "sphere", "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "e.png"]
    assert _marker(out)["outputs"] == ["e.png"]


def test_a_folder_of_another_command_is_refused(tmp_path, monkeypatch, capsys):
    """Audit item 2: `risk --out` a finished `run` folder wrote risk.nc beside band.nc, and `run`
    (which recorded nothing) wrote into any finished folder."""
    assert main(["run", str(_cfg(tmp_path)), "-q"]) == 0
    out = tmp_path / "out"
    risk = tmp_path / "r.toml"
    risk.write_text('[surface]\nshape = [32, 32]\n[ensemble]\nn = 2\nrelative_humidity = [0.5]\n'
                    'adsorbed_layer = ["none"]\n[output]\nfigures = false\n')
    before = sorted(p.name for p in out.iterdir())
    capsys.readouterr()
    assert main(["risk", str(risk), "-q", "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "`roughstick run`" in err and "--overwrite" in err and "--out" in err
    assert sorted(p.name for p in out.iterdir()) == before
    # and `run` into a finished demo folder
    _fake_steps(monkeypatch, [("s10_sphere", ["a.png"])])
    assert main(["demo", "-q", "--out", str(tmp_path / "d")]) == 0
    assert main(["run", str(_cfg(tmp_path)), "-q", "--out", str(tmp_path / "d")]) == 1
    err = capsys.readouterr().err
    assert "`roughstick demo`" in err and "--overwrite" in err and "--out" in err
    assert sorted(p.name for p in (tmp_path / "d").iterdir()) == [MARKER, "a.png"]


def test_the_marker_compares_parameters_not_text(tmp_path, capsys):
    """Audit item 3: a comment added to the config blocked the rerun with a 6 kB error line."""
    cfg = _cfg(tmp_path)
    assert main(["run", str(cfg), "-q"]) == 0
    cfg.write_text(RUN_REWRITTEN)
    assert main(["run", str(cfg), "-q"]) == 0, capsys.readouterr().err
    # other parameters: refused in one short line naming a few of the keys that differ
    cfg.write_text(RUN.format(n=5, rh="[0.4, 0.5, 0.6]", figures="false").replace("seed = 7", "seed = 8")
                   .replace('"t"', '"' + "a very long title " * 20 + '"')
                   .replace("m2 = 0.040", "m2 = 0.041"))
    capsys.readouterr()
    assert main(["run", str(cfg), "-q"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and len(err) < 400, err
    assert "different parameters" in err and "and 2 more" in err and "--overwrite" in err


@pytest.mark.parametrize("where, args, extra", [
    ("[run] scheduler", [], '[run]\nscheduler = "dask"\n'),
    ("--scheduler", ["--scheduler", "thread"], ""),
])
def test_the_scheduler_is_checked_before_any_work(tmp_path, monkeypatch, capsys, where, args, extra):
    """Audit item 4: a bad [run] scheduler failed after the work started, naming a Python remedy."""
    def no_work(*a, **kw):
        raise AssertionError("work started")

    monkeypatch.setattr(run_cmd.rs.ensemble, "distance_grid", no_work)
    assert main(["run", str(_cfg(tmp_path, extra=extra)), *args]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and where in err and "'threads'" in err and "tcp://host:port" in err
    assert "distributed.Client" not in err
    assert not (tmp_path / "out").exists()


def test_risk_scheduler_is_checked_before_any_work(tmp_path, capsys):
    cfg = tmp_path / "r.toml"
    cfg.write_text('[ensemble]\nn = 2\nrelative_humidity = [0.5]\n[run]\nscheduler = "treads"\n')
    assert main(["risk", str(cfg)]) == 1
    err = capsys.readouterr().err
    assert "[run] scheduler = 'treads'" in err and "'threads'" in err
    assert not (tmp_path / "risk-output").exists()


@pytest.mark.parametrize("out, says", [("result.nc", "names a file"),
                                       ("/proc/roughstick-test/o", "cannot create the output folder")])
def test_a_bad_output_folder_is_refused_before_any_work(tmp_path, monkeypatch, capsys, out, says):
    """Audit item 6: an output that cannot be written was found after the computation."""
    def no_work(*a, **kw):
        raise AssertionError("work started")

    monkeypatch.setattr(run_cmd.rs.ensemble, "distance_grid", no_work)
    target = out if out.startswith("/") else str(tmp_path / out)
    assert main(["run", str(_cfg(tmp_path)), "--out", target]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err and "--out" in err
    assert not (tmp_path / out).exists()


def test_run_prints_the_median_with_its_interval(tmp_path, capsys):
    """Audit item 7: the median of Γ was printed bare."""
    assert main(["run", str(_cfg(tmp_path, n=8, rh="[0.9]"))]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if "RH 90%: median" in ln)
    band = rs.io.open_dataset(tmp_path / "out" / "band.nc")
    lo, hi = (float(band[f"adhesive_energy_ci_{s}"].sel(quantile=0.5).squeeze()) * 1e3 for s in ("lower", "upper"))
    assert f"95% CI of the median [{lo:.4g}, {hi:.4g}]" in line
    assert lo < float(band.adhesive_energy.sel(quantile=0.5).squeeze()) * 1e3 < hi
    assert main(["run", str(_cfg(tmp_path, n=4, rh="[0.9]")), "--out", str(tmp_path / "o4")]) == 0
    out = capsys.readouterr().out
    assert "CI of the median: not bounded [1])" in out
    assert "[1] n too small to bound the median (needs n >= 6 realizations)" in out


def test_risk_bem_check_line_says_its_interval():
    d = xr.Dataset({"failure_bem_ratio": 0.9, "failures_confirmed_by_bem": 0.75, "failures_checked_by_bem": 8})
    text = _confirmed(d)
    lo, hi = rs.ensemble.binomial_interval(6, 8, confidence=0.95)
    assert f"6 of 8 failure states confirmed (95 % Wilson [{float(lo):.0%}, {float(hi):.0%}])" in text
    assert "median BEM/Eq. 16 0.90 (no interval: only the median is kept)" in text  # an older risk.nc
    text = _confirmed(d.assign(failure_bem_ratio_low=0.85, failure_bem_ratio_high=0.97))
    assert "median BEM/Eq. 16 0.90 (95 % [0.85, 0.97])" in text
    text = _confirmed(d.assign(failure_bem_ratio_low=np.nan, failure_bem_ratio_high=np.nan))
    assert "too few states checked to bound the median" in text


BEAM = SMALL_BEAM.replace("n = 20\n", "n = 20\nseed = 3\n") + "seed = 5\n"  # seeded: reruns compare


def test_beam_nc_carries_conventions_history_and_bank_provenance(tmp_path):
    """Audit item 5: beam.nc had no Conventions, history, nor which PSD/RH/seeds made its bank."""
    cfg = tmp_path / "beam.toml"
    cfg.write_text(BEAM)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["beam", str(cfg), "--out", str(tmp_path / "o"), "-q"]) == 0
    a = rs.io.open_dataset(tmp_path / "o" / "beam.nc").attrs
    assert a["Conventions"].startswith("CF-") and a["source"] == f"roughstick {rs.__version__}"
    assert "roughstick beam beam.toml" in a["history"]
    assert a["bank_seed"] == 5 and a["beam_seed"] == 3 and a["bank_laws"] == 3
    np.testing.assert_array_equal(a["relative_humidity"], [0.3, 0.9])
    assert "Table 4" in a["psd"] and a["patch_spacing"] == pytest.approx(20e-9)
    assert a["bank_cache_file"].endswith(".nc") and "laws = 3" in a["configuration"]


def test_a_folder_written_by_an_earlier_roughstick_is_still_resumed(tmp_path, capsys):
    """Markers written before parameters were compared parsed recorded the raw config text."""
    cfg = tmp_path / "r.toml"
    cfg.write_text('[surface]\nshape = [32, 32]\n[ensemble]\nn = 2\nrelative_humidity = [0.5]\n'
                   'adsorbed_layer = ["none"]\n[output]\nfigures = false\n')
    out = tmp_path / "risk-output"
    out.mkdir()
    (out / MARKER).write_text(json.dumps({"command": "risk", "params": {"config": cfg.read_text()},
                                          "status": "complete", "started": "2026-01-01T00:00:00Z"}))
    assert main(["risk", str(cfg), "-q"]) == 0, capsys.readouterr().err
    assert _marker(out)["status"] == "complete" and "risk.nc" in _marker(out)["outputs"]


def test_check_output_file_refuses_before_any_work(tmp_path):
    """The check `psd --out` and `curves --out` can make before computing (they wrote NetCDF
    under any name, c.png included, and named no flag when the folder could not be made)."""
    from roughstick.cli._common import check_output_file, user_message

    with pytest.raises(ValueError, match=r"--out .*c\.png.*NetCDF file; give it the \.nc extension.*c\.nc"):
        check_output_file(tmp_path / "c.png")
    (tmp_path / "old.nc").write_text("x")
    with pytest.raises(FileExistsError, match="--overwrite"):
        check_output_file(tmp_path / "old.nc")
    assert check_output_file(tmp_path / "old.nc", overwrite=True) == tmp_path / "old.nc"
    with pytest.raises(FileExistsError) as err:
        check_output_file("/proc/roughstick-test/c.nc", flag="--save")
    assert "cannot write --save" in user_message(err.value)
    assert check_output_file(tmp_path / "a" / "b" / "c.nc").parent.is_dir()
    assert sorted(p.name for p in (tmp_path / "a" / "b").iterdir()) == []  # the probe is gone


def test_inputs_inside_the_output_folder_are_never_removed(tmp_path, capsys):
    """A Γ sample or measured points kept in the output folder (and named by the config) stay
    when another run replaces the folder's results, even if written after that run started."""
    from conftest import lognormal_gamma

    out = tmp_path / "o"
    out.mkdir()
    g, _ = lognormal_gamma(n=25, rh=np.array([0.5, 0.7]))
    cfg = tmp_path / "r.toml"
    cfg.write_text(f'[output]\nfolder = "o"\nfigures = false\n[ensemble]\nadhesive_energy = "{out / "g.nc"}"\n'
                   '[risk]\nlevels = [{lev}]\n')
    rs.io.netcdf.write(rs.conventions.set_attrs(g, "surface_adhesive_energy").to_dataset(name="adhesive_energy"),
                       out / "g.nc", compute=True)
    later = time.time() + 60  # as if rewritten while the run computed: newer than the run's start
    os.utime(out / "g.nc", (later, later))
    cfg.write_text(cfg.read_text().replace("{lev}", "0.5"))
    assert main(["risk", str(cfg), "-q"]) == 0
    assert "g.nc" not in _marker(out)["outputs"] and "risk.nc" in _marker(out)["outputs"]
    cfg.write_text(cfg.read_text().replace("[0.5]", "[0.1]"))
    assert main(["risk", str(cfg), "-q", "--overwrite"]) == 0
    assert (out / "g.nc").is_file() and (out / "risk.nc").is_file()


def test_nested_result_folders_are_the_run_s_and_replaced_with_it(tmp_path):
    """risk's subset-*/rh-0.5000/ and beam's levels/ hold their files one folder down."""
    from roughstick.cli._common import claim_folder, finish_folder

    out = tmp_path / "o"
    claim_folder(out, command="risk", params={"seed": 1}, overwrite=False)
    (out / "subset-paper-400um" / "rh-0.5000").mkdir(parents=True)
    write_text_atomic(out / "subset-paper-400um" / "rh-0.5000" / "run000-level00.nc", "x")
    write_text_atomic(out / "risk.nc", "x")
    finish_folder(out)
    assert _marker(out)["outputs"] == ["risk.nc", "subset-paper-400um"]
    (out / "mine").mkdir()  # made after the run, not listed: stays
    (out / "mine" / "plot.png").write_text("x")
    claim_folder(out, command="risk", params={"seed": 2}, overwrite=True)  # locked while it runs
    assert sorted(p.name for p in out.iterdir()) == [LOCK, MARKER, WRITTEN_LOG, "mine"]


def test_a_figure_saved_into_an_unfinished_run_s_folder_is_not_its_result(tmp_path):
    """The cleanup of an unfinished run took every result-type file written since it started,
    so a PNG the user saved into the folder while the run computed was deleted by the next run
    with other parameters. Now only what roughstick wrote for the run (its log) goes."""
    from roughstick.cli._common import claim_folder, finish_folder

    out = tmp_path / "o"
    claim_folder(out, command="risk", params={"seed": 1}, overwrite=False)
    rs.io.netcdf.write(xr.Dataset(), out / "risk.nc", compute=True)  # the run's, in its log
    (out / "my_plot.png").write_bytes(b"png")  # the user's, saved while it ran (not in the log)
    (out / "levels").mkdir()
    write_text_atomic(out / "levels" / "run000.nc", "x")  # one folder down: noted as "levels"
    # killed here: the next run with other parameters replaces the unfinished one
    claim_folder(out, command="risk", params={"seed": 2}, overwrite=False)
    assert sorted(p.name for p in out.iterdir()) == [LOCK, MARKER, WRITTEN_LOG, "my_plot.png"]
    rs.io.netcdf.write(xr.Dataset(), out / "risk.nc", compute=True)
    finish_folder(out)
    assert _marker(out)["outputs"] == ["risk.nc"]  # the figure is not listed as a result either
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "my_plot.png", "risk.nc"]  # log gone


def test_a_run_resumed_with_the_same_parameters_keeps_its_earlier_results(tmp_path):
    """A killed run resumed with the same parameters: the files of the first attempt are its
    results too (listed when it finishes, removed with it later)."""
    from roughstick.cli._common import claim_folder, finish_folder

    out = tmp_path / "o"
    claim_folder(out, command="run", params={"n": 1}, overwrite=False)
    write_text_atomic(out / "a.csv", "first attempt")
    claim_folder(out, command="run", params={"n": 1}, overwrite=False)  # killed, resumed
    write_text_atomic(out / "b.csv", "second attempt")
    finish_folder(out)
    assert _marker(out)["outputs"] == ["a.csv", "b.csv"]
    claim_folder(out, command="run", params={"n": 2}, overwrite=True)
    assert sorted(p.name for p in out.iterdir()) == [LOCK, MARKER, WRITTEN_LOG]


def test_reproduce_scheduler_is_checked_before_any_work(tmp_path, capsys):
    assert main(["reproduce", "--quick", "--out", str(tmp_path / "rep"), "--scheduler", "thread"]) == 1
    assert "--scheduler 'thread': not a dask scheduler" in capsys.readouterr().err
    assert not (tmp_path / "rep").exists()


def test_overwrite_of_an_older_complete_run_keeps_files_added_after_it(tmp_path):
    """A marker from before the result list: its run's files are those written while it ran;
    a figure the user saved there afterwards is not its result and stays."""
    import os
    import time as _time

    from roughstick.cli._common import claim_folder

    folder = tmp_path / "f"
    folder.mkdir()
    t = _time.time()
    old, mine = folder / "band.nc", folder / "my_figure.png"
    old.write_text("x")
    mine.write_text("y")
    stamp = lambda s: _time.strftime("%Y-%m-%dT%H:%M:%SZ", _time.gmtime(s))  # noqa: E731
    os.utime(old, (t - 3000, t - 3000))  # written during the old run
    os.utime(mine, (t - 60, t - 60))  # saved by the user long after it finished
    (folder / MARKER).write_text(json.dumps({"command": "run", "params": "old text", "status": "complete",
                                             "started": stamp(t - 3600), "finished": stamp(t - 2400)}))
    claim_folder(folder, command="run", params={"n": 4}, overwrite=True)
    assert not old.exists() and mine.exists()
