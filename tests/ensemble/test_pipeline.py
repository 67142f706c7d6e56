"""Tests of roughstick.ensemble.pipeline and run: laziness, chunk invariance, distance grid, the real pipeline (the section 4.3 findings)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr
from ensemble_toys import (
    RH,
    TOY,
    assert_same_values,
    toy_curves,
    toy_generate,
    toy_psd,
    toy_run,
)

import roughstick as rs
from roughstick._core.dask import is_lazy
from roughstick.testing import raise_if_dask_computes

RH6 = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]


@pytest.fixture(scope="module")
def sample_psds():
    return {s: rs.datasets.sample_psd(s) for s in ("S1", "S2")}


def _findings(psd, n, seed):
    ds = rs.ensemble.surface_size_study(psd, shapes=[128, 256], spacing=5e-9, n=n, relative_humidity=[0.3, 0.9],
                               seed=seed, chunks=8, model="modified_dmt").compute()  # the paper's
    g = ds.adhesive_energy
    mean, sd = g.mean("realization"), g.std("realization", ddof=1)
    cv = sd / mean
    lo, hi = 0.3, 0.9
    small, large = 128 * 5e-9, 256 * 5e-9
    # scatter (relative) larger at low RH than at high RH, at both sizes
    assert (cv.sel(rh=lo) > 1.5 * cv.sel(rh=hi)).all(), cv.values
    # larger surfaces: lower mean Γ at low RH, by several standard errors
    se = np.hypot(sd.sel(rh=lo, surface_size=small), sd.sel(rh=lo, surface_size=large)) / np.sqrt(n)
    drop = mean.sel(rh=lo, surface_size=small) - mean.sel(rh=lo, surface_size=large)
    assert drop > 3 * se, (float(drop), float(se))
    # larger surfaces: narrower band (standard deviation) at high RH
    assert sd.sel(rh=hi, surface_size=large) < 0.8 * sd.sel(rh=hi, surface_size=small), sd.values


def test_lazy_nothing_computed_and_layout():
    with raise_if_dask_computes():
        ds = toy_run(n=7, chunks=3)
    assert is_lazy(ds)
    assert ds["pressure"].dims == ("realization", "rh", "distance")
    assert ds["adhesive_energy"].dims == ("realization", "rh")
    assert ds["max_height"].dims == ("realization",)
    assert ds.chunksizes["realization"] == (3, 3, 1)
    assert ds.chunksizes["rh"] == (4,)
    assert ds.chunksizes["distance"] == (ds.sizes["distance"],) and ds.sizes["distance"] >= 100
    for name in list(ds.variables):
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs, name
    assert ds.attrs["Conventions"] == "CF-1.10"
    assert ds.attrs["seed"] == "3" and ds.attrs["n_realizations"] == 7
    np.testing.assert_array_equal(ds.rh.values, RH)


def test_results_independent_of_chunking_and_equal_to_single_realization():
    a = toy_run(n=6, chunks=2).compute()
    b = toy_run(n=6, chunks=4).compute(scheduler="sync")
    assert_same_values(a, b)
    # humidity blocks: the same numbers up to rounding (the curves function sees fewer humidities)
    c = toy_run(n=6, chunks={"realization": 4, "rh": 1}).compute()
    assert c.chunksizes == {} and toy_run(n=6, chunks={"realization": 4, "rh": 1}).chunksizes["rh"] == (1,) * 4
    xr.testing.assert_allclose(a.reset_coords(drop=True), c.reset_coords(drop=True), rtol=1e-13)
    # realization 4 on its own, directly from the stand-in functions
    h = toy_generate(toy_psd(), n=5, shape=(16, 16), spacing=5e-9,
                     seed=np.random.SeedSequence(3)).isel(realization=[4]).compute()
    c = toy_curves(h, relative_humidity=RH, distance=a.distance)
    np.testing.assert_array_equal(c.pressure.values[0], a.pressure.sel(realization=4).values)
    np.testing.assert_allclose(a.max_height.values[4], float(h.max() - h.mean()), rtol=1e-15)


def test_rh_chunk_blocks_and_seed_changes_results():
    a = toy_run(n=3, chunks=1, seed=1).compute()
    b = toy_run(n=3, chunks=1, seed=2).compute()
    assert not np.array_equal(a.pressure.values, b.pressure.values)


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"n": 0}, "at least 1"),
        ({"n": -3}, "at least 1"),
        ({"n": "many"}, "positive integer or 'auto'"),
        ({"n": 2.5}, "positive integer"),
        ({"rh": []}, "relative_humidity is empty"),
        ({"rh": [0.3, 1.2]}, "between 0 and 1"),
        ({"rh": [0.3, 0.3]}, "repeated"),
        ({"chunks": 0}, "chunks must be positive"),
    ],
)
def test_bad_input(kw, match):
    with pytest.raises(ValueError, match=match):
        toy_run(**{"n": 4, **kw})


def test_material_by_name_or_refused_naming_the_names():
    """run_ensemble(material="silicon") raised AttributeError ('str' object has no attribute
    'poisson_ratio') from deep inside the validity check."""
    with pytest.raises(ValueError, match=r"material='silicon' is not a material roughstick knows; known "
                                         r"names: 'poly-silicon'.*roughstick.Material\(youngs_modulus="):
        rs.ensemble.run(rs.datasets.sample_psd("S2"), n=2, shape=32, spacing=5e-9, relative_humidity=[0.5],
                        material="silicon", model="modified_dmt")
    with pytest.raises(TypeError, match="must be a roughstick.Material or a known name"):
        toy_run(n=2, material=164e9)
    named, default = toy_run(n=2, material="poly-Si"), toy_run(n=2)
    assert named.attrs["material"] == default.attrs["material"] == repr(rs.POLYSILICON)
    assert rs.materials.reduced_modulus("polysilicon") == rs.materials.reduced_modulus(rs.POLYSILICON)


def test_lengths_with_their_unit_everywhere():
    """spacing="5 nm" worked in read_afm, the CLI and TOML but run_ensemble and
    generate_surfaces raised "could not convert string to float": one parser for lengths."""
    psd = rs.datasets.sample_psd("S2")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the validity and pixel warnings of this small run
        with_units = rs.ensemble.run(psd, n=2, size="0.32 um", spacing="5 nm", relative_humidity=[0.5], seed=1, model="modified_dmt")
        in_m = rs.ensemble.run(psd, n=2, size=0.32e-6, spacing=5e-9, relative_humidity=[0.5], seed=1, model="modified_dmt")
    assert with_units.attrs["params_hash"] == in_m.attrs["params_hash"]
    assert with_units.sizes == in_m.sizes and with_units.attrs["surface_shape"] == in_m.attrs["surface_shape"]
    a = rs.surface.generate_surfaces(psd, n=1, shape=32, spacing="5 nm", seed=3)
    b = rs.surface.generate_surfaces(psd, n=1, size="160 nm", spacing=5e-9, seed=3)
    np.testing.assert_array_equal(a.values, b.values)
    xr.testing.assert_identical(rs.contact.expected_surface_groups(psd, shape=32, spacing="5 nm", relative_humidity=0.5),
                                rs.contact.expected_surface_groups(psd, shape=32, spacing=5e-9, relative_humidity=0.5))
    h = rs.testing.sphere_topography("200 nm", n=17, spacing="2 nm")  # 200 * 1e-9: 1 ulp from 200e-9
    xr.testing.assert_allclose(h, rs.testing.sphere_topography(200e-9, n=17, spacing=2e-9), rtol=1e-14)
    f = rs.contact.sphere_force([1e-9], model="dmt", radius="200 nm", relative_humidity=0.5)
    xr.testing.assert_allclose(f, rs.contact.sphere_force([1e-9], model="dmt", radius=200e-9, relative_humidity=0.5),
                               rtol=1e-14)
    with pytest.raises(ValueError, match=r"spacing = '2 parsecs': unknown length unit"):
        rs.ensemble.run(psd, n=2, shape=32, spacing="2 parsecs", relative_humidity=[0.5], model="modified_dmt")
    with pytest.raises(ValueError, match=r"spacing\[y\] must be positive and finite, got -2e-09"):
        rs.surface.generate_surfaces(psd, n=1, shape=32, spacing="-2 nm")


def test_bad_shapes():
    with pytest.raises(ValueError, match="exactly one of shape"):
        rs.ensemble.run(toy_psd(), n=2, shape=16, size=1e-6, spacing=5e-9, relative_humidity=RH, **TOY)
    with pytest.raises(ValueError, match="whole number of pixels"):
        rs.ensemble.run(toy_psd(), n=2, size=1.003e-7, spacing=5e-9, relative_humidity=RH, **TOY)
    with pytest.raises(ValueError, match="shape"):
        rs.ensemble.run(toy_psd(), n=2, shape=(2, 16), spacing=5e-9, relative_humidity=RH, **TOY)
    with pytest.raises(TypeError, match="DataArray"):
        rs.ensemble.run(np.ones((4, 4)), n=2, shape=16, spacing=5e-9, relative_humidity=RH, **TOY)


def test_distance_grid_covers_highest_point_and_bottom_check():
    ds = toy_run(n=6).compute()
    top = float(ds.max_height.max()) + float(rs.contact.water_height(max(RH)))
    assert top < float(ds.distance.max())
    # every curve crosses from attractive to repulsive on the grid
    assert bool((ds.pressure.isel(distance=0) > 0).all())
    assert not bool(ds.grid_extension.any())
    # a grid too short at either end extends itself per realization (flagged), and the summaries
    # equal those of a run on a grid long enough from the start
    d_ok = ds.distance.values
    short = toy_run(n=6, distance=d_ok[(d_ok > 0.5 * (d_ok[0] + d_ok[-1]))]).compute()
    assert bool((short.grid_extension & 1).any())
    low = toy_run(n=6, distance=d_ok[d_ok < float(ds.max_height.min())]).compute()
    assert bool((low.grid_extension & 2).all())
    for run in (short, low):
        np.testing.assert_allclose(run.equilibrium_distance, ds.equilibrium_distance, rtol=2e-2)
        # the added levels are the grid's step shifted by a fraction of it; the toy's 16 x 16
        # wetted area is a staircase, so Γ moves by O(step): ~5 % measured, 10 % allowed
        np.testing.assert_allclose(run.adhesive_energy, ds.adhesive_energy, rtol=0.1)


def test_gamma_converges_with_distance_grid_toy():
    """Γ (Eq. 13) on distance_grid: the error against a 3200-point grid shrinks with n_distance.

    The toy's wetted area is a step function of d (16 x 16 pixels), so convergence is O(step).
    """
    g = {}
    for num in (100, 400, 1600, 3200):
        d = rs.ensemble.distance_grid(toy_psd(), shape=(16, 16), n=4, relative_humidity=RH, n_distance=num)
        g[num] = toy_run(n=4, distance=d).adhesive_energy.values
    err = {k: np.mean(np.abs(g[k] / g[3200] - 1)) for k in (100, 400, 1600)}
    assert err[1600] < err[400] < err[100]
    assert err[1600] < 0.01


def test_surface_size_study_shares_grid():
    ds = rs.ensemble.surface_size_study(toy_psd(), shapes=[(16, 16), (32, 32)], spacing=5e-9, n=3,
                               relative_humidity=RH, chunks=3, **TOY)
    assert ds.adhesive_energy.dims == ("surface_size", "realization", "rh")
    np.testing.assert_allclose(ds.surface_size.values, [80e-9, 160e-9])
    assert ds.surface_size.attrs["units"] == "m"
    ds = ds.compute()
    assert np.isfinite(ds.adhesive_energy.values).all()


def test_real_pipeline_layout_and_single_realization(sample_psds):
    psd = sample_psds["S2"]
    with raise_if_dask_computes():
        ds = rs.ensemble.run(psd, n=3, shape=64, spacing=5e-9, relative_humidity=RH6, seed=9, chunks=2, model="modified_dmt")
    for v in ("pressure", "wet_fraction", "contact_fraction", "n_contacts", "fit_error"):
        assert ds[v].dims == ("realization", "rh", "distance"), v
    for v in ("adhesive_energy", "pull_off_pressure", "equilibrium_distance"):
        assert ds[v].dims == ("realization", "rh"), v
    ds = ds.compute()
    # realization 2 regenerated alone and run through the public functions directly
    h = rs.surface.generate_surfaces(psd, realizations=[2], shape=64, spacing=5e-9, seed=9).compute()
    c = rs.contact.curves(h, relative_humidity=RH6, distance=ds.distance, model="modified_dmt")
    s = rs.contact.summary(c)
    np.testing.assert_array_equal(c.pressure.isel(realization=0).transpose("rh", "distance").values,
                                  ds.pressure.sel(realization=2).values)
    # its summaries: each humidity alone on the map's own automatic grid
    own = [float(rs.contact.summary(rs.contact.curves(
        h.isel(realization=0, drop=True), relative_humidity=[r], check_validity=False, model="modified_dmt")
    ).adhesive_energy[0]) for r in RH6]
    np.testing.assert_array_equal(own, ds.adhesive_energy.sel(realization=2).values)
    # and within the grid-convergence tolerance of the common-grid summary
    np.testing.assert_allclose(s.adhesive_energy.isel(realization=0).values, own, rtol=0.02)
    assert (ds.adhesive_energy > 0).all() and np.isfinite(ds.equilibrium_distance).all()


def test_real_gamma_converges_on_default_grid(sample_psds):
    """Γ on the default grid (step = h_water(30 %)/10) against a 4x finer grid."""
    for name, psd in sample_psds.items():
        kw = dict(shape=(128, 128), n=4, relative_humidity=RH6)
        coarse = rs.ensemble.distance_grid(psd, **kw)
        fine = rs.ensemble.distance_grid(psd, points_per_water_height=40, **kw)
        assert fine.size > 3.5 * coarse.size
        run = dict(n=4, shape=128, spacing=5e-9, relative_humidity=RH6, seed=4, chunks=4, model="modified_dmt")
        g0 = rs.ensemble.run(psd, distance=coarse, **run).adhesive_energy.values
        g1 = rs.ensemble.run(psd, distance=fine, **run).adhesive_energy.values
        err = np.abs(g0 / g1 - 1)
        assert np.median(err) < 0.01, (name, err)
        assert err.max() < 0.06, (name, err)


def test_section_4_3_findings_S2(sample_psds):
    _findings(sample_psds["S2"], n=32, seed=3)


@pytest.mark.slow
def test_section_4_3_findings_S1(sample_psds):
    _findings(sample_psds["S1"], n=48, seed=3)


# --- a realization's summaries depend on nothing else in the run (issue 12) ----------------------
def _smooth_psd():
    """The issue's smooth self-affine PSD (rms 2 nm, Hurst 0.8, roll-off 2e7 rad/m, cut 2.89e8)."""
    q0, qmax, hurst = 2e7, 2.89e8, 0.8
    s1_over_s0 = (qmax / q0) ** (-2.0 * (1.0 + hurst))
    m0 = float(rs.surface.self_affine_moments(s0=1.0, s1=s1_over_s0, q0=q0, qmax=qmax).m0)
    s0 = (2e-9) ** 2 / m0
    q = np.geomspace(1e5, 2e9, 300)
    q = xr.DataArray(q, dims="q", coords={"q": q}, attrs={"units": "rad/m"})
    return rs.surface.self_affine_psd(q, s0=s0, s1=s0 * s1_over_s0, q0=q0, qmax=qmax)


