"""Tests of `roughstick run CONFIG.toml` and `roughstick reproduce`: config parsing, bad input, end to end."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

from roughstick._config import load_config, parse_quantity
from roughstick.cli import main

ROOT = pathlib.Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"

BASE = """
title = "test"
[psd]
source = "moments"
m0 = "15.7 nm2"
m2 = 0.040
m4 = "5.08e-4 nm-2"
qmax = "289 rad/um"
[surface]
shape = [64, 64]
spacing = "5 nm"
[ensemble]
n = {n}
relative_humidity = {rh}
seed = 7
chunks = 2
[output]
folder = "out"
figures = {figures}
"""


def _cfg(tmp_path, n="4", rh="[0.3, 0.9]", figures="false", extra=""):
    p = tmp_path / "c.toml"
    p.write_text(BASE.format(n=n, rh=rh, figures=figures) + extra)
    return p


def test_examples_parse_and_psd_moments():
    for f in sorted(EXAMPLES.glob("ensemble_*.toml")):
        cfg = load_config(f)
        assert cfg.spacing == 5e-9 and cfg.relative_humidity
    cfg = load_config(EXAMPLES / "ensemble_S2_moments_auto.toml")
    assert cfg.n == "auto" and cfg.auto["tolerance"] == 0.02
    psd = cfg.build_psd()
    q = psd.q.values
    m0 = 2 * np.pi * np.trapezoid(psd.values * q, q)
    assert m0 == pytest.approx(4.32e-18, rel=2e-3)  # Table 3, S2


def test_quantities():
    assert parse_quantity("15.7 nm2", "length", name="m0", power=2) == pytest.approx(15.7e-18)
    assert parse_quantity(3e-9, "length", name="x") == 3e-9
    assert parse_quantity("1.28 um", "length", name="size") == pytest.approx(1.28e-6)
    with pytest.raises(ValueError, match="unknown length unit"):
        parse_quantity("5 furlong", "length", name="spacing")
    with pytest.raises(ValueError, match="power 2"):
        parse_quantity("15.7 nm", "length", name="m0", power=2)


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"rh": "[]"}, "relative_humidity is empty"),
        ({"rh": "[30, 50]"}, "fractions in"),
        ({"n": "0"}, "integer >= 1 or 'auto'"),
        ({"n": "'lots'"}, "integer >= 1 or 'auto'"),
        ({"extra": "[bogus]\nx = 1\n"}, "unknown table"),
        ({"extra": "[run]\nschedular = 'x'\n"}, "unknown key"),
    ],
)
def test_bad_config(tmp_path, kw, match):
    with pytest.raises(ValueError, match=match):
        load_config(_cfg(tmp_path, **kw))


def test_cli_reports_bad_input(tmp_path, capsys):
    assert main(["run", str(_cfg(tmp_path, rh="[]"))]) == 1
    assert "relative_humidity is empty" in capsys.readouterr().err
    assert main(["run", str(tmp_path / "missing.toml")]) == 1
    assert "not found" in capsys.readouterr().err
