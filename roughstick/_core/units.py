"""Validation and conversion of ``units`` attributes to SI (a small table, no pint)."""

from __future__ import annotations

import numbers

import numpy as np
import xarray as xr

__all__ = ["require", "as_si", "UnitsError"]


class UnitsError(ValueError):
    """A DataArray has missing or incompatible ``units``."""


# factor to SI for each accepted spelling, by dimension kind
_TABLE: dict[str, dict[str, float]] = {
    "length": {
        "m": 1.0, "meter": 1.0, "meters": 1.0, "metre": 1.0, "metres": 1.0,
        "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "micrometer": 1e-6, "micron": 1e-6,
        "nm": 1e-9, "nanometer": 1e-9, "A": 1e-10, "Å": 1e-10, "angstrom": 1e-10, "pm": 1e-12,
    },
    "pressure": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9, "N m-2": 1.0, "N/m2": 1.0, "N/m^2": 1.0},
    "force": {"N": 1.0, "mN": 1e-3, "uN": 1e-6, "µN": 1e-6, "nN": 1e-9},
    "energy_per_area": {"J m-2": 1.0, "J/m2": 1.0, "J/m^2": 1.0, "N m-1": 1.0, "N/m": 1.0, "mJ m-2": 1e-3, "mJ/m2": 1e-3},
    "temperature": {"K": 1.0, "kelvin": 1.0},
    "dimensionless": {"1": 1.0, "": 1.0, "-": 1.0, "fraction": 1.0, "%": 1e-2, "percent": 1e-2},
    "angle": {"rad": 1.0, "radian": 1.0, "radians": 1.0, "deg": np.pi / 180, "degree": np.pi / 180, "degrees": np.pi / 180},
    "wavevector": {"rad m-1": 1.0, "rad/m": 1.0, "m-1": 1.0, "rad um-1": 1e6, "rad/um": 1e6, "rad nm-1": 1e9, "rad/nm": 1e9},
}

_SI = {
    "length": "m", "pressure": "Pa", "force": "N", "energy_per_area": "J m-2", "temperature": "K",
    "dimensionless": "1", "angle": "rad", "wavevector": "rad m-1",
}


def _factor(units: str, kind: str, name: str) -> float:
    table = _TABLE[kind]
    key = units.strip()
    if key in table:
        return table[key]
    raise UnitsError(
        f"{name!r} has units {units!r}, which is not a {kind} unit roughstick knows. "
        f"Use one of {sorted(k for k in table if k)} (stored values are SI: {_SI[kind]!r}), "
        f"e.g. da.attrs['units'] = {_SI[kind]!r}."
    )


def require(da: xr.DataArray, kind: str, *, name: str | None = None) -> xr.DataArray:
    """Check that ``da`` carries a ``units`` attribute of dimension ``kind``; return it in SI.

    Parameters
    ----------
    da : xarray.DataArray
        Input with ``attrs['units']``.
    kind : str
        One of ``length``, ``pressure``, ``force``, ``energy_per_area``, ``temperature``,
        ``dimensionless``, ``angle``, ``wavevector``.
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
    label = name or (da.name if da.name is not None else "input")
    if "units" not in da.attrs:
        if "unit" in da.attrs:
            hint = f" It has attrs['unit']={da.attrs['unit']!r}: rename it to 'units' (CF)."
        else:
            hint = ""
        raise UnitsError(
            f"{label!r} has no 'units' attribute, so roughstick cannot tell its scale.{hint} "
            f"Set it, e.g. da.attrs['units'] = {_SI[kind]!r} (stored values are SI)."
        )
    f = _factor(str(da.attrs["units"]), kind, label)
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
    arr = np.asarray(value, dtype=float)
    return arr
