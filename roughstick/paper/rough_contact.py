"""Rough-surface modified DMT on measured maps, paper §3.4: Figs. 8, 10 and 11.

Every function returns ``(Dataset, Figure)``.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

import roughstick as rs

from ..plotting.rough_contact import (
    plot_adhesion_vs_rh,
    plot_fit_error,
    plot_mdmt_vs_gw,
    plot_rough_curves,
)

__all__ = ["curves_by_map", "fig08_rough_curves", "fig10_mdmt_vs_gw", "fig11_adhesion_vs_rh"]


def curves_by_map(curves: dict, summaries: dict) -> xr.Dataset:
    """The curves and adhesion summaries of several maps in one Dataset over a ``map`` dimension;
    each map keeps its own distance grid as the auxiliary coordinate ``distance(map, point)``
    (CF §5), not as numbered variables; grids shorter than the longest are padded with NaN."""
    parts = []
    for k, c in curves.items():
        c = xr.merge([c, summaries[k]], compat="override", combine_attrs="drop_conflicts")
        d = c["distance"]
        c = c.rename({"distance": "point"}).drop_vars("point")
        parts.append(c.assign_coords(distance=("point", d.values, dict(d.attrs))))
    # automatic grids have as many points as each map's curves need: pad the shorter with NaN
    n_point = max(p.sizes["point"] for p in parts)
    parts = [p.pad(point=(0, n_point - p.sizes["point"])) for p in parts]
    return xr.concat(parts, dim=xr.DataArray(list(curves), dims="map", name="map",
                                             attrs={"long_name": "measured height map (sample name)"}),
                     coords="different", compat="equals", join="exact", combine_attrs="drop_conflicts")


def fig08_rough_curves(curves: xr.Dataset, *, name: str, relative_humidity):
    """Fig. 8: the curves of one map at the given humidities (two panels) and the fit error of the
    asperity spheres at the lowest and highest humidity.

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
        ``curves`` and the figure.
    """
    import matplotlib.pyplot as plt

    rh = list(relative_humidity)
    half = (len(rh) + 1) // 2
    fig, axes = plt.subplots(2, 2, figsize=(10, 7.5), constrained_layout=True)
    plot_rough_curves(curves, rh=rh[:half], ax=axes[0, 0])
    plot_rough_curves(curves, rh=rh[half:], ax=axes[0, 1])
    # the fit error is drawn where the pressure is attractive and asperities touch (the mask of
    # plot_fit_error): at low RH that is a handful of distances (a near-empty panel), so the left
    # panel shows the lowest RH with at least 20 such states
    attractive = ((curves["pressure"] < 0) & (curves["n_contacts"] > 0)).sum("distance")
    counts = {r: int(attractive.sel(rh=r, method="nearest")) for r in rh}
    low = next((r for r in rh if counts[r] >= 20), max(rh, key=lambda r: counts[r]))
    plot_fit_error(curves, rh=low, ax=axes[1, 0])
    plot_fit_error(curves, rh=rh[-1], ax=axes[1, 1])
    if low != rh[0]:
        axes[1, 0].set_title(axes[1, 0].get_title() + f" (lowest RH with ≥ 20 attractive states in contact;"
                             f" RH {rh[0]:.0%} has {counts[rh[0]]})", fontsize="small")
    fig.suptitle(f"Fig. 8: modified DMT on {name}")
    return curves, fig


def fig10_mdmt_vs_gw(maps: dict, curves: dict, *, relative_humidity, rh_shown=(0.3, 0.5, 0.7, 0.9)):
    """Fig. 10: modified DMT per map against Greenwood-Williamson on the maps' mean moments.

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
        The GW curves (Eq. 14) on a grid spanning the maps' grids, and the figure.
    """
    mom = [rs.surface.roughness_moments(rs.surface.level(h, method="mean", nan="fill")) for h in maps.values()]
    moments = xr.concat(mom, "map").mean("map", keep_attrs=True)
    lo = min(float(c.distance.min()) for c in curves.values())
    hi = max(float(c.distance.max()) for c in curves.values())
    gw = rs.contact.gw_curves(moments, relative_humidity=list(relative_humidity),
                              distance=np.linspace(lo, hi, 300))
    fig = plot_mdmt_vs_gw(curves, gw, rh=rh_shown)
    fig.suptitle("Fig. 10: modified DMT per map vs GW on the sample moments")
    return gw, fig


def fig11_adhesion_vs_rh(summaries: dict):
    """Fig. 11: adhesive energy (Eq. 13) per map and wetted fraction at equilibrium versus RH.

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
        The summaries over a ``map`` dimension, and the figure.
    """
    fig = plot_adhesion_vs_rh(summaries)
    fig.suptitle("Fig. 11: adhesive energy and wetted fraction at equilibrium")
    ds = xr.concat(list(summaries.values()),
                   dim=xr.DataArray(list(summaries), dims="map", name="map",
                                    attrs={"long_name": "measured height map (sample name)"}),
                   combine_attrs="drop_conflicts")
    return ds, fig
