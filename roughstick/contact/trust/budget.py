"""The error budget of the summaries of a set of curves: model, distance grid and pixel.

Each summary (Γ of Eq. 13, the pull-off pressure, the equilibrium distance) of
:func:`roughstick.contact.summary` carries, per humidity, in its attributes:

- ``model_error_bound``: the measured upper bound of its relative error against the
  boundary-element reference at this surface's dimensionless groups (:func:`model_error`, the
  validity map; 0 for the reference itself, ``inf`` where the measurements do not bound it);
- ``grid_error_estimate``: the relative change of the summary when every second point of the
  distance grid is dropped (for a converging grid, an upper estimate of the grid's own error);
and :func:`error_budget` gathers them into one Dataset (``roughstick curves`` prints it), with
the pixel's part from a :func:`roughstick.contact.resolution_study` of the same map when one is
given: the relative change at half the pixel (band-limited interpolation, which adds no
roughness: what the model's discretisation costs at the present pixel). The pixel check of the
pipeline says where it matters (:class:`roughstick.contact.PixelResolutionWarning`).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .validity import _QUANTITIES, _group_points, model_error

__all__ = ["error_budget"]

#: The attribute of each summary variable holding each part of the budget.
PARTS = {"model": "model_error_bound", "grid": "grid_error_estimate",
         "pixel": "pixel_error_estimate"}


def _finer_pixel_change(study: xr.Dataset, quantity: str):
    """Largest |relative change| of ``quantity`` at the pixels finer than the native one in a
    resolution study, per humidity (None: the study has no finer pixel)."""
    name = f"relative_change_{quantity}"
    native = study.attrs.get("native_pixel_size")
    if name not in study or native is None or not bool((study["pixel_size"] < native).any()):
        return None
    finer = study[name].sel(pixel_size=study["pixel_size"] < native)
    lead = [d for d in finer.dims if d != "rh"]
    return np.atleast_1d(np.abs(finer).max(lead, skipna=True).values)


def model_bounds(model: str, height, *, relative_humidity, material, material2,
                 adsorbed_layer, groups: xr.Dataset | None = None) -> dict[str, list[float]]:
    """``{quantity: [bound per humidity]}``: the largest measured upper bound over the maps
    (or over the given ``groups``, e.g. those expected from a PSD)."""
    points = _group_points(height, relative_humidity, material, material2, adsorbed_layer, groups)
    return {q: [max(model_error(model, gr, quantity=q).upper for gr in maps) for _, maps in points]
            for q in _QUANTITIES}


def error_budget(summary: xr.Dataset, resolution: xr.Dataset | None = None) -> xr.Dataset:
    """The error budget of a summary: one relative error per part, quantity and humidity.

    Parameters
    ----------
    summary : xarray.Dataset
        As returned by :func:`roughstick.contact.summary` (its variables' attributes hold the
        model and grid parts, see the module docstring).
    resolution : xarray.Dataset, optional
        :func:`roughstick.contact.resolution_study` of the same map at the same humidities with
        a factor below 1: the pixel part is the largest relative change at the factors below 1.

    Returns
    -------
    xarray.Dataset
        Variables ``model`` (measured bound), ``grid`` and ``pixel`` (estimates; NaN where not
        estimated) and ``total`` (their sum, NaN parts left out) over ``(quantity, rh)``, as
        relative errors (1 = 100 %).

    Examples
    --------
    >>> h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    >>> s = rs.contact.summary(rs.contact.curves(h, relative_humidity=[0.5], model="fft_bem"))
    >>> b = rs.contact.error_budget(s)
    >>> b.grid.dims, bool((b.grid >= 0).all())
    (('quantity', 'rh'), True)
    """
    quantities = [q for q in _QUANTITIES if q in summary]
    rh = summary["rh"] if "rh" in summary.dims else None
    n = 1 if rh is None else summary.sizes["rh"]
    data = {}
    for part, attr in PARTS.items():
        rows = []
        for q in quantities:
            v = summary[q].attrs.get(attr)
            if part == "pixel" and resolution is not None:
                v = _finer_pixel_change(resolution, q)
            rows.append(np.full(n, np.nan) if v is None else np.broadcast_to(np.asarray(v, float), (n,)))
        data[part] = (("quantity", "rh"), np.array(rows, dtype=float).reshape(len(quantities), n))
    ds = xr.Dataset(data, coords={"quantity": quantities,
                                  "rh": rh.values if rh is not None else [np.nan]})
    ds["total"] = ds["model"].fillna(0) + ds["grid"].fillna(0) + ds["pixel"].fillna(0)
    for v in ds.data_vars:
        ds[v].attrs = {"units": "1", "long_name": f"{v} part of the relative error"
                       if v != "total" else "sum of the parts of the relative error"}
    return ds
