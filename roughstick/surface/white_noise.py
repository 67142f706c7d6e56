r"""Surfaces as a deterministic map of white noise: the random input of rare-event estimators.

:func:`noise_map` returns the map :math:`w \mapsto z` from a standard-normal field ``w`` of the
zone's shape to a periodic surface with the PSD (Eqs. 33-34): one forward and one inverse real
FFT, the amplitudes :math:`\sqrt{P(\mathbf q)}` in between (the mean mode removed). With a
non-Gaussian height distribution the Gaussian field is the translation process's (its spectrum
pre-corrected as :func:`roughstick.surface.generate_surfaces` does with
``distribution_method="translation"``, its mean mode included: the zone is a piece of a
larger surface with that distribution) and each pixel goes through the distribution's
translation :math:`T`: :math:`z = \sigma\,T(g)`. Either way ``w`` stays standard normal under
a preconditioned Crank-Nicolson move, so a subset simulation on ``w`` samples the surface's own
law, Gaussian or not.
"""

from __future__ import annotations

import numpy as np
import scipy.fft
import xarray as xr

from ._marginal_kernels import cached_setup
from .distribution import as_height_distribution, evaluate
from .generate import surface_filter

__all__ = ["noise_map"]


class NoiseMap:
    """The map of :func:`noise_map`: call it on a white-noise field of ``noise_shape``."""

    def __init__(self, psd, *, shape, spacing, height_distribution=None):
        s = surface_filter(psd, shape=shape, spacing=spacing)
        ny, nx = s.shape
        dy, dx = float(s.attrs["spacing_y"]), float(s.attrs["spacing_x"])
        dq2 = (2 * np.pi / (ny * dy)) * (2 * np.pi / (nx * dx))
        power = np.fft.ifftshift(np.asarray(s.values, dtype=float)) * dq2
        with_mean = power[:, : nx // 2 + 1].copy()
        power[0, 0] = 0.0  # the mean plane is the reference of the distances
        self.amplitude = np.sqrt(power[:, : nx // 2 + 1])
        self.ny, self.nx, self.dy, self.dx = ny, nx, dy, dx
        self.noise_shape = (ny, nx)
        self.variance = float(power.sum())
        self.table, self.scale, self.translation = None, 1.0, None
        dist = None if height_distribution is None else as_height_distribution(height_distribution)
        if dist is not None and dist.attrs.get("family") != "normal":
            table = np.asarray(dist["height"].values, dtype=float)
            # the zone is a piece of a larger surface with this distribution: its mean mode
            # (the long waves the grid does not resolve) enters the field before the translation
            (a_box, rows, ncols), scale, self.table, info = cached_setup(
                "translation", with_mean, nx, ny, table, "fixed")
            gaussian = np.zeros_like(self.amplitude)
            gaussian[np.ix_(rows, np.arange(ncols))] = a_box
            self.amplitude, self.scale = gaussian, float(scale)
            self.translation = (f"{dist.attrs['family']} heights (skewness {dist.attrs['skewness']:.3g}, "
                                f"kurtosis {dist.attrs['kurtosis']:.3g}) by {info}")

    def height_array(self, z) -> xr.DataArray:
        """A height map [m] of this grid as the labelled, periodic DataArray the models take."""
        return xr.DataArray(z, dims=("y", "x"), coords={"y": (np.arange(self.ny) + 0.5) * self.dy,
                                                        "x": (np.arange(self.nx) + 0.5) * self.dx},
                            name="height", attrs={"units": "m", "long_name": "surface height", "periodic": 1})

    def __call__(self, noise) -> np.ndarray:
        w = np.reshape(np.asarray(noise, dtype=float), self.noise_shape)
        spec = scipy.fft.rfft2(w, norm="ortho", workers=1)
        spec *= self.amplitude
        g = scipy.fft.irfft2(spec, s=self.noise_shape, norm="forward", workers=1)
        if self.table is None:
            return g
        return self.scale * evaluate(self.table, g)


def noise_map(psd, *, shape, spacing, height_distribution=None) -> NoiseMap:
    r"""The surface of a white-noise field: :math:`z = \mathcal F^{-1}[\sqrt{P}\,\mathcal F[w]]`.

    Maps a standard-normal field ``w`` of ``shape`` to a circulant (periodic) surface with
    exactly the PSD of Eqs. 33-34 (the power of each mode as :func:`surface_filter` gives it,
    the mean mode removed); with ``height_distribution`` to the translation process
    :math:`z = \sigma\,T(g)` whose Gaussian field :math:`g` has the pre-corrected spectrum, so
    that ``z`` has the PSD and the height distribution (as
    ``generate_surfaces(..., distribution_method="translation")``, the mean mode's power in
    :math:`g` before the translation). Equal in law to
    :func:`generate_surfaces`, not the same realization for the same seed. The random input is
    the white noise itself: the map is what a subset simulation moves through.

    Parameters
    ----------
    psd, shape, spacing
        As in :func:`generate_surfaces`.
    height_distribution : xarray.Dataset, optional
        Of :func:`height_distribution`; None or a normal one: Gaussian surfaces.

    Returns
    -------
    NoiseMap
        Callable ``noise -> height`` [m] (an array of ``shape``), with ``noise_shape``,
        ``variance`` (the expected height variance [m²]) and ``height_array(z)`` (the labelled
        periodic map the contact models take).

    Examples
    --------
    >>> f = rs.surface.noise_map(rs.datasets.family_psd("table4"), shape=(16, 16), spacing=5e-9)
    >>> z = f(np.random.default_rng(0).standard_normal(f.noise_shape))
    >>> z.shape, abs(float(z.mean())) < 1e-20
    ((16, 16), True)
    """
    return NoiseMap(psd, shape=shape, spacing=spacing, height_distribution=height_distribution)
