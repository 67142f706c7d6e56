"""THE unit table of roughstick: validation and conversion of ``units`` to SI (no pint).

Every unit roughstick reads goes through this module: the ``units`` attribute of a DataArray
(:func:`require`), a float-or-DataArray parameter (:func:`as_si`), a string such as ``"5 nm"`` in
a config file or a reader argument (:func:`parse_quantity`), or a bare spelling (:func:`factor`).
Powers of a length (``m2`` for a height variance, ``m4`` for a PSD, ``m-2`` for a curvature
variance) are derived from the length table, so a spelling accepted for a length is accepted for
its powers too (``nm2``, ``um^4``, ``1/um2``). Stored values are SI.
"""

from __future__ import annotations

import numbers
import re

import numpy as np
import xarray as xr

__all__ = ["require", "as_si", "factor", "parse_quantity", "UnitsError", "KINDS"]


class UnitsError(ValueError):
    """A DataArray or a quantity has missing or incompatible ``units``."""


_LENGTH = {
    "m": 1.0, "meter": 1.0, "meters": 1.0, "metre": 1.0, "metres": 1.0,
    "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "micrometer": 1e-6, "micron": 1e-6,
    "nm": 1e-9, "nanometer": 1e-9, "A": 1e-10, "Å": 1e-10, "angstrom": 1e-10, "pm": 1e-12,
}


def _powers(power: int) -> dict[str, float]:
    """Spellings of a length unit raised to ``power`` (2, 4 or -2), e.g. nm2, nm^2, nm**2."""
    out: dict[str, float] = {}
    for unit, f in _LENGTH.items():
        if power > 0:
            spellings = (f"{unit}{power}", f"{unit}^{power}", f"{unit}**{power}")
        else:
            p = -power
            spellings = (f"{unit}-{p}", f"{unit}^-{p}", f"{unit}**-{p}", f"1/{unit}{p}", f"1/{unit}^{p}")
        for s in spellings:
            out[s] = float(f"{f**power:.15g}")  # 1e-18, not (1e-9)**2 = 1.0000000000000001e-18
    return out


#: Factor to SI of each accepted spelling, by kind of quantity.
_TABLE: dict[str, dict[str, float]] = {
    "length": _LENGTH,
    "area": _powers(2),
    "length4": _powers(4),
    "inverse_area": _powers(-2),
    "pressure": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9, "N m-2": 1.0, "N/m2": 1.0, "N/m^2": 1.0},
    "force": {"N": 1.0, "mN": 1e-3, "uN": 1e-6, "µN": 1e-6, "nN": 1e-9},
    "energy_per_area": {"J m-2": 1.0, "J/m2": 1.0, "J/m^2": 1.0, "N m-1": 1.0, "N/m": 1.0, "mJ m-2": 1e-3, "mJ/m2": 1e-3},
    "temperature": {"K": 1.0, "kelvin": 1.0},
    "dimensionless": {"1": 1.0, "": 1.0, "-": 1.0, "fraction": 1.0, "%": 1e-2, "percent": 1e-2},
    "angle": {"rad": 1.0, "radian": 1.0, "radians": 1.0, "deg": np.pi / 180, "degree": np.pi / 180, "degrees": np.pi / 180},
    "wavevector": {"rad m-1": 1.0, "rad/m": 1.0, "m-1": 1.0, "rad um-1": 1e6, "rad/um": 1e6, "rad nm-1": 1e9, "rad/nm": 1e9},
}

#: The SI spelling stored for each kind (what ``attrs['units']`` becomes).
_SI = {
    "length": "m", "area": "m2", "length4": "m4", "inverse_area": "m-2", "pressure": "Pa",
    "force": "N", "energy_per_area": "J m-2", "temperature": "K", "dimensionless": "1",
    "angle": "rad", "wavevector": "rad m-1",
}

#: The kinds of quantity the table knows (a kind's SI spelling is ``KINDS[kind]``).
KINDS = dict(_SI)

_POWER_KIND = {1: "length", 2: "area", 4: "length4", -2: "inverse_area"}


def _table(kind: str) -> dict[str, float]:
    if kind not in _TABLE:
        raise ValueError(f"unknown kind of quantity {kind!r}; roughstick knows {sorted(_TABLE)}.")
    return _TABLE[kind]


def _examples(kind: str) -> list[str]:
    table = _table(kind)
    if kind in ("area", "length4", "inverse_area"):  # the derived tables are long: show the usual ones
        return [k for k in table if k.split("^")[0].split("*")[0].rstrip("-0123456789").lstrip("1/")
                in ("m", "nm", "um", "µm") and "^" not in k and "*" not in k]
    return sorted(k for k in table if k)


