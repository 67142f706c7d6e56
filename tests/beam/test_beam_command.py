"""``roughstick beam CONFIG.toml``: runs, writes the labelled result, reuses the bank on rerun."""

import warnings

import xarray as xr
from _configs import SMALL_BEAM

from roughstick.cli import main

CONFIG = SMALL_BEAM


def test_cli_beam(tmp_path, capsys):
    cfg = tmp_path / "beam.toml"
    cfg.write_text(CONFIG)
    out = tmp_path / "out"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["beam", str(cfg), "--out", str(out)]) == 0
        text = capsys.readouterr().out
        assert "computed" in text
        # what one law is, said with the bank: here the 16 x 16 patch asked for (0.32 µm at 20 nm)
        assert "each law a patch of 0.32 x 0.32 um at 20 nm, contact model modified_dmt" in text
        # 3 laws re-checked cannot bound their median at 95 %: said, not left out
        assert "bank tail: the 3 largest" in text and "(too few laws checked to bound it)" in text
        assert main(["beam", str(cfg), "--out", str(out)]) == 0
        assert "read from cache" in capsys.readouterr().out
    ds = xr.load_dataset(out / "beam.nc")
    assert ds.crack_length.dims == ("realization", "rh", "beam_length")
    assert ds.sizes == {"realization": 20, "rh": 2, "beam_length": 2}
    # the closed form on the bank's CCDF beside the count: inside the count's Wilson interval
    closed = ds.stuck_probability_closed_form
    assert bool(((ds.stuck_probability_lower - 1e-9 <= closed) & (closed <= ds.stuck_probability_upper + 1e-9)).all())


def test_cli_beam_cache_folder_problems_name_the_cache_key(tmp_path, capsys):
    """A cache folder that cannot be written names [bank] cache (not --out); a damaged cache file
    is set aside and rebuilt, so the next run works."""
    (tmp_path / "a-file").write_text("")
    cfg = tmp_path / "beam.toml"
    cfg.write_text(CONFIG + 'cache = "a-file/cache"\n')
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["beam", str(cfg), "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert "cannot write the patch-bank cache folder" in err and "a-file/cache" in err
    assert "set [bank] cache in beam.toml" in err and "--out" not in err
    cfg.write_text(CONFIG)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["beam", str(cfg), "--out", str(tmp_path / "out")]) == 0
        (bank,) = (tmp_path / "beam-bank-cache").glob("patch_bank_*.nc")
        bank.write_bytes(b"not netcdf")
        capsys.readouterr()
        warnings.simplefilter("always", UserWarning)
        assert main(["beam", str(cfg), "--out", str(tmp_path / "out")]) == 0
    err = capsys.readouterr().err
    assert f"{bank}' could not be read" in err and f"moved it to {bank.name}.corrupt and rebuilding" in err
    assert bank.with_name(bank.name + ".corrupt").exists() and xr.load_dataarray(bank).sizes["law"] == 3


def test_cli_beam_bad_key(tmp_path, capsys):
    cfg = tmp_path / "beam.toml"
    cfg.write_text("[beam]\nlength = 3\n")
    assert main(["beam", str(cfg)]) == 1
    assert "unknown key" in capsys.readouterr().err


def test_cli_beam_old_dialect_names_the_fix(tmp_path, capsys):
    """Units in key names and RH in percent are refused with the one schema's spelling."""
    cfg = tmp_path / "beam.toml"
    cfg.write_text('[beam]\nlengths_um = [100.0]\n[surface]\nspacing = "20 nm"\n'
                   "[ensemble]\nrh_percent = [30.0]\n")
    assert main(["beam", str(cfg)]) == 1
    err = capsys.readouterr().err
    assert 'lengths = ["250 um", "300 um"]' in err and "relative_humidity" in err
    assert not (tmp_path / "beam-output").exists()


def test_cli_beam_cohesive_model_matches_the_python_call(tmp_path):
    """beam_model = "cohesive" in [ensemble] runs the cohesive beam; the stuck flags agree with
    the sharp front on the same draws where the laws are short-range (docs/beam.md)."""
    cfg = tmp_path / "beam.toml"
    small = CONFIG.replace("n = 20", "n = 3").replace('lengths = ["100 um", "300 um"]',
                                                      'lengths = ["300 um"]')
    cfg.write_text(small.replace("[bank]", 'beam_model = "cohesive"\n[bank]'))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["beam", str(cfg), "--out", str(tmp_path / "c")]) == 0
        cfg.write_text(small)
        assert main(["beam", str(cfg), "--out", str(tmp_path / "s")]) == 0
    c = xr.load_dataset(tmp_path / "c" / "beam.nc")
    s = xr.load_dataset(tmp_path / "s" / "beam.nc")
    assert c.sizes == s.sizes
    assert "cohesive" in str(c.attrs).lower() and "cohesive" not in str(s.attrs.get("beam_model", ""))
    assert (c.stuck.values == s.stuck.values).all()


def test_cli_beam_patch_longer_than_a_beam_names_the_keys(tmp_path, capsys):
    """A 300 µm patch on 100-200 µm beams ran; it is refused before the bank is built."""
    cfg = tmp_path / "beam.toml"
    cfg.write_text(CONFIG.replace('lengths = ["100 um", "300 um"]',
                                  'lengths = ["100 um", "200 um"]\npatch_length = "300 um"'))
    assert main(["beam", str(cfg)]) == 1
    err = capsys.readouterr().err
    assert ("[beam] patch_length = 300 um is longer than the shortest beam ([beam] lengths: 100 um)" in err
            and "Set [beam] patch_length to at most '100 um'" in err), err
    assert not (tmp_path / "beam-output").exists() and not (tmp_path / "beam-bank-cache").exists()


def test_cli_beam_implausible_cached_bank_names_the_file(tmp_path, capsys):
    """Energies a water meniscus cannot give (a bank in mJ m-2) are refused, naming the cache."""
    cfg = tmp_path / "beam.toml"
    cfg.write_text(CONFIG)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["beam", str(cfg), "--out", str(tmp_path / "a")]) == 0
    capsys.readouterr()
    (cached,) = (tmp_path / "beam-bank-cache").glob("patch_bank_*.nc")
    ds = xr.load_dataset(cached)
    ds["adhesive_energy"] = ds["adhesive_energy"] * 1e3 + 1.0  # mJ m-2 values, still labelled J m-2
    ds.to_netcdf(cached)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["beam", str(cfg), "--out", str(tmp_path / "b")]) == 1
    err = capsys.readouterr().err
    assert "[bank] the patch bank has adhesive energies up to" in err and f"delete {cached}" in err, err


def test_cli_beam_takes_the_film_height_distribution(tmp_path, capsys):
    """[surface] height_distribution = "johnson" builds the bank from skewed patches (said before
    the work, its own cache file); contradictory keys are refused before any work."""
    cfg = tmp_path / "beam.toml"
    cfg.write_text(CONFIG.replace("[surface]", '[surface]\nheight_distribution = "johnson"\n'
                                               "skewness = 1.0\nkurtosis = 4.5"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["beam", str(cfg), "--out", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "heights: johnson" in out
    ds = xr.load_dataset(tmp_path / "out" / "beam.nc")
    assert ds.sizes["beam_length"] == 2
    cfg.write_text(CONFIG.replace("[surface]", '[surface]\nheight_distribution = "johnson"'))
    assert main(["beam", str(cfg), "--out", str(tmp_path / "o2")]) == 1
    assert "needs skewness and kurtosis" in capsys.readouterr().err
    assert not (tmp_path / "o2").exists()
