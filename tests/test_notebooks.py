"""Every notebook in notebooks/ executes without error (each must finish in under a minute), and
every figure it draws passes tests/_figure_lint.py (issue 16 item 8: no overprinted labels, no
1e-23 axis, no literal TeX, no raw xarray labels, no near-empty panel, no unlabelled line)."""

from __future__ import annotations

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
# run after the notebook in its kernel: with the Agg backend every figure is still open
LINT_CELL = f"""
import sys as _sys
_sys.path.insert(0, {str(ROOT / "tests")!r})
import matplotlib.pyplot as _plt
from _figure_lint import figure_problems as _problems
_found = {{n: _problems(_plt.figure(n)) for n in _plt.get_fignums()}}
_found = {{n: p for n, p in _found.items() if p}}
assert not _found, f"figure problems (figure number: problems): {{_found}}"
print(f"{{len(_plt.get_fignums())}} figures checked")
"""
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_runs(path, tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    nb = nbformat.read(path, as_version=4)
    nb.cells.append(nbformat.v4.new_code_cell(LINT_CELL))
    env_backend = os.environ.get("MPLBACKEND")
    os.environ["MPLBACKEND"] = "Agg"
    try:
        client = nbclient.NotebookClient(
            nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}}
        )
        client.execute()
        checked = "".join(o.get("text", "") for o in nb.cells[-1].outputs)
        assert "figures checked" in checked, checked
    finally:
        if env_backend is None:
            os.environ.pop("MPLBACKEND", None)
        else:
            os.environ["MPLBACKEND"] = env_backend
