"""Stiction (paper §5): from the adhesive energy of rough surfaces to the risk of a stuck beam.

:mod:`.cantilever` (the beams, Eq. 36 both ways, the critical adhesive energy), :mod:`.risk` (what
a sample of Γ says: the crossing humidity and length, the designer's summary, measured points)
and :mod:`.interaction_zone` (the §5.2 model of the zone behind the crack front: Table 4 ->
Eq. 37 -> an ensemble of zone surfaces). P(stuck) itself, by counting, subset simulation or the
beam-scale model, is :func:`roughstick.reliability.stuck_probability`.
"""

from . import cantilever, interaction_zone, risk, strip_tail, zone
from .cantilever import *  # noqa: F403
from .interaction_zone import *  # noqa: F403
from .risk import *  # noqa: F403
from .strip_tail import *  # noqa: F403
from .zone import *  # noqa: F403

__all__ = [name for mod in (cantilever, risk, interaction_zone, zone, strip_tail) for name in mod.__all__]
