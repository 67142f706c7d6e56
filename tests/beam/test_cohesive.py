"""Cohesive beam model (roughstick.beam.cohesive, rs.beam.simulate(beam_model="cohesive")):
the Eq. 36 limit, convergence, energy balance, agreement with the sharp front, reproducibility,
the pull-in start and the recording of failed solves."""

import math
from dataclasses import replace

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.beam import _cohesive_kernels as K
from roughstick.beam import cohesive as CB
from roughstick.beam.cohesive import (
    PatchLaws,
    release_cohesive,
    short_range_pressure_law,
)
from roughstick.stiction.cantilever import Cantilever, crack_length_from_adhesive_energy

BEAM = Cantilever()  # paper §5.1: w 30 µm, t 2.62 µm, h 1.9 µm, E 164 GPa, l 1500 µm
ZEROS = np.zeros(1000, int)


def s36(gamma, beam=BEAM):
    return float(crack_length_from_adhesive_energy(gamma, beam=beam))


def test_short_range_law_has_the_requested_work():
    for gamma in [1e-5, 1e-3, 0.1]:
        laws = PatchLaws.uniform(*short_range_pressure_law(gamma))
        assert laws.adhesive_energy[0] == pytest.approx(gamma, rel=1e-3)
        assert laws.equilibrium_gap[0] == pytest.approx(5.0, abs=0.02)  # nm


@pytest.mark.parametrize("gamma", [3e-5, 1e-4, 1e-3, 1e-2, 0.1])
def test_deterministic_limit_is_eq36(gamma):
    """Uniform short-range law (range 2 nm ≪ h = 1.9 µm): s = Eq. 36 within 1 %."""
    laws = PatchLaws.uniform(*short_range_pressure_law(gamma))
    res = release_cohesive(laws, ZEROS, beam=BEAM)
    assert res.stuck and not res.arc
    assert res.crack_length == pytest.approx(s36(gamma), rel=0.01)
    assert res.apparent_adhesive_energy == pytest.approx(gamma, rel=0.04)
    assert res.attached_length == pytest.approx(BEAM.length - res.front)
    assert 0 < res.front < res.crack_length


@pytest.mark.parametrize("gamma", [1e-4, 1e-3, 1e-2])
def test_beams_shorter_than_s_come_free(gamma):
    laws = PatchLaws.uniform(*short_range_pressure_law(gamma))
    s = s36(gamma)
    free = release_cohesive(laws, ZEROS, beam=replace(BEAM, length=0.95 * s))
    assert not free.stuck and math.isnan(free.crack_length)
    res = release_cohesive(laws, ZEROS, beam=replace(BEAM, length=1.05 * s))
    assert res.stuck and res.crack_length == pytest.approx(s, rel=0.01)


@pytest.mark.parametrize("gamma", [1e-4, 1e-2])
def test_energy_balance_at_the_clamp(gamma):
    """J-integral: the strain energy released per unit crack advance, M(0)²/(2 E I w), equals
    the work of separation of the law, whatever the shape of the cohesive zone."""
    laws = PatchLaws.uniform(*short_range_pressure_law(gamma, law_range=5e-9))
    res = release_cohesive(laws, ZEROS, beam=BEAM)
    EI = BEAM.youngs_modulus * BEAM.width * BEAM.thickness**3 / 12
    assert res.clamp_moment**2 / (2 * EI * BEAM.width) == pytest.approx(gamma, rel=0.005)


def test_convergence_in_elements():
    laws = PatchLaws.uniform(*short_range_pressure_law(1e-3))
    beam = replace(BEAM, length=450e-6)  # s = 355 µm
    s = [release_cohesive(laws, ZEROS, beam=beam, element_size=e).crack_length
         for e in (2e-6, 1e-6, 0.5e-6, 0.25e-6)]
    d = np.abs(np.diff(s))
    assert d[-1] < 1e-3 * s[-1]  # 0.5 -> 0.25 µm changes s by < 0.1 %
    assert d[-1] <= d[0]


def test_fine_patches_average_the_laws():
    """Δx → 0 with two alternating laws: the cohesive zone spans many patches and the beam
    sees their mean work of separation (the sharp front would pin on the stronger one)."""
    pa, g = short_range_pressure_law(2e-3)
    pb, _ = short_range_pressure_law(0.5e-3)
    laws = PatchLaws(xr.DataArray(np.stack([pa, pb]), dims=("law", "gap"), coords={"gap": g}))
    beam = replace(BEAM, length=420e-6)  # s(mean) = 336 µm
    s = release_cohesive(laws, np.arange(20000) % 2, beam=beam, patch_length=0.25e-6,
                              element_size=0.25e-6).crack_length
    assert s == pytest.approx(s36(1.25e-3), rel=0.01)


