"""Surfaces: height maps, their statistics and spectra, and random surfaces from a PSD.

The first stage of the data flow (paper §3.1, §4.1-4.2): a height map is validated and levelled
(:mod:`.topography`), its spectrum estimated (:mod:`.spectrum`, Eqs. 26-32) and its Nayak moments
measured (:mod:`.moments`, the one home of :math:`m_0, m_2, m_4`; line scans: :mod:`.profile`); or a PSD is built from a few
numbers (:mod:`.self_affine`, Eq. 37); then surfaces are drawn from it (:mod:`.generate`,
Eqs. 33-35), Gaussian or with a height distribution (:mod:`.distribution`), or mapped from white noise
(:mod:`.white_noise`, the random input of rare-event estimators). :mod:`.summary` chains these as the paper's §4.1 does;
:mod:`.compatibility` says when maps about to be averaged are not of one surface.
"""

from . import (
    combine,
    compatibility,
    distribution,
    gaussianity,
    generate,
    moments,
    profile,
    self_affine,
    spectrum,
    summary,
    topography,
    white_noise,
)
from .combine import *  # noqa: F403
from .compatibility import *  # noqa: F403
from .distribution import *  # noqa: F403
from .gaussianity import *  # noqa: F403
from .generate import *  # noqa: F403
from .moments import *  # noqa: F403
from .profile import *  # noqa: F403
from .self_affine import *  # noqa: F403
from .spectrum import *  # noqa: F403
from .summary import *  # noqa: F403
from .topography import *  # noqa: F403
from .white_noise import *  # noqa: F403

__all__ = [
    name
    for mod in (topography, spectrum, combine, compatibility, moments, profile, self_affine, distribution,
                gaussianity, generate, white_noise, summary)
    for name in mod.__all__
]
