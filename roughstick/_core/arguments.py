"""Rules for the scalar arguments of the public functions: sign, finiteness, integers, fractions
and plausible lengths, checked before any work starts.

:func:`check_number` checks one value against a rule of :data:`NUMBER_RULES`;
:func:`check_numbers` is the decorator that applies rules to a function's arguments before its
body runs, with the argument's default as the example of the fix. Arrays, DataArrays and strings
with units are left to the unit-aware checks of :mod:`roughstick._core.validate`, whose
:func:`~roughstick._core.validate.check_plausible_value` the ``"length"`` rule uses.
"""

from __future__ import annotations

import functools
import inspect
import math
import numbers

import numpy as np
import xarray as xr

from .validate import check_plausible_value

__all__ = ["NUMBER_RULES", "check_number", "check_numbers"]


#: What each rule of :func:`check_number` requires ("name=value: must be <this>").
NUMBER_RULES = {
    "finite": "a finite number",
    "positive": "a finite number > 0",
    "limit": "a number > 0 (inf: no limit)",
    "nonnegative": "a finite number >= 0",
    "fraction": "a fraction strictly between 0 and 1",
    "fraction0": "a fraction in [0, 1)",
    "fraction01": "a fraction in [0, 1]",
    "count": "an integer >= 1",
    "count0": "an integer >= 0",
    "seed": "an integer >= 0 (or None, a SeedSequence or a Generator)",
    "length": "a length in m, finite and > 0",
    "angle": "an angle in rad between 0 and pi",
}
#: Plausible lengths [m] of rule ``"length"`` (below: a slip in pm or fm; above: µm or nm typed as m).
PLAUSIBLE_ARGUMENT_LENGTH = (1e-13, 1e-2)


def _shown(value) -> str:
    """A value as the user would type it: 500, 0.001, nan, -1.0, True."""
    if isinstance(value, (bool, np.bool_)):
        return repr(bool(value))
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        return repr(float(value))
    return repr(value)


def check_number(value, name: str, rule, *, example=None, fix: str = ""):
    """Refuse a scalar argument that breaks ``rule``; return ``value`` unchanged.

    ``rule`` is a key of :data:`NUMBER_RULES` (a trailing ``"?"`` also accepts None) or a tuple
    of the allowed values. Plain real numbers (and 0-d arrays) are checked; strings, arrays,
    DataArrays and other objects pass unchanged (the unit-aware checks of the function take
    them). The error reads ``"name=value: must be ...; pass ..."``: the fix is ``fix``, else
    ``example`` (e.g. the default), else the rule's typical value.

    Raises
    ------
    TypeError
        A boolean or a complex number where a real number is needed.
    ValueError
        NaN, inf, a value of the wrong sign, a fraction outside (0, 1), a non-integer or
        negative count, a length implausible in m.

    Examples
    --------
    >>> from roughstick._core.arguments import check_number
    >>> check_number(0, "max_iterations", "count", example=500)
    Traceback (most recent call last):
    ...
    ValueError: max_iterations=0: must be an integer >= 1; pass e.g. max_iterations=500 (the default).
    """
    optional = isinstance(rule, str) and rule.endswith("?")
    key = rule[:-1] if optional else rule
    if value is None:
        if optional or key == "seed":
            return value
    elif isinstance(value, (str, bytes, xr.DataArray, xr.Dataset)) or (
            not isinstance(value, numbers.Number) and np.ndim(value) != 0):
        return value
    elif not isinstance(value, numbers.Number):
        if not (isinstance(value, np.ndarray) and value.dtype.kind in "biufc"):
            return value  # a Generator, a SeedSequence, a Material ...: the function's own checks
        value = value[()]
    what = (f"one of {', '.join(_shown(v) for v in key)}" if isinstance(key, tuple)
            else NUMBER_RULES[key])
    if optional:
        what += " (or None)"
    if fix:
        remedy = fix
    elif key == "angle" and isinstance(value, numbers.Real) and math.isfinite(value) and value > math.pi:
        remedy = f"radians: {name}=np.deg2rad({_shown(value)}) if it is in degrees"
    elif example is not None and example is not inspect.Parameter.empty:
        remedy = f"e.g. {name}={_shown(example)} (the default)"
    else:
        remedy = {"count": f"e.g. {name}=1", "count0": f"e.g. {name}=0", "seed": f"e.g. {name}=0",
                  "fraction": f"e.g. {name}=0.5"}.get(key, NUMBER_RULES.get(key, what))
    message = f"{name}={_shown(value)}: must be {what}; pass {remedy}."
    if value is None or isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(message)
    v = float(value)
    if isinstance(key, tuple):
        ok = any(v == float(a) for a in key)
    elif key == "limit":
        ok = v > 0
    elif not math.isfinite(v):
        ok = False
    elif key in ("count", "count0", "seed"):
        ok = v == int(v) and v >= (1 if key == "count" else 0)
    else:
        ok = {"finite": True, "positive": v > 0, "nonnegative": v >= 0, "fraction": 0 < v < 1,
              "fraction0": 0 <= v < 1, "fraction01": 0 <= v <= 1, "length": v > 0,
              "angle": 0 <= v <= math.pi}[key]
    if not ok:
        raise ValueError(message)
    if key == "length":
        low, high = PLAUSIBLE_ARGUMENT_LENGTH
        typical = example if isinstance(example, numbers.Real) and example > 0 else 1e-6
        check_plausible_value(v, name=name, kind="length", bounds=(low, high, typical),
                              what="a length in a MEMS contact")
    return value


def check_numbers(**rules):
    """Decorator: check the named scalar arguments of a public function before its body runs.

    ``rules`` maps argument names to rules of :func:`check_number`; the error's example is the
    argument's default. The rules are kept on the function as ``__number_rules__`` (the sweep
    of tests/test_numeric_arguments.py reads them).

    Examples
    --------
    >>> from roughstick._core.arguments import check_numbers
    >>> @check_numbers(tolerance="positive", max_iterations="count")
    ... def solve(*, tolerance=1e-3, max_iterations=500):
    ...     return tolerance
    >>> solve(tolerance=float("nan"))
    Traceback (most recent call last):
    ...
    ValueError: tolerance=nan: must be a finite number > 0; pass e.g. tolerance=0.001 (the default).
    """
    def decorate(func):
        sig = inspect.signature(func)
        unknown = sorted(set(rules) - set(sig.parameters))
        if unknown:
            raise TypeError(f"check_numbers: {func.__qualname__} has no argument(s) {unknown}")
        defaults = {n: sig.parameters[n].default for n in rules}

        @functools.wraps(func)
        def checked(*args, **kwargs):
            try:
                given = sig.bind(*args, **kwargs).arguments
            except TypeError:
                return func(*args, **kwargs)  # the function's own message for a wrong call
            for name, value in given.items():
                if name in rules:
                    check_number(value, name, rules[name], example=defaults[name])
            return func(*args, **kwargs)

        checked.__number_rules__ = dict(rules)
        return checked

    return decorate
