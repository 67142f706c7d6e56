"""One report of what the trust layer checked on a set of curves: :class:`TrustReport`.

The pipeline (:func:`roughstick.contact.curves`) fills it once per call with :func:`assess` and
stores it in the curves' attributes: why ``model="auto"`` chose the model, whether the model's
measured error bound at this surface meets the accuracy (:mod:`.validity`), whether the pixel
resolves the water necks (:mod:`.pixel`). Each check warns (:class:`roughstick.contact.ValidityWarning`)
where it fails, once, at the user's line.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..._core.validate import relative_humidity_values
from .pixel import RESOLVED_NECK_PIXELS, warn_if_unresolved
from .validity import warn_if_outside_validity

__all__ = ["TrustReport"]

#: Attribute of the curves Dataset holding each note of the report.
_ATTRS = {"selection": "model_selection", "validity": "validity_check", "resolution": "resolution_check"}


@dataclasses.dataclass(frozen=True)
class TrustReport:
    """What was checked on one set of contact curves, and what was found.

    Attributes
    ----------
    model : str
        The contact model that computed the curves.
    selection : str or None
        ``model="auto"``: its choice and why (``"auto -> gw: ..."``).
    validity : str or None
        The model's measured error bound at this surface against the accuracy, or why it was not
        checked (None: the check does not apply to this model).
    resolution : str or None
        Whether the pixel resolves the water necks, or why it was not checked.

    Examples
    --------
    >>> r = rs.contact.TrustReport("gw", selection="auto -> gw: its bound meets the accuracy")
    >>> r.to_attrs()
    {'model_selection': 'auto -> gw: its bound meets the accuracy'}
    >>> rs.contact.TrustReport.from_attrs({"contact_model": "gw", **r.to_attrs()}) == r
    True
    """

    model: str
    selection: str | None = None
    validity: str | None = None
    resolution: str | None = None

    def to_attrs(self) -> dict:
        """The notes as Dataset attributes (``model_selection``, ``validity_check``,
        ``resolution_check``; the absent ones left out)."""
        return {key: getattr(self, field) for field, key in _ATTRS.items()
                if getattr(self, field) is not None}

    @classmethod
    def from_attrs(cls, attrs) -> TrustReport:
        """The report stored in the attributes of a curves Dataset."""
        return cls(str(attrs.get("contact_model", "")),
                   **{field: attrs.get(key) for field, key in _ATTRS.items()})


def _eager_humidities(relative_humidity) -> bool:
    rhs = relative_humidity_values(relative_humidity)
    return bool(rhs.size and np.all((rhs > 0) & (rhs < 1)))


def _validity_note(model, height, *, relative_humidity, accuracy, quantity, **common) -> str | None:
    if getattr(height, "chunks", None) is not None:
        # a lazy stack stays lazy: its groups would need a computation
        return ("not checked (lazy input); check one map with roughstick.contact."
                "warn_if_outside_validity(height.isel(...).compute(), ...)")
    if not _eager_humidities(relative_humidity):
        return None
    warned = warn_if_outside_validity(height, relative_humidity=relative_humidity, model=model,
                                      accuracy=accuracy, quantity=quantity, **common)
    return (f"measured error bound above the accuracy {accuracy:g}" if warned else
            f"measured error bound within the accuracy {accuracy:g}")


def _resolution_note(height, *, relative_humidity, adsorbed_layer) -> str:
    if getattr(height, "chunks", None) is not None:
        return ("not checked (lazy input); check one map with roughstick.contact."
                "warn_if_unresolved(height.isel(...).compute(), relative_humidity=...)")
    if not _eager_humidities(relative_humidity):
        return "not checked (relative humidity outside (0, 1))"
    if warn_if_unresolved(height, relative_humidity=relative_humidity, adsorbed_layer=adsorbed_layer):
        return (f"wetted necks narrower than {RESOLVED_NECK_PIXELS:g} pixels: the pixel sets "
                "the adhesive energy (check with roughstick.contact.resolution_study)")
    return f"wetted necks span at least {RESOLVED_NECK_PIXELS:g} pixels at every humidity"


def assess(model, height, *, relative_humidity, material, material2, adsorbed_layer, accuracy,
           quantity, check: bool, selection: str | None = None) -> TrustReport:
    """Run the trust checks that apply to ``model`` (a ContactModel) on these curves' inputs.

    ``check=False`` runs none (an ensemble checks once, before it starts); ``selection`` (the
    reason of ``model="auto"``) skips the validity check, which the choice already met.
    """
    chosen = None if selection is None else f"auto -> {model.name}: {selection}"
    if not check:
        return TrustReport(model.name, selection=chosen)
    validity = None
    if "validity" in model.checks and selection is None:
        validity = _validity_note(model.name, height, relative_humidity=relative_humidity,
                                  accuracy=accuracy, quantity=quantity, material=material,
                                  material2=material2, adsorbed_layer=adsorbed_layer)
    resolution = None
    if "pixel" in model.checks:
        resolution = _resolution_note(height, relative_humidity=relative_humidity,
                                      adsorbed_layer=adsorbed_layer)
    return TrustReport(model.name, selection=chosen, validity=validity, resolution=resolution)
