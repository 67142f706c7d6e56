"""Contact: from a humidity and a surface (or a sphere) to force-distance curves and Eq. 13.

The second stage of the data flow (paper §2-3): meniscus physics (:mod:`.meniscus`, Eqs. 1-6),
sphere-on-flat models (:mod:`.sphere` over the kernels of :mod:`._sphere_kernels`, Eqs. 7-11),
the rough-surface models (:mod:`.rough`, the modified DMT of Eqs. 16-23 with its compiled kernels
and literal reference; :mod:`.gw`, Greenwood-Williamson, Eq. 14; :mod:`.bem`, the boundary-element
reference; :mod:`.fft_bem`, the fast FFT boundary-element model), their measured validity
(:mod:`.validity`), their pixel-size sensitivity (:mod:`.pixel` warns, :mod:`.resolution`
measures), ONE dispatcher above them (:mod:`.curves`, :func:`rough_contact_curves`) and the
reduction to the adhesive energy (:mod:`.adhesion`, Eq. 13). The models never import the dispatcher.
"""

from . import (
    adhesion,
    bem,
    curves,
    fft_bem,
    gw,
    meniscus,
    pixel,
    resolution,
    rough,
    sphere,
    validity,
)
from .adhesion import *  # noqa: F403
from .bem import *  # noqa: F403
from .curves import *  # noqa: F403
from .fft_bem import *  # noqa: F403
from .gw import *  # noqa: F403
from .meniscus import *  # noqa: F403
from .pixel import *  # noqa: F403
from .resolution import *  # noqa: F403
from .rough import *  # noqa: F403
from .sphere import *  # noqa: F403
from .validity import *  # noqa: F403

__all__ = [
    name
    for mod in (meniscus, sphere, rough, gw, bem, fft_bem, validity, pixel, curves, adhesion, resolution)
    for name in mod.__all__
]
