"""Adhesive contact of a rough surface against a flat in humid air: the modified DMT (Eqs. 16-23).

:func:`modified_dmt_curves` takes any ``height`` map (measured or generated) and returns the
mean pressure on the apparent area versus the distance ``d`` between the flat and the mean plane
of the heights, at one or several relative humidities. Asperities are the connected components of
``{z >= d}`` (the paper's flooding); each is fitted with the constrained sphere of Eqs. 19-21 and
Hertz (Eqs. 10-11) gives its repulsive force and contact area; the water term uses the area of
the whole map above ``d - h_water``, so merged menisci (saturation) come out naturally (Eq. 16).

All distances are done in one pass over the heights sorted in descending order, with a
union-find (:mod:`._controller`); the tests hold it to a literal slow implementation that
relabels the map at every distance and fits each asperity with a generic optimiser. This module
registers the model (``"modified_dmt"``) and holds its public functions. See
``docs/rough_contact.md`` for the algorithm, its cost and the accuracy evidence.
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from ..._core.arguments import check_numbers
from ..._core.conventions import set_attrs
from ..._core.dask import is_lazy
from ..._core.materials import POLYSILICON
from ..._core.progress import estimate_model_seconds
from ..._core.references import PAPER, cite
from ..._core.remedy import spell
from ..._core.validate import ValidityWarning, check_has_roughness, external_stacklevel
from .._model import ContactModel, Grid, options_of, register_model
from .._pipeline import apply, default_grid
from ..adhesion import summary_kernel
from . import _controller as _k
from ._grid import auto_curves

__all__ = ["modified_dmt_curves", "contact_distance_grid", "kernel", "MODEL"]

REFERENCES = cite((PAPER, "section 3.3, Eqs. 16-23"), "johnson1985")

_MISSING_NOTE = (
    "heights referred to their mean over the valid pixels; NaN pixels are excluded: never part of "
    "an asperity nor of the wetted area, and the apparent area is that of the valid pixels"
)


@check_numbers(connectivity=(4, 8))
def kernel(z, distance, *, water_height, laplace_pressure, spacing, hertz_modulus, periodic,
           connectivity=4):
    r""":func:`modified_dmt_curves` (Eq. 16) of one eager map on numpy arrays, without checks.

    For callers that evaluate thousands of maps (:func:`roughstick.reliability.failure_probability`): the
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
        (:func:`roughstick.contact.water_height`, :func:`roughstick.contact.laplace_pressure`).
    spacing : tuple of float
        Pixel sizes ``(dy, dx)`` [m].
    hertz_modulus : float
        :math:`K` [Pa] (:func:`roughstick.materials.hertz_modulus`).
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
    >>> out = rs.contact.modified_dmt.kernel(z, np.array([-1e-9, 1e-9]), water_height=np.array([1e-9]),
    ...                                       laplace_pressure=np.array([-1e8]), spacing=(2e-9, 2e-9),
    ...                                       hertz_modulus=1.154e11, periodic=False)
    >>> out[0].shape
    (1, 2)
    """
    dy, dx = (float(v) for v in spacing)
    return _k.curves_kernel(np.asarray(z, dtype=float), distance, np.atleast_1d(water_height),
                            np.atleast_1d(laplace_pressure), dx=dx, dy=dy, K=float(hertz_modulus),
                            periodic=bool(periodic), connectivity=int(connectivity))


# --------------------------------------------------------------------------------------------
# the model's entry: kernel, default grid and hooks of the pipeline


def _settings(ctx):
    o = ctx.options
    return dict(dx=ctx.spacing[1], dy=ctx.spacing[0], K=ctx.hertz_modulus, periodic=o["periodic"],
                connectivity=o["connectivity"])


def _prepare(ctx):
    check_has_roughness(ctx.height)
    periodic = ctx.options["periodic"]
    ctx.options["periodic"] = (bool(ctx.height.attrs.get("periodic", 0)) if periodic is None
                               else bool(periodic))
    ctx.options["connectivity"] = int(ctx.options["connectivity"])


def _kernel(z, distance, ctx):
    out = _k.curves_kernel(z, distance, ctx.water_height, ctx.laplace_pressure, **_settings(ctx))
    return dict(zip(_k.OUTPUTS, out, strict=True))


def _default_grid(z, ctx):
    d, data = auto_curves(z, ctx.water_height, ctx.laplace_pressure, n=ctx.n_distance,
                          **_settings(ctx))
    return Grid(d, curves=dict(zip(_k.OUTPUTS, data, strict=True)))


def _describe(ctx, grid):
    o = ctx.options
    attrs = dict(hertz_modulus=ctx.hertz_modulus, connectivity=o["connectivity"],
                 periodic=int(o["periodic"]), missing_pixels=_MISSING_NOTE)
    return attrs, (f"modified_dmt_curves(n_distance={grid.distance.size}, connectivity="
                   f"{o['connectivity']}, periodic={int(o['periodic'])}); {_MISSING_NOTE}")


def _finish(ds, ctx):
    if not is_lazy(ds["pressure"]):
        _warn_if_not_hard(ds, ctx)


def _warn_if_not_hard(ds, ctx):
    """Warn where the modified DMT's own equilibrium says its assumption (i) fails.

    Eq. 16 sums Hertz forces of hard, independent asperities. When the capillary tension pulls
    the flat past the mean plane of the roughness (the equilibrium distance d_eq < 0, or still
    attractive at some d <= 0 with no equilibrium above), most of the map would be flattened:
    the body is too soft for the model (docs/rough_contact.md).
    """
    p = np.asarray(ds["pressure"].transpose(..., "distance").values, dtype=float)
    d = np.asarray(ds["distance"].values, dtype=float)
    if d.size < 2:
        return
    wet = np.asarray(ds["wet_fraction"].transpose(..., "distance").values, dtype=float)
    deq = np.atleast_1d(summary_kernel(p, wet, d)[2])
    p0 = p[..., 0]
    bad = (deq < 0) | (np.isnan(deq) & (d[0] <= 0) & (p0 < 0))
    if not np.any(bad):
        return
    where = np.unravel_index(int(np.argmax(bad.ravel())), bad.shape) if bad.ndim else ()
    rh = np.atleast_1d(ds["rh"].values)
    r = float(rh[where[-1]] if "rh" in ds.dims else rh[0])
    dp = float(np.abs(np.atleast_1d(ds["laplace_pressure"].values)[where[-1] if "rh" in ds.dims else 0]))
    lead = where[:-1] if "rh" in ds.dims else where
    maps = np.asarray(ctx.height.transpose(..., "y", "x").values, dtype=float)
    z = maps[tuple(lead)] if maps.ndim > 2 else maps
    step = ctx.spacing
    e_star = ctx.reduced_modulus
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
# public functions


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
        Adsorbed-water model of :func:`roughstick.contact.water_height` (0.9 nm per surface above 65 %
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
        is ``"automatic"`` (``distance=None``) or ``"given"``; :func:`roughstick.contact.summary`
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
    :mod:`._controller`. This function does not warn outside the measured validity regime:
    :func:`roughstick.contact.curves` does (docs/accuracy.md).
    An asperity that wraps all the way round a periodic map (far past equilibrium) is fitted in
    the coordinates of its union-find tree; its sphere has no meaning.

    References
    ----------
    Hoang et al. (2015), doi:10.1016/j.cam.2015.02.022, §3.3 (Eqs. 16-23).

    Examples
    --------
    >>> h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    >>> ds = rs.contact.modified_dmt_curves(h, relative_humidity=[0.3, 0.7], distance=[-1e-9, 1e-9])
    >>> ds.pressure.dims
    ('rh', 'distance')
    """
    return apply(MODEL, height, relative_humidity=relative_humidity, distance=distance,
                 material=material, material2=material2, adsorbed_layer=adsorbed_layer,
                 n_distance=n_distance, connectivity=connectivity, periodic=periodic)


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

    One pass of the compiled controller (``auto_pass`` of :mod:`._controller`, settings
    :class:`._policy.GridPolicy`):
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
    refined until the trapezoid of Γ is resolved (``gamma_tolerance``, looser on larger maps, whose
    curves are smoother); the grid is the union.
    So Γ of one humidity is nearly the same whichever other humidities are requested, and close
    to a dense uniform grid (docs/rough_contact.md).

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
    d = default_grid(MODEL, height, relative_humidity=relative_humidity, material=material,
                     material2=material2, adsorbed_layer=adsorbed_layer, n_distance=n,
                     connectivity=connectivity, periodic=periodic).distance
    return set_attrs(xr.DataArray(d, dims=("distance",), coords={"distance": d}), "distance")


MODEL = register_model(ContactModel(
    name="modified_dmt",
    title="rough-surface adhesive contact curves (modified DMT, Eq. 16)",
    description="the modified DMT of Eqs. 16-23: Hertz spheres fitted to the asperities, "
                "merged menisci",
    kernel=_kernel,
    variables=_k.OUTPUTS,
    options=options_of(modified_dmt_curves, connectivity=(4, 8)),
    cost_rank=1.0,
    default_grid=_default_grid,
    references=REFERENCES,
    checks=("validity", "pixel"),
    memory="modified_dmt",
    estimate_seconds=lambda shape, curves, points: estimate_model_seconds("modified_dmt", shape, curves, points),
    prepare=_prepare,
    describe=_describe,
    finish=_finish,
    function=modified_dmt_curves,
))
