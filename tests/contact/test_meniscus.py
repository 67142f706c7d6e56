"""Meniscus physics (Eqs. 1-6): Kelvin radius, Laplace pressure, meniscus height, water height."""

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick._core import constants as C
from roughstick.testing import assert_units, raise_if_dask_computes

RH = np.array([0.3, 0.5, 0.7, 0.9])


def test_kelvin_radius_table():
    # r_K = 0.53 nm / ln RH (Eq. 3), computed by hand
    expected_nm = [-0.44021, -0.76464, -1.48596, -5.03028]
    rk = rs.contact.kelvin_radius(RH)
    np.testing.assert_allclose(rk.values * 1e9, expected_nm, rtol=1e-4)
    assert_units(rk, "m")
    assert rk.dims == ("rh",)
    # from gamma V_m / (R T) instead of the printed 0.53 nm: 0.5196 nm at 300 K (Eq. 1)
    length = C.WATER_SURFACE_TENSION * C.WATER_MOLAR_VOLUME / (C.GAS_CONSTANT * 300.0)
    assert length == pytest.approx(0.5196e-9, rel=1e-3)
    np.testing.assert_allclose(rs.contact.kelvin_radius(RH, kelvin_length=None).values, length / np.log(RH), rtol=1e-12)
    # and it scales as 1/T
    r350 = rs.contact.kelvin_radius(0.5, kelvin_length=None, temperature=350.0)
    r300 = rs.contact.kelvin_radius(0.5, kelvin_length=None, temperature=300.0)
    assert float(r350 / r300) == pytest.approx(300 / 350)


def test_laplace_pressure_values():
    dp = rs.contact.laplace_pressure(RH)
    np.testing.assert_allclose(dp.values / 1e6, [-166.8, -96.05, -49.43, -14.6], rtol=2e-3)
    assert_units(dp, "Pa")
    # Eq. 2 both ways: gamma / r_K with the paper's gamma = 0.072 N/m and r_K from Eq. 1
    rk = rs.contact.kelvin_radius(RH, kelvin_length=None)
    np.testing.assert_allclose(dp.values, C.WATER_SURFACE_TENSION / rk.values, rtol=1e-12)


def test_water_heights_of_the_paper():
    h = rs.contact.water_height([0.3, 0.5, 0.7])
    np.testing.assert_allclose(h.values * 1e9, [0.880, 1.529, 4.772], atol=1e-3)
    assert_units(h, "m")
    # no adsorbed layer (Fig. 20a): only the meniscus height -2 r_K
    h0 = rs.contact.water_height([0.3, 0.5, 0.7], adsorbed_layer="none")
    np.testing.assert_allclose(h0.values, -2 * rs.contact.kelvin_radius([0.3, 0.5, 0.7]).values, rtol=1e-12)
    # the layer switches on above 65 %: 0.9 nm on each surface
    lay = rs.contact.adsorbed_layer([0.64, 0.66])
    np.testing.assert_allclose(lay.values, [0.0, 1.8e-9])


def test_contact_angles_and_subtended_angle():
    rk = float(rs.contact.kelvin_radius(0.5))
    # theta1 = theta2 = 60 deg: h_men = -r_K (cos 60 + cos 60) = -r_K
    h = rs.contact.meniscus_height(0.5, contact_angle_1=np.pi / 3, contact_angle_2=np.pi / 3)
    assert float(h) == pytest.approx(-rk)
    # degrees through a DataArray with units
    deg = xr.DataArray(60.0, attrs={"units": "deg"})
    assert float(rs.contact.meniscus_height(0.5, contact_angle_1=deg, contact_angle_2=deg)) == pytest.approx(-rk)
    # Eq. 5 with a subtended angle psi: -r_K (cos(theta1 + psi) + cos theta2)
    psi = 0.2
    h = rs.contact.meniscus_height(0.5, subtended_angle=psi)
    assert float(h) == pytest.approx(-rk * (np.cos(psi) + 1.0))
    # hydrophobic (theta > 90 deg on both): no meniscus height left (negative)
    assert float(rs.contact.meniscus_height(0.5, contact_angle_1=2.0, contact_angle_2=2.0)) < 0


def test_pluggable_adsorbed_layer():
    def linear(rh):
        return 2e-9 * rh

    h = rs.contact.water_height([0.2, 0.4], adsorbed_layer=linear)
    np.testing.assert_allclose(h.values, -2 * rs.contact.kelvin_radius([0.2, 0.4]).values + 2e-9 * np.array([0.2, 0.4]))
    custom = rs.contact.step_adsorbed_layer(thickness=0.3e-9, onset=0.3, surfaces=1)
    np.testing.assert_allclose(rs.contact.adsorbed_layer([0.2, 0.5], layer_model=custom).values, [0.0, 0.3e-9])
    with pytest.raises(ValueError, match="'paper', 'none' or a callable"):
        rs.contact.water_height(0.5, adsorbed_layer="thick")
    with pytest.raises(ValueError, match=r"thickness=-1e-09: must be a finite number >= 0"):
        rs.contact.step_adsorbed_layer(thickness=-1e-9)


