"""Sphere-on-flat contact models (sphere.py) and their numpy kernels (_kernels.py)."""

from .sphere import *  # noqa: F403
from .sphere import __all__  # noqa: F401
