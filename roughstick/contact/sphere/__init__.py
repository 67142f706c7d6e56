"""Sphere-on-flat contact with capillary adhesion (paper §3.1, Eqs. 7-11, Table 1).

Hertz, JKR, DMT, Maugis-Dugdale and the paper's modified DMT for one sphere against a flat in
humid air (:func:`sphere_force`, :func:`sphere_contact`, :func:`sphere_adhesive_energy`,
:func:`transition_parameter`); their numpy kernels (:func:`force_kernel`, Greenwood-Williamson's
summit force) in :mod:`._kernels` and the work of separation in :mod:`._energy`.
"""

from ._kernels import sphere_force_kernel as force_kernel
from ._models import (
    SPHERE_MODELS,
    sphere_adhesive_energy,
    sphere_contact,
    sphere_force,
    transition_parameter,
)

__all__ = ["SPHERE_MODELS", "sphere_force", "sphere_contact", "sphere_adhesive_energy",
           "transition_parameter", "force_kernel"]
