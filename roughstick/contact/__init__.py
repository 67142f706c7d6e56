"""(temporary)"""

from . import _pipeline, adhesion, bem, fft_bem, gw, meniscus, modified_dmt, sphere, trust
from ._pipeline import *  # noqa: F403
from .adhesion import *  # noqa: F403
from .bem import *  # noqa: F403
from .fft_bem import *  # noqa: F403
from .gw import *  # noqa: F403
from .meniscus import *  # noqa: F403
from .modified_dmt import *  # noqa: F403
from .sphere import *  # noqa: F403
from .trust import *  # noqa: F403
from .trust import resolution
from .trust.resolution import *  # noqa: F403

__all__ = [
    name
    for mod in (meniscus, sphere, modified_dmt, gw, bem, fft_bem, trust, _pipeline, adhesion, resolution)
    for name in mod.__all__
]
