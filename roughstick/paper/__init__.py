"""The paper's figures, computed and drawn once (issue 11's ``paper/``).

One module per figure group; each public function returns ``(xarray.Dataset, Figure)``: the data
behind the figure (CF attributes, SI units, ready for :func:`roughstick.io.netcdf.write`) and the
matplotlib figure. ``roughstick demo`` (:mod:`roughstick.demos`), ``roughstick reproduce`` and the
notebooks call these functions, so a figure's code exists in one place; saving is the caller's.
"""

from . import cantilever, ensemble, rough_contact, sphere, topography

__all__ = ["cantilever", "ensemble", "rough_contact", "sphere", "topography"]
