"""Reliability: P(stuck) by one verb, and small probabilities by subset simulation.

:func:`stuck_probability` estimates the probability that a cantilever stays stuck by counting a
sample, by the beam-scale model or by subset simulation (``method=``). Under it:
:func:`subset_simulation`, the generic engine (any limit state of standard-normal white noise:
adaptive pCN chains, resumable levels on dask, genealogical cv), :func:`failure_probability`
(the rough-surface limit state: a zone's adhesive energy or pull-off above a threshold),
:func:`surface_from_noise` (the surface a failure sample maps to) and :func:`weakest_link`
(structures of independent patches).
"""

from .stuck import stuck_probability
from .subset import subset_simulation, weakest_link
from .surface import failure_probability, surface_from_noise

__all__ = ["stuck_probability", "subset_simulation", "failure_probability", "surface_from_noise",
           "weakest_link"]
