"""The FFT boundary-element model of humid rough contact (registered as ``"fft_bem"``).

:func:`fft_bem_curves`: the full elastic contact of a rough surface with a flat and a Dugdale
capillary zone on the periodic pixel grid, solved by our own conjugate gradient
(:mod:`._kernels`). :func:`periodic_offset_coefficient` converts its periodic distance
convention to the isolated-contact one of Eq. 16.
"""

from .._shared import periodic_offset_coefficient
from ._curves import MODEL, fft_bem_curves

__all__ = ["fft_bem_curves", "periodic_offset_coefficient", "MODEL"]
