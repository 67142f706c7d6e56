"""The beam-scale model (paper §5): cantilevers released onto random patches of an interface.

A bank of patch laws (:func:`build_patch_bank`: the adhesive energies of random surface patches;
:func:`pressure_law_bank`: their pressure-distance curves) is drawn patch by patch under each
beam; :func:`simulate` releases the beams and reports their crack lengths and P(stuck), with the
sharp-front energy balance of Eq. 36 (:func:`crack_length`) or the cohesive Euler-Bernoulli beam
(:func:`release_cohesive`, :func:`step_cohesive`). The probability of staying stuck of any of
these, small values included, is :func:`roughstick.reliability.stuck_probability`.
"""

from . import cohesive, front_tail, patch_bank, sharp_front
from .cohesive import *  # noqa: F403
from .front_tail import *  # noqa: F403
from .patch_bank import *  # noqa: F403
from .sharp_front import *  # noqa: F403

__all__ = [name for mod in (sharp_front, front_tail, cohesive, patch_bank) for name in mod.__all__]
