r"""Does an ensemble contain the measured maps it was built from?

An ensemble built from the PSD (and height distribution) of measured maps claims to describe
surfaces like them, and the maps are themselves samples of that population. So each map's own
summary (one set of curves per map: the same contact model, humidities, material and adsorbed
layer as the ensemble, on the map's own automatic distance grid; of a map larger than the
surfaces, its centre at their size, so that like is compared with like and a map costs one
realization) is placed in the ensemble's distribution of the same summary, by its mid-rank
percentile

.. math::

    P = 100\,\frac{\#\{k : \Gamma_k < \Gamma_\mathrm{map}\} + \tfrac12\,\#\{k : \Gamma_k =
    \Gamma_\mathrm{map}\}}{n}.

A map outside the ensemble's central ``confidence`` band (the band of
:func:`roughstick.ensemble.confidence_band`) is a :class:`ContainmentWarning` naming the likely
causes the run's parameters show (Gaussian surfaces for non-Gaussian maps, surfaces larger or
smaller than the maps, another pixel) and their remedies.
"""

from __future__ import annotations

import pathlib
import warnings

import numpy as np
import xarray as xr

from .._core.arguments import check_numbers
from .._core.remedy import spell
from .._core.validate import external_stacklevel
from ..contact import summary as contact_summary
from ..surface.compatibility import warn_if_incompatible
from ..surface.distribution import height_distribution as _measured_distribution
from ..surface.gaussianity import is_gaussian
from ..surface.topography import level, level_unless_periodic, validate_height

__all__ = ["map_containment", "ContainmentWarning"]

#: The summaries of each map kept in the ensemble (``map_<name>``); percentiles of the first.
MAP_SUMMARIES = ("adhesive_energy", "pull_off_pressure", "equilibrium_distance")


class ContainmentWarning(UserWarning):
    """A measured map's own summary lies outside the band of the ensemble built from it."""


def as_maps(maps) -> list:
    """Measured maps as a list of 2-D DataArrays named ``map_name``, levelled by a plane unless
    periodic (a stack ``(..., y, x)`` is split along its leading dims; names from
    ``attrs['source']`` or the position)."""
    if isinstance(maps, xr.DataArray):
        h = validate_height(maps)
        lead = [d for d in h.dims if d not in ("y", "x")]
        stacked = h.stack(_map=lead) if lead else h.expand_dims(_map=[0])
        maps = [stacked.isel(_map=i, drop=True).assign_attrs(h.attrs) for i in range(stacked.sizes["_map"])]
    elif not isinstance(maps, (list, tuple)) or not maps:
        raise TypeError("maps must be a height map DataArray (..., y, x) or a non-empty list of "
                        f"2-D height maps, got {type(maps).__name__}.")
    out = []
    for i, m in enumerate(maps):
        m = level_unless_periodic(m)
        if m.ndim != 2:
            raise ValueError("each measured map must be 2-D (y, x); pass a stack as one DataArray.")
        name = pathlib.Path(str(m.attrs.get("source", ""))).name or f"map {i}"
        out.append(m.assign_attrs(map_name=name))
    warn_if_incompatible(out, [m.attrs["map_name"] for m in out])  # one surface's maps?
    return out


def resolve_height_distribution(choice, maps):
    """``(distribution or None, maps_gaussian or None, why)`` for ``run(height_distribution=)``:
    ``"auto"`` is the maps' own distribution when they are not Gaussian within their sampling
    error (:func:`roughstick.surface.is_gaussian`), else Gaussian (and Gaussian without maps)."""
    if choice is None or (isinstance(choice, str) and choice == "gaussian"):
        return None, None, "Gaussian heights (asked for)"
    if isinstance(choice, xr.Dataset):
        return choice, None, f"the given {choice.attrs.get('family', '')} height distribution"
    if choice not in ("auto", "maps"):
        raise ValueError("height_distribution must be 'auto', 'maps', 'gaussian', None or a Dataset "
                         f"of rs.surface.height_distribution, got {choice!r}.")
    if maps is None:
        if choice == "maps":
            raise ValueError("height_distribution='maps' needs the measured maps: pass maps=.")
        return None, None, "Gaussian heights (no measured maps given)"
    gaussian = is_gaussian(list(maps))
    if choice == "auto" and gaussian:
        return None, True, "Gaussian heights: the maps are Gaussian within their sampling error"
    why = ("the maps' own height distribution" + ("" if choice == "maps" else
                                                 ": they are not Gaussian within their sampling error"))
    return _measured_distribution(list(maps)), gaussian, why


