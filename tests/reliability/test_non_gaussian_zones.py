"""Rare-event zones with a film's height distribution: the white-noise map is the translation
process of generate_surfaces, and the subset estimate is the crude Monte Carlo of its surfaces."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

import roughstick as rs
from roughstick.reliability import _surface as _s

pytestmark = pytest.mark.filterwarnings("ignore::roughstick.ValidityWarning")

SPACING, SHAPE, RH = 5e-9, (32, 32), 0.5


@pytest.fixture(scope="module")
def skewed():
    return rs.surface.height_distribution(skewness=1.0, kurtosis=5.0)


def _pooled(maps):
    return (maps - maps.mean(axis=(1, 2), keepdims=True)).ravel()


def test_noise_map_is_the_generator_in_law(skewed):
    """The same law as generate_surfaces(height_distribution=...) on a zone smaller than the
    PSD's correlation length (its mean mode carries power): heights about each map's mean plane
    agree in skewness and upper percentiles between the two independent draws, and both differ
    from the Gaussian surfaces of the same PSD."""
    psd = rs.datasets.family_psd("table4")
    f = rs.surface.noise_map(psd, shape=SHAPE, spacing=SPACING, height_distribution=skewed)
    rng = np.random.default_rng(4)
    mine = _pooled(np.stack([f(rng.standard_normal(f.noise_shape)) for _ in range(1500)]))
    gen = _pooled(rs.generate_surfaces(psd, n=1500, shape=SHAPE, spacing=SPACING, seed=9,
                                       height_distribution=skewed).values)
    gauss = _pooled(rs.generate_surfaces(psd, n=1500, shape=SHAPE, spacing=SPACING, seed=9).values)
    assert abs(stats.skew(mine) - stats.skew(gen)) < 0.15 < abs(stats.skew(gen) - stats.skew(gauss))
    for p in (99.0, 99.9):
        a, b, g = (np.percentile(x, p) for x in (mine, gen, gauss))
        assert abs(a / b - 1) < 0.06 < abs(b / g - 1)
    assert "johnson_su" in f.translation


def test_subset_on_a_skewed_film_is_its_crude_monte_carlo(skewed):
    """failure_probability(height_distribution=...) estimates P(Γ > t) of the film's own
    surfaces: its interval meets the binomial interval of crude Monte Carlo on 2000 surfaces of
    generate_surfaces (same distribution, same Eq. 16 response), and lies above the Gaussian
    film's crude estimate (the tall summits of a positively skewed film hold the flat more often)."""
    psd = rs.datasets.family_psd("table4")
    threshold = 0.10
    hw = float(rs.contact.water_height(RH).values)
    crude = {}
    for name, dist in (("skewed", skewed), ("gaussian", None)):
        f = _s.NoiseToSurface(psd, shape=SHAPE, spacing=SPACING, height_distribution=dist)
        response = _s.SurfaceResponse(f, relative_humidity=RH, water_height=hw)
        maps = rs.generate_surfaces(psd, n=2000, shape=SHAPE, spacing=SPACING, seed=21,
                                    height_distribution=dist).values
        k = sum(response.map_response(z, periodic=True) > threshold for z in maps)
        crude[name] = stats.binomtest(int(k), 2000).proportion_ci(0.99)
    ds = rs.reliability.failure_probability(
        psd, threshold=threshold, relative_humidity=RH, shape=SHAPE, spacing=SPACING,
        model="modified_dmt", height_distribution=skewed, n_per_level=1000, seed=3,
        check_failures=0)
    lo, hi = float(ds.failure_probability_lower), float(ds.failure_probability_upper)
    assert lo <= crude["skewed"].high and crude["skewed"].low <= hi
    assert float(ds.failure_probability) > crude["gaussian"].high
    assert "johnson_su" in ds.attrs["height_distribution"]
    back = rs.reliability.surface_from_noise(ds["failure_noise"].values[0].reshape(SHAPE), psd,
                                             shape=SHAPE, spacing=SPACING, height_distribution=skewed)
    f = _s.NoiseToSurface(psd, shape=SHAPE, spacing=SPACING, height_distribution=skewed)
    again = _s.SurfaceResponse(f, relative_humidity=RH, water_height=hw).map_response(
        back.values, periodic=True)
    assert again > threshold  # a stored failure sample regenerates the failing film surface
