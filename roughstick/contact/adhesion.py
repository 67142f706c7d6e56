"""Reduce force-distance curves of rough surfaces to what decides stiction (Eq. 13).

:func:`summary` takes the Dataset of :func:`roughstick.contact.curves` (or of the
Greenwood-Williamson model, same layout) and returns, per humidity and any leading dimension
(e.g. ``realization``), the apparent adhesive energy, the pull-off pressure, the equilibrium
distance and the wetted fraction there.
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from .._core.conventions import append_history, set_attrs
from .._core.remedy import spell
from .._core.validate import check_core_not_chunked

__all__ = ["CurveGridWarning", "summary"]


class CurveGridWarning(UserWarning):
    """The distance grid of a curve does not span what Eq. 13 integrates (its Γ is incomplete)."""


def equilibrium_crossings(p: np.ndarray) -> np.ndarray:
    """Intervals of a curve (pressure ``p`` along ascending distance, last axis) where it goes
    from repulsive below to attractive above: the candidates for the equilibrium of Eq. 13.

    A zero counts as repulsive only where the last non-zero pressure below it is repulsive (or
    there is none): a state that lost all contact and water has exactly zero pressure, and a
    neck caught again just above it is not an equilibrium.

    >>> equilibrium_crossings(np.array([1.0, 0.0, -1.0, 0.0, -2.0, 0.0])).tolist()
    [False, True, False, False, False]
    """
    p = np.asarray(p, dtype=float)
    n = p.shape[-1]
    nonzero = (p != 0) & ~np.isnan(p)
    last = np.maximum.accumulate(np.where(nonzero, np.arange(n), -1), axis=-1)
    repulsive = np.where(last >= 0, np.take_along_axis(p, np.maximum(last, 0), -1) > 0, True)
    with np.errstate(invalid="ignore"):
        return (p[..., :-1] >= 0) & repulsive[..., :-1] & (p[..., 1:] < 0)


def _rh_label(p: xr.DataArray, bad: np.ndarray) -> str:
    """' at RH 0.3, 0.9' for the offending curves (``bad`` over the flattened leading dims)."""
    if "rh" not in p.coords:
        return ""
    lead = [dim for dim in p.dims if dim != "distance"]
    rh = p["rh"].broadcast_like(p.isel(distance=0, drop=True)).transpose(*lead)
    vals = np.unique(np.asarray(rh.values, dtype=float).reshape(-1)[bad])
    return " at RH " + ", ".join(f"{v:.3g}" for v in vals) if vals.size else ""


def _fmt(x: float) -> str:
    return f"{x:.3g}"


def _grid_coverage_warning(p: xr.DataArray, d: np.ndarray, attrs: dict) -> None:
    """Warn when eager curves do not span what Eq. 13 integrates, with a fix for the situation.

    Checked per curve: all zero (grid above the surface); still attractive at the largest
    distance (separation not reached; beyond 1 % of the largest pressure, so a vanishing
    Gaussian tail does not count); attractive at the smallest one with no equilibrium (grid
    entirely inside the adhesive range); repulsive at the largest distance, either with no
    equilibrium (grid entirely below it: Γ = 0 says nothing) or by over 1 % of the largest
    pressure (still in contact at the top). The remedy depends on whether the distance grid was
    given or automatic (``attrs["distance_grid"]``, set by the models).
    """
    lead = [dim for dim in p.dims if dim != "distance"]
    v = np.asarray(p.transpose(*lead, "distance").values, dtype=float).reshape(-1, d.size)
    finite = np.isfinite(v).any(axis=-1)
    with np.errstate(invalid="ignore"):
        scale = np.nanmax(np.abs(v), axis=-1)
    cross = equilibrium_crossings(v).any(axis=-1)
    grid = attrs.get("distance_grid")
    model = str(attrs.get("contact_model", "the model"))
    span = float(d[-1] - d[0])
    n = d.size
    higher = f"distance=np.linspace({_fmt(d[0])}, {_fmt(d[-1] + span)}, {2 * n})"
    lower = f"distance=np.linspace({_fmt(d[0] - span)}, {_fmt(d[-1])}, {2 * n})"
    problems = []

    def remedy(given: str, automatic: str) -> str:
        if grid == "given":
            return given
        if grid == "automatic":
            return automatic
        return f"If the distances were given: {given}. If they were automatic: {automatic}"

    bad = finite & np.all(np.nan_to_num(v) == 0.0, axis=-1)
    if bad.any():
        problems.append(
            f"the pressure is zero at every distance{_rh_label(p, bad)} (the grid lies entirely "
            f"above the surface and its water, from {_fmt(d[0])} m up): Γ = 0 there says nothing "
            "about adhesion. " + remedy(
                "Compute the curves on the automatic grid (distance=None), which starts above "
                "the first water contact, or give distances reaching down to the surface, e.g. "
                + lower,
                f"The automatic grid of {model} found no force at all: its water height or "
                "capillary pressure vanishes at this humidity (or the model has none, e.g. "
                "sphere_model='hertz'), so the model itself predicts no adhesion there"))
    bad = p_att = v[:, -1] < -1e-2 * scale
    if bad.any():
        problems.append(
            f"the pressure is still attractive at the largest distance ({_fmt(d[-1])} m, over "
            f"1 % of the curve's largest pressure){_rh_label(p, bad)}: the grid stops before "
            "separation and Γ misses the rest of the curve. " + remedy(
                "Compute the curves on the automatic grid (distance=None), which starts above "
                "the first water contact, or extend the distances upwards, e.g. " + higher,
                f"The automatic grid of {model} did not reach separation: pass an explicit "
                "grid reaching higher, e.g. " + higher))
    bad = (v[:, 0] < 0) & ~cross
    if bad.any():
        problems.append(
            f"the pressure is attractive at the smallest distance ({_fmt(d[0])} m) and never "
            f"repulsive{_rh_label(p, bad)}: the grid lies inside the adhesive range, no "
            "equilibrium, Γ is a lower bound. " + remedy(
                "Compute the curves on the automatic grid (distance=None), which reaches past "
                "the equilibrium, or extend the distances downwards, e.g. " + lower,
                f"The automatic grid of {model} already reaches its lowest meaningful distance "
                "(for the modified DMT the lowest pixel, where the whole map touches) and finds "
                "no equilibrium: the surfaces collapse into full contact, which a very smooth or "
                "flat map, a soft material or a very low humidity can cause; the model (rigid "
                "asperities, Hertz per asperity) is outside its range there"
                + (f": use {spell('contact_model', 'fft_bem')}" if model in ("modified_dmt", "gw")
                   else "") + "; widen the grid only to inspect the curve, e.g. " + lower))
    with np.errstate(invalid="ignore"):
        bad = (v[:, -1] > 0) & (~cross | (v[:, -1] > 1e-2 * scale)) & ~p_att
    if bad.any():
        problems.append(
            f"the pressure is still repulsive at the largest distance ({_fmt(d[-1])} m)"
            f"{_rh_label(p, bad)}: the grid stops in contact, below "
            + ("the equilibrium (the pressure is never attractive on it), so Γ = 0 and the NaN "
               "equilibrium distance say nothing about adhesion" if (~cross[bad]).all() else
               "separation, so Γ and the equilibrium miss the curve above it") + ". " + remedy(
                "Compute the curves on the automatic grid (distance=None), which starts above "
                "the first water contact, or extend the distances upwards, e.g. " + higher,
                f"The automatic grid of {model} stops in contact: pass an explicit grid reaching "
                "higher, e.g. " + higher + " (or a larger n_distance)"))
    if problems:
        warnings.warn("roughstick.contact.summary: " + "; ".join(problems) + ".", CurveGridWarning,
                      stacklevel=3)


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
    >>> from roughstick.contact.adhesion import adhesive_energy_kernel
    >>> float(adhesive_energy_kernel(np.array([0.0, -2.0, 2.0]), np.array([0.0, 1.0, 2.0])))
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


def summary_kernel(p, wet, d, from_equilibrium=True):
    """:func:`summary` on numpy arrays, without checks (for callers that evaluate
    thousands of curves, e.g. :func:`roughstick.reliability.failure_probability`).

    Parameters
    ----------
    p, wet : numpy.ndarray
        Mean pressure [Pa] and wet fraction, last axis along ``d``.
    d : numpy.ndarray
        Ascending distances [m], 1-D, at least two.
    from_equilibrium : bool, default True
        As in :func:`summary`.

    Returns
    -------
    tuple of numpy.ndarray
        Per curve: adhesive energy [J m-2] (Eq. 13), pull-off pressure [Pa], equilibrium
        distance [m] (NaN if none), wet fraction there, attraction below the equilibrium
        [J m-2]: the variables of :func:`summary`, in that order.

    Examples
    --------
    >>> from roughstick.contact.adhesion import summary_kernel
    >>> g, pull, deq, weq, below = summary_kernel(
    ...     np.array([1.0, -2.0, 0.0]), np.zeros(3), np.array([0.0, 1.0, 2.0]))
    >>> float(deq), float(pull), round(float(g), 3)
    (0.3333333333333333, 2.0, 1.667)
    """
    # equilibrium: the largest d whose interval goes from repulsive below to attractive above
    lower, upper = p[..., :-1], p[..., 1:]
    cross = equilibrium_crossings(p)
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


def summary(curves: xr.Dataset, *, from_equilibrium: bool = True,
                     check_grid: bool = True) -> xr.Dataset:
    r"""Apparent adhesive energy (Eq. 13), pull-off pressure and equilibrium of each curve.

    Parameters
    ----------
    curves : xarray.Dataset
        Output of :func:`roughstick.contact.curves` (or GW): ``pressure`` [Pa] and
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
        before separation (still attractive, or still repulsive, at its largest distance) or
        lies inside the adhesive range, naming the humidities and a remedy that depends on
        whether the grid was given or automatic (``curves.attrs["distance_grid"]``, set by the
        models); ``False`` for callers that extend the grid themselves (a
        ``warnings.catch_warnings`` block is not thread-safe under dask).

    Returns
    -------
    xarray.Dataset
        Over the dims of ``pressure`` but ``distance``:

        - ``adhesive_energy`` [J m-2], :math:`\Gamma^S = -\int p\,\mathbf 1(p<0)\,\mathrm dd`
          (Eq. 13), >= 0, integrated exactly on the piecewise-linear curve;
        - ``pull_off_pressure`` [Pa], the magnitude of the most tensile pressure, >= 0;
        - ``equilibrium_distance`` [m], the largest ``d`` where the pressure changes from
          repulsive below to attractive above (linear interpolation); NaN when the grid holds
          no such change: either it never reaches a repulsive state (attractive down to its
          smallest distance: the grid lies inside the adhesive range, or the model collapses
          into full contact; :math:`\Gamma` is then a lower bound), or it never reaches an
          attractive one (repulsive up to its largest distance: the equilibrium lies above the
          grid and :math:`\Gamma = 0` says nothing), or the curve has no attraction at all
          (e.g. ``sphere_model="hertz"``, or zero everywhere). Each grid case warns
          (:class:`CurveGridWarning`) when ``check_grid``;
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
    >>> c = rs.contact.curves(h, relative_humidity=0.5, distance=np.linspace(-3e-9, 3e-9, 61))
    >>> s = rs.contact.summary(c)
    >>> bool(s.adhesive_energy > 0), bool(s.equilibrium_distance < c.max_interference.distance.max())
    (True, True)
    """
    if "pressure" not in curves or "distance" not in curves["pressure"].dims:
        raise ValueError(
            "curves must hold 'pressure' over a 'distance' dimension, as returned by "
            "roughstick.contact.curves."
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
        summary_kernel,
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
        _grid_coverage_warning(p, d, curves.attrs)
    ds = xr.Dataset({name: set_attrs(o, key) for (name, key), o in zip(names, outs, strict=True)})
    drop = [c for c in ds.coords if "distance" in ds[c].dims]
    ds = ds.drop_vars(drop)
    ds.attrs = dict(curves.attrs)
    ds.attrs["title"] = "adhesion summary (Eq. 13) of " + str(curves.attrs.get("title", "contact curves"))
    ds.attrs["adhesive_energy_range"] = "from_equilibrium" if from_equilibrium else "whole_grid"
    append_history(
        ds,
        "roughstick.contact.summary: Eq. 13 on the piecewise-linear pressure "
        + ("from the equilibrium outwards" if from_equilibrium else "over the whole grid")
        + ", pull-off, equilibrium",
    )
    return ds
