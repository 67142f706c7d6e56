"""Pixel-size sensitivity of the adhesion summaries (resolution_study, resample_pixels)."""

from __future__ import annotations

import numpy as np
import pytest

import roughstick as rs
from roughstick.testing import make_topography


def smooth_bumps(n=64, spacing=5e-9):
    """A band-limited periodic surface (a few long waves): resolved at any of these pixels."""
    x = np.arange(n) * spacing
    L = n * spacing
    X, Y = np.meshgrid(x, x)
    z = 2e-9 * (np.cos(2 * np.pi * X / L) * np.cos(2 * np.pi * Y / L)
                + 0.5 * np.sin(4 * np.pi * X / L + 0.3))
    return make_topography(z, spacing=spacing, periodic=True)


def test_block_average_and_fourier_interpolation():
    h = smooth_bumps()
    coarse = rs.contact.resample_pixels(h, 2)
    assert coarse.shape == (32, 32)
    assert float(coarse.x[1] - coarse.x[0]) == pytest.approx(10e-9)
    np.testing.assert_allclose(coarse.values, h.values.reshape(32, 2, 32, 2).mean(axis=(1, 3)))
    fine = rs.contact.resample_pixels(h, 0.5)
    assert fine.shape == (128, 128)
    # band-limited: the interpolated map keeps the original samples and the analytic surface
    np.testing.assert_allclose(fine.values[::2, ::2], h.values, atol=1e-12 * 2e-9)
    xf = np.arange(128) * 2.5e-9
    L = 64 * 5e-9
    X, Y = np.meshgrid(xf, xf)
    exact = 2e-9 * (np.cos(2 * np.pi * X / L) * np.cos(2 * np.pi * Y / L)
                    + 0.5 * np.sin(4 * np.pi * X / L + 0.3))
    np.testing.assert_allclose(fine.values, exact, atol=1e-6 * 2e-9)
    assert rs.contact.resample_pixels(h, 1).equals(h) or np.array_equal(rs.contact.resample_pixels(h, 1), h)


def test_bad_factors():
    h = smooth_bumps()
    for bad in (1.5, 0.3, 0, -2):
        with pytest.raises(ValueError):
            rs.contact.resample_pixels(h, bad)
    with pytest.raises(ValueError, match="too small"):
        rs.contact.resample_pixels(smooth_bumps(n=16), 8)
    with pytest.raises(ValueError, match="exactly one"):
        rs.contact.resolution_study(relative_humidity=0.7)


def test_a_resolved_surface_does_not_move_with_the_pixel():
    h = smooth_bumps()
    r = rs.contact.resolution_study(h, relative_humidity=0.9, factors=(0.5, 1, 2))
    assert list(r.pixel_size.values) == pytest.approx([2.5e-9, 5e-9, 10e-9])
    assert float(r.relative_change_adhesive_energy.sel(pixel_size=5e-9)) == 0.0
    np.testing.assert_array_less(np.abs(r.relative_change_adhesive_energy.values), 0.05)
    np.testing.assert_array_less(np.abs(r.relative_change_equilibrium_distance.values), 0.02)
    assert "Fourier" in r.attrs["resampling"]


def test_a_rough_surface_at_low_humidity_is_pixel_sensitive_and_says_so():
    psd = rs.datasets.family_psd("S1")
    r = rs.contact.resolution_study(psd=psd, shape=64, spacing=5e-9, seed=3, relative_humidity=0.3,
                            factors=(0.5, 1, 2))
    assert r.sizes["pixel_size"] == 3
    assert "generated from the PSD" in r.attrs["resampling"]
    assert np.all(np.isfinite(r.adhesive_energy))
