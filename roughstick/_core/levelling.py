"""The levelling of a height map, one home for :func:`roughstick.surface.level` (xarray, lazy)
and :func:`roughstick.io.read_afm` (a measured map levelled as it is read).

Heights are ``z`` over the last two axes ``(y, x)``; scan lines run along ``x``.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import distance_transform_edt

#: What each levelling removes (the words of ``history`` and of the commands' printed line).
METHODS = {
    "plane": "its least-squares plane",
    "mean": "its mean height",
    "line": "a least-squares line from each scan line, then the mean",
    "none": "nothing",
}


def _nearest_fill(z, mask):
    idx = distance_transform_edt(mask, return_distances=False, return_indices=True)
    return z[tuple(idx)]


def level_kernel(z, *, method, nan, max_nan_fraction, x, y):
    """Level maps over the last two axes (y, x). Returns a float array of the same shape."""
    out = np.array(z, dtype=float, copy=True)
    flat = out.reshape((-1,) + out.shape[-2:])
    X, Y = np.meshgrid(x - x.mean(), y - y.mean())
    for k in range(flat.shape[0]):
        zz = flat[k]
        bad = ~np.isfinite(zz)
        frac = bad.mean()
        if frac > max_nan_fraction:
            raise ValueError(
                f"{100 * frac:.1f} % of the map is NaN (more than max_nan_fraction="
                f"{max_nan_fraction}); it cannot be levelled reliably. Crop the valid region "
                "(height.isel(x=..., y=...)) or raise max_nan_fraction."
            )
        if bad.any() and nan == "raise":
            raise ValueError(
                f"the map has {int(bad.sum())} NaN pixels (dropouts); pass nan='fill' (nearest valid "
                "value after levelling) or nan='mask' (keep NaN; spectra then refuse the map)."
            )
        good = ~bad
        if method == "mean":
            zz = zz - zz[good].mean()
        elif method == "plane":
            A = np.column_stack([np.ones(good.sum()), X[good], Y[good]])
            coef, *_ = np.linalg.lstsq(A, zz[good], rcond=None)
            zz = zz - (coef[0] + coef[1] * X + coef[2] * Y)
        elif method == "line":
            # scan lines run along x (rows): remove a least-squares line from each row,
            # then the mean plane of the result
            xs = X[0]
            for j in range(zz.shape[0]):
                g = good[j]
                if g.sum() >= 2:
                    p = np.polyfit(xs[g], zz[j, g], 1)
                    zz[j] = zz[j] - np.polyval(p, xs)
                elif g.sum() == 1:
                    zz[j] = zz[j] - zz[j, g][0]
            zz = zz - zz[good].mean()
        if bad.any() and nan == "fill":
            zz = _nearest_fill(zz, bad)
        flat[k] = zz
    return out
