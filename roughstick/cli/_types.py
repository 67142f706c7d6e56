"""argparse types and checks of command-line values whose messages name the flag and the fix.

* :func:`relative_humidity_arg` (``--rh``): a fraction (``0.6``) or a percentage (``"60 %"``);
  ``--rh 60`` is refused with "did you mean 0.6 or '60 %'?";
* :func:`pixel_size_arg` (``--spacing``): a length with its unit, plausible for an AFM pixel;
* :func:`flag_value` applies a type here inside a command (``--qmax``), its
  error one line naming the flag (exit status 1);
* :func:`read_map`: before reading a map, the flags its format needs (:func:`check_map_flags`);
  after reading, heights plausible in the ``--units`` given.

argparse prefixes each :class:`argparse.ArgumentTypeError` with ``argument --flag:``, so a
message here says what is wrong with the value and how to write it, on one line.
"""

from __future__ import annotations

import argparse
import logging
import math
import pathlib
import warnings

import numpy as np

import roughstick as rs

from .._core.materials import Material, material_from
from .._core.units import parse_quantity
from .._core.validate import PLAUSIBLE_SPACING, as_fraction
from ._common import length_with_unit, refuse_bare_number

__all__ = ["relative_humidity_arg", "pixel_size_arg", "wavevector_arg", "positive_float_arg",
           "flag_value", "check_map_flags", "read_map", "material_arg"]

#: Heights spanning more than this [m] are not an AFM map (read_afm warns above it too).
_PLAUSIBLE_SPAN = 1e-3
#: heights spanning less than this [m] in the --units given: converted twice (1 pm)
_PLAUSIBLE_SPAN_MIN = 1e-12

_ARRAY_SUFFIXES = {".npy", ".txt", ".csv", ".asc", ".dat", ".xyz"}


def relative_humidity_arg(text: str) -> float:
    """argparse type of ``--rh``: a fraction in (0, 1) (``0.6``) or a percentage (``"60 %"``,
    ``60%``); returns the fraction. A bare number from 1 to 100 is refused as a likely percentage,
    with both spellings of the fix (:func:`roughstick._core.validate.fraction_advice`)."""
    try:
        return as_fraction(str(text), name="--rh", quantity="relative_humidity")
    except ValueError as exc:  # argparse names the flag: "argument --rh: '60': ..."
        raise argparse.ArgumentTypeError(str(exc).removeprefix("--rh = ").rstrip(".")) from None


def pixel_size_arg(text: str) -> str:
    """argparse type of ``--spacing``: a length with its unit (``"5 nm"``) no larger than an AFM
    pixel can be (:data:`roughstick._core.validate.PLAUSIBLE_SPACING`); returns the text."""
    length_with_unit(text)
    v = parse_quantity(text, "length", name="--spacing")
    if v > PLAUSIBLE_SPACING:
        number = str(text).strip().split()[0].rstrip("abcdefghijklmnopqrstuvwxyzµμ")
        raise argparse.ArgumentTypeError(
            f"{text!r} is a pixel of {v:.4g} m, implausible for an AFM map; did you mean "
            f"'{number} nm' or '{number} um'?")
    if not v > 0:
        raise argparse.ArgumentTypeError(f"{text!r}: the pixel size must be positive, e.g. '5 nm'")
    return text


def wavevector_arg(text: str) -> float:
    """argparse type of ``--qmax``: a wave number with its unit (``"289 rad/um"``); returns rad/m."""
    refuse_bare_number(text, "rad/um")
    try:
        v = parse_quantity(text, "wavevector", name="--qmax")
    except ValueError as exc:
        msg = str(exc).removeprefix(f"--qmax = {text!r}: ")
        raise argparse.ArgumentTypeError(f"{text!r}: {msg}") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"{text!r}: the cutoff must be positive and finite, e.g. '289 rad/um'")
    return v


def positive_float_arg(text: str) -> float:
    """argparse type: a positive finite number (``--tolerance``, ``--resolution-factors``)."""
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"{text!r}: expected a positive number, e.g. 0.1")
    return v


def flag_value(flag: str, convert, text):
    """``convert(text)`` (one of the argparse types here) for a value checked inside a command,
    its error as one line naming ``flag`` (exit status 1, as every user error of a command)."""
    try:
        return convert(text)
    except argparse.ArgumentTypeError as exc:
        raise ValueError(f"{flag} {exc}") from None


