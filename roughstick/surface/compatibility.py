r"""Are the maps about to be averaged into one PSD maps of one surface?

Eq. 31 averages the spectra of several maps as samples of one stationary surface. Maps of
different samples (or of one sample where it is not stationary) give an average that is the PSD of
none of them, and nothing in the average shows it. :func:`warn_if_incompatible` compares the
maps before they are averaged:

* maps of one scan size: their rms heights :math:`S_q` and autocorrelation lengths
  :math:`S_{al}` (ISO 25178-2), which differ by more than :data:`COMPATIBLE_RATIO` between maps
  of different surfaces, far beyond the spread of maps of one surface;
* maps of different scan sizes, whose :math:`S_q` rightly differ (a self-affine film is rougher
  over a larger scan): the height variance each map's radial PSD holds in the band of wavevectors
  every map resolves, :math:`2\pi\int C(q)\,q\,dq`, which differs by more than
  :data:`COMPATIBLE_RATIO` squared between different surfaces.
"""

from __future__ import annotations

import logging
import warnings

import numpy as np
import xarray as xr

from .._core.arguments import check_numbers
from .._core.validate import external_stacklevel, grid_spacing
from .spectrum import power_spectrum, psd_isotropic
from .topography import validate_height

__all__ = ["warn_if_incompatible", "autocorrelation_length", "IncompatibleMapsWarning"]

#: Maps whose rms heights or autocorrelation lengths differ by more than this factor (or whose
#: PSDs over a common band differ by more than its square) are not taken for maps of one surface.
COMPATIBLE_RATIO = 2.0
#: Scan sizes within this relative difference count as one size.
SAME_SIZE = 0.1


class IncompatibleMapsWarning(UserWarning):
    """Maps averaged into one PSD differ more than maps of one surface do."""


@check_numbers(threshold="fraction")
def autocorrelation_length(height: xr.DataArray, *, threshold: float = 0.2) -> float:
    r"""The autocorrelation length :math:`S_{al}` [m] of one map (ISO 25178-2): the shortest
    horizontal distance at which its areal autocorrelation falls to ``threshold``.

    The autocorrelation is that of the map padded with zeros to twice its size (no wrap-round),
    normalised by the overlap, on the pixel grid.

    Examples
    --------
    >>> y, x = np.meshgrid(np.arange(64), np.arange(64), indexing="ij")
    >>> h = rs.testing.make_topography(np.cos(2 * np.pi * x / 32) * 1e-9, spacing=1e-9)
    >>> round(rs.surface.compatibility.autocorrelation_length(h) * 1e9)  # cos(2 pi r/32) = 0.2: 6.97
    7
    """
    h = validate_height(height)
    z = np.asarray(h.values, dtype=float)
    z = np.where(np.isfinite(z), z - np.nanmean(z), 0.0)
    ny, nx = z.shape
    f = np.fft.rfft2(z, s=(2 * ny, 2 * nx))
    acf = np.fft.irfft2(np.abs(f) ** 2, s=(2 * ny, 2 * nx))
    ones = np.fft.rfft2(np.ones_like(z), s=(2 * ny, 2 * nx))
    overlap = np.maximum(np.fft.irfft2(np.abs(ones) ** 2, s=(2 * ny, 2 * nx)), 1.0)
    acf = np.fft.fftshift(acf / overlap)
    acf /= acf[ny, nx]
    dy, dx = grid_spacing(h, "y"), grid_spacing(h, "x")
    yy, xx = np.meshgrid((np.arange(2 * ny) - ny) * dy, (np.arange(2 * nx) - nx) * dx, indexing="ij")
    r = np.hypot(yy, xx)
    # only lags with at least half the map overlapping are trusted
    trusted = (abs(yy) <= ny * dy / 2) & (abs(xx) <= nx * dx / 2)
    below = trusted & (acf <= threshold)
    return float(r[below].min()) if below.any() else float(r[trusted].max())


def _side(h: xr.DataArray) -> float:
    """The shorter side of a map [m]."""
    return min(h.sizes[d] * grid_spacing(h, d) for d in ("y", "x"))


