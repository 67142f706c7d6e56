"""Boundary-element reference for humid rough contact (optional, via Tamaas).

:func:`bem_contact_curves` solves the full elastic contact of a rough surface against a rigid flat
with Dugdale (Maugis) capillary adhesion, on a periodic FFT boundary-element grid, with the
Polonsky-Keer solver of Tamaas [1]_ [2]_. It returns the same curves layout as the modified DMT
(Eq. 16, :func:`roughstick.rough_contact_curves`), so the two can be compared number by number.

Tamaas is an optional dependency: ``pip install roughstick[bem]``.
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
from .._model import ContactModel, Grid, options_of, register_model
from .._pipeline import apply
from .._shared import SOLVED_ATTRS
from ..fft_bem import fft_bem_curves
from ._tamaas import import_tamaas, solve_map

__all__ = ["bem_curves", "MODEL"]

_REFERENCES = cite("frerot2020", "polonsky1999", "rey2017", "maugis1992")


def _automatic_grids(height, rh_values, *, material, material2, adsorbed_layer, adhesion,
                     n_distance) -> tuple[list[np.ndarray], int]:
    """Per humidity, the distances [m] that fft_bem's automatic grid solves on this map: from a
    quarter step below the equilibrium, through the water range and on while a neck holds,
    refined around the pull-off (docs/fft_bem.md). A fixed span misses all of that on a rough,
    stiff map at low humidity, where the water range is a fraction of a nanometre at max z.
    Also the number of those states in contact in fft_bem, the Tamaas solves to expect (states
    above the highest summit held by a water neck included)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # about fft_bem's own values, not about its grid
        f = fft_bem_curves(height, relative_humidity=list(rh_values), material=material,
                           material2=material2, adsorbed_layer=adsorbed_layer,
                           adhesion=adhesion, progress=False, n_distance=n_distance)
    solved = np.asarray(f["solved"].transpose("rh", "distance").values) > 0
    touching = np.asarray(f["contact_fraction"].transpose("rh", "distance").values) > 0
    below = f.distance.values < float(height.max())
    return [f.distance.values[row] for row in solved], int(np.sum(solved & (touching | below)))


# --------------------------------------------------------------------------------------------
# the model's entry


def _check_path(value):
    if value not in ("retract", "approach"):
        raise ValueError(f"path must be 'retract' or 'approach', got {value!r}.")
    return value


def _prepare(ctx):
    tm = import_tamaas()
    hw = ctx.water_height
    if np.any(hw <= 0):
        raise ValueError(
            "water height must be positive at every humidity for the adhesive zone; got "
            f"{hw.tolist()} m. Check the adsorbed_layer model and contact angles."
        )
    o = ctx.options
    ctx.state.update(
        solver=f"tamaas {getattr(tm, '__version__', '?')} PolonskyKeerRey + MaugisAdhesionFunctional",
        stats={"solves": 0, "retries": 0, "unconverged": 0, "solve_seconds": 0.0,
               "max_noncontact_deflection": 0.0},
        sigma0s=np.abs(ctx.laplace_pressure) if o["adhesion"] else np.zeros_like(ctx.laplace_pressure))


def _default_grid(_, ctx):
    """Per humidity, the grid fft_bem's automatic march solves for the same problem."""
    grids, in_contact = _automatic_grids(
        ctx.height, np.atleast_1d(np.asarray(ctx.rh.values, dtype=float)), material=ctx.material,
        material2=ctx.material2, adsorbed_layer=ctx.adsorbed_layer,
        adhesion=ctx.options["adhesion"], n_distance=ctx.n_distance)
    ctx.state["in_contact"] = in_contact
    return Grid(np.sort(np.unique(np.concatenate(grids))), per_rh=grids)


def _kernel(z, distance, ctx):
    o = ctx.options
    return solve_map(z, spacing=ctx.spacing, distances=distance, sigma0s=ctx.state["sigma0s"],
                     h_waters=ctx.water_height, e_star=ctx.reduced_modulus,
                     tolerance=o["solver_tolerance"], max_iterations=o["max_iterations"],
                     path=o["path"], retries=o["retries"], stats=ctx.state["stats"],
                     on_solve=ctx.step)