def test_pull_in_start_gives_the_same_release(monkeypatch):
    """The load-controlled pull-in start (used when the direct start solve fails) lands on
    the same equilibrium path: same crack length as the direct start."""
    laws = PatchLaws.uniform(*short_range_pressure_law(1e-3))
    direct = release_cohesive(laws, ZEROS, beam=BEAM)
    original = K.BeamMesh.solve_constrained

    def no_direct_start(self, u, lam, *args, max_iter=40, **kw):
        if max_iter == 400:  # the direct start solve
            raise K.SolverError("direct start disabled by the test")
        return original(self, u, lam, *args, max_iter=max_iter, **kw)

    monkeypatch.setattr(K.BeamMesh, "solve_constrained", no_direct_start)
    pulled = release_cohesive(laws, ZEROS, beam=BEAM)
    assert pulled.stuck
    assert pulled.crack_length == pytest.approx(direct.crack_length, rel=1e-4)


def _energy_bank(gammas, rh=(0.5,)):
    g = np.atleast_2d(np.asarray(gammas, dtype=float)).T
    return xr.DataArray(g, dims=("law", "rh"), coords={"rh": list(rh)})


def zone_length(gamma, law_range=2e-9):
    """Characteristic cohesive-zone length (E I δ / (w σ_max))^(1/4) of the cubic well."""
    sigma = 16 * gamma / (9 * law_range)
    return (BEAM.youngs_modulus * BEAM.thickness**3 / 12 * law_range / sigma) ** 0.25


def test_cohesive_matches_sharp_front_on_long_patches():
    """Random short-range laws on patches (20 µm) longer than the cohesive zone: the two models
    agree on stuck/free and on s within 4 zone lengths (the cohesive front senses the laws over
    its zone, the sharp front at one point; measured largest difference 18.3 µm, 4 l_z of the
    weakest law = 21.8 µm). With 0.5 µm patches the cohesive s is larger (it averages the laws
    over its zone, the sharp front pins on the first strong patch)."""
    rng = np.random.default_rng(5)
    rng.uniform(size=50)  # the second draw of cmp.py, as measured
    gam = 10 ** rng.uniform(-3.2, -2.8, size=50)
    bank = _energy_bank(gam)
    kw = dict(beam_length=[400e-6, 1500e-6], n=20, seed=3)
    coh = rs.beam.simulate(bank, beam_model="cohesive", element_size=1e-6, patch_length=20e-6, **kw)
    sf = rs.beam.simulate(bank, patch_length=20e-6, **kw)
    assert int(coh.solver_failed.sum()) == 0
    assert (coh.stuck == sf.stuck).all()
    d = np.abs(coh.crack_length - sf.crack_length).max()
    assert float(d) <= 4 * zone_length(gam.min())
    fine_c = rs.beam.simulate(bank, beam_model="cohesive", element_size=0.5e-6, patch_length=0.5e-6,
                            beam_length=[1500e-6], n=4, seed=3)
    fine_s = rs.beam.simulate(bank, patch_length=0.5e-6, beam_length=[1500e-6], n=4,
                            seed=3)
    assert (fine_c.crack_length > fine_s.crack_length).all()


def test_bit_identical_across_chunkings():
    rng = np.random.default_rng(2)
    low = 10 ** rng.uniform(-3.5, -2.5, 30)
    bank = xr.DataArray(np.stack([low, 3 * low], axis=1), dims=("law", "rh"),
                        coords={"rh": [0.5, 0.8]})
    kw = dict(beam_length=[300e-6, 600e-6], seed=7, beam_model="cohesive", element_size=1e-6)
    whole = rs.beam.simulate(bank, n=6, **kw)
    parts = [rs.beam.simulate(bank, realizations=r, **kw) for r in ([0, 1, 2], [3], [4, 5])]
    joined = xr.concat([p[["crack_length", "stuck", "solver_failed", "attached_length"]]
                        for p in parts], dim="realization")
    for v in ["crack_length", "stuck", "solver_failed", "attached_length"]:
        np.testing.assert_array_equal(whole[v].values, joined[v].values)
    assert whole.attrs["model"] == "cohesive"


def test_bit_identical_across_thread_counts(monkeypatch):
    """Realizations are solved on one thread per core; the result must not depend on how many."""
    rng = np.random.default_rng(5)
    low = 10 ** rng.uniform(-3.5, -2.5, 30)
    bank = xr.DataArray(np.stack([low, 3 * low], axis=1), dims=("law", "rh"),
                        coords={"rh": [0.5, 0.8]})
    kw = dict(beam_length=[300e-6, 600e-6], n=5, seed=3, beam_model="cohesive",
              element_size=1e-6)
    runs = {}
    for n in (1, 2, 3):
        monkeypatch.setattr(CB.os, "cpu_count", lambda n=n: n)
        runs[n] = rs.beam.simulate(bank, **kw)
    for n in (2, 3):
        for v in ["crack_length", "stuck", "solver_failed", "attached_length", "arc"]:
            np.testing.assert_array_equal(runs[1][v].values, runs[n][v].values)


