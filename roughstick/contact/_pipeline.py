"""ONE entry point for the force-distance curves of a rough surface: :func:`rough_contact_curves`.

It sits above the models and chooses between them; the models never import it:

- ``model="modified_dmt"``: :func:`roughstick.contact.rough.modified_dmt_curves` (Eqs. 16-23),
  with a :class:`~roughstick.ValidityWarning` where the measured error bound of the modified DMT
  at this surface's dimensionless groups exceeds ``tolerance`` (docs/accuracy.md);
- ``model="gw"``: :func:`roughstick.contact.gw.gw_contact_curves` (Eq. 14) on the map's own
  moments, by the same estimator as ``gw_contact_curves(height)`` (so both entry points agree);
- ``model="fft_bem"``: :func:`roughstick.contact.fft_bem.fft_bem_contact_curves`, the fast FFT
  boundary-element model (the reference's physics at 1/114-1/320 of its cost, 256²-512², docs/accuracy.md);
- ``model="bem"``: :func:`roughstick.contact.bem.bem_contact_curves` (Tamaas extra);
- ``model="auto"``: the cheapest model whose measured error bound at *this surface's* groups meets
  ``tolerance`` (:func:`roughstick.contact.validity.select_model`), recorded in
  ``attrs["model_selection"]``.
"""

from __future__ import annotations

import logging
import threading

import numpy as np
import xarray as xr

from .._core.arguments import check_numbers
from .._core.conventions import append_history
from .._core.materials import POLYSILICON
from .._core.memory import check_map_fits_in_memory
from .._core.progress import estimate_model_seconds, format_seconds
from .._core.validate import (
    MIN_MAP_PIXELS,
    check_height_dtype,
    check_plausible_height,
    distance_array,
    grid_spacing,
    height_in_si,
    relative_humidity_values,
)
from .bem._curves import bem_contact_curves
from .fft_bem._curves import automatic_grid_counts, fft_bem_contact_curves
from .gw._curves import gw_contact_curves
from .trust.pixel import RESOLVED_NECK_PIXELS, warn_if_unresolved
from .modified_dmt._curves import modified_dmt_curves
from .trust.validity import (
    MODEL_COST_ORDER,
    VALIDITY_BOUND,
    NoModelMeetsTolerance,
    select_model,
    warn_if_outside_validity,
)

__all__ = ["rough_contact_curves", "CONTACT_MODELS"]

#: Names accepted by ``rough_contact_curves(model=...)``.
CONTACT_MODELS = ("modified_dmt", "gw", "fft_bem", "bem", "auto")

# keyword arguments of bem_contact_curves that rough_contact_curves passes through
# (``solver_tolerance`` is the solver's own tolerance: ``tolerance`` is the accepted error)
_BEM_KWARGS = ("solver_tolerance", "max_iterations", "path", "retries", "adhesion", "progress")
_FFT_BEM_KWARGS = ("solver_tolerance", "max_iterations", "path", "adhesion", "precision", "progress",
                   "n_contact", "n_free", "refine")
# keyword arguments of gw_contact_curves that rough_contact_curves passes through
_GW_KWARGS = ("sphere_model", "curvature_limits", "height_cutoff", "curvature_measure",
              "apparent_area", "n_height", "n_curvature", "force_table", "moment_method", "qmax")


def _check_tolerance(tolerance):
    if not (isinstance(tolerance, (int, float)) and 0 < tolerance < np.inf):
        raise ValueError(
            f"tolerance must be a positive relative error (e.g. 0.1 for 10 %), got {tolerance!r}; "
            "the solver tolerance of fft_bem/bem is solver_tolerance=."
        )


