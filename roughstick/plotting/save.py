"""Atomic figure files: a PNG under its final name is always complete."""

from __future__ import annotations

import os
import pathlib

from ..io.netcdf import discard_partial_file, partial_file, publish

__all__ = ["save_figure"]


def save_figure(fig, path, *, dpi: int = 110, close: bool = True, **savefig_kwargs) -> pathlib.Path:
    """Save ``fig`` to ``path`` through a temporary file renamed into place once written.

    A run killed during the write leaves a hidden ``.<name>.tmp-<pid><suffix>`` (removed by the
    next run, see :func:`roughstick.io.netcdf.remove_partial_files`), never a truncated or 0-byte
    file under the final name.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = pathlib.Path(path)
    tmp = partial_file(path.with_name(f".{path.stem}.tmp-{os.getpid()}{path.suffix}"))
    try:
        fig.savefig(tmp, dpi=dpi, format=path.suffix.lstrip(".") or "png", **savefig_kwargs)
        publish(tmp, path)
    except BaseException:
        discard_partial_file(tmp)
        raise
    finally:
        if close:
            import matplotlib.pyplot as plt

            plt.close(fig)
    return path
