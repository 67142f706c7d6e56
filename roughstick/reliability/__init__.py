"""Small probabilities: subset simulation, limit states, weakest link."""

from . import subset
from .subset import *  # noqa: F403

__all__ = list(subset.__all__)