@check_numbers(connectivity=(4, 8), n_distance="count?")  # tolerance: _check_tolerance
def rough_contact_curves(
    height: xr.DataArray,
    *,
    relative_humidity,
    distance=None,
    model: str = "modified_dmt",
    material=POLYSILICON,
    material2=None,
    adsorbed_layer="paper",
    connectivity: int = 4,
    periodic: bool | None = None,
    n_distance: int | None = None,
    tolerance: float = VALIDITY_BOUND,
    quantity: str = "adhesive_energy",
    check_validity: bool = True,
    **model_kwargs,
) -> xr.Dataset:
    r"""Force-distance curves of a rough surface against a flat in humid air, by any model.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, at least 8 x 8 pixels (every model), units length
        (converted to m), uniform pixel-centre coords; attribute ``periodic`` as in
        :func:`roughstick.modified_dmt_curves`.
    relative_humidity : float, sequence or xarray.DataArray
        RH as fractions in (0, 1); a sequence gives an ``rh`` dimension.
    distance : array-like or xarray.DataArray, optional
        Distances ``d`` [m] from the flat to the mean plane of the heights. Default: each model's
        automatic grid: :func:`roughstick.contact_distance_grid` for the modified DMT (eager 2-D
        maps only), the summit-height grid of :func:`roughstick.gw_contact_curves` for GW (its
        onset and equilibrium lie in the summits' Gaussian tail, above the highest pixel),
        fft_bem's own; at least ``n_distance`` points (the BEM's default count).
    model : {"modified_dmt", "gw", "fft_bem", "bem", "auto"}, default "modified_dmt"
        ``"modified_dmt"``: :func:`roughstick.modified_dmt_curves` (Eq. 16). ``"gw"``:
        :func:`roughstick.gw_contact_curves` (Eq. 14) on the moments of the map, estimated as
        ``gw_contact_curves(height)`` does (``moment_method``, default the paper's cubic-spline
        moments of Table 2), on the same distances. ``"fft_bem"``: the FFT boundary-element model
        :func:`roughstick.fft_bem_contact_curves` (valid where Eq. 16 is not; its own automatic
        grid when ``distance`` is None). ``"bem"``: the boundary-element reference
        :func:`roughstick.bem_contact_curves` (Tamaas extra). ``"auto"``: the cheapest model whose
        measured error bound at this surface's groups meets ``tolerance`` at every requested
        humidity (:func:`roughstick.select_model`), recorded in ``attrs["model_selection"]`` and
        said before the work, with the chosen model's estimated time (logger ``roughstick``,
        INFO).
    material, material2 : roughstick.Material
        The two bodies (``material2=None``: same as ``material``); poly-silicon by default.
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-water model of :func:`roughstick.water_height`.
    connectivity, periodic
        Asperity connectivity and periodicity of the modified DMT (also used for its grid).
    n_distance : int, optional
        Minimum size of the automatic distance grid (default: as many points as the modified-DMT
        curves need; the BEM's own default count).
    tolerance : float, default 0.10
        Accepted relative error of ``quantity`` against the boundary-element reference:
        ``model="auto"`` picks a model that meets it; ``model="modified_dmt"`` warns
        (:class:`roughstick.ValidityWarning`) where its measured bound exceeds it.
    quantity : {"adhesive_energy", "pull_off_pressure", "equilibrium_distance", "all"}
        The summary the tolerance applies to.
    check_validity : bool, default True
        ``False`` skips the surface-groups check of ``model="modified_dmt"`` (used by
        :func:`roughstick.run_ensemble`, which checks once before it starts).
    **model_kwargs
        Passed to the model: ``sphere_model``, ``curvature_limits``, ``height_cutoff``,
        ``moment_method``, ``qmax`` ... for GW; ``solver_tolerance``, ``max_iterations``,
        ``path``, ``adhesion`` (and ``retries``, ``progress`` for the BEM; ``precision``,
        ``n_contact``, ``n_free``, ``refine`` for fft_bem). The modified DMT takes none.

    Returns
    -------
    xarray.Dataset
        The model's curves over ``(..., rh, distance)`` in the common layout
        (:data:`roughstick.conventions.CURVE_VARIABLES`, docs/architecture.md); ``history`` ends
        with the model chosen.

    Raises
    ------
    ValueError
        Unknown ``model``; the model's own errors (see each model).
    TypeError
        Keyword arguments the chosen model does not take.

    Examples
    --------
    >>> h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    >>> ds = rs.rough_contact_curves(h, relative_humidity=[0.3, 0.7], model="fft_bem")
    >>> ds.pressure.dims, ds.attrs["contact_model"]
    (('rh', 'distance'), 'fft_bem')
    """
    if model not in CONTACT_MODELS:
        raise ValueError(f"model must be one of {CONTACT_MODELS}, got {model!r}.")
    _check_tolerance(tolerance)
    if isinstance(height, xr.DataArray):  # before anything is allocated ("auto": the cheapest model)
        key = "gw" if model == "auto" else model
        check_map_fits_in_memory(height, model="fft_bem_double" if key == "fft_bem" and
                                 model_kwargs.get("precision") == "double" else key,
                                 what="model='auto' (even with its cheapest model, gw)" if model == "auto" else None)
        check_height_dtype(height)
    if getattr(height, "chunks", None) is None and hasattr(height, "dims"):
        values = np.asarray(height)
        infinite = np.isinf(values) if values.dtype.kind == "f" else None
        if infinite is not None and infinite.any():
            iy, ix = (int(i[0]) for i in np.nonzero(infinite)[-2:])
            raise ValueError(
                f"height has {int(infinite.sum())} infinite pixel(s) (the first at "
                f"y index {iy}, x index {ix}): an infinite height is not a surface (one +inf "
                "summit moved Γ by 16 %). Set them to NaN (missing pixels are skipped by the "
                "modified DMT) or crop them away."
            )
        if isinstance(height, xr.DataArray) and "units" in height.attrs:
            # a unit mistake (nm labelled m) is refused before any model or validity lookup;
            # other problems of the map (coordinates, size) are left to the model's own message
            si = height_in_si(height)
            try:
                steps = [grid_spacing(si, d, min_pixels=2, purpose="a contact map") for d in ("x", "y")]
            except ValueError:
                steps = None
            if steps is not None:
                check_plausible_height(si, *steps)
    common = dict(relative_humidity=relative_humidity, material=material, material2=material2,
                  adsorbed_layer=adsorbed_layer)
    reason = None
    if model == "auto":
        allowed_auto = set(_GW_KWARGS) | set(_BEM_KWARGS) | set(_FFT_BEM_KWARGS)
        unexpected = sorted(set(model_kwargs) - allowed_auto)
        if unexpected:
            raise TypeError(f"unexpected keyword argument(s) {unexpected} for model='auto'.")
        candidates = MODEL_COST_ORDER
        if getattr(height, "chunks", None) is None and bool(np.isnan(np.asarray(height)).any()):
            # the boundary-element models need a complete map
            candidates = ("gw", "modified_dmt")
        try:
            model, reason = select_model(height, tolerance=tolerance, quantity=quantity,
                                         candidates=candidates, **common)
        except NoModelMeetsTolerance as err:  # only the NaN pixels kept the BEM models out
            raise NoModelMeetsTolerance(
                f"{err} The map has NaN pixels, which the boundary-element models (fft_bem, "
                "bem) cannot take: crop or fill them, or pass model='modified_dmt' knowingly."
            ) from None
        allowed = {"modified_dmt": (), "gw": _GW_KWARGS, "fft_bem": _FFT_BEM_KWARGS,
                   "bem": _BEM_KWARGS}[model]
        model_kwargs = {k: v for k, v in model_kwargs.items() if k in allowed}
        _announce(model, reason, height, relative_humidity, distance, n_distance)
    allowed = {"modified_dmt": (), "gw": _GW_KWARGS, "fft_bem": _FFT_BEM_KWARGS,
               "bem": _BEM_KWARGS}[model]
    unexpected = sorted(set(model_kwargs) - set(allowed))
    if unexpected:
        raise TypeError(f"unexpected keyword argument(s) {unexpected} for model={model!r}.")
    kwargs = dict(model_kwargs)
    if "solver_tolerance" in kwargs:
        kwargs["tolerance"] = kwargs.pop("solver_tolerance")
    if model == "modified_dmt":
        ds = modified_dmt_curves(height, distance=distance, connectivity=connectivity,
                                 periodic=periodic, n_distance=n_distance, **common)
        # checked after the model validated the input (its errors name the fix first)
        validity_note = None
        if check_validity and reason is None:
            rhs = relative_humidity_values(relative_humidity)
            if getattr(height, "chunks", None) is not None:
                # a lazy stack stays lazy: its groups would need a computation
                validity_note = (
                    "not checked (lazy input); check one map with "
                    "roughstick.warn_if_outside_validity(height.isel(...).compute(), ...)"
                )
            elif rhs.size and np.all((rhs > 0) & (rhs < 1)):
                warned = warn_if_outside_validity(height, tolerance=tolerance,
                                                  quantity=quantity, **common)
                validity_note = (f"measured error bound above the tolerance {tolerance:g}"
                                 if warned else
                                 f"measured error bound within the tolerance {tolerance:g}")
        if validity_note is not None:
            ds.attrs["validity_check"] = validity_note
    elif model == "gw":
        height = height_in_si(height)
        kwargs.setdefault("apparent_area", height.sizes["x"] * height.sizes["y"]
                          * grid_spacing(height, "x", min_pixels=MIN_MAP_PIXELS, purpose="a contact map")
                          * grid_spacing(height, "y", min_pixels=MIN_MAP_PIXELS, purpose="a contact map"))
        if distance is None:  # GW's own grid, set by the summit heights, not the pixels
            ds = gw_contact_curves(height, n_distance=n_distance, **common, **kwargs)
        else:
            ds = gw_contact_curves(height, distance=distance_array(distance), **common, **kwargs)
    elif model == "fft_bem":
        if distance is None and n_distance is not None and not {"n_contact", "n_free"} & set(kwargs):
            # its automatic grid has n_contact + n_free points plus the refinement's
            kwargs.update(automatic_grid_counts(n_distance))
        ds = fft_bem_contact_curves(height, distance=distance, **common, **kwargs)
    else:
        ds = bem_contact_curves(height, distance=distance, **common,
                                **({} if n_distance is None else {"n_distances": n_distance}),
                                **kwargs)
    if check_validity and model != "gw":  # GW's curves come from summit moments, not pixels
        ds.attrs["resolution_check"] = _resolution_check(height, relative_humidity, adsorbed_layer)
    if reason is not None:
        ds.attrs["model_selection"] = f"auto -> {model}: {reason}"
    return append_history(ds, f"rough_contact_curves(model={model!r})"
                              + (" chosen by model='auto'" if reason is not None else ""))


