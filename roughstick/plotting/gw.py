"""Plots of the Greenwood–Williamson statistical contact (paper Fig. 9)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..contact import summary as contact_summary
from ._legend import legend_beside

__all__ = ["plot_gw_cutoff_study"]


def _adhesive_energy(pressure: xr.DataArray) -> xr.DataArray:
    """Eq. 13 per curve (:func:`roughstick.contact.summary`)."""
    return contact_summary(pressure.to_dataset(name="pressure"))["adhesive_energy"]


def plot_gw_cutoff_study(study: xr.Dataset, *, rh=None, axes=None):
    r"""Fig. 9: GW curves and adhesive energy versus the summit-height cutoff.

    Parameters
    ----------
    study : xarray.Dataset
        Output of :func:`roughstick.contact.gw_cutoff_study`: ``pressure`` over
        ``(height_cutoff, rh, distance)`` (``height_cutoff`` in units of √m0, ``inf`` = none).
    rh : sequence of float, optional
        Humidities to draw curves for (one panel each); default: the lowest and highest.
    axes : sequence of matplotlib Axes, optional
        ``len(rh) + 1`` axes: the curve panels, then the :math:`\Gamma(h_{\max})` panel.

    Returns
    -------
    matplotlib.figure.Figure

    Notes
    -----
    Distances in nm, pressures in MPa (positive repulsive), :math:`\Gamma` (Eq. 13) in mJ m-2
    on a log axis; the no-cutoff value is drawn as a dashed line. The Γ panel's legend sits beside
    it (the curves span the whole panel).
    """
    import matplotlib.pyplot as plt

    p = study["pressure"]
    if "height_cutoff" not in p.dims:
        raise ValueError("study must have a 'height_cutoff' dimension: use roughstick.contact.gw_cutoff_study.")
    if "rh" not in p.dims:
        p = p.expand_dims(rh=[np.nan])
    rh_all = p["rh"].values
    rh_sel = [rh_all.min(), rh_all.max()] if rh is None else list(np.atleast_1d(rh))
    rh_sel = list(dict.fromkeys(float(r) for r in rh_sel))
    n = len(rh_sel) + 1
    if axes is None:
        fig, axes = plt.subplots(1, n, figsize=(4.2 * n + 1.8, 3.6), constrained_layout=True)
    else:
        if len(axes) != n:
            raise ValueError(f"axes must hold {n} Axes (one per humidity plus one for Gamma).")
        fig = axes[0].figure
    axes = np.atleast_1d(axes)
    cuts = p["height_cutoff"].values
    colors = plt.cm.viridis(np.linspace(0, 0.9, len(cuts)))
    d_nm = p["distance"].values * 1e9
    for ax, r in zip(axes[:-1], rh_sel, strict=True):
        pr = p.sel(rh=r, method="nearest") if np.isfinite(r) else p.isel(rh=0)
        for c, col in zip(cuts, colors, strict=True):
            label = "no cutoff" if np.isinf(c) else f"{c:g} √m0"
            ax.plot(d_nm, pr.sel(height_cutoff=c).values / 1e6, color=col, label=label)
        ax.axhline(0, color="0.6", lw=0.6)
        neg = pr.where(pr < 0).min().values
        if np.isfinite(neg) and neg < 0:
            ax.set_ylim(1.3 * neg / 1e6, -1.0 * neg / 1e6)
        ax.set_xlabel("distance d [nm]")
        ax.set_ylabel("pressure [MPa]")
        ax.set_title(f"RH = {100 * r:.0f} %" if np.isfinite(r) else "")
    axes[0].legend(fontsize="small", title=r"$h_\mathrm{max}$")
    ax = axes[-1]
    gamma = _adhesive_energy(p)
    finite = np.isfinite(cuts)
    for r in rh_sel:
        g = (gamma.sel(rh=r, method="nearest") if np.isfinite(r) else gamma.isel(rh=0)).values * 1e3
        (line,) = ax.semilogy(cuts[finite], np.where(g[finite] > 0, g[finite], np.nan), "o-",
                              label=f"RH {100 * r:.0f} %" if np.isfinite(r) else None)
        if (~finite).any() and g[~finite][0] > 0:
            no_cut, shown = g[~finite][0], np.nanmin(np.where(g[finite] > 0, g[finite], np.nan))
            if no_cut >= 1e-3 * shown:  # within the plotted decades: a dashed reference line
                ax.axhline(no_cut, color=line.get_color(), ls="--", lw=0.8,
                           label=f"RH {100 * r:.0f} %, no cutoff")
            else:  # far below (e.g. 1e-22 at RH 30 %): say so in the legend instead of stretching the axis
                ax.plot([], [], ls="none", label=f"RH {100 * r:.0f} %, no cutoff: Γ = {no_cut:.1e} mJ m⁻²")
    ax.set_xlabel(r"height cutoff $h_\mathrm{max}\,/\,\sqrt{m_0}$")
    ax.set_ylabel("Γ [mJ m⁻²]")
    legend_beside(ax, fontsize="small")
    ax.set_title("GW adhesive energy (Eq. 13)")
    return fig
