r"""Are measured heights Gaussian within their sampling error? Skewness, kurtosis and upper-tail
quantiles of height maps against those of Gaussian surfaces with the same PSD.

The pixels of a map are correlated, and a map holds few of its longest wavelengths, so a
statistic of its heights scatters far more than that of as many independent values, and is
biased (a Gaussian map much larger than its correlation length has kurtosis 3, a small one
less). The sampling distribution of each statistic *for a Gaussian surface like the map* is
therefore measured on Gaussian surrogates (Schreiber & Schmitz 1996): surfaces drawn from the
map's own PSD (:func:`roughstick.surface.power_spectrum`, Hann-windowed) at its size and pixel
(:func:`roughstick.surface.generate_surfaces` with the map's own Fourier amplitudes and random
phases), levelled like it. With each map standardised by its own mean and rms, the statistics

.. math::

    \mathrm{skewness} = \overline{z^3}, \qquad \mathrm{kurtosis} = \overline{z^4}, \qquad
    z_p = F_n^{-1}(p) \quad (p = 0.99, 0.999)

of the map are compared with the surrogates' sampling interval, mean :math:`\pm\, z\,`sd over
the surrogates (for an infinite Gaussian surface: 0, 3 and :math:`\Phi^{-1}(p)` = 2.326, 3.090).
A map whose statistics all fall inside is Gaussian within its sampling error.
"""

from __future__ import annotations

import hashlib

import numpy as np
import xarray as xr
from scipy import special

from .._core.arguments import check_numbers
from .._core.conventions import append_history, dataset_attrs
from .._core.dask import as_seed_sequence
from .._core.references import cite
from .generate import generate_surfaces
from .spectrum import power_spectrum
from .topography import is_periodic, level_unless_periodic

__all__ = ["height_diagnostics", "is_gaussian"]

REFERENCES = cite("schreiber1996")

#: Upper-tail probabilities whose height quantiles are compared with the Gaussian's.
TAIL_PROBABILITIES = (0.99, 0.999)
#: Surrogates generated at once per map (memory: this many maps).
_BATCH = 16
#: Surrogate amplitudes: "fixed", the map's own Fourier amplitudes with random phases (the
#: classic phase-randomised surrogate; a Gaussian map then passes closer to the nominal rate).
AMPLITUDE = "fixed"


def _plane_removed(z: np.ndarray) -> np.ndarray:
    """The least-squares plane of each map of a stack ``(..., ny, nx)`` removed up to its mean
    (which the statistics remove): on a complete grid the constant and the two centred
    coordinates are orthogonal, so the slopes are two projections."""
    ny, nx = z.shape[-2:]
    y = np.arange(ny) - (ny - 1) / 2
    x = np.arange(nx) - (nx - 1) / 2
    slope_x = (z.sum(axis=-2) @ x) / (ny * np.sum(x * x))
    slope_y = (z.sum(axis=-1) @ y) / (nx * np.sum(y * y))
    return z - slope_x[..., None, None] * x - slope_y[..., None, None] * y[:, None]


def _statistics(maps) -> np.ndarray:
    """(skewness, kurtosis, z_0.99, z_0.999) of the pooled maps (a list of 2-D arrays), each
    map standardised by its own mean and rms first; quantiles as numpy's "linear"."""
    z = np.concatenate([((m - m.mean()) / m.std()).ravel() for m in maps])
    pos = np.asarray(TAIL_PROBABILITIES) * (z.size - 1)
    lo = np.floor(pos).astype(int)
    part = np.partition(z, np.concatenate([lo, lo + 1]))
    quantiles = part[lo] + (pos - lo) * (part[lo + 1] - part[lo])
    z2 = z * z
    return np.array([np.mean(z2 * z), np.mean(z2 * z2), *quantiles])


def _maps(height):
    """The levelled maps as a list of 2-D DataArrays, and the dims, sizes and coordinates of
    the stack they came from (a list of maps of any sizes: dim ``map``)."""
    if isinstance(height, (list, tuple)):
        maps = [level_unless_periodic(m) for m in height]
        if any(m.ndim != 2 for m in maps):
            raise ValueError("a list of height maps must hold 2-D (y, x) maps; stack maps of one "
                             "size into one DataArray instead.")
        dims, sizes, coords = ["map"], [len(maps)], {}
    else:
        h = level_unless_periodic(height)
        dims = [d for d in h.dims if d not in ("y", "x")]
        h = h.transpose(*dims, "y", "x")
        stacked = h.stack(_map=dims) if dims else h.expand_dims(_map=[0])
        maps = [stacked.isel(_map=i, drop=True).transpose("y", "x").assign_attrs(h.attrs)
                for i in range(stacked.sizes["_map"])]
        sizes, coords = [h.sizes[d] for d in dims], {d: h[d] for d in dims if d in h.coords}
    if not all(bool(np.isfinite(m).all()) for m in maps):
        raise ValueError("the maps have NaN pixels; level them with rs.surface.level(height, "
                         "nan='fill') first.")
    return maps, dims, sizes, coords


