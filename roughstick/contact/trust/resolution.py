"""Does the pixel resolve the answer? Summaries of the contact curves versus the pixel size.

At low humidity the apparent adhesive energy (Eq. 13) is set by a few asperities touching over a
handful of pixels, and the pixel moves it as much as the model does (docs/accuracy.md).
:func:`resolution_study` recomputes the energy, the pull-off pressure and the equilibrium distance
at coarser and finer pixels of the same surface, so a user can see whether an AFM pixel is fine
enough.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..._core.arguments import check_numbers
from ..._core.conventions import append_history
from ..._core.validate import height_in_si
from ...surface.generate import generate_surfaces
from ...testing import make_topography
from .._pipeline import curves
from ..adhesion import summary

__all__ = ["resolution_study", "resample_pixels"]

_SUMMARIES = ("adhesive_energy", "pull_off_pressure", "equilibrium_distance")


def _make_map(z, spacing, template=None):
    h = make_topography(z, spacing=spacing, periodic=True)
    if template is not None:
        h.attrs.update({k: v for k, v in template.attrs.items() if k not in ("history",)})
        h.attrs["periodic"] = 1
    return h


def resample_pixels(height: xr.DataArray, factor: float) -> xr.DataArray:
    """The same periodic map with pixels ``factor`` times larger.

    ``factor`` an integer >= 2: block averages of ``factor`` x ``factor`` pixels (what a coarser
    AFM pixel records; the map is cropped to a multiple of ``factor``). ``factor = 1/k`` with an
    integer k >= 2: Fourier (band-limited) interpolation onto k times more pixels per side, which
    adds no roughness beyond the original Nyquist wavenumber. ``factor = 1``: unchanged.

    Parameters
    ----------
    height : xarray.DataArray
        One eager (y, x) map, uniform spacing; treated as periodic.
    factor : float
        Pixel-size ratio, an integer or the inverse of one.

    Returns
    -------
    xarray.DataArray
        The resampled map (m), attribute ``pixel_factor``.
    """
    if not (np.isfinite(factor) and factor > 0):
        raise ValueError(f"factor must be a positive pixel-size ratio, got {factor!r}.")
    height = height_in_si(height)
    if height.ndim != 2:
        raise ValueError("resample_pixels takes one (y, x) map; loop over a stack.")
    z = np.asarray(height.transpose("y", "x").values, dtype=float)
    if not np.all(np.isfinite(z)):
        raise ValueError("height has NaN pixels; fill or crop them before resampling.")
    dy = float(height.y[1] - height.y[0])
    dx = float(height.x[1] - height.x[0])
    if not np.isclose(dx, dy, rtol=1e-6):
        raise ValueError("resample_pixels needs square pixels (dx == dy).")
    if factor >= 1:
        k = int(round(factor))
        if not np.isclose(factor, k) or k < 1:
            raise ValueError(f"factor must be an integer or the inverse of one, got {factor!r}.")
        if k == 1:
            out = _make_map(z, dx, height)
        else:
            ny, nx = (z.shape[0] // k) * k, (z.shape[1] // k) * k
            if ny < 4 * k or nx < 4 * k:
                raise ValueError(f"the map is too small to coarsen {k}x (needs >= {4 * k} pixels).")
            zc = z[:ny, :nx].reshape(ny // k, k, nx // k, k).mean(axis=(1, 3))
            out = _make_map(zc, dx * k, height)
    else:
        k = int(round(1 / factor))
        if not np.isclose(1 / factor, k) or k < 2:
            raise ValueError(f"factor must be an integer or the inverse of one, got {factor!r}.")
        ny, nx = z.shape
        spec = np.fft.fft2(z)
        big = np.zeros((ny * k, nx * k), dtype=complex)
        hy, hx = ny // 2, nx // 2
        big[:hy, :hx] = spec[:hy, :hx]
        big[:hy, -(nx - hx):] = spec[:hy, hx:]
        big[-(ny - hy):, :hx] = spec[hy:, :hx]
        big[-(ny - hy):, -(nx - hx):] = spec[hy:, hx:]
        zf = np.fft.ifft2(big).real * k * k
        out = _make_map(zf, dx / k, height)
    out.attrs["pixel_factor"] = float(factor)
    return out


@check_numbers(seed="seed")
def resolution_study(
    height: xr.DataArray | None = None,
    *,
    psd=None,
    relative_humidity,
    factors=(0.5, 1, 2),
    model: str = "fft_bem",
    shape=None,
    spacing: float | None = None,
    seed=0,
    material=None,
    adsorbed_layer="paper",
    **model_kwargs,
) -> xr.Dataset:
    r"""How much Γ (Eq. 13), the pull-off pressure and d_eq change with the pixel size.

    Give either a measured or generated ``height`` map (coarser pixels: block averages; finer:
    band-limited Fourier interpolation, which adds no roughness, so a change at finer pixels
    means the *contact model* is not resolved by the pixel, not the topography), or a ``psd``
    with ``shape`` and ``spacing`` (one surface is generated at the finest pixel over the same
    area with ``seed`` and block-averaged to the coarser ones, so finer pixels carry the PSD's
    roughness down to their own Nyquist wavenumber, as a finer AFM pixel would).

    Parameters
    ----------
    height : xarray.DataArray, optional
        One (y, x) map, periodic (the contact models treat it so).
    psd : callable or xarray.DataArray, optional
        A PSD accepted by :func:`roughstick.generate_surfaces` (instead of ``height``).
    relative_humidity : float or sequence
        RH fractions in (0, 1).
    factors : sequence of float, default (0.5, 1, 2)
        Pixel sizes relative to the native one: integers (coarser) or inverses of integers
        (finer). 1 is added if absent (the reference of the relative changes).
    model : str, default "fft_bem"
        Any model of :func:`roughstick.contact.curves`; the FFT boundary-element model
        is valid where the modified DMT is not, and costs a second or two per 512² map.
    shape, spacing, seed
        With ``psd``: native map shape (pixels), native pixel size [m] and the seed.
    material, adsorbed_layer, **model_kwargs
        Passed to :func:`roughstick.contact.curves`.

    Returns
    -------
    xarray.Dataset
        Over ``(pixel_size[, rh])``: ``adhesive_energy``, ``pull_off_pressure``,
        ``equilibrium_distance`` and ``relative_change_<summary>`` (against the native pixel),
        ``pixel_size`` [m]; attrs say how the maps were resampled.

    Examples
    --------
    >>> h = rs.generate_surfaces(rs.datasets.family_psd("table4"), n=1, shape=64, spacing=5e-9, seed=1)
    >>> r = rs.contact.resolution_study(h.isel(realization=0).compute(), relative_humidity=0.9)
    >>> r.pixel_size.values * 1e9
    array([ 2.5,  5. , 10. ])
    """
    if (height is None) == (psd is None):
        raise ValueError("give exactly one of height= (a map) or psd= (with shape= and spacing=).")
    factors = sorted({float(f) for f in factors} | {1.0})
    if any(f <= 0 for f in factors):
        raise ValueError(f"factors must be positive, got {factors}.")
    if psd is not None:
        if shape is None or spacing is None:
            raise ValueError("psd= needs shape= (pixels) and spacing= (native pixel size, m).")
        ny, nx = (shape, shape) if np.isscalar(shape) else tuple(shape)
        finest = min(factors)
        k = int(round(1 / finest)) if finest < 1 else 1
        fine = generate_surfaces(psd, n=1, shape=(ny * k, nx * k), spacing=spacing / k,
                                 seed=seed).isel(realization=0).compute()
        maps = {f: resample_pixels(fine, f * k) for f in factors}
        how = (f"generated from the PSD at {spacing / k * 1e9:.3g} nm pixels (seed {seed}), "
               "block-averaged to the coarser pixels")
    else:
        height = height_in_si(height)
        maps = {f: resample_pixels(height, f) for f in factors}
        how = ("coarser pixels: block averages of the map; finer: band-limited Fourier "
               "interpolation (no added roughness)")
    kw = dict(model_kwargs)
    kw.setdefault("check_validity", False)  # this is the measurement the checks would point to
    if material is not None:
        kw["material"] = material
    rows = []
    for f in factors:
        c = curves(maps[f], relative_humidity=relative_humidity, model=model,
                                 adsorbed_layer=adsorbed_layer, **kw)
        s = summary(c)[list(_SUMMARIES)]
        rows.append(s.expand_dims(pixel_size=[float(maps[f].x[1] - maps[f].x[0])]))
    ds = xr.concat(rows, dim="pixel_size", combine_attrs="drop_conflicts")
    native = float(maps[1.0].x[1] - maps[1.0].x[0])
    ref = ds.sel(pixel_size=native)
    for q in _SUMMARIES:
        ch = (ds[q] - ref[q]) / abs(ref[q])
        ch.attrs = {"long_name": f"relative change of {q} against the native pixel", "units": "1"}
        ds[f"relative_change_{q}"] = ch
    ds["pixel_size"].attrs = {"long_name": "pixel size", "units": "m"}
    ds.attrs["resampling"] = how
    ds.attrs["contact_model"] = model
    ds.attrs["native_pixel_size"] = native
    return append_history(ds, f"resolution_study(factors={factors}, model={model!r}): {how}")
