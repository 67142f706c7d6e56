"""CLI conventions (issue 16 items 4, 7 and 12): flags, folders, logging, interrupts, OS errors."""

from __future__ import annotations

import errno
import json

import numpy as np
import pytest

import roughstick as rs
from roughstick.cli import build_parser, main
from roughstick.cli._common import MARKER, user_message
from roughstick.plotting.save import save_figure

WRITERS = ("beam", "curves", "demo", "psd", "reproduce", "risk", "run")


def _sub(name):
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    return sub.choices[name]


def test_version(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--version"])
    assert e.value.code == 0 and capsys.readouterr().out.strip() == f"roughstick {rs.__version__}"


def test_python_dash_m_roughstick_is_the_console_script():
    import subprocess
    import sys

    for mod in ("roughstick", "roughstick.cli"):
        res = subprocess.run([sys.executable, "-m", mod, "--version"], capture_output=True, text=True, timeout=120)
        assert res.returncode == 0 and res.stdout.strip() == f"roughstick {rs.__version__}", (mod, res.stderr)


def test_a_length_flag_without_a_unit_is_refused(tmp_path, capsys):
    """`--spacing 5` was read as 5 m (Γ 0.47 J/m² and a NaN equilibrium, exit 0); like a bare
    number in a config file it is refused, naming the flag and the fix."""
    np.save(tmp_path / "m.npy", rs.datasets.surface_family("S1", shape=(16, 16), seed=1).values * 1e9)
    for cmd in ("curves", "psd"):
        extra = ["--rh", "0.3"] if cmd == "curves" else []
        with pytest.raises(SystemExit) as e:
            main([cmd, str(tmp_path / "m.npy"), *extra, "--spacing", "5", "--units", "nm",
                  "--out", str(tmp_path / f"{cmd}.nc")])
        assert e.value.code == 2
        assert "argument --spacing: '5' has no unit; write it with one, e.g. '5 nm'" in capsys.readouterr().err
        assert not (tmp_path / f"{cmd}.nc").exists()


def test_every_command_has_quiet_verbose_and_writers_overwrite():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    for name, p in sub.choices.items():
        flags = {o for a in p._actions for o in a.option_strings}
        assert {"--quiet", "--verbose"} <= flags, name
        if name in WRITERS:
            assert "--overwrite" in flags, name


def test_demo_unknown_only_step_is_an_error(tmp_path, capsys):
    assert main(["demo", "--only", "sphere", "bogus", "--out", str(tmp_path / "d")]) == 1
    err = capsys.readouterr().err
    assert "--only bogus: no such step" in err and "cantilever" in err
    assert not (tmp_path / "d").exists()


def test_demo_quiet_and_folder_claims(tmp_path, capsys):
    out = tmp_path / "d"
    assert main(["demo", "--quick", "--only", "sphere", "--quiet", "--out", str(out)]) == 0
    assert capsys.readouterr().out == ""
    assert json.loads((out / MARKER).read_text())["status"] == "complete"
    # the same command again rewrites; other options over complete results need --overwrite
    assert main(["demo", "--quick", "--only", "sphere", "-q", "--out", str(out)]) == 0
    assert main(["demo", "--only", "sphere", "-q", "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert "--overwrite" in err and "--out" in err and "quick: True -> False" in err
    # a failed (unfinished) run never blocks the next one
    rec = json.loads((out / MARKER).read_text())
    (out / MARKER).write_text(json.dumps({**rec, "status": "running", "params": {"x": 1}}))
    (out / ".fig3_sphere_models.tmp-99.png").write_bytes(b"")  # left by a kill
    assert main(["demo", "--quick", "--only", "sphere", "-q", "--out", str(out)]) == 0
    assert not list(out.glob("*.tmp-*"))


def test_ctrl_c_is_one_line_and_says_resume(monkeypatch, tmp_path, capsys):
    from roughstick.cli import demo

    def interrupted(out, *, quick, **figure_options):
        raise KeyboardInterrupt

    monkeypatch.setattr(demo, "steps", lambda: [type("M", (), {"__name__": "x.s10_sphere",
                                                                   "run": staticmethod(interrupted)})])
    assert main(["demo", "--out", str(tmp_path / "d")]) == 130
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "re-run the same command to resume" in err


def test_bugs_keep_their_traceback(monkeypatch, tmp_path):
    from roughstick.cli import demo

    def bug(out, *, quick, **figure_options):
        raise AttributeError("'NoneType' object has no attribute 'x'")

    monkeypatch.setattr(demo, "steps", lambda: [type("M", (), {"__name__": "x.s10_sphere",
                                                                   "run": staticmethod(bug)})])
    with pytest.raises(AttributeError):
        main(["demo", "--out", str(tmp_path / "d")])


def test_os_errors_are_one_line_naming_the_flag(tmp_path, capsys):
    (tmp_path / "file").write_text("x")
    assert main(["demo", "--only", "sphere", "--out", str(tmp_path / "file" / "sub")]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--out" in err
    for exc in (PermissionError(errno.EACCES, "Permission denied", "/ro/band.nc"),
                OSError(errno.EROFS, "Read-only file system", "/ro/band.nc"),
                OSError(errno.ENOSPC, "No space left on device", "/x/band.nc")):
        msg = user_message(exc)
        assert "/ro/band.nc" in msg or "/x/band.nc" in msg
        assert "--out" in msg


def test_damaged_netcdf_is_a_clear_error(tmp_path, capsys):
    bad = tmp_path / "gamma.nc"
    bad.write_bytes(b"\x89HDF\r\n\x1a\n" + b"\x00" * 100)  # an HDF5 signature, then nothing
    with pytest.raises(ValueError, match="damaged, truncated or not a NetCDF file"):
        rs.io.open_dataset(bad)
    cfg = tmp_path / "risk.toml"
    cfg.write_text('[ensemble]\nadhesive_energy = "gamma.nc"\n[output]\nfolder = "o"\n')
    assert main(["risk", str(cfg)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "damaged" in err


def test_psd_refuses_to_replace_a_file_silently(tmp_path, capsys):
    np.save(tmp_path / "m.npy", np.random.default_rng(0).normal(size=(64, 64)))
    out = tmp_path / "psd.nc"
    out.write_text("precious")
    args = ["psd", str(tmp_path / "m.npy"), "--spacing", "5 nm", "--units", "nm", "--out", str(out)]
    assert main(args) == 1
    assert "--overwrite" in capsys.readouterr().err and out.read_text() == "precious"
    assert main(args + ["--overwrite", "--qmax", "289 rad/um"]) == 0
    assert main(["psd", str(tmp_path / "m.npy"), "--spacing", "5 nm", "--units", "nm", "--qmax", "289e6",
                 "--out", str(tmp_path / "new" / "p.nc")]) == 1
    assert 'has no unit' in capsys.readouterr().err


def test_figure_write_is_atomic(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1])

    def killed(path, **kw):
        open(path, "wb").close()  # the 0-byte file a kill used to leave
        raise KeyboardInterrupt

    monkeypatch.setattr(fig, "savefig", killed)
    with pytest.raises(KeyboardInterrupt):
        save_figure(fig, tmp_path / "a.png")
    assert list(tmp_path.iterdir()) == []


def test_run_progress_lines_without_terminal_and_tmp_cleanup(tmp_path, capsys):
    from test_run import _cfg

    cfg = _cfg(tmp_path, n="4", rh="[0.3, 0.9]")
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / ".band.nc.tmp-1234-5678").write_bytes(b"half")
    assert main(["run", str(cfg)]) == 0
    out = capsys.readouterr().out
    assert "ensemble blocks: 2/2 done (100 %)" in out  # capsys is no terminal: log lines
    assert not list((tmp_path / "out").glob(".*tmp-*"))


def test_warns_when_generated_surfaces_exceed_the_measured_scan(caplog):
    import logging

    from roughstick.cli.run import _warn_if_extrapolated

    psd = rs.surface.submap_psd(rs.datasets.load_sample("S1A").isel(x=slice(0, 256), y=slice(0, 256)), n=4)
    # 4 sub-maps of a 256² map at 5 nm: the PSD is measured on 0.64 µm scans
    with caplog.at_level(logging.WARNING, logger="roughstick"):
        _warn_if_extrapolated(psd, (128, 128), 5e-9, source="samples")
        assert not caplog.records
        _warn_if_extrapolated(psd, (256, 256), 5e-9, source="samples")
    assert "larger than the scans the PSD was measured on (0.64 x 0.64 µm)" in caplog.text


@pytest.mark.slow
def test_real_ctrl_c_during_a_run_then_resume(tmp_path):
    """SIGINT to a running `roughstick run`: one line, exit 130, blocks kept, the re-run resumes."""
    import signal
    import subprocess
    import sys

    from test_run import BASE

    cfg = tmp_path / "c.toml"
    cfg.write_text(BASE.format(n=200, rh="[0.3, 0.9]", figures="false").replace("[64, 64]", "[256, 256]"))
    cmd = [sys.executable, "-m", "roughstick.cli", "run", str(cfg)]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    for line in p.stdout:  # progress lines arrive while it runs (no terminal)
        if "done (" in line:
            break
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=300)
    assert p.returncode == 130
    lines = [ln for ln in err.splitlines() if "Warning" not in ln]
    assert lines == ["roughstick run: interrupted; completed results are kept: re-run the same command to resume."]
    kept = len(list((tmp_path / "out" / "ensemble").glob("block-*.nc")))
    assert kept >= 1 and not list((tmp_path / "out" / "ensemble").glob(".*tmp-*"))
    m = json.loads((tmp_path / "out" / "ensemble" / "manifest.json").read_text())
    total = len(m["realization_chunks"]) * len(m["rh_chunks"])
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0
    assert f"ensemble blocks: {total - kept} to compute" in res.stdout  # only the missing ones


def test_writers_create_nested_output_folders(tmp_path, capsys):
    """curves, psd and demo create the folders of --out (run, risk, beam, reproduce claim theirs
    through claim_folder, which creates parents: tests/cli/test_run.py, test_risk_command.py)."""
    np.save(tmp_path / "m.npy", rs.datasets.surface_family("smooth", shape=(32, 32), seed=1).values * 1e9)
    common = [str(tmp_path / "m.npy"), "--spacing", "5 nm", "--units", "nm", "-q"]
    assert main(["psd", *common, "--out", str(tmp_path / "a" / "b" / "p.nc")]) == 0
    assert main(["curves", *common, "--rh", "0.5", "--out", str(tmp_path / "c" / "d" / "c.nc")]) == 0
    assert main(["demo", "--quick", "--only", "sphere", "-q", "--out", str(tmp_path / "e" / "f")]) == 0
    assert (tmp_path / "a/b/p.nc").is_file() and (tmp_path / "c/d/c.nc").is_file()
    assert (tmp_path / "e/f" / MARKER).is_file()


def test_curves_refuses_to_replace_a_file_without_overwrite(tmp_path, capsys):
    np.save(tmp_path / "m.npy", rs.datasets.surface_family("smooth", shape=(32, 32), seed=1).values * 1e9)
    out = tmp_path / "c.nc"
    out.write_text("precious")
    args = ["curves", str(tmp_path / "m.npy"), "--spacing", "5 nm", "--units", "nm", "--rh", "0.5",
            "-q", "--out", str(out)]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--overwrite" in err and out.read_text() == "precious"
    assert main(args + ["--overwrite"]) == 0
    assert rs.io.open_dataset(out).attrs["contact_model"] == "fft_bem"  # the default --model auto, on a smooth map
    assert main([*args[:-1], str(tmp_path)]) == 1  # a folder as --out: name a file
    assert "is a folder" in capsys.readouterr().err


def test_folder_commands_refuse_a_file_as_out_and_create_nested_folders(tmp_path, capsys):
    """run and reproduce: --out naming an existing file is one line, the file untouched."""
    (tmp_path / "afile").write_text("precious")
    cfg = tmp_path / "c.toml"
    cfg.write_text('[psd]\nsource = "moments"\nm0 = "15.7 nm2"\nm2 = 0.0279\nm4 = "5.08e-4 nm-2"\n'
                   'qmax = "289 rad/um"\n[surface]\nshape = [32, 32]\nspacing = "5 nm"\n'
                   '[ensemble]\nn = 2\nrelative_humidity = [0.5]\n[output]\nfolder = "o"\n'
                   "figures = false\n")
    for args in (["run", str(cfg)], ["reproduce", "--quick", "--n", "2"]):
        assert main([*args, "-q", "--out", str(tmp_path / "afile")]) == 1
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "is not a folder" in err and "--out" in err
    assert (tmp_path / "afile").read_text() == "precious"
    assert main(["run", str(cfg), "-q", "--out", str(tmp_path / "x" / "y")]) == 0
    assert (tmp_path / "x" / "y" / "band.nc").is_file()


def test_demo_says_the_validity_note_once_without_warnings(tmp_path, capsys):
    """Issue 16 item 2: no warning the user cannot act on along the default path (the demo)."""
    assert main(["demo", "--quick", "--only", "rough_contact", "--out", str(tmp_path / "d")]) == 0
    text = capsys.readouterr()
    assert "ValidityWarning" not in text.err and "rough_contact_curves(" not in text.err
    notes = [line for line in text.out.splitlines() if "note:" in line]
    assert len(notes) <= 1
    if notes:
        assert "--model auto" in notes[0] and "docs/accuracy.md" in notes[0]


def test_the_same_warning_is_printed_once_per_command(capsys):
    """The demo's cantilever step met the same ValidityWarning once per adsorbed-layer model and
    printed it twice; a different warning is still printed."""
    import warnings

    from roughstick.cli._common import setup_logging, teardown_logging

    with warnings.catch_warnings():
        warnings.simplefilter("always")
        setup_logging()
        try:
            for _ in range(3):
                warnings.warn("same advice", rs.ValidityWarning, stacklevel=1)
            warnings.warn("other advice", rs.ValidityWarning, stacklevel=1)
        finally:
            teardown_logging()
    err = capsys.readouterr().err
    assert err.count("same advice") == 1 and err.count("other advice") == 1


def test_a_missing_optional_dependency_is_one_line_with_its_install_command():
    msg = "reading .spm files needs SurfaceTopography: pip install roughstick[afm]"
    assert user_message(ImportError(msg)) == msg
    assert user_message(ImportError("cannot import name 'x' from 'y'")) is None  # a bug: traceback