def _progress(ctx, grid):
    """Size, Tamaas solves to expect and estimated time, said before the work; progress in
    solves, the cost (a state without contact costs a few FFTs)."""
    h = ctx.height
    n_maps = int(np.prod([h.sizes[d] for d in ctx.lead]))
    n_rh = ctx.water_height.size
    per_rh = grid.per_rh if grid.per_rh is not None else [grid.distance] * n_rh
    points = n_maps * sum(g.size for g in per_rh)
    below = n_maps * (sum(int(np.sum(g < float(h.max()))) for g in per_rh)
                      if h.chunks is None else n_rh * grid.distance.size)
    if grid.per_rh is not None:  # the states fft_bem found in contact: above the summit too
        below = max(below, ctx.state["in_contact"])
    ny, nx = h.sizes["y"], h.sizes["x"]
    return WorkProgress(
        below,
        what=(f"bem: {n_maps} map(s) of {ny} x {nx} pixels x {n_rh} humidities x "
              f"{grid.distance.size} distances ({points} points, {below} Tamaas solves)"),
        estimate=estimate_seconds("bem", (ny, nx), below),
        progress=ctx.options["progress"],
        unit="Tamaas solves",
    )


def _describe(ctx, grid):
    o = ctx.options
    attrs = dict(
        solver=ctx.state["solver"], reduced_modulus=ctx.reduced_modulus,
        solver_tolerance=o["solver_tolerance"], path=o["path"], adhesion=int(bool(o["adhesion"])),
        distance_convention="mean gap + mean height (zero-mean elastic displacement); "
        "add distance_offset for the isolated-contact convention of Eq. 16",
        periodic=1)
    return attrs, (
        f"bem_curves(solver_tolerance={o['solver_tolerance']}, path={o['path']!r}, "
        f"n_rh={ctx.water_height.size}, n_distance={grid.distance.size}"
        + (", automatic grid of fft_bem)" if grid.automatic else ")")
        + ("; height not periodic: solved as if it wrapped around"
           if int(ctx.height.attrs.get("periodic", 1)) == 0 else ""))


def _variable_attrs(ctx):
    return {"solved": dict(SOLVED_ATTRS)}


def _finish(ds, ctx):
    if ctx.height.chunks is None:
        st = ctx.state["stats"]
        ds.attrs.update(bem_solves=st["solves"], bem_retries=st["retries"],
                        bem_unconverged=st["unconverged"],
                        bem_solve_seconds=round(st["solve_seconds"], 3),
                        max_noncontact_deflection=st["max_noncontact_deflection"])


# --------------------------------------------------------------------------------------------
# public function


@renamed_keywords(tolerance="solver_tolerance", n_distances="n_distance")
@check_numbers(solver_tolerance="positive", max_iterations="count", retries="count0",
               n_distance="count?")