SUMMARIES = ("adhesive_energy", "pull_off_pressure", "equilibrium_distance")


def _summaries(n, rh, chunks=None):
    ds = rs.ensemble.run(_smooth_psd(), n=n, relative_humidity=rh, spacing=5e-9,
                         shape=(64, 64), seed=11, chunks=chunks, scheduler="sync", model="modified_dmt")
    return ds[list(SUMMARIES)].compute()


@pytest.mark.filterwarnings("ignore::roughstick.ValidityWarning")
def test_summaries_independent_of_other_humidities_n_and_chunks():
    alone = _summaries(4, [0.3])
    # the extreme humidity next to it used to move Γ(0.3) (shared grid capped at 2000 points)
    with_wet = _summaries(4, [0.3, 0.999]).sel(rh=[0.3])
    bigger_n = _summaries(9, [0.3], chunks=4).isel(realization=slice(0, 4))
    for other in (with_wet, bigger_n):
        for v in SUMMARIES:
            np.testing.assert_array_equal(alone[v].values, other[v].values, err_msg=v)
    dry = _summaries(3, [0.01])
    dry_next_to_wet = _summaries(3, [0.01, 0.999]).sel(rh=[0.01])
    for v in SUMMARIES:
        np.testing.assert_array_equal(dry[v].values, dry_next_to_wet[v].values, err_msg=v)
    assert np.all(dry.adhesive_energy.values > 0)  # not the Γ = 0 the shared grid gave


