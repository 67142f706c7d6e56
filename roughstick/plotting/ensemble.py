"""Ensemble figures (paper Figs. 14-17): curve sets with bands, Γ bands versus RH, distributions.

Axes show nm, MPa and mJ m-2; data stay SI. Inputs are the Datasets of
:func:`roughstick.ensemble.run` / :func:`roughstick.ensemble.surface_size_study` (computed or lazy: only
what is plotted is computed).
"""

from __future__ import annotations

import numpy as np

from .._core.api import renamed_keywords
from ..ensemble.distributions import ecdf, histogram
from ..ensemble.statistics import confidence_band
from ._legend import legend_beside

__all__ = ["plot_ensemble_curves", "plot_energy_band", "plot_energy_distribution"]


def _plt():
    import matplotlib.pyplot as plt

    return plt


@renamed_keywords(level="confidence")
def plot_ensemble_curves(ds, *, rh=None, max_curves: int = 200, confidence: float = 0.95, axes=None,
                         ncols: int = 3):
    """Pressure–distance curves of every realization with their band, one panel per RH (Figs. 14-15).

    Parameters
    ----------
    ds : xarray.Dataset
        With ``pressure`` over ``(realization, rh, distance)``.
    rh : sequence of float, optional
        Humidities to show (default all).
    max_curves : int
        Draw at most this many individual curves (grey); the band uses all realizations.
    confidence : float
        Central probability of the band (shaded) around the median (black).
    axes : sequence of matplotlib Axes, optional
    ncols : int

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _plt()
    rhs = list(ds.rh.values) if rh is None else list(np.atleast_1d(rh))
    p = ds["pressure"].sel(rh=rhs)
    band = confidence_band(p.to_dataset(name="pressure"), confidence=confidence,
                           uncertainty=None).compute()
    if axes is None:
        nrows = int(np.ceil(len(rhs) / ncols))
        fig, axes = plt.subplots(nrows, min(ncols, len(rhs)), figsize=(4 * min(ncols, len(rhs)), 3.2 * nrows),
                                 squeeze=False, constrained_layout=True)
        axes = axes.ravel()
    fig = axes[0].figure
    d_nm = ds["distance"].values * 1e9
    n = ds.sizes["realization"]
    show = p.isel(realization=slice(0, max_curves)).transpose("rh", "realization", "distance").values
    for k, (r, ax) in enumerate(zip(rhs, axes, strict=False)):
        for curve in show[k]:
            ax.plot(d_nm, curve / 1e6, color="0.6", lw=0.4, alpha=0.5)
        q = band["pressure"].sel(rh=r).values / 1e6
        ax.fill_between(d_nm, q[0], q[2], color="C0", alpha=0.35, label=f"{confidence:.0%} band")
        ax.plot(d_nm, q[1], color="k", lw=1.2, label="median")
        ax.axhline(0, color="0.3", lw=0.5)
        ax.set_title(f"RH = {r:.0%}, n = {n}")
        ax.set_xlabel("distance d [nm]")
        ax.set_ylabel("mean pressure [MPa]")
        finite = q[np.isfinite(q)]
        if finite.size:
            lo = min(finite.min(), 0)
            top = -0.6 * lo if lo < 0 else float(np.nanmax(q))
            ax.set_ylim(1.15 * lo if lo < 0 else None, top)
            active = np.flatnonzero(np.any(show[k] != 0, axis=0))
            inside = np.flatnonzero(q[2] <= top)
            if active.size and inside.size:
                ax.set_xlim(max(d_nm[0], d_nm[inside[0]] - 1), min(d_nm[-1], d_nm[active[-1]] + 2))
    for ax in axes[len(rhs):]:
        ax.set_visible(False)
    axes[0].legend(fontsize="small")
    return fig


@renamed_keywords(level="confidence")
def plot_energy_band(ds, *, confidence: float = 0.95, ax=None, label: str | None = None):
    """Apparent adhesive energy Γ (Eq. 13) versus RH: median, ``confidence`` band and the band's uncertainty (Fig. 16).

    The line is the median over realizations (the band's middle quantile, what
    :func:`roughstick.ensemble.band_summary` prints and ``band.nc`` holds), the shaded band its central
    ``confidence`` quantiles, the hatched bands the confidence interval of each band edge where the
    sample bounds it. With a ``surface_size`` dimension one band per size is drawn. An ensemble
    run with measured maps (``maps=``) also shows each map's own Γ, labelled with its percentile
    in the ensemble. The legend sits beside the axes.

    Returns
    -------
    matplotlib.axes.Axes
    """
    plt = _plt()
    if ax is None:
        _, ax = plt.subplots(figsize=(6.2, 3.6), constrained_layout=True)
    g = ds["adhesive_energy"]
    sizes = list(g["surface_size"].values) if "surface_size" in g.dims else [None]
    for k, s in enumerate(sizes):
        gs = g if s is None else g.sel(surface_size=s)
        b = confidence_band(gs.to_dataset(name="g"), confidence=confidence).compute()
        rh = b["rh"].values * 100
        q = b["g"].values * 1e3
        name = label or ("" if s is None else f"{s * 1e6:.2f} µm")
        c = f"C{k}"
        ax.fill_between(rh, q[0], q[2], color=c, alpha=0.25, label=f"{name} {confidence:.0%} band".strip())
        for j in (0, 2):
            lo = b["g_ci_lower"].values[j] * 1e3
            hi = b["g_ci_upper"].values[j] * 1e3
            ok = np.isfinite(lo) & np.isfinite(hi) & (lo > 0)  # +-inf: n too small to bound it
            if ok.any():
                ax.fill_between(rh, np.where(ok, lo, np.nan), np.where(ok, hi, np.nan), color=c,
                                alpha=0.15, hatch="//", lw=0,
                                label="95 % CI of the band edges" if (k == 0 and j == 0) else None)
        ax.plot(rh, q[1], "o-", color=c, label=f"{name} median".strip())
    _plot_maps(ds, ax)
    ax.set_yscale("log")
    ax.set_xlabel("relative humidity [%]")
    ax.set_ylabel("Γ [mJ m$^{-2}$]")
    legend_beside(ax, fontsize="small")
    return ax


def _plot_maps(ds, ax) -> None:
    """The measured maps' own Γ (``map_adhesive_energy`` of an ensemble run with ``maps=``), each
    point labelled with its percentile in the ensemble."""
    if "map_adhesive_energy" not in ds:
        return
    own = ds["map_adhesive_energy"].compute()
    pct = ds["map_percentile"].compute() if "map_percentile" in ds else None
    rh = own["rh"].values * 100
    for k, name in enumerate(own["map"].values):
        g = own.sel(map=name).values * 1e3
        ax.plot(rh, g, ls="none", marker="DsP^v"[k % 5], mfc="none", color="k",
                label=f"map {name} (its own Γ)")
        if pct is not None:
            for x, y, p in zip(rh, g, pct.sel(map=name).values, strict=True):
                if np.isfinite(y) and y > 0:
                    ax.annotate(f"{p:.0f}%", (x, y), textcoords="offset points", xytext=(4, 3),
                                fontsize="x-small")


def plot_energy_distribution(ds, *, rh=None, kind: str = "ecdf", ax=None, bins: int = 30):
    """Distribution of Γ over realizations at given humidities, per surface size (Fig. 17); the
    legend sits beside the axes.

    Parameters
    ----------
    ds : xarray.Dataset
        With ``adhesive_energy`` over ``(realization, rh)`` and optionally ``surface_size``.
    rh : sequence of float, optional
    kind : {"ecdf", "histogram"}
    ax : matplotlib Axes, optional
    bins : int
        For histograms.

    Returns
    -------
    matplotlib.axes.Axes
    """
    plt = _plt()
    if ax is None:
        _, ax = plt.subplots(figsize=(6.8, 3.8), constrained_layout=True)
    g = ds["adhesive_energy"].compute()
    rhs = list(g.rh.values) if rh is None else list(np.atleast_1d(rh))
    sizes = list(g["surface_size"].values) if "surface_size" in g.dims else [None]
    styles = ["-", "--", ":", "-."]
    for j, r in enumerate(rhs):
        for k, s in enumerate(sizes):
            gs = g.sel(rh=r) if s is None else g.sel(rh=r, surface_size=s)
            lab = f"RH {r:.0%}" + ("" if s is None else f", {s * 1e6:.2f} µm")
            if kind == "ecdf":
                e = ecdf(gs)
                ax.step(e.values * 1e3, e.cumulative_probability, where="post", color=f"C{j}",
                        ls=styles[k % 4], label=lab)
                ax.set_ylabel("cumulative probability")
            elif kind == "histogram":
                h = histogram(gs, bins=bins)
                ax.plot(h["bin"] * 1e3, h.values / 1e3, color=f"C{j}", ls=styles[k % 4], label=lab,
                        drawstyle="steps-mid")
                ax.set_ylabel("probability density [m$^2$ mJ$^{-1}$]")
            else:
                raise ValueError(f"kind must be 'ecdf' or 'histogram', got {kind!r}.")
    ax.set_xscale("log")
    ax.set_xlabel("Γ [mJ m$^{-2}$]")
    legend_beside(ax, fontsize="small")
    return ax
