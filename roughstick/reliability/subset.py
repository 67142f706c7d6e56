r"""Small failure probabilities of rough-surface stiction: subset simulation (issue 15).

Every roughstick surface is standard-normal white noise filtered by the PSD (Eqs. 33-34). A
failure event (the interaction zone's adhesive energy above the critical energy of a beam,
Eq. 36; the pull-off pressure above a load) is a region of that white-noise space, and its
probability is estimated by

- ``method="subset"``: subset simulation (Au & Beck 2001). Level 0 is crude Monte Carlo; each
  next level keeps the fraction ``level_probability`` p0 of samples with the largest response
  and grows Markov chains from them conditioned on exceeding the intermediate threshold, with
  preconditioned Crank-Nicolson moves :math:`z' = \rho z + \sqrt{1-\rho^2}\,\xi` that leave the
  Gaussian prior (so the PSD) exactly invariant; it stops at the level whose p0-quantile passes
  the failure threshold. :math:`\hat P = \prod_j \hat p_j`.
- ``method="monte_carlo"``: crude Monte Carlo over independent white-noise draws, in batches.

Both add independent runs until the estimate's coefficient of variation meets ``target_cv``
(or ``max_evaluations`` is spent), write every completed level to ``output`` (a rerun resumes),
evaluate the chains of a level in parallel on dask, and give bit-identical results for any
chunking and any number of workers (one SeedSequence child per level-0 sample and per
(run, level, chain)).
"""

from __future__ import annotations

import hashlib
import json
import math
import pathlib

import numpy as np
import xarray as xr

from roughstick._core.conventions import append_history
from roughstick._core.dask import as_seed_sequence
from roughstick._core.validate import adhesive_energy_values, relative_humidity_array
from roughstick.contact import water_height

from . import _beam as _b
from . import _engine as _e
from . import _surface as _s
from ._surface import ARTEFACT_RATIO  # noqa: F401  (the BEM re-check's artefact threshold)
from ..stiction.cantilever import PAPER_CANTILEVER, Cantilever, critical_adhesive_energy
from ..beam.sharp_front import PROTOCOLS, _beam_axes, _n_patches

__all__ = [
    "subset_simulation",
    "failure_probability",
    "stiction_probability_subset",
    "beam_stiction_probability_subset",
    "weakest_link",
    "surface_from_noise",
]


