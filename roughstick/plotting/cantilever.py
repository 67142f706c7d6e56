"""Plots of the cantilever comparison and the stiction risk (paper Figs. 18-20).

Inputs are the Datasets of :func:`roughstick.stiction.risk_summary` (optionally stacked along an
``adsorbed_layer`` dimension) and :func:`roughstick.stiction.measured_adhesion`. Axes show RH in %,
lengths in µm and adhesive energies in mJ m-2; the data stay SI.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..stiction.risk import crossing_humidity
from ._legend import legend_beside

__all__ = [
    "plot_stiction_probability",
    "plot_stiction_vs_length",
    "plot_adhesive_energy_band",
    "plot_crack_length_band",
    "plot_cantilever_comparison",
]

_MJ = 1e3  # J m-2 -> mJ m-2
_UM = 1e6  # m -> µm


def _axes(ax):
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7.2, 4), layout="constrained")
    return ax


def _need(ds, names, what):
    missing = [n for n in names if n not in ds.variables]
    if missing:
        raise ValueError(
            f"{what} needs {missing} in the Dataset (has {sorted(ds.data_vars)}); "
            "pass the output of roughstick.stiction.risk_summary(...)."
        )


def _one_layer(ds, layer):
    if "adsorbed_layer" in ds.dims:
        if layer is None:
            raise ValueError(
                f"the Dataset has an 'adsorbed_layer' dimension {list(ds.adsorbed_layer.values)}; "
                "pick one with layer=..., or use plot_cantilever_comparison for one panel each."
            )
        return ds.sel(adsorbed_layer=layer)
    return ds


def plot_stiction_probability(risk: xr.Dataset, *, ax=None, level=None, layer=None, lengths=None):
    """Stiction probability versus RH, one curve per beam length, with its Monte-Carlo interval.

    Parameters
    ----------
    risk : xarray.Dataset
        From :func:`roughstick.stiction.risk_summary` or :func:`roughstick.stuck_probability`, with an
        ``rh`` dimension (and optionally ``beam_length``).
    ax : matplotlib.axes.Axes, optional
    level : float, optional
        Draw this probability level and mark where each curve first crosses it.
    layer : str, optional
        Which ``adsorbed_layer`` to plot when the Dataset has that dimension.
    lengths : sequence of float, optional
        Subset of beam lengths [m] to plot.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    ds = _one_layer(risk, layer)
    _need(ds, ["stiction_probability", "stiction_probability_lower", "stiction_probability_upper"],
          "plot_stiction_probability")
    if "rh" not in ds.dims:
        raise ValueError("plot_stiction_probability needs an 'rh' dimension (an RH sweep).")
    if "beam_length" not in ds.dims:
        ds = ds.expand_dims(beam_length=[ds.attrs.get("beam_length", np.nan)])
    if lengths is not None:
        ds = ds.sel(beam_length=list(lengths), method="nearest")
    rh = ds.rh.values * 100
    for bl in ds.beam_length.values:
        d = ds.sel(beam_length=bl).transpose("rh", ...)
        (line,) = ax.plot(rh, d.stiction_probability, marker="o", ms=3, label=f"l = {bl * _UM:.0f} µm")
        ax.fill_between(rh, d.stiction_probability_lower, d.stiction_probability_upper,
                        color=line.get_color(), alpha=0.2, lw=0)
        if level is not None:
            c = float(crossing_humidity(d[["stiction_probability", "stiction_probability_lower",
                                           "stiction_probability_upper"]], probability=level).crossing_humidity)
            if np.isfinite(c):
                ax.plot([c * 100], [level], marker="x", color=line.get_color(), ms=8)
    if level is not None:
        ax.axhline(level, color="0.5", lw=0.8, ls="--", label=f"P = {level:g} (× where it is crossed)")
    conf = ds.attrs.get("confidence_level", 0.95)
    ax.set(xlabel="relative humidity [%]", ylabel="P(beam stays stuck)", ylim=(-0.02, 1.02),
           title=f"stiction probability (bands: {conf:.0%} Monte-Carlo interval)")
    legend_beside(ax, fontsize="small")
    return ax


