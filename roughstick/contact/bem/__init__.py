"""(temporary)"""

from . import _curves
from ._curves import *  # noqa: F403

__all__ = list(_curves.__all__)
