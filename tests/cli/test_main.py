"""The console script: help, version and the README's main job (``roughstick demo``)."""

import subprocess
import sys

import pytest

from roughstick.cli import build_parser, main


def test_help_lists_demo(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    assert "demo" in capsys.readouterr().out


def test_no_command_prints_help(capsys):
    assert main([]) == 2


def test_every_subcommand_has_a_handler():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    assert "demo" in sub.choices
    for name, p in sub.choices.items():
        assert p.get_default("func") is not None, f"sub-command {name!r} has no handler"


def test_console_script_entry_point_runs():
    out = subprocess.run(
        [sys.executable, "-m", "roughstick.cli", "--version"], capture_output=True, text=True, check=True
    )
    assert out.stdout.startswith("roughstick ")
