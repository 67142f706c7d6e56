"""(temporary)"""

from . import pixel, validity
from .pixel import *  # noqa: F403
from .validity import *  # noqa: F403

__all__ = [*validity.__all__, *pixel.__all__]
