"""Measured validity of the rough-surface models against the boundary-element reference.

The paper validates the modified DMT (Eq. 16) on a single sphere only (Table 1) and states that it
holds for stiff materials. ``benchmarks/speed_vs_error.py`` measures the relative error of the
modified DMT and of Greenwood-Williamson (Eq. 14) against the full boundary-element solution
(:func:`roughstick.bem_contact_curves`) on S1- and S2-like surfaces, as the contact modulus drops
from poly-silicon to 1 GPa and as the humidity rises, and writes the table
``roughstick/data/validity_map.csv`` that this module reads (docs/accuracy.md gives the command,
date and machine). :func:`select_model` picks the cheapest model that meets a tolerance from that
table; :func:`warn_if_outside_validity` warns once per process when a modified-DMT call falls
where its measured error exceeds the bound. The dispatcher :func:`roughstick.rough_contact_curves`
(:mod:`roughstick.contact.curves`) uses both; the models themselves do not import this module.
"""

from __future__ import annotations

import csv
import functools
import sys
import warnings

import numpy as np

from .._core.materials import POLYSILICON, Material, reduced_modulus
from ..datasets import validity_map_path

__all__ = [
    "ValidityWarning",
    "validity_map",
    "model_error",
    "select_model",
    "warn_if_outside_validity",
    "VALIDITY_BOUND",
]

#: Relative error (on the apparent adhesive energy, Eq. 13) under which the modified DMT is
#: called valid (the issue's 10 %).
VALIDITY_BOUND = 0.10

_QUANTITIES = ("adhesive_energy", "pull_off_pressure", "equilibrium_distance")
_COST_ORDER = ("gw", "modified_dmt", "bem")


class ValidityWarning(UserWarning):
    """A model is used outside the regime where its measured error stays under the bound."""


@functools.lru_cache(maxsize=1)
def validity_map() -> dict[str, np.ndarray]:
    """The measured error table (``roughstick/data/validity_map.csv``) as a dict of arrays.

    Columns: ``sample`` (S1/S2-like surface), ``method`` (``gw`` or ``modified_dmt``),
    ``reduced_modulus`` [Pa], ``rh`` [1], the relative errors against the boundary-element
    reference ``error_adhesive_energy``, ``error_pull_off_pressure``,
    ``error_equilibrium_distance`` [1] (absolute values), and the BEM values they refer to.
    Produced by ``benchmarks/speed_vs_error.py --validity`` (see docs/accuracy.md).
    """
    try:
        path = validity_map_path()
    except FileNotFoundError as err:
        raise FileNotFoundError(
            f"{err} Regenerate it with python benchmarks/speed_vs_error.py --validity (needs the "
            "'bem' extra)."
        ) from None
    with path.open("r", encoding="utf-8") as fh:
        rows = [r for r in csv.DictReader(line for line in fh if not line.startswith("#"))]
    if not rows:
        raise RuntimeError(f"{path} holds no rows; regenerate it with benchmarks/speed_vs_error.py")
    out: dict[str, np.ndarray] = {}
    for key in rows[0]:
        vals = [r[key] for r in rows]
        try:
            out[key] = np.array([float(v) if v != "" else np.nan for v in vals])
        except ValueError:
            out[key] = np.array(vals)
    return out


