"""A fast boundary-element model of humid rough contact, registered as ``"fft_bem"``.

:func:`fft_bem_curves` solves the problem of the Tamaas reference
(:func:`roughstick.contact.bem_curves`): the full elastic contact of a rough surface with a flat,
capillary adhesion as a Dugdale zone of strength :math:`|\\Delta P|` (Eq. 2) and range
:math:`h_{water}` (Eq. 6), on the periodic FFT grid of the map. It solves the non-adhesive
contact problem with the capillary tension on the wet set as a known load (Polonsky-Keer
conjugate gradient, displacement control) and updates the wet set from the deformed gap
(:mod:`._kernels`), at a loose tolerance in single precision, and with ``distance=None`` on few
states, where Eq. 13, the pull-off pressure and the equilibrium distance are decided. Its cost
and accuracy against the reference: docs/accuracy.md.
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from ..._core.api import renamed_keywords
from ..._core.arguments import check_numbers
from ..._core.materials import POLYSILICON, Material
from ..._core.progress import WorkProgress, estimate_model_seconds, estimate_seconds
from ..._core.references import cite
from ..._core.units import require
from ..._core.validate import ValidityWarning, check_has_roughness, external_stacklevel
from .._model import ContactModel, Grid, options_of, register_model
from .._pipeline import apply
from .._shared import (
    SOLVED_ATTRS,
    count_periodic_clusters,
    merge_humidity_grids,
    periodic_offset_coefficient,
)
from . import _kernels as _k

__all__ = ["fft_bem_curves", "periodic_offset_coefficient", "MODEL"]

_REFERENCES = cite("polonsky1999", "rey2017", "maugis1992")
_LENGTH_UNIT = 1e-9
_NAMES = ("pressure", "repulsive_pressure", "wet_fraction", "contact_fraction", "n_contacts",
          "max_interference", "distance_offset", "solver_residual", "solved")


def _states_to_arrays(states, d_nm, zmax, e_star, sigma0, offset_per_pressure):
    vals = {k: np.empty(len(states)) for k in _NAMES}
    for i, (d, st) in enumerate(zip(d_nm, states, strict=True)):
        pbar = st["pbar"]
        dloc = d + offset_per_pressure * pbar
        vals["pressure"][i] = pbar * e_star
        vals["repulsive_pressure"][i] = st["repulsive"] * e_star
        vals["wet_fraction"][i] = st["wet_fraction"]
        vals["contact_fraction"][i] = st["contact_fraction"]
        vals["n_contacts"][i] = st["n_contacts"]
        vals["max_interference"][i] = (zmax - dloc) * _LENGTH_UNIT
        vals["distance_offset"][i] = (dloc - d) * _LENGTH_UNIT
        vals["solver_residual"][i] = st["residual"]
        vals["solved"][i] = 1.0
    return vals


def _count(st):
    contact = st["p"] > 0
    st["n_contacts"] = count_periodic_clusters(contact) if contact.any() else 0
    return st


def _fft_bem_kernel(z, *, spacing, distances, sigma0s, h_waters, e_star, tolerance,
                    max_iterations, path, precision, n_contact, n_free, refine, stats,
                    on_curve=None):
    """Curves of one map (numpy, SI in and out): dict of (n_rh, n_distance) arrays + grid.

    ``on_curve()`` is called after each humidity's curve (progress)."""
    L = _LENGTH_UNIT
    z = np.asarray(z, dtype=float)
    check_has_roughness(z)  # a flat or (almost) all-NaN map: nothing to model
    if not np.all(np.isfinite(z)):
        raise ValueError(
            "height contains NaN or inf; the boundary-element model needs a complete map. "
            "Fill or crop the missing pixels first."
        )
    zn = z / L
    zmax = float(zn.max())
    ny, nx = zn.shape
    sp = (spacing[0] / L, spacing[1] / L)
    size = (ny * sp[0], nx * sp[1])
    offset_per_pressure = size[0] * size[1] * periodic_offset_coefficient(size[1], size[0]) / np.pi
    dtype = np.float32 if precision == "single" else np.float64
    per_rh = []
    for s0, h in zip(sigma0s, h_waters, strict=True):
        s0n, hn = s0 / e_star, h / L
        if distances is None:
            dd, states, grid = _k.auto_curve(
                zn, sp, s0n, hn, tolerance=tolerance, n_contact=n_contact, n_free=n_free,
                refine=refine, dtype=dtype, max_iterations=max_iterations, keep=_count,
            )
        else:
            dn = np.asarray(distances, dtype=float) / L
            states, grid = _k.curve_on_grid(zn, sp, dn, s0n, hn, tolerance=tolerance, path=path,
                                            dtype=dtype, max_iterations=max_iterations)
            states = [_count(st) for st in states]
            dd = dn
        stats["fft_calls"] += grid.calls
        stats["states"] += len(states)
        stats["iterations"] += int(sum(st["iterations"] for st in states))
        stats["unconverged"] += int(sum(not st["converged"] for st in states))
        stats["capped"] += int(sum(not st["converged"] and st["iterations"] >= max_iterations
                                   for st in states))
        per_rh.append((dd, _states_to_arrays(states, dd, zmax, e_star, s0n, offset_per_pressure)))
        if on_curve is not None:
            on_curve()
    if distances is not None:
        grid_nm = per_rh[0][0]
        out = {k: np.stack([v[k] for _, v in per_rh]) for k in _NAMES}
        return grid_nm * L, out
    return merge_humidity_grids(per_rh, zmax, _NAMES, L)