def test_dataarray_broadcasting():
    rh = xr.DataArray([0.3, 0.6], dims="rh", coords={"rh": [0.3, 0.6]}, attrs={"units": "1"})
    T = xr.DataArray([280.0, 300.0, 320.0], dims="temperature", attrs={"units": "K"})
    dp = rs.contact.laplace_pressure(rh, temperature=T)
    assert dict(dp.sizes) == {"rh": 2, "temperature": 3}
    np.testing.assert_allclose(dp.transpose("rh", "temperature").values, C.GAS_CONSTANT * T.values[None, :] * np.log(rh.values)[:, None] / 18e-6)
    theta = xr.DataArray(np.deg2rad([0.0, 30.0]), dims="angle", attrs={"units": "rad"})
    h = rs.contact.water_height(rh, contact_angle_1=theta)
    assert dict(h.sizes) == {"rh": 2, "angle": 2}
    # percent input
    pct = xr.DataArray([30.0, 60.0], dims="rh", attrs={"units": "%"})
    np.testing.assert_allclose(rs.contact.laplace_pressure(pct).values, dp.isel(temperature=1).values)


def test_numpy_and_dask_agree_and_stay_lazy(backend):
    rh = xr.DataArray(np.linspace(0.05, 0.95, 12), dims="rh", attrs={"units": "1"})
    ref = {f.__name__: f(rh) for f in (rs.contact.kelvin_radius, rs.contact.laplace_pressure, rs.contact.water_height, rs.contact.meniscus_height)}
    with raise_if_dask_computes():
        got = {f.__name__: f(backend(rh, {"rh": 4})) for f in (rs.contact.kelvin_radius, rs.contact.laplace_pressure, rs.contact.water_height, rs.contact.meniscus_height)}
    for name, out in got.items():
        assert isinstance(out.data, type(backend(rh).data)), name
        xr.testing.assert_allclose(out.compute(), ref[name])


@pytest.mark.parametrize("bad, says", [
    (0.0, "0 is dry air"), (1.0, r"1 is saturation \(RH 100 %\).*at most e.g. 0.99"),
    (1.5, r"1.5 is above saturation"), (-0.2, "cannot be negative"),
    (30.0, r"did you mean 0.3\?"), (np.nan, "this is not a number")])
def test_relative_humidity_outside_unit_interval(bad, says):
    with pytest.raises(ValueError, match=says):
        rs.contact.laplace_pressure(bad)


def test_relative_humidity_errors_for_dataarrays():
    with pytest.raises(ValueError, match="no 'units' attribute"):
        rs.contact.water_height(xr.DataArray([0.5], dims="rh"))
    with pytest.raises(ValueError, match="not a dimensionless unit"):
        rs.contact.water_height(xr.DataArray([0.5], dims="rh", attrs={"units": "m"}))
    lazy = xr.DataArray([0.5, 1.5], dims="rh", attrs={"units": "1"}).chunk({"rh": 1})
    out = rs.contact.laplace_pressure(lazy)  # validated at compute time
    with pytest.raises(ValueError, match="strictly between 0 and 1"):
        out.compute()
    with pytest.raises(ValueError, match="1-D sequence or a DataArray"):
        rs.contact.kelvin_radius(np.full((2, 2), 0.5))


def test_extreme_humidities_are_finite():
    rh = np.array([0.01, 0.999])
    h = rs.contact.water_height(rh)
    assert np.all(np.isfinite(h.values)) and np.all(h.values > 0)
    assert float(h[1]) == pytest.approx(-2 * 0.53e-9 / np.log(0.999) + 1.8e-9)


def test_a_layer_model_returning_nm_is_refused_naming_it():
    """A callable returning nm (1.8 instead of 1.8e-9) gave Γ = 1.5e8 J m-2 with only a generic
    warning; now the model's output is checked before any contact work."""
    def layer_nm(rh):
        return xr.where(rh > 0.65, 1.8, 0.0)

    with pytest.raises(ValueError, match=r"adsorbed_layer model 'layer_nm' returned 1\.8 m at RH 0\.7, "
                                         r"above 1e-07 m.*almost surely returns nm.*1\.8e-9"):
        rs.contact.water_height([0.5, 0.7], adsorbed_layer=layer_nm)
    h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    for model in ("modified_dmt", "fft_bem"):
        with pytest.raises(ValueError, match="'layer_nm' returned 1.8 m"):
            rs.contact.curves(h, relative_humidity=0.7, adsorbed_layer=layer_nm, model=model)
    with pytest.raises(ValueError, match=r"returned -1e-09 m at RH 0\.5: a layer thickness must be finite and >= 0"):
        rs.contact.adsorbed_layer(0.5, layer_model=lambda rh: -1e-9 + 0 * rh)
    with pytest.raises(ValueError, match=r"returned nan m"):
        rs.contact.water_height(0.5, adsorbed_layer=lambda rh: np.nan)
    with pytest.raises(ValueError, match=r"thickness=0\.9 m is implausible.*looks like nm.*thickness=0\.9e-9"):
        rs.contact.step_adsorbed_layer(thickness=0.9)
    np.testing.assert_allclose(rs.contact.water_height(0.7, adsorbed_layer=lambda rh: 1.8e-9 + 0 * rh),
                               rs.contact.water_height(0.7))  # metres: accepted