def factor(units, kind: str, *, name: str = "input") -> float:
    """Factor that converts a value in ``units`` to the SI unit of ``kind``.

    Raises
    ------
    UnitsError
        ``units`` is None (missing) or not a spelling of ``kind`` in the table.

    Examples
    --------
    >>> from roughstick._core.units import factor
    >>> factor("nm", "length"), factor("um-2", "inverse_area")
    (1e-09, 1000000000000.0)
    """
    si = _SI[kind] if kind in _SI else None
    table = _table(kind)
    if units is None:
        raise UnitsError(
            f"{name!r} has no 'units' attribute, so roughstick cannot tell its scale. "
            f"Set it, e.g. da.attrs['units'] = {si!r} (stored values are SI)."
        )
    key = str(units).strip()
    if key in table:
        return table[key]
    raise UnitsError(
        f"{name!r} has units {units!r}, which is not a {kind} unit roughstick knows. "
        f"Use one of {_examples(kind)} (stored values are SI: {si!r}), "
        f"e.g. da.attrs['units'] = {si!r}."
    )


def require(da: xr.DataArray, kind: str, *, name: str | None = None) -> xr.DataArray:
    """Check that ``da`` carries a ``units`` attribute of dimension ``kind``; return it in SI.

    Parameters
    ----------
    da : xarray.DataArray
        Input with ``attrs['units']``.
    kind : str
        One of :data:`KINDS`: ``length``, ``area`` (m2), ``length4`` (m4), ``inverse_area``
        (m-2), ``pressure``, ``force``, ``energy_per_area``, ``temperature``, ``dimensionless``,
        ``angle``, ``wavevector``.
    name : str, optional
        Name used in error messages (defaults to ``da.name``).

    Returns
    -------
    xarray.DataArray
        ``da`` scaled to SI with ``attrs['units']`` set to the SI spelling. No copy is made when
        the factor is one. Lazy data stay lazy.

    Raises
    ------
    UnitsError
        If ``units`` is missing or not a unit of ``kind``.
    """
    if not isinstance(da, xr.DataArray):
        raise TypeError(
            f"{name or 'input'} must be an xarray.DataArray with a 'units' attribute, got "
            f"{type(da).__name__}; wrap a height map with roughstick.testing.make_topography("
            "values, spacing=...) or read it with roughstick.io.read_afm, other arrays with "
            "xr.DataArray(values, dims=..., attrs={'units': ...})."
        )
    label = name or (da.name if da.name is not None else "input")
    if "units" not in da.attrs:
        hint = ""
        if "unit" in da.attrs:
            hint = f" It has attrs['unit']={da.attrs['unit']!r}: rename it to 'units' (CF)."
        raise UnitsError(
            f"{label!r} has no 'units' attribute, so roughstick cannot tell its scale.{hint} "
            f"Set it, e.g. da.attrs['units'] = {_SI[kind]!r} (stored values are SI)."
        )
    f = factor(da.attrs["units"], kind, name=label)
    if f == 1.0:
        if da.attrs["units"] == _SI[kind]:
            return da
        out = da.copy(deep=False)
    else:
        out = da * f
        out.attrs = dict(da.attrs)
    out.attrs["units"] = _SI[kind]
    return out


def as_si(value, kind: str, *, name: str):
    """Accept a plain number/array (taken as SI) or a DataArray with ``units``; return SI.

    Plain numbers are returned as ``float`` (or ``numpy.ndarray``); DataArrays are converted with
    :func:`require` and returned as DataArrays so that they broadcast.
    """
    if isinstance(value, xr.DataArray):
        return require(value, kind, name=name)
    if isinstance(value, numbers.Number) and not isinstance(value, bool):
        return float(value)
    return np.asarray(value, dtype=float)


_NUM = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")


def parse_quantity(value, kind: str, *, name: str, power: int = 1) -> float:
    """A number (SI) or a string ``"<number> <unit>"`` → SI float.

    ``kind`` is a kind of :data:`KINDS`; with ``kind="length"``, ``power`` selects a power of a
    length (2: ``area``, 4: ``length4``, -2: ``inverse_area``), so ``"15.7 nm2"`` with
    ``power=2`` gives 1.57e-17 (m2). A string without a unit is taken as SI.

    Examples
    --------
    >>> from roughstick._core.units import parse_quantity
    >>> parse_quantity("5 nm", "length", name="spacing")
    5e-09
    >>> parse_quantity("5.08e-4 nm-2", "length", name="m4", power=-2)
    508000000000000.0
    >>> parse_quantity("289 rad/um", "wavevector", name="qmax")
    289000000.0
    """
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a number or a string with units, got {value!r}.")
    if isinstance(value, (int, float, np.integer, np.floating)):
        return float(value)
    if not isinstance(value, str):
        raise ValueError(f"{name} must be a number or a string with units, got {value!r}.")
    m = _NUM.match(value)
    if not m:
        raise ValueError(f"{name} = {value!r}: expected '<number> <unit>', e.g. '5 nm'.")
    number, unit = float(m.group(1)), m.group(2)
    if not unit:
        return number
    if kind == "length" and power != 1:
        if power not in _POWER_KIND or unit not in _TABLE[_POWER_KIND[power]]:
            raise UnitsError(
                f"{name} = {value!r}: expected a length unit to the power {power}, e.g. 'nm{power}'."
            )
        return number * _TABLE[_POWER_KIND[power]][unit]
    table = _table(kind)
    if unit not in table:
        raise UnitsError(
            f"{name} = {value!r}: unknown {kind} unit {unit!r}, which is not a {kind} unit roughstick "
            f"knows; use one of {_examples(kind)}."
        )
    return number * table[unit]
