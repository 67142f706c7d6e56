"""Tests of roughstick.stiction.risk: stiction probability, crossings, measured points, plots.

Stand-in Monte-Carlo samples of Gamma are lognormal, for which the stiction probability and the
crack-length quantiles are known in closed form.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from scipy import stats

import roughstick as rs
from conftest import lognormal_gamma
from roughstick._core.units import UnitsError
from roughstick.testing import raise_if_dask_computes

K = 1.5 * 164e9 * (1.9e-6) ** 2 * (2.62e-6) ** 3  # 3/2 E h^2 t^3 of the paper's beams [N m^2]


def test_probability_counts_and_ecdf_of_crack_length():
    g, _ = lognormal_gamma(n=101)
    lengths = np.array([150e-6, 250e-6, 400e-6, 700e-6, 1500e-6])
    p = rs.stuck_probability(g, beam_length=lengths)
    assert set(p.stiction_probability.dims) == {"rh", "beam_length"}
    s = rs.stiction.crack_length_from_adhesive_energy(g).values  # (realization, rh)
    for i, bl in enumerate(lengths):
        ecdf = (s < bl).mean(axis=0)  # fraction of beams whose predicted crack is shorter than bl
        np.testing.assert_allclose(p.stiction_probability.isel(beam_length=i).transpose("rh").values, ecdf)
        brute = (g.values > K / bl**4).sum(axis=0)
        np.testing.assert_array_equal(p.n_stuck.isel(beam_length=i).transpose("rh").values, brute)
    assert (p.n_samples == 101).all()
    np.testing.assert_allclose(p.critical_adhesive_energy.values, K / lengths**4)
    assert p.stiction_probability.attrs["units"] == "1"
    assert p.beam_length.attrs["units"] == "m"
    assert p.attrs["confidence_level"] == 0.95 and p.attrs["interval_method"] == "wilson"
    assert "10.1016/j.cam.2015.02.022" in p.attrs["references"]


def test_probability_monotone_in_beam_length():
    g, _ = lognormal_gamma(n=300, sigma=1.5)
    lengths = np.geomspace(50e-6, 3e-3, 60)
    p = rs.stuck_probability(g, beam_length=lengths).stiction_probability.transpose("rh", "beam_length")
    assert np.all(np.diff(p.values, axis=-1) >= 0)
    assert p.values[:, 0].max() < 0.05 and p.values[:, -1].min() > 0.95  # spans the range
    # and it rises with RH for this stand-in (median Gamma grows with RH)
    assert np.all(np.diff(p.sel(beam_length=lengths[30]).values) >= 0)


def test_probability_agrees_with_closed_form_and_interval_covers():
    """Lognormal Gamma: P = 1 - Phi((ln Gc - mu)/sigma). The 95 % Wilson interval from n = 60
    members covers it in about 95 % of 400 independent ensembles."""
    n, trials, sigma, median = 60, 400, 0.7, 2e-3
    rng = np.random.default_rng(1)
    vals = median * np.exp(sigma * rng.standard_normal((trials, n)))
    g = xr.DataArray(vals, dims=("trial", "realization"), attrs={"units": "J m-2"})
    length = 300e-6
    truth = stats.norm.sf((np.log(K / length**4) - np.log(median)) / sigma)
    assert 0.2 < truth < 0.8
    for method in ("wilson", "clopper-pearson"):
        p = rs.stuck_probability(g, beam_length=length, interval=method)
        cover = ((p.stiction_probability_lower <= truth) & (truth <= p.stiction_probability_upper)).mean()
        assert 0.92 <= float(cover) <= 0.99, (method, float(cover))
        assert abs(float(p.stiction_probability.mean()) - truth) < 4 * np.sqrt(truth * (1 - truth) / (n * trials))


def test_probability_nan_members_and_errors():
    g, _ = lognormal_gamma(n=10)
    g2 = g.copy()
    g2[0, 0] = np.nan
    p = rs.stuck_probability(g2, beam_length=400e-6)
    assert int(p.n_samples.isel(rh=0)) == 9 and int(p.n_samples.isel(rh=1)) == 10
    ref = (g.values[1:, 0] > K / 400e-6**4).mean()
    assert float(p.stiction_probability.isel(rh=0)) == pytest.approx(ref)
    allnan = rs.stuck_probability(g * np.nan, beam_length=400e-6)
    assert allnan.stiction_probability.isnull().all() and allnan.stiction_probability_lower.isnull().all()
    with pytest.raises(ValueError, match="no 'sample' dimension"):
        rs.stuck_probability(g, dim="sample")
    with pytest.raises(TypeError, match="must be an xarray.DataArray"):
        rs.stuck_probability(np.ones(4))
    with pytest.raises(UnitsError):
        rs.stuck_probability(g.assign_attrs(units="J"))
    with pytest.raises(ValueError, match="must be >= 0"):
        rs.stuck_probability(-g)
    # a summary Dataset is accepted
    ds = xr.Dataset({"adhesive_energy": g})
    xr.testing.assert_identical(rs.stuck_probability(ds).stiction_probability,
                                rs.stuck_probability(g).stiction_probability)


def test_probability_backends_lazy(backend):
    g, _ = lognormal_gamma(n=40)
    gi = backend(g, chunks={"realization": 10, "rh": 2})
    with raise_if_dask_computes():
        p = rs.stuck_probability(gi, beam_length=[200e-6, 500e-6])
    assert isinstance(p.stiction_probability.data, type(gi.data))
    xr.testing.assert_allclose(p.compute(), rs.stuck_probability(g, beam_length=[200e-6, 500e-6]))


def _logit(x):
    return np.log(x / (1 - x))


def test_crossing_humidity_interpolation_and_edges():
    rh = [0.3, 0.4, 0.5, 0.6]
    p = xr.DataArray(
        [[0.0, 0.2, 0.6, 1.0], [0.6, 0.7, 0.8, 0.9], [0.0, 0.1, 0.1, 0.2], [0.0, 0.7, 0.2, 0.9]],
        dims=("beam_length", "rh"), coords={"rh": rh, "beam_length": [1, 2, 3, 4]},
    )
    c = rs.stiction.crossing_humidity(p, probability=0.5).crossing_humidity.values
    # between 0.2 and 0.6: linear in logit(p); next to a counted 0: linear in p
    logit_cross = 0.4 + 0.1 * (_logit(0.5) - _logit(0.2)) / (_logit(0.6) - _logit(0.2))
    np.testing.assert_allclose(c, [logit_cross, -np.inf, np.inf, 0.3 + 0.1 * 0.5 / 0.7])
    assert rs.stiction.crossing_humidity(p, probability=0.5).crossing_humidity.attrs["units"] == "1"
    with pytest.raises(ValueError, match="strictly increasing"):
        rs.stiction.crossing_humidity(p.isel(rh=[1, 0, 2]))
    with pytest.raises(ValueError, match="probability"):
        rs.stiction.crossing_humidity(p, probability=1.0)
    with pytest.raises(ValueError, match="rechunk|Rechunk"):
        rs.stiction.crossing_humidity(p.chunk({"rh": 2}))


def test_crossing_humidity_bounds_order_and_consistency():
    g, _ = lognormal_gamma(n=80, rh=np.arange(0.30, 0.951, 0.05))
    p = rs.stuck_probability(g, beam_length=[300e-6, 400e-6])
    c = rs.stiction.crossing_humidity(p, probability=0.5)
    assert np.all(c.crossing_humidity_lower <= c.crossing_humidity)
    assert np.all(c.crossing_humidity <= c.crossing_humidity_upper)
    # the estimate interpolates the probability: evaluating it there gives the level
    for bl in p.beam_length.values:
        x = float(c.crossing_humidity.sel(beam_length=bl))
        if np.isfinite(x):
            pp = p.stiction_probability.sel(beam_length=bl)
            # logit-linear between the bracketing humidities (or linear next to a 0 or a 1)
            j = int(np.searchsorted(pp.rh.values, x))
            r0, r1 = pp.rh.values[j - 1], pp.rh.values[j]
            p0, p1 = float(pp[j - 1]), float(pp[j])
            t = (x - r0) / (r1 - r0)
            back = (1 / (1 + np.exp(-(_logit(p0) + t * (_logit(p1) - _logit(p0)))))
                    if 0 < p0 and p1 < 1 else p0 + t * (p1 - p0))
            assert back == pytest.approx(0.5)


def test_small_probabilities_cross_where_the_log_plot_shows():
    """1e-4 at RH 60 % and 0.1 at 70 %: 1e-3 is a third of the way on a log axis (≈ 63.3 %);
    linear interpolation in p put it at 60.09 %, next to the point 10× below the level."""
    p = xr.DataArray([1e-4, 0.1], dims="rh", coords={"rh": [0.6, 0.7]})
    x = float(rs.stiction.crossing_humidity(p, probability=1e-3).crossing_humidity)
    assert x == pytest.approx(0.6 + 0.1 * (_logit(1e-3) - _logit(1e-4)) / (_logit(0.1) - _logit(1e-4)))
    assert 0.632 < x < 0.634


def test_crossing_length_is_quantile_and_consistent_with_probability():
    g, _ = lognormal_gamma(n=57)
    for level in (0.1, 0.5, 0.9):
        cl = rs.stiction.crossing_length(g, probability=level)
        lp = cl.crossing_length
        assert lp.dims == ("rh",)
        # a length DataArray over rh broadcasts: one beam length per humidity
        above = rs.stuck_probability(g, beam_length=lp * (1 + 1e-9)).stiction_probability
        below = rs.stuck_probability(g, beam_length=lp * (1 - 1e-9)).stiction_probability
        assert above.dims == ("rh",)
        # P(stuck | l) for l just above l_p reaches the level; just below it does not
        assert np.all(above.values >= level) and np.all(below.values < level)
        assert np.all(cl.crossing_length_lower <= lp) and np.all(lp <= cl.crossing_length_upper)


def test_crossing_length_interval_covers_true_quantile():
    """ln s = (ln K - ln Gamma)/4 is normal: the true p-quantile of s is known. The
    distribution-free order-statistic interval must cover it in >= ~95 % of ensembles."""
    n, trials, sigma, median, level = 40, 400, 0.8, 5e-4, 0.2
    rng = np.random.default_rng(3)
    g = xr.DataArray(median * np.exp(sigma * rng.standard_normal((trials, n))),
                     dims=("trial", "realization"), attrs={"units": "J m-2"})
    truth = np.exp((np.log(K) - np.log(median)) / 4 + sigma / 4 * stats.norm.ppf(level))
    cl = rs.stiction.crossing_length(g, probability=level)
    cover = ((cl.crossing_length_lower <= truth) & (truth <= cl.crossing_length_upper)).mean()
    assert 0.93 <= float(cover) <= 1.0
    # too small a sample cannot bound the upper side of a high quantile
    tiny = rs.stiction.crossing_length(g.isel(trial=0, realization=slice(0, 3)), probability=0.9)
    assert np.isinf(float(tiny.crossing_length_upper))


def test_crossing_length_lazy(backend):
    g, _ = lognormal_gamma(n=30)
    gi = backend(g, chunks={"realization": 7})
    with raise_if_dask_computes():
        cl = rs.stiction.crossing_length(gi, probability=0.3)
    assert isinstance(cl.crossing_length.data, type(gi.data))
    xr.testing.assert_allclose(cl.compute(), rs.stiction.crossing_length(g, probability=0.3))


def test_risk_summary_dataset():
    g, mu = lognormal_gamma(n=41, rh=np.arange(0.3, 0.951, 0.05))
    r = rs.stiction.risk_summary(g, beam_length=[250e-6, 350e-6, 500e-6], probabilities=[0.1, 0.5])
    assert r.crossing_humidity.dims == ("probability_level", "beam_length")
    assert set(r.crossing_length.dims) == {"probability_level", "rh"}
    assert set(r.adhesive_energy_quantile.dims) == {"quantile", "rh"}
    # median crack length is the crack length of the median Gamma (odd n: exact order statistic)
    med_s = r.crack_length_quantile.sel(quantile=0.5)
    np.testing.assert_allclose(med_s.values,
                               rs.stiction.crack_length_from_adhesive_energy(g.median("realization")).values, rtol=1e-12)
    # the median of s is the 0.5 crossing length up to the order-statistic convention (n odd: equal)
    np.testing.assert_allclose(r.crossing_length.sel(probability_level=0.5).values, med_s.values, rtol=1e-12)
    for v in r.data_vars.values():
        assert "units" in v.attrs and "long_name" in v.attrs, v.name
    for c in ("rh", "beam_length", "probability_level", "quantile"):
        assert r[c].attrs["units"] == "1" if c != "beam_length" else r[c].attrs["units"] == "m"
    with pytest.raises(ValueError, match="probabilities"):
        rs.stiction.risk_summary(g, probabilities=[0.0])


def test_measured_adhesion_points():
    m = rs.stiction.measured_adhesion([0.4, 0.6, 0.8], crack_length=xr.DataArray([500.0, 420.0, 380.0], dims="p", attrs={"units": "um"}))
    np.testing.assert_allclose(m.adhesive_energy.values, K / (np.array([500e-6, 420e-6, 380e-6]) ** 4))
    assert m.attrs["given"] == "crack_length" and m.sizes["point"] == 3
    m2 = rs.stiction.measured_adhesion(xr.DataArray([40.0, 60.0], dims="p", attrs={"units": "%"}), adhesive_energy=[1e-4, 2e-4])
    np.testing.assert_allclose(m2.rh.values, [0.4, 0.6])
    np.testing.assert_allclose(m2.crack_length.values, (K / np.array([1e-4, 2e-4])) ** 0.25)
    with pytest.raises(ValueError, match="exactly one"):
        rs.stiction.measured_adhesion([0.5], crack_length=[1e-4], adhesive_energy=[1e-3])
    with pytest.raises(ValueError, match="equal length"):
        rs.stiction.measured_adhesion([0.5, 0.6], crack_length=[1e-4])
    with pytest.raises(ValueError, match="between 0 and 1"):
        rs.stiction.measured_adhesion([50.0], crack_length=[1e-4])


def test_plots_smoke():
    import matplotlib.pyplot as plt

    from roughstick import plotting

    g, _ = lognormal_gamma(n=30, rh=np.arange(0.3, 0.951, 0.05))
    risks = [rs.stiction.risk_summary(g * f, beam_length=[250e-6, 400e-6], probabilities=[0.5]) for f in (1.0, 1.5)]
    both = xr.concat(risks, dim=xr.DataArray(["none", "paper"], dims="adsorbed_layer", name="adsorbed_layer"))
    meas = rs.stiction.measured_adhesion([0.4, 0.7], crack_length=[420e-6, 380e-6], label="my beams")
    ax = plotting.plot_stiction_probability(risks[0], level=0.5)
    assert len(ax.lines) >= 2
    plotting.plot_stiction_vs_length(risks[0], rh=[0.5, 0.9])
    ax = plotting.plot_adhesive_energy_band(risks[0], measured=meas)
    assert ax.get_yscale() == "log"
    plotting.plot_crack_length_band(risks[0], measured=meas)
    fig = plotting.plot_cantilever_comparison(both, measured=meas)
    assert len(fig.axes) == 2
    with pytest.raises(ValueError, match="layer="):
        plotting.plot_stiction_probability(both)
    with pytest.raises(ValueError, match="risk_summary"):
        plotting.plot_adhesive_energy_band(xr.Dataset({"a": 1.0}))
    plt.close("all")


def test_a_zero_estimate_next_to_the_crossing_keeps_the_interval_ordered():
    """Subset simulation's 0 (below its resolution, upper bound 2e-10) at 65 % and 0.09 at 70 %:
    the upper probability bound crosses 1e-3 log-linearly (68.8 %), the lower bound (0 too) can
    only say 'by 70 %', and the estimate, linear in p next to its 0 (65.05 %), is kept inside
    that interval instead of before it (a run of session 6 printed [0.688, 0.651])."""
    rh = [0.6, 0.65, 0.7]
    ds = xr.Dataset({
        "stiction_probability": ("rh", [0.0, 0.0, 0.092]),
        "stiction_probability_lower": ("rh", [0.0, 0.0, 0.069]),
        "stiction_probability_upper": ("rh", [2.5e-10, 1.9e-10, 0.126]),
    }, coords={"rh": rh})
    c = rs.stiction.crossing_humidity(ds, probability=1e-3)
    lo = 0.65 + 0.05 * (_logit(1e-3) - _logit(1.9e-10)) / (_logit(0.126) - _logit(1.9e-10))
    assert float(c.crossing_humidity_lower) == pytest.approx(lo)
    assert float(c.crossing_humidity_upper) == 0.7
    assert float(c.crossing_humidity_lower) <= float(c.crossing_humidity) <= float(c.crossing_humidity_upper)
    assert c.crossing_humidity.attrs["units"] == "1"