@pytest.mark.filterwarnings("ignore::roughstick.ValidityWarning")
def test_summary_is_the_single_map_automatic_grid_result():
    ds = rs.ensemble.run(_smooth_psd(), n=2, relative_humidity=[0.5], spacing=5e-9,
                         shape=(64, 64), seed=5, scheduler="sync", model="modified_dmt").compute()
    h = rs.surface.generate_surfaces(_smooth_psd(), n=2, shape=(64, 64), spacing=5e-9,
                             seed=5).isel(realization=1, drop=True).compute()
    direct = rs.contact.summary(rs.contact.curves(h, relative_humidity=[0.5],
                                                         check_validity=False, model="modified_dmt"))
    np.testing.assert_allclose(ds.adhesive_energy.isel(realization=1).values,
                               direct.adhesive_energy.values, rtol=1e-12)
    assert "own automatic distance grid" in ds.attrs["history"]


def test_run_warns_once_before_the_graph(sample_psds):
    """Extrapolated PSD and model validity are said once per run (realization 0, before any
    block runs), not once per block from inside dask, and not at all when computing."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = rs.ensemble.run(sample_psds["S2"], n=4, shape=512, spacing=5e-9,
                             relative_humidity=[0.7], seed=2, chunks=1, model="modified_dmt")
    kinds = [w.category for w in caught]
    assert kinds.count(rs.surface.ExtrapolatedPSDWarning) == 1, kinds
    assert kinds.count(rs.ValidityWarning) == 1, kinds
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds.adhesive_energy.compute(scheduler="sync")
    assert not [w for w in caught if issubclass(w.category, (rs.surface.ExtrapolatedPSDWarning,
                                                              rs.ValidityWarning))]


def test_the_parameter_hash_is_the_same_in_a_new_process():
    """A run interrupted and resumed in a new process must find the same parameter hash: the
    ensemble's contact function is a functools.partial, whose repr holds a memory address
    (the slow Ctrl-C test of `roughstick run` was refused its resume by it)."""
    import functools
    import subprocess
    import sys

    from roughstick.ensemble.pipeline import _callable_id

    code = ("import functools, roughstick as rs; from roughstick.ensemble.pipeline import _callable_id; "
            "print(_callable_id(functools.partial(rs.contact.curves, check_validity=False)))")
    here = _callable_id(functools.partial(rs.contact.curves, check_validity=False))
    there = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert here == there and "0x" not in here and "check_validity=False" in here
    other = _callable_id(functools.partial(rs.contact.curves, check_validity=True))
    assert other != here  # different parameters still hash apart
