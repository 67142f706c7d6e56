"""`roughstick risk` on surfaces with a film's own height distribution ([surface]
height_distribution): a skewed film's zones have taller summits than Gaussian ones, and the
keys are checked before any work."""

from __future__ import annotations

import numpy as np
import pytest

import roughstick as rs
from roughstick.cli import main

CONFIG = """
[output]
folder = "{folder}"
[surface]
shape = [32, 256]
{surface}
[ensemble]
n = 4
seed = 1
relative_humidity = [0.5]
adsorbed_layer = ["none"]
"""


def _run(tmp_path, name, surface=""):
    cfg = tmp_path / f"{name}.toml"
    cfg.write_text(CONFIG.format(folder=name, surface=surface))
    assert main(["risk", str(cfg), "-q"]) == 0
    return rs.ensemble.open_ensemble(tmp_path / name / "ensemble-none").load()


def test_risk_zones_take_the_height_distribution(tmp_path):
    gauss = _run(tmp_path, "gaussian")
    skewed = _run(tmp_path, "johnson", 'height_distribution = "johnson"\nskewness = 1.0\nkurtosis = 5.0')
    assert gauss.attrs["height_distribution"] == "gaussian"
    assert skewed.attrs["height_distribution"] == "johnson_su"
    # same PSD (same rms height), same seeds: a skewness of 1 puts the tallest summits of a
    # 32 x 256 zone near 6 rms heights instead of the Gaussian's ~4
    top_g, top_s = (float(ds.max_height.mean()) for ds in (gauss, skewed))
    assert top_s > 1.25 * top_g
    # the distance grid reaches them (no realization needed its grid extended upwards)
    assert float(skewed.distance.max()) > float(skewed.max_height.max())
    assert np.all(np.isfinite(skewed.adhesive_energy.values))


def test_risk_height_keys_are_checked_before_work(tmp_path):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(CONFIG.format(folder="bad", surface='height_distribution = "johnson"\nskewness = 1.0')
                   + '[risk]\nmethod = "subset"\n')
    with pytest.raises(Exception, match="needs skewness and kurtosis"):
        from roughstick.cli.risk import load_risk_config
        load_risk_config(cfg)
    cfg.write_text(CONFIG.format(folder="bad", surface='height_distribution = "maps"'))
    with pytest.raises(Exception, match=r'needs the maps: maps = \["scan1.tiff"'):
        load_risk_config(cfg)


def test_risk_subset_zones_are_the_films(tmp_path):
    """method = "subset" simulates the film's own zones (translation process): the run records
    the distribution, and a positively skewed film's P(stuck) at RH 0.5 is above the Gaussian
    film's, beyond both intervals (taller summits hold the flat more often)."""
    out = {}
    for name, surface in (("gaussian", ""), ("johnson", 'height_distribution = "johnson"\n'
                                                          "skewness = 1.0\nkurtosis = 5.0")):
        cfg = tmp_path / f"{name}.toml"
        cfg.write_text(CONFIG.format(folder=name, surface=surface).replace("[32, 256]", "[24, 24]")
                       + '[beam]\nlengths = ["110 um"]\n[risk]\nmethod = "subset"\nmodel = "modified_dmt"\n'
                         "target_cv = 0.3\nmax_evaluations = 2000\nn_per_level = 400\n")
        assert main(["risk", str(cfg), "-q"]) == 0
        out[name] = rs.io.open_dataset(tmp_path / name / "risk.nc").load()
    assert out["gaussian"].attrs["height_distribution"] == "gaussian"
    assert out["johnson"].attrs["height_distribution"] == "johnson_su"
    # 24 x 24 zones at RH 0.5, a 110 um beam: about 4.5 % (Gaussian) and 10.6 % (skewness 1) here
    assert float(out["johnson"].stiction_probability_lower.squeeze()) > float(
        out["gaussian"].stiction_probability_upper.squeeze())