def _band_psd(maps: list) -> tuple[np.ndarray, tuple[float, float]]:
    r"""Each map's height variance in the band every map resolves well (from four times its
    lowest wavevector to half its Nyquist wavevector), :math:`2\pi\int C(q)\,q\,dq` over the
    band; ``(values [m2], (q_lo, q_hi))``, NaN when the maps share no such band."""
    lo = max(4 * 2 * np.pi / _side(m) for m in maps)
    hi = min(0.5 * np.pi / max(grid_spacing(m, d) for d in ("y", "x")) for m in maps)
    if not lo < hi:
        return np.full(len(maps), np.nan), (lo, hi)
    out = []
    for m in maps:
        s = psd_isotropic(power_spectrum(m.fillna(float(m.mean()))))
        band = s.where((s.q >= lo) & (s.q <= hi), drop=True)
        out.append(float(2 * np.pi * np.trapezoid(band.values * band.q.values, band.q.values)))
    return np.array(out), (lo, hi)


def warn_if_incompatible(maps, names=None) -> dict:
    """An :class:`IncompatibleMapsWarning` when maps about to be averaged into one PSD differ more
    than maps of one surface do (the module's tests); returns each map's ``rms_height`` and
    ``autocorrelation_length`` [m] (and ``band_psd``, the variance in the shared band [m2], for
    maps of different sizes) by name.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> a = rs.testing.make_topography(rng.normal(size=(32, 32)) * 1e-9, spacing=1e-9)
    >>> b = rs.testing.make_topography(rng.normal(size=(32, 32)) * 5e-9, spacing=1e-9)
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     _ = rs.surface.compatibility.warn_if_incompatible([a, b], ["a", "b"])
    >>> [w.category.__name__ for w in caught]
    ['IncompatibleMapsWarning']
    """
    maps = [validate_height(m) for m in maps]
    names = [str(n) for n in (names or range(len(maps)))]
    stats = {n: {"rms_height": float(np.nanstd(np.asarray(m.values, dtype=float))),
                 "autocorrelation_length": autocorrelation_length(m)} for n, m in zip(names, maps)}
    if len(maps) < 2:
        return stats
    sides = np.array([_side(m) for m in maps])
    bad = []
    if sides.max() / sides.min() - 1 <= SAME_SIZE:
        for key, label in (("rms_height", "rms height Sq"), ("autocorrelation_length", "autocorrelation length Sal")):
            v = np.array([s[key] for s in stats.values()])
            if v.min() > 0 and v.max() / v.min() > COMPATIBLE_RATIO:
                bad.append(f"{label} {v.min() * 1e9:.3g}-{v.max() * 1e9:.3g} nm ({v.max() / v.min():.3g}x)")
    else:
        band, (lo, hi) = _band_psd(maps)
        for n, v in zip(names, band):
            stats[n]["band_psd"] = float(v)
        if not np.isfinite(band).all():
            bad.append(f"scans of {sides.min() * 1e6:.3g}-{sides.max() * 1e6:.3g} um share no band "
                       "of wavevectors that every map resolves, so nothing shows they are of one surface")
        elif band.max() / band.min() > COMPATIBLE_RATIO ** 2:
            bad.append(f"PSDs {band.max() / band.min():.3g}x apart over the band every map resolves "
                       f"({lo * 1e-6:.3g}-{hi * 1e-6:.3g} rad/um, the heights' variance in it; "
                       f"scans of {sides.min() * 1e6:.3g}-{sides.max() * 1e6:.3g} um)")
    if not bad:
        spread = (f"Sq {min(s['rms_height'] for s in stats.values()) * 1e9:.3g}-"
                  f"{max(s['rms_height'] for s in stats.values()) * 1e9:.3g} nm" if "band_psd" not in stats[names[0]]
                  else "rms heights in the band they share " + ", ".join(
                      f"{s['band_psd'] ** 0.5 * 1e9:.3g}" for s in stats.values()) + " nm")
        logging.getLogger("roughstick").info(f"the {len(maps)} maps are alike enough to be of one surface "
                                             f"({spread}): averaged")
    if bad:
        each = "; ".join(f"{n}: Sq {s['rms_height'] * 1e9:.3g} nm, Sal {s['autocorrelation_length'] * 1e9:.3g} nm"
                         for n, s in stats.items())
        limit = (f"more than {COMPATIBLE_RATIO:g}x" if sides.max() / sides.min() - 1 <= SAME_SIZE
                 else f"more than {COMPATIBLE_RATIO ** 2:g}x")
        warnings.warn(
            f"the {len(maps)} maps averaged into one PSD differ more than maps of one surface do "
            f"({' and '.join(bad)}; {limit}; {each}): their average is the PSD of none of them. "
            "Average only maps of one sample (give each sample's maps to a command or run of "
            "their own).",
            IncompatibleMapsWarning, stacklevel=external_stacklevel())
    return stats
