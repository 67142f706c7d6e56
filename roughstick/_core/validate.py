"""ONE home for the input checks every stage shares, each declared once (cf. MetPy's helpers).

- positivity: :func:`check_positive_block` (plain arrays) and :func:`positive` (floats, strings
  with a unit such as ``"2 nm"``, 1-D sequences or DataArrays with ``units``; lazy data are
  checked lazily); :func:`as_length`, one length (``spacing``, ``size`` ...) in m;
- relative humidity: :func:`as_relative_humidity` (the public coercion, a DataArray of fractions),
  :func:`relative_humidity_coordinate` (known in advance: it becomes the ``rh`` coordinate),
  :func:`relative_humidity_array` (a 1-D list of distinct humidities, e.g. of an ensemble) and
  :func:`relative_humidity_values` (best-effort values to look up, never computing dask data);
- fractions: :func:`as_fraction` and :func:`fraction_advice` (the one advice for a humidity,
  probability or ratio outside (0, 1), from Python, a flag or a config file);
- grids: :func:`grid_spacing` (uniform ascending pixel-centre coordinates of a map),
  :func:`check_plausible_height` (pixel size and rms height plausible in m),
  :func:`check_has_roughness` (a map with at least 2 finite pixels and a non-zero rms) and
  :func:`distance_array` (a distance grid);
- dask: :func:`check_core_not_chunked` (core dimensions must be single chunks);
- maps and spectra: :func:`check_height_dtype` / :func:`height_in_si` (a dtype a height can
  have, then SI) and :func:`check_moments` (spectral moments finite and > 0);
- energies and layers: :func:`adhesive_energy_values` (an energy bank: units, sign, physical
  upper bound) and :func:`check_layer_thickness` (an adsorbed layer in m, not nm);
- scalar arguments (sign, finiteness, integers, fractions, plausible lengths) are checked by the
  rules of :mod:`roughstick._core.arguments` (its decorator ``check_numbers``), which builds on
  :func:`check_plausible_value` here;
- figures: :func:`figure_format` and :func:`figure_dpi` (what a saved figure may be);
- :class:`ValidityWarning`, the warning of a model used outside its validity (declared here so
  that the models and :mod:`roughstick.contact.trust.validity` share it).

Every error names the problem and the fix.
"""

from __future__ import annotations

import math
import numbers
import sys

import numpy as np
import xarray as xr

from .conventions import ATTRS
from .dask import is_lazy
from .units import as_si, factor, parse_quantity, require

__all__ = [
    "check_positive_block",
    "positive",
    "as_length",
    "as_relative_humidity",
    "as_fraction",
    "fraction_advice",
    "FRACTION_QUANTITIES",
    "relative_humidity_coordinate",
    "relative_humidity_array",
    "relative_humidity_values",
    "grid_spacing",
    "check_plausible_height",
    "check_plausible_value",
    "RIGID_MODULUS",
    "check_has_roughness",
    "check_height_dtype",
    "height_in_si",
    "check_moments",
    "moments_si",
    "surface_shape",
    "MIN_MAP_PIXELS",
    "distance_array",
    "check_core_not_chunked",
    "adhesive_energy_values",
    "MAX_ADHESIVE_ENERGY",
    "check_layer_thickness",
    "MAX_LAYER_THICKNESS",
    "FIGURE_FORMATS",
    "FIGURE_DPI_RANGE",
    "figure_format",
    "figure_dpi",
    "ValidityWarning",
    "external_stacklevel",
]


class ValidityWarning(UserWarning):
    """A model is used where its measured error (upper bound) exceeds the accepted tolerance, or
    outside the assumptions it is built on."""


_SKIP_MODULES = ("roughstick", "xarray", "dask", "distributed", "numpy", "toolz", "concurrent",
                 "threading", "asyncio", "tornado", "importlib", "runpy", "pandas")


def external_stacklevel() -> int:
    """``stacklevel`` (for the caller's ``warnings.warn``) of the first frame outside roughstick
    and the libraries that call it: a warning points at the user's line."""
    frame = sys._getframe(1)
    level = 1
    while frame is not None:
        name = frame.f_globals.get("__name__", "") or ""
        if name.split(".")[0] not in _SKIP_MODULES:
            return level
        frame = frame.f_back
        level += 1
    return 1


# ------------------------------------------------------------------------------- positivity


def check_positive_block(a, name: str, fix: str = "", *, allow_zero: bool = False,
                         finite: bool = False):
    """Raise ``ValueError`` if any element of ``a`` is <= 0 (< 0 with ``allow_zero``).

    NaN passes unless ``finite``. Returns ``a`` as a float array (usable inside ``apply_ufunc``).
    """
    a = np.asarray(a, dtype=float)
    bad = (a < 0) if allow_zero else (a <= 0)
    if finite:
        bad = bad | ~np.isfinite(a)
    if np.any(bad):
        what = ">= 0" if allow_zero else ("positive and finite" if finite else "positive")
        raise ValueError(f"{name} must be {what}, got {float(a[bad].ravel()[0])!r}."
                         + (f" {fix}" if fix else ""))
    return a


