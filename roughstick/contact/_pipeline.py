"""The one pipeline every contact model runs through, and the dispatcher :func:`curves`.

:func:`apply` does, once for every model of the registry (:mod:`roughstick.contact._model`):
the checks of the height map (dtype, units, plausibility, memory, infinite pixels), the options
(typed, with their defaults), the relative humidity as the ``rh`` coordinate with
:math:`\\Delta P` (Eq. 2) and :math:`h_{water}` (Eq. 6), the distance grid (given, or the
model's default), the kernel mapped over the maps with ``xarray.apply_ufunc``, the Dataset of
:data:`roughstick.conventions.CURVE_VARIABLES` with its attributes and history, and the trust
checks (:mod:`roughstick.contact.trust`), whose :class:`~roughstick.contact.TrustReport` it
stores in the attributes. :func:`curves` chooses the model (``model="auto"``: the cheapest whose
measured error bound meets ``accuracy``) and calls :func:`apply`.
"""

from __future__ import annotations

import dataclasses
import logging
import threading
from collections.abc import Callable
from typing import Any

import numpy as np
import xarray as xr

from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.conventions import ATTRS, CURVE_VARIABLES, append_history, dataset_attrs
from .._core.dask import is_lazy
from .._core.materials import POLYSILICON, hertz_modulus, reduced_modulus
from .._core.memory import check_map_fits_in_memory
from .._core.progress import format_seconds
from .._core.validate import (
    MIN_MAP_PIXELS,
    as_relative_humidity,
    check_core_not_chunked,
    check_height_dtype,
    check_plausible_height,
    distance_array,
    grid_spacing,
    height_in_si,
    relative_humidity_coordinate,
    relative_humidity_values,
)
from ._model import MODELS, ContactModel, Grid, get_model, model_names
from .meniscus import laplace_pressure, water_height
from .trust.budget import model_bounds
from .trust.report import assess
from .trust.validity import VALIDITY_BOUND, NoModelMeetsAccuracy, select_model, shared_groups

__all__ = ["curves", "apply", "default_grid", "Context"]


@dataclasses.dataclass(eq=False)
class Context:
    """What a model's kernel and hooks see of one call (SI values).

    ``height``: the map(s) in m (None for a model given spectral moments); ``spacing``: pixel
    sizes ``(dy, dx)``; ``rh``: the relative humidity (the ``rh`` coordinate);
    ``water_height``, ``laplace_pressure``: :math:`h_{water}` [m] and :math:`\\Delta P` [Pa]
    per humidity as 1-D arrays (and as DataArrays in ``humidity``); ``reduced_modulus``
    :math:`E^*` and ``hertz_modulus`` :math:`K = 4E^*/3` [Pa]; ``options``: the model's options;
    ``state``: what a model derives for itself (settings, counters); ``step()``: progress,
    called by the kernel.
    """

    model: ContactModel
    height: xr.DataArray | None
    source: Any
    spacing: tuple[float, float] | None
    rh: xr.DataArray
    water_height: np.ndarray | None
    laplace_pressure: np.ndarray | None
    humidity: dict
    material: Any
    material2: Any
    adsorbed_layer: Any
    reduced_modulus: float
    hertz_modulus: float
    options: dict
    n_distance: int | None
    state: dict = dataclasses.field(default_factory=dict)
    step: Callable[[], None] = lambda: None

    @property
    def lead(self) -> tuple[str, ...]:
        """Dims of the input other than the map's ``(y, x)`` (e.g. ``realization``)."""
        src = self.height if self.height is not None else self.source
        return tuple(d for d in src.dims if d not in self.model.input_dims)


# --------------------------------------------------------------------------------- inputs


