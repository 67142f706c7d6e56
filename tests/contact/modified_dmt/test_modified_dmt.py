"""Public layer of the rough-surface modified DMT: physics checks, backends, metadata, errors."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from scipy import ndimage

import roughstick as rs
from roughstick.testing import make_topography, raise_if_dask_computes, sphere_topography

RH6 = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]


def s1_like(shape=(64, 64), seed=0, periodic=True):
    rng = np.random.default_rng(seed)
    z = ndimage.gaussian_filter(rng.standard_normal(shape), 4, mode="wrap")
    return make_topography(z / z.std() * 4e-9, spacing=5e-9, periodic=periodic)


def sphere_mdmt(delta, R, K, hw, dp):
    """Modified DMT of one sphere (Eq. 9 with Hertz, Eqs. 10-11), written independently."""
    delta = np.asarray(delta, float)
    fr = np.where(delta > 0, K * np.sqrt(R) * np.clip(delta, 0, None) ** 1.5, 0.0)
    a2 = np.where(delta > 0, R * np.clip(delta, 0, None), 0.0)
    c2 = np.where(delta + hw > 0, R**2 - (R - delta - hw) ** 2, 0.0)
    return fr + dp * np.pi * (c2 - a2)


def test_single_sphere_reproduces_sphere_modified_dmt():
    R, dx = 500e-9, 1e-9
    h = sphere_topography(R, n=141, spacing=dx)
    K = rs.materials.hertz_modulus()
    top = float(h.max() - h.mean())
    d = top - np.linspace(-1.0e-9, 2.5e-9, 15)
    ds = rs.contact.curves(h, relative_humidity=[0.5, 0.7], distance=d)
    area = h.size * dx * dx
    for rh in (0.5, 0.7):
        sub = ds.sel(rh=rh)
        delta = sub.max_interference.values
        expect = sphere_mdmt(delta, R, K, float(sub.water_height), float(sub.laplace_pressure))
        got = sub.pressure.values * area
        # pixel discretisation of the footprints (1 nm pixels, radii 20-70 px): within 2 %
        scale = np.abs(expect).max()
        np.testing.assert_allclose(got, expect, atol=0.02 * scale)
        # the repulsive part alone, where it is sizeable
        rep = np.where(delta > 0, K * np.sqrt(R) * np.clip(delta, 0, None) ** 1.5, 0)
        big = rep > 0.2 * rep.max()
        np.testing.assert_allclose(sub.repulsive_pressure.values[big] * area, rep[big], rtol=0.03)
    assert set(np.unique(ds.n_contacts.values)) <= {0.0, 1.0}


def test_pressure_bounded_by_laplace_pressure_and_saturation():
    # the water term can never pull harder than Delta P on the whole map (saturation, §3.4.2)
    h = s1_like()
    ds = rs.contact.curves(h, relative_humidity=RH6, n_distance=120)
    assert bool((ds.pressure >= ds.laplace_pressure * (1 + 1e-12)).all())
    assert bool(((ds.wet_fraction >= 0) & (ds.wet_fraction <= 1)).all())
    # far above the surface: nothing; pressure is zero at the top of the grid
    np.testing.assert_array_equal(ds.pressure.isel(distance=-1).values, 0.0)


def test_adhesive_energy_converges_with_grid():
    h = s1_like((48, 48), seed=1)
    auto = rs.contact.curves(h, relative_humidity=[0.3, 0.9])
    lo, hi = float(auto.distance.min()), float(auto.distance.max())
    gammas = []
    for n in (50, 100, 200, 400, 800):
        c = rs.contact.curves(h, relative_humidity=[0.3, 0.9], distance=np.linspace(lo, hi, n))
        gammas.append(rs.contact.summary(c).adhesive_energy.values)
    g = np.array(gammas)
    err = np.abs(g[:-1] - g[-1]) / g[-1]
    assert np.all(err[-1] < 0.02)
    assert np.all(err[2] < err[0])  # refining reduces the error
    # the automatic grid (refined where the curve turns) is within 1 % of itself with every
    # interval split in four (a uniform grid of the same span converges more slowly: the 800-point
    # one is itself ~1 % off on this 48^2 staircase)
    ga = rs.contact.summary(auto).adhesive_energy.values
    d = auto.distance.values
    d4 = np.unique(np.concatenate([d, (d[:-1, None] + np.diff(d)[:, None] * [0.25, 0.5, 0.75]).ravel()]))
    fine = rs.contact.curves(h, relative_humidity=[0.3, 0.9], distance=d4)
    g4 = rs.contact.summary(fine).adhesive_energy.values
    assert np.all(np.abs(ga - g4) / g4 < 0.01)


@pytest.mark.parametrize("sample", ["S1A", "S2A"])
def test_fit_error_below_unit_cell_where_attractive(sample):
    h = rs.datasets.load_sample(sample).isel(x=slice(0, 256), y=slice(0, 256))
    ds = rs.contact.curves(h, relative_humidity=[0.3, 0.5, 0.7, 0.8], n_distance=120)
    att = ds.pressure < 0
    es = ds.fit_error.where(att & (ds.n_contacts > 0))
    # Eq. 23 error below the silicon unit cell and well below the interference (Fig. 8c-d).
    # Measured on these 256^2 crops (RH <= 80 %): max E^S 0.11 nm (S1A), 0.53 nm (S2A); E^S /
    # delta_max <= 0.11 (S1A), 0.24 (S2A) where delta_max > 0.5 nm. At RH 90 % on S1A the
    # deepest attractive states reach E^S = 0.548 nm, just above the unit cell (docs).
    assert float(es.max()) < rs.constants.SILICON_UNIT_CELL
    dm = ds.max_interference.where(att & (ds.max_interference > 0.5e-9))
    ratio = (es / dm).where(dm.notnull() & es.notnull())
    assert int(ratio.notnull().sum()) > 20
    assert float(ratio.max()) < 0.3


def test_numpy_dask_and_leading_dims(backend):
    maps = xr.concat([s1_like((32, 40), seed=s) for s in range(3)], dim="realization")
    maps = maps.assign_coords(realization=np.arange(3))
    maps.attrs = {**s1_like((4, 4)).attrs}
    d = np.linspace(-2e-9, 14e-9, 25)
    inp = backend(maps, {"realization": 1})
    with raise_if_dask_computes():
        ds = rs.contact.curves(inp, relative_humidity=[0.4, 0.8], distance=d)
    assert ds.pressure.dims == ("realization", "rh", "distance")
    assert isinstance(ds.pressure.data, type(inp.data))
    ds = ds.compute()
    one = rs.contact.curves(maps.isel(realization=2), relative_humidity=[0.4, 0.8], distance=d)
    xr.testing.assert_allclose(ds.isel(realization=2), one, rtol=1e-12)


def test_chunked_core_dims_raise():
    h = s1_like((32, 32)).chunk({"x": 16})
    with pytest.raises(ValueError, match=r'\.chunk\(\{.x.: -1\}\)'):
        rs.contact.curves(h, relative_humidity=0.5, distance=[0.0, 1e-9])


def test_metadata_and_scalar_rh():
    h = s1_like((32, 32))
    ds = rs.contact.curves(h, relative_humidity=0.5, distance=[3e-9, 0.0, 1e-9])
    np.testing.assert_array_equal(ds.distance.values, [0.0, 1e-9, 3e-9])  # stored ascending
    assert "rh" not in ds.dims and float(ds.rh) == 0.5
    for name, units in [("pressure", "Pa"), ("repulsive_pressure", "Pa"), ("wet_fraction", "1"),
                        ("contact_fraction", "1"), ("n_contacts", "1"), ("fit_error", "m"),
                        ("max_interference", "m")]:
        rs.testing.assert_units(ds[name], units)
        assert ds[name].attrs["long_name"] == rs.conventions.ATTRS[name]["long_name"]
    assert ds.attrs["Conventions"] == "CF-1.10" and ds.attrs["contact_model"] == "modified_dmt"
    assert "roughstick.contact.curves" in ds.attrs["history"] and "doi" in ds.attrs["references"]
    assert ds.attrs["periodic"] == 1


def test_nan_pixels_documented_and_finite():
    h = s1_like((40, 40))
    h[10:12, :] = np.nan
    ds = rs.contact.curves(h, relative_humidity=[0.3, 0.9], n_distance=60)
    assert bool(np.isfinite(ds.pressure).all())
    assert "NaN pixels are excluded" in ds.attrs["history"]


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(relative_humidity=1.2), "between 0 and 1"),
        (dict(relative_humidity=0.5, distance=[1e-9, 1e-9]), "repeated"),
        (dict(relative_humidity=0.5, distance=[np.nan]), "finite"),
        (dict(relative_humidity=0.5, connectivity=6), "connectivity"),
        (dict(relative_humidity=0.5, model="jkr"), "model"),
    ],
)
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        rs.contact.curves(s1_like((16, 16)), **kwargs)


def test_bad_maps():
    with pytest.raises(ValueError, match="no finite pixel"):
        rs.contact.curves(make_topography(np.full((8, 8), np.nan)), relative_humidity=0.5)
    with pytest.raises(ValueError, match="at least 8 x 8"):
        rs.contact.curves(make_topography(np.zeros((2, 8))), relative_humidity=0.5)
    h = s1_like((8, 8))
    h = h.assign_coords(x=h.x.values ** 1.1)
    with pytest.raises(ValueError, match="uniform"):
        rs.contact.curves(h, relative_humidity=0.5, distance=[0.0])
    stack = xr.concat([s1_like((8, 8))] * 2, "realization")
    with pytest.raises(ValueError, match="distance= explicitly"):
        rs.contact.curves(stack, relative_humidity=0.5)
    with pytest.raises(ValueError, match="model"):
        rs.contact.curves(s1_like((8, 8)), relative_humidity=0.5, model="no_such_model")


def test_model_auto_records_its_choice_and_runs_the_chosen_model():
    # A loose tolerance is met by the cheapest adequate model, a strict one only by the BEM;
    # either way "auto" must say what it chose and return exactly that model's curves.
    h = s1_like((24, 24))
    d = np.linspace(float(h.max()) - 2e-9, float(h.max()) + 3e-9, 11)
    for tolerance in (10.0, 1e-6):
        chosen, _ = rs.contact.select_model(h, accuracy=tolerance, relative_humidity=0.9)
        if chosen == "bem":
            pytest.importorskip("tamaas")
        auto = rs.contact.curves(
            h, relative_humidity=0.9, distance=d, model="auto", accuracy=tolerance
        )
        assert auto.attrs["model_selection"].startswith(f"auto -> {chosen}:")
        if chosen == "bem":
            ref = rs.contact.bem_curves(h, relative_humidity=0.9, distance=d)
        else:
            ref = rs.contact.curves(h, relative_humidity=0.9, distance=d, model=chosen)
        xr.testing.assert_allclose(auto.pressure, ref.pressure)
    assert rs.contact.select_model(h, accuracy=1e-6, relative_humidity=0.9)[0] == "bem"
    assert rs.contact.select_model(h, accuracy=10.0, relative_humidity=0.9)[0] in ("gw", "modified_dmt")


def test_nanometre_input_is_converted():
    h = s1_like((24, 24))
    nm = h * 1e9
    nm.attrs = {**h.attrs, "units": "nm"}
    d = [0.0, 2e-9]
    a = rs.contact.curves(h, relative_humidity=0.5, distance=d)
    b = rs.contact.curves(nm, relative_humidity=0.5, distance=d)
    # nm -> m rounds the heights in the last bit; the fastmath sphere fits (Eq. 21) guarantee 1e-6
    xr.testing.assert_allclose(a.pressure, b.pressure, rtol=1e-6)


def test_gw_forwarding():
    h = s1_like((64, 64))
    d = np.linspace(0, 16e-9, 17)
    ds = rs.contact.curves(h, relative_humidity=[0.3, 0.9], distance=d, model="gw")
    assert ds.pressure.dims[-2:] == ("rh", "distance")
    np.testing.assert_allclose(ds.distance.values, d)


def test_plots_smoke():
    import matplotlib.pyplot as plt

    from roughstick.plotting.rough_contact import (
        plot_adhesion_vs_rh,
        plot_fit_error,
        plot_mdmt_vs_gw,
        plot_rough_curves,
    )

    c = rs.contact.curves(s1_like((48, 48)), relative_humidity=[0.3, 0.9], n_distance=60)
    ax = plot_rough_curves(c)
    assert len(ax.lines) == 3  # two curves and the zero line
    plot_fit_error(c, rh=0.9)
    plot_adhesion_vs_rh({"a": rs.contact.summary(c)})
    fig = plot_mdmt_vs_gw({"a": c}, None, rh=(0.3, 0.9))
    assert len(fig.axes) == 2
    plt.close("all")


# --- the automatic grid is strictly increasing for every requested size -------------------
@pytest.mark.parametrize("family", ["S1", "S2", "table4", "smooth", "rough"])
def test_automatic_grid_strictly_increasing_for_any_n(family):
    # the controller bisects sign changes down to adjacent floats; splitting such an interval
    # for n= used to repeat a distance (S1 64x64 seed 1, n=100: 100 values, 99 distinct)
    for seed in (0, 1):
        h = rs.datasets.surface_family(family, shape=(64, 64), seed=seed)
        for n in (None, 10, 64, 100, 101, 257):
            for rh in ([0.3], [0.3, 0.9]):
                d = rs.contact.contact_distance_grid(h, relative_humidity=rh, n=n).values
                assert np.all(np.diff(d) > 0), (family, seed, n, rh)
                assert n is None or d.size >= n


def test_automatic_grid_of_n_points_feeds_every_model():
    h = rs.datasets.surface_family("S1", shape=(64, 64), seed=1)
    c = rs.contact.curves(h, relative_humidity=[0.3], n_distance=100, check_validity=False)
    assert c.sizes["distance"] >= 100 and np.all(np.diff(c.distance.values) > 0)
    assert c.attrs["distance_grid"] == "automatic"
    g = rs.contact.curves(h, relative_humidity=[0.3], model="gw", n_distance=100)
    assert g.sizes["distance"] >= 100 and np.all(np.diff(g.distance.values) > 0)
    given = rs.contact.modified_dmt_curves(h, relative_humidity=0.3, distance=c.distance.values[::3])
    assert given.attrs["distance_grid"] == "given"
