"""Beam-scale stochastic model: Eq. 36 limit, energy balance, convergence, seeding, protocols."""

from dataclasses import replace

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.stiction.cantilever import PAPER_CANTILEVER, crack_length_from_adhesive_energy

BEAM = PAPER_CANTILEVER  # 1500 µm, t 2.62 µm, h 1.9 µm, E 164 GPa


def bending_energy(s, beam, n=4001):
    """EI/2 ∫ w''² dx of the S-shape w = h(3ξ²-2ξ³) on [0, s], per unit width, by quadrature."""
    x = np.linspace(0.0, s, n)
    w = beam.gap * (3 * (x / s) ** 2 - 2 * (x / s) ** 3)
    curv = np.gradient(np.gradient(w, x, edge_order=2), x, edge_order=2)
    ei = beam.youngs_modulus * beam.thickness**3 / 12.0
    return 0.5 * ei * np.trapezoid(curv**2, x)


def total_energy(s, gamma, patch_length, beam):
    """Π(s) = bending energy − ∫_s^l Γ(x) dx (patchwise constant Γ), independent of the kernel."""
    s = float(s)
    edges = np.arange(len(gamma) + 1) * patch_length
    hi = np.minimum(edges[1:], beam.length)
    lo = np.minimum(edges[:-1], beam.length)
    covered = np.clip(hi - np.maximum(lo, s), 0.0, None)
    bending = beam.youngs_modulus * beam.thickness**3 * beam.gap**2 / (2 * s**3)
    return bending - np.sum(gamma * covered)


def test_s_shape_bending_energy():
    """The closed form E t³ h² / (2 s³) used for Π is the quadrature of the S-shape's curvature."""
    for s in [100e-6, 700e-6]:
        closed = BEAM.youngs_modulus * BEAM.thickness**3 * BEAM.gap**2 / (2 * s**3)
        assert bending_energy(s, BEAM) == pytest.approx(closed, rel=1e-3)


@pytest.mark.parametrize("gamma0", [1e-5, 1e-4, 1e-3, 1e-2, 0.1, 1.0])
@pytest.mark.parametrize("patch_length", [0.5e-6, 2.62e-6, 20e-6])
def test_uniform_law_gives_eq36(gamma0, patch_length):
    s36 = crack_length_from_adhesive_energy(gamma0, beam=BEAM)
    for length in [0.5 * s36, 0.99 * s36, 1.01 * s36, 3 * s36, 1500e-6]:
        beam = replace(BEAM, length=length)
        n = int(np.ceil(length / patch_length)) + 1
        s = float(rs.beam.crack_length(np.full(n, gamma0), beam=beam, patch_length=patch_length))
        if s36 < length:
            assert s == pytest.approx(s36, rel=0.01)
        else:  # shorter beams come free
            assert np.isinf(s)


def test_eq36_is_the_energy_minimum():
    """The uniform-law crack length minimises Π(s) computed by quadrature of the S-shape."""
    for gamma0 in [1e-3, 3e-2]:
        s36 = crack_length_from_adhesive_energy(gamma0, beam=BEAM)
        grid = np.linspace(0.6 * s36, 1.6 * s36, 401)
        pi = [total_energy(s, np.full(1000, gamma0), 2e-6, BEAM) for s in grid]
        assert grid[int(np.argmin(pi))] == pytest.approx(s36, rel=0.01)


def test_random_fronts_are_energy_minima_reached_downhill():
    rng = np.random.default_rng(3)
    patch = 2.62e-6
    for _ in range(10):
        gamma = rng.lognormal(np.log(5e-3), 1.0, size=600)
        s = float(rs.beam.crack_length(gamma, beam=BEAM, patch_length=patch))
        if not np.isfinite(s):
            continue
        delta = 0.05e-6
        p0 = total_energy(s, gamma, patch, BEAM)
        assert total_energy(s - delta, gamma, patch, BEAM) >= p0 - 1e-12 * abs(p0)
        assert total_energy(s + delta, gamma, patch, BEAM) >= p0 - 1e-12 * abs(p0)
        # release: energy falls all the way from a front near the clamp to s
        path = np.linspace(0.3 * s, s, 200)
        pis = np.array([total_energy(x, gamma, patch, BEAM) for x in path])
        assert np.all(np.diff(pis) <= 1e-9 * np.abs(pis).max())