def _announce(model, reason, height, relative_humidity, distance, n_distance) -> None:
    """Say ``model="auto"``'s choice, why, and its estimated cost before the work starts (logger
    ``roughstick``, INFO; DEBUG inside a task of a larger computation, which has its own)."""
    lead = [d for d in height.dims if d not in ("y", "x")]
    curves = int(np.prod([height.sizes[d] for d in lead])) * max(relative_humidity_values(relative_humidity).size, 1)
    points = (np.size(distance) if distance is not None else
              int(1.3 * n_distance) if n_distance is not None else 47)  # fft_bem's automatic grid
    cost = estimate_model_seconds(model, (height.sizes["y"], height.sizes["x"]), curves, points)
    main = threading.current_thread() is threading.main_thread()
    logging.getLogger("roughstick").log(
        logging.INFO if main else logging.DEBUG,
        f"contact model auto -> {model} for {curves} curve(s) of {height.sizes['y']} x {height.sizes['x']} "
        f"pixels, estimated {format_seconds(cost)} (within a factor ~3): {reason}")


def _resolution_check(height, relative_humidity, adsorbed_layer) -> str:
    """Warn where the pixel does not resolve the water necks; the note for ``attrs``."""
    if getattr(height, "chunks", None) is not None:
        return ("not checked (lazy input); check one map with "
                "roughstick.warn_if_unresolved(height.isel(...).compute(), relative_humidity=...)")
    rhs = relative_humidity_values(relative_humidity)
    if not (rhs.size and np.all((rhs > 0) & (rhs < 1))):
        return "not checked (relative humidity outside (0, 1))"
    if warn_if_unresolved(height, relative_humidity=relative_humidity, adsorbed_layer=adsorbed_layer):
        return (f"wetted necks narrower than {RESOLVED_NECK_PIXELS:g} pixels: the pixel sets "
                "the adhesive energy (check with roughstick.resolution_study)")
    return f"wetted necks span at least {RESOLVED_NECK_PIXELS:g} pixels at every humidity"
