"""The beam-scale model (paper §5): sharp front, cohesive beam, patch banks."""

from . import cohesive, patch_bank, sharp_front
from .cohesive import *  # noqa: F403
from .patch_bank import *  # noqa: F403
from .sharp_front import *  # noqa: F403

__all__ = [name for mod in (sharp_front, cohesive, patch_bank) for name in mod.__all__]
