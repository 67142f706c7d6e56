"""Legends that never cover the data: placed beside the axes, outside the plotted area."""

from __future__ import annotations

__all__ = ["legend_beside"]


def legend_beside(ax, **kwargs):
    """A legend of ``ax`` to the right of its plotted area (top-aligned), so no curve, band or
    point is drawn under it whatever the data. A layout engine (``layout="constrained"``) or
    ``bbox_inches="tight"`` keeps it inside the saved figure. Artists sharing a label (e.g. every
    line of a family) get one entry.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    **kwargs
        Passed to :meth:`matplotlib.axes.Axes.legend` (e.g. ``fontsize``, ``title``).

    Returns
    -------
    matplotlib.legend.Legend
    """
    kwargs.setdefault("loc", "upper left")
    kwargs.setdefault("bbox_to_anchor", (1.02, 1.0))
    kwargs.setdefault("borderaxespad", 0.0)
    if "handles" not in kwargs:
        seen = {}
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            seen.setdefault(label, handle)
        kwargs["handles"], kwargs["labels"] = list(seen.values()), list(seen)
    return ax.legend(**kwargs)
