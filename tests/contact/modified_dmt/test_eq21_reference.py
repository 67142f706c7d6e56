"""The fast modified-DMT path (union-find + Newton fits) against the literal reference.

The reference (`eq21_reference` (beside this file)) relabels the map at every distance with
scipy.ndimage.label, unwraps each asperity by a breadth-first walk and fits it with
scipy.optimize.least_squares; the test asks the pressure to agree to 1e-6 (relative) wherever
|p| > 1e-3 max|p|, and every other output to agree closely, on small maps with the hard cases.

Per asperity (the same footprint, from the reference's labelling), the fast fit's rms error of
Eq. 23 must not exceed the reference's by more than FIT_RTOL relative plus FIT_ATOL times the
footprint radius a_f: the fast iteration stops when its step is below 1e-9 (in units of a_f,
relative to 1 + |centre|), which moves the residuals by ~1e-9 a_f, and its sums are reassociated
(fastmath), ~1e-13 relative; the misses this guards against were 1e-5 to 3e-2 relative.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from eq21_reference import fit_asperity, footprints, reference_curves
from scipy import ndimage

from roughstick import datasets, materials
from roughstick.contact import laplace_pressure, water_height
from roughstick.contact.modified_dmt._controller import (
    curves,
    curves_kernel,
    hertz_levels,
    prepare_heights,
)
from roughstick.contact.modified_dmt._fit import fit_footprint

K = materials.hertz_modulus()
RH = np.array([0.3, 0.7, 0.9])
HW = water_height(RH).values
DP = laplace_pressure(RH).values
DX = 5e-9


def smooth_field(shape, *, sigma_px, rms, seed, wrap=True):
    """S1-like surface: Gaussian-filtered white noise (correlation ~ sigma_px pixels)."""
    rng = np.random.default_rng(seed)
    z = ndimage.gaussian_filter(rng.standard_normal(shape), sigma_px, mode="wrap" if wrap else "reflect")
    return z / z.std() * rms


def levels_without_percolation(z, d, periodic, connectivity=4):
    """Drop distances where an asperity wraps all the way round a periodic map."""
    hz = hertz_levels(z, d, dx=DX, dy=DX, K=K, periodic=periodic, connectivity=connectivity)
    return np.sort(np.asarray(d)[hz[:, 5] == 0])


FIT_RTOL = 1e-9
FIT_ATOL = 1e-9  # times a_f


def fits_per_asperity(z, d, *, periodic, connectivity=4, dx=DX, dy=DX):
    """(E fast, E reference, a_f) [m] of every asperity at level d (reference footprints)."""
    zc, _ = prepare_heights(z)
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # scipy's LinAlgWarning on singular paraboloid systems
        for x, y, h in footprints(zc, d, dx=dx, dy=dy, periodic=periodic, connectivity=connectivity):
            area = x.size * dx * dy
            _, e_ref = fit_asperity(x, y, h, d, area, dx, dy)
            _, e_fast = fit_footprint(x, y, h, d, dx, dy)
            rows.append((e_fast, e_ref, np.sqrt(area / np.pi), x.size))
    return np.array(rows).reshape(-1, 4)


def assert_fits_no_worse(z, d, **kw):
    """No asperity fitted worse by the fast path; returns, per level, whether every asperity's
    fit has the reference's residual (within the tolerance: the same minimum), and the number of
    asperities."""
    same = np.zeros(len(d), bool)
    n_total = 0
    for j, level in enumerate(d):
        e = fits_per_asperity(z, level, **kw)
        tol = FIT_RTOL * e[:, 1] + FIT_ATOL * e[:, 2]
        worse = e[:, 0] > e[:, 1] + tol
        assert not worse.any(), (level, e[worse])
        n_total += len(e)
        same[j] = np.all(np.abs(e[:, 0] - e[:, 1]) <= tol)
    return same, n_total


def compare(z, d, *, periodic, connectivity=4, hw=HW, dp=DP, dy=DX):
    kw = dict(dx=DX, dy=dy, K=K, periodic=periodic, connectivity=connectivity)
    fast = curves_kernel(z, d, hw, dp, **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # scipy's LinAlgWarning on singular paraboloid systems
        ref = reference_curves(z, d, hw, dp, **kw)
    p, pr = fast[0], ref[0]
    big = np.abs(pr) > 1e-3 * np.max(np.abs(pr))
    assert np.all(np.isfinite(p))
    rel = np.abs(p - pr)[big] / np.abs(pr)[big]
    assert rel.max(initial=0) < 1e-6, rel.max()
    np.testing.assert_array_equal(fast[4], ref[4])  # number of asperities
    np.testing.assert_allclose(fast[2], ref[2], rtol=1e-6, atol=1e-12)  # wet fraction
    np.testing.assert_allclose(fast[3], ref[3], rtol=1e-6, atol=1e-12)  # contact fraction
    np.testing.assert_allclose(fast[5], ref[5], rtol=1e-5, atol=1e-15)  # E^S (NaN alike)
    np.testing.assert_allclose(fast[6], ref[6], rtol=0, atol=1e-20)
    assert assert_fits_no_worse(z, d, periodic=periodic, connectivity=connectivity, dy=dy)[0].all()
    return fast


@pytest.mark.parametrize("connectivity", [4, 8])
def test_periodic_smooth(connectivity):
    z = smooth_field((40, 48), sigma_px=4, rms=4e-9, seed=1)
    zc = z - z.mean()
    d = np.linspace(zc.max() + 2e-9, zc.max() - 8e-9, 16)
    d = levels_without_percolation(z, d, True, connectivity)
    out = compare(z, d, periodic=True, connectivity=connectivity)
    assert out[4].max() >= 3  # several asperities, merging as d goes down


def test_measured_map_edge_bump():
    # a smooth bump whose top lies 3 pixels inside the edge of a measured map: the asperity is
    # cut by the edge at every level below the first few
    ny, nx = 30, 40
    X, Y = np.meshgrid((np.arange(nx) + 0.5) * DX, (np.arange(ny) + 0.5) * DX)
    z = 6e-9 * np.exp(-((X - 3.5 * DX) ** 2 + (Y - 15 * DX) ** 2) / (2 * (9 * DX) ** 2))
    z += 3e-9 * np.exp(-((X - 28 * DX) ** 2 + (Y - 12 * DX) ** 2) / (2 * (7 * DX) ** 2))
    zc = z - z.mean()
    d = np.linspace(zc.max() - 0.05e-9, zc.max() - 5e-9, 12)
    out = compare(z, d, periodic=False)
    assert out[4].max() == 2


@pytest.mark.parametrize("connectivity", [4, 8])
def test_measured_random_map(connectivity):
    # non-periodic, odd non-square random map: asperities are cut by the edges. Eq. 21 has several
    # local minima for steep asperities cut by the edge. Before the compass search
    # (roughstick.contact.modified_dmt._search) an 18-pixel asperity in the map's corner was fitted 5 %
    # worse than by the reference (whose least_squares reached a lower minimum from the same
    # start); now no asperity is fitted worse, and at levels where every asperity reaches the
    # reference's minimum the pressures agree to 1e-6 (measured: 13 of 14 levels; at the other
    # the fast fit of that asperity is 2.5 % better, the best minimum a dense grid finds)
    z = smooth_field((37, 52), sigma_px=4, rms=4e-9, seed=2, wrap=False)
    zc = z - z.mean()
    d = np.linspace(zc.max() + 2e-9, zc.max() - 8e-9, 14)
    same, _ = assert_fits_no_worse(z, d, periodic=False, connectivity=connectivity)
    kw = dict(dx=DX, dy=DX, K=K, periodic=False, connectivity=connectivity)
    fast = curves_kernel(z, d[same], HW, DP, **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = reference_curves(z, d[same], HW, DP, **kw)
    big = np.abs(ref[0]) > 1e-3 * np.max(np.abs(ref[0]))
    assert np.max(np.abs(fast[0] - ref[0])[big] / np.abs(ref[0])[big]) < 1e-6
    np.testing.assert_array_equal(fast[4], ref[4])
    np.testing.assert_allclose(fast[2], ref[2], rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(fast[3], ref[3], rtol=1e-6, atol=1e-12)


@pytest.mark.parametrize("seed", [0, 2])
def test_steep_measured_maps(seed):
    # Gaussian-filtered measured maps of 2-pixel correlation: steep asperities of a few pixels,
    # many cut by the edges, where Eq. 21 has several minima. Before the searches of
    # roughstick.contact.modified_dmt._search the fast fit was worse than the reference on a 7-pixel
    # (+0.03 %) and a 16-pixel asperity (+2.0 %) of these two maps
    z = smooth_field((48, 56), sigma_px=2, rms=4e-9, seed=seed, wrap=False)
    zc = z - z.mean()
    d = np.linspace(zc.max() - 0.2e-9, zc.max() - 8e-9, 10)
    assert assert_fits_no_worse(z, d, periodic=False)[1] > 30


def test_straight_line_of_four_pixels():
    # quantised S1A (0.3 nm steps), a level where a 4-pixel straight asperity on the crop's edge
    # was fitted 3.0 % worse than the reference (one start for 3-4 pixel footprints)
    z, periodic = family_map("S1A", 256, 2)
    z = np.round(z / 0.3e-9) * 0.3e-9
    assert assert_fits_no_worse(z, [1.0796853395820637e-08], periodic=periodic)[1] > 10


def test_asperity_wrapping_round_periodic_edges():
    # a bump centred on the corner of a periodic map: one asperity in four pieces
    n = 32
    c = (np.arange(n) + 0.5) * DX
    X, Y = np.meshgrid(c, c)
    r2 = np.minimum(X, n * DX - X) ** 2 + np.minimum(Y, n * DX - Y) ** 2
    z = 6e-9 * np.exp(-r2 / (2 * (8 * DX) ** 2))
    zc = z - z.mean()
    d = np.linspace(zc.max() - 0.1e-9, zc.max() - 3e-9, 8)
    per = compare(z, d, periodic=True)
    npe = compare(z, d, periodic=False)
    np.testing.assert_array_equal(per[4][0], 1)  # one asperity when wrapped
    assert npe[4][0].max() == 4  # four pieces on a measured map
    # the wrapped asperity is the same as the bump moved to the centre
    zs = np.roll(z, (n // 2, n // 2), axis=(0, 1))
    centred = curves_kernel(zs, d, HW, DP, dx=DX, dy=DX, K=K, periodic=False, connectivity=4)
    np.testing.assert_allclose(per[0], centred[0], rtol=1e-7)


def test_quantised_heights_with_ties():
    # integer AFM counts (0.5 nm step): many equal heights, levels exactly on the steps
    z = np.round(smooth_field((36, 36), sigma_px=4, rms=4e-9, seed=3) / 0.5e-9) * 0.5e-9
    zc, _ = prepare_heights(z)
    steps = np.unique(zc)[::-1]
    d = np.concatenate([steps[:8], steps[:6] - 0.25e-9])
    assert np.unique(zc, return_counts=True)[1].max() > 20
    compare(z, levels_without_percolation(z, d, True), periodic=True)


def test_nan_pixels_are_excluded():
    z = smooth_field((32, 40), sigma_px=4, rms=4e-9, seed=4)
    z[5:8, 10:30] = np.nan  # a dropout scan line band
    z[20, 20] = np.nan
    zc, nvalid = prepare_heights(z)
    assert nvalid == z.size - 61
    d = np.linspace(np.nanmax(zc) + 1e-9, np.nanmax(zc) - 7e-9, 12)
    out = compare(z, levels_without_percolation(z, d, False), periodic=False)
    assert np.all(out[2] <= 1)


def test_one_and_two_pixel_asperities_and_plateaus():
    z = np.zeros((20, 24))
    z[3, 3] = 2e-9  # a one-pixel spike
    z[10, 5:7] = [1.5e-9, 1.0e-9]  # a two-pixel asperity
    z[14:19, 12:20] = 1.2e-9  # a plateau (R -> infinity)
    z[16, 15] = 1.3e-9  # with a one-pixel bump on it
    z[2:5, 18:21] = 0.8e-9  # a small plateau
    zc, _ = prepare_heights(z)
    top = zc.max()
    d = np.array([top + 0.1e-9, top - 0.05e-9, zc[10, 6] - 1e-12, zc[16, 14], zc[16, 14] - 0.3e-9,
                  zc[3, 19] - 0.1e-9])
    out = compare(z, d, periodic=False)
    assert np.all(np.isfinite(out[0])) and np.all(np.isfinite(out[1]))
    # the plateau exactly at the level: zero force, Hertz area half the footprint (t = 0)
    plate = curves_kernel(np.pad(np.ones((4, 4)), 3) * 1e-9, [np.pad(np.ones((4, 4)), 3).mean() * -1e-9 + 1e-9],
                          HW[:1], DP[:1], dx=DX, dy=DX, K=K, periodic=False, connectivity=4)
    assert plate[1][0, 0] == 0
    np.testing.assert_allclose(plate[3][0, 0], 0.5 * 16 / 100, rtol=1e-12)


def test_flat_map():
    z = np.full((12, 15), 3e-9)
    d = np.array([2e-9, 0.5e-9, 0.0, -1e-9])
    out = compare(z, d, periodic=False)
    # flat on flat: above the water height nothing, then the full water term; touching
    # (d = 0): a plateau exactly at the plane, t = 0, no force and Hertz area A/2;
    # pressed 1 nm: one flat-topped asperity over the whole map, a large finite force
    np.testing.assert_array_equal(out[1][:, :3], 0)
    np.testing.assert_array_equal(out[0][:, 0], np.where(HW >= 2e-9, DP, 0.0))
    np.testing.assert_allclose(out[0][:, 1], DP)
    np.testing.assert_allclose(out[0][:, 2], DP * 0.5)
    assert np.all(out[1][:, 3] > 1e8) and np.all(np.isfinite(out[1][:, 3]))
    per = compare(z, d, periodic=True)  # one asperity wrapping everywhere: still no overflow
    assert np.all(np.isfinite(per[0]))


@pytest.mark.parametrize("rh", [0.01, 0.999])
def test_extreme_humidity(rh):
    hw = water_height([rh]).values
    dp = laplace_pressure([rh]).values
    z = smooth_field((30, 30), sigma_px=4, rms=4e-9, seed=5)
    zc = z - z.mean()
    d = np.concatenate([np.linspace(zc.max() + hw[0] * 1.01, zc.max() + 1e-9, 4),
                        np.linspace(zc.max(), zc.max() - 5e-9, 6)])
    d = levels_without_percolation(z, d, True)
    out = compare(z, d, periodic=True, hw=hw, dp=dp)
    j = np.searchsorted(d, zc.max() + 1e-9)
    if rh == 0.999:  # h_water ~ 1 um: the whole map is wet well before contact
        assert out[2][0, j] == 1.0
        assert out[0][0, j] == pytest.approx(dp[0], rel=1e-12)
    else:  # h_water = 0.23 nm: dry just before contact
        assert out[0][0, j] == 0.0


def family_map(family, n, seed=0):
    """A crop of a bundled sample (measured, not periodic) or a periodic surface of a family."""
    if family in ("S1A", "S2A"):
        off = 128 * seed
        h = datasets.load_sample(family).isel(y=slice(off, off + n), x=slice(off, off + n))
        return h.values, False
    return datasets.surface_family(family, shape=(n, n), seed=seed).values, True


def family_levels(z, periodic, count):
    """``count`` levels of the automatic grid spread over the levels with asperities."""
    d, out = curves(z, HW, DP, dx=DX, dy=DX, K=K, periodic=periodic, connectivity=4)
    with_contact = np.flatnonzero(out[4][0] > 0)
    return d[with_contact[np.linspace(0, with_contact.size - 1, count).astype(int)]]


def check_family(family, n, seed, count, quantum=0.0):
    z, periodic = family_map(family, n, seed)
    if quantum:
        z = np.round(z / quantum) * quantum
    d = family_levels(z, periodic, count)
    same, n_total = assert_fits_no_worse(z, d, periodic=periodic)
    # every asperity at the same minimum on these maps (before the plateau escape, 10 of 2,500
    # asperities on the families were not, and pressures differed by up to 2e-2)
    assert same.all(), d[~same]
    kw = dict(dx=DX, dy=DX, K=K, periodic=periodic, connectivity=4)
    fast = curves_kernel(z, d, HW, DP, **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = reference_curves(z, d, HW, DP, **kw)
    big = np.abs(ref[0]) > 1e-3 * np.max(np.abs(ref[0]))
    rel = np.abs(fast[0] - ref[0])[big] / np.abs(ref[0])[big]
    assert rel.max(initial=0) < 1e-6, rel.max()
    np.testing.assert_array_equal(fast[4], ref[4])
    return n_total


@pytest.mark.parametrize("family", ["S1A", "S2A", "table4", "smooth", "rough"])
def test_fits_no_worse_than_reference_on_families(family):
    # 256^2 crops, 8 levels of the automatic grid: the sphere fits of the fast path against
    # scipy's least_squares. Without the plateau escape this failed on S2A, Table 4 and smooth
    # (one asperity each stopped on the plateau t = 0 with a 1e-4..3e-2 larger residual)
    assert check_family(family, 256, 1, 8) > 0


@pytest.mark.slow
@pytest.mark.parametrize("quantum", [0.0, 0.3e-9])
@pytest.mark.parametrize("family", ["S1A", "S2A", "table4", "smooth", "rough"])
def test_fits_no_worse_than_reference_on_families_sweep(family, quantum):
    # 256^2, three crops / seeds, 16 levels; and heights quantised to 0.3 nm (ties): no asperity
    # fitted worse than the reference, and the pressure within 1e-6 at every level
    assert sum(check_family(family, 256, seed, 16, quantum) for seed in range(3)) > 0