def positive(value, kind: str | None, name: str, fix: str = "", *, dim: str | None = None,
             allow_zero: bool = False, finite: bool = False, arrays: bool = False):
    """``value`` in SI (``kind`` of :mod:`roughstick._core.units`, None: already SI), checked > 0.

    Floats come back as ``float``; a string with its unit (``"100 nm"``, with ``kind``) is
    converted by :func:`roughstick._core.units.parse_quantity`, and so is each string of a
    sequence; a DataArray is converted with its ``units`` and checked (lazily, at compute time,
    when dask-backed); a 1-D sequence becomes a DataArray along ``dim`` when ``dim`` is given;
    other arrays are refused unless ``arrays`` (then returned as arrays).
    """
    kw = dict(allow_zero=allow_zero, finite=finite)
    if kind is not None and isinstance(value, str):
        value = parse_quantity(value, kind, name=name)
    elif kind is not None and isinstance(value, (list, tuple)) and any(isinstance(v, str) for v in value):
        value = [parse_quantity(v, kind, name=f"{name}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, xr.DataArray):
        da = require(value, kind, name=name) if kind is not None else value
        if da.chunks is None:
            check_positive_block(da.data, name, fix, **kw)
            return da
        out = xr.apply_ufunc(check_positive_block, da, kwargs={"name": name, "fix": fix, **kw},
                             dask="parallelized", output_dtypes=[float])
        out.attrs = dict(da.attrs)
        return out
    if isinstance(value, numbers.Number) and not isinstance(value, bool):
        check_positive_block(value, name, fix, **kw)
        return float(value)
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        check_positive_block(arr, name, fix, **kw)
        return float(arr)
    if arrays:
        return check_positive_block(arr, name, fix, **kw)
    if arr.ndim == 1 and dim is not None:
        check_positive_block(arr, name, fix, **kw)
        return xr.DataArray(arr, dims=(dim,), coords={dim: arr},
                            attrs={"units": ATTRS.get(dim, {}).get("units", "")})
    raise ValueError(
        f"{name} must be a scalar, a 1-D sequence or a DataArray with named dims; got shape "
        f"{arr.shape}. Wrap it in xarray.DataArray(..., dims=...) with a 'units' attribute."
    )


def as_length(value, *, name: str) -> float:
    """One positive, finite length in m from a number (m), a string with its unit (``"2 nm"``,
    :func:`roughstick._core.units.parse_quantity`) or a 0-d DataArray with length ``units``: the
    one parser of the length arguments (``spacing``, ``size`` ...) of every function.

    Examples
    --------
    >>> from roughstick._core.validate import as_length
    >>> as_length("2 nm", name="spacing"), as_length(5e-9, name="spacing")
    (2e-09, 5e-09)
    """
    if isinstance(value, xr.DataArray):
        if value.ndim != 0:
            raise ValueError(f"{name} must be one length, got a DataArray with dims {value.dims}.")
        value = float(require(value, "length", name=name))
    elif isinstance(value, np.ndarray) and value.ndim == 0:
        value = value.item()
    v = parse_quantity(value, "length", name=name)
    check_positive_block(v, name, "Pass a positive length, e.g. '5 nm' or 5e-9 (m).", finite=True)
    return v


# ------------------------------------------------------------------------- relative humidity

_RH_ATTRS = {"units": "1", "long_name": "relative humidity", "standard_name": "relative_humidity"}

#: The quantities given as a fraction in (0, 1), for :func:`fraction_advice` and :func:`as_fraction`:
#: ``relative_humidity`` (1 is saturation), ``fraction`` (a probability, level, confidence or
#: quantile: a number from 1 to 100 is likely a percentage) and ``ratio`` (a relative size such
#: as a coefficient of variation or a tolerance: not a percentage, so none is guessed).
FRACTION_QUANTITIES = ("relative_humidity", "fraction", "ratio")


def fraction_advice(value, *, quantity: str = "fraction", percent: bool = False,
                    spell_percent: bool = True, label: str | None = None) -> str | None:
    """What is wrong with ``value`` as a fraction in (0, 1), and how to write it; None when valid.

    The one source of the advice given for a fraction typed wrong, from Python, a command-line
    flag or a configuration file.

    Parameters
    ----------
    value : float
        The value as a fraction (a percentage already divided by 100).
    quantity : {"relative_humidity", "fraction", "ratio"}
        What the value is (:data:`FRACTION_QUANTITIES`): RH (1 is saturation, outside the models'
        range), a probability-like fraction (a number from 1 to 100 is taken for a percentage),
        or a ratio (a relative size, never a percentage).
    percent : bool
        The value was written as a percentage (``"120 %"``, or a DataArray in ``%``).
    spell_percent : bool
        The place the value was written also accepts ``"30 %"`` (a flag or a config file; a
        Python float does not).
    label : str, optional
        The name of the quantity in the advice (default "RH" or "the value").

    Returns
    -------
    str or None
        One sentence (no trailing period), e.g. "RH must lie strictly between 0 and 1 (a
        fraction): did you mean 0.3 or '30 %'?"; None for a value in (0, 1).

    Examples
    --------
    >>> from roughstick._core.validate import fraction_advice
    >>> fraction_advice(30.0, quantity="relative_humidity")
    "RH must lie strictly between 0 and 1 (a fraction): did you mean 0.3 or '30 %'?"
    >>> fraction_advice(1.0, quantity="relative_humidity", spell_percent=False)
    "RH must lie strictly between 0 and 1: 1 is saturation (RH 100 %), outside the models' range; give at most e.g. 0.99"
    >>> fraction_advice(1.5, quantity="ratio", label="target_cv")
    'target_cv must lie strictly between 0 and 1 (a ratio such as 0.3, not a percentage)'
    """
    if quantity not in FRACTION_QUANTITIES:  # a bug of the caller, not a user error
        raise ValueError(f"unknown fraction quantity {quantity!r}; one of {FRACTION_QUANTITIES}.")
    v = float(value)
    if 0 < v < 1:
        return None
    rh = quantity == "relative_humidity"
    what = label or ("RH" if rh else "the value")
    head = f"{what} must lie strictly between 0 and 1"

    def pct(text: str) -> str:  # the percentage spelling, where it can be written
        return f" or '{text}'" if spell_percent else ""

    if quantity == "ratio":
        return f"{head} (a ratio such as 0.3, not a percentage)"
    example = "0.6" if rh else "0.5"
    if not np.isfinite(v):
        return f"{head} (a fraction, e.g. {example}{pct(example[2:] + '0 %')}); this is not a number"
    if percent:
        p = v * 100
        if p <= 0:
            return (f"{what} must lie strictly between 0 and 100 %"
                    + (" (0 % is dry air, outside the models' range)" if rh else "") + ", e.g. '30 %'")
        if rh:
            return ("100 % is saturation, outside the models' range: RH must lie strictly between 0 and "
                    "100 %; give at most e.g. '99 %'" if p == 100 else
                    f"{p:g} % is not a relative humidity: RH must lie strictly between 0 and 100 % "
                    "(100 % is saturation), e.g. '60 %'")
        return (f"{what} must lie strictly between 0 and 100 % (100 % itself is excluded): give e.g. '99 %'"
                if p == 100 else f"{what} must lie strictly between 0 and 100 % ({p:g} % is not), e.g. '50 %'")
    if v <= 0:
        return (f"{head} (a fraction, e.g. {example}{pct(example[2:] + '0 %')})"
                + (("; 0 is dry air, outside the models' range" if v == 0 else "; it cannot be negative")
                   if rh else ""))
    if v == 1:
        return (f"{head}: 1 is saturation (RH 100 %), outside the models' range; give at most e.g. "
                f"0.99{pct('99 %')}" if rh else f"{head} (1 itself is excluded): give e.g. 0.99")
    if v < 2:  # just above 1: not a percentage typed for a fraction
        return f"{head} (a fraction, e.g. {example})" + (f"; {v:g} is above saturation (1)" if rh else "")
    if v < 100:
        return f"{head} (a fraction): did you mean {v / 100:g}{pct(f'{v:g} %')}?"
    if v == 100 and rh:
        return (f"{head}: 100 would be 100 %, saturation, outside the models' range; give at most e.g. "
                f"0.99{pct('99 %')}")
    return (f"{head} (a fraction, e.g. {example}"
            + (f", or a percentage below 100 %, e.g. '{example[2:]}0 %'" if spell_percent else "") + ")"
            + (f"; {v:g} is not a relative humidity" if rh else ""))


def as_fraction(value, *, name: str, quantity: str = "fraction", spell_percent: bool = True,
                label: str | None = None) -> float:
    """A fraction in (0, 1) from a number or a percentage string (``"30 %"``).

    Raises ``ValueError`` ``"<name> = <value>: <advice>."`` with the advice of
    :func:`fraction_advice` (``label`` names the quantity in it).

    Examples
    --------
    >>> from roughstick._core.validate import as_fraction
    >>> as_fraction("30 %", name="relative_humidity", quantity="relative_humidity")
    0.3
    """
    percent = False
    v = value
    if isinstance(value, str):
        s = value.strip()
        percent = s.endswith("%")
        try:
            v = float(s[:-1].strip() if percent else s)
        except ValueError:
            v = np.nan
        if percent:
            v = v / 100.0
    elif isinstance(value, bool) or not (isinstance(value, numbers.Real)
                                         or (isinstance(value, np.ndarray) and value.ndim == 0)):
        v = np.nan
    advice = fraction_advice(v, quantity=quantity, percent=percent, spell_percent=spell_percent,
                             label=label)
    if advice is not None:
        raise ValueError(f"{name} = {value!r}: {_sentence(advice)}")
    return float(v)


def _sentence(advice: str) -> str:
    return advice if advice.endswith("?") else advice + "."


def _check_rh_block(a, percent: bool = False):
    a = np.asarray(a, dtype=float)
    bad = ~((a > 0) & (a < 1))
    if np.any(bad):
        v = float(a[bad].ravel()[0])
        shown = f"'{v * 100:g} %'" if percent else repr(v)
        raise ValueError(
            f"relative_humidity = {shown}: "
            + _sentence(fraction_advice(v, quantity="relative_humidity", percent=percent,
                                        spell_percent=False))
        )
    return a


def as_relative_humidity(relative_humidity) -> xr.DataArray:
    """Validate a relative humidity and return it as a DataArray (fraction, units "1").

    A float gives a 0-d DataArray; a sequence or 1-D array gives dimension ``rh`` with an ``rh``
    coordinate; a DataArray must carry ``units`` ("1", "%" ...). Lazy inputs are validated at
    compute time.

    Examples
    --------
    >>> rs.contact.as_relative_humidity([0.3, 0.7]).rh.values
    array([0.3, 0.7])
    """
    percent = False
    if isinstance(relative_humidity, xr.DataArray):
        percent = str(relative_humidity.attrs.get("units", "")).strip() in ("%", "percent")
        da = require(relative_humidity, "dimensionless", name="relative_humidity")
    else:
        arr = np.asarray(relative_humidity, dtype=float)
        if arr.ndim == 0:
            da = xr.DataArray(arr)
        elif arr.ndim == 1:
            da = xr.DataArray(arr, dims=("rh",), coords={"rh": arr})
        else:
            raise ValueError(
                "relative_humidity must be a scalar, a 1-D sequence or a DataArray; "
                f"got an array of shape {arr.shape}. Wrap it in a DataArray with named dims."
            )
    if da.chunks is None:
        _check_rh_block(da.data, percent)
        out = da
    else:
        out = xr.apply_ufunc(_check_rh_block, da, kwargs={"percent": percent}, dask="parallelized",
                             output_dtypes=[float])
    out = out.copy(deep=False)
    out.attrs = dict(_RH_ATTRS)
    if "rh" in out.coords:
        out["rh"].attrs = dict(_RH_ATTRS)
    return out


def relative_humidity_coordinate(relative_humidity) -> xr.DataArray:
    """An RH known in advance (it becomes the ``rh`` coordinate): eager, scalar or 1-D along ``rh``."""
    rh = as_relative_humidity(relative_humidity)
    if is_lazy(rh):
        raise ValueError(
            "relative_humidity must be known in advance (it becomes the 'rh' coordinate); pass "
            "floats or a computed DataArray, e.g. rh.compute()."
        )
    if rh.ndim > 1 or (rh.ndim == 1 and rh.dims != ("rh",)):
        raise ValueError(
            f"relative_humidity must be a scalar or 1-D along 'rh'; got dims {rh.dims}. "
            "Pass e.g. [0.3, 0.5, 0.7]."
        )
    return rh


def relative_humidity_array(relative_humidity) -> np.ndarray:
    """A non-empty 1-D array of distinct humidities in (0, 1) (e.g. the ``rh`` of an ensemble)."""
    if isinstance(relative_humidity, xr.DataArray):
        arr = np.atleast_1d(np.asarray(relative_humidity_coordinate(relative_humidity).values, float))
    else:
        arr = np.atleast_1d(np.asarray(relative_humidity, dtype=float))
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(
            "relative_humidity is empty: give at least one humidity as a fraction in (0, 1), "
            "e.g. relative_humidity=[0.3, 0.5, 0.7, 0.9]."
        )
    as_relative_humidity(arr)  # validates (0, 1)
    if np.unique(arr).size != arr.size:
        raise ValueError(f"relative_humidity has repeated values {arr.tolist()}; give each humidity once.")
    return arr


def relative_humidity_values(relative_humidity) -> np.ndarray:
    """RH fractions to look up, without validating or computing: a lazy DataArray gives its ``rh``
    coordinate (or nothing), an eager one its values converted by its ``units`` ("%" ...)."""
    if isinstance(relative_humidity, xr.DataArray):
        if relative_humidity.chunks is not None:
            if "rh" in relative_humidity.coords:
                return np.asarray(relative_humidity["rh"].values, dtype=float).ravel()
            return np.array([], dtype=float)
        if "units" in relative_humidity.attrs:
            relative_humidity = require(relative_humidity, "dimensionless", name="relative_humidity")
        return np.asarray(relative_humidity.values, dtype=float).ravel()
    return np.asarray(relative_humidity, dtype=float).ravel()


# ---------------------------------------------------------------------------------- grids


def grid_spacing(da: xr.DataArray, dim: str, *, min_pixels: int = 8,
                 purpose: str = "roughness statistics and spectra") -> float:
    """Pixel size [m] along ``dim`` of a map with uniform ascending pixel-centre coordinates.

    Raises ``ValueError`` naming the fix for a missing dimension or coordinate, fewer than
    ``min_pixels`` pixels, descending, non-monotonic or non-uniform coordinates (relative spread of
    the steps above 1e-6); coordinate ``units`` other than m are converted.
    """
    if dim == "y" and "y" not in da.dims and "x" in da.dims:
        raise ValueError(
            f"this is a line scan (1-D profile, dims {da.dims}), not a height map: contact, "
            "ensembles and surface generation need a 2-D map (..., 'y', 'x'). For a profile's PSD "
            "and moments use roughstick.surface.profile_psd / profile_moments (CLI: roughstick psd)."
        )
    if dim not in da.dims:
        raise ValueError(
            f"height must have dims (..., 'y', 'x'); got {da.dims}. Rename with "
            f".rename({{'<row dim>': 'y', '<column dim>': 'x'}})."
        )
    n = da.sizes[dim]
    if n < min_pixels:
        raise ValueError(
            f"the map has {n} pixel(s) along {dim!r}; {purpose} need(s) at least "
            f"{min_pixels} x {min_pixels} pixels: give a larger map (crop less, or a larger scan)."
        )
    if dim not in da.coords:
        raise ValueError(
            f"height has no {dim!r} coordinate, so its pixel size is unknown. Assign pixel centres "
            f"in m, e.g. height.assign_coords({dim}=(np.arange(n) + 0.5) * spacing), or build it "
            "with roughstick.testing.make_topography(values, spacing=...)."
        )
    c = da[dim]
    f = factor(c.attrs.get("units", "m"), "length", name=f"coordinate {dim}")
    d = np.diff(np.asarray(c.values, dtype=float) * f)
    if np.any(d <= 0):
        if np.all(d < 0):
            raise ValueError(
                f"coordinate {dim!r} is descending; roughstick expects ascending pixel centres. "
                f"Use height.sortby({dim!r}) (or height.isel({dim}=slice(None, None, -1)))."
            )
        raise ValueError(f"coordinate {dim!r} is not monotonic: sort it with height.sortby({dim!r}).")
    step = d.mean()
    if np.max(np.abs(d - step)) > 1e-6 * step:
        raise ValueError(
            f"coordinate {dim!r} is not uniformly spaced (steps from {d.min():.6g} to {d.max():.6g} m); "
            f"FFT spectra and asperity fits need a uniform grid. Interpolate first, e.g. "
            f"height.interp({dim}=np.linspace(first, last, n))."
        )
    return float(step)


#: Smallest map (pixels along each side) every contact model, spectrum and statistic takes.
MIN_MAP_PIXELS = 8

#: Largest pixel size [m] and rms height [m] taken at face value: above them a map of a MEMS
#: surface is almost surely in other units than its label says (nm read as m, pixel indices).
PLAUSIBLE_SPACING = 1e-3
PLAUSIBLE_RMS = 1e-3
#: Smallest rms height [m] taken at face value: below the noise floor of any AFM (~1e-11 m) by
#: 100 x, so a map this flat is heights in m labelled nm (or scaled twice), not a surface.
PLAUSIBLE_RMS_MIN = 1e-13


#: Plausible SI ranges (low, high, typical) of scalar inputs whose unit is easily slipped (GPa for Pa, µm for m).
#: Generous: they catch a slip by a factor 1e3 or more, not an unusual design. Moduli and
#: hardness from soft polymers (~1 MPa; down to 0.1 MPa) to diamond (~1.2 TPa).
PLAUSIBLE_MODULUS = (1e5, 2e12, 1e10)
#: A modulus at or above this stands for a rigid body (e.g. a rigid counter-face), not a slip.
RIGID_MODULUS = 1e18
#: Beam length [m]: 1 µm to 10 mm (MEMS cantilevers are ~10 µm-2 mm).
PLAUSIBLE_BEAM_LENGTH = (1e-6, 1e-2, 3e-4)
#: Other beam dimensions (width, thickness, gap, interaction length) [m]: 10 nm to 10 mm.
PLAUSIBLE_BEAM_DIMENSION = (1e-8, 1e-2, 3e-6)
_SLIPS = {"pressure": (("GPa", 1e9), ("MPa", 1e6), ("kPa", 1e3)),
          "length": (("µm", 1e-6), ("mm", 1e-3), ("nm", 1e-9))}


def check_plausible_value(value, *, name: str, kind: str, bounds, what: str) -> None:
    """Refuse a positive scalar (or each value of a sequence) outside ``bounds`` = (low, high,
    typical) in SI as a likely unit slip, naming the argument, the value, the unit it looks like
    (the one that brings it nearest to ``typical``) and the fix.

    ``kind`` is ``"pressure"`` (Pa) or ``"length"`` (m); ``what`` says what the value is for
    (e.g. "a solid", "a MEMS beam"). Non-finite or non-positive values are left to the
    positivity checks; a Young's modulus >= ``RIGID_MODULUS`` is a rigid body and passes.
    """
    low, high, typical = bounds
    si = {"pressure": "Pa", "length": "m"}[kind]
    rigid = kind == "pressure" and name.endswith("youngs_modulus")
    for v in np.atleast_1d(np.asarray(value, dtype=float)).ravel():
        if not (np.isfinite(v) and v > 0) or low <= v <= high or (rigid and v >= RIGID_MODULUS):
            continue
        fits = [(abs(np.log10(v * f / typical)), unit, f) for unit, f in _SLIPS[kind]
                if low <= v * f <= high]
        slip = f"; give it in {si}"
        if fits:
            _, unit, f = min(fits)
            slip = (f"; it looks like {unit}: give it in {si}, e.g. "
                    f"{name}={v:g}e{int(round(np.log10(f)))}")
        rigid_note = f"; a rigid body: >= {_short(RIGID_MODULUS)} {si}" if rigid else ""
        raise ValueError(
            f"{name}={v:g} {si} is implausible for {what} (plausible {_short(low)} to "
            f"{_short(high)} {si}{rigid_note}){slip}."
        )


def _short(x: float) -> str:
    """1e5, 2e12, 1e-6: a bound in the shortest scientific form."""
    mant, exp = f"{x:.0e}".split("e")
    return f"{mant}e{int(exp)}"


def check_plausible_height(h, dx: float, dy: float) -> None:
    """Refuse a height map (in SI, pixel sizes ``dx``, ``dy`` [m]) whose values are implausible
    for a MEMS surface: a likely unit mistake (nm labelled m, pixel indices), with the fix.
    Lazy maps are checked on their pixel sizes only."""
    for dim, d in (("x", dx), ("y", dy)):
        if d > PLAUSIBLE_SPACING:
            has = "units" in h[dim].attrs
            raise ValueError(
                f"the pixel size along {dim!r} is {d:.4g} m"
                + ("" if has else f" (coordinate {dim!r} has no 'units', so it was taken as m)")
                + ": implausible for an AFM map. Set the coordinate's units, e.g. "
                f"height[{dim!r}].attrs['units'] = 'nm' (or 'um'), or build the map with "
                "roughstick.testing.make_topography(values, spacing=5e-9)."
            )
    if h.chunks is None and h.size:
        values = np.asarray(h.values, dtype=float)
        # (np.std where every pixel is finite: a plausibility bound, nanstd's copies not needed)
        rms = float(values.std()) if np.isfinite(values.sum()) else float(np.nanstd(values))
        if rms > PLAUSIBLE_RMS:
            raise ValueError(
                f"the rms height is {rms:.4g} m: implausible for a MEMS surface; the heights are "
                "probably in nm or um labelled m. Set height.attrs['units'] = 'nm' (or 'um') "
                "to what they are."
            )
        # (a constant map's rms is rounding noise: check_has_roughness names it flat)
        if 0 < rms < PLAUSIBLE_RMS_MIN and rms > 1e-9 * float(np.nanmax(np.abs(values))):
            raise ValueError(
                f"the rms height is {rms:.4g} m: below anything an AFM can measure (its noise is "
                "~1e-11 m); the heights are probably in m labelled nm or um, or converted twice. "
                "Set height.attrs['units'] to the unit the values are in (e.g. 'm')."
            )


def check_has_roughness(values, *, name: str = "height") -> None:
    """Refuse an eager map ``(..., y, x)`` with no roughness to model: fewer than 2 finite pixels,
    or flat (its finite heights spread by <= 1e-12 of their magnitude, rms 0), per map of a stack.

    Lazy (dask) maps are not computed. The errors name the map of a stack, the problem and the fix.
    """
    if is_lazy(values):
        return
    z = np.asarray(getattr(values, "values", values), dtype=float)
    if z.ndim < 2 or z.size == 0:
        return
    maps = z.reshape((-1,) + z.shape[-2:])
    for k, m in enumerate(maps):
        which = f"{name} (map {k} of the stack)" if maps.shape[0] > 1 else name
        lo, hi = float(m.min()), float(m.max())
        if np.isfinite(lo) and np.isfinite(hi) and m.size >= 2:
            # every pixel finite (no copy of the map): the same test as below
            if hi - lo > 1e-12 * max(abs(lo), abs(hi), np.finfo(float).tiny):
                continue
        finite = m[np.isfinite(m)]
        if finite.size < 2:
            raise ValueError(
                f"{which} has {'no finite pixel' if finite.size == 0 else 'only 1 finite pixel'} "
                f"(of {m.size}; the rest NaN/inf): no roughness to model. Check the channel, or "
                "crop the valid region (height.isel(x=..., y=...))."
            )
        spread = float(finite.max() - finite.min())
        if spread <= 1e-12 * max(float(np.abs(finite).max()), np.finfo(float).tiny):
            raise ValueError(
                f"{which} is flat (constant (zero variance), rms 0 over its {finite.size} finite "
                "pixels): no roughness to model, so moments, spectra and contact curves are "
                "undefined. Check the channel (a height, not a phase or error channel) and the "
                "units."
            )


def check_height_dtype(height, *, name: str = "height") -> None:
    """Refuse a map whose dtype a height cannot have (bool, complex, object, text, bytes,
    date-time, time-delta), naming the dtype and what it probably is."""
    dtype = height.dtype if hasattr(height, "dtype") else np.asarray(height).dtype
    kind = np.dtype(dtype).kind
    if kind not in "fiu":
        what = {"b": "boolean (a mask?)", "c": "complex (an FFT?)", "O": "object",
                "U": "text", "S": "bytes", "M": "date-time", "m": "time-delta"}.get(kind, kind)
        raise TypeError(
            f"{name} has dtype {dtype} ({what}); a height map holds real numbers. Pass the "
            "heights themselves (e.g. np.abs(...) or .real only if that is what you mean), as "
            "float."
        )


def height_in_si(height, *, name: str = "height") -> xr.DataArray:
    """A height map checked for its dtype (:func:`check_height_dtype`) and converted to m by its
    ``units`` (:func:`roughstick._core.units.require`): the entry check of the contact models."""
    if isinstance(height, xr.DataArray):
        check_height_dtype(height, name=name)
    return require(height, "length", name=name)


def check_moments(m0, m2, m4, *, what: str, fix: str) -> None:
    """Refuse eager spectral moments that are zero, negative or not finite, naming the moment,
    the problem, ``what`` they came from and ``fix`` (lazy moments are not computed)."""
    for key, m in (("m0", m0), ("m2", m2), ("m4", m4)):
        if is_lazy(m):
            continue
        v = np.asarray(getattr(m, "values", m), dtype=float)
        if not v.size:
            continue
        if not np.all(np.isfinite(v)):
            problem = (f"is not finite ({float(v[~np.isfinite(v)].ravel()[0])!r}): {key} must be "
                       "positive and finite; the spectrum has NaN or inf values, or overflows")
        elif np.any(v == 0):
            problem = (f"= 0.0: {key} must be positive; the spectrum has no power (zero everywhere, "
                       "or nothing below the cutoff), so the surface would be flat")
        elif np.any(v < 0):
            problem = f"= {float(v[v < 0].ravel()[0])!r}: {key} must be positive (a variance)"
        else:
            continue
        raise ValueError(f"{what}: {key} {problem}. {fix}")


#: Kind of quantity (:mod:`roughstick._core.units`) of each spectral moment.
_MOMENT_KIND = {"m0": "area", "m2": "dimensionless", "m4": "inverse_area"}


def moments_si(moments: xr.Dataset) -> tuple[xr.DataArray, xr.DataArray, xr.DataArray]:
    """``m0``, ``m2``, ``m4`` of a moments Dataset, checked and converted to SI (m2, 1, m-2).

    Raises
    ------
    TypeError
        ``moments`` is not a Dataset.
    ValueError
        A moment is missing, or its ``units`` are missing or not a power of a length
        (:class:`roughstick.UnitsError`); an eager moment is zero, negative or not finite.
    """
    if not isinstance(moments, xr.Dataset):
        raise TypeError(
            "moments must be an xarray.Dataset with m0, m2, m4 (e.g. from roughstick.surface.fit_self_affine, "
            f"roughness_moments or psd_moments); got {type(moments).__name__}."
        )
    out = []
    for key in ("m0", "m2", "m4"):
        if key not in moments:
            raise ValueError(
                f"moments must be a Dataset with variables 'm0', 'm2' and 'm4' (Nayak's one-direction "
                f"spectral moments, docs/architecture.md); {key!r} is missing. "
                "roughstick.surface.fit_self_affine / moments_from_asperities return such a Dataset."
            )
        da = require(moments[key], _MOMENT_KIND[key], name=f"moments[{key!r}]").copy(deep=False)
        da.attrs = {"units": da.attrs["units"]}
        out.append(da)
    check_moments(*out, what="moments", fix="Moments of a rough surface are finite and > 0: check the "
                  "map or PSD they came from (a flat map, a zero PSD, a cutoff below its wave numbers).")
    return out[0], out[1], out[2]


def surface_shape(*, shape=None, size=None, spacing: float) -> tuple[int, int]:
    """Pixels ``(ny, nx)`` of the surfaces from ``shape`` (pixels) or ``size`` (m) and ``spacing``.

    Exactly one of ``shape`` and ``size`` (each a number or a ``(y, x)`` pair; a size and the
    spacing in m or with their unit, ``"1.28 um"``); a size must be a whole number of pixels; both
    sides at least 4 pixels.

    Examples
    --------
    >>> from roughstick._core.validate import surface_shape
    >>> surface_shape(size=(1.28e-6, 2.56e-6), spacing=5e-9)
    (256, 512)
    """
    if (shape is None) == (size is None):
        raise ValueError("give exactly one of shape=(ny, nx) (pixels) or size=(Ly, Lx) (m).")
    spacing = as_length(spacing, name="spacing")
    if shape is not None:
        shp = (int(shape), int(shape)) if np.ndim(shape) == 0 else tuple(int(s) for s in shape)
        if np.ndim(shape) == 0 and int(shape) != shape or any(
            s != o for s, o in zip(shp, np.atleast_1d(shape), strict=False)
        ):
            raise ValueError(f"shape must be integers, got {shape!r}.")
    else:
        sz = tuple(as_length(s, name="size") for s in ((size, size) if np.ndim(size) == 0 else size))
        shp = tuple(int(round(s / spacing)) for s in sz)
        for s, n in zip(sz, shp, strict=True):
            if n < 1 or not math.isclose(n * spacing, s, rel_tol=1e-6):
                raise ValueError(
                    f"size {s!r} m is not a whole number of pixels of spacing {spacing!r} m; "
                    f"use size={n * spacing!r} or give shape= instead."
                )
    if len(shp) != 2 or min(shp) < 4:
        raise ValueError(f"surface shape must be two integers >= 4, got {shp}.")
    return shp


def distance_array(distance, *, min_size: int = 1) -> np.ndarray:
    """A distance grid [m] as a sorted 1-D float array: finite, distinct, at least ``min_size``.

    A DataArray must be 1-D, carry length ``units`` and be eager (distances become a coordinate).
    """
    if distance is None:
        raise ValueError(
            "distance is required: the flat-to-mean-plane distances d [m] at which to evaluate, e.g. "
            "np.linspace(-1, 6, 200) * sqrt(m0)."
        )
    if isinstance(distance, xr.DataArray):
        if distance.ndim != 1:
            raise ValueError(f"distance must be 1-D, got dims {distance.dims}.")
        d = as_si(distance, "length", name="distance")
        if is_lazy(d):
            raise ValueError("distance must be eager (it becomes a coordinate): call .compute().")
        d = np.asarray(d.values, dtype=float)
    else:
        d = np.atleast_1d(np.asarray(distance, dtype=float))
    if d.ndim != 1 or d.size < min_size:
        raise ValueError(
            f"distance must be a 1-D array of at least {min_size} distance(s) [m]; got shape {d.shape}."
        )
    if not np.all(np.isfinite(d)):
        raise ValueError("distance contains NaN or inf; pass finite distances in m.")
    if np.unique(d).size != d.size:
        raise ValueError("distance has repeated values; pass each distance once.")
    return np.sort(d)


# ------------------------------------------------------------------------------------ dask


def check_core_not_chunked(da: xr.DataArray, dims) -> None:
    """Raise ``ValueError`` if any of ``dims`` is split over several dask chunks.

    The message names the fix, ``.chunk({dim: -1})``, in the xarray style.
    """
    if da.chunks is None:
        return
    bad = [d for d in dims if d in da.dims and len(da.chunksizes[d]) > 1]
    if bad:
        fix = ", ".join(f"{d!r}: -1" for d in bad)
        raise ValueError(
            f"dimension(s) {bad} of {da.name or 'the input'!r} are split over several dask chunks, "
            f"but they are core dimensions of this computation. Rechunk first: "
            f".chunk({{{fix}}})."
        )


# ------------------------------------------------------------------- energies and layers

#: Largest adhesive energy [J m-2] taken at face value. A water meniscus holds at most
#: 2 gamma = 0.144 J m-2 (Eq. 13 on flat surfaces) plus the adsorbed layers' share
#: (|Delta P| x 1.8 nm, about 0.1 J m-2 at the 65 % onset), so about 0.25 J m-2: above twice
#: that, the values are almost surely mJ m-2 labelled J m-2.
MAX_ADHESIVE_ENERGY = 0.5


def adhesive_energy_values(energy, *, name: str = "bank", units_fix: str = "") -> np.ndarray:
    """Adhesive energies [J m-2] of a patch bank or a sample, as a float array, checked.

    A DataArray's ``units`` are converted (``"mJ m-2"`` ...); without ``units`` it is taken as
    J m-2. Refuses NaN (drop the failed laws), inf, negative values and values above
    :data:`MAX_ADHESIVE_ENERGY` (more than any water meniscus holds: mJ m-2 labelled J m-2),
    naming ``name`` and the fix (``units_fix`` replaces the default one for the unit slip).
    """
    if isinstance(energy, xr.DataArray) and "units" in energy.attrs:
        energy = require(energy, "energy_per_area", name=name)
    values = np.asarray(getattr(energy, "values", energy), dtype=float)
    if values.size == 0:
        raise ValueError(f"{name} holds no adhesive energy (size 0); build it with "
                         "roughstick.beam.build_patch_bank(..., n_law=1000).")
    if np.isnan(values).any():
        raise ValueError(f"{name} has NaN adhesive energies: drop those laws ({name}.dropna('law'))")
    if np.isinf(values).any() or (values < 0).any():
        bad = float(values[np.isinf(values) | (values < 0)].ravel()[0])
        raise ValueError(
            f"{name} has the adhesive energy {bad!r} J m-2: an adhesive energy (work of separation, "
            "Eq. 13) is finite and >= 0. Drop or fix those laws; a sign flip of pressures "
            "(repulsive positive) gives negative energies."
        )
    top = float(values.max())
    if top > MAX_ADHESIVE_ENERGY:
        fix = units_fix or (f"divide by 1000 ({name} / 1000) or set {name}.attrs['units'] = 'mJ m-2'")
        raise ValueError(
            f"{name} has adhesive energies up to {top:.4g} J m-2 (median "
            f"{float(np.median(values)):.4g}): above {MAX_ADHESIVE_ENERGY} J m-2, more than a water "
            "meniscus and its adsorbed layers can hold (2 gamma + layers, about 0.25 J m-2). The "
            f"values look like mJ m-2: {fix}."
        )
    return values


#: Largest total adsorbed-layer thickness [m] taken at face value: the layers are a few water
#: monolayers (paper: 0.9 nm per surface); above 100 nm a model almost surely returns nm.
MAX_LAYER_THICKNESS = 1e-7


def check_layer_thickness(thickness, *, name: str, rh=None) -> None:
    """Refuse an adsorbed-layer thickness [m] (eager values) that is negative, not finite or
    above :data:`MAX_LAYER_THICKNESS` (nm returned as m), naming the model ``name``."""
    if is_lazy(thickness):
        return
    t = np.asarray(getattr(thickness, "values", thickness), dtype=float)
    at = ""
    bad = ~np.isfinite(t) | (t < 0) | (t > MAX_LAYER_THICKNESS)
    if not bad.any():
        return
    v = float(t[bad].ravel()[0])
    if rh is not None and not is_lazy(rh) and np.shape(rh) == t.shape:
        at = f" at RH {float(np.asarray(getattr(rh, 'values', rh), dtype=float)[bad].ravel()[0]):g}"
    if np.isfinite(v) and v > MAX_LAYER_THICKNESS:
        problem = (f", above {MAX_LAYER_THICKNESS:g} m: an adsorbed water layer is a few nm (the "
                   "paper's 0.9e-9 m per surface), so the model almost surely returns nm. Make "
                   f"it return metres (e.g. {v:g}e-9 for {v:g} nm)")
    else:
        problem = ": a layer thickness must be finite and >= 0 (in m, e.g. 1.8e-9)"
    raise ValueError(f"the adsorbed_layer model {name} returned {v!r} m{at}{problem}.")


# ------------------------------------------------------------------------------------ figures

#: File formats a figure is saved in: a raster image and two vector formats for reports.
FIGURE_FORMATS = ("png", "pdf", "svg")
#: Plausible resolutions [dots per inch]: below, text is unreadable; above, a page-size figure
#: needs gigabytes of memory to draw.
FIGURE_DPI_RANGE = (50, 1200)


def figure_format(value, *, name: str = "format") -> str:
    """``value`` as one of :data:`FIGURE_FORMATS` (case and a leading dot ignored), or a
    ``ValueError`` naming ``name`` and the formats to choose from."""
    text = str(value).strip().lower().lstrip(".")
    if text not in FIGURE_FORMATS:
        raise ValueError(f"{name}={value!r}: not a figure format; use {', '.join(map(repr, FIGURE_FORMATS))} "
                         "(pdf and svg are vector formats for reports).")
    return text


def figure_dpi(value, *, name: str = "dpi") -> int:
    """``value`` as an integer resolution within :data:`FIGURE_DPI_RANGE`, or a ``ValueError``
    naming ``name``, the value and the range."""
    low, high = FIGURE_DPI_RANGE
    try:
        dpi = float(value)
    except (TypeError, ValueError):
        dpi = float("nan")
    if not (np.isfinite(dpi) and dpi == int(dpi) and low <= dpi <= high) or isinstance(value, bool):
        raise ValueError(f"{name}={value!r}: give a whole number of dots per inch from {low} to {high}, "
                         "e.g. 200 for print or 600 for line art.")
    return int(dpi)
