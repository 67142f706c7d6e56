"""Stiction: from the adhesive energy of rough surfaces to the risk that a structure stays stuck.

The last stage of the paper (§5): :mod:`.beam` (cantilevers, Eq. 36 both ways, the critical
adhesive energy), :mod:`.risk` (stiction probability, crossing humidity and length, with their
Monte-Carlo intervals) and :mod:`.interaction_zone` (the §5.2 model of the zone behind the crack
front: Table 4 → Eq. 37 → an ensemble of zone surfaces). The beam-scale stochastic
model (:mod:`.beam_model`, :mod:`.patch_bank`; the cohesive beam of
:mod:`.cohesive_beam`, reached through ``simulate_beams(model="cohesive")``) and small probabilities (:mod:`.rare_events`) sit
beside them.
"""

from . import beam, beam_model, cohesive_beam, interaction_zone, patch_bank, rare_events, risk
from .beam import *  # noqa: F403
from .beam_model import *  # noqa: F403
from .cohesive_beam import *  # noqa: F403
from .interaction_zone import *  # noqa: F403
from .patch_bank import *  # noqa: F403
from .rare_events import *  # noqa: F403
from .risk import *  # noqa: F403

__all__ = [name for mod in (beam, risk, interaction_zone, beam_model, cohesive_beam, patch_bank,
                             rare_events)
           for name in mod.__all__]
