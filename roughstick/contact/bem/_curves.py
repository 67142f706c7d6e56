"""The boundary-element reference, registered as the contact model ``"bem"``: its entry and
:func:`bem_curves`. The solver is :mod:`._tamaas`; the default grid is fft_bem's automatic one.
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
    """Per humidity, the distances [m] that fft_bem's automatic grid solves on this map (from
    just below the equilibrium, through the water range and on while a neck holds, refined at
    the pull-off: docs/fft_bem.md), and the number of those states in contact in fft_bem: the
    Tamaas solves to expect (states above the highest summit held by a neck included)."""
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

    The reference the other models are measured against: the full elastic contact of the rough
    surface with a rigid flat, the capillary adhesion a Dugdale (Maugis) zone of strength
    :math:`\sigma_0 = |\Delta P|` (Eq. 2) and range :math:`h_{water}` (Eq. 6), solved on the
    periodic pixel grid by Tamaas' Polonsky-Keer solver [1]_ [2]_ [3]_ [4]_. Unlike Eq. 16 it
    keeps the deformation caused by the tension, the elastic interaction of the asperities and
    the exact contact shapes; it fits no spheres (``fit_error`` is NaN). Tamaas is optional:
    ``pip install roughstick[bem]``.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, at least 8 x 8 pixels, units length, uniform spacing;
        treated as periodic (a measured map's wrap-around step is part of the geometry).
    relative_humidity : float, sequence or xarray.DataArray
        RH as a fraction in (0, 1); a sequence gives dimension ``rh``.
    distance : array_like, optional
        Flat positions :math:`d` [m] (Notes), above the mean plane of every map. Default (one
        eager map): per humidity, the distances :func:`roughstick.contact.fft_bem_curves`'
        automatic grid solves on the same map, reported on their union (``solved`` marks each
        humidity's own points; linear in between, NaN below its first, dry above its last).
    material, material2 : Material
        The two bodies; only :math:`E^*` enters (86.6 GPa for poly-Si).
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-layer model of :func:`roughstick.contact.water_height`.
    solver_tolerance : float, default 1e-6
        Relative tolerance of the Polonsky-Keer iterations.
    max_iterations : int, default 1000
        Iteration cap per solve.
    path : {"retract", "approach"}
        March order (states are warm-started, and adhesive contact is path dependent):
        ``"retract"`` pulls the flat away from the closest distance, the branch of stiction.
    retries : int, default 1
        Fresh-solver retries of a solve whose residual stays above ``10 * solver_tolerance``.
    n_distance : int, optional
        About this many points per humidity on the default grid (fft_bem's).
    adhesion : bool, default True
        ``False``: dry contact (validation against Hertz).
    progress : bool or None, default None
        The size, Tamaas solves and estimated time are logged (logger ``roughstick``, INFO)
        before the run; runs estimated at 5 s or more show their progress in solves.
        ``True`` always, ``False`` never.

    Returns
    -------
    xarray.Dataset
        The curves layout over ``(..., rh, distance)`` plus ``distance_offset``
        (:math:`d_{local} - d`, m), ``solver_residual`` and ``solved`` (0 where interpolated,
        or where Tamaas stalled after the retries: counted in ``attrs["bem_unconverged"]``);
        attributes ``max_noncontact_deflection`` [m] and the solver statistics.

    Notes
    -----
    *Distance convention.* The solver imposes the mean gap :math:`\bar g`; ``distance`` is
    :math:`d = \bar g + \bar z`, the periodic convention where the elastic displacement has
    zero mean. Eq. 16's isolated-contact convention differs by
    :math:`d_{local} - d = \bar p A Z/(\pi E^*)` (``periodic_offset_coefficient`` of
    :mod:`roughstick.contact.fft_bem`), stored as ``distance_offset``; it vanishes at the
    equilibrium and :math:`\oint \bar p\, d\bar p = 0`, so Eq. 13, the pull-off pressure and the
    equilibrium distance are the same in either convention.

    *States with water but no hard contact* (:math:`d \ge \max z`) are evaluated as a Dugdale
    tension on the undeformed surface (the adhesive deflection neglected, as in Eq. 16; its
    largest value is ``attrs["max_noncontact_deflection"]``). Tamaas is serial: maps are solved
    one at a time per process (dask processes parallelise a stack).

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
