"""Measured validity per surface: groups, error bounds, model choice, the warning and its remedy."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.contact.trust import validity
from roughstick.testing import make_topography


def sinusoid(n=64, spacing=5e-9, amplitude=2e-9, periods=4):
    x = np.arange(n) * spacing
    z = amplitude * np.sin(2 * np.pi * periods * x / (n * spacing))
    return make_topography(np.tile(z, (n, 1)), spacing=spacing, periodic=True)


def family_map(name, seed=7, n=128):
    return rs.datasets.surface_family(name, shape=(n, n), seed=seed)


def test_surface_groups_of_a_sinusoid_match_closed_forms():
    a, n, dx, k = 2e-9, 256, 5e-9, 8
    h = sinusoid(n, dx, a, k)
    g = rs.contact.surface_groups(h, relative_humidity=0.7)
    sigma = a / np.sqrt(2)
    assert float(g.sigma) == pytest.approx(sigma, rel=1e-9)
    q = 2 * np.pi * k / (n * dx)
    # forward differences of a sampled sine: rms slope a q sinc(q dx / 2) / sqrt 2, to the
    # O(1/n) of the one difference across the edge that a (possibly measured) map has not
    slope = a * q * np.sinc(q * dx / (2 * np.pi)) / np.sqrt(2)
    assert float(g.rms_slope) == pytest.approx(slope, rel=2 / n)
    hw, dp = float(rs.contact.water_height(0.7)), abs(float(rs.contact.laplace_pressure(0.7)))
    e_star = rs.materials.reduced_modulus()
    assert float(g.hw_over_sigma) == pytest.approx(hw / sigma, rel=1e-9)
    assert float(g.dp_over_E) == pytest.approx(dp / e_star, rel=1e-12)
    assert float(g.pressure_ratio) == pytest.approx(dp / (e_star * slope), rel=2 / n)
    # ACF of a sine is cos(q r): it drops below 1/e at r = acos(1/e)/q (to a pixel)
    r = np.arccos(np.exp(-1)) / q
    assert abs(float(g.corr_over_L) * n * dx - r) <= dx


def test_surface_groups_over_a_stack_and_humidities():
    h = xr.concat([sinusoid(periods=2), sinusoid(periods=4)], dim="realization")
    g = rs.contact.surface_groups(h, relative_humidity=[0.3, 0.9])
    assert g.pressure_ratio.dims == ("realization", "rh")
    assert float(g.rms_slope[0]) < float(g.rms_slope[1])
    # a lazy stack: its first map stands for it (one map computed, not the ensemble)
    lazy = rs.contact.surface_groups(h.chunk(realization=1), relative_humidity=[0.3, 0.9])
    assert lazy.sizes["realization"] == 1
    np.testing.assert_allclose(lazy.maugis_lambda, g.maugis_lambda.isel(realization=[0]),
                               rtol=1e-12)


@pytest.mark.parametrize("rh", [0.6, [0.3, 0.9]])
def test_the_warning_reads_the_same_groups_as_surface_groups(rh):
    # warn_if_outside_validity computes its three features without surface_groups' Dataset and
    # correlation length (the cost of the default rough_contact_curves call): same numbers,
    # for one map, a stack and a map with NaN pixels
    one = family_map("S2")
    holes = one.copy(data=np.where(np.arange(one.size).reshape(one.shape) % 97 == 0, np.nan, one.values))
    stack = xr.concat([one, family_map("table4")], dim="realization")
    for h in (one, holes, stack):
        fast = validity._group_points(h, rh, rs.POLYSILICON, None, "paper")
        ref = validity._group_points(None, rh, rs.POLYSILICON, None, "paper",
                                     groups=rs.contact.surface_groups(h, relative_humidity=rh))
        assert fast == ref


def test_the_reference_has_no_error_and_the_bound_covers_the_measured_cases():
    t = rs.contact.validity_map()
    assert validity.model_error("bem", {}).upper == 0.0
    for method in ("modified_dmt", "fft_bem"):
        sel = np.nonzero((t["method"] == method) & (t["converged"] == 1))[0][:20]
        for i in sel:
            groups = {f: t[f][i] for f in validity.GROUP_FEATURES}
            bound = validity.model_error(method, groups)
            # the case itself is among its nearest neighbours: the bound is at least its error
            assert bound.upper >= abs(t["error_adhesive_energy"][i]) - 1e-12
            assert bound.n == validity.N_NEIGHBOURS


def test_far_outside_the_measured_range_is_unbounded():
    groups = {"pressure_ratio": 1e3, "maugis_lambda": 1e3, "hw_over_sigma": 1e-4}
    b = validity.model_error("modified_dmt", groups)
    assert np.isinf(b.upper) and "outside the measured range" in b.reason


def test_select_model_is_the_cheapest_within_tolerance():
    h = family_map("smooth")
    for tol in (0.02, 0.1, 0.5):
        model, reason = rs.contact.select_model(h, relative_humidity=[0.5, 0.9], accuracy=tol)
        g = rs.contact.surface_groups(h, relative_humidity=[0.5, 0.9])
        order = [m for m in rs.contact.model_names() if rs.contact.MODELS[m].cost_rank is not None]
        worst = {m: max(validity.model_error(m, {f: float(g[f].sel(rh=r))
                                                 for f in validity.GROUP_FEATURES}).upper
                        for r in (0.5, 0.9)) for m in order}
        assert worst[model] <= tol or model == "bem"
        assert all(worst[m] > tol for m in order[: order.index(model)])
        assert model in reason


def test_auto_records_its_choice_and_stays_within_tolerance_of_the_fft_bem():
    h = family_map("smooth", n=96)
    ds = rs.contact.curves(h, relative_humidity=0.7, model="auto", accuracy=0.1)
    sel = ds.attrs["model_selection"]
    assert sel.startswith("auto -> " + ds.attrs["contact_model"])
    ref = rs.contact.summary(rs.contact.fft_bem_curves(h, relative_humidity=0.7, solver_tolerance=1e-4))
    got = rs.contact.summary(ds)
    assert float(got.adhesive_energy) == pytest.approx(float(ref.adhesive_energy), rel=0.1)


def test_warning_fires_only_above_the_bound_and_points_at_this_line():
    h = family_map("smooth")
    g = rs.contact.surface_groups(h, relative_humidity=0.7)
    bound = validity.model_error("modified_dmt", {f: float(g[f]) for f in validity.GROUP_FEATURES})
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        rs.contact.curves(h, relative_humidity=0.7, model="modified_dmt",
                          accuracy=bound.upper * 0.5 if np.isfinite(bound.upper) else 0.1)
        line = __import__("inspect").currentframe().f_lineno - 2
    hits = [w for w in rec if issubclass(w.category, rs.contact.ValidityWarning)]
    assert hits, "the measured bound exceeds the tolerance: the warning must fire"
    assert hits[0].filename == __file__ and hits[0].lineno == line
    msg = str(hits[0].message)
    # from Python the remedy is the argument (the command-line spelling is the CLI's)
    assert "roughstick.contact.curves(..., model='auto', accuracy=" in msg and "--model" not in msg
    if np.isfinite(bound.upper):
        with warnings.catch_warnings():
            warnings.simplefilter("error", rs.contact.ValidityWarning)
            rs.contact.curves(h, relative_humidity=0.7, model="modified_dmt",
                              accuracy=bound.upper * 1.01)


def test_a_lazy_stack_stays_lazy_and_says_it_was_not_checked():
    from roughstick.testing import raise_if_dask_computes

    h = family_map("smooth", n=64)
    stack = xr.concat([h, h], "realization").chunk(realization=1)
    d = float(h.max()) + np.linspace(-3e-9, 1e-9, 8)
    with warnings.catch_warnings(record=True) as rec, raise_if_dask_computes():
        warnings.simplefilter("always")
        ds = rs.contact.curves(stack, relative_humidity=0.7, distance=d, accuracy=1e-6, model="modified_dmt")
    assert not [w for w in rec if issubclass(w.category, rs.contact.ValidityWarning)]
    assert ds.attrs["validity_check"].startswith("not checked (lazy input)")
    # the check the note names works on one computed map and points at the caller's line
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        warned = rs.contact.warn_if_outside_validity(stack.isel(realization=0).compute(),
                                             relative_humidity=0.7, accuracy=1e-6)
        line = __import__("inspect").currentframe().f_lineno - 2
    hits = [w for w in rec if issubclass(w.category, rs.contact.ValidityWarning)]
    assert warned and hits and hits[0].filename == __file__ and hits[0].lineno == line


def test_the_remedy_flags_exist_on_the_command_line():
    from roughstick.cli import build_parser

    args = build_parser().parse_args(
        ["curves", "map.nc", "--rh", "0.7", "--out", "x.nc", "--model", "auto", "--accuracy",
         "0.1"])
    assert args.model == "auto" and args.accuracy == 0.1
    old = build_parser().parse_args(["curves", "map.nc", "--rh", "0.7", "--out", "x.nc", "--tolerance", "0.2"])
    assert old.accuracy == 0.2  # the flag's old name


@pytest.mark.parametrize("name", ["S1A", "S2A"])
def test_paper_samples_warn_exactly_where_the_measured_bound_exceeds_the_tolerance(name):
    h = rs.datasets.load_sample(name).isel(y=slice(0, 256), x=slice(0, 256))
    for rh in (0.3, 0.7, 0.9):
        g = rs.contact.surface_groups(h, relative_humidity=rh)
        bound = validity.model_error("modified_dmt",
                                     {f: float(g[f]) for f in validity.GROUP_FEATURES})
        with warnings.catch_warnings(record=True) as rec:
            warnings.simplefilter("always")
            ds = rs.contact.curves(h, relative_humidity=rh, n_distance=16, model="modified_dmt")
        hits = [w for w in rec if issubclass(w.category, rs.contact.ValidityWarning)]
        assert bool(hits) == (bound.upper > 0.1), (rh, bound)
        assert ds.attrs["validity_check"].startswith(
            "measured error bound " + ("above" if hits else "within"))


def test_bad_tolerance_quantity_and_nan_maps():
    h = sinusoid()
    with pytest.raises(ValueError, match="accuracy must be a positive relative error"):
        rs.contact.curves(h, relative_humidity=0.7, model="auto", accuracy=0)
    with pytest.raises(ValueError, match="accuracy"):
        rs.contact.select_model(h, relative_humidity=0.7, accuracy=-1)
    with pytest.raises(ValueError, match="quantity must be one of"):
        validity.model_error("modified_dmt", {f: 1.0 for f in validity.GROUP_FEATURES},
                             quantity="energy")
    with pytest.raises(ValueError, match="method must be one of"):
        validity.model_error("jkr", {f: 1.0 for f in validity.GROUP_FEATURES})
    z = family_map("smooth", n=64).values.copy()
    z[3, 5] = np.nan
    nan_map = make_topography(z, spacing=5e-9)
    # the boundary-element models need a complete map: auto either finds a cheaper model
    # within the tolerance or says why it cannot
    try:
        ds = rs.contact.curves(nan_map, relative_humidity=0.7, model="auto",
                                     accuracy=0.1)
    except ValueError as err:
        assert "NaN pixels" in str(err) and "crop or fill" in str(err)
    else:
        assert ds.attrs["contact_model"] in ("gw", "modified_dmt")


@pytest.mark.parametrize("z, says", [
    (np.zeros((64, 64)), r"height is flat \(constant"),
    (np.full((16, 16), 3e-9), r"height is flat \(constant"),
    (np.ones((1, 1)) * 1e-9, r"1 pixel\(s\) along 'y'.*at least 8 x 8 pixels: give a larger map"),
    (np.random.default_rng(1).normal(size=(4, 4)) * 1e-9, r"4 pixel\(s\) along 'y'.*give a larger map"),
])
def test_auto_on_a_map_without_roughness_names_the_real_problem(z, says):
    """model='auto' on a constant or tiny map (no NaN pixel) says so, not "the map has NaN pixels"."""
    with pytest.raises(ValueError, match=says) as err:
        rs.contact.curves(make_topography(z, spacing=5e-9), relative_humidity=0.5, model="auto")
    assert "NaN" not in str(err.value)


def test_expected_groups_from_the_psd_match_generated_maps():
    """The PSD-side expectation of the groups (no map generated) agrees with the mean of the
    map estimators over generated surfaces, within their sampling error."""
    psd = rs.datasets.sample_psd("S2")
    shape, spacing = (128, 128), 5e-9
    exp = rs.contact.expected_surface_groups(psd, shape=shape, spacing=spacing, relative_humidity=[0.5])
    maps = rs.generate_surfaces(psd, n=24, shape=shape, spacing=spacing, seed=3).compute()
    got = rs.contact.surface_groups(maps, relative_humidity=[0.5])
    for v in ("sigma", "rms_slope", "pressure_ratio", "maugis_lambda", "hw_over_sigma"):
        x = got[v].values.reshape(24, -1)
        mean, se = x.mean(axis=0), x.std(axis=0, ddof=1) / np.sqrt(24)
        e = np.asarray(exp[v].values).reshape(-1)
        assert np.all(np.abs(e - mean) < 4 * se + 0.01 * np.abs(mean)), (v, e, mean, se)
    assert abs(float(exp.corr_over_L) - float(got.corr_over_L.mean())) < 0.05


def test_groups_do_not_depend_on_the_units_of_the_map_coordinates():
    """The same map with x, y in nm (coordinate units 'nm') has the same groups, so the validity
    warning and model='auto' see the same surface (they used to read the raw coordinate step)."""
    h = rs.datasets.surface_family("S1", shape=(32, 32), seed=1)
    hn = h.assign_coords(x=h.x.values * 1e9, y=h.y.values * 1e9)
    hn.x.attrs["units"] = hn.y.attrs["units"] = "nm"
    a = rs.contact.surface_groups(h, relative_humidity=[0.3, 0.8])
    b = rs.contact.surface_groups(hn, relative_humidity=[0.3, 0.8])
    for v in a.data_vars:
        np.testing.assert_allclose(b[v].values, a[v].values, rtol=1e-9)


def test_the_trust_checks_of_one_call_compute_the_groups_once(monkeypatch):
    # validity note, pixel note and error budget of one curves call share the map's moments;
    # outside a call nothing is kept (a map changed in place gets new groups)
    from roughstick.contact.trust import validity as V

    h = rs.datasets.surface_family("S2", shape=(64, 64), seed=1)
    calls = []
    kernel = V._centred_moments_kernel
    monkeypatch.setattr(V, "_centred_moments_kernel", lambda *a: calls.append(1) or kernel(*a))
    c = rs.contact.curves(h, relative_humidity=[0.3, 0.9], model="modified_dmt")
    assert len(calls) == 1
    assert "model_error_bound_adhesive_energy" in c.attrs
    args = ([0.3, 0.9], rs.materials.POLYSILICON, None, "paper")
    first = V._group_points(h, *args)
    h.values[:] *= 2.0  # twice the rms height: h_water / sigma halves
    second = V._group_points(h, *args)
    assert second[0][1][0]["hw_over_sigma"] == pytest.approx(first[0][1][0]["hw_over_sigma"] / 2)
    with V.shared_groups():
        assert V._group_points(h, *args) is V._group_points(h, *args)
