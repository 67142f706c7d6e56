"""The ``.rough`` accessor on DataArray and Dataset: explicit one-line forwarding methods.

``height.rough.power_spectrum(window="hann")`` is ``roughstick.power_spectrum(height,
window="hann")``: each method passes the object as the first argument and nothing else happens
(no logic, no caching; cf. xskillscore's ``core/accessor.py``). Only the functions whose first
argument is that kind of object are offered: on a DataArray those of a height map, of a PSD, of a
relative humidity and of a Monte-Carlo sample; on a Dataset those of curves, summaries, moments and
ensembles. Importing :mod:`roughstick` registers it.
"""

from __future__ import annotations

import functools

import xarray as xr

from . import contact
from .contact import MODELS, meniscus
from .ensemble import distributions, statistics
from .ensemble import run as ensemble_run
from .stiction import beam, risk
from .surface import generate, moments, spectrum, summary, topography

__all__: list[str] = []


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
        methods = sorted(n for n in dir(self) if not n.startswith("_"))
        raise AttributeError(
            f"roughstick has no public function {name!r} that .rough forwards for a "
            f"{type(self._obj).__name__}; its methods are {methods}. Call roughstick.<function> directly."
        )


def _doc(func):
    home = "roughstick.contact" if func.__name__ in contact.__all__ else "roughstick"
    return f"``obj.rough.{func.__name__}(...)`` is :func:`{home}.{func.__name__}` ``(obj, ...)``."


@xr.register_dataarray_accessor("rough")
class RoughDataArrayAccessor(_Accessor):
    """Forwarding methods for a height map, a PSD, a relative humidity or a Monte-Carlo sample."""

    # ---- height map (y, x)
    def validate_height(self):
        return topography.validate_height(self._obj)

    def level(self, **kwargs):
        return topography.level(self._obj, **kwargs)

    def power_spectrum(self, **kwargs):
        return spectrum.power_spectrum(self._obj, **kwargs)

    def submap_psd(self, **kwargs):
        return spectrum.submap_psd(self._obj, **kwargs)

    def submap_variance_check(self, **kwargs):
        return spectrum.submap_variance_check(self._obj, **kwargs)

    def roughness_moments(self, **kwargs):
        return moments.roughness_moments(self._obj, **kwargs)

    def roughness_statistics(self, **kwargs):
        return summary.roughness_statistics(self._obj, **kwargs)

    def psd_summary(self, **kwargs):
        return summary.psd_summary(self._obj, **kwargs)

    def curves(self, **kwargs):  # and <model>_curves of every registered contact model
        return contact.curves(self._obj, **kwargs)

    def contact_distance_grid(self, **kwargs):
        return contact.contact_distance_grid(self._obj, **kwargs)

    # ---- PSD (qy, qx) or (q)
    def psd_isotropic(self, **kwargs):
        return spectrum.psd_isotropic(self._obj, **kwargs)

    def psd_moments(self, **kwargs):
        return moments.psd_moments(self._obj, **kwargs)

    def interpolate_psd(self, **kwargs):
        return spectrum.interpolate_psd(self._obj, **kwargs)

    def choose_cutoff(self, target, **kwargs):
        return moments.choose_cutoff(self._obj, target, **kwargs)

    def generate_surfaces(self, **kwargs):
        return generate.generate_surfaces(self._obj, **kwargs)

    def run_ensemble(self, **kwargs):
        return ensemble_run.run_ensemble(self._obj, **kwargs)

    # ---- relative humidity
    def kelvin_radius(self, **kwargs):
        return meniscus.kelvin_radius(self._obj, **kwargs)

    def laplace_pressure(self, **kwargs):
        return meniscus.laplace_pressure(self._obj, **kwargs)

    def meniscus_height(self, **kwargs):
        return meniscus.meniscus_height(self._obj, **kwargs)

    def adsorbed_layer(self, **kwargs):
        return meniscus.adsorbed_layer(self._obj, **kwargs)

    def water_height(self, **kwargs):
        return meniscus.water_height(self._obj, **kwargs)

    # ---- Monte-Carlo sample (e.g. adhesive_energy over realization)
    def confidence_band(self, **kwargs):
        return statistics.confidence_band(self._obj, **kwargs)

    def quantile_interval(self, quantiles, **kwargs):
        return statistics.quantile_interval(self._obj, quantiles, **kwargs)

    def ensemble_histogram(self, **kwargs):
        return distributions.ensemble_histogram(self._obj, **kwargs)

    def ensemble_ecdf(self, **kwargs):
        return distributions.ensemble_ecdf(self._obj, **kwargs)

    def stiction_probability(self, **kwargs):
        return risk.stiction_probability(self._obj, **kwargs)

    def crossing_length(self, **kwargs):
        return risk.crossing_length(self._obj, **kwargs)

    def stiction_risk(self, **kwargs):
        return risk.stiction_risk(self._obj, **kwargs)

    def crack_length_from_adhesive_energy(self, **kwargs):
        return beam.crack_length_from_adhesive_energy(self._obj, **kwargs)


@xr.register_dataset_accessor("rough")
class RoughDatasetAccessor(_Accessor):
    """Forwarding methods for curves, summaries, moments and ensembles."""

    _moments = True

    # ---- force-distance curves (..., rh, distance)
    def summary(self, **kwargs):
        return contact.summary(self._obj, **kwargs)

    # ---- moments m0, m2, m4
    def asperity_statistics(self):
        return moments.asperity_statistics(self._obj)

    def plasticity_index(self, **kwargs):
        return moments.plasticity_index(self._obj, **kwargs)

    def summit_density(self):
        return moments.summit_density(self._obj)

    def gw_cutoff_study(self, **kwargs):  # and <model>_curves of the models that take moments
        return contact.gw_cutoff_study(self._obj, **kwargs)

    # ---- ensembles and summaries over realization
    def confidence_band(self, **kwargs):
        return statistics.confidence_band(self._obj, **kwargs)

    def stiction_probability(self, **kwargs):
        return risk.stiction_probability(self._obj, **kwargs)

    def stiction_risk(self, **kwargs):
        return risk.stiction_risk(self._obj, **kwargs)

    def crossing_humidity(self, **kwargs):
        return risk.crossing_humidity(self._obj, **kwargs)


def _document(cls):
    """Each method's docstring names the function it forwards to (one line, as xskillscore)."""
    for name, meth in list(vars(cls).items()):
        if callable(meth) and not name.startswith("_"):
            meth.__doc__ = _doc(meth)


_document(RoughDataArrayAccessor)
_document(RoughDatasetAccessor)
