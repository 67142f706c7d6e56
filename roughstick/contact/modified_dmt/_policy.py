"""The grid policy of the modified DMT: the named settings of its one-pass controller.

The controller (:func:`._controller.auto_pass`) walks down from the first water contact and
accepts an interval of distances when its midpoint lies on the chord of its ends; it bisects the
zero crossings (the equilibrium), refines around the pull-off and stops a margin below every
humidity's equilibrium. Each setting below says what it bounds; the curve's scale ``S`` is the
largest |pressure| met so far (at least the water term just above the first contact), ``sigma``
the rms height of the map and ``span`` its height range. :func:`policy_for` scales the shape
tolerances with the map size; :data:`GAMMA_TOLERANCE` (:mod:`._grid`) then refines each
humidity's Γ in Python.
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["GridPolicy", "DEFAULT_POLICY", "policy_for"]


class GridPolicy(NamedTuple):
    """Settings of the one-pass controller of the automatic grid (all relative, see the module)."""

    #: midpoint test: an interval passes when |p(mid) - chord| <= eps * S
    eps: float = 0.02
    #: ... or when it is narrower than eta * (distance below the first wetting), at most eta * sigma
    eta: float = 0.02
    #: near zero pressure (|p| <= zero_band * S) the test is fine times stricter
    fine: float = 0.1
    zero_band: float = 0.03
    #: pull-off rounds refine the intervals within pull_band of the most tensile pressure ...
    pull_band: float = 0.003
    #: ... and stop when a round improves it by less than pull_stop (0: run the rounds out)
    pull_stop: float = 0.0
    #: the walk stops margin * sigma below the outermost equilibrium of every humidity
    margin: float = 0.03
    #: no interval narrower than wfloor_rel * span is split
    wfloor_rel: float = 1e-5
    #: at most this many levels per pass
    max_points: int = 4000
    #: the equilibrium is bracketed to deq_tol * max(|d|, sigma) ...
    deq_tol: float = 0.004
    #: an interval at the pull-off is resolved below pull_fine * eta * min(distance below the
    #: first wetting, sigma)
    pull_fine: float = 2.0
    #: ... and smooth when its ends lie on their neighbours' chords within pull_smooth * |pull-off|
    pull_smooth: float = 0.002
    #: weight of the largest tie of pixels drying at one height inside an interval
    tie: float = 1.0
    #: in the zero band the width floor is zcap * eta * sigma
    zcap: float = 3.0
    #: ... or when the roots of the chord and of the half holding the crossing agree within
    #: deq_est * the bracket (intervals up to deq_maxw * the bracket)
    deq_est: float = 0.25
    deq_maxw: float = 2.0


#: The settings of a 1024 x 1024 map.
DEFAULT_POLICY = GridPolicy()


def policy_for(npix: int) -> GridPolicy:
    """Controller settings for a map of ``npix`` pixels: the tolerances on the curves' shape
    scale with sqrt(npix / 1024^2) between 0.25 and 1. Small maps have few contacting pixels, so
    their curves are staircases of large jumps that need a finer grid, and each level is cheap."""
    p = DEFAULT_POLICY
    f = min(1.0, max(0.25, (npix / 1024.0**2) ** 0.5))
    return p._replace(eps=p.eps * f, eta=p.eta * f, pull_smooth=p.pull_smooth * f)
