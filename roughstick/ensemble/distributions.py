r"""Distributions of a Monte Carlo sample (Fig. 17): :func:`histogram` (density over ``bin``,
common edges) and :func:`ecdf` (sorted values over ``cumulative_probability``).
Their uncertainty is that of :mod:`.statistics` (quantile intervals, bands)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from .._core.arguments import check_numbers
from .._core.conventions import ATTRS, coord_attrs

__all__ = ["histogram", "ecdf"]


def _inverse_units(units: str) -> str:
    if units in ("1", ""):
        return "1"
    out = []
    for tok in units.split():
        base = tok.rstrip("-0123456789")
        exp = tok[len(base):] or "1"
        e = -int(exp)
        out.append(base if e == 1 else f"{base}{e}")
    return " ".join(out)


def _hist_kernel(a, edges, density):
    a = np.asarray(a, float)
    flat = a.reshape(-1, a.shape[-1])
    res = np.empty((flat.shape[0], edges.size - 1))
    for k, row in enumerate(flat):
        res[k] = np.histogram(row[np.isfinite(row)], bins=edges, density=density)[0] if np.isfinite(row).any() else np.nan
    return res.reshape(a.shape[:-1] + (edges.size - 1,))


@check_numbers(bins="count")
def histogram(da: xr.DataArray, *, dim: str = "realization", bins=30, range=None,
                       density: bool = True) -> xr.DataArray:
    """Histogram along ``dim`` as a labelled DataArray (Fig. 17), one per remaining element.

    The bin edges are common to every element (``range``, or the data's min/max for in-memory
    data), so histograms at different humidities or sizes can be compared directly.

    Parameters
    ----------
    da : xarray.DataArray
        Samples, e.g. ``ds.adhesive_energy`` over ``(realization, rh)``.
    dim : str
    bins : int or sequence of float
        Number of bins or edges (in the units of ``da``).
    range : (float, float), optional
        Required for lazy inputs when ``bins`` is an int (the library does not compute on its own).
    density : bool, default True
        Probability density (units inverse of ``da``'s) instead of counts.

    Returns
    -------
    xarray.DataArray
        Dim ``bin`` with coords ``bin`` (centres), ``bin_lower`` and ``bin_upper``.

    Examples
    --------
    >>> x = xr.DataArray(np.array([0.1, 0.2, 0.2, 0.9]), dims="realization", name="g",
    ...                  attrs={"units": "J m-2", "long_name": "energy"})
    >>> h = rs.ensemble.histogram(x, bins=2, range=(0, 1), density=False)
    >>> h.values, h.attrs["units"]
    (array([3., 1.]), '1')
    """
    if dim not in da.dims:
        raise ValueError(f"{da.name!r} has no dimension {dim!r}.")
    if np.ndim(bins) == 0:
        if range is None:
            if da.chunks is not None:
                raise ValueError("pass range=(lo, hi) for a lazy input (or .compute() it first).")
            vals = np.asarray(da.values, float)
            vals = vals[np.isfinite(vals)]
            if vals.size == 0:
                raise ValueError(f"{da.name!r} holds no finite value to histogram.")
            range = (float(vals.min()), float(vals.max()))
            if range[0] == range[1]:
                range = (range[0] - 0.5 * abs(range[0] or 1), range[1] + 0.5 * abs(range[1] or 1))
        edges = np.linspace(float(range[0]), float(range[1]), int(bins) + 1)
    else:
        edges = np.asarray(bins, float)
    if da.chunks is not None:
        da = da.chunk({dim: -1})
    out = xr.apply_ufunc(
        _hist_kernel, da, kwargs={"edges": edges, "density": density},
        input_core_dims=[[dim]], output_core_dims=[["bin"]], dask="parallelized",
        output_dtypes=[float], dask_gufunc_kwargs={"output_sizes": {"bin": edges.size - 1}},
    )
    units = da.attrs.get("units", "1")
    cattrs = {"units": units}
    out = out.assign_coords(
        bin=("bin", 0.5 * (edges[1:] + edges[:-1]), {**cattrs, "long_name": f"bin centre of {da.attrs.get('long_name', da.name)}"}),
        bin_lower=("bin", edges[:-1], {**cattrs, "long_name": "lower bin edge"}),
        bin_upper=("bin", edges[1:], {**cattrs, "long_name": "upper bin edge"}),
    )
    out.name = f"{da.name}_{'density' if density else 'count'}"
    out.attrs = {
        "units": _inverse_units(units) if density else "1",
        "long_name": f"{'probability density' if density else 'count'} over {dim} of "
                     f"{da.attrs.get('long_name', da.name)}",
    }
    for c in out.coords:
        if c in ATTRS and c not in ("bin",):
            out[c].attrs = coord_attrs(c, out[c])
    return out


def ecdf(da: xr.DataArray, *, dim: str = "realization") -> xr.DataArray:
    r"""Empirical CDF along ``dim`` (Fig. 17): sorted values over ``cumulative_probability``.

    Value ``k`` (0-based) of the result is the :math:`(k+1)`-th smallest sample, where the ECDF
    reaches :math:`(k+1)/n`; plot ``x=values, y=cumulative_probability``. NaN samples sort last.

    Examples
    --------
    >>> x = xr.DataArray([3.0, 1.0, 2.0], dims="realization", name="g",
    ...                  attrs={"units": "J m-2", "long_name": "energy"})
    >>> e = rs.ensemble.ecdf(x)
    >>> e.values, e.cumulative_probability.values
    (array([1., 2., 3.]), array([0.33333333, 0.66666667, 1.        ]))
    """
    if dim not in da.dims:
        raise ValueError(f"{da.name!r} has no dimension {dim!r}.")
    n = da.sizes[dim]
    if da.chunks is not None:
        da = da.chunk({dim: -1})
    out = xr.apply_ufunc(
        np.sort, da, kwargs={"axis": -1}, input_core_dims=[[dim]],
        output_core_dims=[["cumulative_probability"]], dask="parallelized", output_dtypes=[da.dtype],
        dask_gufunc_kwargs={"output_sizes": {"cumulative_probability": n}},
    )
    out = out.assign_coords(cumulative_probability=np.arange(1, n + 1) / n)
    out["cumulative_probability"].attrs = dict(ATTRS["cumulative_probability"])
    out.attrs = dict(da.attrs)
    out.name = da.name
    return out
