"""roughstick: uncertainty of humid stiction between rough, hard surfaces.

Implements T.-V. Hoang, L. Wu, S. Paquay, A.C. Obreja, R.C. Voicu, R. Müller, J.-C. Golinval,
L. Noels, "A probabilistic model for predicting the uncertainties of the humid stiction phenomenon
on hard materials", J. Comput. Appl. Math. 289 (2015) 173-195, doi:10.1016/j.cam.2015.02.022
(:data:`roughstick._core.references.BIBLIOGRAPHY`), as an xarray toolkit.
All values are SI; see :mod:`roughstick._core.conventions`.
"""

from . import (  # noqa: E402
    accessor,  # noqa: E402  registers the .rough accessor
    contact,
    datasets,
    ensemble,
    stiction,
    surface,
    testing,
)
from ._core import constants, conventions, materials
from ._core.materials import *  # noqa: F403
from ._core.units import UnitsError
from ._core.version import __version__
from .contact import *  # noqa: F403
from .ensemble import *  # noqa: F403
from .io import afm as _afm  # noqa: E402
from .io import netcdf as _netcdf
from .io.afm import *  # noqa: F403
from .io.netcdf import *  # noqa: F403
from .stiction import *  # noqa: F403
from .surface import *  # noqa: F403

#: Every public function and class, gathered from the modules' own ``__all__``.
__all__ = sorted(
    name
    for mod in (
        materials, contact, _afm, _netcdf, surface, ensemble, stiction,
    )
    for name in mod.__all__
)
