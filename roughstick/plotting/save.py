"""Figure files for reports: PNG, PDF or SVG at a chosen resolution, each written atomically."""

from __future__ import annotations

import os
import pathlib

from .._core.validate import FIGURE_FORMATS, figure_dpi, figure_format
from ..io.netcdf import discard_partial_file, partial_file, publish

__all__ = ["save_figure", "FIGURE_FORMATS", "DEFAULT_DPI", "DEFAULT_FORMAT"]

#: Resolution of saved figures unless told otherwise [dots per inch]: sharp in print.
DEFAULT_DPI = 200
#: Format of saved figures unless told otherwise.
DEFAULT_FORMAT = "png"

_NO_DATE = {"pdf": {"CreationDate": None}, "svg": {"Date": None}}


def save_figure(fig, path, *, format: str | None = None, dpi: int = DEFAULT_DPI, close: bool = True,
                **savefig_kwargs) -> pathlib.Path:
    """Save ``fig`` as a PNG, PDF or SVG file through a temporary file renamed into place.

    A run killed during the write leaves a hidden ``.<name>.tmp-<pid><suffix>`` (removed by the
    next run, see :func:`roughstick.io.netcdf.remove_partial_files`), never a truncated or 0-byte
    file under the final name. PDF and SVG files carry no creation date, so the same figure gives
    the same file.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    path : str or pathlib.Path
        File to write. With ``format`` its extension is replaced by the format's
        (``fig.png`` with ``format="pdf"`` writes ``fig.pdf``); without, the extension picks the
        format (none: PNG).
    format : {"png", "pdf", "svg"}, optional
        PNG is a raster image; PDF and SVG are vector formats (lines and text stay sharp at any
        size; image panels such as height maps are embedded at ``dpi``).
    dpi : int
        Resolution in dots per inch, 50 to 1200 (of the whole PNG, of the embedded images of a
        PDF or SVG).
    close : bool
        Close the figure once written.
    **savefig_kwargs
        Passed to :meth:`matplotlib.figure.Figure.savefig` (e.g. ``bbox_inches="tight"``).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ValueError
        An unknown format or extension, or an implausible ``dpi``, before anything is written.
    """
    path = pathlib.Path(path)
    if format is not None:
        fmt = figure_format(format)
        path = path.with_suffix(f".{fmt}")
    else:
        fmt = figure_format(path.suffix or DEFAULT_FORMAT,
                            name=f"the extension of {path.name!r} (or pass format=)")
    dpi = figure_dpi(dpi)
    if fmt in _NO_DATE and "metadata" not in savefig_kwargs:
        savefig_kwargs["metadata"] = _NO_DATE[fmt]
    tmp = partial_file(path.with_name(f".{path.stem}.tmp-{os.getpid()}{path.suffix}"))
    try:
        fig.savefig(tmp, dpi=dpi, format=fmt, **savefig_kwargs)
        publish(tmp, path)
    except BaseException:
        discard_partial_file(tmp)
        raise
    finally:
        if close:
            import matplotlib.pyplot as plt

            plt.close(fig)
    return path
