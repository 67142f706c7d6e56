"""How far to trust a set of contact curves: measured validity, pixel resolution, one report.

:mod:`.validity` bounds each model's error at a surface by the measured error of the nearest
measured cases (the table of ``roughstick/data/validity_map.csv``) and picks the cheapest model
within an accuracy; :mod:`.pixel` warns where the pixel does not resolve the water necks;
:mod:`.report` gathers what the pipeline checked in one :class:`TrustReport`, stored in the
curves' attributes. :mod:`.resolution` measures what the pixel costs (it calls the pipeline, so
this package does not import it: ``roughstick.contact.resolution_study``).
"""

from .pixel import FINE_PIXEL, RESOLVED_NECK_PIXELS, PixelResolutionWarning, warn_if_unresolved
from .report import TrustReport
from .validity import (
    VALIDITY_BOUND,
    ErrorBound,
    ValidityWarning,
    expected_surface_groups,
    model_error,
    select_model,
    surface_groups,
    validity_map,
    warn_if_outside_validity,
)

__all__ = [
    "TrustReport", "ValidityWarning", "PixelResolutionWarning", "ErrorBound", "VALIDITY_BOUND",
    "RESOLVED_NECK_PIXELS", "FINE_PIXEL", "surface_groups", "expected_surface_groups",
    "validity_map", "model_error", "select_model", "warn_if_outside_validity",
    "warn_if_unresolved",
]
