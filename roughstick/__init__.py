"""roughstick: uncertainty of humid stiction between rough, hard surfaces.

Implements T.-V. Hoang, L. Wu, S. Paquay, A.C. Obreja, R.C. Voicu, R. Müller, J.-C. Golinval,
L. Noels, "A probabilistic model for predicting the uncertainties of the humid stiction phenomenon
on hard materials", J. Comput. Appl. Math. 289 (2015) 173-195, doi:10.1016/j.cam.2015.02.022
(:data:`roughstick._core.references.BIBLIOGRAPHY`), as an xarray toolkit. All values are SI; see
:mod:`roughstick.conventions`.

The subpackages follow the data flow (docs/architecture.md): :mod:`.surface` (maps, spectra,
moments, generation) and :mod:`.io` → :mod:`.contact` (meniscus, sphere and rough-surface models,
Eq. 13) → :mod:`.ensemble` (Monte Carlo, bands) → :mod:`.stiction` (beams, risk). Their public
functions are re-exported here (``__all__`` gathers the subpackages' own, as MetPy's
``calc/__init__.py`` does); :mod:`.datasets`, :mod:`.testing`, :mod:`.plotting` and :mod:`.cli`
are used as modules.
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
    reliability,
    stiction,
    surface,
    testing,
)
from ._core import constants, conventions, materials
from ._core.materials import *  # noqa: F403
from ._core.units import UnitsError
from ._core.version import __version__
from ._renamed import RENAMED
from .contact import *  # noqa: F403
from .ensemble import *  # noqa: F403
from .io import *  # noqa: F403
from .reliability import stuck_probability
from .stiction import *  # noqa: F403
from .surface import *  # noqa: F403

#: Every public function and class, gathered from the subpackages' own ``__all__``.
__all__ = sorted(
    [name
     for mod in (materials, io, surface, contact, ensemble, stiction)
     for name in mod.__all__] + ["stuck_probability"]
)


def __getattr__(name: str):
    """Serve an old top-level name from its new home (:mod:`roughstick._renamed`), saying so."""
    target = RENAMED.get(name)
    if target is None:
        raise AttributeError(f"module 'roughstick' has no attribute {name!r}")
    module, _, attr = target.rpartition(".")
    obj = getattr(importlib.import_module(f"roughstick.{module}"), attr)
    warnings.warn(f"roughstick.{name} is now roughstick.{target}; the old name will be removed",
                  DeprecationWarning, stacklevel=2)
    return obj