def check_height(height, *, memory: str | None, what: str | None = None) -> None:
    """The checks of a height map that no model repeats: memory (before anything is allocated),
    dtype, infinite pixels and the plausibility of its units (eager maps with units)."""
    if not isinstance(height, xr.DataArray):
        return
    if memory is not None:
        check_map_fits_in_memory(height, model=memory, what=what)
    check_height_dtype(height)
    if height.chunks is not None:
        return
    values = np.asarray(height)
    if values.dtype.kind == "f" and np.isinf(values).any():
        infinite = np.isinf(values)
        iy, ix = (int(i[0]) for i in np.nonzero(infinite)[-2:])
        raise ValueError(
            f"height has {int(infinite.sum())} infinite pixel(s) (the first at y index {iy}, x "
            f"index {ix}): an infinite height is not a surface (one +inf summit moved Γ by 16 %). "
            "Set them to NaN (missing pixels are skipped by the modified DMT) or crop them away."
        )
    if "units" in height.attrs:
        # a unit mistake (nm labelled m) is refused before any model or validity lookup; other
        # problems of the map (coordinates, size) are left to the messages that follow
        si = height_in_si(height)
        try:
            steps = [grid_spacing(si, d, min_pixels=2, purpose="a contact map") for d in ("x", "y")]
        except ValueError:
            return
        check_plausible_height(si, *steps)


def _check_is_map(height) -> None:
    if not isinstance(height, xr.DataArray):
        raise TypeError(
            "height must be an xarray.DataArray with dims (..., y, x) and units; wrap a numpy "
            "array with roughstick.testing.make_topography(values, spacing=...)."
        )


def _map(height) -> tuple[xr.DataArray, tuple[float, float]]:
    _check_is_map(height)
    height = height_in_si(height)
    spacing = tuple(grid_spacing(height, d, min_pixels=MIN_MAP_PIXELS, purpose="a contact map")
                    for d in ("y", "x"))
    check_core_not_chunked(height, ["y", "x"])
    return height, spacing


def _context(model, source, *, relative_humidity, material, material2, adsorbed_layer, n_distance,
             options) -> Context:
    moments = model.accepts_moments and not isinstance(source, xr.DataArray)
    height, spacing = (None, None) if moments else _map(source)
    if model.broadcast_humidity:
        rh = as_relative_humidity(relative_humidity)
    else:
        rh = relative_humidity_coordinate(relative_humidity)
    hw = water_height(rh, adsorbed_layer=adsorbed_layer)
    dp = laplace_pressure(rh)
    one_d = not is_lazy(rh) and rh.ndim <= 1 and (rh.ndim == 0 or rh.dims == ("rh",))
    e_star = reduced_modulus(material, material2)
    return Context(
        model=model, height=height, source=source, spacing=spacing, rh=rh,
        water_height=np.atleast_1d(np.asarray(hw.values, dtype=float)) if one_d else None,
        laplace_pressure=np.atleast_1d(np.asarray(dp.values, dtype=float)) if one_d else None,
        humidity={"water_height": hw, "laplace_pressure": dp},
        material=material, material2=material2, adsorbed_layer=adsorbed_layer,
        reduced_modulus=e_star, hertz_modulus=hertz_modulus(material, material2), options=options,
        n_distance=n_distance)


# ----------------------------------------------------------------------------------- grid


def _one_map(ctx: Context) -> np.ndarray:
    h = ctx.height
    if h.ndim != 2 or is_lazy(h):
        name = ctx.model.name
        raise ValueError(
            f"the automatic distance grid of {name} needs one eager (y, x) map; for stacks or dask "
            "maps pass distance= explicitly so that all maps share one grid, e.g. the automatic "
            "grid of one map: distance=roughstick.contact.curves(height.isel(realization=0)"
            f".compute(), relative_humidity=..., model={name!r}).distance.values."
        )
    return np.asarray(h.transpose("y", "x").values, dtype=float)


def _grid(ctx: Context, distance) -> Grid:
    if distance is not None:
        return Grid(distance_array(distance, min_size=ctx.model.min_distances), automatic=False)
    if ctx.model.default_grid is None:
        raise ValueError(f"model {ctx.model.name!r} has no automatic distance grid: pass distance=.")
    z = _one_map(ctx) if ctx.model.grid_needs_one_map else None
    return ctx.model.default_grid(z, ctx)


