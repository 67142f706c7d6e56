"""``roughstick beam CONFIG.toml``: runs, writes the labelled result, reuses the bank on rerun."""

import warnings

import xarray as xr

from roughstick.cli import main

CONFIG = """
[beam]
lengths_um = [100.0, 300.0]
[surface]
shape = [16, 16]
[humidity]
rh_percent = [30.0, 90.0]
[bank]
laws = 3
[ensemble]
realizations = 20
"""


def test_cli_beam(tmp_path, capsys):
    cfg = tmp_path / "beam.toml"
    cfg.write_text(CONFIG)
    out = tmp_path / "out"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["beam", str(cfg), "--out", str(out)]) == 0
        assert "computed" in capsys.readouterr().out
        assert main(["beam", str(cfg), "--out", str(out)]) == 0
        assert "read from cache" in capsys.readouterr().out
    ds = xr.load_dataset(out / "beam.nc")
    assert ds.crack_length.dims == ("realization", "rh", "beam_length")
    assert ds.sizes == {"realization": 20, "rh": 2, "beam_length": 2}


def test_cli_beam_bad_key(tmp_path, capsys):
    cfg = tmp_path / "beam.toml"
    cfg.write_text("[beam]\nlength = 3\n")
    assert main(["beam", str(cfg)]) == 1
    assert "unknown key" in capsys.readouterr().err
