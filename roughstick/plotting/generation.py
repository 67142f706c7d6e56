"""Plots of generated surfaces (paper Fig. 13) and of their spectra against the target PSD.

Axes show nm and µm, wave numbers in rad/µm and PSDs in nm⁴; the data stay SI.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..surface.generate import surface_filter

__all__ = ["plot_surfaces", "plot_generated_psd", "ensemble_psd"]

_NM = 1e9
_UM = 1e6


def plot_surfaces(height: xr.DataArray, *, realizations=None, ncols: int = 3, axes=None,
                  cmap: str = "viridis", title: str | None = None):
    """Images of a few generated surfaces (Fig. 13), heights in nm, x and y in µm.

    Parameters
    ----------
    height : xarray.DataArray
        ``height`` [m] over ``(realization, y, x)`` (e.g. :func:`roughstick.surface.generate_surfaces`)
        or a single map ``(y, x)``.
    realizations : sequence of int, optional
        Realization labels to show (default: the first ``ncols``).
    ncols : int
        Number of panels when ``realizations`` is not given.
    axes : sequence of matplotlib Axes, optional
        One per panel.
    cmap : str
        Colour map.
    title : str, optional
        Prefix of each panel title.

    Returns
    -------
    list of matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt

    if "realization" not in height.dims:
        height = height.expand_dims(realization=[0])
    if realizations is None:
        realizations = height.realization.values[:ncols]
    sel = height.sel(realization=list(realizations)).compute()
    if axes is None:
        _, axes = plt.subplots(1, len(realizations), figsize=(3.4 * len(realizations), 3.0),
                               layout="constrained", squeeze=False)
        axes = axes[0]
    x, y = sel.x.values * _UM, sel.y.values * _UM
    extent = (x[0], x[-1], y[0], y[-1])
    for ax, k in zip(axes, realizations, strict=True):
        z = sel.sel(realization=k).values * _NM
        im = ax.imshow(z - z.mean(), origin="lower", extent=extent, cmap=cmap)
        ax.set_xlabel("x [µm]")
        ax.set_ylabel("y [µm]")
        ax.set_title(f"{title + ' ' if title else ''}realization {k}")
        ax.figure.colorbar(im, ax=ax, label="height [nm]", shrink=0.8)
    return list(axes)


def ensemble_psd(height: xr.DataArray) -> xr.DataArray:
    """Ensemble-mean radially averaged periodogram of surfaces ``(realization, y, x)``.

    The periodogram uses the project normalisation (docs/architecture.md, ``sum * dq² = m0``,
    mean not removed) and rings of width :math:`\\min(\\Delta q_x, \\Delta q_y)`.

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4] over ``q`` [rad m-1], with coordinate ``n_samples`` (modes per ring).
    """
    z = height.transpose(..., "y", "x")
    if "realization" not in z.dims:
        z = z.expand_dims(realization=[0])
    ny, nx = z.sizes["y"], z.sizes["x"]
    dx = float(z.x[1] - z.x[0])
    dy = float(z.y[1] - z.y[0])
    power = xr.apply_ufunc(
        lambda a: np.abs(np.fft.fft2(a)) ** 2, z, input_core_dims=[["y", "x"]],
        output_core_dims=[["y", "x"]], dask="parallelized", output_dtypes=[float],
    ).mean("realization").values
    dqx, dqy = 2 * np.pi / (nx * dx), 2 * np.pi / (ny * dy)
    s2d = power / (ny * nx) ** 2 / (dqx * dqy)
    return _ring_average(s2d, ny, nx, dy, dx)


def _ring_average(s2d_fft_order, ny, nx, dy, dx):
    qy = 2 * np.pi * np.fft.fftfreq(ny, dy)
    qx = 2 * np.pi * np.fft.fftfreq(nx, dx)
    dq = min(abs(qx[1]), abs(qy[1]))
    qmag = np.hypot(qy[:, None], qx[None, :])
    k = np.rint(qmag / dq).astype(int).ravel()
    kmax = int(np.floor(min(np.abs(qx).max(), np.abs(qy).max()) / dq))
    keep = k <= kmax
    counts = np.bincount(k[keep], minlength=kmax + 1)
    sums = np.bincount(k[keep], weights=s2d_fft_order.ravel()[keep], minlength=kmax + 1)
    with np.errstate(invalid="ignore"):
        mean = sums / counts
    out = xr.DataArray(mean, dims="q", coords={"q": np.arange(kmax + 1) * dq}, name="psd",
                       attrs={"units": "m4", "long_name": "radially averaged power spectral density"})
    out = out.assign_coords(n_samples=("q", counts))
    out["q"].attrs = {"units": "rad m-1", "long_name": "angular wavevector magnitude"}
    return out


def plot_generated_psd(height: xr.DataArray, psd, *, ax=None, label: str = "generated",
                       band: bool = True, color=None):
    """Ensemble-mean radial PSD of generated surfaces against the target PSD (log-log).

    The target is mapped onto the same grid with :func:`roughstick.surface.surface_filter` and averaged
    over the same rings, so the two curves agree in expectation at every ring; the shaded band is
    the ±2 standard-error Monte Carlo band of the mean (each mode's periodogram has standard
    deviation equal to its mean for Gaussian amplitudes).

    Parameters
    ----------
    height : xarray.DataArray
        Generated ``height`` over ``(realization, y, x)``.
    psd : DataArray or callable
        The PSD passed to :func:`roughstick.surface.generate_surfaces`.
    ax : matplotlib Axes, optional
    label : str
        Legend label of the generated curve.
    band : bool
        Draw the Monte Carlo band.
    color : optional
        Line colour.

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(5.5, 4), layout="constrained")
    ny, nx = height.sizes["y"], height.sizes["x"]
    dx = float(height.x[1] - height.x[0])
    dy = float(height.y[1] - height.y[0])
    gen = ensemble_psd(height)
    target2d = np.fft.ifftshift(np.asarray(surface_filter(psd, shape=(ny, nx), spacing=(dy, dx)).values))
    target = _ring_average(target2d, ny, nx, dy, dx)
    n = height.sizes.get("realization", 1)
    q = gen.q.values[1:] / _UM
    g = gen.values[1:] * 1e36
    t = target.values[1:] * 1e36
    ok = t > 0
    (line,) = ax.loglog(q[ok], g[ok], ".", ms=3, color=color, label=f"{label} (mean of {n})")
    ax.loglog(q[ok], t[ok], "-", color="k", lw=1, label="target PSD on the grid")
    if band:
        # a ring holds n_samples/2 independent modes (Hermitian pairs)
        se = t / np.sqrt(n * np.maximum(gen.n_samples.values[1:] / 2, 1))
        ax.fill_between(q[ok], (t - 2 * se)[ok].clip(min=t[ok].min() * 1e-3), (t + 2 * se)[ok],
                        color=line.get_color(), alpha=0.25, lw=0, label="±2 s.e. (Monte Carlo)")
    ax.set_xlabel("q [rad/µm]")
    ax.set_ylabel("PSD [nm⁴]")
    ax.legend(fontsize="small")
    return ax