@_e.checked(*_e.SETTING_RULES)
def subset_simulation(
    limit_state,
    *,
    noise_shape,
    threshold: float,
    method: str = "subset",
    samples_per_level: int = 1000,
    level_probability: float = 0.2,
    independent_runs: int = 1,
    proposal: str = "adaptive",
    proposal_scale: float = 0.6,
    target_acceptance: float = 0.44,
    max_levels: int = 12,
    target_cv: float | None = None,
    max_evaluations: int | None = None,
    confidence: float = 0.95,
    seed=0,
    chunks: int = 100,
    scheduler=None,
    output=None,
    overwrite: bool = False,
    token: str | None = None,
    response_attrs: dict | None = None,
) -> xr.Dataset:
    r"""Probability that ``limit_state(z) > threshold`` for standard-normal ``z``.

    Parameters
    ----------
    limit_state : callable
        Maps one white-noise array of shape ``noise_shape`` to a float response; larger is
        closer to failure. Must be thread-safe (dask threads) and picklable (processes and
        distributed). NaN responses count as no failure (and are never accepted in a chain).
    noise_shape : tuple of int
        Shape of the white noise. Level-0 sample ``i`` is
        ``realization_rng(SeedSequence(seed), i).standard_normal(noise_shape)``.
    threshold : float
        Failure when the response is strictly above it.
    method : {"subset", "monte_carlo"}
        Subset simulation or crude Monte Carlo (batches of ``samples_per_level``).
    samples_per_level : int, default 1000
        Samples per level of each run (Monte Carlo: of the first batch).
    independent_runs : int, default 1
        Subset simulation runs at least this many independent runs (each from its own level-0
        samples) and reports their mean. With 3 or more, the spread of the runs gives a second,
        model-free cv estimate, used when it is the larger.
    level_probability : float, default 0.2
        Conditional probability p0 of each intermediate level; p0 * samples_per_level chains
        of length 1/p0. 0.2 rather than the customary 0.1: shorter chains are less correlated,
        which more than pays for the extra levels (linear limit state in 128 x 128 white noise,
        P = 1e-4, 100 seeds each: rms error 0.25 at 4,539 evaluations with p0 = 0.2, N = 900,
        against 0.34 at 4,205 with p0 = 0.1, N = 1000 and 0.29 at 4,960 with p0 = 0.1,
        N = 1200).
    proposal : {"adaptive", "pcn", "shell"}, default "adaptive"
        ``"pcn"``: every coordinate moves as :math:`\rho z + \sigma\xi`,
        :math:`\sigma` = ``proposal_scale``, :math:`\rho = \sqrt{1-\sigma^2}`, fixed.
        ``"adaptive"``: adaptive conditional sampling (Papaioannou et al. 2015): coordinate
        :math:`i` moves with :math:`\sigma_i = \min(1, \lambda s_i)`, :math:`s_i` the spread of
        the level's seeds in that coordinate, :math:`\lambda` updated after every round of the
        chains towards ``target_acceptance``. ``"shell"`` (experimental; limit states with a
        ``shell_labels`` attribute, e.g. the surface ones): every second round keeps the noise's
        norm in each shell of equal |q| and PSD amplitude and moves its direction; measured
        *worse* than ``"adaptive"`` on the surface model (docs/rare_events.md). All keep the
        Gaussian prior exactly.
    proposal_scale : float, default 0.6
        :math:`\sigma` (``"pcn"``) or the first level's :math:`\lambda` (``"adaptive"``).
    target_acceptance : float, default 0.44
    max_levels : int, default 12
        At most this many levels (p0^11 = 2e-8 at p0 = 0.2): the last one counts the states
        above the failure threshold itself. With none there, the estimate is 0 and the upper
        bound is the probability of the last level times the Wilson bound of 0 out of N.
    target_cv : float, optional
        Stopping rule: runs are added (subset: one more run of the same size; Monte Carlo: a
        batch sized to reach the target) until the coefficient of variation is at most
        ``target_cv``. None: ``independent_runs`` runs (Monte Carlo: one batch).
    max_evaluations : int, optional
        Budget of model evaluations: a run is started only if one as large as the largest so
        far still fits (``independent_runs`` always complete; a run needing more levels than
        all before it can overshoot by one level); ``converged`` says whether the target was
        met.
    confidence : float, default 0.95
        Level of the interval.
    seed : int or numpy.random.SeedSequence
        Root seed.
    chunks : int, default 100
        Model evaluations per dask task (level 0: samples; higher levels: whole chains).
        Results do not depend on it.
    scheduler : None, str or distributed.Client
        ``None`` (the active dask scheduler: an active Client, else ``dask.config``'s, else
        threads), "threads", "sync", "processes", a scheduler address or a Client.
        ("processes" starts a worker pool for every round of the chains: slow; prefer threads
        or a distributed Client.)
    output : path, optional
        Folder receiving one NetCDF file per completed level and a manifest; a rerun with the same
        parameters resumes (and a larger ``target_cv``/budget adds runs to the stored ones).
    overwrite : bool
        Replace an output folder holding another run.
    token : str, optional
        Identifies the limit state in the manifest (the caller's parameter hash); required with
        ``output`` when the limit state's repr holds a memory address (a lambda, a plain object).
    response_attrs : dict, optional
        ``units`` and ``long_name`` of the response.

    Returns
    -------
    xarray.Dataset
        Scalars ``failure_probability``, ``failure_probability_lower``/``_upper``,
        ``coefficient_of_variation``, ``n_evaluations``, ``converged``; per ``(run, level)``
        the thresholds, conditional probabilities, correlation factors and acceptance; per
        ``(run, level, round)`` the proposal scale; per ``(run, level, sample)`` every state's ``response``, ``proposal_response``,
        ``accepted`` and ``chain``; ``failure_noise`` of the last level's failure samples.

    Notes
    -----
    One run: :math:`\hat P_r = \prod_j \hat p_j`. Its cv :math:`\delta_r` is the genealogical
    estimate: every state descends from one level-0 sample, :math:`\hat P_r` is the sum of the
    contributions of the :math:`N` level-0 samples (:math:`\propto n_i`, the final failures
    descending from sample :math:`i`), and
    :math:`\delta_r^2 = \frac{N}{N-1}\sum_i (n_i/n_F - 1/N)^2` (the ancestral-lineage estimator
    of sequential Monte Carlo, Chan & Lai 2013, Lee & Whiteley 2018). It contains the
    correlation of the states of a chain and between levels. ``au_beck_cv`` is Au & Beck's
    (2001, Eqs. 25-30) :math:`\sum_j \frac{1 - p_j}{N p_j}(1 + \gamma_j)`, :math:`\gamma_j`
    from the lag correlations of the failure indicator inside the chains; it neglects the
    correlation between levels and measurably underestimates the error (linear limit state,
    P = 1e-4, p0 = 0.1, N = 1200, 100 seeds: spread 0.29, Au-Beck 0.25, genealogical 0.27;
    p0 = 0.2, N = 800: 0.32, 0.25, 0.29). :math:`R` runs: :math:`\hat P = \overline{\hat P_r}`,
    cv :math:`\sqrt{\overline{\delta_r^2}/R}`; ``between_run_cv``
    :math:`= s(\hat P_r)/(\sqrt R\,\hat P)` replaces it when :math:`R \ge 3` and it is larger. Interval: log-normal,
    :math:`\hat P\sqrt{1+\delta^2}\,e^{\pm q\sqrt{\ln(1+\delta^2)}}`, :math:`q` the normal quantile
    (Au-Beck cv) or Student's t with :math:`R - 1` degrees of freedom (between-run cv). Monte
    Carlo: :math:`k/n`, :math:`\delta = \sqrt{(1-\hat P)/(n\hat P)}`, Wilson interval.
    """
    _e._check_settings(method, samples_per_level, level_probability, proposal, proposal_scale,
                    target_acceptance, max_levels, target_cv, max_evaluations, confidence)

    response_attrs = {"units": "1", **(response_attrs or {})}  # a bare limit state: dimensionless
    root = as_seed_sequence(seed)
    settings = _e._Settings(method, int(samples_per_level), float(level_probability), proposal,
                         float(proposal_scale), float(target_acceptance), int(max_levels))
    store = None
    if output is not None:
        info = {"method": method, "samples_per_level": int(samples_per_level), "threshold": float(threshold),
                "seed": str(root.entropy)}
        h = hashlib.sha256(json.dumps({
            "token": _e.store_token(limit_state, token), "settings": _e.dataclasses.asdict(settings),
            "threshold": float(threshold), "entropy": str(root.entropy), "spawn": list(root.spawn_key),
            "noise_shape": list(noise_shape)}, sort_keys=True).encode()).hexdigest()[:16]
        store = _e._Store(output, h, overwrite, info, response_attrs or {})
    eng = _e._Engine(limit_state, noise_shape, threshold, settings, root, chunks, scheduler, store, max_evaluations)

    if not (isinstance(independent_runs, (int, np.integer)) and independent_runs >= 1):
        raise ValueError(f"independent_runs must be an integer >= 1, got {independent_runs!r}.")
    min_runs = int(independent_runs)
    runs, sizes, offsets = [], [], []
    n, offset = settings.samples, 0
    converged = False
    while True:
        runs.append(eng.run(len(runs), offset, n))
        sizes.append(n)
        offsets.append(offset)
        offset += n
        if method == "subset" and len(runs) < min_runs:
            continue
        est = _e._estimate(runs, sizes, method, confidence)
        if target_cv is None:
            break
        if est["cv"] <= target_cv:
            converged = True
            break
        spent = sum(_e._run_summary(lv)[2] for lv in runs)
        if method == "monte_carlo":
            need = sum(sizes) * (est["cv"] ** 2 / target_cv**2 - 1.0) * 1.1 if np.isfinite(est["cv"]) else n
            n = max(int(math.ceil(need)), settings.samples)
            more = n
        else:  # one more run of the same size, costing as much as the largest so far
            more = max(_e._run_summary(lv)[2] for lv in runs)
        if max_evaluations is not None and spent + more > max_evaluations:
            if method == "monte_carlo" and spent < max_evaluations:
                n = int(max_evaluations - spent)
            else:
                break
        if len(runs) >= 1000:
            break
    return _e._to_dataset(runs, sizes, offsets, settings, threshold, target_cv, converged, confidence,
                       root, response_attrs or {}, method)