def model_error(
    method: str,
    *,
    reduced_modulus_value: float,
    relative_humidity: float,
    quantity: str = "adhesive_energy",
) -> tuple[float, str]:
    """Measured relative error of ``method`` against the BEM at one (E*, RH) point.

    The table is interpolated linearly in (log E*, RH) between measured points, taking the worst
    sample; outside the measured range the nearest edge is used and the reason says so.

    Parameters
    ----------
    method : {"gw", "modified_dmt"}
        Model whose error is wanted.
    reduced_modulus_value : float
        Contact modulus E* [Pa].
    relative_humidity : float
        RH fraction in (0, 1).
    quantity : {"adhesive_energy", "pull_off_pressure", "equilibrium_distance"}
        Summary whose error is looked up.

    Returns
    -------
    (float, str)
        The relative error (NaN if never measured) and a note on how it was obtained.
    """
    if method not in ("gw", "modified_dmt"):
        raise ValueError(f"method must be 'gw' or 'modified_dmt', got {method!r}.")
    if quantity not in _QUANTITIES:
        raise ValueError(f"quantity must be one of {_QUANTITIES}, got {quantity!r}.")
    if not 0 < relative_humidity < 1:
        raise ValueError(f"relative_humidity must lie in (0, 1), got {relative_humidity!r}.")
    if not reduced_modulus_value > 0:
        raise ValueError(f"reduced modulus must be positive (Pa), got {reduced_modulus_value!r}.")
    try:
        table = validity_map()
    except FileNotFoundError:
        return float("nan"), "the measured validity map is not installed"
    sel = table["method"] == method
    err = np.abs(table[f"error_{quantity}"][sel])
    if "converged" in table:
        # no equilibrium on the measurement grid: the error is not a number, only "large"
        err = np.where(table["converged"][sel] == 0, np.inf, err)
    logE = np.log(table["reduced_modulus"][sel])
    rh = table["rh"][sel]
    if err.size == 0:
        return float("nan"), f"no measurement of {method} in the validity map"
    note = []
    Es = np.unique(logE)
    RHs = np.unique(rh)
    x = float(np.log(reduced_modulus_value))
    y = float(relative_humidity)
    if x < Es.min() or x > Es.max():
        note.append(
            f"E* outside the measured {np.exp(Es.min()) / 1e9:.3g}-{np.exp(Es.max()) / 1e9:.3g} GPa"
        )
    if y < RHs.min() or y > RHs.max():
        note.append(f"RH outside the measured {RHs.min():.2f}-{RHs.max():.2f}")
    x = float(np.clip(x, Es.min(), Es.max()))
    y = float(np.clip(y, RHs.min(), RHs.max()))

    def worst(e_val, r_val):
        m = (logE == e_val) & (rh == r_val)
        vals = err[m][~np.isnan(err[m])]
        return float(vals.max()) if vals.size else np.nan

    def bracket(values, v):
        i = int(np.clip(np.searchsorted(values, v), 1, max(len(values) - 1, 1)))
        if len(values) == 1:
            return values[0], values[0], 0.0
        lo, hi = values[i - 1], values[i]
        t = 0.0 if hi == lo else (v - lo) / (hi - lo)
        return lo, hi, float(np.clip(t, 0, 1))

    e0, e1, te = bracket(Es, x)
    r0, r1, tr = bracket(RHs, y)
    corners = np.array([[worst(e0, r0), worst(e0, r1)], [worst(e1, r0), worst(e1, r1)]])
    if np.all(np.isnan(corners)):
        return float("nan"), "no measurement near this point"
    # missing corners: fall back to the worst measured neighbour (conservative)
    corners = np.where(np.isnan(corners), np.nanmax(corners), corners)
    weights = np.array([[(1 - te) * (1 - tr), (1 - te) * tr], [te * (1 - tr), te * tr]])
    if np.any(np.isinf(corners) & (weights > 0)):
        value = np.inf
    else:
        value = float(np.sum(weights * np.where(weights > 0, corners, 0.0)))
    how = "interpolated from the measured map (worst of the S1/S2-like surfaces)"
    return float(value), "; ".join([how, *note])


def _modulus(material, material2, reduced_modulus_value):
    if reduced_modulus_value is not None:
        return float(reduced_modulus_value)
    return reduced_modulus(material, material2)


