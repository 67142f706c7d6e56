"""Greenwood-Williamson statistical rough contact (paper §3.2, Eq. 14).

:func:`gw_curves` (registered as the contact model ``"gw"``) from spectral moments or from a
height map's own, :func:`gw_cutoff_study` (Fig. 9) and the joint density of summit height and
curvature :func:`summit_joint_density`; the quadrature kernels in :mod:`._kernels`.
"""

from ._curves import MODEL, REFERENCES, gw_curves, gw_cutoff_study, summit_joint_density

__all__ = ["gw_curves", "gw_cutoff_study", "summit_joint_density", "MODEL", "REFERENCES"]
