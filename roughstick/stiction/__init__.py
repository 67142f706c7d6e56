"""Stiction (paper §5): cantilevers, Eq. 36, the risk read off a sample of Γ, the interaction zone."""

from . import cantilever, interaction_zone, risk
from .cantilever import *  # noqa: F403
from .interaction_zone import *  # noqa: F403
from .risk import *  # noqa: F403

__all__ = [name for mod in (cantilever, risk, interaction_zone) for name in mod.__all__]