def _warn_unconverged(stats, max_iterations, tolerance, e_star) -> None:
    """Warn when states stopped unconverged (residual at or over 10 x the tolerance), saying how
    many hit ``max_iterations`` and how many stalled before it (no descent direction left)."""
    n, total, capped = stats["unconverged"], stats["states"], stats["capped"]
    if n:
        how = []
        if capped:
            how.append(f"{capped} hit max_iterations={max_iterations} conjugate-gradient iterations per "
                       "wet-set update: raise max_iterations (e.g. 2000)")
        if n - capped:
            how.append(f"{n - capped} stalled before it (no descent direction left): compare with "
                       "model='bem'")
        warnings.warn(
            f"fft_bem: {n} of {total} contact states did not converge (residual >= 10 x "
            f"tolerance={tolerance:g}, E* = {e_star:.3g} Pa); their pressures, and Γ, pull-off and "
            f"d_eq built on them, are not trustworthy (see solver_residual). {'; '.join(how)}. On a "
            "soft material the wet and contact sets may also cycle.",
            ValidityWarning, stacklevel=external_stacklevel())


def automatic_grid_counts(n_distance: int) -> dict:
    """``n_contact`` and ``n_free`` of the automatic grid for about ``n_distance`` points (a
    third below the first water contact, the rest across the water range; the refinement adds
    its own)."""
    n_contact = max(4, -(-int(n_distance) // 3))
    return {"n_contact": n_contact, "n_free": max(4, int(n_distance) - n_contact)}


def _check_choice(name, choices):
    def check(value):
        if value not in choices:
            raise ValueError(f"{name} must be {' or '.join(map(repr, choices))}, got {value!r}.")
        return value
    return check


# --------------------------------------------------------------------------------------------
# the model's entry


def _solver_spacing(height):
    """Pixel sizes ``(dy, dx)`` [m] the solver uses: the first step of each coordinate (the
    pipeline has checked them uniform to 1e-6; this keeps the solver's numbers unchanged)."""
    out = []
    for dim in ("y", "x"):
        coord = height[dim]
        if coord.attrs.get("units", "m") != "m":
            coord = require(coord.copy(), "length", name=dim)
        out.append(float(np.diff(np.asarray(coord.values, dtype=float))[0]))
    return tuple(out)


def _prepare(ctx):
    ctx.spacing = _solver_spacing(ctx.height)
    o = ctx.options
    hw, dp = ctx.water_height, ctx.laplace_pressure
    if o["adhesion"] and np.any(hw <= 0):
        raise ValueError(
            f"water height must be positive at every humidity; got {hw.tolist()} m. Check the "
            "adsorbed_layer model."
        )
    counts = automatic_grid_counts(ctx.n_distance) if ctx.n_distance is not None else {}
    n_contact = o["n_contact"] if o["n_contact"] is not None else counts.get("n_contact", 12)
    n_free = o["n_free"] if o["n_free"] is not None else counts.get("n_free", 24)
    ctx.state["stats"] = {"fft_calls": 0, "states": 0, "iterations": 0, "unconverged": 0, "capped": 0}
    ctx.state["kw"] = dict(
        spacing=ctx.spacing, sigma0s=np.abs(dp) if o["adhesion"] else np.zeros_like(dp),
        h_waters=hw, e_star=ctx.reduced_modulus, tolerance=o["solver_tolerance"],
        max_iterations=o["max_iterations"], path=o["path"], precision=o["precision"],
        n_contact=n_contact, n_free=n_free, refine=o["refine"], stats=ctx.state["stats"])


def _bar(ctx, n_points):
    """Size and estimated time said before the work; progress one step per humidity and map."""
    h = ctx.height
    n_maps = int(np.prod([h.sizes[d] for d in ctx.lead]))
    ny, nx = h.sizes["y"], h.sizes["x"]
    n_rh = ctx.water_height.size
    return WorkProgress(
        n_maps * n_rh,
        what=(f"fft_bem: {n_maps} map(s) of {ny} x {nx} pixels x {n_rh} humidities "
              f"(about {n_maps * n_rh * n_points} states)"),
        estimate=estimate_seconds("fft_bem", (ny, nx), n_maps * n_rh * n_points),
        progress=ctx.options["progress"],
        unit="curves",
    )


def _progress(ctx, grid):
    return _bar(ctx, grid.distance.size)


def _kernel(z, distance, ctx):
    zbar = float(np.mean(z))
    if distance[0] <= zbar:
        raise ValueError(
            f"distance {distance[0]!r} m lies at or below the mean plane of the heights "
            f"({zbar!r} m): the mean gap would be <= 0 (full contact). Pass distances above the "
            "mean plane."
        )
    return _fft_bem_kernel(z, distances=distance, on_curve=ctx.step, **ctx.state["kw"])[1]


def _default_grid(z, ctx):
    kw = ctx.state["kw"]
    # about 1.3 states per point of n_contact + n_free (docs/fft_bem.md)
    with _bar(ctx, int(1.3 * (kw["n_contact"] + kw["n_free"]))) as bar:
        dist, res = _fft_bem_kernel(z, distances=None, on_curve=bar.update, **kw)
    return Grid(dist, curves=res)


def _variable_attrs(ctx):
    return {"solved": dict(SOLVED_ATTRS)}


def _describe(ctx, grid):
    o = ctx.options
    attrs = dict(
        solver="Polonsky-Keer conjugate gradient with Dugdale wet-set updates (roughstick)",
        reduced_modulus=ctx.reduced_modulus, solver_tolerance=o["solver_tolerance"],
        precision=o["precision"], path=o["path"], adhesion=int(bool(o["adhesion"])),
        distance_convention="mean gap + mean height (zero-mean elastic displacement); "
        "add distance_offset for the isolated-contact convention of Eq. 16",
        periodic=1)
    return attrs, (
        f"fft_bem_curves(solver_tolerance={o['solver_tolerance']}, precision={o['precision']!r}, "
        f"n_rh={ctx.water_height.size}, n_distance={grid.distance.size}"
        + (", automatic grid" if grid.automatic else "") + ")"
        + ("; height not periodic: solved as if it wrapped around"
           if int(ctx.height.attrs.get("periodic", 1)) == 0 else ""))


def _finish(ds, ctx):
    if ctx.height.chunks is None:
        st = ctx.state["stats"]
        ds.attrs.update(fft_calls=st["fft_calls"], states=st["states"],
                        iterations=st["iterations"], unconverged=st["unconverged"])
        _warn_unconverged(st, ctx.options["max_iterations"], ctx.options["solver_tolerance"],
                          ctx.reduced_modulus)


# --------------------------------------------------------------------------------------------
# public function


@renamed_keywords(tolerance="solver_tolerance")
@check_numbers(solver_tolerance="positive", max_iterations="count", n_contact="count?",
               n_free="count?", refine="count0", n_distance="count?")
def fft_bem_curves(
    height: xr.DataArray,
    *,
    relative_humidity,
    distance=None,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    adsorbed_layer="paper",
    solver_tolerance: float = 1e-3,
    max_iterations: int = 500,
    path: str = "retract",
    precision: str = "single",
    n_contact: int | None = None,
    n_free: int | None = None,
    refine: int = 2,
    adhesion: bool = True,
    progress: bool | None = None,
    n_distance: int | None = None,
) -> xr.Dataset:
    r"""Humid adhesive contact of a rough surface and a flat: fast FFT boundary-element model.

    The problem of :func:`roughstick.contact.bem_curves` (elastic half-space of contact modulus
    :math:`E^*` against the rigid rough profile on the periodic pixel grid; capillary adhesion
    as a Dugdale zone, tension :math:`\sigma_0 = |\Delta P|` (Eq. 2) wherever the gap is below
    :math:`h_{water}` (Eq. 6)), solved by our own conjugate-gradient solver at a loose tolerance.
    Unlike Eq. 16 it keeps the deformation caused by the tension, the elastic interaction of the
    contacts and the exact contact shapes, so it stays valid on smooth surfaces in deep contact
    and on soft materials (docs/accuracy.md). No optional dependency; thread-safe.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, at least 8 x 8 pixels, units length, uniform ascending
        coordinates. Treated as periodic (the FFT grid wraps around), like the reference.
    relative_humidity : float, sequence or xarray.DataArray
        RH fractions in (0, 1); a sequence gives dimension ``rh``.
    distance : array_like, optional
        Flat positions :math:`d` [m] (mean gap + mean height, the reference's convention; see
        :func:`roughstick.contact.bem_curves`), all above the mean plane. Default: an automatic
        grid per humidity, concentrated where Eq. 13, the pull-off and the equilibrium are
        decided (eager single map only); the humidities' grids are merged, see ``solved``.
    material, material2 : Material
        The two bodies; only :math:`E^*` enters.
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-layer model of :func:`roughstick.contact.water_height`.
    solver_tolerance : float, default 1e-3
        Conjugate-gradient tolerance: rms gap on the contact set (and of any interpenetration)
        over the rms height (its effect on Γ, pull-off and d_eq: docs/accuracy.md).
    max_iterations : int, default 500
        Conjugate-gradient iterations per wet-set update.
    path : {"retract", "approach"}
        March order on a given ``distance`` grid (states are warm-started from the previous one):
        ``"retract"`` (default) pulls the flat away from the closest distance, like the reference.
    precision : {"single", "double"}
        FFT precision; single is twice as fast and resolves gaps to ~1e-6 of the heights.
    n_contact, n_free : int, optional
        Automatic grid: uniform retraction steps in contact (default 12) and points over the
        water range without contact (default 24); with ``n_distance``, a third and two thirds
        of it.
    refine : int, default 2
        Bisection rounds around the pull-off and the equilibrium (then, if > 0, four more around
        the pull-off: docs/fft_bem.md). The retraction starts just below the zero-load
        equilibrium, so Γ is the work of separation from a contact under no load (on soft bodies
        that differs from a loaded contact's: pass ``distance=`` starting at the preload).
    adhesion : bool, default True
        ``False``: dry contact (validation against Hertz).
    progress : bool or None, default None
        The size and estimated time are logged (INFO) before the run; runs estimated at 5 s or
        more show their progress, one step per humidity and map. ``True`` always, ``False``
        never.
    n_distance : int, optional
        About this many points of the automatic grid (sets ``n_contact`` and ``n_free``).

    Returns
    -------
    xarray.Dataset
        The layout of :func:`roughstick.contact.bem_curves` over ``(..., rh, distance)``:
        ``pressure``, ``repulsive_pressure``, ``wet_fraction``, ``contact_fraction``,
        ``n_contacts``, ``fit_error`` (NaN), ``max_interference``, ``distance_offset``,
        ``solver_residual``, plus ``solved`` (1 where this humidity was solved; with
        ``distance=None`` and several humidities the other points are interpolated linearly
        between solved ones, or NaN below the first). Attributes give the cost counters
        (``fft_calls``, ``states``, ``iterations``) and ``unconverged``.

    Raises
    ------
    ValueError
        A distance at or below the mean plane, NaN heights, ``distance=None`` for a stack or a
        dask map, unknown ``path``/``precision``, a solver_tolerance not finite and > 0, a
        ``max_iterations``, ``n_contact`` or ``n_free`` that is not an integer >= 1.

    Warns
    -----
    ValidityWarning
        Contact states that did not converge within ``max_iterations`` (eager maps), naming
        their number and the argument to raise.

    Notes
    -----
    The reference and this model share the physics, the grid and the distance convention, so
    on the same distances they differ only by the solver tolerance (docs/accuracy.md). Like the
    reference, a state with water but no hard contact starts from
    the undeformed wet set :math:`\{d - z < h_{water}\}` and iterates the adhesive deflection to a
    fixed point.

    References
    ----------
    .. [1] Polonsky, I. A., Keer, L. M. (1999). Wear 231, 206-219.
       https://doi.org/10.1016/S0043-1648(99)00113-1
    .. [2] Rey, V., Anciaux, G., Molinari, J.-F. (2017). Comput. Mech. 60, 69-81.
       https://doi.org/10.1007/s00466-017-1392-5
    .. [3] Maugis, D. (1992). J. Colloid Interface Sci. 150, 243-269.
       https://doi.org/10.1016/0021-9797(92)90285-T

    Examples
    --------
    >>> h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    >>> ds = rs.contact.fft_bem_curves(h, relative_humidity=0.5)
    >>> s = rs.contact.summary(ds)
    >>> bool(s.adhesive_energy > 0)
    True
    """
    return apply(MODEL, height, relative_humidity=relative_humidity, distance=distance,
                 material=material, material2=material2, adsorbed_layer=adsorbed_layer,
                 n_distance=n_distance, solver_tolerance=solver_tolerance,
                 max_iterations=max_iterations, path=path, precision=precision,
                 n_contact=n_contact, n_free=n_free, refine=refine, adhesion=adhesion,
                 progress=progress)


MODEL = register_model(ContactModel(
    name="fft_bem",
    title="Humid adhesive contact of a rough surface and a flat: FFT boundary-element model",
    description="the FFT boundary-element model: elastic half-space, Dugdale capillary zone, "
                "periodic map (no optional dependency)",
    kernel=_kernel,
    options=options_of(fft_bem_curves, solver_tolerance="positive", max_iterations="count",
                       path=_check_choice("path", ("retract", "approach")),
                       precision=_check_choice("precision", ("single", "double")),
                       n_contact="count?", n_free="count?", refine="count0"),
    cost_rank=2.0,
    default_grid=_default_grid,
    extra_variables=("distance_offset", "solver_residual", "solved"),
    references=_REFERENCES,
    complete_map=True,
    memory=lambda o: "fft_bem_double" if o.get("precision") == "double" else "fft_bem",
    estimate_seconds=lambda shape, curves, points: estimate_model_seconds("fft_bem", shape, curves, points),
    prepare=_prepare,
    progress=_progress,
    describe=_describe,
    variable_attrs=_variable_attrs,
    finish=_finish,
    function=fft_bem_curves,
))
