"""`roughstick risk CONFIG.toml`: from a given sample of Gamma, and bad configs."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from conftest import lognormal_gamma


def test_cli_risk_from_given_sample(tmp_path, capsys):
    from roughstick.cli import main

    g, _ = lognormal_gamma(n=25, rh=np.arange(0.3, 0.951, 0.05))
    g = rs.conventions.set_attrs(g, "surface_adhesive_energy")
    sample = xr.concat([g, 2 * g], dim=xr.DataArray(["none", "paper"], dims="adsorbed_layer"))
    sample["adsorbed_layer"].attrs = {"units": "1", "long_name": "adsorbed water layer model"}
    ds = sample.to_dataset(name="adhesive_energy")
    rs.io.netcdf.write(ds, tmp_path / "gamma.nc", compute=True)
    (tmp_path / "points.csv").write_text("relative_humidity,crack_length [um]\n0.4,420\n0.7,380\n")
    cfg = tmp_path / "risk.toml"
    cfg.write_text(
        '[output]\nfolder = "out"\n'
        '[beam]\nlengths = ["250 um", "350 um", "500 um"]\n'
        '[ensemble]\nadhesive_energy = "gamma.nc"\n'
        "[risk]\nlevels = [0.1, 0.5]\n"
        '[[measured]]\nfile = "points.csv"\nlabel = "csv"\n'
        '[[measured]]\nrelative_humidity = [0.5]\nadhesive_energy = ["0.5 mJ m-2"]\n'
    )
    assert main(["risk", str(cfg)]) == 0
    text = capsys.readouterr().out
    assert "RH where P(stuck) reaches 0.5" in text
    out = tmp_path / "out"
    for f in ("risk.nc", "stiction_probability.png", "stiction_vs_length.png",
              "adhesive_energy_bands.png", "crack_length.png"):
        assert (out / f).stat().st_size > 1000, f
    got = rs.io.open_dataset(out / "risk.nc").load()
    # issue 16 item 6: the string coordinate is the layer model, not a thickness in metres
    assert got["adsorbed_layer"].attrs == {"long_name": "adsorbed water layer model"}
    ref = rs.stiction.risk_summary(sample, beam_length=[250e-6, 350e-6, 500e-6], probabilities=[0.1, 0.5])
    np.testing.assert_allclose(got.stiction_probability.transpose(*ref.stiction_probability.dims),
                               ref.stiction_probability)
    np.testing.assert_allclose(got.crossing_humidity.transpose(*ref.crossing_humidity.dims),
                               ref.crossing_humidity)
    # the layer doubles Gamma here, so P(stuck) with the layer is never below the no-layer one
    assert (got.stiction_probability.sel(adsorbed_layer="paper")
            >= got.stiction_probability.sel(adsorbed_layer="none")).all()


def test_cli_risk_bad_config(tmp_path):
    from roughstick.cli import main

    cfg = tmp_path / "bad.toml"
    cfg.write_text("[beam]\nlength_um = 300\n")
    assert main(["risk", str(cfg)]) == 1
    cfg.write_text("[beems]\n")
    assert main(["risk", str(cfg)]) == 1
    assert main(["risk", str(tmp_path / "missing.toml")]) == 1


def test_failed_risk_run_never_blocks_the_next(tmp_path, monkeypatch, capsys):
    """Issue 16 item 4: a failed run left its folder; the retry (other parameters) was refused
    with a hint to --overwrite, which risk did not take."""
    from roughstick.cli import main, risk

    cfg = tmp_path / "r.toml"
    text = ('[output]\nfolder = "out"\n[surface]\nshape = [64, 512]\n'
            '[ensemble]\nn = 2\nseed = {seed}\nrelative_humidity = [0.5, 0.7, 0.9]\nadsorbed_layer = ["none"]\n')
    cfg.write_text(text.format(seed=1))
    real = rs.stiction.predict_adhesive_energy

    def fails_after_writing(*a, **kw):
        real(*a, **kw)  # the ensemble folder is written, then the run fails
        raise ValueError("the mean pressure is still attractive at the bottom of the distance grid")

    monkeypatch.setattr(risk.rs.stiction, "predict_adhesive_energy", fails_after_writing)
    assert main(["risk", str(cfg), "-q"]) == 1
    monkeypatch.setattr(risk.rs.stiction, "predict_adhesive_energy", real)
    cfg.write_text(text.format(seed=2))  # the user's retry with other parameters
    assert main(["risk", str(cfg), "-q"]) == 0
    assert (tmp_path / "out" / "risk.nc").is_file()
    # a COMPLETE run with other parameters is not replaced silently; --overwrite replaces it
    cfg.write_text(text.format(seed=3))
    assert main(["risk", str(cfg), "-q"]) == 1
    assert "--overwrite" in capsys.readouterr().err
    assert main(["risk", str(cfg), "-q", "--overwrite"]) == 0


def test_cli_risk_subset_method_is_checked_before_work(tmp_path, capsys):
    """method = 'subset' needs a zone shape, a whole number of chains, and no given Γ sample;
    each mistake is named with its fix before any simulation starts."""
    from roughstick.cli import main
    from roughstick.cli._config import ConfigError
    from roughstick.cli.risk import load_risk_config

    cfg = tmp_path / "r.toml"
    cfg.write_text('[risk]\nmethod = "subset"\nn_per_level = 333\nmax_evaluations = 100\n')
    try:
        load_risk_config(cfg)
    except ConfigError as exc:
        msg = str(exc)
    else:  # pragma: no cover
        raise AssertionError("no ConfigError")
    assert "set [surface] shape" in msg and "multiple of 5" in msg and "below n_per_level" in msg
    cfg.write_text('[risk]\nmethod = "importance"\n')
    assert main(["risk", str(cfg)]) == 1
    cfg.write_text('[risk]\nmethod = "subset"\ntarget_cv = 1.5\n[surface]\nshape = [16, 16]\n')
    assert main(["risk", str(cfg)]) == 1
    cfg.write_text('[risk]\nmethod = "subset"\ntarget_cv = "20 %"\n[surface]\nshape = [16, 16]\n')
    c = load_risk_config(cfg)
    assert c["risk"]["method"] == "subset" and c["risk"]["target_cv"] == 0.2
    assert c["risk"]["n_per_level"] == 1000 and c["risk"]["max_evaluations"] == 20000
    assert c["risk"]["model"] == "auto"  # the cheaper model measured within 10 % on the zones
    cfg.write_text('[risk]\nmodel = "modified_dmt"\n')  # counting: the ensemble's model
    assert load_risk_config(cfg)["risk"]["model"] == "modified_dmt"
    cfg.write_text('[risk]\nmodel = "fft_bem"\n[ensemble]\nadhesive_energy = "g.nc"\n')
    (tmp_path / "g.nc").write_text("")
    with pytest.raises(ConfigError, match="model = 'fft_bem' computes Γ, which"):
        load_risk_config(cfg)
    cfg.write_text('[risk]\nmethod = "subset"\nmodel = "bem"\n[surface]\nshape = [16, 16]\n')
    assert main(["risk", str(cfg)]) == 1
    assert "fft_bem" in capsys.readouterr().err
    for old_key, new in (('contact_model = "fft_bem"', 'model = "fft_bem"'),
                         ("samples_per_level = 500", "n_per_level = 1000")):
        cfg.write_text(f'[risk]\n{old_key}\n')  # the keys of earlier releases name the new one
        key = new.split()[0]
        with pytest.raises(ConfigError, match=f"unknown key .* (Write {new}|It is now '{key}')"):
            load_risk_config(cfg)


def test_cli_risk_subset_run(tmp_path, capsys):
    """A small subset-simulation risk run: P(stuck) per layer, length and RH with its interval,
    cv and evaluations in risk.nc, crossing humidities read from it; and the numbers are those of
    rs.stuck_probability(psd, method="subset") with the same settings."""
    from roughstick.cli import main

    cfg = tmp_path / "r.toml"
    cfg.write_text(
        '[output]\nfolder = "out"\n'
        '[beam]\nlengths = ["400 um"]\n'
        '[surface]\nshape = [16, 16]\n'
        '[ensemble]\nrelative_humidity = [0.5, 0.7]\nadsorbed_layer = ["paper"]\nseed = 3\n'
        '[run]\nscheduler = "sync"\n'
        '[risk]\nmethod = "subset"\nn_per_level = 50\ntarget_cv = 0.5\nmax_evaluations = 400\n'
        "levels = [0.01]\n")
    assert main(["risk", str(cfg), "-q"]) == 0
    got = rs.io.open_dataset(tmp_path / "out" / "risk.nc").load()
    assert got.stiction_probability.dims == ("adsorbed_layer", "beam_length", "rh")
    p = got.stiction_probability.values
    assert np.all((got.stiction_probability_lower.values <= p) & (p <= got.stiction_probability_upper.values))
    assert np.all(got.n_evaluations.values <= 400 + 40)
    assert "crossing_humidity" in got and got.attrs["method"] == "subset"
    fit = rs.stiction.cantilever_psd(**{k: rs.stiction.interaction_zone.TABLE4[k]
                               for k in ("roughness", "asperity_radius", "asperity_density", "qmax")})
    ref = rs.stuck_probability(
        lambda q: rs.surface.self_affine_psd(q, **{k: float(fit[k]) for k in ("s0", "s1", "q0", "qmax")}), method="subset",
        relative_humidity=[0.5, 0.7], shape=(16, 16), spacing=5e-9, beam_length=400e-6, target_cv=0.5,
        max_evaluations=400, seed=3, n_per_level=50, scheduler="sync")
    np.testing.assert_array_equal(p[0, 0], ref.stiction_probability.values)


def test_cli_risk_subset_on_the_boundary_element_model(tmp_path, capsys):
    """[risk] model = 'fft_bem' runs the estimate on the FFT-BEM (the model to use where Eq. 16's
    tail is an artefact): the numbers are those of rs.stuck_probability(method="subset") with
    model='fft_bem', they differ from the Eq. 16 run's, and the Eq. 16 run carries its
    BEM re-check into risk.nc."""
    from roughstick.cli import main

    def run(model, folder):
        cfg = tmp_path / f"{folder}.toml"
        cfg.write_text(
            f'[output]\nfolder = "{folder}"\n'
            '[beam]\nlengths = ["120 um"]\n'
            '[surface]\nshape = [16, 16]\n'
            '[ensemble]\nrelative_humidity = [0.5]\nadsorbed_layer = ["paper"]\nseed = 5\n'
            '[run]\nscheduler = "sync"\n'
            '[risk]\nmethod = "subset"\nn_per_level = 50\ntarget_cv = 0.9\nmax_evaluations = 200\n'
            f'levels = [0.01]\nmodel = "{model}"\n')
        assert main(["risk", str(cfg), "-q"]) == 0
        return rs.io.open_dataset(tmp_path / folder / "risk.nc").load()

    bem = run("fft_bem", "bem")
    assert bem.attrs["contact_model"] == "fft_bem" and "failures_confirmed_by_bem" not in bem
    fit = rs.stiction.cantilever_psd(**{k: rs.stiction.interaction_zone.TABLE4[k]
                               for k in ("roughness", "asperity_radius", "asperity_density", "qmax")})
    ref = rs.stuck_probability(
        lambda q: rs.surface.self_affine_psd(q, **{k: float(fit[k]) for k in ("s0", "s1", "q0", "qmax")}), method="subset",
        relative_humidity=[0.5], shape=(16, 16), spacing=5e-9, beam_length=120e-6, target_cv=0.9,
        max_evaluations=200, seed=5, n_per_level=50, scheduler="sync", model="fft_bem")
    np.testing.assert_array_equal(bem.stiction_probability.values[0, 0], ref.stiction_probability.values)
    dmt = run("modified_dmt", "dmt")
    assert dmt.attrs["contact_model"] == "modified_dmt"
    assert not np.array_equal(dmt.stiction_probability.values, bem.stiction_probability.values)
    assert "failures_confirmed_by_bem" in dmt


def test_cli_risk_subset_shows_each_level_with_the_time_left(tmp_path, capsys):
    """`roughstick risk` on method = 'subset' printed one line, then nothing until the end: each
    completed level now prints a line with its threshold, the evaluations and the time left,
    re-estimated from what has run; --quiet keeps them out."""
    from roughstick.cli import main

    cfg = tmp_path / "r.toml"
    cfg.write_text(
        '[output]\nfolder = "out"\n'
        '[beam]\nlengths = ["105 um", "400 um"]\n'
        '[surface]\nshape = [16, 16]\n'
        '[ensemble]\nrelative_humidity = [0.5]\nadsorbed_layer = ["paper"]\nseed = 3\n'
        '[run]\nscheduler = "sync"\n'
        '[risk]\nmethod = "subset"\nmodel = "modified_dmt"\nn_per_level = 50\ntarget_cv = 0.9\nmax_evaluations = 300\n'
        "levels = [0.01]\n")
    with warnings.catch_warnings():
        warnings.simplefilter("always", rs.ValidityWarning)  # printed by the command
        assert main(["risk", str(cfg)]) == 0
    text = capsys.readouterr()
    # the BEM re-check's remedy is the key of this file, not failure_probability's argument
    assert '[risk] model = "fft_bem"' in text.err and "model='" not in text.err
    out = text.out.splitlines()
    levels = [i for i, line in enumerate(out) if line.startswith("subset [paper] l = ")]
    assert len(levels) >= 3, out  # the short beam needs several levels, the long one one
    assert levels[-1] < next(i for i, line in enumerate(out) if line.startswith("subset: P(stuck)"))
    first, last = out[levels[0]], out[levels[-1]]
    assert "(point 1 of 2): run 1, level 0 done (threshold " in first
    assert "at most" in first and "evaluations per point)" in first
    assert "(point 2 of 2)" in last and "left (as the 1 point done)" in last  # re-estimated
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        assert main(["risk", str(cfg), "-q", "--overwrite"]) == 0
    assert "level 0 done" not in capsys.readouterr().out


def test_risk_answers_on_the_beams_zone_and_warns_with_the_cost_of_a_smaller_one(tmp_path, capsys):
    """With no [surface] shape, `roughstick risk` answers on the beam's whole interaction zone Δs × w
    (524 x 6000 px for the paper's beam at 5 nm), not on a square; a smaller shape is said before the
    work with its measured cost (the zone-size law: a 0.64 µm square carries 170 x the zone's median Γ
    at 30 % RH), and risk.nc records the zone its P(stuck) belongs to."""
    from roughstick.cli import main
    from roughstick.cli._config import ConfigError
    from roughstick.cli.risk import _beam, load_risk_config, zone_of_the_answer

    cfg = tmp_path / "r.toml"
    cfg.write_text('[beam]\nlengths = ["300 um"]\n')
    c = load_risk_config(cfg)
    zone = zone_of_the_answer(c, _beam(c)[0])
    assert zone["zone_shape"] == list(rs.stiction.interaction_zone_shape()) == [524, 6000]
    assert "zone_size_bias" not in zone
    cfg.write_text('[risk]\nmethod = "subset"\n')  # no shape: the whole zone is out of its reach
    with pytest.raises(ConfigError, match="use method = 'count' .*, which answers on the whole zone"):
        load_risk_config(cfg)
    cfg.write_text('[output]\nfolder = "out"\nfigures = false\n[beam]\nlengths = ["300 um", "1500 um"]\n'
                   '[surface]\nshape = [128, 128]\n[ensemble]\nn = 2\nrelative_humidity = [0.5]\n'
                   'adsorbed_layer = ["none"]\nstream = false\n[risk]\nmodel = "modified_dmt"\n')
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["risk", str(cfg)]) == 0
    captured = capsys.readouterr()
    assert "170 at 30 %" in captured.err and "Remove [surface] shape" in captured.err, captured.err
    got = rs.io.open_dataset(tmp_path / "out" / "risk.nc")
    assert list(got.attrs["zone_shape"]) == [128, 128] and "135 at 50 %" in got.attrs["zone_size_bias"]
    assert "P(stuck) of a zone of 128 x 128 px" in captured.out


@pytest.mark.parametrize("band", ["[0.01, 0.05]", "[-0.01, -0.002]", "[-1.5, 0.1]", "[0.1]"])
def test_cli_risk_refuses_a_model_band_that_is_not_below_and_above(tmp_path, band):
    """The config's band is checked by the library's rule before any work, and the message names
    the key and a band to copy."""
    from roughstick.cli._config import ConfigError
    from roughstick.cli.risk import load_risk_config

    cfg = tmp_path / "r.toml"
    cfg.write_text(f'[risk]\nmethod = "strips"\nmodel_band = {band}\n')
    with pytest.raises(ConfigError, match=r"\[risk\] model_band = .*below <= 0 <= above.*"
                                          r"e\.g\. model_band = \[-0\.005, 0\.045\]"):
        load_risk_config(cfg)
    with pytest.raises(ValueError, match=r"model_band=.*below <= 0 <= above"):
        rs.stiction.strip_stuck_probability(rs.datasets.family_psd("table4"), relative_humidity=[0.8],
                                            beam_length=[250e-6], n=96, model_band=eval(band))


def test_cli_risk_strips_refines_each_layers_crossings_on_its_own_humidities(tmp_path, capsys):
    """refine_crossing = true: each layer gets its own further humidities near its crossings; a
    humidity refined for one layer is NaN in the other, and each layer's crossing is read from its
    own points (the same as the library's on that layer alone)."""
    from roughstick.cli import main

    cfg = tmp_path / "r.toml"
    cfg.write_text(
        '[output]\nfolder = "out"\n[beam]\nlengths = ["250 um"]\n'
        '[ensemble]\nrelative_humidity = [0.66, 0.8]\nadsorbed_layer = ["none", "paper"]\nseed = 1\n'
        '[risk]\nmethod = "strips"\nmodel = "modified_dmt"\nn_subzones = 96\nlevels = [0.9]\n'
        'refine_crossing = true\n')
    assert main(["risk", str(cfg)]) == 0
    assert "[paper] refined at RH" in capsys.readouterr().out
    risk = xr.open_dataset(tmp_path / "out" / "risk.nc").load()
    assert risk.rh.size > 2
    for layer in ("none", "paper"):
        mine = risk.sel(adsorbed_layer=layer).dropna("rh", subset=["stiction_probability"])
        assert {0.66, 0.8} <= set(np.round(mine.rh.values, 3).tolist())
        x = rs.stiction.crossing_humidity(mine.drop_vars([v for v in mine.data_vars if v.startswith("crossing")]),
                                          probability=0.9)
        np.testing.assert_array_equal(risk.crossing_humidity.sel(adsorbed_layer=layer, probability_level=0.9).values,
                                      x.crossing_humidity.values)
    assert np.isfinite(risk.crossing_humidity.sel(adsorbed_layer="paper")).all()