def _run_maps(ctx: Context, grid: Grid) -> dict:
    """The kernel over every map (``xarray.apply_ufunc``: vectorised over the leading dims, lazy
    for dask maps); {variable: DataArray (..., rh, distance)}."""
    model = ctx.model
    lead = list(ctx.lead)
    names = model.solved_variables
    where = grid.per_rh if grid.per_rh is not None else grid.distance

    def one(z):
        out = model.kernel(z, where, ctx)
        return tuple(out[n] for n in names) if len(names) > 1 else out[names[0]]

    outs = xr.apply_ufunc(
        one,
        ctx.height.transpose(*lead, "y", "x"),
        input_core_dims=[["y", "x"]],
        output_core_dims=[["rh", "distance"]] * len(names),
        vectorize=bool(lead),
        dask="parallelized",
        output_dtypes=[float] * len(names),
        dask_gufunc_kwargs={"output_sizes": {"rh": ctx.water_height.size, "distance": grid.distance.size}},
    )
    return dict(zip(names, outs if isinstance(outs, tuple) else (outs,), strict=True))


# ------------------------------------------------------------------------------- Dataset


def _assemble(ctx: Context, grid: Grid, data: dict) -> xr.Dataset:
    """The curves Dataset in the common layout: ``CURVE_VARIABLES`` (those the model does not
    compute are NaN), the model's extra variables, coordinates ``rh``, ``distance``,
    ``water_height`` and ``laplace_pressure`` with the attributes of ``conventions.ATTRS``."""
    model = ctx.model
    layout = (*CURVE_VARIABLES, *model.extra_variables)
    ds = xr.Dataset({k: (("rh", "distance"), v) if not isinstance(v, xr.DataArray) else v
                     for k, v in data.items()})
    coords = {"distance": ("distance", grid.distance, dict(ATTRS["distance"]))}
    rh, hw, dp = ctx.rh, ctx.humidity["water_height"], ctx.humidity["laplace_pressure"]
    if not model.broadcast_humidity:  # the rh coordinate, scalar or 1-D, known in advance
        coords.update(rh=("rh", np.atleast_1d(np.asarray(rh.values, dtype=float)), dict(ATTRS["rh"])),
                      water_height=("rh", ctx.water_height, dict(ATTRS["water_height"])),
                      laplace_pressure=("rh", ctx.laplace_pressure, dict(ATTRS["laplace_pressure"])))
    else:  # broadcast with the inputs: any dims, lazy too
        coords.update(water_height=hw.variable.copy(deep=False), laplace_pressure=dp.variable.copy(deep=False))
        coords["water_height"].attrs = dict(ATTRS["water_height"])
        coords["laplace_pressure"].attrs = dict(ATTRS["laplace_pressure"])
    ds = ds.assign_coords(coords)
    for name in CURVE_VARIABLES:
        if name not in ds:
            ds[name] = xr.full_like(ds["pressure"], np.nan)
    ds = ds[[n for n in layout if n in ds] + [n for n in ds.data_vars if n not in layout]]
    extra = model.variable_attrs(ctx) if model.variable_attrs is not None else {}
    for name in ds.data_vars:
        ds.variables[name].attrs = {**ATTRS.get(name, {}), **extra.get(name, {})}
    for name in ds.coords:
        if name in ATTRS and not ds[name].attrs:
            ds[name].attrs = dict(ATTRS[name])
    if rh.ndim == 0 and "rh" in ds.dims:
        ds = ds.squeeze("rh")
    src = ctx.height if ctx.height is not None else ctx.source
    for c in ctx.lead:
        if c in src.coords:
            ds = ds.assign_coords({c: src[c]})
    return ds


# --------------------------------------------------------------------------------- apply


def _prepared(entry, height, *, options, **kwargs) -> Context:
    """Options bound and checked, the height checked, the context built and prepared."""
    opts = entry.bind(options)
    check_height(height, memory=entry.memory_row(opts))
    ctx = _context(entry, height, options=opts, **kwargs)
    if entry.prepare is not None:
        entry.prepare(ctx)
    return ctx