def _surrogate_statistics(maps: list, n: int, seed: np.random.SeedSequence) -> np.ndarray:
    """Statistics of ``n`` sets of Gaussian surrogates: per set, one surrogate of each map (from
    that map's own PSD, at its size and pixel, levelled like it), pooled."""
    psds = [power_spectrum(m) for m in maps]
    out = np.empty((n, 2 + len(TAIL_PROBABILITIES)))
    for start in range(0, n, _BATCH):
        idx = np.arange(start, min(start + _BATCH, n))
        sets = []
        for j, (p, m) in enumerate(zip(psds, maps, strict=True)):
            z = np.asarray(generate_surfaces(
                p, realizations=idx, seed=np.random.SeedSequence(seed.entropy, spawn_key=(*seed.spawn_key, j)),
                chunks=-1, amplitude=AMPLITUDE, dtype="float32").values)
            sets.append(z if is_periodic(m) else _plane_removed(z))  # levelled like the map
        for i in range(idx.size):
            out[idx[i]] = _statistics([s[i] for s in sets])
    return out


@check_numbers(confidence="fraction", n="count", seed="seed")
def height_diagnostics(height: xr.DataArray, *, pooled: bool = False, confidence: float = 0.95,
                       n: int = 50, seed=0) -> xr.Dataset:
    r"""Skewness, kurtosis and upper-tail quantiles of height maps against a Gaussian's, with
    the Gaussian's sampling intervals for a map like this one (module docstring).

    The maps are levelled by a least-squares plane (periodic ones, e.g. generated surfaces, are
    not) and each standardised by its own mean and
    rms. The Gaussian's interval of each statistic is its mean :math:`\pm z` standard deviations
    (:math:`z = \Phi^{-1}((1 + c)/2)`) over ``n`` sets of Gaussian surrogates with the maps' own
    PSDs, sizes and pixels. ``gaussian``
    is True where all four statistics fall inside their intervals widened to the Bonferroni
    level :math:`1 - (1 - c)/4` (four statistics tested at once, so that a Gaussian map passes
    with probability about ``confidence``).

    Parameters
    ----------
    height : xarray.DataArray or list of xarray.DataArray
        Height maps ``(..., y, x)`` (at least 8 x 8 pixels), or a list of 2-D maps of any sizes
        and pixels (dim ``map``).
    pooled : bool, default False
        One set of statistics for all the maps pooled, instead of one per map along the leading
        dims.
    confidence : float, default 0.95
        Level of each interval.
    n : int, default 50
        Surrogates per map (the cost: ``n`` Gaussian surfaces of each map's size).
    seed : int, default 0
        Root seed of the surrogates.

    Returns
    -------
    xarray.Dataset
        ``skewness``, ``kurtosis`` and ``tail_quantile`` (heights over the rms height at
        ``probability`` 0.99 and 0.999) of the maps [1]; ``<name>_gaussian_lower`` and
        ``_upper``: the Gaussian's sampling interval of each; ``tail_quantile_gaussian``:
        :math:`\Phi^{-1}(p)`; ``gaussian`` (bool): Gaussian within the sampling error.

    Examples
    --------
    >>> h = rs.surface.generate_surfaces(rs.datasets.family_psd("S1"), n=1, shape=64,
    ...                                  spacing=5e-9, seed=3).isel(realization=0)
    >>> d = rs.surface.height_diagnostics(h, n=50)
    >>> bool(d.gaussian), d.tail_quantile.sizes["probability"]
    (True, 2)
    """
    maps, lead, sizes, coords = _maps(height)
    root = as_seed_sequence(seed)
    groups = [maps] if pooled or not lead else [[m] for m in maps]
    alpha = (1 - confidence) / 2
    wide = alpha / (2 + len(TAIL_PROBABILITIES))
    rows = []
    for g, group in enumerate(groups):
        value = _statistics([np.asarray(m.values, dtype=float) for m in group])
        child = np.random.SeedSequence(root.entropy, spawn_key=(*root.spawn_key, g))
        reps = _surrogate_statistics(group, n, child)
        mean, sd = reps.mean(axis=0), reps.std(axis=0, ddof=1)
        lo, hi = mean - special.ndtri(1 - alpha) * sd, mean + special.ndtri(1 - alpha) * sd
        vlo, vhi = mean - special.ndtri(1 - wide) * sd, mean + special.ndtri(1 - wide) * sd
        rows.append((value, lo, hi, bool(np.all((vlo <= value) & (value <= vhi)))))
    shape, dims = ([], []) if pooled or not lead else (sizes, lead)
    return _as_dataset(rows, shape, dims, coords if dims else {}, confidence, n, pooled)


