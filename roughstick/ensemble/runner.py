r"""The entry point of the Monte Carlo ensembles: :func:`run` (paper §4.3, Figs. 14-17).

:func:`run` builds the pipeline ``generate_surfaces`` → contact curves → adhesion summary
(:mod:`.pipeline`) as one Dataset over ``(realization, rh, distance)`` and ``(realization, rh)``,
chunked over realization and humidity; nothing is computed until asked. With ``output=folder`` it
streams one CF NetCDF file per block into ``folder`` as blocks complete and resumes from what is
there (:mod:`.store`, :mod:`.execute`); with ``n="auto"`` realizations are added in batches until
the band of Γ and of the pressure curve stops moving. :func:`surface_size_study` repeats it at
several surface sizes on one distance grid.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import logging
import math
import pathlib
import time
import warnings
from collections.abc import Callable, Sequence

import numpy as np
import xarray as xr

from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.conventions import ATTRS, append_history
from .._core.dask import as_seed_sequence
from .._core.materials import POLYSILICON, as_material
from .._core.progress import estimate_model_seconds, format_seconds
from .._core.remedy import argument, spelled
from .._core.validate import (
    as_length,
    distance_array,
    external_stacklevel,
    relative_humidity_array,
    surface_shape,
)
from ..contact import (
    MODELS,
    VALIDITY_BOUND,
    expected_surface_groups,
    model_names,
    select_model,
    warn_if_outside_validity,
    warn_if_unresolved,
)
from ..contact import curves as contact_curves
from ..contact import summary as contact_summary
from ..contact.trust.budget import model_bounds
from ..surface.gaussianity import is_gaussian
from ..surface.generate import ExtrapolatedPSDWarning, generate_surfaces
from .execute import auto_ensemble, stream
from .maps import (
    as_maps,
    attach,
    compared,
    map_containment,
    map_summaries,
    resolve_height_distribution,
)
from .multifidelity import accurate_subset, accurate_subset_size
from .pipeline import (
    Spec,
    _attrs,
    _hash_params,
    _water_heights,
    compute_block,
    distance_grid,
    lazy_ensemble,
)
from .store import open_ensemble

__all__ = ["run", "surface_size_study"]

#: The contact model run when ``model`` is not named: the cheapest that meets ``accuracy``.
DEFAULT_MODEL = "auto"
#: The cheap model of a default multi-fidelity ensemble (the paper's model, Eq. 16).
CHEAP_MODEL = "modified_dmt"
#: From this many realizations a default ensemble whose accuracy needs a costlier model than
#: :data:`CHEAP_MODEL` runs the cheap model on all and the accurate one on a subset; below it, the
#: accurate model on all (the pilot would be a large part of the run).
MULTIFIDELITY_FROM = 200
#: A pilot asking for more than this fraction of the realizations runs the accurate model on all.
MULTIFIDELITY_MAX_FRACTION = 0.6


def _contact_options(model, accuracy, curves_kwargs):
    """``(model, accuracy, curves_kwargs)`` with the old spellings ``curves_kwargs["model"]`` and
    ``curves_kwargs["tolerance"]`` moved to ``model=`` and ``accuracy=`` (DeprecationWarning)."""
    ck = dict(curves_kwargs or {})
    given = {"model": model, "accuracy": accuracy}
    for old, new in (("model", "model"), ("tolerance", "accuracy"), ("accuracy", "accuracy")):
        if old not in ck:
            continue
        if given[new] is not None:
            raise TypeError(f"run() got both curves_kwargs[{old!r}] (the old spelling) and {new}=; "
                            f"pass {new}= only")
        warnings.warn(f"run(curves_kwargs={{{old!r}: ...}}) is now run({new}=...); the old spelling "
                      "will be removed", DeprecationWarning, stacklevel=external_stacklevel())
        given[new] = ck.pop(old)
    return given["model"], given["accuracy"], ck


def _check_once(psd, shape, spacing, rh, material, adsorbed_layer, model, accuracy, quantity, *,
                warn=True):
    """Choose and check the contact model once per run, before the graph and without computing a
    surface. Returns ``(model, model_selection)``: the model every realization runs (``"auto"``
    resolved by :func:`roughstick.contact.select_model` on the groups expected from the PSD) and, for
    ``"auto"``, why.

    With ``warn`` (the default surfaces): generated surfaces larger than the PSD's scan
    (ExtrapolatedPSDWarning) and the measured validity of the model actually used at the groups
    expected from the PSD (ValidityWarning, docs/accuracy.md; none for the reference ``"bem"``
    nor for ``"auto"``, whose choice meets the accuracy), and whether the pixel resolves the
    water necks (:func:`roughstick.contact.warn_if_unresolved`; not for ``"gw"``). Blocks then compute
    without warnings.
    """
    model = DEFAULT_MODEL if model is None else model
    if model not in model_names(auto=True):
        raise ValueError(f"model must be one of {model_names(auto=True)}, got {model!r}.")
    tolerance = VALIDITY_BOUND if accuracy is None else accuracy
    if not (isinstance(tolerance, (int, float)) and not isinstance(tolerance, bool) and tolerance > 0):
        raise ValueError(f"accuracy must be a positive relative error (e.g. 0.1 for 10 %), got "
                         f"{tolerance!r}.")
    if not warn and model != "auto":
        return model, None
    with warnings.catch_warnings():
        if not warn:  # a custom generator: the PSD filter of generate_surfaces is not used
            warnings.simplefilter("ignore", ExtrapolatedPSDWarning)
        groups = expected_surface_groups(psd, shape=shape, spacing=spacing, relative_humidity=rh,
                                         material=material, adsorbed_layer=adsorbed_layer)
    selection = None
    if model == "auto":
        model, reason = select_model(None, relative_humidity=rh, accuracy=tolerance,
                                     quantity=quantity, groups=groups)
        selection = (
            f"auto -> {model} for every realization, chosen once for the ensemble from the "
            f"surface groups expected from the PSD at shape {tuple(shape)} "
            f"(roughstick.contact.expected_surface_groups), not per map: {reason}")
        # said before any surface is computed, with what one surface will cost
        logging.getLogger("roughstick").info(
            f"{selection.split(': ', 1)[0]}: estimated "
            f"{format_seconds(estimate_model_seconds(model, shape, len(rh)))} per surface "
            f"(within a factor ~3); {reason}")
    with spelled(**PYTHON_SPELLING):  # the remedies named in run's arguments
        if selection is None and warn and model != "bem":  # "auto"'s choice meets the tolerance
            warn_if_outside_validity(None, relative_humidity=rh, model=model, accuracy=tolerance,
                                     quantity=quantity, material=material,
                                     adsorbed_layer=adsorbed_layer, groups=groups)
        if warn and model != "gw":  # the pixel models: does the pixel resolve the water necks?
            warn_if_unresolved(groups=groups, spacing=spacing)
    return model, selection


#: How run's warnings spell their remedies (:mod:`roughstick._core.remedy`).
PYTHON_SPELLING = {
    "contact_model": lambda v, tolerance=None, accuracy=None, **kw: (
        f"model={v!r}" + ("" if (accuracy if accuracy is not None else tolerance) is None
                          else f", accuracy={accuracy if accuracy is not None else tolerance!r}")),
    "spacing": argument("spacing", fmt=lambda v: f"{v:.2g}"),
    "resolution": lambda v=None, **kw: ("roughstick.contact.resolution_study(psd=psd, shape=shape, spacing=spacing, "
                                        "relative_humidity=...) (a generated surface at half and twice the pixel)"),
}


@renamed_keywords(level="confidence", tolerance="target_precision")
@check_numbers(seed="seed", connect_timeout="nonnegative", batch="count", target_precision="positive",
               n_max="count", patience="count", confidence="fraction")
def run(
    psd: xr.DataArray,
    *,
    n,
    relative_humidity,
    spacing: float,
    size=None,
    shape=None,
    model: str | None = None,
    accuracy: float | None = None,
    seed=0,
    chunks=None,
    distance=None,
    adsorbed_layer="paper",
    material=POLYSILICON,
    output=None,
    overwrite: bool = False,
    scheduler=None,
    connect_timeout: float = 5.0,
    progress: bool | None = None,
    batch: int = 100,
    target_precision: float = 0.02,
    n_max: int = 3000,
    patience: int = 2,
    confidence: float = 0.95,
    generate: Callable | None = None,
    curves: Callable | None = None,
    summary: Callable | None = None,
    generate_kwargs: dict | None = None,
    curves_kwargs: dict | None = None,
    accurate_model: str | bool | None = None,
    n_accurate="auto",
    maps=None,
    height_distribution="auto",
    distribution_method: str = "translation",
) -> xr.Dataset:
    r"""Monte Carlo ensemble of rough-surface humid adhesion from a PSD (paper §4.3).

    For realization :math:`k = 0 … n-1`: a surface from ``psd`` (Eqs. 33-34,
    :func:`roughstick.surface.generate_surfaces`), its pressure–distance curves at every humidity
    by the contact model ``model`` (by default the cheapest measured within ``accuracy`` of the
    boundary-element reference) on a distance grid
    common to all realizations, and their summaries (Γ of Eq. 13, pull-off pressure, equilibrium
    distance).

    Parameters
    ----------
    psd : xarray.DataArray
        2-D ``(qy, qx)`` or isotropic ``(q)`` PSD [m4] (architecture.md normalisation).
    n : int or "auto"
        Number of realizations (>= 1), or ``"auto"``: add batches of ``batch`` realizations until
        the ``confidence`` band of Γ and of the pressure curve moves by less than
        ``target_precision`` (relative) for ``patience`` consecutive batches (at most ``n_max``).
        The stopping rule, the final n and the band changes are recorded in ``attrs``. ``"auto"``
        computes (it must look at the results).
    relative_humidity : sequence of float
        Humidities as fractions in (0, 1); becomes the ``rh`` dimension.
    spacing : float or str
        Pixel size [m], or with its unit (``"5 nm"``).
    size, shape : float, str or (float, float), int or (int, int)
        Surface side(s) in metres (or with a unit, ``"1.28 um"``), or in pixels; give exactly one.
    model : {"auto", "modified_dmt", "gw", "fft_bem", "bem"}, default "auto"
        ``"auto"`` (also ``None``): the accuracy target by the cheapest plan, resolved once for
        the whole ensemble before the graph is built. The model is the cheapest whose measured
        error bound at the surface groups expected from the PSD
        (:func:`roughstick.contact.expected_surface_groups`) meets ``accuracy`` at every
        humidity; where it is costlier than the modified DMT and ``n >= MULTIFIDELITY_FROM``
        (200; not with ``n="auto"`` nor with ``accurate_model``, a name or ``False``), the modified DMT runs on every
        realization and the chosen model on a subset sized by a pilot (``n_accurate="auto"``; on
        all where the pilot asks for more than 60 % of them): a multi-fidelity ensemble, whose
        accurate band :func:`confidence_band` gives. The model run is
        ``attrs["contact_model"]`` (and ``attrs["accurate_model"]``), the reason
        ``attrs["model_selection"]``. A named model runs on every realization;
        ``"modified_dmt"`` is the paper's model (§3.4, Eqs. 16-23); ``"bem"`` needs the Tamaas
        extra.
    accuracy : float, optional
        Accepted relative error of the model against the boundary-element reference (default
        0.1): what ``"auto"`` (and the default) must meet, and above which a named model gets a
        ValidityWarning.
    seed : int or numpy.random.SeedSequence, default 0
        Root seed; realization ``k`` uses its child ``k`` whatever the chunking.
    chunks : int or dict, optional
        Realizations per block (default: about 4 MiB of heights, at least 1), or
        ``{"realization": c, "rh": r}`` to split humidities too (each humidity block regenerates
        its surfaces, which costs one inverse FFT per surface).
    distance : array-like or xarray.DataArray, optional
        Common distance grid [m]; default :func:`distance_grid`.
    adsorbed_layer : {"paper", "none"} or callable, default "paper"
        Adsorbed-layer model (§2.1).
    material : roughstick.Material or str, default POLYSILICON
        Both bodies' material (or a name roughstick knows: ``"poly-Si"``).
    output : str or pathlib.Path, optional
        Stream results into this folder (one CF NetCDF file per block plus ``manifest.json``) as
        blocks complete, resuming from any blocks already there, and return the Dataset opened from
        it (lazily). A folder holding a run with other parameters is refused unless ``overwrite``.
    overwrite : bool, default False
        Replace a different run in ``output``.
    scheduler : None, "threads", "sync", "processes", str or distributed.Client
        Where blocks run when streaming or with ``n="auto"``: by default the active dask scheduler
        (an active ``distributed.Client``, which is the default once created; else one set with
        ``dask.config.set(scheduler=...)``; else local threads), or an existing dask.distributed
        cluster by its address (``"tcp://host:8786"``) or client. The lazy result (no
        ``output``) computes with whatever dask scheduler is active.
    connect_timeout : float, default 5
        Seconds to wait for a scheduler address to answer before raising ``ConnectionError``.
    progress : bool, optional
        Progress bar when streaming/auto; default: only when interactive.
    batch, target_precision, n_max, patience, confidence
        The stopping rule of ``n="auto"``.
    generate, curves, summary : callable, optional
        Replace :func:`roughstick.surface.generate_surfaces`, the contact curves and the adhesion
        summary (same signatures).
    generate_kwargs, curves_kwargs : dict, optional
        Extra keyword arguments for ``generate`` and for the contact model (e.g. ``quantity``,
        whose measured error ``accuracy`` bounds).
    accurate_model : str or False, optional
        ``False``: one model on every realization, never a multi-fidelity plan (what a
        per-realization count needs, e.g. P(stuck) from the sample).
        A model name: multi-fidelity: every realization runs ``model`` (the cheap one), and a subset drawn from
        the seed alone (:func:`roughstick.ensemble.multifidelity.accurate_subset`) also runs this
        registered contact model (e.g. ``"fft_bem"``), adding ``adhesive_energy_accurate``,
        ``pull_off_pressure_accurate`` and ``equilibrium_distance_accurate`` (NaN off the
        subset). :func:`confidence_band` combines them into the accurate model's band, with an
        interval that holds the sampling and the model correction together.
    n_accurate : int or "auto", default "auto"
        How many realizations run ``accurate_model``; ``"auto"``: from a pilot of
        ``PILOT_SIZE`` realizations run with both models (computed before the graph is built),
        as many as make the model correction of Γ's median and band edges lie within
        ``accuracy`` (:func:`roughstick.ensemble.multifidelity.accurate_subset_size`), at most n.
    maps : xarray.DataArray or list of xarray.DataArray, optional
        The measured maps the PSD was estimated from (``(..., y, x)`` or a list of 2-D maps;
        levelled by a plane here unless periodic or levelled already, as
        :func:`roughstick.io.read_afm` does; maps whose rms heights or correlation lengths differ
        more than twofold are an ``IncompatibleMapsWarning``). Each map's own summaries are
        computed with the same model, humidities, material and layer (one set of curves per map,
        at once; of a map larger than the surfaces, its centre at their size) and placed in the
        ensemble: ``map_adhesive_energy`` ... over ``(map, rh)`` and ``map_percentile``, the
        percentile of each map's Γ among the realizations (:func:`map_containment`). A computed
        result (``output=`` or ``n="auto"``) warns at once for a map outside the ``confidence``
        band; a lazy one when :func:`map_containment` is called on it.
    height_distribution : "auto", "maps", "gaussian", None or xarray.Dataset, default "auto"
        The height distribution of the surfaces (:func:`roughstick.surface.generate_surfaces`):
        ``"auto"`` is the maps' own (:func:`roughstick.surface.height_distribution`) when they
        are not Gaussian within their sampling error (:func:`roughstick.surface.is_gaussian`),
        and Gaussian when they are or when no ``maps`` are given; ``"maps"`` their own always;
        ``"gaussian"``/None Gaussian; or a distribution Dataset (e.g. Johnson, from skewness
        and kurtosis). The choice and why are ``attrs["height_distribution"]`` and
        ``attrs["height_distribution_reason"]``.
    distribution_method : {"translation", "iaaft"}
        How a height distribution is imposed (:func:`roughstick.surface.generate_surfaces`).

    Returns
    -------
    xarray.Dataset
        Curves over ``(realization, rh, distance)`` (``pressure`` … as returned by ``curves``),
        summaries over ``(realization, rh)`` (``adhesive_energy`` …) and ``max_height`` over
        ``(realization)``; dask-backed and chunked over realization and rh unless ``n="auto"``.
        The variables are those of the contact model run (e.g. ``fft_bem`` adds ``solved``,
        ``solver_residual``, ``distance_offset``; ``gw`` adds ``summit_density``).

    Warns
    -----
    ValidityWarning
        Once, before the graph: the measured error bound of the model actually run (not for
        ``"bem"``, the reference, nor for ``"auto"``, whose choice meets it) exceeds ``accuracy``
        at the groups expected from the PSD. Default ``generate`` and ``curves`` only.
    ExtrapolatedPSDWarning
        The surfaces are larger than the scan the PSD was measured on.

    Raises
    ------
    ValueError
        n < 1, empty or invalid humidities, bad shapes, a grid that does not cover a realization,
        an unknown ``model``.
    ConnectionError
        A scheduler address that does not answer within ``connect_timeout``.
    FileExistsError
        ``output`` holds a different run (pass ``overwrite=True``) or unrelated files.

    See Also
    --------
    confidence_band, histogram, ecdf, open_ensemble

    Notes
    -----
    Each block is a pure function of (parameters, realization range, humidity range), so a block
    recomputed after an interruption is bit-identical, and the lazy Dataset, the streamed folder,
    a threaded run and a run on a distributed cluster give the same numbers.

    References
    ----------
    Hoang et al. (2015), doi:10.1016/j.cam.2015.02.022, §4.3.
    """
    n_total, auto = _realizations(n, n_max)
    _check_psd(psd)
    spacing = as_length(spacing, name="spacing")
    shp = surface_shape(shape=shape, size=size, spacing=spacing)
    rh = relative_humidity_array(relative_humidity)
    material = POLYSILICON if material is None else as_material(material)
    model, accuracy, curves_kwargs = _contact_options(model, accuracy, curves_kwargs)
    maps = as_maps(maps) if maps is not None else None
    heights, maps_gaussian, why = resolve_height_distribution(height_distribution, maps)
    defaulted, chosen, selection, accurate_model = _model_plan(
        psd, shp, spacing, rh, material, adsorbed_layer, model, accuracy, curves_kwargs,
        accurate_model=accurate_model, custom=(curves is not None, generate is not None),
        many=not auto and n_total >= MULTIFIDELITY_FROM)
    if chosen is not None or model is not None:  # resolved before the graph, named in the parameters
        curves_kwargs["model"] = chosen if chosen is not None else model
    generate = generate_surfaces if generate is None else generate
    # no per-surface validity check (once per realization, from inside dask): checked once above
    curves = (functools.partial(contact_curves, check_validity=False) if curves is None
              else curves)
    summary = contact_summary if summary is None else summary
    root = as_seed_sequence(seed)
    generate_kwargs = dict(generate_kwargs or {})
    if heights is not None:
        generate_kwargs.update(height_distribution=heights, distribution_method=distribution_method)
    if distance is None:
        dist = np.asarray(distance_grid(psd, shape=shp, n=n_total, relative_humidity=rh,
                                        adsorbed_layer=adsorbed_layer,
                                        height_distribution=heights).values)
    else:
        dist = distance_array(distance, min_size=2)
    c_r, c_h = _chunks(chunks, shp, rh.size)
    if auto:
        batch = max(c_r, int(math.ceil(batch / c_r)) * c_r)
    # summaries on each map's own automatic grid unless the user fixed the distances
    spec = _spec(dict(
        psd=psd.load() if psd.chunks is not None else psd, shape=shp, spacing=spacing, rh=rh,
        distance=dist, chunk=c_r, rh_chunk=min(c_h, rh.size), adsorbed_layer=adsorbed_layer,
        material=material, generate=generate, curves=curves, summary=summary,
        generate_kwargs=generate_kwargs, curves_kwargs=curves_kwargs,
        seed_entropy=str(root.entropy), seed_spawn_key=list(root.spawn_key),
        own_grid=distance is None), root)
    if accurate_model is not None:
        spec = _with_accurate_subset(spec, accurate_model, n_accurate, n_total, auto=auto,
                                     accuracy=VALIDITY_BOUND if accuracy is None else accuracy)
        if defaulted and len(spec.accurate[1]) > MULTIFIDELITY_MAX_FRACTION * n_total:
            # the pilot asks for most realizations: the accurate model on all is cheaper
            selection += (f"; the pilot asked for {len(spec.accurate[1])} of {n_total} "
                          f"realizations with {accurate_model}: it runs on all")
            chosen, spec = accurate_model, _single_model(spec, accurate_model)
    attrs = _attrs(spec, n_total)
    if chosen is not None and spec.generate is generate_surfaces:  # the default stages
        attrs.update(_model_error_attrs(psd, shp, spacing, rh, material, adsorbed_layer,
                                        accurate_model or chosen or curves_kwargs.get("model")))
    if chosen is not None:
        attrs["contact_model"] = chosen
    if selection is not None:
        attrs["model_selection"] = selection
    attrs.update(height_distribution="gaussian" if heights is None else heights.attrs["family"],
                 height_distribution_reason=why)
    if heights is not None:
        attrs["distribution_method"] = distribution_method
    folder = pathlib.Path(output) if output is not None else None
    if auto:
        ds = auto_ensemble(spec, batch=batch, target_precision=target_precision, n_max=n_total,
                           patience=patience, confidence=confidence, folder=folder,
                           stream_kw={"overwrite": overwrite}, scheduler=scheduler,
                           connect_timeout=connect_timeout, progress=progress, attrs=attrs)
        line = f"ensemble.run(n='auto') stopped at n={ds.attrs['n_final']}"
    elif folder is not None:
        t0 = time.perf_counter()
        stream(spec, n_total, folder, overwrite=overwrite, scheduler=scheduler,
               connect_timeout=connect_timeout, progress=progress, attrs=attrs)
        ds = open_ensemble(folder, chunks={})
        line = f"ensemble.run streamed to {str(folder)!r} ({time.perf_counter() - t0:.1f} s this session)"
    else:
        ds = lazy_ensemble(spec, 0, n_total)
        ds.attrs = attrs
        line = f"ensemble.run(n={n_total}, shape={shp}, rh={rh.tolist()}); {ds.attrs.get('summary_grid', '')}"
    ds = append_history(_say_cheap(ds, spec), line)
    if maps is None:
        return ds
    return _with_maps(ds, spec, maps, maps_gaussian, confidence, computed=auto or folder is not None)


def _spec(fields: dict, root) -> Spec:
    """The run's :class:`Spec` from its parameters (their hash is the run's token: a stored run
    with other parameters is another run)."""
    return Spec(
        psd=fields["psd"], shape=fields["shape"], spacing=fields["spacing"], rh=fields["rh"],
        distance=fields["distance"], seed=root, chunk=fields["chunk"], rh_chunk=fields["rh_chunk"],
        adsorbed_layer=fields["adsorbed_layer"], material=fields["material"],
        generate=fields["generate"], curves=fields["curves"], summary=fields["summary"],
        generate_kwargs=fields["generate_kwargs"], curves_kwargs=fields["curves_kwargs"],
        water_max=float(np.max(_water_heights(fields["rh"], fields["adsorbed_layer"]))),
        token=_hash_params(fields), own_grid=fields["own_grid"],
    )


def _model_plan(psd, shp, spacing, rh, material, adsorbed_layer, model, accuracy, curves_kwargs, *,
                accurate_model, custom, many):
    """``(defaulted, chosen, selection, accurate_model)``: the model every realization runs
    ("auto" resolved once, before the graph: one template, one variable set) and, for the default
    (no model, no accurate model, ``many`` realizations) where it is costlier than Eq. 16, the
    multi-fidelity plan: Eq. 16 on all, the chosen model as the accurate one.
    ``accurate_model=False``: one model on every realization, never that plan."""
    one_model = accurate_model is False
    accurate_model = None if one_model else accurate_model
    custom_curves, custom_generate = custom
    defaulted = model in (None, "auto") and accurate_model is None and not custom_curves
    chosen = selection = None
    if not custom_curves:
        chosen, selection = _check_once(psd, shp, spacing, rh, material, adsorbed_layer, model,
                                        accuracy, curves_kwargs.get("quantity", "adhesive_energy"),
                                        warn=not custom_generate)
    if defaulted and not one_model and many and _costlier(chosen, CHEAP_MODEL):
        accurate_model, chosen = chosen, CHEAP_MODEL
        selection += (f"; multi-fidelity: {CHEAP_MODEL} on every realization, {accurate_model} on "
                      "a subset sized by a pilot (n >= "
                      f"{MULTIFIDELITY_FROM}), combined by roughstick.ensemble.confidence_band")
    return defaulted, chosen, selection, accurate_model


def _say_cheap(ds: xr.Dataset, spec: Spec) -> xr.Dataset:
    """A multi-fidelity ensemble's own summaries are the cheap model's: said on each variable, so
    none is read (or counted) as the accurate model's."""
    if spec.accurate:
        for v in ("adhesive_energy", "pull_off_pressure", "equilibrium_distance"):
            if v in ds:
                ds[v].attrs["multifidelity"] = (
                    f"the cheap model's ({spec.curves_kwargs.get('model')}) on every realization; "
                    f"{spec.accurate[0]}'s: {v}_accurate on a subset; the accurate band: "
                    "roughstick.ensemble.confidence_band")
    return ds