def test_converges_with_patch_length_to_a_smooth_interface():
    """Γ(x) smooth, sampled on patches: s converges (first order) to the continuous solution."""
    g0, amp, wl = 2e-3, 0.5, 40e-6

    def gamma(x):
        return g0 * (1 + amp * np.sin(2 * np.pi * x / wl))

    # continuous solution: first x where G(x) <= Γ(x)
    x = np.linspace(1e-6, 1500e-6, 3_000_001)
    ref = x[np.argmax(BEAM.stiffness_term / x**4 <= gamma(x))]
    errors = []
    for dx in [4e-6, 1e-6, 0.25e-6]:
        centres = (np.arange(int(1500e-6 / dx) + 1) + 0.5) * dx
        errors.append(abs(float(rs.beam.crack_length(gamma(centres), beam=BEAM, patch_length=dx)) - ref))
    assert errors[2] < errors[0] / 4
    assert errors[2] / ref < 1e-3


def _bank(rh=(0.3, 0.6, 0.9), n_law=50, seed=1):
    rng = np.random.default_rng(seed)
    base = rng.lognormal(np.log(2e-3), 1.2, size=(n_law, 1))
    growth = np.array(rh)[None, :] ** 3 * 20  # adhesion rises with RH, per patch
    return xr.DataArray(base * (1 + growth), {"law": np.arange(n_law), "rh": list(rh)}, ("law", "rh"),
                        attrs={"units": "J m-2"})


def test_layout_and_probability():
    ds = rs.beam.simulate(_bank(), beam_length=[300e-6, 1500e-6], n=40, seed=5,
                        shape_points=11)
    assert ds.crack_length.dims == ("realization", "rh", "beam_length")
    assert ds.crack_length.attrs["units"] == "m"
    assert bool((ds.stuck == ds.crack_length.notnull()).all())
    assert bool((ds.crack_length < ds.beam_length).where(ds.stuck, True).all())
    p = ds.stuck_probability
    assert bool(((ds.stuck_probability_lower <= p) & (p <= ds.stuck_probability_upper)).all())
    # longer beams and higher RH stick more often (same patches: common random numbers)
    assert bool((ds.stuck.sel(beam_length=1500e-6) >= ds.stuck.sel(beam_length=300e-6)).all())
    # Eq. 36 back: the apparent energy is that of the crack length
    s = ds.crack_length.isel(rh=2, beam_length=1).dropna("realization")
    g = ds.apparent_adhesive_energy.isel(rh=2, beam_length=1).dropna("realization")
    np.testing.assert_allclose(crack_length_from_adhesive_energy(g.values, beam=BEAM), s.values,
                               rtol=1e-9)
    assert float(ds.shape.isel(x_over_length=-1).where(ds.stuck).max()) == pytest.approx(BEAM.gap)


def test_bit_identical_across_chunkings():
    bank = _bank()
    whole = rs.beam.simulate(bank, beam_length=1500e-6, n=30, seed=9)
    parts = [rs.beam.simulate(bank, beam_length=1500e-6, realizations=r, seed=9)
             for r in (range(0, 7), range(7, 30))]
    merged = xr.concat([p.crack_length for p in parts], "realization")
    np.testing.assert_array_equal(merged.values, whole.crack_length.values)


def test_step_up_hysteresis():
    bank = _bank()
    rel = rs.beam.simulate(bank, beam_length=1500e-6, n=200, seed=2)
    up = rs.beam.simulate(bank, beam_length=1500e-6, n=200, seed=2, protocol="step_up")
    np.testing.assert_array_equal(rel.crack_length.isel(rh=0).values, up.crack_length.isel(rh=0).values)
    both = rel.stuck & up.stuck
    diff = (up.crack_length - rel.crack_length).where(both)
    assert float(diff.min()) >= -1e-15  # (edge round-off) the stepped front stays pinned further out
    assert float(diff.max()) > 1e-6  # ... and the two protocols differ: hysteresis
    # a uniform interface has no hysteresis
    uni = xr.DataArray(np.tile([[1e-3, 3e-3, 1e-2]], (5, 1)), dims=("law", "rh"),
                       coords={"rh": [0.3, 0.6, 0.9]})
    a = rs.beam.simulate(uni, beam_length=1500e-6, n=3)
    b = rs.beam.simulate(uni, beam_length=1500e-6, n=3, protocol="step_up")
    np.testing.assert_allclose(a.crack_length.values, b.crack_length.values, rtol=1e-12)


def test_bad_input():
    with pytest.raises(ValueError, match="patch energies"):
        rs.beam.crack_length(np.ones(10), beam=BEAM)
    with pytest.raises(ValueError, match="metres"):
        rs.beam.crack_length(np.ones(10), beam=BEAM, patch_length=2.62)
    with pytest.raises(ValueError, match="NaN"):
        rs.beam.crack_length(np.full(600, np.nan), beam=BEAM)
    with pytest.raises(ValueError, match="protocol"):
        rs.beam.crack_length(np.ones(600), beam=BEAM, protocol="down")
    bad = _bank().assign_coords(rh=[0.9, 0.6, 0.3])
    with pytest.raises(ValueError, match="increasing"):
        rs.beam.simulate(bad, beam_length=1e-3, protocol="step_up")


