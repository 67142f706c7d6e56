"""`roughstick curves MAP --model auto|fft_bem|bem --accuracy A --resolution`."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import roughstick as rs


def _map(tmp_path, family="smooth", n=64):
    h = rs.datasets.surface_family(family, shape=(n, n), seed=11)
    path = tmp_path / f"{family}.npy"
    np.save(path, h.values * 1e9)
    return path, h


def test_model_auto_and_accuracy_reach_the_dispatcher(tmp_path, capsys):
    from roughstick.cli import main

    path, h = _map(tmp_path)
    out = tmp_path / "auto.nc"
    assert main(["curves", str(path), "--spacing", "5 nm", "--units", "nm", "--rh", "0.7",
                 "--model", "auto", "--accuracy", "0.1", "--out", str(out)]) == 0
    text = capsys.readouterr()
    # the choice, why and its cost are said before the work, so before the results
    said = text.out.index("contact model auto -> ")
    assert "estimated about" in text.out[said:] and said < text.out.index("RH 0.7: adhesive energy")
    assert "warning" not in text.err  # auto never warns about its own choice
    with xr.open_dataset(out) as ds:
        chosen = ds.attrs["contact_model"]
        assert ds.attrs["model_selection"].startswith(f"auto -> {chosen}:")
        assert "--model auto --accuracy 0.1" in ds.attrs["history"]
        api = rs.contact.curves(rs.io.read_afm(path, spacing=5e-9, units="nm"),
                                      relative_humidity=[0.7], model="auto", accuracy=0.1)
        assert api.attrs["contact_model"] == chosen
        np.testing.assert_allclose(ds.adhesive_energy.values,
                                   rs.contact.summary(api).adhesive_energy.values, rtol=1e-6)


def test_modified_dmt_warning_is_a_message_naming_the_flags(tmp_path, capsys):
    from roughstick.cli import main

    path, _ = _map(tmp_path)
    assert main(["curves", str(path), "--spacing", "5 nm", "--units", "nm", "--rh", "0.7",
                 "--accuracy", "1e-4", "--out", str(tmp_path / "m.nc")]) == 0
    err = capsys.readouterr().err
    assert err.startswith("roughstick curves: warning: modified_dmt may be off")
    assert "--model auto --accuracy 0.0001" in err


def test_bem_model_and_resolution_option(tmp_path, capsys):
    pytest.importorskip("tamaas")
    from roughstick.cli import main

    path, _ = _map(tmp_path, family="rough", n=32)
    out = tmp_path / "bem.nc"
    assert main(["curves", str(path), "--spacing", "5 nm", "--units", "nm", "--rh", "0.9",
                 "--model", "bem", "--out", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert ds.attrs["contact_model"] == "bem"
    out = tmp_path / "res.nc"
    assert main(["curves", str(path), "--spacing", "5 nm", "--units", "nm", "--rh", "0.9",
                 "--model", "fft_bem", "--resolution", "--resolution-factors", "1", "2",
                 "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "pixel-size sensitivity" in text and "pixel     10 nm" in text
    with xr.open_dataset(out) as ds:
        change = ds.resolution_relative_change_adhesive_energy
        assert float(change.sel(resolution_pixel_size=5e-9, method="nearest").squeeze()) == 0.0
        assert np.isfinite(change.sel(resolution_pixel_size=10e-9, method="nearest")).all()


def test_validity_remedy_is_said_in_flags_only(tmp_path, capsys):
    """Issue 16 item 7: messages name CLI flags, not Python arguments."""
    from roughstick.cli import main

    path, _ = _map(tmp_path)
    assert main(["curves", str(path), "--spacing", "5 nm", "--units", "nm", "--rh", "0.7",
                 "--accuracy", "1e-4", "--out", str(tmp_path / "m.nc")]) == 0
    err = capsys.readouterr().err
    assert "rough_contact_curves(" not in err and "model='" not in err
    assert "Remedy: --model auto --accuracy 0.0001 picks the cheapest model" in err


def test_curves_reads_a_bundled_map_by_name(tmp_path, capsys):
    from roughstick.cli import main

    out = tmp_path / "c.nc"
    assert main(["curves", "bundled:S1A", "--rh", "0.5", "--n-distance", "10", "--out", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert ds.attrs["input_file"] == "bundled:S1A" and ds.pressure.sizes["distance"] >= 10
    capsys.readouterr()
    assert main(["curves", "bundled:S1", "--rh", "0.5", "--out", str(out), "--overwrite"]) == 1
    err = capsys.readouterr().err
    assert "unknown bundled map 'bundled:S1'" in err and "bundled:S1A" in err


@pytest.mark.parametrize("grid, says", [
    (["1", "20", "50"], "--distance '1' has no unit"),
    (["20 nm", "1 nm", "50"], "LOW must be below HIGH"),
    (["1 nm", "20 nm", "one"], "N must be a whole number of points >= 2"),
])
def test_distance_grid_is_checked_before_reading_the_map(tmp_path, capsys, grid, says):
    """--distance took bare metres (1 20 50 meant nm made a grid of metres) and any order."""
    from roughstick.cli import main

    code = main(["curves", str(tmp_path / "absent.npy"), "--rh", "0.5", "--distance", *grid,
                 "--out", str(tmp_path / "c.nc")])
    assert code == 1
    assert says in capsys.readouterr().err


def test_distance_grid_with_units_is_used(tmp_path):
    from roughstick.cli import main

    rs.datasets.surface_family("S1", shape=(32, 32), seed=1).to_netcdf(tmp_path / "m.nc")
    assert main(["curves", str(tmp_path / "m.nc"), "--rh", "0.5", "--distance", "2 nm", "30 nm", "60",
                 "--out", str(tmp_path / "c.nc"), "-q"]) == 0
    d = xr.open_dataset(tmp_path / "c.nc").distance
    assert d.size == 60 and np.isclose(float(d.min()), 2e-9) and np.isclose(float(d.max()), 30e-9)
