"""roughstick: uncertainty of humid stiction between rough, hard surfaces.

Implements T.-V. Hoang, L. Wu, S. Paquay, A.C. Obreja, R.C. Voicu, R. Müller, J.-C. Golinval,
L. Noels, "A probabilistic model for predicting the uncertainties of the humid stiction phenomenon
on hard materials", J. Comput. Appl. Math. 289 (2015) 173-195, doi:10.1016/j.cam.2015.02.022
(:data:`roughstick._core.references.BIBLIOGRAPHY`), as an xarray toolkit. All values are SI; see
:mod:`roughstick.conventions`.

The front door: the stage namespaces in the order of the data flow (docs/architecture.md),
:mod:`.io` and :mod:`.surface` (maps, spectra, moments, random surfaces) → :mod:`.contact`
(meniscus, sphere and rough-surface models, Eq. 13) → :mod:`.ensemble` (Monte Carlo, bands) →
:mod:`.stiction` (Eq. 36, the §5 risk) → :mod:`.beam` (the beam-scale model) →
:mod:`.reliability` (P(stuck), small probabilities); the bodies and the beam; and the few verbs a
newcomer needs first. Everything else is in its namespace (``rs.contact.curves``); an old
top-level name still works, with a ``DeprecationWarning`` naming its new home.
"""

import importlib
import warnings

from . import (
    accessor,  # registers the .rough accessor on DataArray and Dataset
    beam,
    contact,
    datasets,
    ensemble,
    io,
    plotting,
    reliability,
    stiction,
    surface,
    testing,
)
from ._core import constants, conventions, materials
from ._core.materials import POLYSILICON, Material
from ._core.units import UnitsError
from ._core.validate import ValidityWarning
from ._core.version import __version__
from ._renamed import RENAMED
from .contact import PixelResolutionWarning
from .ensemble import band_summary, confidence_band
from .io import open_dataset, read_afm, write
from .reliability import stuck_probability
from .stiction import PAPER_CANTILEVER, Cantilever
from .surface import generate_surfaces, psd_moments, submap_psd

__all__ = [
    # the stage namespaces, in the order of the data flow
    "io", "surface", "contact", "ensemble", "stiction", "beam", "reliability",
    # bundled data, test helpers, figures, the metadata conventions, constants, materials
    "datasets", "testing", "plotting", "conventions", "constants", "materials",
    # the two bodies and the beam
    "Material", "POLYSILICON", "Cantilever", "PAPER_CANTILEVER",
    # what a result may raise or warn
    "UnitsError", "ValidityWarning", "PixelResolutionWarning",
    # the verbs a newcomer needs first: a map and its spectrum, surfaces, the band, P(stuck)
    "read_afm", "open_dataset", "write", "submap_psd", "psd_moments", "generate_surfaces",
    "confidence_band", "band_summary", "stuck_probability",
]


def _resolve(path: str):
    """The object at ``roughstick.<path>`` (attributes, importing sub-modules on the way)."""
    obj = importlib.import_module(__name__)
    for i, part in enumerate(path.split(".")):
        if not hasattr(obj, part):
            importlib.import_module(".".join([__name__, *path.split(".")[: i + 1]]))
        obj = getattr(obj, part)
    return obj


def __getattr__(name: str):
    """Serve an old top-level name from its new home (:mod:`roughstick._renamed`), saying so."""
    target = RENAMED.get(name)
    if target is None:
        raise AttributeError(f"module 'roughstick' has no attribute {name!r}")
    obj = _resolve(target)
    warnings.warn(f"roughstick.{name} is now roughstick.{target}; the old name will be removed",
                  DeprecationWarning, stacklevel=2)
    return obj
