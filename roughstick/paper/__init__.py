"""The paper's figures, computed and drawn once, and the steps of ``roughstick demo``.

One module per figure group; each public function returns ``(xarray.Dataset, Figure)``: the data
behind the figure (CF attributes, SI units, ready for :func:`roughstick.io.write`) and the
matplotlib figure. ``roughstick demo`` (its steps are :mod:`roughstick.paper.demo`),
``roughstick reproduce`` and the notebooks call these functions, so a figure's code exists in one
place; saving is the caller's.
"""

from . import cantilever, demo, ensemble, rough_contact, sphere, topography

__all__ = ["cantilever", "demo", "ensemble", "rough_contact", "sphere", "topography"]