def default_grid(model, height, *, relative_humidity, material=POLYSILICON, material2=None,
                 adsorbed_layer="paper", n_distance=None, **options) -> Grid:
    """The automatic distance grid of ``model`` on ``height`` (and what it computed on the way)."""
    entry = model if isinstance(model, ContactModel) else get_model(model)
    ctx = _prepared(entry, height, relative_humidity=relative_humidity, material=material,
                    material2=material2, adsorbed_layer=adsorbed_layer, n_distance=n_distance,
                    options=options)
    return _grid(ctx, None)



def apply(model, height, *, relative_humidity, distance=None, material=POLYSILICON, material2=None,
          adsorbed_layer="paper", n_distance=None, accuracy=VALIDITY_BOUND,
          quantity="adhesive_energy", check_validity=False, selection=None, **options) -> xr.Dataset:
    """Curves of ``height`` by the registered model ``model`` (its name or a ContactModel).

    The shared pipeline (module docstring); ``check_validity`` runs the trust checks that apply
    to the model (``selection``: why ``model="auto"`` chose it). Used by :func:`curves` and by
    the public function of each model.
    """
    entry = model if isinstance(model, ContactModel) else get_model(model)
    ctx = _prepared(entry, height, relative_humidity=relative_humidity, material=material,
                    material2=material2, adsorbed_layer=adsorbed_layer, n_distance=n_distance,
                    options=options)
    grid = _grid(ctx, distance)
    if grid.curves is not None:
        data = dict(grid.curves)
    else:
        bar = entry.progress(ctx, grid) if entry.progress is not None else None
        if bar is not None:
            ctx.step = bar.update
        try:
            data = (entry.run or _run_maps)(ctx, grid)
        finally:
            if bar is not None:
                bar.close()
    ds = _assemble(ctx, grid, data)
    attrs, history = entry.describe(ctx, grid) if entry.describe is not None else ({}, entry.name)
    ds.attrs = dataset_attrs(
        entry.title, references=entry.references, contact_model=entry.name, **attrs,
        adsorbed_layer=str(getattr(adsorbed_layer, "__name__", adsorbed_layer)),
        distance_grid="automatic" if grid.automatic else "given",
    )
    append_history(ds, history)
    if entry.finish is not None:
        entry.finish(ds, ctx)
    with shared_groups():  # the checks below compute the map's groups once
        report = assess(entry, ctx.height if ctx.height is not None else height,
                        relative_humidity=relative_humidity, material=material, material2=material2,
                        adsorbed_layer=adsorbed_layer, accuracy=accuracy, quantity=quantity,
                        check=check_validity, selection=selection)
        ds.attrs.update(report.to_attrs())
        if check_validity and isinstance(height, xr.DataArray):
            _budget(ds, entry, ctx.height if ctx.height is not None else height,
                    relative_humidity=relative_humidity, material=material, material2=material2,
                    adsorbed_layer=adsorbed_layer)
    return ds


def _budget(ds, entry, height, *, relative_humidity, material, material2, adsorbed_layer) -> None:
    """The model's measured error bounds per humidity in ``ds.attrs`` (read by
    :func:`roughstick.contact.summary` and :func:`roughstick.contact.error_budget`)."""
    rhs = relative_humidity_values(relative_humidity)
    if getattr(height, "chunks", None) is not None or not (rhs.size and np.all((rhs > 0) & (rhs < 1))):
        return
    try:
        bounds = model_bounds(entry.name, height, relative_humidity=relative_humidity,
                              material=material, material2=material2, adsorbed_layer=adsorbed_layer)
    except ValueError:  # no finite pixel to compute the groups of: nothing to bound
        return
    for q, b in bounds.items():
        ds.attrs[f"model_error_bound_{q}"] = b


# ------------------------------------------------------------------------------ dispatch


def _check_accuracy(accuracy):
    if not (isinstance(accuracy, (int, float)) and not isinstance(accuracy, bool)
            and 0 < accuracy < np.inf):
        raise ValueError(
            f"accuracy must be a positive relative error (e.g. 0.1 for 10 %), got {accuracy!r}; "
            "the solver tolerance of fft_bem/bem is solver_tolerance=."
        )