def test_beam_length_unit_slip_is_refused_by_name():
    # before: beam_length=[300] (µm meant) ran 300 m beams (model="cohesive" checks the lengths
    # in the same place, _run_axes)
    with pytest.raises(ValueError, match=r"beam_length=300 m is implausible for a MEMS beam "
                                         r"\(plausible 1e-6 to 1e-2 m\); it looks like µm: give "
                                         r"it in m, e\.g\. beam_length=300e-6"):
        rs.beam.simulate(_bank(), beam_length=[300], n=2)
    rs.beam.simulate(_bank(), beam_length=[1e-6, 1e-2], n=2, patch_length=0.5e-6)  # the bounds are allowed


def test_a_bank_in_mj_labelled_j_is_refused_with_the_fix():
    """Energies in mJ m-2 read as J m-2 gave P(stuck) = 1 everywhere, without a word."""
    mj = (_bank() * 1e3).assign_attrs(units="J m-2")
    fix = r"look like mJ m-2: divide by 1000 \(bank / 1000\) or set bank\.attrs\['units'\] = 'mJ m-2'"
    with pytest.raises(ValueError, match=r"bank has adhesive energies up to 395\.7 J m-2 .*above 0\.5 J m-2.*" + fix):
        rs.beam.simulate(mj, beam_length=[300e-6], n=2)
    with pytest.raises(ValueError, match=fix):
        rs.stuck_probability(mj, method="subset", beam_length=300e-6)
    # labelled as what they are, the same energies give the same beams
    got = rs.beam.simulate(mj.assign_attrs(units="mJ m-2"), beam_length=[300e-6, 1500e-6], n=30, seed=1)
    ref = rs.beam.simulate(_bank(), beam_length=[300e-6, 1500e-6], n=30, seed=1)
    np.testing.assert_array_equal(got.stuck.values, ref.stuck.values)
    np.testing.assert_allclose(got.crack_length.values, ref.crack_length.values, rtol=1e-9)


@pytest.mark.parametrize("bad, said", [(-1e-3, "-0.001 J m-2"), (np.inf, "inf J m-2")])
def test_negative_or_infinite_energies_are_refused(bad, said):
    bank = _bank().copy()
    bank[3, 1] = bad
    with pytest.raises(ValueError, match=rf"bank has the adhesive energy {said}.*finite and >= 0"):
        rs.beam.simulate(bank, beam_length=[300e-6], n=2)
    with pytest.raises(ValueError, match="finite and >= 0"):
        rs.stuck_probability(bank, method="subset", beam_length=300e-6)
    with pytest.raises(ValueError, match="finite and >= 0"):
        rs.beam.simulate(bank, beam_length=[300e-6], n=2, beam_model="cohesive")
    with pytest.raises(ValueError, match="patch_energy must be finite and >= 0"):
        rs.beam.crack_length(np.full(600, bad), beam=BEAM)


def test_no_beams_is_an_error_not_nan():
    """n=0 (n_realization=0) returned P(stuck) = NaN."""
    with pytest.raises(ValueError, match=r"n=0: must be an integer >= 1; pass e\.g\. n=100"):
        rs.beam.simulate(_bank(), beam_length=[300e-6], n=0)
    with pytest.raises(ValueError, match="realizations must be a non-empty"):
        rs.beam.simulate(_bank(), beam_length=[300e-6], realizations=[])


def test_a_patch_longer_than_the_shortest_beam_is_refused():
    """A 300 µm patch on 100-200 µm beams ran (each beam one patch longer than itself)."""
    said = (r"patch_length=0\.0003 m is longer than the shortest beam \(beam_length=0\.0001 m\).*"
            r"Pass a shorter patch_length")
    with pytest.raises(ValueError, match=said):
        rs.beam.simulate(_bank(), beam_length=[100e-6, 200e-6], patch_length=300e-6, n=2)
    with pytest.raises(ValueError, match=said):
        rs.stuck_probability(_bank(), method="subset", beam_length=[100e-6, 200e-6], patch_length=300e-6)
    with pytest.raises(ValueError, match=r"patch_length=0\.0003 m is longer than the beam"):
        rs.beam.crack_length(np.ones(10), beam=replace(BEAM, length=100e-6), patch_length=300e-6)
    rs.beam.simulate(_bank(), beam_length=[100e-6, 200e-6], patch_length=100e-6, n=2)  # one patch
