"""Plots of height maps and power spectral densities (Figs. 5, 12 and 19 of the paper).

Data are SI; axes show nm, µm and rad/µm.
"""

from __future__ import annotations

import numpy as np

from ..surface.self_affine import self_affine_psd
from ..surface.spectrum import psd_isotropic

__all__ = ["plot_height", "plot_psd_schemes", "plot_self_affine_psd"]


def _ax(ax):
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(5, 4))
    return ax


def plot_height(height, *, ax=None, cmap="viridis"):
    """Image of one height map ``(y, x)`` in nm over µm axes (Fig. 5 style). Returns the Axes."""
    ax = _ax(ax)
    h = height.transpose(..., "y", "x")
    x, y = h["x"].values * 1e6, h["y"].values * 1e6
    im = ax.pcolormesh(x, y, np.asarray(h.values) * 1e9, shading="auto", cmap=cmap)
    ax.set_aspect("equal")
    ax.set_xlabel("x [µm]")
    ax.set_ylabel("y [µm]")
    ax.figure.colorbar(im, ax=ax, label="height [nm]")
    return ax


def _iso(psd):
    return psd if "q" in psd.dims else psd_isotropic(psd)


def plot_psd_schemes(psds: dict, *, ax=None, qmax=None, title=None):
    """Radially averaged PSDs of several estimation schemes on log-log axes (Fig. 12).

    Parameters
    ----------
    psds : dict of str to xarray.DataArray
        Label → 2D ``(qy, qx)`` or isotropic ``(q)`` PSD [m4].
    ax : matplotlib.axes.Axes, optional
    qmax : float, optional
        Draw the cutoff wave number [rad m-1] as a vertical line.
    title : str, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _ax(ax)
    for label, psd in psds.items():
        iso = _iso(psd)
        q = iso["q"].values
        keep = q > 0
        ax.loglog(q[keep] * 1e-6, np.asarray(iso.values)[keep] * 1e36, label=label, lw=1)
    if qmax is not None:
        ax.axvline(float(qmax) * 1e-6, color="k", ls=":", lw=1, label=f"ξmax = {float(qmax) * 1e-6:.0f} rad/µm")
    ax.set_xlabel("wave number ξ [rad/µm]")
    ax.set_ylabel("PSD s(ξ) [nm⁴]")
    if title:
        ax.set_title(title)
    ax.legend(fontsize=8)
    return ax


def plot_self_affine_psd(fits: dict, *, measured: dict | None = None, ax=None, q=None):
    """Eq. 37 PSDs (from :func:`roughstick.surface.fit_self_affine`) against measured PSDs (Fig. 19).

    Parameters
    ----------
    fits : dict of str to xarray.Dataset
        Label → Dataset with ``s0``, ``s1``, ``q0``, ``qmax``.
    measured : dict of str to xarray.DataArray, optional
        Label → 2D or isotropic PSD [m4] drawn for reference.
    ax : matplotlib.axes.Axes, optional
    q : array_like, optional
        Wave numbers [rad m-1] at which to draw Eq. 37 (default 1 to 700 rad/µm).

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = _ax(ax)
    q = np.geomspace(1e6, 7e8, 600) if q is None else np.asarray(q, dtype=float)
    for label, fit in fits.items():
        s = self_affine_psd(q, s0=fit.s0, s1=fit.s1, q0=fit.q0, qmax=fit.qmax)
        v = np.asarray(s.values)
        ax.loglog(q * 1e-6, np.where(v > 0, v * 1e36, np.nan), lw=2, label=label)
    for label, psd in (measured or {}).items():
        iso = _iso(psd)
        qq = iso["q"].values
        keep = qq > 0
        ax.loglog(qq[keep] * 1e-6, np.asarray(iso.values)[keep] * 1e36, lw=1, alpha=0.8, label=label)
    ax.set_xlabel("wave number ξ [rad/µm]")
    ax.set_ylabel("PSD s(ξ) [nm⁴]")
    ax.legend(fontsize=8)
    return ax