def _choose(height, *, relative_humidity, material, material2, adsorbed_layer, accuracy, quantity,
            options, distance, n_distance):
    """``model="auto"``: the cheapest registered model whose measured error bound at this
    surface's groups meets ``accuracy``, the options it takes, and why."""
    known = {name for m in MODELS.values() for name in m.options}
    unexpected = sorted(set(options) - known)
    if unexpected:
        raise TypeError(f"unexpected keyword argument(s) {unexpected} for model='auto'.")
    ranked = [MODELS[n] for n in model_names() if MODELS[n].cost_rank is not None]
    check_height(height, memory=ranked[0].memory_row({}) if ranked else None,
                 what=f"model='auto' (even with its cheapest model, {ranked[0].name})" if ranked else None)
    candidates = tuple(m.name for m in ranked)
    nan_map = getattr(height, "chunks", None) is None and bool(np.isnan(np.asarray(height)).any())
    if nan_map:  # the models that need a complete map are out
        candidates = tuple(m.name for m in ranked if not m.complete_map)
    try:
        name, reason = select_model(height, relative_humidity=relative_humidity, accuracy=accuracy,
                                    quantity=quantity, candidates=candidates, material=material,
                                    material2=material2, adsorbed_layer=adsorbed_layer)
    except NoModelMeetsAccuracy as err:
        if not nan_map:
            raise
        out = ", ".join(m.name for m in ranked if m.complete_map)
        raise NoModelMeetsAccuracy(
            f"{err} The map has NaN pixels, which the models that need a complete map ({out}) "
            "cannot take: crop or fill them, or pass model='modified_dmt' knowingly."
        ) from None
    chosen = MODELS[name]
    if chosen.positive_mean_gap and distance is not None:
        _check_gap_for_auto(height, distance, chosen.name)
    _announce(chosen, reason, height, relative_humidity, distance, n_distance)
    return name, reason, {k: v for k, v in options.items() if k in chosen.options}


def _check_gap_for_auto(height, distance, name) -> None:
    """Refuse, before the work, given distances at or below a map's mean plane when
    ``model="auto"`` chose a model that needs a positive mean gap, naming both fixes."""
    d = np.asarray(getattr(distance, "values", distance), dtype=float)
    if d.size == 0:
        return
    plane = float(height.mean(("y", "x"), skipna=True).max())  # a lazy map: one pass, no model
    if float(np.nanmin(d)) <= plane:
        raise ValueError(
            f"model='auto' chose {name} (the cheaper models are not within the accuracy on this "
            f"surface), which needs every distance above the maps' mean plane ({plane:.3g} m; "
            f"below it the mean gap is <= 0, full contact), but the smallest given distance is "
            f"{float(np.nanmin(d)):.3g} m. Pass distances above the mean plane (or distance=None "
            "for the automatic grid), or model='modified_dmt' knowingly (Eq. 16 takes any "
            "distance, with the error bound it warns about).")


def _announce(model, reason, height, relative_humidity, distance, n_distance) -> None:
    """Say ``model="auto"``'s choice, why, and its estimated cost before the work starts (logger
    ``roughstick``, INFO; DEBUG inside a task of a larger computation, which has its own)."""
    lead = [d for d in height.dims if d not in ("y", "x")]
    n = int(np.prod([height.sizes[d] for d in lead])) * max(relative_humidity_values(relative_humidity).size, 1)
    points = (np.size(distance) if distance is not None else
              int(1.3 * n_distance) if n_distance is not None else 47)  # fft_bem's automatic grid
    shape = (height.sizes["y"], height.sizes["x"])
    cost = ("an unknown time" if model.estimate_seconds is None else
            format_seconds(model.estimate_seconds(shape, n, points)) + " (within a factor ~3)")
    main = threading.current_thread() is threading.main_thread()
    logging.getLogger("roughstick").log(
        logging.INFO if main else logging.DEBUG,
        f"contact model auto -> {model.name} for {n} curve(s) of {shape[0]} x {shape[1]} pixels, "
        f"estimated {cost}: {reason}")


