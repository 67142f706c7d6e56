"""The error budget of every summary: the model's measured bound, the distance grid's estimate and
the pixel's (from a resolution study), in the summary's attributes, in error_budget, in the
ensemble band's lines and in what `roughstick curves` prints."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import roughstick as rs

RH = [0.3, 0.9]


@pytest.fixture(scope="module")
def s2_map():
    return rs.datasets.surface_family("S2", shape=(48, 48), seed=2)


def _quiet(f, *a, **k):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        return f(*a, **k)


def test_the_model_part_is_the_measured_bound_of_the_model_run(s2_map):
    for model in ("modified_dmt", "fft_bem"):
        s = rs.contact.summary(_quiet(rs.contact.curves, s2_map, relative_humidity=RH, model=model))
        budget = rs.contact.error_budget(s)
        groups = rs.contact.surface_groups(s2_map, relative_humidity=RH)
        for j, r in enumerate(RH):
            g = {f: float(groups[f].sel(rh=r)) for f in ("pressure_ratio", "maugis_lambda", "hw_over_sigma")}
            expect = rs.contact.model_error(model, g, quantity="adhesive_energy").upper
            assert float(budget.model.sel(quantity="adhesive_energy").isel(rh=j)) == expect


def test_the_grid_part_shrinks_when_the_grid_is_refined(s2_map):
    """Dropping every second point of a 30-point grid moves Γ more than of a 600-point one."""
    top = float(s2_map.max())
    parts = []
    for n in (30, 600):
        d = np.linspace(top - 6e-9, top + 2e-9, n)
        s = rs.contact.summary(_quiet(rs.contact.curves, s2_map, relative_humidity=[0.5], distance=d,
                                      model="modified_dmt"), check_grid=False)
        parts.append(float(rs.contact.error_budget(s).grid.sel(quantity="adhesive_energy").max()))
    assert parts[1] < parts[0]
    assert 0 <= parts[1] < 0.02


def test_the_pixel_part_is_the_change_at_the_finer_pixel_of_a_resolution_study(s2_map):
    s = rs.contact.summary(rs.contact.curves(s2_map, relative_humidity=RH, model="fft_bem"))
    assert np.isnan(rs.contact.error_budget(s).pixel).all()  # not measured without a study
    study = rs.contact.resolution_study(s2_map, relative_humidity=RH, factors=(0.5, 1))
    budget = rs.contact.error_budget(s, study)
    change = study.relative_change_adhesive_energy.sel(pixel_size=study.pixel_size.min())
    np.testing.assert_allclose(budget.pixel.sel(quantity="adhesive_energy"), np.abs(change))
    total = budget.model.fillna(0) + budget.grid.fillna(0) + budget.pixel.fillna(0)
    np.testing.assert_allclose(budget.total, total)


def test_the_band_lines_say_the_model_error_of_the_model_run():
    psd = rs.surface.self_affine_psd(np.geomspace(1e5, 1e10, 2000), **rs.datasets.family_parameters("S2"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.PixelResolutionWarning)
        ds = rs.ensemble.run(psd, n=2, relative_humidity=[0.5], spacing=5e-9, shape=(32, 32))
    bound = ds.attrs["model_error_bound_adhesive_energy"]
    line = rs.ensemble.band_summary(rs.ensemble.confidence_band(ds))[0]
    assert f"({ds.attrs['contact_model']}: model error <= {bound[0]:.0%})" in line


def test_roughstick_curves_prints_the_budget(tmp_path, capsys):
    from roughstick.cli import main

    np.save(tmp_path / "m.npy", rs.datasets.surface_family("S2", shape=(32, 32), seed=1).values * 1e9)
    assert main(["curves", str(tmp_path / "m.npy"), "--spacing", "5 nm", "--units", "nm", "--rh",
                 "0.5", "--out", str(tmp_path / "c.nc")]) == 0
    out = capsys.readouterr().out
    assert "relative error budget" in out and "[model <= " in out and "pixel not measured" in out
