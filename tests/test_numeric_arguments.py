"""Every numeric argument of every public function is checked before any work starts.

The sweep: for each public callable of ``rs.__all__`` and of the stage namespaces' ``__all__``
(``rs.beam.simulate``, ...) and each of its arguments whose default is
a number, NaN, inf and (where the default is positive) a negative value and zero must raise a
ValueError or TypeError whose message names the argument. The other arguments are a sentinel
object no function can use, so a check that trips only after some work (or not at all) fails
here with another error. Values that are legal for a given argument are listed, with the
reason, in ``LEGAL``.
"""

from __future__ import annotations

import inspect
import math
import numbers
import re

import pytest

import roughstick as rs
from roughstick._core.arguments import check_number, check_numbers

#: (public name, argument) -> the bad values that are legal there ("negative", "zero"), and why.
LEGAL = {
    # auxetic solids have nu < 0, and nu = 0 (cork) exists: the range is (-1, 0.5]
    ("Material", "poisson_ratio"): {"negative", "zero"},
    # a distance grid may start at or below the mean plane (in units of the rms height)
    ("cantilever_distance_grid", "lower"): {"negative", "zero"},
    ("distance_grid", "lower"): {"negative", "zero"},
    ("failure_probability", "lower"): {"negative", "zero"},
    # 0 switches a step off: no BEM re-check of the tail / of the failures, no retry, no
    # bisection round, no wait for a distributed scheduler
    ("build_patch_bank", "check_tail"): {"zero"},
    ("failure_probability", "check_failures"): {"zero"},
    ("bem_curves", "retries"): {"zero"},
    ("fft_bem_curves", "refine"): {"zero"},
    ("run", "connect_timeout"): {"zero"},
    # the cheap model alone; no further fft_bem sub-zones beside the random pairs
    ("strip_stuck_probability", "n_accurate"): {"zero"},
    ("strip_stuck_probability", "n_tail"): {"zero"},
    # no adsorbed layer; a layer at every humidity
    ("step_adsorbed_layer", "thickness"): {"zero"},
    ("step_adsorbed_layer", "onset"): {"zero"},
    # no NaN pixel tolerated
    ("level", "max_nan_fraction"): {"zero"},
    # inf accepts the closest Eq. 37 PSD whatever its residual
    ("fit_self_affine", "solver_tolerance"): {"inf"},
}
#: Public classes that are results, not inputs (their fields are set by the solver).
RESULTS = {"CohesiveRelease"}


class _Unusable:
    """Stands for every argument the sweep does not test: no function can use it."""


#: The stage namespaces whose public functions the sweep covers beside ``rs.__all__``.
NAMESPACES = ("io", "surface", "contact", "ensemble", "stiction", "beam", "reliability")


def _public():
    """(name, object) of every public callable once: ``rs.<name>``, else ``<namespace>.<name>``."""
    seen = set()
    for ns in ("",) + NAMESPACES:
        mod = getattr(rs, ns) if ns else rs
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name)
            if id(obj) not in seen:
                seen.add(id(obj))
                yield (f"{ns}.{name}" if ns else name), obj


def _cases():
    for name, obj in _public():
        if not callable(obj) or name.rsplit(".", 1)[-1] in RESULTS:
            continue
        try:
            sig = inspect.signature(obj)
        except (TypeError, ValueError):
            continue
        for p in sig.parameters.values():
            d = p.default
            if not isinstance(d, numbers.Real) or isinstance(d, bool):
                continue
            bad = {"nan": math.nan, "inf": math.inf}
            if d > 0:
                bad.update(negative=-d, zero=type(d)(0))
            for what, value in bad.items():
                if what not in LEGAL.get((name.rsplit(".", 1)[-1], p.name), ()):
                    yield pytest.param(name, p.name, value, id=f"{name}-{p.name}={what}")


