"""AFM maps, roughness statistics and PSDs, paper §4.1: Tables 2-4, Figs. 12 and 19.

The figure functions return ``(Dataset, Figure)``.
"""

from __future__ import annotations

import xarray as xr

import roughstick as rs

from ..plotting import plot_psd_schemes, plot_self_affine_psd

__all__ = ["QMAX_PAPER", "SCHEME_NAMES", "fig12_psd_schemes", "table4_self_affine", "fig19_self_affine_psd"]

QMAX_PAPER = rs.datasets.QMAX_PAPER  # rad/m, Table 3
SCHEME_NAMES = {1: "scheme 1: whole maps", 4: "scheme 2: 4 sub-maps each", 16: "scheme 3: 16 sub-maps each"}


def _stack(psds: dict, dim: str) -> xr.Dataset:
    da = xr.concat(list(psds.values()), dim=xr.DataArray(list(psds), dims=dim, name=dim,
                                                         attrs={"long_name": dim.replace("_", " ")}),
                   coords="minimal", compat="override", join="outer", combine_attrs="drop_conflicts")
    return da.to_dataset(name="psd")


def fig12_psd_schemes(schemes: dict):
    """Fig. 12: the PSDs of S1 by the three sub-map schemes and of S2 by scheme 3 (Eq. 31).

    Parameters
    ----------
    schemes : dict
        ``{"S1": {1: psd, 4: psd, 16: psd}, "S2": {..., 16: psd}}`` from :func:`roughstick.surface.submap_psd`.

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
        The S1 PSDs over a ``scheme`` dimension, and the figure.
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    plot_psd_schemes({SCHEME_NAMES[n]: s for n, s in schemes["S1"].items()}, ax=axes[0],
                     qmax=QMAX_PAPER, title="S1")
    plot_psd_schemes({SCHEME_NAMES[16]: schemes["S2"][16]}, ax=axes[1], qmax=QMAX_PAPER, title="S2")
    fig.tight_layout()
    return _stack({SCHEME_NAMES[n]: s for n, s in schemes["S1"].items()}, "scheme"), fig


def table4_self_affine(densities=(80.1e12, 88.1e12)):
    """Table 4 -> Eq. 37: the self-affine PSD parameters solved from the asperity statistics.

    Returns
    -------
    dict of str to xarray.Dataset
        :func:`roughstick.surface.fit_self_affine` per asperity density, keyed by a legend label.
    """
    fits = {}
    for dens in densities:
        m = rs.surface.moments_from_asperities(roughness=[2.6e-9, 2.4e-9], radius=220e-9, density=dens)
        fit = rs.surface.fit_self_affine(m0=m.m0, m2=m.m2, m4=m.m4, qmax=QMAX_PAPER)
        fit.attrs["asperity_moments"] = (float(m.m0), float(m.m2), float(m.m4))
        fits[f"Eq. 37, Table 4, N = {dens * 1e-12:.1f} µm⁻²"] = fit
    return fits


def fig19_self_affine_psd(fits: dict, measured: dict):
    """Fig. 19: the Eq. 37 PSDs of :func:`table4_self_affine` against measured PSDs.

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
        The fitted parameters over ``fit``, and the figure.
    """
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.5))
    plot_self_affine_psd(fits, measured=measured, ax=ax)
    ax.set_title("Fig. 19: Eq. 37 PSD from Table 4 vs samples")
    fig.tight_layout()
    params = xr.concat([f.drop_attrs() if hasattr(f, "drop_attrs") else f for f in fits.values()],
                       dim=xr.DataArray(list(fits), dims="fit", name="fit", attrs={"long_name": "fit"}))
    return params, fig