def test_failed_solves_are_recorded_not_dropped(monkeypatch):
    bank = _energy_bank([1e-3, 2e-3, 3e-3])
    original = CB.release_cohesive
    calls = {"n": 0}

    def flaky(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 2:
            raise K.SolverError("injected failure")
        return original(*args, **kwargs)

    monkeypatch.setattr(CB, "release_cohesive", flaky)
    monkeypatch.setattr(CB.os, "cpu_count", lambda: 1)  # the call counter needs one thread
    ds = rs.beam.simulate(bank, beam_length=[600e-6], n=4, seed=1, beam_model="cohesive",
                        element_size=1e-6)
    assert ds.sizes["realization"] == 4
    assert int(ds.solver_failed.sum()) == 1
    assert bool(ds.solver_failed.isel(realization=1, rh=0, beam_length=0))
    assert np.isnan(ds.crack_length.isel(realization=1, rh=0, beam_length=0))
    assert int(ds.n_solved.squeeze()) == 3
    assert float(ds.stuck_probability.squeeze()) == int(ds.stuck.sum()) / 3


def test_bad_input():
    laws = PatchLaws.uniform(*short_range_pressure_law(1e-3))
    with pytest.raises(ValueError, match="patch laws"):
        release_cohesive(laws, np.zeros(3, int))
    with pytest.raises(ValueError, match=r"\[0, 1\)"):
        release_cohesive(laws, np.ones(1000, int))
    p, g = short_range_pressure_law(1e-3)
    with pytest.raises(ValueError, match="uniform"):
        PatchLaws.uniform(p[[0, 1, 3, 4]], g[[0, 1, 3, 4]])
    bank = _energy_bank([1e-3])
    with pytest.raises(ValueError, match="model must be one of"):
        rs.beam.simulate(bank, beam_length=[600e-6], beam_model="fem")
    with pytest.raises(ValueError, match="rh coordinate increasing"):
        rs.beam.simulate(xr.DataArray([[2e-3, 1e-3]], dims=("law", "rh"), coords={"rh": [0.6, 0.3]}),
                         beam_length=[600e-6], beam_model="cohesive", protocol="step_up")
    with pytest.raises(ValueError, match="dims"):
        rs.beam.simulate(bank.expand_dims(x=[0]), beam_length=[600e-6], beam_model="cohesive")


def test_step_up_on_a_uniform_interface():
    """RH stepped up with the beam left in place: a stuck front zips in to the Eq. 36 crack
    length of the stronger law (as a fresh release would put it), a free beam stays free
    (a fresh release would leave it stuck): the hysteresis of the free state."""
    g1, g2 = 1e-4, 4e-4  # s36 = 632 and 447 µm
    bank = xr.DataArray([[g1, g2]], dims=("law", "rh"), coords={"rh": [0.3, 0.6]})
    kw = dict(n=1, beam_model="cohesive", element_size=1e-6)
    up = rs.beam.simulate(bank, beam_length=[500e-6, 800e-6], protocol="step_up", **kw)
    rel = rs.beam.simulate(bank, beam_length=[500e-6, 800e-6], protocol="release", **kw)
    assert not up.solver_failed.any()
    assert not up.stuck.isel(beam_length=0).any()  # 500 µm: free at RH 0.3, stays free
    assert bool(rel.stuck.isel(beam_length=0, rh=1).all())
    s_up = float(up.crack_length.isel(beam_length=1, rh=1).squeeze())
    assert s_up == pytest.approx(s36(g2), rel=0.01)


def test_step_up_is_pinned_further_out_on_random_patches():
    rng = np.random.default_rng(8)
    low = 10 ** rng.uniform(-4.5, -3.5, 40)
    bank = xr.DataArray(np.stack([low, 4 * low], 1), dims=("law", "rh"), coords={"rh": [0.3, 0.6]})
    kw = dict(beam_length=[1000e-6], n=8, seed=2, beam_model="cohesive", element_size=1e-6)
    rel = rs.beam.simulate(bank, protocol="release", **kw).isel(rh=1)
    up = rs.beam.simulate(bank, protocol="step_up", **kw).isel(rh=1)
    assert not up.solver_failed.any() and up.stuck.all() and rel.stuck.all()
    assert (up.crack_length >= rel.crack_length * (1 - 1e-3)).all()
    assert int((up.crack_length > 1.05 * rel.crack_length).sum()) >= 4  # measured 8 of 8


@pytest.mark.slow
def test_table4_pressure_bank_releases_are_solved():
    """Real modified-DMT laws (several wells, scattered equilibrium gaps) of small Table-4
    patches: every release of 12 beams solved (the direct start failed on them all)."""
    from roughstick.stiction.interaction_zone import cantilever_psd
    from roughstick.surface import self_affine_psd
    par = cantilever_psd()
    kw = {k: float(par[k]) for k in ("s0", "s1", "q0", "qmax")}

    def psd(q):
        return self_affine_psd(q, **kw)

    bank = rs.beam.pressure_law_bank(psd, relative_humidity=[0.7], n=6, shape=(256, 524),
                                spacing=5e-9, seed=3)
    assert bank.dims == ("law", "rh", "gap")
    ds = rs.beam.simulate(bank, beam_length=[1500e-6], n=12, seed=1, beam_model="cohesive")
    assert int(ds.solver_failed.sum()) == 0
    assert ds.stuck.all()