def plot_stiction_vs_length(risk: xr.Dataset, *, rh=None, ax=None, layer=None):
    """Stiction probability versus beam length at a few humidities, with its interval.

    A marker (with its interval as an error bar) at each computed length; lines join neighbouring
    lengths only, never across a gap in the computed lengths (a step more than twice the step
    beside it), where nothing was computed.

    Parameters
    ----------
    risk : xarray.Dataset
        From :func:`roughstick.stiction.risk_summary` with a ``beam_length`` dimension.
    rh : sequence of float, optional
        Humidities (fractions) to plot; default: all.
    ax, layer
        See :func:`plot_stiction_probability`.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    ds = _one_layer(risk, layer)
    _need(ds, ["stiction_probability"], "plot_stiction_vs_length")
    if "beam_length" not in ds.dims:
        raise ValueError("plot_stiction_vs_length needs a 'beam_length' dimension: pass several lengths.")
    if "rh" not in ds.dims:
        ds = ds.expand_dims(rh=[np.nan])
    if rh is not None:
        ds = ds.sel(rh=list(np.atleast_1d(rh)), method="nearest")
    ds = ds.sortby("beam_length")
    length = ds.beam_length.values * _UM
    runs = _contiguous_runs(length)
    for r in ds.rh.values:
        d = ds.sel(rh=r).transpose("beam_length", ...)
        p = np.asarray(d.stiction_probability, float)
        color = None
        for k, run in enumerate(runs):
            (line,) = ax.plot(length[run], p[run], marker="o", ms=4, color=color,
                              label=f"RH {r * 100:.0f} %" if k == 0 else None)
            color = line.get_color()
        if "stiction_probability_lower" in d:
            lo, hi = np.asarray(d.stiction_probability_lower, float), np.asarray(d.stiction_probability_upper, float)
            ax.errorbar(length, p, yerr=np.vstack([np.clip(p - lo, 0, None), np.clip(hi - p, 0, None)]),
                        fmt="none", ecolor=color, elinewidth=0.8, capsize=2, alpha=0.7)
    ax.set(xlabel="beam length [µm]", ylabel="P(beam stays stuck)", ylim=(-0.02, 1.02))
    legend_beside(ax, fontsize="small")
    return ax


def _contiguous_runs(x) -> list[slice]:
    """Split sorted positions ``x`` into runs of neighbours: a step more than twice as long as the
    step before or after it is a gap in the computed grid (a line drawn across it would show
    values nothing computed).

    Examples
    --------
    >>> _contiguous_runs([250, 300, 350, 400, 500, 1500])
    [slice(0, 5, None), slice(5, 6, None)]
    >>> _contiguous_runs([100, 200, 400, 800])  # a geometric grid has no gap
    [slice(0, 4, None)]
    """
    x = np.asarray(x, dtype=float)
    if x.size < 3:
        return [slice(0, x.size)]
    step = np.diff(x)
    before = np.r_[np.inf, step[:-1]]
    after = np.r_[step[1:], np.inf]
    gaps = np.flatnonzero(step > 2 * np.minimum(before, after))
    edges = [0, *(gaps + 1).tolist(), x.size]
    return [slice(a, b) for a, b in zip(edges[:-1], edges[1:], strict=True)]


def _band(ds, var, scale):
    q = ds[var]
    qs = q["quantile"].values
    lo, hi = q.sel(quantile=qs.min()), q.sel(quantile=qs.max())
    mid = q.sel(quantile=0.5) if 0.5 in qs else None
    return lo * scale, hi * scale, (mid * scale if mid is not None else None), (qs.min(), qs.max())


def plot_adhesive_energy_band(risk: xr.Dataset, *, measured=None, ax=None, layer=None,
                              critical=True, label="model", color=None):
    """Fig. 20-style band of the predicted apparent adhesive energy versus RH.

    Error bars span the outer quantiles of ``adhesive_energy_quantile`` (the 95 % band by
    default), the dot is the median; measured points (RH, Γ) are overlaid and the critical
    adhesive energy of each beam length is drawn as a dashed line (above it the beam stays stuck).

    Parameters
    ----------
    risk : xarray.Dataset
        From :func:`roughstick.stiction.risk_summary`.
    measured : xarray.Dataset or sequence of them, optional
        From :func:`roughstick.stiction.measured_adhesion`; the attribute ``label`` is the legend text.
    ax : matplotlib.axes.Axes, optional
    layer : str, optional
        ``adsorbed_layer`` to plot if the Dataset has that dimension.
    critical : bool
        Draw :math:`\\Gamma_{crit}` of the beam lengths in ``risk``.
    label, color
        Legend text and colour of the model band.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    ds = _one_layer(risk, layer)
    _need(ds, ["adhesive_energy_quantile"], "plot_adhesive_energy_band")
    lo, hi, mid, (qa, qb) = _band(ds, "adhesive_energy_quantile", _MJ)
    rh = ds.rh.values * 100
    mid = mid if mid is not None else (lo + hi) / 2
    yerr = np.vstack([np.clip(mid.values - lo.values, 0, None), np.clip(hi.values - mid.values, 0, None)])
    ax.errorbar(rh, mid.values, yerr=yerr, fmt="o", ms=4, capsize=3, color=color,
                label=f"{label} ({qb - qa:.0%} band, median)")
    if critical and "critical_adhesive_energy" in ds:
        g = ds["critical_adhesive_energy"]
        if "beam_length" in g.dims:
            for bl in g.beam_length.values:
                ax.axhline(float(g.sel(beam_length=bl)) * _MJ, ls="--", lw=0.8, color="0.4")
                ax.annotate(f"Γcrit, l = {bl * _UM:.0f} µm", (rh.min(), float(g.sel(beam_length=bl)) * _MJ),
                            fontsize="x-small", color="0.3", va="bottom")
        else:
            ax.axhline(float(g) * _MJ, ls="--", lw=0.8, color="0.4", label="Γcrit")
    for m in _as_list(measured):
        ax.plot(m.rh.values * 100, m.adhesive_energy.values * _MJ, "s", mfc="none", mew=1.5,
                label=m.attrs.get("label", "measured"))
    ax.set_yscale("log")
    ax.set(xlabel="relative humidity [%]", ylabel="apparent adhesive energy Γ [mJ m⁻²]")
    legend_beside(ax, fontsize="small")
    return ax


