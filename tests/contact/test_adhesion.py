"""adhesion_summary (Eq. 13): closed forms, the sphere's adhesive energy, backends, metadata."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
import xarray as xr
from scipy import integrate

import roughstick as rs
from roughstick.contact.adhesion import adhesive_energy_kernel
from roughstick.testing import raise_if_dask_computes, sphere_topography


def curves_from(p, d, wet=None):
    p = np.asarray(p, float)
    wet = np.zeros_like(p) if wet is None else np.asarray(wet, float)
    dims = ("rh", "distance")[-p.ndim:]
    return xr.Dataset({"pressure": (dims, p), "wet_fraction": (dims, wet)}, coords={"distance": d})


def test_kernel_closed_forms():
    d = np.array([0.0, 1.0, 2.0, 3.0])
    # negative from the crossing at 0.5 to the one at 2.5: triangles 0.5 + 0.5, trapezoid 2
    p = np.array([2.0, -2.0, -2.0, 2.0])
    assert adhesive_energy_kernel(p, d) == pytest.approx(3.0)
    assert adhesive_energy_kernel(np.array([1.0, 2.0, 0.0, 5.0]), d) == 0.0
    # exact for a piecewise-linear curve, independent of where the grid points fall
    dd = np.linspace(-1, 1, 7)
    assert adhesive_energy_kernel(np.abs(dd) - 0.5, dd) == pytest.approx(0.25)


def test_summary_values_and_equilibrium():
    d = np.array([0.0, 1.0, 2.0, 3.0, 4.0]) * 1e-9
    p = np.array([[3.0, 1.0, -1.0, -0.5, 0.0], [5.0, 4.0, 3.0, 2.0, 1.0]]) * 1e6
    wet = np.array([[0.5, 0.4, 0.2, 0.1, 0.0], [0.1] * 5])
    # the second curve is repulsive over the whole grid: its equilibrium lies above it
    with pytest.warns(rs.contact.CurveGridWarning, match="still repulsive at the largest distance"):
        s = rs.contact.summary(curves_from(p, d, wet))
    np.testing.assert_allclose(s.pull_off_pressure, [1e6, 0.0])
    assert float(s.equilibrium_distance[0]) == pytest.approx(1.5e-9)
    assert float(s.wet_fraction_at_equilibrium[0]) == pytest.approx(0.3)
    assert np.isnan(s.equilibrium_distance[1]) and np.isnan(s.wet_fraction_at_equilibrium[1])
    expect = (0.5 * 1e6 * 0.5 + 0.75e6 + 0.25e6) * 1e-9
    assert float(s.adhesive_energy[0]) == pytest.approx(expect)
    assert float(s.adhesive_energy[1]) == 0.0
    # descending distance input gives the same answer
    with pytest.warns(rs.contact.CurveGridWarning, match="still repulsive"):
        s2 = rs.contact.summary(curves_from(p[:, ::-1], d[::-1], wet[:, ::-1]))
    xr.testing.assert_allclose(s, s2)


def test_sphere_adhesive_energy_matches_integral_of_eq9():
    # one finely resolved sphere: Gamma * A equals the integral of the sphere's modified DMT
    # force (Eq. 9, 10, 11) over the interference, computed independently with scipy.quad
    R, dx, rh = 300e-9, 1e-9, 0.5
    h = sphere_topography(R, n=121, spacing=dx)
    hw = float(rs.contact.water_height(rh))
    dp = float(rs.contact.laplace_pressure(rh))
    K = rs.materials.hertz_modulus()
    top = float(h.max() - h.mean())
    d = top - np.linspace(-hw - 0.2e-9, 0.3e-9, 400)
    c = rs.contact.curves(h, relative_humidity=rh, distance=d)
    gamma = float(rs.contact.summary(c).adhesive_energy) * h.size * dx * dx

    def force(delta):
        fr = K * np.sqrt(R) * max(delta, 0) ** 1.5
        a2 = R * max(delta, 0)
        c2 = R**2 - (R - delta - hw) ** 2 if delta + hw > 0 else 0.0
        return fr + dp * np.pi * (c2 - a2)

    from scipy import optimize

    eq = optimize.brentq(force, 1e-15, 5e-9)
    expect = -integrate.quad(force, -hw, eq, limit=200, points=[0.0])[0]
    assert gamma == pytest.approx(expect, rel=0.03)


def test_dask_lazy_and_metadata(backend):
    d = np.linspace(0, 4e-9, 5)
    p = np.array([[3.0, 1.0, -1.0, -0.5, 0.0]] * 4) * 1e6
    c = curves_from(p, d).assign_coords(rh=[0.3, 0.5, 0.7, 0.9])
    c = c.assign_attrs(title="t", history="x")
    inp = backend(c, {"rh": 2})
    with raise_if_dask_computes():
        s = rs.contact.summary(inp)
    assert isinstance(s.adhesive_energy.data, type(inp.pressure.data))
    s = s.compute()
    rs.testing.assert_units(s.adhesive_energy, "J m-2")
    rs.testing.assert_units(s.pull_off_pressure, "Pa")
    rs.testing.assert_units(s.equilibrium_distance, "m")
    rs.testing.assert_units(s.wet_fraction_at_equilibrium, "1")
    assert set(s.dims) == {"rh"} and "roughstick.contact.summary" in s.attrs["history"]


def test_errors():
    with pytest.raises(ValueError, match="distance"):
        rs.contact.summary(xr.Dataset({"pressure": ("x", [1.0])}))
    c = curves_from(np.zeros(6), np.arange(6.0)).chunk({"distance": 3})
    with pytest.raises(ValueError, match="chunk"):
        rs.contact.summary(c)


def _curve(values, distance):
    """Summaries of one curve along the separation path and over the whole grid."""
    p = xr.DataArray(np.asarray(values, float), dims="distance", coords={"distance": distance})
    ds = xr.Dataset({"pressure": p, "wet_fraction": xr.zeros_like(p)})
    return rs.contact.summary(ds), rs.contact.summary(ds, from_equilibrium=False)


def test_gamma_integrates_from_equilibrium_outwards():
    # repulsive at d<=1, attractive triangle between 1 and 3, zero beyond; plus a spurious
    # attractive dip deep in contact (d = -2 .. 0) that a pull-off test never visits
    # (balanced, not separated, at d = 0 and 1: an exact zero after attraction is a separated
    # state, which no equilibrium follows; see the next test)
    d = np.array([-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0])
    p = np.array([5.0, 0.0, -4.0, 0.0, 1e-12, -2.0, 0.0, 0.0])
    sep, whole = _curve(p, d)
    # separation path: equilibrium at d = 1 (p >= 0 below, < 0 above); Gamma = 1/2 * 2 * 2 = 2
    assert float(sep.equilibrium_distance) == pytest.approx(1.0)
    assert float(sep.adhesive_energy) == pytest.approx(2.0)
    assert float(sep.pull_off_pressure) == pytest.approx(2.0)
    # the literal Eq. 13 over the whole grid adds the deep dip: 1/2 * 2 * 4 = 4 more
    assert float(whole.adhesive_energy) == pytest.approx(6.0)
    assert float(sep.attraction_below_equilibrium) == pytest.approx(4.0)
    assert float(whole.attraction_below_equilibrium) == pytest.approx(4.0)
    assert sep.attrs["adhesive_energy_range"] == "from_equilibrium"


def test_a_neck_caught_again_after_separation_is_not_an_equilibrium():
    """A 128² S2 map at RH 1e-4 (benchmarks/fft_bem_neck_break.py): the FFT-BEM's automatic grid
    held a one-pixel neck a little beyond where its finer steps let go, so exactly zero pressure
    (separated) came before one more attractive state. Taken for the equilibrium, it left Γ at
    0.75 % of the curve's."""
    d = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    p = np.array([3.0, -1.0, -2.0, 0.0, -2.0, 0.0, 0.0])
    sep, _ = _curve(p, d)
    assert float(sep.equilibrium_distance) == pytest.approx(0.75)
    # a triangle from d_eq = 0.75 to 1, then trapezoids to 5 (the old rule: d_eq = 3, Γ = 2)
    expected = 0.5 * 0.25 * 1 + 1.5 + 1.0 + 1.0 + 1.0
    assert float(sep.adhesive_energy) == pytest.approx(expected)


