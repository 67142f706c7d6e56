r"""Subset simulation: small probabilities of any limit state of standard-normal white noise; the
weakest link of independent patches.

Every roughstick surface is standard-normal white noise filtered by the PSD (Eqs. 33-34), so a
failure event (a zone's adhesive energy above the critical energy of a beam, Eq. 36; a beam of
random patches staying stuck) is a region of a white-noise space, and its probability is
estimated by

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
(run, level, chain, step)).
"""

from __future__ import annotations

import hashlib
import json
import math
import warnings

import numpy as np
import xarray as xr

from .._core.api import renamed_keywords
from .._core.conventions import append_history
from .._core.dask import as_seed_sequence
from .._core.remedy import spell
from .._core.validate import external_stacklevel
from . import _engine as _e

__all__ = ["subset_simulation", "weakest_link"]


@renamed_keywords(samples_per_level="n_per_level")
@_e.checked(*_e.SETTING_RULES)
def subset_simulation(
    limit_state,
    *,
    noise_shape,
    threshold: float,
    method: str = "subset",
    n_per_level: int = 1000,
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
        distributed). A NaN response is missing, never "no failure": it is counted per level
        (``nan_responses``), left out of the level's fraction (a chain rejects a NaN proposal),
        and the interval is widened to cover every NaN failing or none (with a warning). Return
        ``-inf`` where a state certainly does not fail.
    noise_shape : tuple of int
        Shape of the white noise. Level-0 sample ``i`` is
        ``realization_rng(SeedSequence(seed), i).standard_normal(noise_shape)``.
    threshold : float
        Failure when the response is strictly above it.
    method : {"subset", "monte_carlo"}
        Subset simulation or crude Monte Carlo (batches of ``n_per_level``).
    n_per_level : int, default 1000
        Samples per level of each run (Monte Carlo: of the first batch).
    level_probability : float, default 0.2
        Conditional probability p0 of each intermediate level; p0 * n_per_level chains of
        length 1/p0 (0.2 rather than the customary 0.1: shorter, less correlated chains;
        docs/rare_events.md).
    independent_runs : int, default 1
        Subset simulation runs at least this many independent runs (each from its own level-0
        samples) and reports their mean. With 3 or more, the spread of the runs gives a second,
        model-free cv estimate, used when it is the larger.
    proposal : {"adaptive", "pcn"}, default "adaptive"
        ``"pcn"``: every coordinate moves as :math:`\rho z + \sigma\xi`,
        :math:`\sigma` = ``proposal_scale``, :math:`\rho = \sqrt{1-\sigma^2}`, fixed.
        ``"adaptive"``: adaptive conditional sampling (Papaioannou et al. 2015): coordinate
        :math:`i` moves with :math:`\sigma_i = \min(1, \lambda s_i)`, :math:`s_i` the spread of
        the level's seeds in that coordinate, :math:`\lambda` updated after every round of the
        chains towards ``target_acceptance``. Both keep the Gaussian prior exactly.
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
        ``target_cv``; subset simulation stops only once at least 3 runs agree (the spread of
        their estimates is consistent with their reported cv: ``spread_p_value`` >= 0.05), or
        10 runs give the spread's own cv. None: ``independent_runs`` runs (Monte Carlo: one
        batch).
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
        ``coefficient_of_variation``, ``n_evaluations``, ``converged``, ``few_lineages`` (runs
        flagged for fewer than 5 effective final lineages), ``spread_p_value``; per ``run``
        ``run_probability``, ``run_cv``, ``run_lineages``; per ``(run, level)`` the thresholds,
        conditional probabilities, correlation factors, acceptance and ``nan_responses``; per
        ``(run, level, round)`` the proposal scale; per ``(run, level, sample)`` every state's
        ``response``, ``proposal_response``, ``accepted`` and ``chain``; ``failure_noise`` of
        the last level's failure samples.

    Notes
    -----
    One run: :math:`\hat P_r = \prod_j \hat p_j`. Its cv :math:`\delta_r` is the genealogical
    estimate: every state descends from one level-0 sample, :math:`\hat P_r` is the sum of the
    contributions of the :math:`N` level-0 samples (:math:`\propto n_i`, the final failures
    descending from sample :math:`i`), and
    :math:`\delta_r^2 = \frac{N}{N-1}\sum_i (n_i/n_F - 1/N)^2` (the ancestral-lineage estimator
    of sequential Monte Carlo, Chan & Lai 2013, Lee & Whiteley 2018). It contains the
    correlation of the states of a chain and between levels. It equals
    :math:`\frac{N}{N-1}(1/N_{\rm eff} - 1/N)`, :math:`N_{\rm eff} = 1/\sum_i (n_i/n_F)^2` the
    effective number of independent final lineages (``run_lineages``), so it cannot exceed 1 and
    is optimistic exactly when the lineages collapse: the reported :math:`\delta_r^2` is it
    times :math:`N_{\rm eff}/(N_{\rm eff}-1)` (a variance from :math:`N_{\rm eff}` values;
    infinite for one lineage, whose interval is then [0, 1]), and a run with
    :math:`N_{\rm eff} < 5` is flagged (``few_lineages``, a warning naming ``n_per_level``).
    ``au_beck_cv`` is Au & Beck's (2001, Eqs. 25-30) :math:`\sum_j \frac{1 - p_j}{N p_j}(1 + \gamma_j)`, :math:`\gamma_j`
    from the lag correlations of the failure indicator inside the chains; it neglects the
    correlation between levels and underestimates the error (docs/rare_events.md).
    :math:`R` runs: :math:`\hat P = \overline{\hat P_r}`, cv
    :math:`\sqrt{\overline{\delta_r^2}/R}`; ``between_run_cv``
    :math:`= s(\hat P_r)/(\sqrt R\,\hat P)` replaces it when :math:`R \ge 3` and it is larger.
    Interval: log-normal, :math:`\hat P\sqrt{1+\delta^2}\,e^{\pm q\sqrt{\ln(1+\delta^2)}}`,
    :math:`q` the quantile of Student's t with :math:`\sum_r (N_{{\rm eff},r} - 1)` degrees of
    freedom (genealogical cv: the variance rests on the lineages) or :math:`R - 1` (between-run
    cv). Monte Carlo: :math:`k/n`, :math:`\delta = \sqrt{(1-\hat P)/(n\hat P)}`, Wilson
    interval. NaN responses: :math:`p_j` over the finite responses; the interval's ends are
    multiplied by :math:`\prod_j (1-f_j)` and :math:`\prod_j (p_j(1-f_j)+f_j)/\prod_j p_j`
    (:math:`f_j` the NaN share of level :math:`j`'s evaluations: every NaN a non-failure, or a
    failure); Monte Carlo: the Wilson bounds of :math:`k` and :math:`k + u` out of :math:`n`.

    Examples
    --------
    >>> from scipy.stats import norm
    >>> ds = rs.reliability.subset_simulation(lambda z: float(z.sum()) / 2, noise_shape=(4,),
    ...                                       threshold=2.0, n_per_level=200, scheduler="sync")
    >>> bool(ds.failure_probability_lower < norm.sf(2.0) < ds.failure_probability_upper)
    True
    """
    settings = _e._Settings.checked(
        method=method, n_per_level=n_per_level, level_probability=level_probability, proposal=proposal,
        proposal_scale=proposal_scale, target_acceptance=target_acceptance, max_levels=max_levels)
    settings.check_stopping(target_cv, max_evaluations, confidence)
    response_attrs = {"units": "1", **(response_attrs or {})}  # a bare limit state: dimensionless
    root = as_seed_sequence(seed)
    store = None
    if output is not None:
        info = {"method": method, "samples_per_level": int(n_per_level), "threshold": float(threshold),
                "seed": str(root.entropy)}
        h = hashlib.sha256(json.dumps({
            "token": _e.store_token(limit_state, token), "settings": _e.dataclasses.asdict(settings),
            "threshold": float(threshold), "entropy": str(root.entropy), "spawn": list(root.spawn_key),
            "noise_shape": list(noise_shape)}, sort_keys=True).encode()).hexdigest()[:16]
        store = _e._Store(output, h, overwrite, info, response_attrs)
    eng = _e._Engine(limit_state, noise_shape, threshold, settings, root, chunks, scheduler, store, max_evaluations)
    if not (isinstance(independent_runs, (int, np.integer)) and independent_runs >= 1):
        raise ValueError(f"independent_runs must be an integer >= 1, got {independent_runs!r}.")
    runs, converged = _run_to_target(eng, settings, int(independent_runs), target_cv, max_evaluations,
                                     confidence)
    ds = _e._to_dataset(runs, settings, threshold=threshold, target_cv=target_cv, converged=converged,
                        confidence=confidence, root=root, rattrs=response_attrs)
    _warn_if_not_honest(ds, settings)
    return ds


def _warn_if_not_honest(ds, settings):
    """Warn when the runs' final failures descend from few lineages (the genealogical cv is
    unreliable: the interval is wide, the remedy is more samples per level) or when responses
    were NaN (counted as missing; the interval covers them failing or not)."""
    if int(ds.few_lineages) and ds.sizes["run"] < _e.SPREAD_RUNS:  # else the runs' spread checks it
        few = [(r, float(v)) for r, v in enumerate(ds.run_lineages.values)
               if float(ds.run_probability[r]) > 0 and v < _e.MIN_LINEAGES]
        listed = ", ".join(f"run {r}: {v:.1f}" for r, v in few)
        warnings.warn(
            f"subset simulation: the final failures descend from fewer than {_e.MIN_LINEAGES:g} effective "
            f"independent level-0 lineages ({listed}): the reported cv "
            f"({float(ds.coefficient_of_variation):.2g}, corrected for them) rests on them and is a rough "
            f"figure, and the interval uses Student's t on their number ({ds.attrs['interval_method']}). For a "
            f"trustworthy cv, give the levels more samples: {spell('samples_per_level', 2 * settings.samples)} "
            f"(now {settings.samples}).", UserWarning, stacklevel=external_stacklevel())
    nan = ds.nan_responses.fillna(0).sum("run")
    if float(nan.sum()) > 0:
        per = ", ".join(f"level {j}: {int(v)}" for j, v in enumerate(nan.values) if v > 0)
        warnings.warn(
            f"subset simulation: {int(nan.sum())} NaN responses ({per}) of {int(ds.n_evaluations)} evaluations: "
            "they count as missing (the probability is over the finite responses), and the interval "
            "is widened to cover them all failing or none. Make the limit state return a finite response "
            "(-inf where the state certainly does not fail).", UserWarning, stacklevel=external_stacklevel())


def _run_to_target(eng, settings, min_runs, target_cv, max_evaluations, confidence):
    """Add runs (subset) or batches (Monte Carlo) until the cv meets ``target_cv`` or the budget
    is spent; returns the :class:`~._engine.Runs` and whether the target was met."""
    method = settings.method
    runs = _e.Runs()
    n, offset = settings.samples, 0
    while True:
        runs.add(eng.run(len(runs), offset, n), n, offset)
        offset += n
        if method == "subset" and len(runs) < min_runs:
            continue
        est = _e._estimate(runs, method, confidence)
        if target_cv is None:
            return runs, False
        if est.cv <= target_cv and (method == "monte_carlo" or est.interval == "wilson"
                                    or est.agrees(len(runs))):
            return runs, True
        spent = runs.evaluations()
        if method == "monte_carlo":
            need = sum(runs.sizes) * (est.cv ** 2 / target_cv**2 - 1.0) * 1.1 if np.isfinite(est.cv) else n
            n = max(int(math.ceil(need)), settings.samples)
            more = n
        else:  # one more run of the same size, costing as much as the largest so far
            more = runs.largest_run()
        if max_evaluations is not None and spent + more > max_evaluations:
            if method == "monte_carlo" and spent < max_evaluations:
                n = int(max_evaluations - spent)
            else:
                return runs, False
        if len(runs) >= 1000:
            return runs, False


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
        Output of :func:`failure_probability` or :func:`subset_simulation`.
    patches : int, sequence or xarray.DataArray
        Number(s) of patches m >= 1; a sequence adds a ``patches`` dimension.

    Returns
    -------
    xarray.Dataset
        ``failure_probability``, ``failure_probability_lower``/``_upper``,
        ``coefficient_of_variation`` of the structure, and ``patch_failure_probability``.

    Examples
    --------
    >>> one = xr.Dataset({"failure_probability": 1e-3, "failure_probability_lower": 5e-4,
    ...                   "failure_probability_upper": 2e-3, "coefficient_of_variation": 0.3})
    >>> p = rs.reliability.weakest_link(one, patches=[1, 10])
    >>> p.failure_probability.values.round(5)
    array([0.001  , 0.00996])
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
