"""The one verb for P(stuck): each method on its data, the same numbers as the function it
dispatches to, wrong combinations refused with the fix, the old names served with a warning."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.beam.sharp_front import stuck_probability_from_beams
from roughstick.stiction.risk import stuck_probability_from_sample

LENGTHS = [200e-6, 400e-6, 800e-6]


def _sample():
    g = np.random.default_rng(1).lognormal(-7, 1.5, (60, 3))
    return xr.DataArray(g, dims=("realization", "rh"), coords={"rh": [0.4, 0.6, 0.8]},
                        attrs={"units": "J m-2"})


def _bank(n=300):
    e = np.random.default_rng(3).lognormal(-6, 1.0, (n, 2))
    return xr.DataArray(e, dims=("law", "rh"), coords={"rh": [0.4, 0.6]}, attrs={"units": "J m-2"})


def test_the_verb_is_the_front_door():
    assert rs.stuck_probability is rs.reliability.stuck_probability
    assert "stuck_probability" in rs.__all__ and "stuck_probability" in rs.reliability.__all__


def test_count_on_a_sample_and_on_simulated_beams():
    g = _sample()
    xr.testing.assert_identical(rs.stuck_probability(g, beam_length=LENGTHS),
                                stuck_probability_from_sample(g, beam_length=LENGTHS))
    beams = rs.beam.simulate(_bank(), beam_length=[150e-6, 300e-6], n=40, seed=2)
    got = rs.stuck_probability(beams, confidence=0.9, interval="clopper-pearson")
    xr.testing.assert_identical(got, stuck_probability_from_beams(beams, confidence=0.9,
                                                                  interval="clopper-pearson"))
    # the crossing humidity reads both kinds of result
    assert "crossing_humidity" in rs.stiction.crossing_humidity(got, probability=0.5)


def test_beam_method_simulates_and_counts():
    bank = _bank()
    kw = dict(beam_length=[150e-6, 300e-6], n=40, seed=2, protocol="step_up")
    xr.testing.assert_identical(rs.stuck_probability(bank, method="beam", **kw),
                                stuck_probability_from_beams(rs.beam.simulate(bank, **kw)))


def test_subset_on_a_bank_and_on_a_psd():
    bank = _bank(2000)
    ds = rs.stuck_probability(bank, method="subset", beam_length=130e-6, n_per_level=200, seed=1,
                              target_cv=None)
    assert {"stiction_probability", "bank_stiction_probability", "coefficient_of_variation"} <= set(ds)
    mc = rs.stuck_probability(bank, method="monte_carlo", beam_length=130e-6, n_per_level=200, seed=1,
                              target_cv=None)
    assert mc.attrs["method"] == "monte_carlo"
    psd = rs.datasets.family_psd("table4")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        z = rs.stuck_probability(psd, method="monte_carlo", relative_humidity=0.5, shape=(16, 16),
                                 spacing=5e-9, beam_length=150e-6, n_per_level=20, target_cv=None,
                                 scheduler="sync", check_failures=0)
    assert z.attrs["beam_length"] == 150e-6 and int(z.n_evaluations) == 20


@pytest.mark.parametrize("call, match", [
    (lambda g, b, p: rs.stuck_probability(p, relative_humidity=0.5), "method='subset'"),
    (lambda g, b, p: rs.stuck_probability(b, beam_length=1e-4), "method='beam'"),
    (lambda g, b, p: rs.stuck_probability(g, method="beam"), "method='count'"),
    (lambda g, b, p: rs.stuck_probability(g, method="subset"), "method='count'"),
    (lambda g, b, p: rs.stuck_probability(p, method="beam"), "build_patch_bank"),
    (lambda g, b, p: rs.stuck_probability(g, method="bisection"), "method must be one of"),
])
def test_a_method_on_data_it_cannot_use_names_the_fix(call, match):
    with pytest.raises(ValueError, match=match):
        call(_sample(), _bank(), rs.datasets.family_psd("table4"))


@pytest.mark.parametrize("call, match", [
    (lambda g, b, p: rs.stuck_probability(g, target_cv=0.1), r"target_cv= is for method 'subset' / 'monte_carlo'"),
    (lambda g, b, p: rs.stuck_probability(g, n=10), r"n= is for method 'beam'"),
    (lambda g, b, p: rs.stuck_probability(g, chunks=7), r"chunks"),
    (lambda g, b, p: rs.stuck_probability(b, method="subset", beam_length=1e-4, shape=(8, 8)),
     r"shape= is for method"),
    (lambda g, b, p: rs.stuck_probability(p, method="subset", relative_humidity=0.5, shape=(8, 8),
                                          spacing=5e-9, protocol="step_up"), r"protocol= is for method"),
    (lambda g, b, p: rs.stuck_probability(p, method="subset", relative_humidity=0.5), r"shape=, spacing="),
    (lambda g, b, p: rs.stuck_probability(b, method="subset"), r"needs beam_length="),
    (lambda g, b, p: rs.stuck_probability(rs.beam.simulate(b, beam_length=2e-4, n=2), beam_length=1e-4),
     r"sel\(beam_length"),
    (lambda g, b, p: rs.stuck_probability(np.ones(3)), r"must be an xarray.DataArray"),
])
def test_a_keyword_the_method_does_not_read_is_refused(call, match):
    with pytest.raises(TypeError, match=match):
        call(_sample(), _bank(), rs.datasets.family_psd("table4"))


def test_the_interval_of_the_old_call_is_now_interval():
    beams = rs.beam.simulate(_bank(), beam_length=2e-4, n=4)
    with pytest.raises(ValueError, match=r"write interval='clopper-pearson'"):
        rs.stuck_probability(beams, method="clopper-pearson")


def _same(a, b):
    """Identical but for the time stamps of ``history`` (written a moment apart)."""
    a, b = a.copy(), b.copy()
    for x in (a, b):
        x.attrs.pop("history", None)
    xr.testing.assert_identical(a, b)


def test_old_names_warn_naming_the_new_call_and_give_the_same_numbers():
    g, bank = _sample(), _bank()
    new = rs.stuck_probability(g, beam_length=LENGTHS)
    with pytest.warns(DeprecationWarning, match=r"roughstick\.reliability\.stuck_probability") as rec:
        old = rs.stiction_probability(g, length=LENGTHS)
    assert any("beam_length" in str(w.message) for w in rec)  # length= is now beam_length=
    _same(old, new)
    with pytest.warns(DeprecationWarning, match=r"roughstick\.stiction\.risk_summary"):
        risk = rs.stiction_risk(g, length=LENGTHS, levels=[0.5])
    _same(risk, rs.stiction.risk_summary(g, beam_length=LENGTHS, probabilities=[0.5]))
    with pytest.warns(DeprecationWarning, match=r"roughstick\.beam\.simulate"):
        beams = rs.simulate_beams(bank, beam_length=2e-4, n_realization=5, seed=3)
    _same(beams, rs.beam.simulate(bank, beam_length=2e-4, n=5, seed=3))
    for old_name, new_name in (("beam_stiction_probability_subset", "reliability.stuck_probability"),
                               ("stiction_probability_subset", "reliability.stuck_probability"),
                               ("failure_probability", "reliability.failure_probability"),
                               ("subset_simulation", "reliability.subset_simulation"),
                               ("weakest_link", "reliability.weakest_link"),
                               ("build_patch_bank", "beam.build_patch_bank"),
                               ("beam_crack_length", "beam.crack_length")):
        with pytest.warns(DeprecationWarning, match=new_name.replace(".", r"\.")):
            getattr(rs, old_name)
    # the old subset call without method= now says which method it needs
    with pytest.warns(DeprecationWarning), pytest.raises(ValueError, match="method='subset'"):
        rs.beam_stiction_probability_subset(bank, beam_length=1e-4)