def test_gamma_without_equilibrium_is_whole_grid_lower_bound():
    d = np.array([0.0, 1.0, 2.0])
    with pytest.warns(rs.contact.CurveGridWarning, match="never repulsive"):
        sep, whole = _curve([-1.0, -1.0, 0.0], d)
    assert np.isnan(float(sep.equilibrium_distance))
    assert float(sep.adhesive_energy) == pytest.approx(float(whole.adhesive_energy)) == pytest.approx(1.5)


# --- grids that do not span what Eq. 13 integrates (issue 16 item 11) -----------------------
def _sphere_curves(distance):
    h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    return rs.contact.curves(h, relative_humidity=0.5, distance=distance,
                                   check_validity=False)


def test_grid_above_the_surface_warns_that_gamma_zero_means_nothing():
    h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    top = float((h - h.mean()).max())
    curves = _sphere_curves(np.linspace(top + 5e-9, top + 20e-9, 16))
    assert float(np.abs(curves.pressure).max()) == 0.0
    with pytest.warns(rs.contact.CurveGridWarning, match="zero at every distance"):
        s = rs.contact.summary(curves)
    assert float(s.adhesive_energy) == 0.0


def test_grid_stopping_before_separation_warns():
    full = _sphere_curves(None)  # the automatic grid spans equilibrium to separation
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.contact.CurveGridWarning)
        whole = rs.contact.summary(full)
    p = full.pressure.values
    k_eq = int(np.nonzero((p[:-1] >= 0) & (p[1:] < 0))[0][-1])
    cut = full.isel(distance=slice(0, k_eq + 4))
    with pytest.warns(rs.contact.CurveGridWarning, match="still attractive at the largest distance"):
        part = rs.contact.summary(cut)
    assert float(part.adhesive_energy) < float(whole.adhesive_energy)


