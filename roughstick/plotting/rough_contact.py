"""Plots of the rough-surface modified DMT (paper Figs. 8, 10, 11). Axes in nm, MPa, mJ m-2."""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..contact.meniscus import laplace_pressure

__all__ = ["plot_rough_curves", "plot_fit_error", "plot_adhesion_vs_rh", "plot_mdmt_vs_gw"]

SILICON_UNIT_CELL_NM = 0.543


def _rh_list(ds, rh):
    if "rh" not in ds.dims:
        return [float(ds.rh)] if "rh" in ds.coords else [None]
    return list(np.atleast_1d(ds.rh.values if rh is None else rh))


def plot_rough_curves(curves: xr.Dataset, *, rh=None, ax=None, label_prefix="", **line_kwargs):
    """Fig. 8a-b: mean pressure [MPa] versus distance [nm], one line per humidity.

    Parameters
    ----------
    curves : xarray.Dataset
        Output of :func:`roughstick.contact.curves` over ``(rh, distance)``.
    rh : sequence of float, optional
        Humidities to draw (default all).
    ax : matplotlib Axes, optional
    label_prefix : str
        Prepended to the legend labels.

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(5, 3.6), constrained_layout=True)
    for r in _rh_list(curves, rh):
        sub = curves if r is None or "rh" not in curves.dims else curves.sel(rh=r)
        lab = f"{label_prefix}RH {100 * r:.0f} %" if r is not None else label_prefix
        ax.plot(sub.distance * 1e9, sub.pressure * 1e-6, label=lab, **line_kwargs)
    ax.axhline(0, color="0.6", lw=0.6)
    ax.set_xlabel("distance d [nm]")
    ax.set_ylabel("pressure [MPa] (+ repulsive)")
    ax.legend(fontsize=7)
    return ax


def plot_fit_error(curves: xr.Dataset, *, rh, ax=None):
    r"""Fig. 8c-d: fit error :math:`E^S` (Eq. 23) and :math:`\delta_{max}` where the pressure is
    attractive, with the silicon unit cell (0.543 nm).

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(5, 3.6), constrained_layout=True)
    sub = curves.sel(rh=rh) if "rh" in curves.dims else curves
    att = (sub.pressure < 0) & (sub.n_contacts > 0)
    d = sub.distance.where(att) * 1e9
    ax.semilogy(d, sub.fit_error.where(att) * 1e9, "o-", ms=2, label=r"$E^S$ (Eq. 23)")
    ax.semilogy(d, sub.max_interference.where(att) * 1e9, "s-", ms=2, label=r"$\delta_{max}$")
    ax.axhline(SILICON_UNIT_CELL_NM, color="k", ls="--", lw=0.8, label="Si unit cell 0.543 nm")
    ax.set_ylim(bottom=1e-3)  # one-pixel asperities fit exactly (E^S ~ 0): keep the axis readable
    ax.set_xlabel("distance d [nm]")
    ax.set_ylabel("[nm]")
    ax.set_title(f"RH {100 * float(sub.rh):.0f} %, attractive states", fontsize=9)
    ax.legend(fontsize=7)
    return ax


def plot_adhesion_vs_rh(summaries: dict, *, axes=None):
    """Fig. 11: adhesive energy (Eq. 13) per map and wetted fraction at equilibrium versus RH.

    Parameters
    ----------
    summaries : dict of str -> xarray.Dataset
        Outputs of :func:`roughstick.contact.summary` over ``rh``, keyed by map name.
    axes : pair of matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    if axes is None:
        fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    else:
        fig = axes[0].figure
    for name, s in summaries.items():
        r = s.rh.values * 100
        axes[0].semilogy(r, s.adhesive_energy * 1e3, "o-", label=name)
        axes[1].semilogy(r, s.wet_fraction_at_equilibrium, "o-", label=name)
    axes[0].set_xlabel("RH [%]")
    axes[0].set_ylabel(r"adhesive energy $\Gamma$ [mJ m$^{-2}$]")
    axes[1].set_xlabel("RH [%]")
    axes[1].set_ylabel("wetted area fraction at equilibrium")
    axes[0].legend(fontsize=7)
    return fig


def plot_mdmt_vs_gw(curves: dict, gw: xr.Dataset | None = None, *, rh=(0.3, 0.5, 0.7, 0.9), axes=None):
    """Fig. 10: modified DMT on several maps against GW on the sample's moments.

    Parameters
    ----------
    curves : dict of str -> xarray.Dataset
        Modified-DMT curves per map (e.g. S1A, S1B, S1C).
    gw : xarray.Dataset, optional
        Greenwood-Williamson curves (same layout), drawn dashed.
    rh : sequence of float
        One panel per humidity.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    rh = list(rh)
    if axes is None:
        fig, axes = plt.subplots(1, len(rh), figsize=(3.4 * len(rh), 3.4), constrained_layout=True)
    else:
        fig = axes[0].figure
    for ax, r in zip(np.atleast_1d(axes), rh, strict=True):
        for name, c in curves.items():
            s = c.sel(rh=r, method="nearest")
            ax.plot(s.distance * 1e9, s.pressure * 1e-6, label=f"mDMT {name}")
        if gw is not None:
            s = gw.sel(rh=r, method="nearest")
            ax.plot(s.distance * 1e9, s.pressure * 1e-6, "k--", label="GW (sample moments)")
            # Draw Delta P only where it does not squash the curves: at low RH it is 10-100x
            # the adhesive pressures (that gap *is* the finding), so it goes into the title.
            data_lim = ax.get_ylim()
            dp = float(laplace_pressure(float(s.rh))) * 1e-6
            span = data_lim[1] - data_lim[0]
            if dp >= data_lim[0] - 0.5 * span:
                ax.axhline(dp, color="r", lw=0.6, ls=":", label=r"$\Delta P$")
            else:
                ax.set_ylim(*data_lim)
        ax.axhline(0, color="0.6", lw=0.6)
        title = f"RH {100 * r:.0f} %"
        if gw is not None:
            title += f" ($\\Delta P$ = {dp:.1f} MPa)"
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("distance d [nm]")
    np.atleast_1d(axes)[0].set_ylabel("pressure [MPa]")
    np.atleast_1d(axes)[0].legend(fontsize=6)
    return fig
