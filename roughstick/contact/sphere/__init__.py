"""(temporary)"""

from . import _models
from ._models import *  # noqa: F403

__all__ = list(_models.__all__)
