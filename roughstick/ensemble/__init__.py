"""Ensembles: Monte Carlo over generated surfaces, reduced to bands and distributions (§4.3).

The third stage of the data flow: :mod:`.pipeline` (one block: surfaces → curves → summaries, and
the lazy layout of all blocks), :mod:`.store` (streaming to a folder, resume), :mod:`.execute`
(threads or a cluster, progress, auto-n), :mod:`.run` (:func:`run_ensemble`, the entry point) and
:mod:`.statistics` (bands, intervals, proportions) and :mod:`.distributions` (histograms, ECDF).
"""

from . import distributions, execute, pipeline, run, statistics, store
from .distributions import *  # noqa: F403
from .execute import *  # noqa: F403
from .pipeline import *  # noqa: F403
from .run import *  # noqa: F403
from .statistics import *  # noqa: F403
from .store import *  # noqa: F403

__all__ = [
    name for mod in (pipeline, store, execute, run, statistics, distributions) for name in mod.__all__
]
