"""Sphinx configuration (``pip install -e ".[docs]"``, then ``sphinx-build docs docs/_build``).

The pages follow the Diátaxis split (index.md): tutorials are the notebooks of ``notebooks/``
(linked from ``docs/tutorials/``, committed with their outputs and not executed here), how-to
guides, reference pages generated from each namespace's ``__all__`` (``_ext/rs_reference.py``),
explanation pages and the evidence behind the figures.
"""

import os
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).parent / "_ext"))

project = "roughstick"
author = "roughstick developers"
extensions = [
    "myst_nb",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx_autosummary_accessors",
    "rs_reference",
]
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3
# The notebooks are committed with their outputs (tests/test_gallery.py checks it) and run by
# tests/test_notebooks.py: the docs show them as they are.
nb_execution_mode = "off"
# Reference pages are written by the {namespace} directive, not by autosummary stub files.
autosummary_generate = False
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
html_theme = "pydata_sphinx_theme"
html_title = "roughstick"
# Without network (ROUGHSTICK_DOCS_OFFLINE=1) the build skips the links to other projects' docs.
if not os.environ.get("ROUGHSTICK_DOCS_OFFLINE"):
    intersphinx_mapping = {
        "python": ("https://docs.python.org/3", None),
        "numpy": ("https://numpy.org/doc/stable", None),
        "scipy": ("https://docs.scipy.org/doc/scipy", None),
        "xarray": ("https://docs.xarray.dev/en/stable", None),
        "dask": ("https://docs.dask.org/en/stable", None),
    }
# myst-nb writes the notebooks it reads to jupyter_execute/ beside the output folder (docs/ when
# the output is docs/_build): not a source.
exclude_patterns = ["_build", "_ext", "jupyter_execute", "**.ipynb_checkpoints"]