def surface_from_noise(noise, psd, *, shape, spacing):
    """The surface [m] a white-noise field (e.g. one of ``failure_noise``) maps to (Eqs. 33-34).

    The same map :func:`failure_probability` evaluates, so a failure sample can be looked at,
    or fed to another model (the BEM, a beam model).
    """
    f = _s.NoiseToSurface(psd, shape=shape, spacing=spacing)
    return f.height_array(f(noise))


# ============================================================================ public: surfaces
def _psd_token(amplitude):
    return hashlib.sha256(np.ascontiguousarray(amplitude).tobytes()).hexdigest()[:16]


@_e.checked(*_e.SETTING_RULES, **_e.SURFACE_RULES)
def failure_probability(
    psd,
    *,
    threshold,
    relative_humidity,
    shape,
    spacing: float,
    quantity: str = "adhesive_energy",
    contact_model: str = "modified_dmt",
    method: str = "subset",
    samples_per_level: int = 1000,
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
) -> xr.Dataset:
    r"""Probability that a zone's adhesive energy (or pull-off pressure) exceeds a threshold.

    One model evaluation = one surface of ``shape`` pixels generated from ``psd`` (Eqs. 33-34,
    the white noise being the random input), its modified-DMT curve at one humidity (Eq. 16) and
    its adhesive energy (Eq. 13, from the equilibrium outwards) or pull-off pressure. With the
    beam's critical energy as threshold, ``rs.critical_adhesive_energy(length=l)`` (Eq. 36), the
    result is the pull-out proxy of P(stuck) of paper §5.2.

    Parameters
    ----------
    psd : xarray.DataArray or callable
        As in :func:`roughstick.generate_surfaces`.
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
    contact_model : {"modified_dmt", "fft_bem"}, default "modified_dmt"
        Eq. 16 (2 ms per 128 x 128 zone) or the fast boundary-element model (~40 ms; periodic
        zones only). On 128² Table-4 zones the Eq. 16 tail below P ~ 1e-2 is made of states
        whose boundary-element Γ is typical (docs/rare_events.md): use ``"fft_bem"`` there.
    method, samples_per_level, level_probability, independent_runs, proposal, proposal_scale,
    target_acceptance,
    target_cv, max_evaluations, max_levels, confidence, seed, chunks, scheduler
        See :func:`subset_simulation`.
    material, material2, adsorbed_layer, connectivity
        As in :func:`roughstick.rough_contact_curves`.
    points_per_water_height : float, default 20
        Distance step h_water / this. Measured on 30 Table-4 128 x 128 zones at 50 % RH against
        40 points: median |ΔΓ|/Γ 0.2 % (max 0.6 %) at 20, 0.8 % (max 6 %) at 10.
    lower : float, default 2
        First bottom of each surface's distance grid, in sqrt(m0) (the equilibrium of those
        zones lies at 1.4-3 sqrt(m0), median 2.5); extended by 0.5 sqrt(m0) until the curve has
        an equilibrium.
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
        With ``contact_model="modified_dmt"``, re-evaluate this many failure samples with the
        FFT-BEM (``failures_confirmed_by_bem`` and ``failure_bem_ratio``; a ValidityWarning
        when the ratio is below one half, artefacts, or fewer than half stay failures). 0: no
        check.

    Returns
    -------
    xarray.Dataset
        The variables of :func:`subset_simulation` along ``rh``.
    """
    rh_in = relative_humidity_array(relative_humidity)
    if quantity not in _s.QUANTITIES:
        raise ValueError(f"quantity must be one of {_s.QUANTITIES}, got {quantity!r}.")
    if not (np.isfinite(threshold) and threshold > 0):
        raise ValueError(f"threshold must be a positive finite number in SI units, got {threshold!r}.")
    to_surface = _s.NoiseToSurface(psd, shape=shape, spacing=spacing)
    ny, nx, dy, dx = to_surface.ny, to_surface.nx, to_surface.dy, to_surface.dx
    m0 = to_surface.variance
    hw = np.atleast_1d(water_height(rh_in, adsorbed_layer=adsorbed_layer).values)
    ptoken = _psd_token(to_surface.amplitude)
    units = "J m-2" if quantity == "adhesive_energy" else "Pa"
    mat = [_s.material_token(m) for m in (material, material2)]
    out = []
    for i, rh in enumerate(rh_in):
        model = _s.SurfaceResponse(
            to_surface, relative_humidity=rh, water_height=hw[i], quantity=quantity,
            material=material, material2=material2, adsorbed_layer=adsorbed_layer,
            points_per_water_height=points_per_water_height, lower=lower, connectivity=connectivity,
            periodic=periodic, patches=patches, contact_model=contact_model)
        key = {"psd": ptoken, "shape": [ny, nx], "spacing": [dy, dx], "rh": float(rh),
               "hw": float(hw[i]), "materials": mat, "quantity": quantity,
               "pph": float(points_per_water_height), "lower": float(lower),
               "connectivity": int(connectivity), "periodic": bool(periodic),
               "patches": int(patches), "map": "circulant/1"}
        if contact_model != "modified_dmt":  # earlier outputs (Eq. 16 only) still resume
            key["contact_model"] = contact_model
        token = json.dumps(key)
        sub = None if output is None else pathlib.Path(output) / f"rh-{rh:.4f}"
        ds = subset_simulation(
            model, noise_shape=model.noise_shape, threshold=float(threshold), method=method,
            samples_per_level=samples_per_level, level_probability=level_probability,
            independent_runs=independent_runs, proposal=proposal, proposal_scale=proposal_scale, target_acceptance=target_acceptance,
            max_levels=max_levels, target_cv=target_cv, max_evaluations=max_evaluations,
            confidence=confidence, seed=seed, chunks=chunks, scheduler=scheduler, output=sub,
            overwrite=overwrite, token=token,
            response_attrs={"units": units, "quantity": quantity})
        if contact_model == "modified_dmt":  # rare states are where Eq. 16 may fail: measure it
            ds = _s.bem_check(ds, model, float(threshold), check_failures)
        # index every dim so humidities with different level/run/failure counts align (outer join)
        out.append(ds.assign_coords({d: np.arange(n) for d, n in ds.sizes.items() if d not in ds.coords}))
    fill = {"accepted": np.int8(-1), "chain": np.int32(-1)}
    res = xr.concat(out, dim="rh", join="outer", fill_value=fill, combine_attrs="drop_conflicts",
                    data_vars="all", coords="different", compat="equals")
    for d in res.dims:  # the index coords added above for the alignment: CF attrs to be written
        if d in _e.ATTRS and not res[d].attrs:
            res[d].attrs = dict(_e.ATTRS[d])
    res = res.assign_coords(rh=("rh", rh_in, {"units": "1", "long_name": "relative humidity",
                                             "standard_name": "relative_humidity"}))
    res = res.assign_coords(water_height=("rh", hw, {"units": "m", "long_name": "water height h_water"}))
    if np.ndim(relative_humidity) == 0:
        res = res.squeeze("rh")
    res.attrs.update({"quantity": quantity, "contact_model": contact_model, "threshold": float(threshold), "threshold_units": units,
                      "zone_shape": [ny, nx], "spacing": float(dx), "zone_area": float(ny * nx * dx * dy),
                      "patches": int(patches), "periodic": int(periodic), "height_rms": math.sqrt(m0),
                      "adsorbed_layer": str(getattr(adsorbed_layer, "__name__", adsorbed_layer)),
                      "points_per_water_height": float(points_per_water_height)})
    append_history(res, f"failure_probability(quantity={quantity!r}, shape={ny}x{nx}, spacing={dx:.3g} m, "
                        f"method={method!r}, patches={patches})")
    return res


