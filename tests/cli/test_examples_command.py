"""`roughstick examples`: the example configurations ship with the package (a wheel user has no
examples/ folder) and copies of them run from any folder (their maps are bundled:S1A ...)."""

from __future__ import annotations

import pathlib

import roughstick as rs
from roughstick.cli import main
from roughstick.cli._config import load_config

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_every_example_of_the_repository_is_shipped_unchanged():
    shipped = rs.datasets.example_configs()
    repo = sorted(p.name for p in (ROOT / "examples").glob("*.toml"))
    assert sorted(shipped) == repo
    for name, path in shipped.items():
        assert path.read_bytes() == (ROOT / "examples" / name).read_bytes(), name


def test_no_example_points_into_the_checkout():
    """A copy outside the repository runs: maps are named bundled:..., no '../' paths."""
    for name, path in rs.datasets.example_configs().items():
        assert "../" not in path.read_text(), name


def test_list_copy_and_run_a_copy_elsewhere(tmp_path, capsys, monkeypatch):
    assert main(["examples"]) == 0
    listing = capsys.readouterr().out
    assert "roughstick run examples/ensemble_S1_samples.toml" in listing
    assert "roughstick risk examples/risk.toml" in listing and "roughstick beam examples/beam.toml" in listing
    monkeypatch.chdir(tmp_path)
    assert main(["examples", "ensemble_S1_samples", "risk.toml", "--out", "mine"]) == 0
    assert "run: roughstick run mine/ensemble_S1_samples.toml" in capsys.readouterr().out
    assert sorted(p.name for p in (tmp_path / "mine").iterdir()) == ["ensemble_S1_samples.toml", "risk.toml"]
    cfg = load_config(tmp_path / "mine" / "ensemble_S1_samples.toml")
    assert cfg.psd["files"] == [str(rs.datasets.sample_path(n)) for n in ("S1A", "S1B", "S1C")]
    assert cfg.folder == tmp_path / "mine" / "out-ensemble-S1"  # beside the copy


def test_bad_names_and_existing_files_are_refused_with_the_fix(tmp_path, capsys):
    assert main(["examples", "risc", "--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err.strip()
    assert "NAME risc: no such example" in err and "risk_subset" in err and "\n" not in err
    assert not list(tmp_path.iterdir())
    assert main(["examples", "risk", "--out", str(tmp_path)]) == 0
    (tmp_path / "risk.toml").write_text("# mine\n")
    assert main(["examples", "risk", "--out", str(tmp_path)]) == 1
    assert "pass --overwrite" in capsys.readouterr().err
    assert (tmp_path / "risk.toml").read_text() == "# mine\n"  # kept
    assert main(["examples", "risk", "--out", str(tmp_path), "--overwrite"]) == 0
    assert (tmp_path / "risk.toml").read_text() == rs.datasets.example_configs()["risk.toml"].read_text()


def test_missing_config_names_the_examples_command(tmp_path, capsys):
    assert main(["run", str(tmp_path / "missing.toml")]) == 1
    assert "roughstick examples --out examples" in capsys.readouterr().err


def test_each_example_says_what_it_answers(capsys):
    """The listing named the files but not what each computes (two printed nothing at all): every
    shipped example opens with a one-line ``# description:`` that the listing prints under it."""
    from roughstick.cli.examples import description

    shipped = rs.datasets.example_configs()
    texts = {name: description(path) for name, path in shipped.items()}
    assert all(len(t) > 40 and "\n" not in t for t in texts.values()), texts
    assert len(set(texts.values())) == len(texts)  # each its own
    assert main(["examples"]) == 0
    lines = capsys.readouterr().out.splitlines()
    for name, text in texts.items():
        k = next(i for i, line in enumerate(lines) if line.endswith(f" examples/{name}"))
        assert lines[k + 1].strip() == text, name