def _with_maps(ds, spec, maps, maps_gaussian, confidence, *, computed) -> xr.Dataset:
    """The measured maps' own summaries and percentiles in the ensemble (maps.attach); at once
    the containment check when the ensemble is already computed."""
    if maps_gaussian is None and ds.attrs.get("height_distribution") == "gaussian":
        maps_gaussian = is_gaussian(maps)  # a Gaussian run: are the maps? (a likely cause)
    parts, what = compared(maps, spec.shape, spec.spacing)
    own = map_summaries(parts, relative_humidity=spec.rh, curves=spec.curves, summary=spec.summary,
                        curves_kwargs=spec.curves_kwargs, material=spec.material,
                        adsorbed_layer=spec.adsorbed_layer)
    ds = attach(ds, own, maps, {"maps_gaussian": None if maps_gaussian is None else int(maps_gaussian),
                                "maps_compared": what})
    if computed:
        check = map_containment(ds, confidence=confidence)
        ds["map_percentile"] = check["map_percentile"]
        ds.attrs["map_containment"] = check.attrs["causes"]
    return append_history(ds, f"ensemble.run: {len(maps)} measured map(s)' own summaries "
                              "(map_adhesive_energy ..., map_percentile)")


#: Realizations a multi-fidelity pilot runs with both models (``n_accurate="auto"``).
PILOT_SIZE = 40


