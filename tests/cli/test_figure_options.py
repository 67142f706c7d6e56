"""Output for reports from the command line: ``--format png|pdf|svg`` and ``--dpi`` on every command
that draws, one definition for all, and every figure they save passes the figure lint (legends
beside the data, not over it)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from _configs import MOMENTS_PSD
from _figure_lint import figure_problems
from matplotlib.figure import Figure
from test_figure_files import MAGIC, png_dpi

import roughstick as rs
from conftest import lognormal_gamma
from roughstick.cli import build_parser, main

RUN = """
title = "report"
""" + MOMENTS_PSD.lstrip("\n") + """[surface]
shape = [64, 64]
spacing = "5 nm"
[ensemble]
n = 4
relative_humidity = [0.3, 0.9]
seed = 7
chunks = 2
[output]
folder = "out"
figures = true
"""


def _risk_config(tmp_path):
    g, _ = lognormal_gamma(n=25, rh=np.arange(0.3, 0.951, 0.05))
    g = rs.conventions.set_attrs(g, "surface_adhesive_energy")
    sample = xr.concat([g, 2 * g], dim=xr.DataArray(["none", "paper"], dims="adsorbed_layer"))
    sample["adsorbed_layer"].attrs = {"units": "1", "long_name": "adsorbed water layer model"}
    rs.io.netcdf.write(sample.to_dataset(name="adhesive_energy"), tmp_path / "gamma.nc", compute=True)
    cfg = tmp_path / "risk.toml"
    cfg.write_text('[output]\nfolder = "risk-out"\n'
                   '[beam]\nlengths = ["250 um", "300 um", "350 um", "400 um", "500 um", "1500 um"]\n'
                   '[ensemble]\nadhesive_energy = "gamma.nc"\n[risk]\nlevels = [0.5]\n')
    return cfg


@pytest.fixture
def linted(monkeypatch):
    """Every figure saved while the test runs, with the figure lint's findings."""
    found = {}
    save = Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        found[str(fname)] = figure_problems(self)
        return save(self, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", savefig)
    return found


def test_every_drawing_command_has_the_same_figure_options():
    sub = build_parser()._subparsers._group_actions[0].choices
    for name in ("demo", "run", "risk", "reproduce"):
        opts = {a.dest: a for a in sub[name]._actions}
        assert opts["figure_format"].option_strings == ["--format"] and opts["figure_format"].default == "png"
        assert opts["dpi"].option_strings == ["--dpi"] and opts["dpi"].default == 200
        assert opts["figure_format"].type is sub["demo"]._option_string_actions["--format"].type, name


@pytest.mark.parametrize("fmt", ["pdf", "svg"])
def test_run_and_risk_write_vector_figures(tmp_path, fmt, capsys, linted):
    (tmp_path / "c.toml").write_text(RUN)
    assert main(["run", str(tmp_path / "c.toml"), "--format", fmt, "--dpi", "150"]) == 0
    figs = sorted(p.name for p in (tmp_path / "out").iterdir() if p.suffix in (".png", ".pdf", ".svg"))
    assert figs == [f"curves.{fmt}", f"energy_band.{fmt}", f"energy_ecdf.{fmt}"]
    assert main(["risk", str(_risk_config(tmp_path)), "--format", fmt]) == 0
    risk_figs = sorted(p.name for p in (tmp_path / "risk-out").iterdir() if p.suffix in (".png", ".pdf", ".svg"))
    assert risk_figs == sorted(f"{n}.{fmt}" for n in ("stiction_probability", "stiction_vs_length",
                                                     "adhesive_energy_bands", "crack_length"))
    for p in [tmp_path / "out" / f for f in figs] + [tmp_path / "risk-out" / f for f in risk_figs]:
        assert p.read_bytes().startswith(MAGIC[fmt]), p
    # every figure `run` drew passes the whole lint; no legend of `run` or `risk` covers data
    assert len(linted) == 7
    assert not {k: v for k, v in linted.items() if v and "risk-out" not in k}
    assert not {k: [p for p in v if "legend" in p] for k, v in linted.items() if any("legend" in p for p in v)}


def test_default_png_at_200_dpi_and_bad_options_refused_before_work(tmp_path, capsys):
    (tmp_path / "c.toml").write_text(RUN.replace("n = 4", "n = 2"))
    assert main(["run", str(tmp_path / "c.toml"), "--dpi", "120"]) == 0
    assert png_dpi(tmp_path / "out" / "energy_band.png") == pytest.approx(120, abs=0.1)
    for bad, says in ((["--format", "jpg"], "--format='jpg': not a figure format; use 'png', 'pdf', 'svg'"),
                      (["--dpi", "20000"], "--dpi='20000': give a whole number of dots per inch from 50 to 1200")):
        with pytest.raises(SystemExit) as exc:
            main(["demo", "--out", str(tmp_path / "demo"), *bad])
        assert exc.value.code == 2 and says in capsys.readouterr().err
        assert not (tmp_path / "demo").exists()


def test_demo_figures_in_svg_pass_the_legend_check(tmp_path, capsys, linted):
    """The demo's ensemble and cantilever figures (fig17 and stiction_probability.png had their
    legends over the data) written as SVG."""
    out = tmp_path / "demo"
    assert main(["demo", "--quick", "--only", "ensemble", "cantilever", "--out", str(out), "--format", "svg"]) == 0
    svgs = sorted(p.name for p in out.iterdir() if p.suffix == ".svg")
    assert svgs == ["crack_length.svg", "fig14_ensemble_curves.svg", "fig16_energy_band.svg",
                    "fig17_energy_ecdf.svg", "fig20_adhesive_energy_bands.svg", "stiction_probability.svg"]
    assert not list(out.glob("*.png"))
    legend = {k: [p for p in v if "legend" in p] for k, v in linted.items()}
    assert len(legend) == 6 and not {k: v for k, v in legend.items() if v}, legend
