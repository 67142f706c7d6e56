"""Does the pixel resolve the water necks? The check that runs before a contact solve.

Below about 60 % RH the adhesive energy (Eq. 13) is carried by water necks around the touching
summits: the ring where the gap is below the water height :math:`h_{water}` (Eq. 6). Around a
summit of mean curvature :math:`\\kappa` its radius is :math:`\\sqrt{2 h_{water}/\\kappa}`; the
map's groups give it in pixels for the rms curvature (``neck_pixels`` of
:func:`roughstick.contact.surface_groups`). Where that radius spans fewer than
:data:`RESOLVED_NECK_PIXELS` pixels the pixel, not the surface, sets Γ.
:func:`roughstick.contact.resolution_study` measures how much; this module only warns, at the cost of one
pass over the map. docs/accuracy.md ("Is the pixel fine enough?") gives the measurement behind
the threshold.
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from ..._core.remedy import spell
from ..._core.validate import ValidityWarning, external_stacklevel
from ..meniscus import as_relative_humidity, water_height
from .validity import _neck_radius, map_moments

__all__ = ["RESOLVED_NECK_PIXELS", "FINE_PIXEL", "PixelResolutionWarning", "warn_if_unresolved"]

#: Wetted-neck radius, in pixels, below which Γ depends on the pixel (docs/accuracy.md, "Is the
#: pixel fine enough?").
RESOLVED_NECK_PIXELS = 3.0
#: About 1 nm: the pixel of the finest topography maps of such films. At or below it the warning
#: does not ask for finer data but for the pixel's cost to be measured and quoted.
FINE_PIXEL = 1.0e-9


class PixelResolutionWarning(ValidityWarning):
    """The pixel does not resolve the water necks: Γ depends on the pixel (a ValidityWarning, so
    ``warnings.simplefilter("error", rs.ValidityWarning)`` catches it; filter it alone by name)."""


def warn_if_unresolved(
    height: xr.DataArray | None = None,
    *,
    relative_humidity=None,
    adsorbed_layer="paper",
    groups: xr.Dataset | None = None,
    spacing: float | None = None,
    generated: bool | None = None,
    stacklevel: int | None = None,
) -> bool:
    """Warn (:class:`PixelResolutionWarning`) if the pixel does not resolve the water necks.

    The warning names the remedy that exists for this surface, spelled where the user is
    (:mod:`roughstick._core.remedy`): for generated surfaces a finer ``spacing`` (the value that
    makes the neck span :data:`RESOLVED_NECK_PIXELS` pixels); for a measured map, or a pixel
    already at or below :data:`FINE_PIXEL`, measuring what the pixel costs
    (:func:`roughstick.contact.resolution_study`, ``roughstick curves --resolution``) and quoting Γ with
    that change, since finer data may not exist.

    Parameters
    ----------
    height : xarray.DataArray, optional
        The map or stack of maps, dims ``(..., y, x)`` (every map is checked); or None with
        ``groups``.
    relative_humidity : float or sequence
        RH fractions in (0, 1) (with ``height``).
    adsorbed_layer : {"paper", "none"} or callable
        Water-height model of :func:`roughstick.contact.water_height`.
    groups : xarray.Dataset, optional
        Groups with ``neck_pixels`` (:func:`roughstick.contact.surface_groups`, or
        :func:`roughstick.contact.expected_surface_groups` of an ensemble's PSD) instead of ``height``.
    spacing : float, optional
        Pixel size [m] of the surfaces ``groups`` describe (with ``height``: its own).
    generated : bool, optional
        Whether the surfaces are generated from a PSD (a finer ``spacing`` is then the remedy)
        or measured. Default: True for ``groups``; for ``height``, True when its attributes are
        those of :func:`roughstick.generate_surfaces` (``periodic = 1`` and a ``seed``).
    stacklevel : int, optional
        Default: the first frame outside roughstick (the user's line).

    Returns
    -------
    bool
        True when some map at some humidity has a neck below :data:`RESOLVED_NECK_PIXELS`.

    Examples
    --------
    >>> h = rs.datasets.surface_family("S1", shape=(64, 64), seed=0, n=1).isel(realization=0)
    >>> rs.contact.surface_groups(h, relative_humidity=[0.05, 0.9]).neck_pixels.round(1).values
    array([1.3, 7.5])
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     rs.contact.warn_if_unresolved(h, relative_humidity=0.05), len(w)
    (True, 1)
    """
    if groups is None:
        if height is None or relative_humidity is None:
            raise ValueError("give height= and relative_humidity=, or groups= (with neck_pixels).")
        # the moments of every map only (the groups' correlation length would cost 8 x more)
        h, vals, flat, lead, dy, dx, moments = map_moments(height)
        m4 = moments[:, 3]
        rh = as_relative_humidity(relative_humidity)
        rh1 = rh if rh.ndim == 1 else rh.expand_dims(rh=[float(rh.values)])
        hw = np.asarray(water_height(rh1, adsorbed_layer=adsorbed_layer).values, dtype=float)
        neck = xr.DataArray((_neck_radius(hw[None, :], m4[:, None]) / max(dx, dy)).reshape(
            *vals.shape[:-2], hw.size), dims=(*lead, "rh"), coords={"rh": rh1.values})
        spacing = max(dx, dy)
        if generated is None:
            generated = int(height.attrs.get("periodic", 0)) == 1 and "seed" in height.attrs
    else:
        neck = groups["neck_pixels"]
        generated = True if generated is None else generated
    if "rh" not in neck.dims:
        neck = neck.expand_dims(rh=[float(neck["rh"])] if "rh" in neck.coords else [np.nan])
    per_rh = neck.min([d for d in neck.dims if d != "rh"]) if neck.ndim > 1 else neck
    low = per_rh.values < RESOLVED_NECK_PIXELS
    if not low.any():
        return False
    j = int(np.argmin(per_rh.values))
    n = float(per_rh.values[j])
    rh_list = ", ".join(f"{r:g}" for r in neck["rh"].values[low])
    maps = "" if neck.ndim == 1 else (
        f" (the worst of {int(np.prod([neck.sizes[d] for d in neck.dims if d != 'rh']))} maps)")
    pixel = "" if spacing is None else f" ({spacing * 1e9:.3g} nm)"
    warnings.warn(
        f"The pixel{pixel} does not resolve the water necks at RH {rh_list}: the ring wetted "
        f"around a typical summit spans {n:.1f} pixels at RH {float(neck['rh'][j]):g}{maps}, fewer "
        f"than {RESOLVED_NECK_PIXELS:g}. There the pixel sets the adhesive energy as much as the "
        "model does (on measured maps with such necks, Γ moved by more than 10 % at half the "
        "pixel on most; docs/accuracy.md)." + _remedy(n, spacing, generated),
        PixelResolutionWarning,
        stacklevel=external_stacklevel() if stacklevel is None else stacklevel,
    )
    return True


def _remedy(neck_pixels: float, spacing: float | None, generated: bool) -> str:
    """What to do, in the user's spelling: a finer spacing where one can be had (generated
    surfaces above :data:`FINE_PIXEL`), otherwise what the pixel costs, measured."""
    fine = spacing is not None and spacing <= FINE_PIXEL * (1 + 1e-6)  # coordinates' rounding
    if generated and spacing is not None and not fine:
        need = neck_pixels * spacing / RESOLVED_NECK_PIXELS
        return (f" The remedy is a finer pixel for the generated surfaces: {spell('spacing', need)} "
                f"or finer (the neck then spans {RESOLVED_NECK_PIXELS:g} pixels; "
                f"{(spacing / need) ** 2:.1f} x the pixels to compute). What the present pixel "
                f"costs: {spell('resolution')}.")
    if fine:
        return (f" A pixel of {spacing * 1e9:.2g} nm is already about as fine as topography maps "
                "come, so finer data are not to be had: measure what the pixel costs here with "
                f"{spell('resolution')}, and quote Γ with the change it reports.")
    return (f" Measure what the pixel costs here with {spell('resolution')}: where Γ moves more "
            "than you can accept, a scan with finer pixels is the remedy (its finer roughness is "
            "then checked anew); where none can be made, quote Γ with the change it reports.")