def test_grid_inside_the_adhesive_range_warns_lower_bound():
    full = _sphere_curves(None)
    p = full.pressure.values
    k_eq = int(np.nonzero((p[:-1] >= 0) & (p[1:] < 0))[0][-1])
    inside = full.isel(distance=slice(k_eq + 2, None))
    with pytest.warns(rs.contact.CurveGridWarning, match="never repulsive"):
        s = rs.contact.summary(inside)
    assert np.isnan(float(s.equilibrium_distance))


def test_infinite_pixels_are_refused_with_the_fix():
    h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    h[5, 7] = np.inf
    with pytest.raises(ValueError, match=r"1 infinite pixel.*y index 5, x index 7.*NaN"):
        rs.contact.curves(h, relative_humidity=0.5)
    h[5, 7] = -np.inf
    with pytest.raises(ValueError, match="infinite"):
        rs.contact.curves(h, relative_humidity=0.5, model="gw")


def test_grid_below_the_equilibrium_warns_that_gamma_zero_means_nothing():
    # a grid entirely in contact (repulsive everywhere): no equilibrium, Γ = 0, yet the curve
    # above the grid is adhesive
    full = _sphere_curves(None)
    whole = rs.contact.summary(full)
    p = full.pressure.values
    k_eq = int(np.nonzero((p[:-1] >= 0) & (p[1:] < 0))[0][-1])
    below = full.isel(distance=slice(0, k_eq))
    assert float(below.pressure.min()) >= 0.0
    with pytest.warns(rs.contact.CurveGridWarning, match="still repulsive at the largest distance"):
        s = rs.contact.summary(below)
    assert np.isnan(float(s.equilibrium_distance)) and float(whole.adhesive_energy) > 0


def _grid_warning(curves):
    with pytest.warns(rs.contact.CurveGridWarning) as record:
        rs.contact.summary(curves)
    return " ".join(str(w.message) for w in record if issubclass(w.category, rs.contact.CurveGridWarning))


_S1 = rs.datasets.surface_family("S1", shape=(64, 64), seed=1)


@pytest.mark.parametrize(
    "height, kwargs",
    [
        (_S1 * (0.1e-9 / float(_S1.std())), {}),  # rms 0.1 nm: the flat touches every pixel
        (_S1, dict(material=rs.Material(youngs_modulus=1e9, poisson_ratio=0.3))),  # soft
    ],
    ids=["rms_0.1nm", "soft"],
)
def test_grid_warning_on_automatic_grid_does_not_advise_the_automatic_grid(height, kwargs):
    # the flat is pulled past the mean plane: the modified DMT says its curves are not physical
    # (a constant map is refused: tests/contact/test_rough_soft.py)
    with pytest.warns(rs.contact.ValidityWarning, match="not physical"):
        c = rs.contact.curves(height, relative_humidity=[0.3, 0.9], check_validity=False,
                                    **kwargs)
    assert c.attrs["distance_grid"] == "automatic"
    s = rs.contact.summary(c, check_grid=False)
    bad = s.rh.values[np.isnan(s.equilibrium_distance.values)]
    assert bad.size  # these surfaces collapse into contact at some humidity
    msg = _grid_warning(c)
    assert "distance=None" not in msg  # the curves were already on the automatic grid
    assert "outside its range" in msg and "distance=np.linspace(" in msg
    named = re.search(r"never repulsive at RH ([0-9.e, -]+):", msg).group(1)
    assert [float(v) for v in named.split(", ")] == pytest.approx(list(bad))  # only those


def test_grid_warning_on_given_grid_advises_the_automatic_grid():
    h = sphere_topography(200e-9, n=33, spacing=2e-9)
    full = rs.contact.curves(h, relative_humidity=[0.5, 0.7], check_validity=False)
    p = full.pressure.sel(rh=0.5).values
    k_eq = int(np.nonzero((p[:-1] >= 0) & (p[1:] < 0))[0][-1])
    given = rs.contact.curves(h, relative_humidity=[0.5, 0.7], check_validity=False,
                                    distance=full.distance.values[k_eq + 2:])
    assert given.attrs["distance_grid"] == "given"
    msg = _grid_warning(given)
    assert "never repulsive at RH 0.5" in msg and "distance=None" in msg
    # curves of unknown origin (hand-made) get both remedies
    bare = given.copy()
    del bare.attrs["distance_grid"]
    msg = _grid_warning(bare)
    assert "If the distances were given" in msg and "If they were automatic" in msg