def select_model(
    *,
    tolerance: float,
    relative_humidity: float,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    reduced_modulus_value: float | None = None,
    quantity: str = "adhesive_energy",
) -> tuple[str, str]:
    """Cheapest model whose measured error against the BEM meets ``tolerance``.

    GW (Eq. 14) is the cheapest, then the modified DMT (Eq. 16), then the boundary-element
    reference; the errors come from :func:`model_error` (the measured validity map).

    Parameters
    ----------
    tolerance : float
        Accepted relative error of ``quantity`` (e.g. 0.1 for 10 %), > 0.
    relative_humidity : float
        RH fraction in (0, 1); for several humidities call once per value or pass the highest
        error case.
    material, material2 : Material
        The two bodies (E* as in :func:`roughstick.reduced_modulus`).
    reduced_modulus_value : float, optional
        E* [Pa], overrides the materials.
    quantity : {"adhesive_energy", "pull_off_pressure", "equilibrium_distance"}
        Summary the tolerance applies to.

    Returns
    -------
    (str, str)
        ``"gw"``, ``"modified_dmt"`` or ``"bem"``, and the reason (measured errors quoted).
    """
    if not tolerance > 0:
        raise ValueError(f"tolerance must be a positive relative error, got {tolerance!r}.")
    E = _modulus(material, material2, reduced_modulus_value)
    notes = []
    for method in _COST_ORDER[:2]:
        err, how = model_error(
            method, reduced_modulus_value=E, relative_humidity=relative_humidity, quantity=quantity
        )
        if np.isinf(err):
            notes.append(f"{method}: unbounded (no equilibrium on the measurement grid)")
        else:
            notes.append(f"{method}: {err:.1%}" if np.isfinite(err) else f"{method}: unmeasured")
        if np.isfinite(err) and err <= tolerance:
            return method, (
                f"measured {quantity} error of {method} vs BEM {err:.1%} <= tolerance "
                f"{tolerance:.1%} at E* = {E / 1e9:.3g} GPa, RH = {relative_humidity:.2f} ({how})"
            )
    return "bem", (
        f"no cheaper model meets tolerance {tolerance:.1%} at E* = {E / 1e9:.3g} GPa, "
        f"RH = {relative_humidity:.2f} (measured {quantity} errors vs BEM: {', '.join(notes)})"
    )


_WARNED: set = set()


def _external_stacklevel() -> int:
    """``stacklevel`` of the first caller frame that is not inside the roughstick package."""
    frame = sys._getframe(1)
    level = 1
    while frame is not None and frame.f_globals.get("__name__", "").split(".")[0] == "roughstick":
        frame = frame.f_back
        level += 1
    return level


def warn_if_outside_validity(
    *,
    relative_humidity,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    reduced_modulus_value: float | None = None,
    bound: float = VALIDITY_BOUND,
    stacklevel: int | None = None,
) -> bool:
    """Warn (once per process) if the modified DMT's measured error exceeds ``bound`` here.

    Parameters
    ----------
    relative_humidity : float or array_like
        RH fraction(s); the worst one decides.
    material, material2, reduced_modulus_value
        As in :func:`select_model`.
    bound : float, default 0.10
        Relative error of the apparent adhesive energy taken as the validity limit.
    stacklevel : int, optional
        Passed to :func:`warnings.warn`; default: the first frame outside roughstick, so the
        warning points at the user's call.

    Returns
    -------
    bool
        True when the call lies outside the measured validity regime (warned or already warned).
    """
    E = _modulus(material, material2, reduced_modulus_value)
    rhs = np.atleast_1d(np.asarray(relative_humidity, dtype=float)).ravel()
    worst, where = 0.0, None
    for r in rhs:
        if not 0 < r < 1:
            continue
        err, how = model_error("modified_dmt", reduced_modulus_value=E, relative_humidity=float(r))
        if not np.isnan(err) and err > worst:
            worst, where = err, (float(r), how)
    if worst <= bound or where is None:
        return False
    key = ("modified_dmt", bound)
    if key not in _WARNED:
        _WARNED.add(key)
        warnings.warn(
            f"the modified DMT (Eq. 16) is outside its measured validity regime here: its "
            f"apparent adhesive energy differs from the boundary-element reference by "
            f"{'an unbounded amount' if np.isinf(worst) else format(worst, '.0%')} "
            f"(> {bound:.0%}) at E* = {E / 1e9:.3g} GPa, RH = {where[0]:.2f} "
            f"({where[1]}). Use model='bem' (pip install roughstick[bem]) or model='auto'; see "
            "docs/accuracy.md. This warning is shown once per process.",
            ValidityWarning,
            stacklevel=_external_stacklevel() if stacklevel is None else stacklevel,
        )
    return True