def _as_list(measured):
    if measured is None:
        return []
    if isinstance(measured, xr.Dataset):
        return [measured]
    return list(measured)


def plot_crack_length_band(risk: xr.Dataset, *, measured=None, ax=None, layer=None, beam_lengths=True):
    """Band of the predicted crack length :math:`s` versus RH (Eq. 36 on the Γ sample).

    Beams longer than the band stay stuck; the horizontal lines are the beam lengths in ``risk``.

    Parameters
    ----------
    risk : xarray.Dataset
        From :func:`roughstick.stiction.risk_summary`.
    measured : xarray.Dataset or sequence, optional
        From :func:`roughstick.stiction.measured_adhesion` (RH, s).
    ax, layer
        See :func:`plot_adhesive_energy_band`.
    beam_lengths : bool
        Draw the beam lengths of ``risk``.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _axes(ax)
    ds = _one_layer(risk, layer)
    _need(ds, ["crack_length_quantile"], "plot_crack_length_band")
    lo, hi, mid, (qa, qb) = _band(ds, "crack_length_quantile", _UM)
    rh = ds.rh.values * 100
    lo_v, hi_v = np.where(np.isfinite(lo.values), lo.values, np.nan), np.where(np.isfinite(hi.values), hi.values, np.nan)
    n = int(ds["n_samples"].max()) if "n_samples" in ds else ds.sizes.get("realization")
    of_n = f" of n = {n}" if n else ""
    ax.fill_between(rh, lo_v, hi_v, alpha=0.3, label=f"predicted s ({qb - qa:.0%} band{of_n})")
    if mid is not None:
        ax.plot(rh, np.where(np.isfinite(mid.values), mid.values, np.nan), "-o", ms=3, label="median")
    if beam_lengths and "beam_length" in ds.coords and ds["beam_length"].ndim == 1:
        import matplotlib.transforms as mtransforms

        on_right = mtransforms.blended_transform_factory(ax.transAxes, ax.transData)
        lengths = np.sort(ds.beam_length.values * _UM)
        for bl in lengths:
            ax.axhline(bl, ls="--", lw=0.8, color="0.4", label="beam lengths l")  # one legend entry
        # one label per group of lines closer than 6 % of the axis height (no overprinting)
        y0, y1 = ax.get_ylim()
        groups = [[lengths[0]]]
        for bl in lengths[1:]:
            if bl - groups[-1][-1] < 0.06 * (y1 - y0):
                groups[-1].append(bl)
            else:
                groups.append([bl])
        for g in groups:
            ax.text(0.99, g[-1], "l = " + ", ".join(f"{v:.0f}" for v in g) + " µm", transform=on_right,
                    ha="right", va="bottom", fontsize="x-small", color="0.3")
    for m in _as_list(measured):
        ax.plot(m.rh.values * 100, m.crack_length.values * _UM, "s", mfc="none", mew=1.5,
                label=m.attrs.get("label", "measured"))
    ax.set(xlabel="relative humidity [%]", ylabel="crack length s [µm]",
           title="beams longer than s stay stuck")
    legend_beside(ax, fontsize="small")
    return ax


def plot_cantilever_comparison(risk: xr.Dataset, *, measured=None, axes=None):
    """Fig. 20a/b: the Γ band for each adsorbed-layer model side by side, with measured points.

    Parameters
    ----------
    risk : xarray.Dataset
        :func:`roughstick.stiction.risk_summary` outputs concatenated along ``adsorbed_layer`` (as written
        by ``roughstick risk``), or a single one.
    measured : xarray.Dataset or sequence, optional
        From :func:`roughstick.stiction.measured_adhesion`.
    axes : sequence of matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    layers = list(risk.adsorbed_layer.values) if "adsorbed_layer" in risk.dims else [None]
    if axes is None:
        fig, axes = plt.subplots(1, len(layers), figsize=(6.8 * len(layers), 4), sharey=True,
                                 layout="constrained", squeeze=False)
        axes = axes[0]
    else:
        fig = axes[0].figure
    titles = {"none": "no adsorbed layer (Fig. 20a)", "paper": "0.9 nm layers above 65 % RH (Fig. 20b)"}
    for ax, layer in zip(axes, layers, strict=True):
        plot_adhesive_energy_band(risk, measured=measured, ax=ax, layer=layer)
        if layer is not None:
            ax.set_title(titles.get(str(layer), f"adsorbed layer: {layer}"))
    return fig
