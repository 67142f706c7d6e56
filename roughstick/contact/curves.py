"""ONE entry point for the force-distance curves of a rough surface: :func:`rough_contact_curves`.

It sits above the models and chooses between them; the models never import it:

- ``model="modified_dmt"``: :func:`roughstick.contact.rough.modified_dmt_curves` (Eqs. 16-23),
  with a once-per-process :class:`~roughstick.ValidityWarning` where the measured error of the
  modified DMT against the boundary-element reference exceeds 10 % (docs/accuracy.md);
- ``model="gw"``: :func:`roughstick.contact.gw.gw_contact_curves` (Eq. 14) on the map's own
  moments, by the same estimator as ``gw_contact_curves(height)`` (so both entry points agree);
- ``model="bem"``: :func:`roughstick.contact.bem.bem_contact_curves` (Tamaas extra);
- ``model="auto"``: the cheapest of the three whose measured error meets ``error_tolerance``
  (:func:`roughstick.contact.validity.select_model`), recorded in ``attrs["model_selection"]``.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .._core.conventions import append_history
from .._core.materials import POLYSILICON
from .._core.units import require
from .._core.validate import distance_array, relative_humidity_values
from .bem import bem_contact_curves
from .gw import gw_contact_curves
from .rough import _spacing, contact_distance_grid, modified_dmt_curves
from .validity import VALIDITY_BOUND, select_model, warn_if_outside_validity

__all__ = ["rough_contact_curves", "CONTACT_MODELS"]

#: Names accepted by ``rough_contact_curves(model=...)``.
CONTACT_MODELS = ("modified_dmt", "gw", "bem", "auto")

# keyword arguments of bem_contact_curves that rough_contact_curves passes through
_BEM_KWARGS = ("tolerance", "max_iterations", "path", "retries", "adhesion")
# keyword arguments of gw_contact_curves that rough_contact_curves passes through
_GW_KWARGS = ("sphere_model", "curvature_limits", "height_cutoff", "curvature_measure",
              "apparent_area", "n_height", "n_curvature", "force_table", "moment_method", "qmax")


def _auto_model(relative_humidity, *, error_tolerance, quantity, material, material2):
    """(model, reason): the costliest of the per-humidity choices of :func:`select_model`."""
    rhs = relative_humidity_values(relative_humidity)
    order = {"gw": 0, "modified_dmt": 1, "bem": 2}
    model, reason = "gw", None
    for r in rhs if rhs.size else [np.nan]:
        if not np.isfinite(r):
            m, why = "bem", "humidity not known before computing; BEM chosen to be safe"
        else:
            m, why = select_model(tolerance=error_tolerance, relative_humidity=float(r),
                                  material=material, material2=material2, quantity=quantity)
        if reason is None or order[m] > order[model]:
            model, reason = m, why
    return model, reason


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
    error_tolerance: float = VALIDITY_BOUND,
    quantity: str = "adhesive_energy",
    **model_kwargs,
) -> xr.Dataset:
    r"""Force-distance curves of a rough surface against a flat in humid air, by any model.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, units length (converted to m), uniform pixel-centre
        coords; attribute ``periodic`` as in :func:`roughstick.modified_dmt_curves`.
    relative_humidity : float, sequence or xarray.DataArray
        RH as fractions in (0, 1); a sequence gives an ``rh`` dimension.
    distance : array-like or xarray.DataArray, optional
        Distances ``d`` [m] from the flat to the mean plane of the heights. Default: the automatic
        grid of :func:`roughstick.contact_distance_grid` (``n_distance`` points; eager 2-D maps
        only), for every model (the BEM takes ``n_distance`` as its own default count).
    model : {"modified_dmt", "gw", "bem", "auto"}, default "modified_dmt"
        ``"modified_dmt"``: :func:`roughstick.modified_dmt_curves` (Eq. 16). ``"gw"``:
        :func:`roughstick.gw_contact_curves` (Eq. 14) on the moments of the map, estimated as
        ``gw_contact_curves(height)`` does (``moment_method``, default the paper's cubic-spline
        moments of Table 2), on the same distances. ``"bem"``: the boundary-element reference
        :func:`roughstick.bem_contact_curves` (Tamaas extra). ``"auto"``: the cheapest model whose
        measured error against the BEM meets ``error_tolerance`` (:func:`roughstick.select_model`
        at the worst requested humidity), recorded in ``attrs["model_selection"]``.
    material, material2 : roughstick.Material
        The two bodies (``material2=None``: same as ``material``); poly-silicon by default.
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-water model of :func:`roughstick.water_height`.
    connectivity, periodic
        Asperity connectivity and periodicity of the modified DMT (also used for its grid).
    n_distance : int, optional
        Minimum size of the automatic distance grid (default: as many points as the modified-DMT
        curves need; the BEM's own default count).
    error_tolerance : float, default 0.10
        ``model="auto"`` only: accepted relative error of ``quantity`` against the BEM.
    quantity : {"adhesive_energy", "pull_off_pressure", "equilibrium_distance"}
        ``model="auto"`` only: the summary the tolerance applies to.
    **model_kwargs
        Passed to the model: ``sphere_model``, ``curvature_limits``, ``height_cutoff``,
        ``moment_method``, ``qmax`` ... for GW; ``tolerance``, ``max_iterations``, ``path``,
        ``retries``, ``adhesion`` for the BEM. The modified DMT takes none.

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
    >>> ds = rs.rough_contact_curves(h, relative_humidity=[0.3, 0.7], distance=[-1e-9, 1e-9])
    >>> ds.pressure.dims, ds.attrs["contact_model"]
    (('rh', 'distance'), 'modified_dmt')
    """
    if model not in CONTACT_MODELS:
        raise ValueError(f"model must be one of {CONTACT_MODELS}, got {model!r}.")
    reason = None
    if model == "auto":
        model, reason = _auto_model(relative_humidity, error_tolerance=error_tolerance,
                                    quantity=quantity, material=material, material2=material2)
    allowed = {"modified_dmt": (), "gw": _GW_KWARGS, "bem": _BEM_KWARGS}[model]
    unexpected = sorted(set(model_kwargs) - set(allowed))
    if unexpected:
        raise TypeError(f"unexpected keyword argument(s) {unexpected} for model={model!r}.")
    common = dict(relative_humidity=relative_humidity, material=material, material2=material2,
                  adsorbed_layer=adsorbed_layer)
    if model == "modified_dmt":
        rhs = relative_humidity_values(relative_humidity)
        rhs = rhs[(rhs > 0) & (rhs < 1)]
        if rhs.size:  # once-per-process ValidityWarning outside the measured regime
            warn_if_outside_validity(relative_humidity=rhs, material=material, material2=material2)
        ds = modified_dmt_curves(height, distance=distance, connectivity=connectivity,
                                 periodic=periodic, n_distance=n_distance, **common)
    elif model == "gw":
        height = require(height, "length", name="height")
        if distance is None:
            distance = contact_distance_grid(height, n=n_distance, connectivity=connectivity,
                                             periodic=periodic, **common)
        kwargs = dict(model_kwargs)
        kwargs.setdefault("apparent_area", height.sizes["x"] * height.sizes["y"]
                          * _spacing(height, "x") * _spacing(height, "y"))
        ds = gw_contact_curves(height, distance=distance_array(distance), **common, **kwargs)
    else:
        ds = bem_contact_curves(height, distance=distance, **common,
                                **({} if n_distance is None else {"n_distances": n_distance}),
                                **model_kwargs)
    if reason is not None:
        ds.attrs["model_selection"] = f"auto -> {model}: {reason}"
    return append_history(ds, f"rough_contact_curves(model={model!r})"
                              + (" chosen by model='auto'" if reason is not None else ""))