def material_arg(tokens, flag: str = "--material") -> Material:
    """``--material NAME``, ``--material E NU`` or ``--material LABEL E NU``: a material known
    by name (:data:`roughstick._core.materials.MATERIALS`), or Young's modulus with its unit and
    the Poisson ratio; a ValueError naming the flag and the spellings otherwise."""
    tokens = list(tokens)
    example = f"e.g. {flag} polysilicon, or {flag} '250 GPa' 0.23 (a label first: {flag} SiN '250 GPa' 0.23)"
    if len(tokens) not in (1, 2, 3):
        raise ValueError(f"{flag} takes a name, or Young's modulus and Poisson ratio; {example}.")
    name = tokens[0] if len(tokens) != 2 else None
    try:
        if len(tokens) == 1:
            return material_from(name)
        refuse_bare_number(tokens[-2], "GPa")
        e = parse_quantity(tokens[-2], "pressure", name="Young's modulus")
        nu = float(tokens[-1])
        return material_from(name, youngs_modulus=e, poisson_ratio=nu)
    except (ValueError, argparse.ArgumentTypeError) as exc:
        raise ValueError(f"{flag} {' '.join(map(repr, tokens))}: {exc} ({example}).") from None


def check_map_flags(path, *, spacing=None, units=None) -> None:
    """Refuse, before reading it, a ``.npy``/text map given without ``--spacing`` or ``--units``
    (it holds bare numbers), naming the flags."""
    name = pathlib.Path(str(path)).name
    if pathlib.Path(str(path)).suffix.lower() in _ARRAY_SUFFIXES and (spacing is None or units is None):
        missing = " and ".join(f for f, v in (("--spacing '5 nm'", spacing), ("--units nm", units))
                               if v is None)
        raise ValueError(f"{name} holds bare numbers: give their pixel size and height unit, e.g. "
                         f"{missing}.")


#: The help of ``--level`` (psd, curves): every command levels a measured map the same way.
LEVEL_HELP = ("what is removed from the map as it is read, as every command does (printed): "
              "auto (default) = its least-squares plane, unless the map is periodic (a generated "
              "surface) or levelled already; plane, mean, line (scan-line alignment), or none "
              "(the raw heights)")


def read_map(path, *, spacing=None, units=None, **kwargs):
    """:func:`roughstick.io.read_afm` for a command: the flags checked first, and heights spanning
    more than 1 mm in the ``--units`` given refused naming ``--units`` (read_afm only warns, in
    its Python words). The map is levelled as ``read_afm(levelling=...)`` says (``--level``,
    default ``auto``), which the command prints (logger ``roughstick``)."""
    check_map_flags(path, spacing=spacing, units=units)
    with warnings.catch_warnings():
        if units is not None:  # said below, in flags
            warnings.filterwarnings("ignore", message=".*heights span .* more than 1 mm", category=UserWarning)
        h = rs.io.read_afm(path, spacing=spacing, units=units, **kwargs)
    if units is not None and h.chunks is None and h.size:
        finite = np.asarray(h.values, dtype=float)
        finite = finite[np.isfinite(finite)]
        span = float(np.ptp(finite)) if finite.size else 0.0
        if 0 < span < _PLAUSIBLE_SPAN_MIN:
            raise ValueError(f"{pathlib.Path(str(path)).name}: with --units {units} the heights span "
                             f"{span:.4g} m, below anything an AFM can measure; the file probably "
                             "carries its unit already (NetCDF does): drop --units, or give the unit "
                             "the numbers are in.")
        if span > _PLAUSIBLE_SPAN:
            raise ValueError(f"{pathlib.Path(str(path)).name}: with --units {units} the heights span "
                             f"{span:.4g} m, implausible for an AFM map (more than 1 mm); give the "
                             "unit the heights are in, e.g. --units nm.")
    used = h.attrs.get("channel")
    size = f"{h.sizes['y']} x {h.sizes['x']} px" if "y" in h.dims else f"line scan of {h.sizes['x']} points"
    logging.getLogger("roughstick").info(
        f"{path}: {size} of {float(h.x[1] - h.x[0]) * 1e9:.4g} nm"
        + (f", channel {used}" + (f" (of {h.attrs['channels_in_file']})" if "channels_in_file" in h.attrs else "")
           if used else "")
        + (", periodic (a generated surface)" if str(h.attrs.get("periodic", 0)) in ("1", "True") else ""))
    return h