def compared(maps: list, shape, spacing: float) -> tuple[list, str]:
    """The part of each map compared with the surfaces: its centre at the surfaces' size when the
    map is larger (same pixel), so that like is compared with like and a map costs one
    realization; else the whole map."""
    out, what = [], "the whole maps"
    for m in maps:
        same_pixel = abs(float(m.attrs["spacing_x"]) / spacing - 1) < 1e-6
        ny, nx = min(m.sizes["y"], shape[0]), min(m.sizes["x"], shape[1])
        if same_pixel and (ny, nx) != (m.sizes["y"], m.sizes["x"]):
            y0, x0 = (m.sizes["y"] - ny) // 2, (m.sizes["x"] - nx) // 2
            m = level(m.isel(y=slice(y0, y0 + ny), x=slice(x0, x0 + nx)), method="plane").assign_attrs(
                map_name=m.attrs["map_name"])
            what = f"the central {ny} x {nx} pixels of each map (the surfaces' size)"
        out.append(m)
    return out, what


def map_summaries(maps: list, *, relative_humidity, curves, summary, curves_kwargs, material,
                  adsorbed_layer) -> xr.Dataset:
    """Each map's summaries over ``(map, rh)``: one call of ``curves`` per map (every humidity,
    the model's automatic distance grid), then ``summary``."""
    parts = []
    for m in maps:
        c = curves(m, relative_humidity=relative_humidity, distance=None, material=material,
                   adsorbed_layer=adsorbed_layer, **curves_kwargs)
        s = summary(c, check_grid=False) if summary is contact_summary else summary(c)
        keep = [v for v in MAP_SUMMARIES if v in s]
        parts.append(s[keep].drop_vars([c for c in s.coords if c != "rh"], errors="ignore"))
    names = [m.attrs["map_name"] for m in maps]
    own = xr.concat(parts, dim="map", combine_attrs="drop_conflicts").assign_coords(map=names)
    own["map"].attrs = {"long_name": "measured map the ensemble was built from"}
    return own


def attach(ds: xr.Dataset, own: xr.Dataset, maps: list, info: dict) -> xr.Dataset:
    """The maps' summaries as ``map_<name>`` over ``(map, rh)``, the percentile of each map's
    Γ in the ensemble (``map_percentile``, lazy with a lazy ensemble) and what the run knows
    about the (whole) maps in ``attrs``."""
    ds = ds.copy()
    for v in own.data_vars:
        ds[f"map_{v}"] = own[v].assign_attrs(own[v].attrs, long_name="the measured map's own "
                                             + own[v].attrs.get("long_name", v))
    ds["map_percentile"] = _percentile(ds["adhesive_energy"], own["adhesive_energy"])
    sizes = [(m.sizes["y"] * m.attrs["spacing_y"], m.sizes["x"] * m.attrs["spacing_x"]) for m in maps]
    ds.attrs.update(
        maps=", ".join(m.attrs["map_name"] for m in maps),
        maps_size_m=float(max(max(s) for s in sizes)),
        maps_spacing_m=float(np.mean([m.attrs["spacing_x"] for m in maps])),
        **{k: v for k, v in info.items() if v is not None})
    return ds


def _percentile(ensemble: xr.DataArray, value: xr.DataArray) -> xr.DataArray:
    valid = ensemble.notnull()
    below = ((ensemble < value) & valid).sum("realization")
    equal = ((ensemble == value) & valid).sum("realization")
    p = 100 * (below + 0.5 * equal) / valid.sum("realization")
    return p.transpose("map", "rh").assign_attrs(
        units="%", long_name="percentile of the measured map's own adhesive energy in the ensemble")


def _causes(attrs: dict) -> list[tuple[str, str]]:
    """(likely cause, remedy) pairs the run's parameters point to."""
    out = []
    if attrs.get("height_distribution", "gaussian") == "gaussian" and attrs.get("maps_gaussian") == 0:
        out.append(("the surfaces are Gaussian but the maps' heights are not (their skewness, "
                    "kurtosis or tallest summits are outside a Gaussian's sampling error)",
                    spell("height_distribution", "maps")))
    size = float(np.max(json_list(attrs.get("surface_size_m", "[0]"))))
    maps_size = float(attrs.get("maps_size_m", size))
    if size > maps_size * (1 + 1e-6):
        out.append((f"the surfaces ({size * 1e6:.3g} µm) are larger than the maps "
                    f"({maps_size * 1e6:.3g} µm): their PSD below the maps' lowest wave number is "
                    "extrapolated", spell("surface_size", maps_size)))
    elif size < maps_size * (1 - 1e-6) and "whole" in attrs.get("maps_compared", "whole"):
        out.append((f"the surfaces ({size * 1e6:.3g} µm) are smaller than the maps "
                    f"({maps_size * 1e6:.3g} µm): Γ of a smaller area has a wider spread and "
                    "lower tallest summits", spell("surface_size", maps_size)))
    spacing, maps_spacing = float(attrs.get("spacing_m", 0)), float(attrs.get("maps_spacing_m", 0))
    if maps_spacing and abs(spacing / maps_spacing - 1) > 1e-6:
        out.append((f"the surfaces' pixel ({spacing * 1e9:.3g} nm) is not the maps' "
                    f"({maps_spacing * 1e9:.3g} nm)", spell("spacing", maps_spacing)))
    return out


