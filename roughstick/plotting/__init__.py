"""Plotting with matplotlib only (not imported by ``import roughstick``).

Axes show nm / µm / MPa for readability; data stay SI. One submodule per area.
"""

from .cantilever import *  # noqa: F403
from .ensemble import *  # noqa: F403
from .generation import *  # noqa: F403
from .gw import *  # noqa: F403
from .rough_contact import *  # noqa: F403
from .save import *  # noqa: F403
from .sphere import *  # noqa: F403
from .topography import *  # noqa: F403
