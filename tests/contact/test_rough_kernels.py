"""The speed-ups of `roughstick.contact._rough_kernels` keep its values.

- the water count (bucketed lookup) equals a brute-force count, with ties, NaN and inf;
- the allocation-free sphere fit recovers an exact constrained sphere (Eqs. 19-21);
- the default (cold) fits depend only on the asperity and d: the same distance gives the same
  bits in any grid;
- the opt-in warm start equals the cold fits where Eq. 21 has one minimum (a smooth bump), and
  it is only used for asperities whose pixels did not change.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import ndimage

from roughstick import hertz_modulus, laplace_pressure, water_height
from roughstick.contact._rough_kernels import (
    _count_above,
    _fit_sphere,
    curves_kernel,
    fit_workspace,
)

K = hertz_modulus()
RH = np.array([0.3, 0.7, 0.9])
HW = water_height(RH).values
DP = laplace_pressure(RH).values
DX = 5e-9


@pytest.mark.parametrize("seed", range(6))
def test_count_above_equals_brute_force(seed):
    rng = np.random.default_rng(seed)
    m = int(rng.integers(1, 40))
    thr = np.sort(np.round(rng.normal(size=m), 1))  # ties among thresholds
    z = np.round(rng.normal(size=500), 1)  # heights exactly on thresholds
    z[:7] = np.nan
    z[7], z[8] = np.inf, -np.inf
    if seed % 2:
        thr = np.concatenate([[-1e300], thr, [1e300]])  # a huge span: few populated buckets
    expected = np.array([(z >= t).sum() for t in thr])
    np.testing.assert_array_equal(_count_above(z, thr), expected)


def test_count_above_edge_sizes():
    assert _count_above(np.array([1.0, np.nan]), np.empty(0)).size == 0
    np.testing.assert_array_equal(_count_above(np.array([1.0, 2.0, np.nan]), np.array([2.0])), [1])
    np.testing.assert_array_equal(_count_above(np.full(4, np.nan), np.array([0.0, 1.0])), [0, 0])


@pytest.mark.parametrize("t_true, cx, cy", [(0.3, 0.1, -0.05), (0.05, 0.0, 0.2), (0.9, -0.1, 0.0)])
def test_fit_recovers_exact_constrained_sphere(t_true, cx, cy):
    # pixels of a footprint disc sampled from the constrained sphere of cap height t (lengths
    # in units of a_f): the fit must return t and the centre with zero residual
    g = np.arange(-12, 13) / 12.0
    X, Y = np.meshgrid(g, g)
    inside = (X - cx) ** 2 + (Y - cy) ** 2 <= 1.0
    xs, ys = X[inside], Y[inside]
    R = (1 + t_true**2) / (2 * t_true)
    c = (1 - t_true**2) / (2 * t_true)
    hs = np.sqrt(R**2 - (xs - cx) ** 2 - (ys - cy) ** 2) - c
    ws, iw, free = fit_workspace()
    t, cost, x0, y0 = _fit_sphere(xs, ys, hs, 0.5 / 12, 0.5 / 12, ws, iw, free)
    assert t == pytest.approx(t_true, rel=1e-9)
    assert (x0, y0) == pytest.approx((cx, cy), abs=1e-9)
    assert cost < 1e-20 * xs.size


def smooth_crop(shape, seed):
    rng = np.random.default_rng(seed)
    z = ndimage.gaussian_filter(rng.standard_normal(shape), 4, mode="reflect")
    return z / z.std() * 4e-9


def test_cold_fits_do_not_depend_on_the_grid():
    z = smooth_crop((64, 72), 11)
    zc = z - z.mean()
    fine = np.linspace(zc.max() + 1e-9, zc.max() - 8e-9, 61)
    kw = dict(dx=DX, dy=DX, K=K, periodic=False, connectivity=4)
    a = curves_kernel(z, fine, HW, DP, **kw)
    b = curves_kernel(z, fine[::6], HW, DP, **kw)
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x[:, ::6], y)


def test_warm_start_equals_cold_on_a_smooth_bump():
    # one smooth bump quantised in 0.5 nm steps, four distances per step: between steps the
    # asperity keeps its pixels, so the warm start is used at most levels
    n = 48
    c = (np.arange(n) + 0.5) * DX
    X, Y = np.meshgrid(c, c)
    z = 6e-9 * np.exp(-((X - 24 * DX) ** 2 + (Y - 22 * DX) ** 2) / (2 * (10 * DX) ** 2))
    z = np.round(z / 0.5e-9) * 0.5e-9
    zc = z - z.mean()
    top = zc.max()
    d = top + 0.1e-9 - np.arange(40) * 0.125e-9
    kw = dict(dx=DX, dy=DX, K=K, periodic=False, connectivity=4)
    cold = curves_kernel(z, d, HW, DP, **kw)
    warm = curves_kernel(z, d, HW, DP, **kw, warm_start=True)
    big = np.abs(cold[0]) > 1e-3 * np.abs(cold[0]).max()
    rel = np.abs(warm[0] - cold[0])[big] / np.abs(cold[0])[big]
    # same local minimum; the two iterations stop at different points of its flat valley
    # (quantised, flat-topped asperity): measured 2.3e-8, a basin change would be >= 1e-5
    assert rel.max() < 1e-7, rel.max()
    np.testing.assert_array_equal(warm[4], cold[4])
    assert math.isfinite(float(np.nanmax(warm[5])))


def test_warm_start_hard_cases_stay_finite():
    # one- and two-pixel asperities, a plateau exactly at a level and a flat map
    z = np.zeros((20, 24))
    z[3, 3] = 2e-9
    z[10, 5:7] = [1.5e-9, 1.0e-9]
    z[14:19, 12:20] = 1.2e-9
    zc = z - z.mean()
    d = np.concatenate([np.linspace(zc.max() + 0.1e-9, zc[14, 12], 12), [zc[14, 12] - 1e-12]])
    kw = dict(dx=DX, dy=DX, K=K, periodic=False, connectivity=4)
    cold = curves_kernel(z, d, HW, DP, **kw)
    warm = curves_kernel(z, d, HW, DP, **kw, warm_start=True)
    assert np.all(np.isfinite(warm[0]))
    np.testing.assert_allclose(warm[0], cold[0], rtol=1e-8, atol=0)


@pytest.mark.parametrize("order", ["C", "F"])
def test_prepare_heights_fast_path_equals_masked_mean(order):
    # all-valid maps skip the masked copy; the mean must be the same bits as over the mask
    from roughstick.contact._rough_kernels import prepare_heights

    rng = np.random.default_rng(7)
    z = np.asarray(rng.normal(1e-7, 3e-9, size=(37, 51)), order=order)
    out, n = prepare_heights(z)
    assert n == z.size and out.flags.c_contiguous
    np.testing.assert_array_equal(out, z - z[np.isfinite(z)].mean())
    z[3, 4] = np.nan
    out, n = prepare_heights(z)
    assert n == z.size - 1 and np.isnan(out[3, 4])
    np.testing.assert_array_equal(out[np.isfinite(z)], z[np.isfinite(z)] - z[np.isfinite(z)].mean())