def json_list(text) -> list:
    """A JSON list attribute (e.g. ``surface_size_m``) as a list of floats."""
    if isinstance(text, str):
        return [float(v) for v in text.strip("[]").split(",") if v.strip()]
    return list(np.atleast_1d(text))


@check_numbers(confidence="fraction")
def map_containment(ensemble: xr.Dataset, *, confidence: float = 0.95, warn: bool = True) -> xr.Dataset:
    """Where the measured maps' own Γ fall in the ensemble built from them (module docstring).

    Parameters
    ----------
    ensemble : xarray.Dataset
        A :func:`run` result with ``maps=`` (variables ``map_adhesive_energy`` and
        ``adhesive_energy``); computed here if lazy.
    confidence : float, default 0.95
        The central band a map should fall in.
    warn : bool, default True
        Give a :class:`ContainmentWarning` for each map outside the band.

    Returns
    -------
    xarray.Dataset
        ``map_percentile`` [%] and ``inside`` (bool) over ``(map, rh)``, the band's edges
        ``band_lower``/``band_upper`` over ``rh`` [J m-2]; attrs ``causes``.

    Examples
    --------
    >>> g = xr.DataArray(np.linspace(1e-3, 2e-3, 40)[:, None], dims=("realization", "rh"),
    ...                  coords={"rh": [0.7]})
    >>> own = xr.DataArray([[1.5e-3], [9e-3]], dims=("map", "rh"), coords={"map": ["a", "b"], "rh": [0.7]})
    >>> ds = xr.Dataset({"adhesive_energy": g, "map_adhesive_energy": own})
    >>> rs.ensemble.map_containment(ds, warn=False).map_percentile.values.ravel()
    array([ 50., 100.])
    """
    if "map_adhesive_energy" not in ensemble:
        raise ValueError("the ensemble has no measured maps' summaries (map_adhesive_energy): "
                         "run it with roughstick.ensemble.run(..., maps=maps).")
    g = ensemble["adhesive_energy"].load()
    own = ensemble["map_adhesive_energy"].load()
    lo, hi = ((1 - confidence) / 2, (1 + confidence) / 2)
    edges = g.quantile([lo, hi], dim="realization").drop_vars("quantile")
    inside = (own >= edges.isel(quantile=0)) & (own <= edges.isel(quantile=1))
    out = xr.Dataset({"map_percentile": _percentile(g, own),
                      "inside": inside.transpose("map", "rh").assign_attrs(
                          long_name=f"the map's own adhesive energy lies in the {confidence:.0%} band"),
                      "band_lower": edges.isel(quantile=0).assign_attrs(units="J m-2"),
                      "band_upper": edges.isel(quantile=1).assign_attrs(units="J m-2")})
    causes = _causes(ensemble.attrs)
    out.attrs["causes"] = "; ".join(f"{c} (remedy: {r})" for c, r in causes) or "none of the run's parameters"
    if warn:
        _warn_outside(out, own, confidence, causes, ensemble.sizes.get("realization", 0))
    return out


def _warn_outside(out, own, confidence, causes, n) -> None:
    for name in out["map"].values:
        miss = ~out["inside"].sel(map=name)
        if not bool(miss.any()):
            continue
        rh = out["rh"].values[miss.values]
        parts = [f"RH {r:.2g}: Γ = {float(own.sel(map=name, rh=r)) * 1e3:.3g} mJ/m² at percentile "
                 f"{float(out.map_percentile.sel(map=name, rh=r)):.0f} (band "
                 f"{float(out.band_lower.sel(rh=r)) * 1e3:.3g}-{float(out.band_upper.sel(rh=r)) * 1e3:.3g})"
                 for r in rh]
        why = ("; ".join(f"{c}: {r}" for c, r in causes) if causes else
               "none of the usual causes (heights, size, pixel) applies to this run: the maps hold a "
               "feature that neither their PSD nor their height distribution describes (anisotropy, "
               "non-stationarity, tall isolated particles), or the band of "
               f"n = {n} surfaces is too narrow")
        warnings.warn(f"the measured map {str(name)!r} lies outside the {confidence:.0%} band of the "
                      f"ensemble built from it, at {'; '.join(parts)}. Likely cause and remedy: {why}.",
                      ContainmentWarning, stacklevel=external_stacklevel())
