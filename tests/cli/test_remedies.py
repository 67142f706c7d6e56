"""A warning's remedy is usable where the warning is printed (a flag or configuration key from the
command line, an argument from Python); the contact model and the material can be set from every
command; the pixel warning says what to do when no finer data exist."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr
from _configs import MOMENTS_PSD, SMALL_BEAM

import roughstick as rs
from conftest import lognormal_gamma
from roughstick.cli import main

RUN = 'title = "t"\n' + MOMENTS_PSD.lstrip("\n") + """[surface]
shape = [32, 32]
spacing = "5 nm"
[ensemble]
n = 2
relative_humidity = [0.3, 0.9]
seed = 7
{ensemble}
[output]
folder = "{folder}"
figures = false
"""


def _run_cfg(tmp_path, name, ensemble="", extra=""):
    p = tmp_path / f"{name}.toml"
    p.write_text(RUN.format(ensemble=ensemble, folder=name) + extra)
    return p


def test_run_takes_the_contact_model_its_warnings_name_and_says_it_in_config_keys(tmp_path, capsys):
    """`roughstick run` warned "use model='auto'" and refused a model key: the warning now names
    [ensemble] model, which the run takes ("auto" then says its choice before the work)."""
    assert main(["run", str(_run_cfg(tmp_path, "plain"))]) == 0
    err = capsys.readouterr().err
    assert 'Remedy: [ensemble] model = "auto" picks the cheapest model' in err
    assert '[surface] spacing = "' in err  # the pixel warning: a finer spacing, as a key
    assert "model='" not in err and "curves_kwargs" not in err and "spacing=" not in err
    assert main(["run", str(_run_cfg(tmp_path, "auto", 'model = "auto"'))]) == 0
    text = capsys.readouterr()
    assert "ValidityWarning" not in text.err
    said = text.out.index("auto -> ")
    assert "per surface" in text.out[said:] and said < text.out.index("apparent adhesive energy")
    band = rs.io.open_dataset(tmp_path / "auto" / "band.nc")
    assert band.attrs["contact_model"] in ("gw", "modified_dmt", "fft_bem", "bem")
    # the model key has one name in every command: the old `contact_model` is refused with it
    assert main(["run", str(_run_cfg(tmp_path, "old", 'contact_model = "fft_bem"'))]) == 1
    assert "It is now 'model': write model = ... instead" in capsys.readouterr().err


def test_the_console_script_spells_the_remedies_as_config_keys_too(tmp_path):
    """Run as a program the command computes in its own thread (so that Ctrl-C ends it at once);
    its warnings still name the configuration keys, not the Python arguments."""
    import os
    import subprocess
    import sys

    cfg = _run_cfg(tmp_path, "plain")
    res = subprocess.run([sys.executable, "-m", "roughstick.cli", "run", str(cfg)], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300,
                         env={**os.environ, "CI": "true", "MPLBACKEND": "Agg"})
    assert res.returncode == 0, res.stderr[-2000:]
    assert 'Remedy: [ensemble] model = "auto" picks the cheapest model' in res.stderr
    assert "model='" not in res.stderr and "spacing=" not in res.stderr


def test_python_callers_get_their_own_arguments_named():
    """The same warnings from Python name the argument of the function called."""
    psd = rs.surface.self_affine_psd(np.geomspace(1e5, 3e9, 300), s0=1e-36, s1=1e-37, q0=1e7, qmax=2.9e8)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rs.ensemble.run(psd, n=1, shape=(16, 16), spacing=5e-9, relative_humidity=[0.05])
    text = " ".join(str(w.message) for w in caught if issubclass(w.category, rs.ValidityWarning))
    assert "spacing=" in text and "[surface]" not in text and "--" not in text


def test_material_is_set_from_every_command_and_recorded(tmp_path, capsys):
    """Non-polysilicon films ran as poly-Si: [material] (run, risk, beam) and --material
    (curves) now set both bodies' constants, the beam's modulus follows, and outputs record it."""
    soft = '[material]\nname = "soft film"\nyoungs_modulus = "10 GPa"\npoisson_ratio = 0.3\n'
    assert main(["run", str(_run_cfg(tmp_path, "soft", extra=soft)), "-q"]) == 0
    band = rs.io.open_dataset(tmp_path / "soft" / "band.nc")
    assert (band.attrs["material"], band.attrs["material_youngs_modulus"]) == ("soft film", 10e9)
    ens = rs.ensemble.open_ensemble(tmp_path / "soft" / "ensemble")
    assert "youngs_modulus=10000000000.0" in ens.attrs["material"]  # what the curves ran on
    # curves: the same map on a soft material has another Γ
    h = rs.datasets.surface_family("S1", shape=(32, 32), seed=0, n=1).isel(realization=0).compute()
    rs.io.netcdf.write(h.to_dataset(name="height"), tmp_path / "m.nc", compute=True)
    gammas = []
    for flags, name in (([], "poly"), (["--material", "SiN", "250 GPa", "0.23"], "sin")):
        out = tmp_path / f"{name}.nc"
        assert main(["curves", str(tmp_path / "m.nc"), "--rh", "0.9", "--out", str(out), "-q", *flags]) == 0
        with xr.open_dataset(out) as ds:
            gammas.append(float(ds.adhesive_energy.squeeze()))
            assert ds.attrs["material"] == ("SiN" if flags else "poly-silicon")
    assert gammas[0] != gammas[1]
    # risk: the beam is made of the film (Γ_crit follows its modulus)
    g, _ = lognormal_gamma(n=25, rh=np.arange(0.3, 0.951, 0.05))
    rs.io.netcdf.write(rs.conventions.set_attrs(g, "surface_adhesive_energy").to_dataset(name="adhesive_energy"),
                       tmp_path / "gamma.nc", compute=True)
    cfg = tmp_path / "risk.toml"
    cfg.write_text('[output]\nfolder = "risk"\nfigures = false\n[beam]\nlengths = ["250 um"]\n'
                   '[ensemble]\nadhesive_energy = "gamma.nc"\n[material]\nyoungs_modulus = "100 GPa"\n'
                   "poisson_ratio = 0.2\n")
    assert main(["risk", str(cfg), "-q"]) == 0
    risk = rs.io.open_dataset(tmp_path / "risk" / "risk.nc")
    assert risk.attrs["material_youngs_modulus"] == 100e9 and risk.attrs["beam_youngs_modulus"] == 100e9
    # beam: the patch laws and the beam
    cfg = tmp_path / "beam.toml"
    cfg.write_text(SMALL_BEAM + soft + '[output]\nfolder = "beam"\n')
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # 16 x 16 patches are not independent: said, not the point here
        assert main(["beam", str(cfg), "-q"]) == 0
    beam = rs.io.open_dataset(tmp_path / "beam" / "beam.nc")
    assert beam.attrs["material"] == "soft film" and beam.attrs["youngs_modulus"] == 10e9  # the beam's
    # an unknown name is refused before any work, naming the known ones and the constants
    cfg.write_text(SMALL_BEAM + '[material]\nname = "silicon"\n[output]\nfolder = "beam2"\n')
    capsys.readouterr()
    assert main(["beam", str(cfg)]) == 1
    err = capsys.readouterr().err
    assert "no material named 'silicon'" in err and "youngs_modulus" in err and "poisson_ratio" in err
    assert not (tmp_path / "beam2").exists()
    assert main(["curves", str(tmp_path / "m.nc"), "--rh", "0.9", "--out", str(tmp_path / "x.nc"),
                 "--material", "250 GPa"]) == 1
    assert "--material" in capsys.readouterr().err and not (tmp_path / "x.nc").exists()


def _pixel_message(h, rh=0.05):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rs.contact.warn_if_unresolved(h, relative_humidity=rh)
    (w,) = [w for w in caught if issubclass(w.category, rs.PixelResolutionWarning)]
    return str(w.message)


def test_the_pixel_warning_asks_for_finer_data_only_where_they_can_be_had(tmp_path, capsys):
    """A 0.98 nm AFM map was asked for finer pixels than any AFM gives: a measured map, or a pixel
    at or below 1 nm, is told to measure and quote what the pixel costs; a generated surface is
    told the spacing that resolves the neck."""
    gen = rs.datasets.surface_family("S1", shape=(64, 64), seed=0, n=1).isel(realization=0).compute()
    fine = rs.testing.make_topography(gen.values, spacing=0.98e-9)  # a measured map, 0.98 nm
    msg = _pixel_message(fine)
    assert "0.98 nm is already about as fine as topography maps come" in msg
    assert "resolution_study" in msg and "finer pixels" not in msg and "spacing" not in msg
    coarse = rs.testing.make_topography(gen.values, spacing=5e-9)  # measured, 5 nm
    msg = _pixel_message(coarse)
    assert "a scan with finer pixels is the remedy" in msg and "where none can be made" in msg
    msg = _pixel_message(gen)  # generated: the spacing that makes the neck 3 pixels wide
    neck = float(rs.contact.surface_groups(gen, relative_humidity=0.05).neck_pixels)
    assert f"spacing={neck * 5e-9 / rs.contact.RESOLVED_NECK_PIXELS:.2g} or finer" in msg
    # from `roughstick curves` the same check is its --resolution flag
    rs.io.netcdf.write(fine.to_dataset(name="height"), tmp_path / "afm.nc", compute=True)
    assert main(["curves", str(tmp_path / "afm.nc"), "--rh", "0.05", "--model", "fft_bem",
                 "--out", str(tmp_path / "c.nc"), "-q"]) == 0
    err = capsys.readouterr().err
    assert "--resolution (add it to this command" in err and "resolution_study(" not in err


@pytest.mark.parametrize("command", ["demo", "reproduce"])
def test_fixed_commands_name_the_key_of_the_users_own_run(command):
    from roughstick._core.remedy import spell, spelled
    from roughstick.cli import build_parser

    args = build_parser().parse_args([command])
    with spelled(**args.remedies(args)):
        text = spell("contact_model", "auto")
    assert text.startswith('[ensemble] model = "auto" in a `roughstick run` configuration')
    assert f"`roughstick {command}` are fixed" in text