def _with_accurate_subset(spec: Spec, model: str, n_accurate, n_total: int, *, auto: bool,
                          accuracy: float) -> Spec:
    """``spec`` with its multi-fidelity subset: the first ``n_accurate`` realizations of the
    seed's permutation (``"auto"``: sized from a pilot run with both models)."""
    if model not in model_names():
        raise ValueError(f"accurate_model must be a registered contact model {model_names()}, got "
                         f"{model!r}.")
    if auto:
        raise ValueError("n='auto' with accurate_model= is not supported: give n (the number of "
                         "realizations), e.g. n=1000.")
    if n_accurate == "auto":
        pilot = accurate_subset(n_total, min(PILOT_SIZE, n_total), seed=spec.seed)
        probe = dataclasses.replace(spec, accurate=(model, frozenset(int(k) for k in pilot)))
        parts = [compute_block(probe, int(k), int(k) + 1, 0, spec.rh.size) for k in pilot]
        both = xr.concat([p[["adhesive_energy", "adhesive_energy_accurate"]] for p in parts],
                         "realization")
        n_accurate = max(
            accurate_subset_size(both["adhesive_energy"].sel(rh=r).values,
                                 both["adhesive_energy_accurate"].sel(rh=r).values,
                                 n_total=n_total, accuracy=accuracy)
            for r in spec.rh)
        logging.getLogger("roughstick").info(
            f"multi-fidelity: a pilot of {pilot.size} realizations run with both models asks for "
            f"{n_accurate} of {n_total} with {model} (accuracy {accuracy:g} on Γ's median and band "
            "edges)")
    elif not (isinstance(n_accurate, (int, np.integer)) and 1 <= n_accurate <= n_total):
        raise ValueError(f"n_accurate must be 'auto' or an integer from 1 to n={n_total}, got "
                         f"{n_accurate!r}.")
    members = frozenset(int(k) for k in accurate_subset(n_total, int(n_accurate), seed=spec.seed))
    return dataclasses.replace(spec, accurate=(model, members),
                               token=_hash_params({**_spec_fields(spec), "accurate": (model, members)}))


