"""Canonical dimension names, variable names and their CF attributes.

This module is the single source of truth for metadata. Functions never
hand-write attributes: they call :func:`set_attrs` with a key of :data:`ATTRS`.
All stored values are SI.
"""

from __future__ import annotations

import datetime as _dt

import xarray as xr

from .references import PAPER, cite
from .version import __version__

__all__ = ["ATTRS", "DIMS", "CONVENTIONS", "PAPER_REFERENCE", "CURVE_VARIABLES", "set_attrs", "coord_attrs", "append_history", "dataset_attrs"]

CONVENTIONS = "CF-1.10"

#: The paper this package implements (checked against the journal record).
PAPER_REFERENCE = cite(PAPER)

#: Variables of every force-distance curve Dataset over ``(..., rh, distance)``, in order: the
#: modified DMT (rough_contact), Greenwood-Williamson (``fit_error`` NaN) and the BEM reference
#: (which adds ``distance_offset`` and ``solver_residual``) all return them (docs/architecture.md).
CURVE_VARIABLES = (
    "pressure",
    "repulsive_pressure",
    "wet_fraction",
    "contact_fraction",
    "n_contacts",
    "fit_error",
    "max_interference",
)

#: Short dimension names.
DIMS = {
    "x": "x",
    "y": "y",
    "qx": "qx",
    "qy": "qy",
    "q": "q",
    "realization": "realization",
    "rh": "rh",
    "distance": "distance",
    "interference": "interference",
    "quantile": "quantile",
}

#: CF attributes of every coordinate and variable the package writes.
ATTRS: dict[str, dict[str, str]] = {
    # coordinates
    "x": {"units": "m", "long_name": "x position (pixel centre)", "axis": "X"},
    "y": {"units": "m", "long_name": "y position (pixel centre)", "axis": "Y"},
    "qx": {"units": "rad m-1", "long_name": "angular wavevector, x component"},
    "qy": {"units": "rad m-1", "long_name": "angular wavevector, y component"},
    "q": {"units": "rad m-1", "long_name": "angular wavevector magnitude"},
    "realization": {"units": "1", "long_name": "realization index", "standard_name": "realization"},
    "rh": {"units": "1", "long_name": "relative humidity", "standard_name": "relative_humidity"},
    "distance": {"units": "m", "long_name": "distance from the flat to the mean plane of the rough surface"},
    "interference": {"units": "m", "long_name": "interference (approach of the sphere past first contact)"},
    "radius": {"units": "m", "long_name": "sphere (asperity) radius"},
    "quantile": {"units": "1", "long_name": "quantile"},
    "temperature": {"units": "K", "long_name": "absolute temperature", "standard_name": "air_temperature"},
    "contact_angle": {"units": "rad", "long_name": "water contact angle"},
    # topography and spectra
    "height": {"units": "m", "long_name": "surface height"},
    "psd": {"units": "m4", "long_name": "power spectral density of height (2D)", "scaling": "density"},
    "psd_isotropic": {"units": "m4", "long_name": "radially averaged power spectral density of height", "scaling": "density"},
    "psd_1d": {"units": "m3", "long_name": "power spectral density of height profiles (1D)", "scaling": "density"},
    "m0": {"units": "m2", "long_name": "variance of height (m0)"},
    "m2": {"units": "1", "long_name": "variance of slope in one direction (m2)"},
    "m4": {"units": "m-2", "long_name": "variance of curvature in one direction (m4)"},
    "summit_density": {"units": "m-2", "long_name": "Nayak summit density"},
    "summit_radius": {"units": "m", "long_name": "mean summit radius"},
    "bandwidth": {"units": "1", "long_name": "Nayak bandwidth parameter alpha = m0 m4 / m2**2"},
    "plasticity_index": {"units": "1", "long_name": "Greenwood-Williamson plasticity index"},
    # meniscus
    "kelvin_radius": {"units": "m", "long_name": "Kelvin radius"},
    "laplace_pressure": {"units": "Pa", "long_name": "Laplace pressure inside the meniscus (negative: tension)"},
    "meniscus_height": {"units": "m", "long_name": "meniscus height"},
    "adsorbed_layer": {"units": "m", "long_name": "adsorbed water layer thickness (sum over both surfaces)"},
    "adsorbed_layer_model": {"long_name": "adsorbed water layer model"},  # a string label: no units (CF)
    "water_height": {"units": "m", "long_name": "height of condensed water"},
    # sphere contact
    "force": {"units": "N", "long_name": "normal force (positive repulsive)"},
    "contact_radius": {"units": "m", "long_name": "radius of the repulsive contact"},
    "adhesive_radius": {"units": "m", "long_name": "outer radius of the adhesive zone"},
    "indentation": {"units": "m", "long_name": "indentation"},
    "adhesive_energy": {"units": "J", "long_name": "work to separate the sphere from the flat"},
    "transition_parameter": {"units": "1", "long_name": "Maugis transition parameter lambda"},
    "work_of_adhesion": {"units": "J m-2", "long_name": "work of adhesion"},
    "reduced_modulus": {"units": "Pa", "long_name": "reduced (contact) modulus E*"},
    # rough contact
    "pressure": {"units": "Pa", "long_name": "mean pressure on the apparent area (positive repulsive)"},
    "repulsive_pressure": {"units": "Pa", "long_name": "repulsive (Hertz) part of the mean pressure"},
    "wet_fraction": {"units": "1", "long_name": "wetted area fraction (net of the contact area)"},
    "contact_fraction": {"units": "1", "long_name": "real contact area fraction"},
    "n_contacts": {"units": "1", "long_name": "number of contacting asperities"},
    "fit_error": {"units": "m", "long_name": "area-weighted rms error of the asperity sphere fits (Eq. 23)"},
    "max_interference": {"units": "m", "long_name": "interference of the highest asperity"},
    "surface_adhesive_energy": {"units": "J m-2", "long_name": "apparent adhesive energy (Eq. 13)"},
    "pull_off_pressure": {"units": "Pa", "long_name": "largest tensile mean pressure (pull-off)"},
    "equilibrium_distance": {"units": "m", "long_name": "distance at which the mean pressure vanishes",
                             "comment": "outermost stable zero crossing (repulsive below, attractive "
                                        "above); NaN where the pressure is attractive down to the "
                                        "bottom of the grid (no equilibrium: the surfaces collapse "
                                        "into contact, adhesive_energy is then a lower bound) or "
                                        "repulsive up to its top (the equilibrium lies above the "
                                        "grid: adhesive_energy = 0 then says nothing; a "
                                        "CurveGridWarning names the fix)"},
    "attraction_below_equilibrium": {"units": "J m-2", "long_name": "attractive work below the equilibrium distance (excluded from the adhesive energy)"},
    "wet_fraction_at_equilibrium": {"units": "1", "long_name": "wetted area fraction at the equilibrium distance"},
    "distance_offset": {"units": "m", "long_name": "isolated-contact distance minus periodic (mean-gap) distance of the BEM"},
    "solver_residual": {"units": "1", "long_name": "relative residual of the boundary-element solve"},
    # ensembles
    "max_height": {"units": "m", "long_name": "highest point of the surface above its mean plane"},
    "surface_size": {"units": "m", "long_name": "side length of the generated surface (x)"},
    "cumulative_probability": {"units": "1", "long_name": "empirical cumulative probability"},
    # cantilever (Eq. 36) and stiction risk
    "beam_length": {"units": "m", "long_name": "cantilever beam length"},
    "crack_length": {"units": "m", "long_name": "crack length s of an S-shaped stuck cantilever (Eq. 36)"},
    "critical_adhesive_energy": {"units": "J m-2", "long_name": "adhesive energy at which the crack length equals the beam length (Eq. 36, s = l)"},
    "stiction_probability": {"units": "1", "long_name": "probability that the beam stays stuck, P(Gamma > Gamma_crit)"},
    "n_stuck": {"units": "1", "long_name": "number of Monte-Carlo members with Gamma > Gamma_crit"},
    "n_samples": {"units": "1", "long_name": "number of valid Monte-Carlo members"},
    "probability_level": {"units": "1", "long_name": "stiction probability level"},
    "crossing_humidity": {"units": "1", "long_name": "relative humidity at which the stiction probability first reaches the level"},
    "crossing_length": {"units": "m", "long_name": "beam length above which the stiction probability reaches the level"},
}


