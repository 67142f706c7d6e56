"""Execute every notebook in place so the gallery can be read without running it:
python notebooks/_execute.py  (after python notebooks/_build_0N.py; needs nbclient, ipykernel).

The outputs are those of this checkout on the machine that runs it; tests/test_notebooks.py
re-executes the notebooks anyway (it does not read the stored outputs)."""

from __future__ import annotations

import os
import pathlib
import sys

import nbclient
import nbformat

HERE = pathlib.Path(__file__).resolve().parent


def main(names=None) -> None:
    os.environ.pop("MPLBACKEND", None)  # the kernel's inline backend stores the figures
    for path in sorted(HERE.glob("*.ipynb")):
        if names and not any(n in path.name for n in names):
            continue
        nb = nbformat.read(path, as_version=4)
        nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                                resources={"metadata": {"path": str(HERE)}}).execute()
        for cell in nb.cells:  # no machine-specific execution metadata in the repository
            cell.get("metadata", {}).pop("execution", None)
        nbformat.write(nb, path)
        print(f"executed {path.name} ({path.stat().st_size / 1e3:.0f} kB)")


if __name__ == "__main__":
    main(sys.argv[1:])