def _model_error_attrs(psd, shape, spacing, rh, material, adsorbed_layer, model) -> dict:
    """``model_error_bound_<summary>``: the measured bound of the model whose answer the
    ensemble gives (the accurate one of a multi-fidelity run) at the surface groups expected
    from the PSD, per humidity."""
    if model not in MODELS:
        return {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ExtrapolatedPSDWarning)  # said once by the run
        groups = expected_surface_groups(psd, shape=shape, spacing=spacing, relative_humidity=rh,
                                         material=material, adsorbed_layer=adsorbed_layer)
    bounds = model_bounds(model, None, relative_humidity=rh, material=material, material2=None,
                          adsorbed_layer=adsorbed_layer, groups=groups)
    return {f"model_error_bound_{q}": b for q, b in bounds.items()}


def _costlier(model: str | None, than: str) -> bool:
    """Whether ``model`` ranks above ``than`` in the contact-model registry's cost order."""
    if model is None or model not in MODELS or MODELS[model].cost_rank is None:
        return False
    return MODELS[model].cost_rank > MODELS[than].cost_rank


def _single_model(spec: Spec, model: str) -> Spec:
    """``spec`` running ``model`` on every realization, without a multi-fidelity subset."""
    kw = {**spec.curves_kwargs, "model": model}
    fields = {**_spec_fields(spec), "curves_kwargs": kw}
    return dataclasses.replace(spec, curves_kwargs=kw, accurate=(), token=_hash_params(fields))