def bem_curves(
    height: xr.DataArray,
    *,
    relative_humidity,
    distance=None,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    adsorbed_layer="paper",
    solver_tolerance: float = 1e-6,
    max_iterations: int = 1000,
    path: str = "retract",
    retries: int = 1,
    n_distance: int | None = None,
    adhesion: bool = True,
    progress: bool | None = None,
) -> xr.Dataset:
    r"""Humid adhesive contact of a rough surface and a flat by the boundary-element method.

    The reference for the modified DMT (Eq. 16): the full elastic contact of the rough surface with
    a rigid flat, with the capillary adhesion modelled as a Dugdale (Maugis) cohesive zone of
    strength :math:`\sigma_0 = |\Delta P|` (Eq. 2) and range :math:`h_{water}` (Eq. 6), solved on
    the pixel grid by an FFT boundary-element method (Polonsky-Keer with Maugis adhesion,
    Tamaas [1]_ [2]_ [3]_). Unlike Eq. 16 it keeps the deformation caused by the adhesive
    tension, the elastic interaction between asperities and the exact contact shapes; it does
    not fit spheres, so ``fit_error`` is NaN.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, at least 8 x 8 pixels, units length (converted to m),
        uniform spacing. Treated
        as periodic (the FFT solver wraps it around): for a measured map (``periodic=0``) the
        wrap-around step is part of the solved geometry.
    relative_humidity : float, sequence or xarray.DataArray
        RH as a fraction in (0, 1); a sequence gives dimension ``rh``.
    distance : array_like, optional
        Positions :math:`d` of the flat above the mean plane [m] (see Notes for the convention),
        all above the mean plane of every map. Default (one eager (y, x) map): per humidity,
        the grid that :func:`roughstick.fft_bem_contact_curves`' automatic march solves on the
        same map (from just below the equilibrium through the water range and on while a neck
        holds, refined at the pull-off; on the maps of benchmarks/untuned_surfaces.py that
        call took 0.6-5 % of the BEM's time, 63-82 % on soft maps at RH 1e-3). Several
        humidities are then reported on the union of their grids, as fft_bem does (linear
        interpolation between a humidity's own points, NaN below its first, dry above its
        last; ``solved`` marks the computed points). A fixed span from ``max(z) - 0.5 std(z)``,
        as before, missed the whole adhesive range of a rough, stiff map at low humidity
        (σ 28 nm, RH 0.05: Γ = 0 against 8.6e-6 J/m² on this grid).
    material, material2 : Material
        The two bodies (``material2=None``: same as ``material``); only
        :math:`E^* = [(1-\nu_1^2)/E_1 + (1-\nu_2^2)/E_2]^{-1}` enters (86.6 GPa for poly-Si).
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-layer model of :func:`roughstick.water_height`.
    tolerance : float, default 1e-6
        Relative tolerance of the Polonsky-Keer iterations.
    max_iterations : int, default 1000
        Iteration cap per solve.
    path : {"retract", "approach"}
        Order in which the distances are marched (the solver is warm-started from the previous
        distance, and adhesive contact is path dependent): ``"retract"`` (default) starts from
        the closest distance and pulls the flat away, the branch that decides stiction;
        ``"approach"`` comes in from far.
    retries : int, default 1
        A solve whose residual stays above ``10 * tolerance`` is retried this many times from a
        fresh solver; the best residual is kept and reported in ``solver_residual``.
    n_distances : int, optional
        About this many points per humidity on the default grid (as ``n_distance`` of
        :func:`roughstick.rough_contact_curves` for fft_bem); None: fft_bem's defaults.
    adhesion : bool, default True
        ``False`` switches the capillary tension off (dry Hertz-type contact, used for
        validation); ``wet_fraction`` is then zero.
    progress : bool or None, default None
        Before it starts, the run logs (logger ``roughstick``, INFO) its size, the Tamaas solves
        to expect (on the default grid: the states fft_bem found in contact, those above the
        highest summit held by a water neck included) and an estimate of its time
        (:mod:`roughstick._core.progress`, within a factor ~3); runs estimated at 5 s or more
        then show their progress in solves, the cost, as a bar (terminal; a widget in Jupyter
        with ipywidgets) or INFO lines every 30 s (no terminal), the time left at the measured
        rate; a run measured outside a factor 3 of its estimate says so once, and shows its
        progress from then on. ``True`` always shows it, ``False`` never.

    Returns
    -------
    xarray.Dataset
        Over ``(..., rh, distance)`` (``rh`` dropped for a scalar humidity, as in
        :func:`roughstick.rough_contact_curves`), coordinates ``water_height`` and
        ``laplace_pressure`` along ``rh``: ``pressure`` (mean pressure, Pa, + repulsive),
        ``repulsive_pressure`` (Pa, the traction carried by the contact area),
        ``wet_fraction`` (adhesive zone: gap below :math:`h_{water}` and not in contact),
        ``contact_fraction``, ``n_contacts`` (periodic 4-connected contact clusters),
        ``fit_error`` (NaN), ``max_interference`` (:math:`\max z - d_{local}`),
        ``distance_offset`` (:math:`d_{local} - d`, m), ``solver_residual`` and ``solved`` (1
        where this humidity was solved; 0 where interpolated: on the default grid's union, or
        where Tamaas stalled, residual above 10 × ``tolerance`` after the retries, counted in
        the attribute ``bem_unconverged``).
        Attributes record the model, ``max_noncontact_deflection`` (m) and solver statistics.

    Raises
    ------
    ImportError
        If Tamaas is not installed (``pip install roughstick[bem]``).
    ValueError
        If a distance lies at or below the mean plane, the map has NaN, or ``path`` is unknown.

    Notes
    -----
    *Distance convention.* The solver imposes the mean gap :math:`\bar g`; the output coordinate
    is :math:`d = \bar g + \bar z`, the flat position in the periodic convention where the
    elastic displacement has zero mean. Eq. 16 measures :math:`d` with no displacement away from
    the contacts; for a periodic cell of area :math:`A` the two differ by
    :math:`d_{local} - d = \bar p A Z/(\pi E^*)` (:func:`periodic_offset_coefficient`,
    :math:`\approx -1.24\,\bar p L/E^*` for a square of side :math:`L`), stored as
    ``distance_offset``; with it a single sphere follows Hertz (tested). The offset is
    proportional to :math:`\bar p`, so it vanishes at the equilibrium distance and
    :math:`\oint \bar p\, d\bar p = 0` along the adhesive branch: the apparent adhesive energy
    (Eq. 13), the pull-off pressure and the equilibrium distance are the same in either
    convention.

    *States with water but no hard contact* (:math:`d \ge \max z`) are not passed to the solver
    (its relative error is 0/0 there and it runs to the iteration cap). They are evaluated as a
    Dugdale tension :math:`\Delta P` on :math:`\{z \ge d_{local} - h_{water}\}` of the undeformed
    surface: the adhesive deflection is neglected, as in Eq. 16. The largest deflection this
    tension would cause is reported in the attribute ``max_noncontact_deflection``; it is a few
    pm for poly-silicon, but it is not small for soft materials, where jump-in to contact is
    missed.

    Costs (DESIGN.md §7): about 28 s per curve of 40 separations at 256², 4.5 min at 512² on one
    core, tolerance 1e-6. Tamaas is serial; dask input parallelises over the leading dimensions.

    References
    ----------
    .. [1] Frérot, L., Anciaux, G., Rey, V., Pham-Ba, S., Molinari, J.-F. (2020). Tamaas: a
       library for elastic-plastic contact of periodic rough surfaces. J. Open Source Softw. 5,
       2121. https://doi.org/10.21105/joss.02121
    .. [2] Polonsky, I. A., Keer, L. M. (1999). A numerical method for solving rough contact
       problems based on the multi-level multi-summation and conjugate gradient techniques.
       Wear 231, 206-219. https://doi.org/10.1016/S0043-1648(99)00113-1
    .. [3] Rey, V., Anciaux, G., Molinari, J.-F. (2017). Normal adhesive contact on rough
       surfaces: efficient algorithm for FFT-based BEM resolution. Comput. Mech. 60, 69-81.
       https://doi.org/10.1007/s00466-017-1392-5
    .. [4] Maugis, D. (1992). Adhesion of spheres: the JKR-DMT transition using a Dugdale model.
       J. Colloid Interface Sci. 150, 243-269. https://doi.org/10.1016/0021-9797(92)90285-T
    """
    return apply(MODEL, height, relative_humidity=relative_humidity, distance=distance,
                 material=material, material2=material2, adsorbed_layer=adsorbed_layer,
                 n_distance=n_distance, solver_tolerance=solver_tolerance,
                 max_iterations=max_iterations, path=path, retries=retries, adhesion=adhesion,
                 progress=progress)


MODEL = register_model(ContactModel(
    name="bem",
    title="Humid adhesive contact of a rough surface and a flat: boundary-element reference",
    description="the boundary-element reference (Tamaas, optional: pip install roughstick[bem])",
    kernel=_kernel,
    options=options_of(bem_curves, solver_tolerance="positive", max_iterations="count",
                       path=_check_path, retries="count0"),
    cost_rank=3.0,
    default_grid=_default_grid,
    extra_variables=("distance_offset", "solver_residual", "solved"),
    references=_REFERENCES,
    reference=True,
    complete_map=True,
    min_distances=2,
    memory="bem",
    estimate_seconds=lambda shape, curves, points: estimate_model_seconds("bem", shape, curves, points),
    prepare=_prepare,
    progress=_progress,
    describe=_describe,
    variable_attrs=_variable_attrs,
    finish=_finish,
    function=bem_curves,
))
