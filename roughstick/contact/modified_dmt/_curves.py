"""Adhesive contact of a rough surface against a flat in humid air: the modified DMT (Eqs. 16-23).

:func:`modified_dmt_curves` takes any ``height`` map (measured or generated) and returns the
mean pressure on the apparent area versus the distance ``d`` between the flat and the mean plane
of the heights, at one or several relative humidities. Asperities are the connected components of
``{z >= d}`` (the paper's flooding); each is fitted with the constrained sphere of Eqs. 19-21 and
Hertz (Eqs. 10-11) gives its repulsive force and contact area; the water term uses the area of
the whole map above ``d - h_water``, so merged menisci (saturation) come out naturally (Eq. 16).

All distances are done in one pass over the heights sorted in descending order, with a
union-find (:mod:`roughstick.contact._rough_kernels`); a literal slow implementation that relabels
the map at every distance and fits each asperity with a generic optimiser lives in
:mod:`roughstick.contact._rough_reference` and the tests hold the two together. The public entry
that chooses between this model, Greenwood-Williamson and the BEM is
:func:`roughstick.rough_contact_curves` (:mod:`roughstick.contact.curves`). See
``docs/rough_contact.md`` for the algorithm, its cost and the accuracy evidence.
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from ..._core.arguments import check_numbers
from ..._core.conventions import ATTRS, append_history, dataset_attrs, set_attrs
from ..._core.dask import is_lazy
from ..._core.materials import POLYSILICON, hertz_modulus, reduced_modulus
from ..._core.memory import check_map_fits_in_memory
from ..._core.references import PAPER, cite
from ..._core.remedy import spell
from ..._core.validate import (
    MIN_MAP_PIXELS,
    ValidityWarning,
    check_core_not_chunked,
    check_has_roughness,
    distance_array,
    external_stacklevel,
    grid_spacing,
    height_in_si,
    relative_humidity_coordinate,
)
from . import _controller as _k
from ..adhesion import adhesion_summary_kernel
from ..meniscus import laplace_pressure, water_height

__all__ = ["modified_dmt_curves", "modified_dmt_kernel", "contact_distance_grid"]

REFERENCES = cite((PAPER, "section 3.3, Eqs. 16-23"), "johnson1985")

_MISSING_NOTE = (
    "heights referred to their mean over the valid pixels; NaN pixels are excluded: never part of "
    "an asperity nor of the wetted area, and the apparent area is that of the valid pixels"
)


# --------------------------------------------------------------------------------------------
# input checks


def _spacing(height: xr.DataArray, dim: str) -> float:
    return grid_spacing(height, dim, min_pixels=MIN_MAP_PIXELS, purpose="a contact map")


def _connectivity(connectivity):
    if connectivity not in (4, 8):
        raise ValueError(
            f"connectivity must be 4 (pixels sharing an edge) or 8 (edges or corners); got {connectivity!r}."
        )
    return int(connectivity)


# --------------------------------------------------------------------------------------------
# automatic distance grid


#: Error of Γ allowed per interval, relative (:func:`_allowed`); realised against 8,000 uniform
#: distances on the five families: ≤ 0.52 % at 128², ≤ 1.4 % at 512², ≤ 0.40 % at 1024²
#: (benchmarks/grid_refinement_tradeoff.py, docs/rough_contact.md).
GAMMA_TOLERANCE = 1e-2
_MAX_ROUNDS = 20


def _allowed(gamma, width, levels):
    """Error of Γ allowed to an interval: ``GAMMA_TOLERANCE`` Γ × max(its share of the range, 1/64)."""
    span = max(float(levels[-1] - levels[0]), 1e-300)
    return GAMMA_TOLERANCE * gamma * np.maximum(width / span, 1 / 64)


def _refine_gamma(z, d, out, mem, hw, dp, kw):
    """Refine each humidity's own grid until the trapezoid of Eq. 13 (Γ) is resolved.

    The controller's midpoint test bounds the pressure's deviation from a chord, which a
    staircase curve (few contacting pixels on small maps) can pass by chance: Γ was then off by
    up to 4 % on a 128² S1 map. Here, per humidity and on that humidity's own levels only (so
    its grid, and its Γ, do not depend on the other humidities requested), every attractive
    interval above the equilibrium whose ends differ enough to matter gets its midpoint; an
    interval whose two-half trapezoid differs from its one-interval trapezoid by more than
    :func:`_allowed` has its halves tested in the next round. New levels are evaluated once for
    every humidity (a level's values do not depend on the others).
    """
    out = [np.asarray(a) for a in out]
    todo = [None] * hw.size  # per humidity: intervals to test (None: every attractive one)
    for _ in range(_MAX_ROUNDS):
        asks = []
        for j in range(hw.size):
            if todo[j] is not None and todo[j].size == 0:
                asks.append(np.empty(0))
                continue
            own = np.flatnonzero(mem[j])
            dj, pj = d[own], out[0][j, own]
            g, _, deq, _, _ = adhesion_summary_kernel(pj, out[2][j, own], dj)
            mid = 0.5 * (dj[:-1] + dj[1:])
            w, q = np.diff(dj), np.maximum(-pj, 0.0)
            # an interval whose ends differ too little to move Γ (a monotone integrand lies
            # between its ends' values) is not tested
            room = 0.5 * w * np.abs(np.diff(q)) > _allowed(g, w, dj)
            cand = room & ((pj[:-1] < 0) | (pj[1:] < 0)) & (mid > dj[:-1]) & (mid < dj[1:])
            if np.isfinite(deq):
                cand &= dj[1:] > deq
            if todo[j] is not None:
                cand &= np.isin(dj[:-1], todo[j])
            asks.append(mid[cand])
        new = np.setdiff1d(np.concatenate(asks), d)
        if new.size == 0:
            break
        more = _k.curves_kernel(z, new, hw, dp, **kw)
        srt = np.argsort(np.concatenate([d, new]), kind="stable")
        d = np.concatenate([d, new])[srt]
        out = [np.concatenate([a, b], axis=1)[:, srt] for a, b in zip(out, more, strict=True)]
        mem = np.concatenate([mem, np.zeros((hw.size, new.size), bool)], axis=1)[:, srt]
        for j, m in enumerate(asks):
            mem[j, np.searchsorted(d, m)] = True
            own = np.flatnonzero(mem[j])
            dj, qj = d[own], np.maximum(-out[0][j, own], 0.0)
            g = adhesion_summary_kernel(out[0][j, own], out[2][j, own], dj)[0]
            i = np.searchsorted(dj, m)  # each asked midpoint, between own levels i-1 and i+1
            lo, hi = dj[i - 1], dj[i + 1]
            w = hi - lo
            err = np.abs(0.25 * w * (qj[i - 1] + 2 * qj[i] + qj[i + 1]) - 0.5 * w * (qj[i - 1] + qj[i + 1]))
            bad = err > _allowed(g, w, dj)
            todo[j] = np.concatenate([lo[bad], m[bad]])
    return d, out


def _auto_curves(z, hw, dp, *, dx, dy, K, periodic, connectivity, n):
    """Distance grid and curves of one eager map (see :func:`contact_distance_grid`).

    The grid is strictly increasing: levels the controller placed at one distance are kept
    once, and an interval is split only if its midpoint is a float strictly between its ends
    (the controller bisects sign changes down to adjacent floats, whose midpoint is an end).
    """
    kw = dict(dx=dx, dy=dy, K=K, periodic=periodic, connectivity=connectivity)
    d, out, *mem = _k.curves(z, hw, dp, per_rh="union", **kw)
    d, keep = np.unique(np.asarray(d, dtype=float), return_index=True)
    out = [np.asarray(a)[:, keep] for a in out]
    if mem:  # not a flat map (its grid is uniform): refine each humidity's Γ on its own grid
        d, out = _refine_gamma(z, d, out, np.asarray(mem[0])[:, keep], hw, dp, kw)
    if n is None or d.size >= int(n):
        return d, list(out)
    # more points on request: split the widest intervals (each level is evaluated on its own, so
    # the added levels do not change the others)
    n = int(n)
    while d.size < n:
        widths = np.diff(d)
        mids = 0.5 * (d[:-1] + d[1:])
        splittable = np.flatnonzero((mids > d[:-1]) & (mids < d[1:]))
        if splittable.size == 0:  # every interval is two adjacent floats: nothing left to split
            break
        order = np.argsort(-widths[splittable], kind="stable")
        pick = np.sort(splittable[order[: n - d.size]])
        new = mids[pick]
        more = _k.curves_kernel(z, new, hw, dp, **kw)
        d = np.concatenate([d, new])
        srt = np.argsort(d, kind="stable")
        d = d[srt]
        out = [np.concatenate([a, b], axis=1)[:, srt] for a, b in zip(out, more, strict=True)]
    return d, list(out)


@check_numbers(connectivity=(4, 8))
def modified_dmt_kernel(z, distance, *, water_height, laplace_pressure, spacing, hertz_modulus,
                        periodic, connectivity=4):
    r""":func:`modified_dmt_curves` (Eq. 16) of one eager map on numpy arrays, without checks.

    For callers that evaluate thousands of maps (:func:`roughstick.failure_probability`): the
    same compiled kernel and the same numbers as :func:`modified_dmt_curves`, without building
    a Dataset per map (which costs several times the kernel on a 128 x 128 map).

    Parameters
    ----------
    z : numpy.ndarray
        Heights [m], shape ``(ny, nx)``, referred to their mean.
    distance : numpy.ndarray
        Distances [m] from the flat to the mean plane, 1-D, any order.
    water_height, laplace_pressure : numpy.ndarray
        :math:`h_{water}` [m] and :math:`\Delta P` [Pa] per RH, 1-D of equal size
        (:func:`roughstick.water_height`, :func:`roughstick.laplace_pressure`).
    spacing : tuple of float
        Pixel sizes ``(dy, dx)`` [m].
    hertz_modulus : float
        :math:`K` [Pa] (:func:`roughstick.hertz_modulus`).
    periodic : bool
        Asperities connect across the map edges.
    connectivity : {4, 8}, default 4

    Returns
    -------
    tuple of numpy.ndarray
        The variables of :func:`modified_dmt_curves` in its order (``pressure``,
        ``repulsive_pressure``, ``wet_fraction``, ...), each over ``(rh, distance)``.

    Examples
    --------
    >>> h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    >>> z = h.values - h.values.mean()
    >>> out = rs.modified_dmt_kernel(z, np.array([-1e-9, 1e-9]), water_height=np.array([1e-9]),
    ...                              laplace_pressure=np.array([-1e8]), spacing=(2e-9, 2e-9),
    ...                              hertz_modulus=1.154e11, periodic=False)
    >>> out[0].shape
    (1, 2)
    """
    dy, dx = (float(v) for v in spacing)
    return _k.curves_kernel(np.asarray(z, dtype=float), distance, np.atleast_1d(water_height),
                            np.atleast_1d(laplace_pressure), dx=dx, dy=dy, K=float(hertz_modulus),
                            periodic=bool(periodic), connectivity=_connectivity(connectivity))


@check_numbers(connectivity=(4, 8), n="count?")
def contact_distance_grid(
    height: xr.DataArray,
    *,
    relative_humidity,
    n: int | None = None,
    material=POLYSILICON,
    material2=None,
    adsorbed_layer="paper",
    connectivity: int = 4,
    periodic: bool | None = None,
) -> xr.DataArray:
    """Automatic distance grid of :func:`modified_dmt_curves` for one eager map.

    One pass of the compiled controller :func:`roughstick.contact._rough_kernels.auto_pass`:
    from just above the first water contact (``d = max z + h_water`` of the wettest humidity) it
    walks down, halving an interval until its midpoint lies on the chord of its ends (pressure
    within a tolerance of the curve's scale), bisects the sign changes of the mean pressure and
    stops a margin below the outermost stable zero crossing (equilibrium) of every humidity, or
    at the lowest pixel; then it refines around the pull-off (the most tensile point) and the
    wetting/contact events next to it: every interval near the most tensile point, or that a
    tie of pixels drying at one height could make deeper than it, is split until resolved. Every
    level is evaluated once (one union-find over the top tail of the heights, moving both ways),
    and a level's values do not depend on the other levels. Each humidity has its own controller
    (its levels do not depend on the other humidities requested), and its own levels are then
    refined until the trapezoid of Γ is resolved (``GAMMA_TOLERANCE``); the grid is the union.
    So Γ of one humidity is nearly the same whichever other humidities are requested, and close
    to a dense uniform grid: on one map of each of the five families, six humidities, five other
    sets (``benchmarks/grid_refinement_tradeoff.py``, docs/rough_contact.md), the spread over
    the sets is ≤ 0.54 % at 128², ≤ 1.6 % at 512² (rough family; ≤ 0.5 % on the others), ≤ 0.35 %
    at 1024², and Γ is within 0.52 %, 1.4 % and 0.40 % of 8,000 uniform distances (without the
    refinement: up to 4.3 % spread and 3.9 % error, at 1.5-4 × less time). Pull-off and d_eq
    agree within 0.5 % with a 4× finer grid (``tests/contact/test_rough_kernels.py``).

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(y, x)``, units length, eager (numpy).
    relative_humidity : float or sequence
        RH fractions in (0, 1).
    n : int, optional
        At least this many distances (the widest intervals are split, each added level evaluated
        on its own); default: as many as the curves need (typically 200-500 on a 1024² map).
    material, material2, adsorbed_layer, connectivity, periodic
        As in :func:`modified_dmt_curves`.

    Returns
    -------
    xarray.DataArray
        ``distance`` [m], ascending, dims ``("distance",)``.
    """
    height = height_in_si(height)
    _check_eager_map(height)
    rh = relative_humidity_coordinate(relative_humidity)
    d, _ = _auto_curves(
        _map_values(height), np.atleast_1d(water_height(rh, adsorbed_layer=adsorbed_layer).values),
        np.atleast_1d(laplace_pressure(rh).values), dx=_spacing(height, "x"),
        dy=_spacing(height, "y"), K=hertz_modulus(material, material2),
        periodic=bool(height.attrs.get("periodic", 0)) if periodic is None else bool(periodic),
        connectivity=_connectivity(connectivity), n=n,
    )
    return set_attrs(xr.DataArray(d, dims=("distance",), coords={"distance": d}), "distance")


def _check_eager_map(height):
    if height.ndim != 2 or is_lazy(height):
        raise ValueError(
            "the automatic distance grid needs one eager (y, x) map; for stacks or dask arrays pass "
            "distance= explicitly, e.g. distance=roughstick.contact_distance_grid(height.isel("
            "realization=0).compute(), relative_humidity=...)."
        )


def _map_values(height):
    return np.asarray(height.transpose("y", "x").values, dtype=float)  # eager, checked


def _warn_if_not_hard(ds, height, e_star):
    """Warn where the modified DMT's own equilibrium says its assumption (i) fails.

    Eq. 16 sums Hertz forces of hard, independent asperities. When the capillary tension pulls
    the flat past the mean plane of the roughness (the equilibrium distance d_eq < 0, or still
    attractive at some d <= 0 with no equilibrium above), most of the map would be flattened:
    the body is too soft for the model. Measured on a 64² S1 map (docs/rough_contact.md): there
    Γ exceeded the FFT boundary-element model's by 1.7× to 10^5× (E* 0.55-5.5 GPa); on
    poly-silicon the five families keep d_eq > 0 at every humidity.
    """
    p = np.asarray(ds["pressure"].transpose(..., "distance").values, dtype=float)
    d = np.asarray(ds["distance"].values, dtype=float)
    if d.size < 2:
        return
    wet = np.asarray(ds["wet_fraction"].transpose(..., "distance").values, dtype=float)
    deq = np.atleast_1d(adhesion_summary_kernel(p, wet, d)[2])
    p0 = p[..., 0]
    bad = (deq < 0) | (np.isnan(deq) & (d[0] <= 0) & (p0 < 0))
    if not np.any(bad):
        return
    where = np.unravel_index(int(np.argmax(bad.ravel())), bad.shape) if bad.ndim else ()
    rh = np.atleast_1d(ds["rh"].values)
    r = float(rh[where[-1]] if "rh" in ds.dims else rh[0])
    dp = float(np.abs(np.atleast_1d(ds["laplace_pressure"].values)[where[-1] if "rh" in ds.dims else 0]))
    lead = where[:-1] if "rh" in ds.dims else where
    maps = np.asarray(height.transpose(..., "y", "x").values, dtype=float)
    z = maps[tuple(lead)] if maps.ndim > 2 else maps
    step = (_spacing(height, "y"), _spacing(height, "x"))
    gy, gx = (np.diff(z, axis=a).ravel() / step[a] for a in (0, 1))
    gy, gx = gy[np.isfinite(gy)], gx[np.isfinite(gx)]
    slope = float(np.sqrt((np.mean(gy**2) if gy.size else 0.0) + (np.mean(gx**2) if gx.size else 0.0)))
    ratio = dp / (e_star * slope) if slope > 0 else np.inf
    value = float(np.ravel(deq)[int(np.argmax(bad.ravel()))])
    where_text = (f"the equilibrium distance d_eq = {value * 1e9:.3g} nm is below the limit 0 "
                  "(the mean plane of the roughness)" if np.isfinite(value) else
                  f"there is no equilibrium: the pressure is still attractive at d = "
                  f"{d[0] * 1e9:.3g} nm, below the limit 0 (the mean plane of the roughness)")
    warnings.warn(
        f"modified_dmt: these curves are not physical at RH {r:.2f}: {where_text}. Eq. 16 sums "
        "Hertz forces of hard, independent asperities (its assumption i), but the capillary "
        f"tension |ΔP| = {dp / 1e6:.3g} MPa is {ratio:.3g} × E*·rms slope (E* = "
        f"{e_star / 1e9:.3g} GPa; pressure ratio |ΔP|/(E*·slope) = {ratio:.3g}, poly-silicon on the "
        "paper's surfaces <= 0.06) and pulls the flat into the roughness: the body is too soft "
        "for the model, whose Γ and pull-off then exceed the boundary-element model's by 1.7× "
        f"to 10^5× (measured). Remedy: {spell('contact_model', 'fft_bem')} (or "
        f"{spell('contact_model', 'auto')}).",
        ValidityWarning,
        stacklevel=external_stacklevel(),
    )


# --------------------------------------------------------------------------------------------
# public entry point


@check_numbers(connectivity=(4, 8), n_distance="count?")
def modified_dmt_curves(
    height: xr.DataArray,
    *,
    relative_humidity,
    distance=None,
    material=POLYSILICON,
    material2=None,
    adsorbed_layer="paper",
    connectivity: int = 4,
    periodic: bool | None = None,
    n_distance: int | None = None,
) -> xr.Dataset:
    r"""Force-distance curves of a rough surface against a flat in humid air (Eqs. 16-23).

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, at least 8 x 8 pixels, units length (converted to m),
        uniform pixel-centre coords ``x``, ``y``. Attribute ``periodic`` (1: generated, wraps round; 0: measured)
        decides whether asperities connect across the map edges. Leading dims (e.g.
        ``realization``) are carried through; dask arrays stay lazy (chunk over the leading
        dims only; ``x`` and ``y`` must be single chunks).
    relative_humidity : float, sequence or xarray.DataArray
        RH as fractions in (0, 1); a sequence gives an ``rh`` dimension.
    distance : array-like or xarray.DataArray, optional
        Distances ``d`` [m] from the flat to the mean plane of the heights, any order. Default:
        an automatic grid of ``n_distance`` points (:func:`contact_distance_grid`; eager 2-D
        maps only).
    material, material2 : roughstick.Material
        The two bodies (``material2=None``: same as ``material``); poly-silicon by default,
        :math:`K = \tfrac43 E^* = 115.4` GPa.
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-water model of :func:`roughstick.water_height` (0.9 nm per surface above 65 %
        RH by default).
    connectivity : {4, 8}, default 4
        Pixels of one asperity share an edge (4) or an edge or a corner (8). 4 is the paper's
        flooding on a square grid and scipy's default.
    periodic : bool, optional
        Override ``height.attrs["periodic"]``.
    n_distance : int, optional
        Minimum size of the automatic distance grid (see :func:`contact_distance_grid`); default:
        as many points as the curves need.

    Returns
    -------
    xarray.Dataset
        Over ``(..., rh, distance)`` (``distance`` ascending): ``pressure`` [Pa] (force per
        apparent area, positive repulsive), ``repulsive_pressure`` [Pa] (the Hertz part),
        ``wet_fraction`` (wetted area net of the contact area, over the apparent area; Fig. 11b),
        ``contact_fraction`` (Hertz contact area over apparent area), ``n_contacts``,
        ``fit_error`` [m] (:math:`E^S` of Eq. 23; NaN without contact) and
        ``max_interference`` [m] (:math:`\delta_{max} = \max z - d`, negative before contact).
        Coordinates ``water_height`` and ``laplace_pressure`` along ``rh``. ``attrs["distance_grid"]``
        is ``"automatic"`` (``distance=None``) or ``"given"``; :func:`roughstick.adhesion_summary`
        words its grid warnings by it.

    Raises
    ------
    ValueError
        Chunked ``x``/``y``, non-uniform coords, fewer than 3 pixels along an axis, an all-NaN
        map, RH outside (0, 1), a bad ``distance``, or ``distance=None`` for a stack / dask map.

    Notes
    -----
    Eq. 16, per unit apparent area :math:`A`:

    .. math:: p(d) = \frac{1}{A}\Big[\sum_i F_r^{a_i}(d)
              + \Delta P\big(A\{z \ge d - h_{water}\} - \sum_i \pi a_i^2\big)\Big]

    with, for the sphere of Eqs. 19-21 fitted to asperity :math:`a_i` (footprint area
    :math:`A_i = \pi a_f^2`, radius :math:`R_i`, :math:`z_0 = d - \sqrt{R_i^2 - A_i/\pi}`),
    the interference :math:`\delta_i = z_0 + R_i - d`, :math:`F_r = K\sqrt{R_i}\delta_i^{3/2}`
    and :math:`a_i^2 = R_i\delta_i` (Eqs. 10-11). Assumptions (paper §3.3): stiff bodies, so
    the adhesive stress does not deform the asperities and the water footprint is that of the
    undeformed surface (valid for poly-silicon; not for soft materials); non-interacting
    asperities. Conventions of the fit (centre kept in the footprint's bounding box, one- and
    two-pixel footprints, plateaus, NaN pixels) are listed in
    :mod:`roughstick.contact._rough_kernels`. This function does not warn outside the measured
    validity regime: :func:`roughstick.rough_contact_curves` does (docs/accuracy.md).
    An asperity that wraps all the way round a periodic map (far past equilibrium) is fitted in
    the coordinates of its union-find tree; its sphere has no meaning.

    References
    ----------
    Hoang et al. (2015), doi:10.1016/j.cam.2015.02.022, §3.3 (Eqs. 16-23).

    Examples
    --------
    >>> h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    >>> ds = rs.modified_dmt_curves(h, relative_humidity=[0.3, 0.7], distance=[-1e-9, 1e-9])
    >>> ds.pressure.dims
    ('rh', 'distance')
    """
    check_map_fits_in_memory(height, model="modified_dmt")  # before anything is allocated
    height = height_in_si(height)
    dx, dy = _spacing(height, "x"), _spacing(height, "y")
    check_core_not_chunked(height, ["y", "x"])
    check_has_roughness(height)
    rh = relative_humidity_coordinate(relative_humidity)
    connectivity = _connectivity(connectivity)
    per = bool(height.attrs.get("periodic", 0)) if periodic is None else bool(periodic)
    K = hertz_modulus(material, material2)
    hw_da = water_height(rh, adsorbed_layer=adsorbed_layer)
    dp_da = laplace_pressure(rh)
    hw = np.atleast_1d(hw_da.values)
    dp = np.atleast_1d(dp_da.values)

    if distance is None:
        _check_eager_map(height)
        d, data = _auto_curves(_map_values(height), hw, dp, dx=dx, dy=dy, K=K, periodic=per,
                               connectivity=connectivity, n=n_distance)
        lead: tuple = ()
    else:
        d = distance_array(distance)
        lead = tuple(dim for dim in height.dims if dim not in ("y", "x"))

    rh_vals = np.atleast_1d(rh.values)
    if distance is not None:
        def kernel(z):
            return _k.curves_kernel(z, d, hw, dp, dx=dx, dy=dy, K=K, periodic=per,
                                    connectivity=connectivity)

        outs = xr.apply_ufunc(
            kernel,
            height.transpose(*lead, "y", "x"),
            input_core_dims=[["y", "x"]],
            output_core_dims=[["rh", "distance"]] * len(_k.OUTPUTS),
            vectorize=bool(lead),
            dask="parallelized",
            output_dtypes=[float] * len(_k.OUTPUTS),
            dask_gufunc_kwargs={"output_sizes": {"rh": rh_vals.size, "distance": d.size}},
        )
        data = list(outs)
    # one Dataset built at once (per-variable assignment re-aligned the coords every time)
    new_coords = {
        "rh": ("rh", rh_vals, dict(ATTRS["rh"])),
        "distance": ("distance", d, dict(ATTRS["distance"])),
        "water_height": ("rh", hw, ATTRS["water_height"]),
        "laplace_pressure": ("rh", dp, ATTRS["laplace_pressure"]),
    }
    if distance is None:
        ds = xr.Dataset({name: (("rh", "distance"), arr)
                         for name, arr in zip(_k.OUTPUTS, data, strict=True)}, coords=new_coords)
    else:
        ds = xr.Dataset(dict(zip(_k.OUTPUTS, data, strict=True))).assign_coords(new_coords)
    for name in _k.OUTPUTS:
        ds.variables[name].attrs = dict(ATTRS[name])
    if rh.ndim == 0:
        ds = ds.squeeze("rh")
    for c in lead:
        if c in height.coords:
            ds = ds.assign_coords({c: height[c]})
    ds.attrs = dataset_attrs(
        "rough-surface adhesive contact curves (modified DMT, Eq. 16)",
        references=REFERENCES,
        contact_model="modified_dmt",
        hertz_modulus=K,
        connectivity=connectivity,
        periodic=int(per),
        adsorbed_layer=str(getattr(adsorbed_layer, "__name__", adsorbed_layer)),
        missing_pixels=_MISSING_NOTE,
        distance_grid="automatic" if distance is None else "given",
    )
    append_history(
        ds,
        f"modified_dmt_curves(n_distance={d.size}, connectivity={connectivity}, "
        f"periodic={int(per)}); {_MISSING_NOTE}",
    )
    if not is_lazy(ds["pressure"]):
        _warn_if_not_hard(ds, height, reduced_modulus(material, material2))
    return ds