def _spec_fields(spec: Spec) -> dict:
    """The fields :func:`roughstick.ensemble.pipeline._hash_params` reads, from a Spec."""
    return dict(psd=spec.psd, shape=spec.shape, spacing=spec.spacing, rh=spec.rh,
                distance=spec.distance, chunk=spec.chunk, rh_chunk=spec.rh_chunk,
                adsorbed_layer=spec.adsorbed_layer, material=spec.material, generate=spec.generate,
                curves=spec.curves, summary=spec.summary, generate_kwargs=spec.generate_kwargs,
                curves_kwargs=spec.curves_kwargs, seed_entropy=str(spec.seed.entropy),
                seed_spawn_key=list(spec.seed.spawn_key), own_grid=spec.own_grid)


def _realizations(n, n_max) -> tuple[int, bool]:
    """``(number of realizations to plan for, whether n is "auto")``."""
    if isinstance(n, str):
        if n != "auto":
            raise ValueError(f"n must be a positive integer or 'auto', got {n!r}.")
        n_total, auto = int(n_max), True
    else:
        if isinstance(n, bool) or int(n) != n:
            raise ValueError(f"n must be a positive integer or 'auto', got {n!r}.")
        n_total, auto = int(n), False
    if n_total < 1:
        raise ValueError(f"n must be at least 1 realization, got {n_total}.")
    return n_total, auto


