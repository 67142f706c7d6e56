"""Reduce force-distance curves of rough surfaces to what decides stiction (Eq. 13).

:func:`adhesion_summary` takes the Dataset of :func:`roughstick.rough_contact_curves` (or of the
Greenwood-Williamson model, same layout) and returns, per humidity and any leading dimension
(e.g. ``realization``), the apparent adhesive energy, the pull-off pressure, the equilibrium
distance and the wetted fraction there.
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from .._core.conventions import append_history, set_attrs
from .._core.validate import check_core_not_chunked

__all__ = ["CurveGridWarning", "adhesion_summary", "adhesion_summary_kernel", "adhesive_energy_kernel"]


class CurveGridWarning(UserWarning):
    """The distance grid of a curve does not span what Eq. 13 integrates (its Γ is incomplete)."""


def _grid_coverage_warning(p, d):
    """Warn when eager curves are all zero (grid above the surface), still attractive at the
    largest distance (separation not reached; beyond 1 % of the largest pressure, so a
    vanishing Gaussian tail does not count) or attractive at the smallest one with no
    equilibrium (grid entirely inside the adhesive range)."""
    p = np.asarray(p, dtype=float).reshape(-1, d.size)
    finite = np.isfinite(p).any(axis=-1)
    problems = []
    if np.any(finite & np.all(np.nan_to_num(p) == 0.0, axis=-1)):
        problems.append(
            "the pressure is zero at every distance (the grid lies entirely above the surface "
            f"and its water, from {d[0]:.3g} m up): Γ = 0 there says nothing about adhesion")
    with np.errstate(invalid="ignore"):
        scale = np.nanmax(np.abs(p), axis=-1)
    if np.any(p[:, -1] < -1e-2 * scale):
        problems.append(
            f"the pressure is still attractive at the largest distance ({d[-1]:.3g} m, over 1 % "
            "of the curve's largest pressure): the grid stops before separation "
            "and Γ misses the rest of the curve")
    cross = (p[:, :-1] >= 0) & (p[:, 1:] < 0)
    if np.any((p[:, 0] < 0) & ~cross.any(axis=-1)):
        problems.append(
            f"the pressure is attractive at the smallest distance ({d[0]:.3g} m) and never "
            "repulsive: the grid lies inside the adhesive range, no equilibrium, Γ is a lower "
            "bound")
    if problems:
        warnings.warn(
            "adhesion_summary: " + "; ".join(problems) + ". Fix: compute the curves on the "
            "automatic grid (distance=None), which spans the surface from above its highest "
            "summit to the equilibrium.",
            CurveGridWarning, stacklevel=3)


def adhesive_energy_kernel(pressure, distance):
    r"""Eq. 13 on a grid: :math:`\Gamma = -\int p\,\mathbf 1(p<0)\,\mathrm dd` [J m-2].

    The pressure is taken piecewise linear between the grid points and its negative part is
    integrated exactly (an interval where ``p`` changes sign contributes the triangle on its
    negative side), so a zero crossing between two points costs no first-order error.

    Parameters
    ----------
    pressure : numpy.ndarray
        Mean pressure [Pa], last axis along ``distance``.
    distance : numpy.ndarray
        Ascending distances [m], 1-D.

    Returns
    -------
    numpy.ndarray
        :math:`\Gamma` >= 0, shape ``pressure.shape[:-1]``.

    Examples
    --------
    >>> float(rs.adhesive_energy_kernel(np.array([0.0, -2.0, 2.0]), np.array([0.0, 1.0, 2.0])))
    1.5
    """
    p = np.asarray(pressure, dtype=float)
    d = np.asarray(distance, dtype=float)
    a, b = p[..., :-1], p[..., 1:]
    w = np.diff(d)
    both = np.where((a <= 0) & (b <= 0), -(a + b) / 2 * w, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        # one end negative: the triangle between the negative end and the zero crossing
        neg = np.minimum(a, b)
        pos = np.maximum(a, b)
        frac = np.where(pos > 0, -neg / (pos - neg), 0.0)
        tri = np.where((neg < 0) & (pos > 0), -neg * frac * w / 2, 0.0)
    return np.sum(both + tri, axis=-1)


def adhesion_summary_kernel(p, wet, d, from_equilibrium=True):
    """:func:`adhesion_summary` on numpy arrays, without checks (for callers that evaluate
    thousands of curves, e.g. :func:`roughstick.failure_probability`).

    Parameters
    ----------
    p, wet : numpy.ndarray
        Mean pressure [Pa] and wet fraction, last axis along ``d``.
    d : numpy.ndarray
        Ascending distances [m], 1-D, at least two.
    from_equilibrium : bool, default True
        As in :func:`adhesion_summary`.

    Returns
    -------
    tuple of numpy.ndarray
        Per curve: adhesive energy [J m-2] (Eq. 13), pull-off pressure [Pa], equilibrium
        distance [m] (NaN if none), wet fraction there, attraction below the equilibrium
        [J m-2]: the variables of :func:`adhesion_summary`, in that order.

    Examples
    --------
    >>> g, pull, deq, weq, below = rs.adhesion_summary_kernel(
    ...     np.array([1.0, -2.0, 0.0]), np.zeros(3), np.array([0.0, 1.0, 2.0]))
    >>> float(deq), float(pull), round(float(g), 3)
    (0.3333333333333333, 2.0, 1.667)
    """
    # equilibrium: the largest d whose interval goes from repulsive (>= 0) below to attractive above
    lower, upper = p[..., :-1], p[..., 1:]
    cross = (lower >= 0) & (upper < 0)
    k = cross.shape[-1] - 1 - np.argmax(cross[..., ::-1], axis=-1)
    found = np.any(cross, axis=-1)
    kk = np.where(found, k, 0)[..., None]
    pl = np.take_along_axis(lower, kk, -1)[..., 0]
    pu = np.take_along_axis(upper, kk, -1)[..., 0]
    frac = np.where(found, pl / np.where(found, pl - pu, 1.0), np.nan)
    d0, d1 = d[kk[..., 0]], d[kk[..., 0] + 1]
    deq = np.where(found, d0 + frac * (d1 - d0), np.nan)
    w0 = np.take_along_axis(wet[..., :-1], kk, -1)[..., 0]
    w1 = np.take_along_axis(wet[..., 1:], kk, -1)[..., 0]
    weq = np.where(found, w0 + frac * (w1 - w0), np.nan)
    # separation path: from the equilibrium outwards. Points at or below the lower end of the
    # crossing interval are clipped to >= 0, so only the attraction above d_eq is integrated
    # (the crossing interval keeps its exact triangle).
    below = np.arange(p.shape[-1]) <= np.where(found, k, -1)[..., None]
    p_sep = np.where(below, np.maximum(p, 0.0), p)
    gamma_all = adhesive_energy_kernel(p, d)
    gamma_sep = adhesive_energy_kernel(p_sep, d)
    with np.errstate(invalid="ignore"):
        pull = np.maximum(-np.nanmin(np.where(np.isnan(p_sep), np.inf, p_sep), axis=-1), 0.0)
    gamma = gamma_sep if from_equilibrium else gamma_all
    return gamma, pull, deq, weq, gamma_all - gamma_sep


def adhesion_summary(curves: xr.Dataset, *, from_equilibrium: bool = True,
                     check_grid: bool = True) -> xr.Dataset:
    r"""Apparent adhesive energy (Eq. 13), pull-off pressure and equilibrium of each curve.

    Parameters
    ----------
    curves : xarray.Dataset
        Output of :func:`roughstick.rough_contact_curves` (or GW): ``pressure`` [Pa] and
        ``wet_fraction`` over ``(..., distance)``; ``distance`` a single dask chunk.
    from_equilibrium : bool, default True
        Integrate Eq. 13 along the separation path only, from the equilibrium distance
        outwards: the work to pull the surfaces apart from where they rest, which is how the
        paper defines the adhesive energy. Deep in contact the modified DMT fits merged
        asperities with huge flat spheres whose Hertz force can fall below the water term, a
        spurious attraction *below* the equilibrium; ``False`` integrates Eq. 13 literally over
        the whole grid, and ``attraction_below_equilibrium`` reports the difference either way.
        The pull-off pressure is taken over the same range.
    check_grid : bool, default True
        Warn (:class:`CurveGridWarning`) when an eager grid never reaches the surface, stops
        before separation or lies inside the adhesive range; ``False`` for callers that extend
        the grid themselves (a ``warnings.catch_warnings`` block is not thread-safe under dask).

    Returns
    -------
    xarray.Dataset
        Over the dims of ``pressure`` but ``distance``:

        - ``adhesive_energy`` [J m-2], :math:`\Gamma^S = -\int p\,\mathbf 1(p<0)\,\mathrm dd`
          (Eq. 13), >= 0, integrated exactly on the piecewise-linear curve;
        - ``pull_off_pressure`` [Pa], the magnitude of the most tensile pressure, >= 0;
        - ``equilibrium_distance`` [m], the largest ``d`` where the pressure changes from
          repulsive below to attractive above (linear interpolation); NaN when the grid never
          reaches a repulsive state (then :math:`\Gamma` is a lower bound);
        - ``wet_fraction_at_equilibrium``, interpolated at that distance (Fig. 11b);
        - ``attraction_below_equilibrium`` [J m-2], the attractive work below the equilibrium
          distance (0 on a well-behaved curve; large values mean the grid reaches deep into the
          regime where the modified DMT breaks down).

    Raises
    ------
    ValueError
        If ``distance`` is missing or split over several dask chunks.

    Examples
    --------
    >>> h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    >>> c = rs.rough_contact_curves(h, relative_humidity=0.5, distance=np.linspace(-3e-9, 3e-9, 61))
    >>> s = rs.adhesion_summary(c)
    >>> bool(s.adhesive_energy > 0), bool(s.equilibrium_distance < c.max_interference.distance.max())
    (True, True)
    """
    if "pressure" not in curves or "distance" not in curves["pressure"].dims:
        raise ValueError(
            "curves must hold 'pressure' over a 'distance' dimension, as returned by "
            "roughstick.rough_contact_curves."
        )
    p = curves["pressure"]
    check_core_not_chunked(p, ["distance"])
    wet = curves["wet_fraction"] if "wet_fraction" in curves else xr.full_like(p, np.nan)
    d = np.asarray(curves["distance"].values, dtype=float)  # coordinate: eager
    order = np.argsort(d)
    if not np.array_equal(order, np.arange(d.size)):
        p = p.isel(distance=order)
        wet = wet.isel(distance=order)
        d = d[order]
    if d.size < 2:
        raise ValueError("curves need at least two distances to integrate Eq. 13.")
    outs = xr.apply_ufunc(
        adhesion_summary_kernel,
        p,
        wet,
        kwargs={"d": d, "from_equilibrium": bool(from_equilibrium)},
        input_core_dims=[["distance"], ["distance"]],
        output_core_dims=[[], [], [], [], []],
        dask="parallelized",
        output_dtypes=[float] * 5,
    )
    names = [
        ("adhesive_energy", "surface_adhesive_energy"),
        ("pull_off_pressure", "pull_off_pressure"),
        ("equilibrium_distance", "equilibrium_distance"),
        ("wet_fraction_at_equilibrium", "wet_fraction_at_equilibrium"),
        ("attraction_below_equilibrium", "attraction_below_equilibrium"),
    ]
    if check_grid and not hasattr(p.data, "dask"):
        _grid_coverage_warning(p.values, d)
    ds = xr.Dataset({name: set_attrs(o, key) for (name, key), o in zip(names, outs, strict=True)})
    drop = [c for c in ds.coords if "distance" in ds[c].dims]
    ds = ds.drop_vars(drop)
    ds.attrs = dict(curves.attrs)
    ds.attrs["title"] = "adhesion summary (Eq. 13) of " + str(curves.attrs.get("title", "contact curves"))
    ds.attrs["adhesive_energy_range"] = "from_equilibrium" if from_equilibrium else "whole_grid"
    append_history(
        ds,
        "adhesion_summary: Eq. 13 on the piecewise-linear pressure "
        + ("from the equilibrium outwards" if from_equilibrium else "over the whole grid")
        + ", pull-off, equilibrium",
    )
    return ds
