"""Plots of the meniscus physics (Fig. 1b) and of the sphere contact models (Fig. 3).

Data are SI; axes show nm, nN and MPa.
"""

from __future__ import annotations

import numpy as np

__all__ = ["plot_meniscus", "plot_sphere_curves"]

_STYLE = {
    "maugis": {"color": "C0", "ls": "-", "label": "Maugis"},
    "dmt": {"color": "C1", "ls": "--", "label": "DMT"},
    "modified_dmt": {"color": "C2", "ls": ":", "label": "modified DMT", "lw": 2.0},
    "jkr": {"color": "C3", "ls": "-.", "label": "JKR"},
    "hertz": {"color": "0.4", "ls": "-", "label": "Hertz"},
}


def plot_meniscus(laplace_pressure, water_height, *, ax=None):
    """Fig. 1b: Laplace pressure [MPa] (left axis) and water height [nm] (right) against RH [%].

    Parameters
    ----------
    laplace_pressure, water_height : xarray.DataArray
        Over dimension ``rh`` (fraction), from :func:`roughstick.contact.laplace_pressure` and
        :func:`roughstick.contact.water_height`.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    tuple of matplotlib.axes.Axes
        The pressure axes and the twin water-height axes.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(5.5, 4))
    rh = laplace_pressure["rh"].values * 100
    ax.plot(rh, np.asarray(laplace_pressure.values) / 1e6, "C0-", label=r"$\Delta P$")
    ax.set_xlabel("relative humidity [%]")
    ax.set_ylabel(r"Laplace pressure $\Delta P$ [MPa]", color="C0")
    ax2 = ax.twinx()
    ax2.plot(water_height["rh"].values * 100, np.asarray(water_height.values) * 1e9, "C3--", label=r"$h_{water}$")
    ax2.set_ylabel(r"water height $h_{water}$ [nm]", color="C3")
    ax2.set_yscale("log")
    ax.grid(True, alpha=0.3)
    ax.set_title("Fig. 1b: Laplace pressure and water height")
    return ax, ax2


def plot_sphere_curves(curves, *, axes=None, xlim_factor=(1.2, 1.0)):
    """Fig. 3: force-interference curves per model in a (radius x rh) grid of panels.

    Parameters
    ----------
    curves : xarray.Dataset
        With ``force`` over ``(model, radius, rh, interference)`` (as written by the demo) and
        optionally ``water_height`` over ``rh``.
    axes : array of matplotlib.axes.Axes, optional
        Shape ``(n_radius, n_rh)``.
    xlim_factor : tuple of float
        Each panel shows interference from ``-xlim_factor[0] * h_water`` to the largest
        equilibrium interference times ``1 + xlim_factor[1]``.

    Returns
    -------
    numpy.ndarray of matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt

    force = curves["force"]
    nr, nh = force.sizes["radius"], force.sizes["rh"]
    if axes is None:
        _, axes = plt.subplots(nr, nh, figsize=(4 * nh, 3.2 * nr), squeeze=False)
    axes = np.asarray(axes).reshape(nr, nh)
    d = force["interference"].values
    for i in range(nr):
        for j in range(nh):
            ax = axes[i, j]
            sub = force.isel(radius=i, rh=j)
            deq = []
            for model in sub["model"].values:
                f = np.asarray(sub.sel(model=model).values)
                st = _STYLE.get(str(model), {"label": str(model)})
                ax.plot(d * 1e9, f * 1e9, **st)
                pos = np.nonzero((f > 0) & (d > 0))[0]
                if pos.size:
                    deq.append(d[pos[0]])
            ax.axhline(0, color="k", lw=0.5)
            if "water_height" in curves:
                h = float(curves["water_height"].isel(rh=j))
                hi = (max(deq) if deq else h) * (1 + xlim_factor[1])
                ax.set_xlim(-xlim_factor[0] * h * 1e9, hi * 1e9)
                sel = (d >= -xlim_factor[0] * h) & (d <= hi)
                vals = np.asarray(sub.values)[..., sel]
                if vals.size:
                    lo_f, hi_f = np.nanmin(vals), np.nanmax(vals)
                    pad = 0.08 * (hi_f - lo_f)
                    ax.set_ylim((lo_f - pad) * 1e9, (hi_f + pad) * 1e9)
            R = float(sub["radius"]) * 1e9
            rh = float(sub["rh"]) * 100
            ax.set_title(f"R = {R:.0f} nm, RH = {rh:.0f} %")
            ax.set_xlabel(r"interference $\delta$ [nm]")
            ax.set_ylabel("force [nN]")
            ax.grid(True, alpha=0.3)
    axes[0, 0].legend(fontsize=8)
    axes[0, 0].figure.tight_layout()
    return axes