def weakest_link(result: xr.Dataset, *, patches) -> xr.Dataset:
    r"""Failure probability of a structure of ``patches`` independent patches (weakest link).

    .. math:: P_m = 1 - (1 - p)^m

    The interval maps through the same increasing function, so it keeps its confidence level:
    :math:`[1-(1-p_{lo})^m,\ 1-(1-p_{hi})^m]`; the coefficient of variation by the delta method,
    :math:`\delta_m = \delta\, m p (1-p)^{m-1} / P_m`.

    The structure fails if any patch fails: a beam held by any one of ``m`` interaction zones
    along its landing length, a contact failing at its weakest spot. Patches must be
    independent (longer than the correlation length of the PSD, about 2π/q0) and each must be
    a patch of the kind the probability was computed for. A zone's adhesive energy is an
    average over the zone, not a union of its parts: do not scale it this way.

    Parameters
    ----------
    result : xarray.Dataset
        Output of :func:`failure_probability` / :func:`subset_simulation`.
    patches : int, sequence or xarray.DataArray
        Number(s) of patches m >= 1; a sequence adds a ``patches`` dimension.

    Returns
    -------
    xarray.Dataset
        ``failure_probability``, ``failure_probability_lower``/``_upper``,
        ``coefficient_of_variation`` of the structure, and ``patch_failure_probability``.
    """
    m = patches
    if not isinstance(m, xr.DataArray):
        arr = np.asarray(m)
        m = xr.DataArray(arr, dims=("patches",), coords={"patches": arr}) if arr.ndim else xr.DataArray(arr)
    if np.any(np.asarray(m) < 1):
        raise ValueError(f"patches must be >= 1, got {patches!r}.")
    p = result["failure_probability"]
    lo = result["failure_probability_lower"]
    hi = result["failure_probability_upper"]
    cv = result["coefficient_of_variation"]

    def scale(q):
        return -np.expm1(m * np.log1p(-q))

    pm = scale(p)
    with np.errstate(invalid="ignore", divide="ignore"):
        cvm = cv * m * p * np.exp((m - 1) * np.log1p(-p)) / pm
    ds = xr.Dataset({
        "failure_probability": _e._attrs(pm, "failure_probability"),
        "failure_probability_lower": _e._attrs(scale(lo), "failure_probability_lower"),
        "failure_probability_upper": _e._attrs(scale(hi), "failure_probability_upper"),
        "coefficient_of_variation": _e._attrs(cvm, "coefficient_of_variation"),
        "patch_failure_probability": _e._attrs(p, "failure_probability", long_name="failure probability of one patch"),
    })
    ds.attrs = {**result.attrs, "title": "weakest-link failure probability of m independent patches"}
    append_history(ds, "weakest_link: P_m = 1 - (1 - p)^m, interval mapped through the same function")
    return ds