def _call(name, arg, value):
    obj = rs
    for part in name.split("."):
        obj = getattr(obj, part)
    args, kwargs = [], {arg: value}
    for p in inspect.signature(obj).parameters.values():
        if p.name == arg or p.default is not inspect.Parameter.empty:
            continue
        if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD):
            args.append(_Unusable())
        elif p.kind == p.KEYWORD_ONLY:
            kwargs[p.name] = _Unusable()
    return obj(*args, **kwargs)


CASES = list(_cases())


def test_the_sweep_covers_the_public_api():
    # the numeric arguments of the solvers, samplers and statistics are all in the sweep
    names = {c.values[0] for c in CASES}
    assert {"contact.fft_bem_curves", "contact.bem_curves", "beam.simulate",
            "reliability.subset_simulation", "beam.build_patch_bank", "ensemble.run",
            "confidence_band", "contact.kelvin_radius", "stuck_probability"} <= names
    assert len(CASES) > 200


@pytest.mark.parametrize("name, arg, value", CASES)
def test_bad_numeric_argument_is_refused_by_name(name, arg, value):
    with pytest.raises((ValueError, TypeError), match=rf"\b{re.escape(arg)}\b"):
        _call(name, arg, value)


def test_legal_values_of_the_allow_list_are_accepted():
    """The allow-list is not a blanket: those values pass the argument checks."""
    rs.Material(poisson_ratio=-0.2)
    rs.Material(poisson_ratio=0.0)
    assert "residual_m2" in rs.surface.fit_self_affine(m0=1e-17, m2=0.5, m4=1e12, qmax=2.89e8, solver_tolerance=math.inf)
    model = rs.contact.step_adsorbed_layer(thickness=0.0, onset=0.0)
    assert float(rs.contact.adsorbed_layer(0.5, layer_model=model)) == 0.0
    d = rs.ensemble.distance_grid(m0=16e-18, shape=(64, 64), n=10, relative_humidity=[0.5], lower=0.0)
    assert float(d[0]) == 0.0


def test_rules_and_messages():
    assert check_number(3, "n", "count") == 3
    assert check_number(3.0, "n", "count") == 3.0  # a whole number written as a float
    assert check_number(None, "n", "count?") is None
    assert check_number("2 nm", "spacing", "length") == "2 nm"  # strings go to the unit parser
    with pytest.raises(ValueError, match=r"^n=2\.5: must be an integer >= 1; pass e\.g\. n=1\.$"):
        check_number(2.5, "n", "count")
    with pytest.raises(TypeError, match=r"n=True: must be an integer >= 1"):
        check_number(True, "n", "count")
    with pytest.raises(TypeError, match=r"n=None: must be an integer >= 1"):
        check_number(None, "n", "count")
    with pytest.raises(ValueError, match=r"seed=-1: must be an integer >= 0"):
        check_number(-1, "seed", "seed")
    with pytest.raises(ValueError, match=r"connectivity=6: must be one of 4, 8"):
        check_number(6, "connectivity", (4, 8))
    with pytest.raises(ValueError, match=r"level=1\.0: must be a fraction strictly between 0 and 1"):
        check_number(1.0, "level", "fraction")
    with pytest.raises(ValueError, match=r"spacing=5 m is implausible.*looks like nm.*spacing=5e-9"):
        check_number(5, "spacing", "length", example=5e-9)
    with pytest.raises(ValueError, match=r"contact_angle_1=30\.0: must be an angle in rad.*np\.deg2rad\(30\.0\)"):
        check_number(30.0, "contact_angle_1", "angle", example=0.0)

    @check_numbers(tolerance="positive")
    def f(x, *, tolerance=1e-3):
        return x

    assert f(1, tolerance=0.5) == 1 and f.__number_rules__ == {"tolerance": "positive"}
    with pytest.raises(ValueError, match=r"tolerance=-0\.001: must be a finite number > 0; pass e\.g\. "
                                         r"tolerance=0\.001 \(the default\)\."):
        f(1, tolerance=-1e-3)
    with pytest.raises(TypeError, match="check_numbers: .* has no argument"):
        check_numbers(tol="positive")(f)