def coord_attrs(name: str, var) -> dict:
    """Canonical attributes of coordinate ``name``; a string-valued coordinate (e.g. the
    ``adsorbed_layer`` model labels "none"/"paper") gets a ``long_name`` and no ``units`` (CF)."""
    if getattr(var, "dtype", None) is not None and var.dtype.kind in "OSU":
        attrs = ATTRS.get(f"{name}_model", ATTRS.get(name, {}))
        return {k: v for k, v in attrs.items() if k == "long_name"} or {"long_name": name}
    return dict(ATTRS[name])


def set_attrs(obj: xr.DataArray, name: str, **extra) -> xr.DataArray:
    """Return ``obj`` with the canonical attributes of ``name`` (plus ``extra``).

    Coordinates that have a canonical name also get their attributes.
    """
    out = obj.copy(deep=False)
    out.attrs = {**ATTRS[name], **extra}
    for c in out.coords:
        if c in ATTRS:
            out[c].attrs = coord_attrs(c, out[c])
    return out


def set_coord_attrs(obj):
    """Give every coordinate with a canonical name its canonical attributes (in place)."""
    for c in obj.coords:
        if c in ATTRS:
            obj[c].attrs = coord_attrs(c, obj[c])
    return obj


def append_history(obj, line: str):
    """Append one timestamped line to ``obj.attrs['history']`` (in place) and return ``obj``."""
    stamp = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    prev = obj.attrs.get("history", "")
    obj.attrs["history"] = (prev + "\n" if prev else "") + f"{stamp} {line}"
    return obj


def dataset_attrs(title: str, *, references: str = "", **params) -> dict:
    """Global attributes of a Dataset written by roughstick."""
    attrs = {
        "Conventions": CONVENTIONS,
        "title": title,
        "source": f"roughstick {__version__}",
        "references": references,
    }
    for k, v in params.items():
        attrs[k] = v
    return attrs
