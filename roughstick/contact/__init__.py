"""Contact: from a humidity and a surface (or a sphere) to force-distance curves and Eq. 13.

The second stage of the data flow (paper §2-3):

- meniscus physics (:mod:`.meniscus`, Eqs. 1-6) and sphere-on-flat models (:mod:`.sphere`,
  Eqs. 7-11);
- the rough-surface contact models, one registry (:data:`MODELS`, :func:`register_model`) of
  one protocol (:class:`ContactModel`): the modified DMT (:mod:`.modified_dmt`, Eqs. 16-23),
  Greenwood-Williamson (:mod:`.gw`, Eq. 14), the FFT boundary-element model (:mod:`.fft_bem`)
  and the Tamaas reference (:mod:`.bem`), all run by one pipeline behind :func:`curves`
  (``model=`` a registered name or ``"auto"``);
- how far to trust the curves (:mod:`.trust`: measured validity, pixel resolution, one
  :class:`TrustReport`);
- the reduction to the adhesive energy, pull-off and equilibrium (:func:`summary`, Eq. 13).
"""

import importlib
import warnings

from .._renamed import RENAMED
from . import meniscus, trust
from ._model import (
    MODEL_CHOICES,
    MODELS,
    ContactModel,
    Grid,
    Option,
    model_names,
    register_model,
    unregister_model,
)
from ._pipeline import curves
from .adhesion import CurveGridWarning, summary
from .bem import bem_curves
from .fft_bem import fft_bem_curves
from .gw import gw_curves, gw_cutoff_study, summit_joint_density
from .meniscus import *  # noqa: F403
from .modified_dmt import contact_distance_grid, modified_dmt_curves
from .sphere import (
    SPHERE_MODELS,
    sphere_adhesive_energy,
    sphere_contact,
    sphere_force,
    transition_parameter,
)
from .trust import *  # noqa: F403
from .trust.resolution import resample_pixels, resolution_study

__all__ = [
    # the pipeline and the registry
    "curves", "summary", "MODELS", "MODEL_CHOICES", "model_names", "register_model",
    "unregister_model",
    "ContactModel", "Option", "Grid",
    # the models' own functions
    "modified_dmt_curves", "contact_distance_grid", "gw_curves", "gw_cutoff_study",
    "summit_joint_density", "fft_bem_curves", "bem_curves",
    # meniscus and sphere
    *meniscus.__all__, "SPHERE_MODELS", "sphere_force", "sphere_contact", "sphere_adhesive_energy",
    "transition_parameter",
    # trust
    *trust.__all__, "resolution_study", "resample_pixels", "CurveGridWarning",
]


def __getattr__(name: str):
    """An old name of this namespace, served from its new home with a DeprecationWarning."""
    target = RENAMED.get(name, "")
    if target.startswith("contact."):
        module, _, attr = target.rpartition(".")
        obj = getattr(importlib.import_module(f"roughstick.{module}"), attr)
        warnings.warn(f"roughstick.contact.{name} is now roughstick.{target}; the old name will be "
                      "removed", DeprecationWarning, stacklevel=2)
        return obj
    raise AttributeError(f"module 'roughstick.contact' has no attribute {name!r}")

# the public names say where users reach them (pickles and the API page follow), as numpy does
for _name in __all__:
    _obj = globals()[_name]
    if callable(_obj) and getattr(_obj, "__module__", "").startswith(__name__ + "."):
        _obj.__module__ = __name__
del _name, _obj
