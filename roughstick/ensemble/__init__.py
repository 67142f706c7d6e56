"""Ensembles: Monte Carlo over generated surfaces, reduced to bands and distributions (§4.3).

The third stage of the data flow. :func:`run` is the entry point (surfaces → curves → summaries
for every realization, lazy or streamed to a folder that :func:`open_ensemble` reads back);
:func:`confidence_band`, :func:`quantile_interval`, :func:`binomial_interval`, :func:`histogram`
and :func:`ecdf` reduce a sample with its own uncertainty; :func:`map_containment` says where the
measured maps an ensemble was built from fall in it.

Modules: :mod:`.pipeline` (one block, the lazy layout, :func:`distance_grid`), :mod:`.store`
(the ensemble folder), :mod:`.execute` (threads or a cluster, auto-n), :mod:`.runner`
(:func:`run`, :func:`surface_size_study`), :mod:`.statistics`, :mod:`.distributions`,
:mod:`.multifidelity` (a cheap model on every realization corrected by an accurate one on a
seeded subset) and :mod:`.maps` (the measured maps in their ensemble).
"""

from .distributions import ecdf, histogram
from .maps import ContainmentWarning, map_containment
from .multifidelity import accurate_subset, accurate_subset_size, multifidelity_band
from .pipeline import distance_grid
from .runner import run, surface_size_study
from .statistics import (
    band_summary,
    binomial_interval,
    confidence_band,
    min_samples_to_bound,
    quantile_interval,
)
from .store import open_ensemble

__all__ = [
    "run",
    "surface_size_study",
    "map_containment",
    "ContainmentWarning",
    "open_ensemble",
    "distance_grid",
    "confidence_band",
    "quantile_interval",
    "band_summary",
    "min_samples_to_bound",
    "binomial_interval",
    "histogram",
    "ecdf",
    "multifidelity_band",
    "accurate_subset",
    "accurate_subset_size",
]