@_e.checked("target_cv", "max_evaluations", "seed", length="length?")
def stiction_probability_subset(
    psd,
    *,
    relative_humidity,
    shape,
    spacing: float,
    length: float | None = None,
    beam: Cantilever = PAPER_CANTILEVER,
    method: str = "subset",
    target_cv: float | None = 0.3,
    max_evaluations: int | None = 20_000,
    seed=0,
    **options,
) -> xr.Dataset:
    r"""P(stuck) of a beam from the zone model, small values included: :math:`P(\Gamma > \Gamma_{crit}(l))`.

    The rare-event counterpart of :func:`roughstick.stiction_probability` (which counts a
    Monte-Carlo sample): the pull-out proxy of paper §5.2 (a beam of length ``l`` stays stuck
    when the zone's adhesive energy, Eq. 13, exceeds :math:`\Gamma_{crit}` of Eq. 36 at
    :math:`s = l`), estimated by :func:`failure_probability` with ``method`` ("subset" or
    "monte_carlo") until the coefficient of variation meets ``target_cv`` or
    ``max_evaluations`` is spent (``converged`` says which). The output carries the names
    :func:`roughstick.crossing_humidity` reads, so ``rs.crossing_humidity(out, level=1e-3)``
    gives the RH at which P(stuck) reaches 1e-3 with its interval.

    Parameters
    ----------
    psd, relative_humidity, shape, spacing, method, target_cv, max_evaluations, seed
        As in :func:`failure_probability` (``relative_humidity`` a sequence: an ``rh`` dim).
    length : float, optional
        Beam length [m]; default ``beam.length``.
    beam : Cantilever
        Geometry and modulus of the beam (Eq. 36).
    **options
        Further keywords of :func:`failure_probability` (``samples_per_level``, ``output`` ...).

    Returns
    -------
    xarray.Dataset
        ``stiction_probability`` with ``stiction_probability_lower``/``_upper`` (the
        confidence interval), ``coefficient_of_variation``, ``n_evaluations``, ``converged``,
        and the level samples of :func:`failure_probability`; attribute
        ``critical_adhesive_energy`` [J m-2].
    """
    gc = float(critical_adhesive_energy(length=beam.length if length is None else length, beam=beam))
    ds = failure_probability(psd, threshold=gc, relative_humidity=relative_humidity, shape=shape,
                             spacing=spacing, method=method, target_cv=target_cv,
                             max_evaluations=max_evaluations, seed=seed, **options)
    ds = ds.rename({"failure_probability": "stiction_probability",
                    "failure_probability_lower": "stiction_probability_lower",
                    "failure_probability_upper": "stiction_probability_upper"})
    ds["stiction_probability"].attrs["long_name"] = "probability that the beam stays stuck"
    ds.attrs.update({"critical_adhesive_energy": gc,
                     "beam_length": float(beam.length if length is None else length)})
    append_history(ds, f"stiction_probability_subset(length={ds.attrs['beam_length']:.4g} m, method={method!r})")
    return ds