@renamed_keywords(tolerance="accuracy")
@check_numbers(n_distance="count?")  # accuracy: _check_accuracy (its message names solver_tolerance)
def curves(
    height: xr.DataArray,
    *,
    relative_humidity,
    model: str = "auto",
    distance=None,
    material=POLYSILICON,
    material2=None,
    adsorbed_layer="paper",
    n_distance: int | None = None,
    accuracy: float = VALIDITY_BOUND,
    quantity: str = "adhesive_energy",
    check_validity: bool = True,
    **options,
) -> xr.Dataset:
    r"""Force-distance curves of a rough surface against a flat in humid air, by any model.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, at least 8 x 8 pixels, units length (converted to m),
        uniform pixel-centre coords; attribute ``periodic`` (1: generated, wraps round).
    relative_humidity : float, sequence or xarray.DataArray
        RH as fractions in (0, 1); a sequence gives an ``rh`` dimension.
    model : str, default "auto"
        ``"auto"``: the cheapest registered model whose measured error bound at this surface's
        groups meets ``accuracy`` at every requested humidity
        (:func:`roughstick.contact.select_model`), said before the work with its estimated time
        (logger ``roughstick``, INFO) and recorded in ``attrs["model_selection"]``. Or a
        registered contact model by name (:data:`roughstick.contact.MODELS`): ``"modified_dmt"``
        (the paper's model, Eq. 16), ``"gw"`` (Eq. 14, on the map's moments), ``"fft_bem"`` (the
        FFT boundary-element model), ``"bem"`` (the Tamaas reference).
    distance : array-like or xarray.DataArray, optional
        Distances ``d`` [m] from the flat to the mean plane of the heights. Default: the model's
        automatic grid (one eager map; Greenwood-Williamson: any moments).
    material, material2 : roughstick.Material
        The two bodies (``material2=None``: same as ``material``); poly-silicon by default.
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-water model of :func:`roughstick.contact.water_height`.
    n_distance : int, optional
        At least this many points of the automatic grid.
    accuracy : float, default 0.10
        Accepted relative error of ``quantity`` against the boundary-element reference:
        ``model="auto"`` picks a model that meets it; a model with the ``"validity"`` check (the
        modified DMT) warns (:class:`roughstick.contact.ValidityWarning`) where its bound exceeds it.
    quantity : {"adhesive_energy", "pull_off_pressure", "equilibrium_distance", "all"}
        The summary the accuracy applies to.
    check_validity : bool, default True
        ``False`` skips the trust checks (used by ensembles, which check once before they start).
    **options
        The chosen model's options (e.g. ``connectivity`` of the modified DMT,
        ``solver_tolerance`` of fft_bem and bem, ``sphere_model`` of GW: see each model's
        function); a keyword the model does not take is a ``TypeError``.

    Returns
    -------
    xarray.Dataset
        The model's curves over ``(..., rh, distance)`` in the common layout
        (:data:`roughstick.conventions.CURVE_VARIABLES`, docs/architecture.md); the trust checks
        in ``attrs`` (:class:`roughstick.contact.TrustReport`); ``history`` ends with the model.

    Examples
    --------
    >>> h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    >>> ds = rs.contact.curves(h, relative_humidity=[0.3, 0.7], model="fft_bem")
    >>> ds.pressure.dims, ds.attrs["contact_model"]
    (('rh', 'distance'), 'fft_bem')
    """
    if model != "auto":
        get_model(model)
    _check_accuracy(accuracy)
    _check_is_map(height)
    reason = None
    if model == "auto":
        model, reason, options = _choose(
            height, relative_humidity=relative_humidity, material=material, material2=material2,
            adsorbed_layer=adsorbed_layer, accuracy=accuracy, quantity=quantity, options=options,
            distance=distance, n_distance=n_distance)
    ds = apply(model, height, relative_humidity=relative_humidity, distance=distance,
               material=material, material2=material2, adsorbed_layer=adsorbed_layer,
               n_distance=n_distance, accuracy=accuracy, quantity=quantity,
               check_validity=check_validity, selection=reason, **options)
    return append_history(ds, f"roughstick.contact.curves(model={model!r})"
                              + (" chosen by model='auto'" if reason is not None else ""))
