"""The ``.rough`` accessor on DataArray and Dataset: one-line forwarding methods.

``height.rough.power_spectrum(window="hann")`` is ``roughstick.surface.power_spectrum(height,
window="hann")``: each method passes the object as the first argument and nothing else happens (no
logic, no caching; cf. xskillscore's ``core/accessor.py``). The methods come from one table per
kind of data, ``{method name: function}``: a DataArray offers those of a height map, a PSD, a
relative humidity and a Monte-Carlo sample; a Dataset those of curves, moments and ensembles.
Besides the tables, ``<model>_curves`` is served for every model of the contact-model registry
(:data:`roughstick.contact.MODELS`) that takes the object (a map; moments for the models that take
them). Importing :mod:`roughstick` registers it.
"""

from __future__ import annotations

import functools
import warnings

import xarray as xr

from . import contact, ensemble, surface
from .contact import MODELS, meniscus
from .reliability import stuck
from .stiction import cantilever, risk

__all__ = ["HEIGHT_MAP", "PSD", "RELATIVE_HUMIDITY", "SAMPLE", "CURVES", "MOMENTS", "ENSEMBLE"]

# ------------------------------------------------------------------ DataArray: one table per kind
#: A height map ``(y, x)``.
HEIGHT_MAP = {
    "validate_height": surface.validate_height,
    "level": surface.level,
    "power_spectrum": surface.power_spectrum,
    "submap_psd": surface.submap_psd,
    "submap_variance_check": surface.submap_variance_check,
    "roughness_moments": surface.roughness_moments,
    "roughness_statistics": surface.roughness_statistics,
    "psd_summary": surface.psd_summary,
    "curves": contact.curves,  # and <model>_curves of every registered contact model
    "contact_distance_grid": contact.contact_distance_grid,
}
#: A PSD ``(qy, qx)`` or ``(q)``.
PSD = {
    "psd_isotropic": surface.psd_isotropic,
    "psd_moments": surface.psd_moments,
    "interpolate_psd": surface.interpolate_psd,
    "choose_cutoff": surface.choose_cutoff,
    "generate_surfaces": surface.generate_surfaces,
    "run": ensemble.run,
}
#: A relative humidity.
RELATIVE_HUMIDITY = {
    "kelvin_radius": meniscus.kelvin_radius,
    "laplace_pressure": meniscus.laplace_pressure,
    "meniscus_height": meniscus.meniscus_height,
    "adsorbed_layer": meniscus.adsorbed_layer,
    "water_height": meniscus.water_height,
}
#: A Monte-Carlo sample, e.g. ``adhesive_energy`` over ``realization``.
SAMPLE = {
    "confidence_band": ensemble.confidence_band,
    "quantile_interval": ensemble.quantile_interval,
    "histogram": ensemble.histogram,
    "ecdf": ensemble.ecdf,
    "stuck_probability": stuck.stuck_probability,
    "crossing_length": risk.crossing_length,
    "risk_summary": risk.risk_summary,
    "crack_length_from_adhesive_energy": cantilever.crack_length_from_adhesive_energy,
}

# -------------------------------------------------------------------- Dataset: one table per kind
#: Force-distance curves ``(..., rh, distance)``.
CURVES = {
    "summary": contact.summary,
}
#: Spectral moments ``m0``, ``m2``, ``m4`` (and <model>_curves of the models that take moments).
MOMENTS = {
    "asperity_statistics": surface.asperity_statistics,
    "plasticity_index": surface.plasticity_index,
    "summit_density": surface.summit_density,
    "gw_cutoff_study": contact.gw_cutoff_study,
}
#: Ensembles and summaries over ``realization``.
ENSEMBLE = {
    "confidence_band": ensemble.confidence_band,
    "stuck_probability": stuck.stuck_probability,
    "risk_summary": risk.risk_summary,
    "crossing_humidity": risk.crossing_humidity,
}

#: Method names of earlier releases and the method that replaced each (served with a warning).
RENAMED_METHODS = {
    "rough_contact_curves": "curves",
    "gw_contact_curves": "gw_curves", "bem_contact_curves": "bem_curves",
    "fft_bem_contact_curves": "fft_bem_curves", "adhesion_summary": "summary",
    "run_ensemble": "run", "ensemble_histogram": "histogram", "ensemble_ecdf": "ecdf",
    "stiction_probability": "stuck_probability", "stiction_risk": "risk_summary",
}


# ------------------------------------------------------------------------------- the mechanism
def _public_path(func) -> str:
    """``roughstick.<namespace>.<name>`` of a public function."""
    return ".".join(func.__module__.split(".")[:2] + [func.__name__])


def _forward(name: str, func):
    """The method ``obj.rough.<name>(...)``: ``func(obj, ...)``, nothing else."""

    def method(self, *args, **kwargs):
        return func(self._obj, *args, **kwargs)

    method.__name__ = method.__qualname__ = name
    method.__doc__ = f"``obj.rough.{name}(...)`` is :func:`{_public_path(func)}` ``(obj, ...)``."
    method.__forwards_to__ = func
    return method


class _Accessor:
    #: Whether the object is the input of a contact model (a map; moments for a Dataset).
    _moments = False

    def __init__(self, obj):
        self._obj = obj

    def _models(self) -> dict:
        """``<model>_curves`` of every registered contact model that takes this object."""
        return {f"{name}_curves": m for name, m in MODELS.items()
                if not self._moments or m.accepts_moments}

    def __dir__(self):
        return sorted({*super().__dir__(), *self._models()})

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        model = self._models().get(name)
        if model is not None:  # read from the contact-model registry
            return functools.partial(model.function or functools.partial(contact.curves, model=model.name),
                                     self._obj)
        new = RENAMED_METHODS.get(name)
        if new is not None and new != name and (hasattr(type(self), new) or new in self._models()):
            warnings.warn(f".rough.{name} is now .rough.{new}; the old name will be removed",
                          DeprecationWarning, stacklevel=2)
            return getattr(self, new)
        methods = sorted(n for n in dir(self) if not n.startswith("_"))
        raise AttributeError(
            f"roughstick has no public function {name!r} that .rough forwards for a "
            f"{type(self._obj).__name__}; its methods are {methods}. Call the function of its "
            "namespace directly (roughstick.surface, roughstick.contact, ...)."
        )


def _accessor(cls_name: str, doc: str, *tables: dict, moments: bool = False) -> type:
    methods = {}
    for table in tables:
        for name, func in table.items():
            if name in methods:
                raise ValueError(f".rough.{name} is in two tables of one accessor")
            methods[name] = _forward(name, func)
    return type(cls_name, (_Accessor,), {"__doc__": doc, "__module__": __name__, "_moments": moments,
                                         **methods})


RoughDataArrayAccessor = xr.register_dataarray_accessor("rough")(_accessor(
    "RoughDataArrayAccessor",
    "Forwarding methods for a height map, a PSD, a relative humidity or a Monte-Carlo sample.",
    HEIGHT_MAP, PSD, RELATIVE_HUMIDITY, SAMPLE))
RoughDatasetAccessor = xr.register_dataset_accessor("rough")(_accessor(
    "RoughDatasetAccessor",
    "Forwarding methods for curves, moments and ensembles.",
    CURVES, MOMENTS, ENSEMBLE, moments=True))