def _as_dataset(rows, shape, dims, coords, confidence, n, pooled) -> xr.Dataset:
    stack = [np.array([r[i] for r in rows]) for i in range(4)]
    suffix = ("", "_gaussian_lower", "_gaussian_upper")
    what = ("", f", lower end of the Gaussian's {confidence:.0%} sampling interval",
            f", upper end of the Gaussian's {confidence:.0%} sampling interval")

    def var(column, long_name, k):
        return xr.DataArray(stack[k][:, column].reshape(shape), dims=dims, coords=coords,
                            attrs={"units": "1", "long_name": long_name + what[k]})

    ds = xr.Dataset()
    for i, (name, long) in enumerate((("skewness", "height skewness"),
                                      ("kurtosis", "height kurtosis (3 for a Gaussian)"))):
        for k in range(3):
            ds[name + suffix[k]] = var(i, long, k)
    p = xr.DataArray(list(TAIL_PROBABILITIES), dims="probability",
                     attrs={"units": "1", "long_name": "cumulative probability of the height quantile"})
    for k in range(3):
        parts = [var(2 + j, "height quantile over the rms height", k) for j in range(len(TAIL_PROBABILITIES))]
        ds["tail_quantile" + suffix[k]] = xr.concat(parts, dim=p).transpose(..., "probability")
    ds["tail_quantile_gaussian"] = xr.DataArray(
        special.ndtri(TAIL_PROBABILITIES), dims="probability",
        attrs={"units": "1", "long_name": "height quantile of an infinite Gaussian surface, Phi^-1(p)"})
    ds["gaussian"] = xr.DataArray(stack[3].reshape(shape), dims=dims, coords=coords,
                                  attrs={"long_name": "heights Gaussian within their sampling error"})
    ds.attrs = dataset_attrs(
        "height-distribution diagnostics: skewness, kurtosis and tail quantiles against a Gaussian's",
        references=REFERENCES, confidence=confidence, n_surrogates=n, pooled=int(pooled),
        interval_method="mean +- z sd over Gaussian surrogates with each map's own Fourier "
                        "amplitudes (Hann-windowed power_spectrum), size and pixel, random "
                        "phases, levelled like the map",
        verdict=f"gaussian: all four statistics inside the Gaussian's intervals at the Bonferroni "
                f"level 1 - (1 - {confidence:g}) / 4")
    return append_history(ds, f"height_diagnostics: pooled={pooled}, n={n}")


@check_numbers(confidence="fraction", n="count")
def is_gaussian(height: xr.DataArray, *, confidence: float = 0.95, n: int = 50) -> bool:
    """Whether a set of maps is Gaussian within its sampling error: the pooled verdict of
    :func:`height_diagnostics` (skewness, kurtosis and the 99th and 99.9th height percentiles
    all inside the sampling intervals of Gaussian surfaces with the maps' own PSDs, sizes and
    pixels; Bonferroni-corrected to ``confidence``).

    Examples
    --------
    >>> h = rs.surface.generate_surfaces(rs.datasets.family_psd("S1"), n=2, shape=64,
    ...                                  spacing=5e-9, seed=3)
    >>> rs.surface.is_gaussian(h, n=50)
    True
    """
    maps = height if isinstance(height, (list, tuple)) else [height]
    # the key: each map in single precision (a map levelled once more, its plane ~1e-25 m,
    # is the same map), its shape and pixel
    key = (confidence, n, *(
        (hashlib.sha1(np.ascontiguousarray(np.asarray(m.values, dtype=np.float32))).hexdigest(), m.shape,
         tuple(float(m[d][1] - m[d][0]) if m.sizes[d] > 1 else 0.0 for d in ("y", "x"))) for m in maps))
    if key not in _VERDICTS:  # the same maps asked twice (a command, then the ensemble it runs)
        _VERDICTS[key] = bool(height_diagnostics(height, pooled=True, confidence=confidence, n=n).gaussian)
        while len(_VERDICTS) > 8:
            _VERDICTS.pop(next(iter(_VERDICTS)))
    return _VERDICTS[key]


_VERDICTS: dict = {}
