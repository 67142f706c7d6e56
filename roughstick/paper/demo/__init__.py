"""Steps of ``roughstick demo``: each module ``sNN_<name>.py`` defines

``run(out: pathlib.Path, *, quick: bool, figure_format: str = "png", dpi: int = 200) -> list[pathlib.Path]``

which computes on the bundled samples (:mod:`roughstick.datasets`), writes NetCDF files and figures
(PNG, PDF or SVG at ``dpi``, :func:`roughstick.plotting.save_figure`) into ``out`` and returns their
paths. Steps run in the order of their names.
"""

from __future__ import annotations

import importlib
import pkgutil

__all__ = ["steps"]


def steps():
    """The demo step modules, in order."""
    names = sorted(m.name for m in pkgutil.iter_modules(__path__) if m.name.startswith("s"))
    return [importlib.import_module(f"{__name__}.{n}") for n in names]
