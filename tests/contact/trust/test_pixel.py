"""The pixel check: does the pixel resolve the water necks (roughstick.contact.pixel)?"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import roughstick as rs


def _family_map(name, seed=0, shape=(64, 64)):
    return rs.datasets.surface_family(name, shape=shape, seed=seed, n=1).isel(realization=0).compute()


def _pixel_warnings(fn, *args, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = fn(*args, **kwargs)
    return out, [w for w in caught if issubclass(w.category, rs.contact.PixelResolutionWarning)]


def test_the_curvature_of_the_neck_is_the_rms_mean_curvature_of_an_isotropic_map():
    """kappa = sqrt(2 m4 / 3) is the rms of (Laplacian z) / 2 on an isotropic random map: the
    group against the discrete Laplacian of the same map (an independent estimator)."""
    h = _family_map("S1", seed=3, shape=(128, 128))
    z, dx = h.values, float(h.x[1] - h.x[0])
    lap = (np.roll(z, 1, 0) + np.roll(z, -1, 0) + np.roll(z, 1, 1) + np.roll(z, -1, 1) - 4 * z) / dx**2
    kappa = np.sqrt(np.mean(lap**2)) / 2
    rh = 0.4
    expected = np.sqrt(2 * float(rs.contact.water_height(rh)) / kappa) / dx
    got = float(rs.contact.surface_groups(h, relative_humidity=rh).neck_pixels)
    assert got == pytest.approx(expected, rel=0.05)


def test_the_neck_widens_with_humidity_and_narrows_with_the_pixel():
    h = _family_map("table4")
    g = rs.contact.surface_groups(h, relative_humidity=[0.1, 0.5, 0.9]).neck_pixels.values
    assert np.all(np.diff(g) > 0)
    # 2 x 2 block means: the smoothing lowers the curvature (a wider neck in metres) by less
    # than the 4 x that would keep its count in pixels twice as large
    coarse = rs.contact.resample_pixels(h, 2)
    gc = float(rs.contact.surface_groups(coarse, relative_humidity=0.5).neck_pixels)
    assert gc < g[1]


@pytest.mark.parametrize("family, rh", [("S1", 0.05), ("S2", 1e-3), ("S1", 0.9), ("table4", 0.5)])
def test_the_warning_says_what_resolution_study_measures(family, rh):
    """Warned exactly where half the pixel moves Γ by more than 10 % (the independent
    measurement), on maps of two families at low and high humidity."""
    h = _family_map(family)
    _, said = _pixel_warnings(rs.contact.curves, h, relative_humidity=rh, model="fft_bem")
    study = rs.contact.resolution_study(h, relative_humidity=rh, factors=(0.5, 1))
    moved = abs(float(study.relative_change_adhesive_energy.isel(pixel_size=0))) > 0.1
    assert bool(said) == moved, (family, rh, float(study.relative_change_adhesive_energy[0]))
    if said:
        msg = str(said[0].message)
        # a generated map: the remedy is a finer spacing, named as the Python argument
        assert "resolution_study" in msg and "spacing=" in msg and "--resolution" not in msg


def test_every_pixel_model_is_checked_gw_is_not_and_the_note_is_kept():
    h = _family_map("S1")
    for model in ("modified_dmt", "fft_bem", "auto"):
        ds, said = _pixel_warnings(rs.contact.curves, h, relative_humidity=[0.05, 0.9], model=model)
        assert len(said) == 1, model
        assert "RH 0.05:" in str(said[0].message) and "0.9" not in str(said[0].message).split(":")[0]
        assert ds.attrs["resolution_check"].startswith("wetted necks narrower than 3 pixels")
        assert said[0].filename == __file__  # points at the user's line
    ds, said = _pixel_warnings(rs.contact.curves, h, relative_humidity=0.05, model="gw")
    assert not said and "resolution_check" not in ds.attrs
    ds, said = _pixel_warnings(rs.contact.curves, h, relative_humidity=0.9, model="fft_bem")
    assert not said and ds.attrs["resolution_check"].startswith("wetted necks span at least")
    ds, said = _pixel_warnings(rs.contact.curves, h, relative_humidity=0.05, model="fft_bem",
                               check_validity=False)
    assert not said and "resolution_check" not in ds.attrs


def test_a_stack_is_judged_by_its_worst_map_and_a_lazy_one_is_not_computed():
    smooth = _family_map("table4").values
    rough = _family_map("S1").values
    h = rs.testing.make_topography(np.stack([smooth, rough]), spacing=5e-9, periodic=True)
    h = h.rename({d: "realization" for d in h.dims if d not in ("y", "x")})
    g = rs.contact.surface_groups(h, relative_humidity=0.05).neck_pixels.values
    assert g[0] >= rs.contact.RESOLVED_NECK_PIXELS > g[1]
    _, said = _pixel_warnings(rs.contact.warn_if_unresolved, h, relative_humidity=0.05)
    assert len(said) == 1 and f"{g[1]:.1f} pixels" in str(said[0].message) and "worst of 2 maps" in str(said[0].message)
    _, said = _pixel_warnings(rs.contact.warn_if_unresolved, h.isel(realization=[0]), relative_humidity=0.05)
    assert not said
    grid = rs.contact.contact_distance_grid(h.isel(realization=1), relative_humidity=0.05)
    ds, said = _pixel_warnings(rs.contact.curves, h.chunk({"realization": 1}), relative_humidity=0.05,
                               distance=grid)
    assert not said and ds.attrs["resolution_check"].startswith("not checked (lazy input)")


def test_an_ensemble_is_warned_once_before_its_graph_from_the_psd():
    psd = rs.surface.self_affine_psd(np.geomspace(1e5, 1e10, 2000), **rs.datasets.family_parameters("S1"))
    ds, said = _pixel_warnings(rs.ensemble.run, psd, n=2, shape=(32, 32), spacing=5e-9,
                               relative_humidity=[0.05, 0.9])
    expected = rs.contact.expected_surface_groups(psd, shape=(32, 32), spacing=5e-9, relative_humidity=[0.05, 0.9])
    assert float(expected.neck_pixels[0]) < rs.contact.RESOLVED_NECK_PIXELS <= float(expected.neck_pixels[1])
    assert len(said) == 1 and "RH 0.05:" in str(said[0].message)
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.contact.PixelResolutionWarning)  # said before, never per block
        ds.compute(scheduler="sync")


def test_resolution_study_itself_does_not_warn_about_the_pixel():
    h = _family_map("S1")
    _, said = _pixel_warnings(rs.contact.resolution_study, h, relative_humidity=0.05, factors=(1, 2))
    assert not said


def test_the_check_needs_a_map_or_groups():
    with pytest.raises(ValueError, match="height= and relative_humidity=, or groups="):
        rs.contact.warn_if_unresolved(relative_humidity=0.5)
    with pytest.raises(ValueError, match="height= and relative_humidity=, or groups="):
        rs.contact.warn_if_unresolved(_family_map("S1"))
