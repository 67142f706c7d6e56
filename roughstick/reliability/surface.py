r"""Small probabilities of rough-surface zones: P(response > threshold) by subset simulation.

The limit state: white noise -> surface with the PSD (Eqs. 33-34) -> modified-DMT curve (Eq. 16;
or the FFT boundary-element model) at one humidity -> the zone's adhesive energy (Eq. 13) or
pull-off pressure. With the critical adhesive energy of a beam (Eq. 36) as threshold it is the
pull-out proxy of P(stuck) of paper §5.2, which :func:`roughstick.reliability.stuck_probability`
(``method="subset"`` on a PSD) reads as such.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import pathlib

import numpy as np
import xarray as xr

from .._core.api import renamed_keywords
from .._core.conventions import append_history
from .._core.validate import relative_humidity_array
from ..contact import water_height
from ..stiction.cantilever import critical_adhesive_energy
from . import _engine as _e
from . import _fidelity as _f
from . import _surface as _s
from ._surface import ARTEFACT_RATIO  # noqa: F401  (the BEM re-check's threshold, read by the CLI)
from .subset import subset_simulation

__all__ = ["failure_probability", "surface_from_noise"]


def surface_from_noise(noise, psd, *, shape, spacing, height_distribution=None):
    """The surface [m] a white-noise field (e.g. one of ``failure_noise``) maps to (Eqs. 33-34).

    The same map :func:`failure_probability` evaluates (:func:`roughstick.surface.noise_map`;
    pass the run's ``height_distribution`` for a non-Gaussian one), so a failure sample can be
    looked at, or fed to another model (the BEM, a beam model).

    Examples
    --------
    >>> import numpy as np
    >>> z = rs.reliability.surface_from_noise(np.zeros((8, 8)), rs.datasets.family_psd("table4"),
    ...                                       shape=(8, 8), spacing=5e-9)
    >>> z.dims, float(abs(z).max())
    (('y', 'x'), 0.0)
    """
    f = _s.NoiseToSurface(psd, shape=shape, spacing=spacing, height_distribution=height_distribution)
    return f.height_array(f(noise))


def _psd_token(amplitude):
    return hashlib.sha256(np.ascontiguousarray(amplitude).tobytes()).hexdigest()[:16]


@renamed_keywords(contact_model="model", samples_per_level="n_per_level")
@_e.checked(*_e.SETTING_RULES, n_accurate="count", ratio_bound="positive?", **_e.SURFACE_RULES)
def failure_probability(
    psd,
    *,
    threshold,
    relative_humidity,
    shape,
    spacing: float,
    quantity: str = "adhesive_energy",
    model: str = "auto",
    height_distribution=None,
    method: str = "subset",
    n_per_level: int = 1000,
    level_probability: float = 0.2,
    independent_runs: int = 1,
    proposal: str = "adaptive",
    proposal_scale: float = 0.6,
    target_acceptance: float = 0.44,
    target_cv: float | None = None,
    max_evaluations: int | None = None,
    max_levels: int = 12,
    confidence: float = 0.95,
    seed=0,
    material=None,
    material2=None,
    adsorbed_layer="paper",
    points_per_water_height: float = 20.0,
    lower: float = 2.0,
    connectivity: int = 4,
    periodic: bool = True,
    patches: int = 1,
    chunks: int = 100,
    scheduler=None,
    output=None,
    overwrite: bool = False,
    check_failures: int = 8,
    accurate_model: str | None = None,
    n_accurate: int = 300,
    ratio_bound: float | None = None,
) -> xr.Dataset:
    r"""Probability that a zone's adhesive energy (or pull-off pressure) exceeds a threshold.

    One model evaluation = one surface of ``shape`` pixels generated from ``psd`` (Eqs. 33-34,
    the white noise being the random input), its curve at one humidity (Eq. 16, or the FFT
    boundary-element model) and its adhesive energy (Eq. 13, from the equilibrium outwards) or
    pull-off pressure. With the beam's critical energy as threshold,
    ``rs.stiction.critical_adhesive_energy(beam_length=l)`` (Eq. 36), the result is the pull-out
    proxy of P(stuck) of paper §5.2 (what ``stuck_probability(psd, method="subset")`` computes).

    Parameters
    ----------
    psd : xarray.DataArray or callable
        As in :func:`roughstick.surface.generate_surfaces`.
    threshold : float
        Failure: response strictly above it [J m-2 for the energy, Pa for the pull-off].
    relative_humidity : float or sequence
        One estimate per humidity (``rh`` dim). The same seed serves every humidity, so level 0
        uses the same surfaces at each (common random numbers: smoother curves in RH).
    shape : (int, int)
        Pixels of the zone.
    spacing : float
        Pixel size [m].
    quantity : {"adhesive_energy", "pull_off_pressure"}
    height_distribution : xarray.Dataset, optional
        Of :func:`roughstick.surface.height_distribution` (a measured film's, or a Johnson
        system's): the zones are the translation process with this distribution and the PSD
        (:func:`roughstick.surface.noise_map`), the white noise still their random input, so
        the estimator samples the film's own law. None: Gaussian zones.
    model : {"auto", "modified_dmt", "fft_bem"}, default "auto"
        The contact model of each zone: Eq. 16, or the FFT boundary-element model (periodic
        zones only, about 20 times the cost; needed where the Eq. 16 tail is made of artefacts,
        docs/rare_events.md). ``"auto"``: the cheaper of the two whose measured error bound at
        the surface groups expected from the PSD at this zone meets 10 % at every humidity
        (:func:`roughstick.contact.select_model`; ``attrs["model_selection"]``).
    method, n_per_level, level_probability, independent_runs, proposal, proposal_scale,
    target_acceptance, target_cv, max_evaluations, max_levels, confidence, seed, chunks, scheduler
        See :func:`subset_simulation`.
    material, material2, adsorbed_layer, connectivity
        As in :func:`roughstick.contact.curves`.
    points_per_water_height : float, default 20
        Distance step h_water / this (docs/rare_events.md for its accuracy).
    lower : float, default 2
        First bottom of each surface's distance grid, in sqrt(m0); extended by 0.5 sqrt(m0)
        until the curve has an equilibrium.
    periodic : bool, default True
        Evaluate each surface as periodic (asperities wrap round, as the ensembles do) or as a
        piece cut from a larger surface (``False``): the patch kind :func:`weakest_link` needs.
    patches : int, default 1
        > 1: cut the surface into this many strips along ``y``, each evaluated alone as a piece
        (not periodic); the response is the largest: the direct simulation of a weakest-link
        structure.
    output : path, optional
        Folder; one sub-folder per humidity with one file per completed level (resume).
    check_failures : int, default 8
        With ``model="modified_dmt"``, re-evaluate this many failure samples with the
        FFT-BEM (``failures_confirmed_by_bem`` and ``failure_bem_ratio``; a ValidityWarning
        when the ratio is below one half, artefacts, or fewer than half stay failures). 0: no
        check.

    Returns
    -------
    xarray.Dataset
        The variables of :func:`subset_simulation` along ``rh``. With ``accurate_model``:
        ``failure_probability`` and its interval and cv are the accurate model's, beside
        ``cheap_probability`` (the Eq. 16 run's), ``conditional_fraction``, ``n_evaluations``
        (Eq. 16) and ``n_accurate_evaluations``, ``ratio_bound``, ``pilot_ratio``,
        ``relaxed_threshold``, ``band_threshold``, ``containment_checked`` and
        ``containment_violations`` (accurate failures just below the relaxed level, after a
        second pass with the bound re-measured when the first found any: ``passes``,
        ``first_pass_violations``; a warning when any are left), ``cheap_within_accuracy``.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore", rs.ValidityWarning)  # Eq. 16 off its map: the point
    ...     ds = rs.reliability.failure_probability(
    ...         rs.datasets.family_psd("table4"), threshold=0.1, relative_humidity=0.5, shape=(8, 8),
    ...         spacing=5e-9, model="modified_dmt", accurate_model="fft_bem", n_accurate=20,
    ...         n_per_level=50, scheduler="sync")
    >>> int(ds.n_accurate_evaluations) <= 2 * (20 + 32), bool(ds.failure_probability <= ds.cheap_probability)
    (True, True)
    """
    rh_in = relative_humidity_array(relative_humidity)
    _check_two_fidelity(accurate_model, model, method, target_cv, periodic, patches, n_accurate, ratio_bound)
    if quantity not in _s.QUANTITIES:
        raise ValueError(f"quantity must be one of {_s.QUANTITIES}, got {quantity!r}.")
    if not (np.isfinite(threshold) and threshold > 0):
        raise ValueError(f"threshold must be a positive finite number in SI units, got {threshold!r}.")
    to_surface = _s.NoiseToSurface(psd, shape=shape, spacing=spacing,
                                   height_distribution=height_distribution)
    if accurate_model is not None:
        model = "modified_dmt"
    model, selection = _s.zone_model(model, psd, shape=(to_surface.ny, to_surface.nx),
                                     spacing=spacing, relative_humidity=rh_in, material=material,
                                     material2=material2, adsorbed_layer=adsorbed_layer,
                                     periodic=periodic, patches=patches)
    ny, nx, dy, dx = to_surface.ny, to_surface.nx, to_surface.dy, to_surface.dx
    m0 = to_surface.variance
    hw = np.atleast_1d(water_height(rh_in, adsorbed_layer=adsorbed_layer).values)
    units = "J m-2" if quantity == "adhesive_energy" else "Pa"
    mat = [_s.material_token(m) for m in (material, material2)]
    out = []
    for i, rh in enumerate(rh_in):
        response = _s.SurfaceResponse(
            to_surface, relative_humidity=rh, water_height=hw[i], quantity=quantity,
            material=material, material2=material2, adsorbed_layer=adsorbed_layer,
            points_per_water_height=points_per_water_height, lower=lower, connectivity=connectivity,
            periodic=periodic, patches=patches, model=model)
        token = _resume_token(to_surface, rh=rh, hw=hw[i], materials=mat, quantity=quantity,
                              pph=points_per_water_height, lower=lower, connectivity=connectivity,
                              periodic=periodic, patches=patches, model=model)
        sub = None if output is None else pathlib.Path(output) / f"rh-{rh:.4f}"
        ds = functools.partial(
            subset_simulation, response, noise_shape=response.noise_shape, method=method,
            n_per_level=n_per_level, level_probability=level_probability,
            independent_runs=independent_runs, proposal=proposal, proposal_scale=proposal_scale, target_acceptance=target_acceptance,
            max_levels=max_levels, target_cv=target_cv, max_evaluations=max_evaluations,
            confidence=confidence, seed=seed, chunks=chunks, scheduler=scheduler, output=sub,
            overwrite=overwrite, token=token,
            response_attrs={"units": units, "quantity": quantity})
        if accurate_model is not None:
            accurate = _s.SurfaceResponse(to_surface, relative_humidity=rh, water_height=hw[i], quantity=quantity,
                                          material=material, material2=material2, adsorbed_layer=adsorbed_layer,
                                          model=accurate_model)
            ds = _f.two_fidelity(response, accurate, threshold=float(threshold), run=functools.partial(_second_pass_aside, ds, sub),
                                 n_accurate=n_accurate, ratio_bound=ratio_bound, n_pool=n_per_level,
                                 seed=seed, confidence=confidence, independent_runs=independent_runs)
        else:
            ds = ds(threshold=float(threshold))
        if model == "modified_dmt" and accurate_model is None:  # rare states: measure Eq. 16 there
            ds = _s.bem_check(ds, response, float(threshold), check_failures)
        # index every dim so humidities with different level/run/failure counts align (outer join)
        out.append(ds.assign_coords({d: np.arange(n) for d, n in ds.sizes.items() if d not in ds.coords}))
    res = _along_rh(out, rh_in, hw)
    if np.ndim(relative_humidity) == 0:
        res = res.squeeze("rh")
    res.attrs.update({"quantity": quantity, "contact_model": model, "threshold": float(threshold), "threshold_units": units,
                      "zone_shape": [ny, nx], "spacing": float(dx), "zone_area": float(ny * nx * dx * dy),
                      "patches": int(patches), "periodic": int(periodic), "height_rms": math.sqrt(m0),
                      "adsorbed_layer": str(getattr(adsorbed_layer, "__name__", adsorbed_layer)),
                      "points_per_water_height": float(points_per_water_height)})
    if to_surface.translation is not None:
        res.attrs["height_distribution"] = to_surface.translation
        if selection is not None:
            selection += " (judged on the Gaussian surfaces of the PSD)"
    if selection is not None:
        res.attrs["model_selection"] = selection
    if accurate_model is not None:
        res.attrs.update({"method": "two_fidelity", "accurate_model": accurate_model})
    append_history(res, f"failure_probability(quantity={quantity!r}, shape={ny}x{nx}, spacing={dx:.3g} m, "
                        f"method={method!r}, patches={patches})")
    return res


def _resume_token(to_surface, *, rh, hw, materials, quantity, pph, lower, connectivity, periodic,
                  patches, model) -> str:
    """What a stored run of one humidity must match to be resumed (the zone, its law, the model)."""
    key = {"psd": _psd_token(to_surface.amplitude), "shape": [to_surface.ny, to_surface.nx],
           "spacing": [to_surface.dy, to_surface.dx], "rh": float(rh), "hw": float(hw),
           "materials": materials, "quantity": quantity, "pph": float(pph), "lower": float(lower),
           "connectivity": int(connectivity), "periodic": bool(periodic), "patches": int(patches),
           "map": "circulant/1"}
    if model != "modified_dmt":  # earlier outputs (Eq. 16 only) still resume
        key["contact_model"] = model
    if to_surface.table is not None:  # Gaussian runs stored before keep resuming
        key["heights"] = _psd_token(to_surface.table)
    return json.dumps(key)


def _along_rh(out, rh_in, hw) -> xr.Dataset:
    """The per-humidity results on one ``rh`` dim (outer join: their level/run/failure counts
    differ), with the CF attributes of the index coords and the humidity's own coords."""
    fill = {"accepted": np.int8(-1), "chain": np.int32(-1)}
    res = xr.concat(out, dim="rh", join="outer", fill_value=fill, combine_attrs="drop_conflicts",
                    data_vars="all", coords="different", compat="equals")
    for d in res.dims:  # the index coords added for the alignment: CF attrs to be written
        if d in _e.ATTRS and not res[d].attrs:
            res[d].attrs = dict(_e.ATTRS[d])
    res = res.assign_coords(rh=("rh", rh_in, {"units": "1", "long_name": "relative humidity",
                                             "standard_name": "relative_humidity"}))
    return res.assign_coords(water_height=("rh", hw, {"units": "m", "long_name": "water height h_water"}))


def _second_pass_aside(run, output, threshold, seed, attempt):
    """The two-fidelity estimator's subset run; a second pass stores its levels beside the first."""
    if output is not None and attempt:
        output = output / "second-pass"
    return run(threshold=threshold, seed=seed, output=output)


def _check_two_fidelity(accurate_model, model, method, target_cv, periodic, patches, n_accurate, ratio_bound):
    """Refuse, before any work, a two-fidelity request the estimator cannot run, naming the fix."""
    if accurate_model is None:
        return
    if accurate_model != "fft_bem":
        raise ValueError(f"accurate_model must be 'fft_bem' (the boundary-element model corrects Eq. 16 in "
                         f"the tail), got {accurate_model!r}; or leave accurate_model=None.")
    if model not in ("auto", "modified_dmt"):
        raise ValueError(f"accurate_model={accurate_model!r} corrects the modified DMT: pass "
                         f"model='modified_dmt' (or 'auto'), not model={model!r}; for the accurate model "
                         "alone pass model='fft_bem' without accurate_model.")
    if method != "subset" or target_cv is not None:
        raise ValueError("accurate_model= runs one subset simulation on Eq. 16 and corrects its final "
                         "level: pass method='subset' and target_cv=None (for a smaller cv give more "
                         "independent_runs= or n_per_level=).")
    if not periodic or patches != 1:
        raise ValueError("accurate_model='fft_bem' solves periodic zones only: pass periodic=True and patches=1.")
    if not (isinstance(n_accurate, (int, np.integer)) and n_accurate >= 10):
        raise ValueError(f"n_accurate must be an integer >= 10 (a few hundred is typical), got {n_accurate!r}.")
    if ratio_bound is not None and not (np.isfinite(ratio_bound) and ratio_bound > 0):
        raise ValueError(f"ratio_bound must be a positive number (accurate / Eq. 16 response) or None "
                         f"(measured by a pilot), got {ratio_bound!r}.")


def _zone_stuck_probability(psd, *, beam_length, beam, method, relative_humidity, shape, spacing,
                            target_cv, max_evaluations, n_per_level, seed, model, confidence, **options):
    """P(stuck) by the pull-out proxy of paper §5.2 on zones drawn from ``psd``:
    :func:`failure_probability` with the critical adhesive energy of the beam as threshold."""
    length = beam.length if beam_length is None else beam_length
    if np.ndim(length) != 0:
        raise ValueError(f"stuck_probability(psd, method={method!r}) takes one beam_length per call "
                         f"(got {np.size(length)}): loop over the lengths (each is its own estimate).")
    gc = float(critical_adhesive_energy(beam_length=length, beam=beam))
    ds = failure_probability(psd, threshold=gc, relative_humidity=relative_humidity, shape=shape,
                             spacing=spacing, method=method, target_cv=target_cv,
                             max_evaluations=max_evaluations, n_per_level=n_per_level, seed=seed,
                             model=model, confidence=confidence, **options)
    ds = ds.rename({"failure_probability": "stiction_probability",
                    "failure_probability_lower": "stiction_probability_lower",
                    "failure_probability_upper": "stiction_probability_upper"})
    ds["stiction_probability"].attrs["long_name"] = "probability that the beam stays stuck"
    ds.attrs.update({"critical_adhesive_energy": gc, "beam_length": float(length)})
    append_history(ds, f"stuck_probability(psd, beam_length={float(length):.4g} m, method={method!r})")
    return ds