_BEAM_VARS = ("failure_probability", "failure_probability_lower", "failure_probability_upper",
              "coefficient_of_variation", "au_beck_cv", "n_evaluations", "converged")


@_e.checked("target_cv", "max_evaluations", "samples_per_level", "seed")
def beam_stiction_probability_subset(
    bank: xr.DataArray,
    *,
    beam_length,
    protocol: str = "release",
    beam: Cantilever = PAPER_CANTILEVER,
    patch_length: float | None = None,
    method: str = "subset",
    target_cv: float | None = 0.3,
    max_evaluations: int | None = 20_000,
    samples_per_level: int = 1000,
    seed=0,
    output=None,
    overwrite: bool = False,
    **options,
) -> xr.Dataset:
    r"""P(stuck) of the beam-scale model (sharp front on a patch bank) by subset simulation.

    The rare-event counterpart of :func:`roughstick.simulate_beams` (``model="sharp_front"``):
    patch :math:`j` of a beam takes law :math:`\lfloor\Phi(z_j) n_{law}\rfloor` of ``bank``
    for standard-normal :math:`z_j` (uniform, independent laws, as ``simulate_beams`` draws
    them), and a released beam is stuck exactly when
    :math:`R = \max_j \Gamma_j x_{j+1}^4/K > 1` (the front stops at the first patch whose
    Eq. 36 equilibrium lies before its far edge; :math:`K = \tfrac32 E h^2 t^3`). One model
    evaluation is one beam (microseconds), so the cost is the sampler's.

    On a bank the same probability has a closed form, :math:`1-\prod_j(1-q_j)` with
    :math:`q_j` the fraction of laws above :math:`K/x_{j+1}^4`, returned as
    ``bank_stiction_probability``: the subset estimate is checked against it (tests). Both are
    probabilities *given the bank*: a bank of :math:`n` laws cannot give a non-zero P(stuck)
    below :math:`1/n` (one law able to hold the beam's last patch already gives :math:`1/n`),
    so smaller risks need the zone model (:func:`stiction_probability_subset`, the pull-out
    proxy on surfaces) or a larger bank. ``protocol="step_up"``: a beam stuck at the first RH
    stays stuck and a free one stays free (the front only closes), so P(stuck) at every RH is
    that of the first.

    Parameters
    ----------
    bank : xarray.DataArray
        Adhesive energy [J m-2] over ``(law, rh)`` (:func:`roughstick.build_patch_bank`).
    beam_length : float or sequence
        Beam lengths [m].
    protocol : {"release", "step_up"}
    beam : Cantilever
        Thickness, gap, width and modulus (its length is replaced by ``beam_length``).
    patch_length : float, optional
        Patch length [m]; default the beam thickness (paper §5.2).
    method, target_cv, max_evaluations, samples_per_level, seed
        As in :func:`subset_simulation` (the same seed at every RH and length: common random
        numbers).
    output : path, optional
        Folder; one sub-folder per (rh, length) with one file per completed level (resume).
    **options
        Further keywords of :func:`subset_simulation`.

    Returns
    -------
    xarray.Dataset
        Over ``(rh, beam_length)``: ``stiction_probability`` with
        ``stiction_probability_lower``/``_upper``, ``coefficient_of_variation``,
        ``au_beck_cv``, ``n_evaluations``, ``converged`` and ``bank_stiction_probability``.
    """
    if protocol not in PROTOCOLS:
        raise ValueError(f"protocol must be one of {PROTOCOLS}, got {protocol!r}")
    if set(bank.dims) != {"law", "rh"}:
        raise ValueError(f"bank must have dims ('law', 'rh') (an energy bank of build_patch_bank), got "
                         f"{bank.dims}; method='subset' works on the sharp-front model only")
    bank = bank.transpose("law", "rh")
    energy = adhesive_energy_values(bank)
    rh = bank["rh"].values if "rh" in bank.coords else np.arange(bank.sizes["rh"])
    if protocol == "step_up" and np.any(np.diff(rh) <= 0):
        raise ValueError("protocol='step_up' needs the bank's rh coordinate increasing")
    lengths, patch_length = _beam_axes(beam_length, patch_length, beam)
    kterm = beam.stiffness_term  # K does not depend on the length
    options.setdefault("scheduler", "sync")  # microseconds per beam: dask tasks would cost more
    options.setdefault("chunks", 100_000)
    rows = []
    for k in range(len(rh)):
        kk = 0 if protocol == "step_up" else k
        row = []
        for length in lengths:
            w = _b.edge_weights(_n_patches(length, patch_length), patch_length, float(length), kterm)
            model = _b.BeamMargin(energy[:, kk], w)
            sub = None if output is None else pathlib.Path(output) / f"rh-{rh[kk]:.4f}-l-{length * 1e6:.4g}um"
            ds = subset_simulation(model, noise_shape=model.noise_shape, threshold=1.0, method=method,
                                   samples_per_level=samples_per_level, target_cv=target_cv,
                                   max_evaluations=max_evaluations, seed=seed, output=sub,
                                   overwrite=overwrite, token=model.token(),
                                   response_attrs={"long_name": "stuck margin max_j Gamma_j x_j+1^4 / K"},
                                   **options)
            d = ds[list(_BEAM_VARS)].drop_vars([c for c in ds.coords], errors="ignore")
            d["bank_stiction_probability"] = xr.DataArray(model.exact(), attrs={
                "units": "1", "long_name": "P(stuck) on the bank, closed form 1 - prod_j (1 - q_j)"})
            row.append(d)
        rows.append(xr.concat(row, dim="beam_length"))
    res = xr.concat(rows, dim="rh")
    res = res.rename({"failure_probability": "stiction_probability",
                      "failure_probability_lower": "stiction_probability_lower",
                      "failure_probability_upper": "stiction_probability_upper"})
    res["stiction_probability"].attrs["long_name"] = "probability that the beam stays stuck"
    res = res.assign_coords(rh=("rh", np.asarray(rh, dtype=float), {
        "units": "1", "long_name": "relative humidity", "standard_name": "relative_humidity"}),
        beam_length=("beam_length", lengths, {"units": "m", "long_name": "beam length"}))
    for name in ("coefficient_of_variation", "au_beck_cv", "n_evaluations", "converged"):
        res[name].attrs.setdefault("units", "1")
    if np.ndim(beam_length) == 0:
        res = res.squeeze("beam_length")
    res.attrs.update({"method": method, "protocol": protocol, "patch_length": patch_length,
                      "n_law": int(energy.shape[0]), "bank_resolution": 1.0 / energy.shape[0],
                      "target_cv": float("nan") if target_cv is None else float(target_cv),
                      "probability_model": "sharp-front beam on the patch bank (beam_model), laws drawn "
                                           "uniformly by white noise; P given the bank"})
    append_history(res, f"beam_stiction_probability_subset(method={method!r}, protocol={protocol!r}, "
                        f"n_law={energy.shape[0]})")
    return res
