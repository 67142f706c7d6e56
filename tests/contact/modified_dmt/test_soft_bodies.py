"""The modified DMT (Eq. 16) says when its hard-body assumption fails (soft materials), checked
against the FFT boundary-element model on the same map."""

import functools
import warnings

import numpy as np
import pytest

import roughstick as rs

RH = [0.5, 0.7]


@pytest.fixture(scope="module")
def s1():
    return rs.datasets.surface_family("S1", shape=(64, 64), seed=1)


def _gamma(curves):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.contact.CurveGridWarning)  # no equilibrium: Γ a lower bound
        return rs.contact.summary(curves).adhesive_energy.values


def test_soft_material_warns_where_it_disagrees_with_fft_bem(s1):
    soft = rs.Material(youngs_modulus=2e9, poisson_ratio=0.3, name="soft polymer")  # E* 1.1 GPa
    with pytest.warns(rs.contact.ValidityWarning) as rec:
        c = rs.contact.modified_dmt_curves(s1, relative_humidity=RH, material=soft)
    msg = " ".join(str(w.message) for w in rec)
    # names the quantity, its value and limit, that the result is not physical, and the remedy
    assert "not physical" in msg and "limit 0" in msg and "no equilibrium" in msg, msg
    assert "pressure ratio" in msg and "model='fft_bem'" in msg and "model='auto'" in msg, msg
    ref = rs.contact.fft_bem_curves(s1, relative_humidity=RH, material=soft, max_iterations=3000)
    # measured: 22× and 4.1× (Γ 0.54 vs 0.024 J/m² at RH 0.5, 0.35 vs 0.086 at RH 0.7); an
    # explicit grid retracting from 0.2 nm gives fft_bem 0.028 and 0.088 (ratios 19 and 4.0)
    assert np.all(_gamma(c) > 3 * _gamma(ref)), (_gamma(c), _gamma(ref))


def test_polysilicon_does_not_warn_and_agrees_with_fft_bem(s1):
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.contact.ValidityWarning)
        c = rs.contact.modified_dmt_curves(s1, relative_humidity=RH)
    ref = rs.contact.fft_bem_curves(s1, relative_humidity=RH)
    # measured: 1.05 and 1.03
    np.testing.assert_allclose(_gamma(c), _gamma(ref), rtol=0.15)


def test_auto_does_not_pick_the_modified_dmt_on_a_soft_material(s1):
    soft = rs.Material(youngs_modulus=2e9, poisson_ratio=0.3)
    model, _ = rs.contact.select_model(s1, relative_humidity=RH, material=soft)
    assert model in ("fft_bem", "bem")


# ------------------------------------------------------------------ maps without roughness

def _curves(h, model):
    return rs.contact.curves(h, relative_humidity=0.5, model=model)


_ENTRY_POINTS = {
    "power_spectrum": lambda h: rs.surface.power_spectrum(h),
    "roughness_moments": lambda h: rs.surface.roughness_moments(h),
    "surface_groups": lambda h: rs.contact.surface_groups(h, relative_humidity=0.5),
    "modified_dmt_curves": lambda h: rs.contact.modified_dmt_curves(h, relative_humidity=0.5),
    **{f"rough_contact_curves[{m}]": functools.partial(_curves, model=m)
       for m in ("modified_dmt", "gw", "fft_bem", "auto")},
}


def _one_pixel():
    z = np.full((32, 32), np.nan)
    z[3, 4] = 1e-9
    return z


@pytest.mark.parametrize("entry", sorted(_ENTRY_POINTS))
@pytest.mark.parametrize("values, match", [
    (np.full((32, 32), 1e-9), r"is flat \(constant \(zero variance\), rms 0 over its 1024"),
    (_one_pixel(), r"has only 1 finite pixel \(of 1024"),
])
def test_maps_without_roughness_are_refused_by_name(entry, values, match):
    # before: numpy's "divide by zero" / "Mean of empty slice" RuntimeWarnings (or a
    # ZeroDivisionError) and curves of nothing
    h = rs.testing.make_topography(values, spacing=5e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning on the way to the error
        with pytest.raises(ValueError, match=match) as err:
            _ENTRY_POINTS[entry](h)
    assert "no roughness to model" in str(err.value)


@pytest.mark.parametrize("model", ["modified_dmt", "gw", "fft_bem", "auto"])
def test_every_contact_model_needs_8_by_8_pixels(model):
    # docs: a map of at least 8 x 8 pixels; before, modified_dmt and fft_bem took 7 x 7
    rng = np.random.default_rng(0)
    h = rs.testing.make_topography(rng.normal(scale=3e-9, size=(7, 9)), spacing=5e-9)
    with pytest.raises(ValueError, match=r"7 pixel\(s\) along 'y'|only 7 pixels along 'y'") as err:
        rs.contact.curves(h, relative_humidity=0.5, model=model)
    assert "at least 8 x 8" in str(err.value)
    ok = rs.testing.make_topography(rng.normal(scale=3e-9, size=(8, 8)), spacing=5e-9)
    rs.contact.curves(ok, relative_humidity=0.5, model="fft_bem")  # 8 x 8 is taken
