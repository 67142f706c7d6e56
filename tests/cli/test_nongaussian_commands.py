"""`roughstick psd` prints the height-distribution diagnostics; `roughstick run` from maps picks the
height distribution ([surface] height_distribution) and reports where the maps fall."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.cli import main
from roughstick.cli._config import ConfigError, load_config
from roughstick.cli.run import run_params

SPACING = 5e-9
Q0 = 2 * np.pi / (8 * SPACING)


def psd_function(q):
    return 1.6e-35 * (1 + (np.asarray(q) / Q0) ** 2) ** -2


def _skewed_map(path, seed=3, shape=64):
    d = rs.surface.height_distribution(skewness=1.0, kurtosis=5.0)
    h = rs.surface.generate_surfaces(psd_function, n=1, shape=shape, spacing=SPACING, seed=seed,
                                     height_distribution=d).isel(realization=0, drop=True).compute()
    h = h.drop_vars([c for c in h.coords if c not in ("x", "y")])
    h.attrs = {"units": "m", "long_name": "surface height", "periodic": 0}
    h.to_dataset(name="height").to_netcdf(path)
    return path


def test_psd_prints_the_height_diagnostics(tmp_path, capsys):
    _skewed_map(tmp_path / "a.nc")
    assert main(["psd", str(tmp_path / "a.nc"), "--submaps", "1", "--out", str(tmp_path / "p.nc")]) == 0
    out = capsys.readouterr().out
    assert "height distribution of the map" in out and "NOT Gaussian within the sampling error" in out
    assert '[surface] height_distribution = "maps"' in out
    with xr.open_dataset(tmp_path / "p.nc") as ds:
        assert int(ds.gaussian) == 0 and ds.gaussian.attrs["units"] == "1"
        assert float(ds.skewness) > float(ds.skewness_gaussian_upper)
        assert ds.tail_quantile.dims == ("probability",)
    assert main(["psd", str(tmp_path / "a.nc"), "--submaps", "1", "--surrogates", "0",
                 "--out", str(tmp_path / "q.nc")]) == 0
    assert "height distribution" not in capsys.readouterr().out


RUN = """
[psd]
source = "samples"
files = ["a.nc"]
submaps = 1
[surface]
shape = 64
spacing = "5 nm"
{surface}
[ensemble]
n = 8
relative_humidity = [0.5, 0.9]
model = "fft_bem"
[output]
folder = "out"
figures = false
"""


def _config(tmp_path, surface=""):
    _skewed_map(tmp_path / "a.nc")
    p = tmp_path / "c.toml"
    p.write_text(RUN.format(surface=surface))
    return p


def test_run_config_keys_are_checked(tmp_path):
    cfg = load_config(_config(tmp_path))
    assert cfg.height_distribution["height_distribution"] == "auto"
    assert "height_distribution" not in run_params(cfg)  # earlier folders still resume
    cfg = load_config(_config(tmp_path, 'height_distribution = "johnson"\nskewness = 0.4\nkurtosis = 3.8'))
    assert cfg.heights().attrs["family"] == "johnson_su" and "height_distribution" in run_params(cfg)
    for surface, match in [('height_distribution = "johnson"', "needs skewness and kurtosis"),
                           ("skewness = 0.4", "only apply with"),
                           ('height_distribution = "johnson"\nskewness = 1.0\nkurtosis = 1.5',
                            "no distribution has skewness"),
                           ('height_distribution = "normal"', "must be one of")]:
        with pytest.raises(ConfigError, match=match):
            load_config(_config(tmp_path, surface))


def test_run_from_a_skewed_map_uses_its_distribution_and_places_it(tmp_path, capsys):
    assert main(["run", str(_config(tmp_path))]) == 0
    out = capsys.readouterr().out
    assert "heights: the maps' own distribution" in out and "not Gaussian" in out
    assert "the maps' own Γ" in out and "a.nc: RH 0.5" in out
    with xr.open_dataset(tmp_path / "out" / "band.nc") as band:
        assert band.map_adhesive_energy.dims == ("map", "rh") and "map_percentile" in band
        assert band.attrs["height_distribution"] == "empirical"


def test_run_with_gaussian_heights_warns_with_the_config_key(tmp_path, capsys):
    assert main(["run", str(_config(tmp_path, 'height_distribution = "gaussian"'))]) == 0
    captured = capsys.readouterr()
    assert "heights: Gaussian" in captured.out
    assert "ContainmentWarning" in captured.err and '[surface] height_distribution = "maps"' in captured.err