def _check_psd(psd) -> None:
    if not isinstance(psd, xr.DataArray):
        hint = (" A callable PSD (e.g. roughstick.datasets.family_psd) is for generate_surfaces; an "
                "ensemble records its PSD, so evaluate it on wave vectors first, e.g. "
                "roughstick.surface.self_affine_psd(numpy.geomspace(1e5, 1e10, 2000), "
                "**roughstick.datasets.family_parameters(name))." if callable(psd) else "")
        raise TypeError(f"psd must be an xarray.DataArray, got {type(psd).__name__}.{hint}")


def _chunks(chunks, shape, n_rh) -> tuple[int, int]:
    """Realizations and humidities per block (default: about 4 MiB of heights, all humidities)."""
    if isinstance(chunks, dict):
        c_r = chunks.get("realization")
        c_h = chunks.get("rh", -1)
    else:
        c_r, c_h = chunks, -1
    if c_r is None:
        c_r = max(1, int(4 * 2**20 // (8 * shape[0] * shape[1])))
    c_r = int(c_r)
    c_h = n_rh if c_h in (-1, None) else int(c_h)
    if c_r < 1 or c_h < 1:
        raise ValueError(f"chunks must be positive, got realization={c_r}, rh={c_h}.")
    return c_r, c_h


def _select_for_sizes(psd, shapes, spacing, rh, accuracy, kwargs):
    """``model="auto"`` resolved once for all ``shapes`` (each size and each humidity must meet
    ``accuracy``: :func:`roughstick.contact.select_model` on the stacked groups expected from the
    PSD), and the reason."""
    material = as_material(kwargs.get("material") or POLYSILICON)
    with warnings.catch_warnings():
        if kwargs.get("generate") is not None:  # the PSD filter of generate_surfaces is not used
            warnings.simplefilter("ignore", ExtrapolatedPSDWarning)
        groups = xr.concat([expected_surface_groups(psd, shape=s, spacing=spacing, relative_humidity=rh,
                                                    material=material,
                                                    adsorbed_layer=kwargs.get("adsorbed_layer", "paper"))
                            for s in shapes], dim="size")
    quantity = (kwargs.get("curves_kwargs") or {}).get("quantity", "adhesive_energy")
    chosen, reason = select_model(None, relative_humidity=rh,
                                  accuracy=VALIDITY_BOUND if accuracy is None else accuracy,
                                  quantity=quantity, groups=groups)
    return chosen, (f"auto -> {chosen} for every size and realization, chosen once from the surface "
                    f"groups expected from the PSD at shapes {[tuple(s) for s in shapes]}: {reason}")


@check_numbers(seed="seed")
def surface_size_study(
    psd: xr.DataArray,
    *,
    sizes: Sequence[float] | None = None,
    shapes: Sequence | None = None,
    spacing: float,
    n: int,
    relative_humidity,
    seed=0,
    **kwargs,
) -> xr.Dataset:
    """The same PSD at several surface sizes on one distance grid (paper Figs. 16-17).

    Runs :func:`run` once per size with a common distance grid (built for the largest
    surface) and independent seeds (child ``i`` of ``seed`` for size ``i``) and concatenates along a
    new ``surface_size`` dimension (side length along x, m).

    Parameters
    ----------
    psd : xarray.DataArray
        PSD [m4].
    sizes : sequence of float, optional
        Side lengths [m] of square surfaces (e.g. ``[5.12e-6, 10.24e-6]``); or give ``shapes``.
    shapes : sequence of (int, int), optional
        Surface shapes in pixels.
    spacing : float
        Pixel size [m].
    n : int
        Realizations per size.
    relative_humidity : sequence of float
        Humidities.
    seed : int or numpy.random.SeedSequence
        Root seed.
    **kwargs
        Passed to :func:`run` (``output`` is not supported here). With ``model="auto"`` the
        model is chosen once for every size (each size and humidity must meet ``accuracy``) so
        that the sizes, not the models, differ; the reason is ``attrs["model_selection"]``.

    Returns
    -------
    xarray.Dataset
        As :func:`run` plus a leading ``surface_size`` dimension; lazy.
    """
    if (sizes is None) == (shapes is None):
        raise ValueError("give exactly one of sizes= (m) or shapes= (pixels).")
    if "output" in kwargs:
        raise ValueError("surface_size_study does not stream; call roughstick.ensemble.run(output=...) per size.")
    spacing = as_length(spacing, name="spacing")
    shp = [surface_shape(size=s, spacing=spacing) for s in sizes] if sizes is not None else [
        surface_shape(shape=s, spacing=spacing) for s in shapes
    ]
    if not shp:
        raise ValueError("sizes/shapes is empty; give at least one surface size.")
    rh = relative_humidity_array(relative_humidity)
    selection = None
    model, accuracy, curves_kwargs = _contact_options(kwargs.pop("model", None),
                                                      kwargs.pop("accuracy", None),
                                                      kwargs.pop("curves_kwargs", None))
    kwargs.update(model=model, accuracy=accuracy, curves_kwargs=curves_kwargs)
    if model == "auto" and kwargs.get("curves") is None:
        # one model for every size: the sizes are compared, not the models
        kwargs["model"], selection = _select_for_sizes(psd, shp, spacing, rh, accuracy, kwargs)
    dist = kwargs.pop("distance", None)
    if dist is None:
        big = max(shp, key=lambda s: s[0] * s[1])
        dist = distance_grid(psd, shape=big, n=n, relative_humidity=rh,
                                      adsorbed_layer=kwargs.get("adsorbed_layer", "paper"))
    root = as_seed_sequence(seed)
    parts = []
    for i, s in enumerate(shp):
        child = np.random.SeedSequence(root.entropy, spawn_key=tuple(root.spawn_key) + (i,))
        parts.append(run(psd, n=n, shape=s, spacing=spacing, relative_humidity=rh,
                                  seed=child, distance=dist, **kwargs))
    lengths = [s[1] * spacing for s in shp]
    ds = xr.concat(parts, dim=xr.DataArray(lengths, dims="surface_size", name="surface_size"),
                   combine_attrs="drop_conflicts", data_vars="all", coords="minimal", compat="override")
    ds["surface_size"].attrs = dict(ATTRS["surface_size"])
    ds.attrs = {**parts[0].attrs, "surface_sizes_m": json.dumps(lengths)}
    if selection is not None:
        ds.attrs["model_selection"] = selection
    for k in ("surface_shape", "surface_size_m", "params_hash", "seed_spawn_key"):
        ds.attrs.pop(k, None)
    return ds
