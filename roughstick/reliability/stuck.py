r"""P(stuck): the probability that a cantilever stays stuck, by one verb with a ``method``.

The paper's §5 proxy counts a Monte-Carlo sample of the interaction zone's Γ against the beam's
critical energy (Eq. 36); the beam-scale model releases beams on random patches; small
probabilities need subset simulation of either. :func:`stuck_probability` is the front door to
all of them; what ``data`` is (a sample, simulated beams, a PSD, a bank of patch laws) and
``method`` say which one runs.
"""

from __future__ import annotations

import inspect
import warnings

import numpy as np
import xarray as xr

from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.validate import external_stacklevel
from ..beam.front_tail import adhesive_energy_ccdf, stuck_probability_from_ccdf
from ..beam.sharp_front import simulate, stuck_probability_from_beams
from ..stiction.cantilever import PAPER_CANTILEVER, Cantilever
from ..stiction.risk import stuck_probability_from_sample
from ..stiction.strip_tail import strip_stuck_probability
from ._beam import _bank_stuck_probability
from .surface import _zone_stuck_probability

__all__ = ["stuck_probability", "METHODS"]

#: How :func:`stuck_probability` estimates P(stuck).
METHODS = ("count", "beam", "front", "subset", "monte_carlo", "strips")

#: The inputs each method reads, beside ``data`` (and ``beam``, ``confidence``).
_TAKES = {
    "count": {"beam_length", "dim", "interval"},
    "beam": {"beam_length", "interval", "n", "seed", "protocol", "beam_model", "patch_length"},
    "front": {"beam_length", "dim", "patch_length"},
    "subset": {"beam_length", "seed", "target_cv", "max_evaluations", "n_per_level", "protocol",
               "patch_length", "relative_humidity", "shape", "spacing", "model"},
}
_TAKES["monte_carlo"] = _TAKES["subset"]
_TAKES["strips"] = {"beam_length", "seed", "relative_humidity", "spacing", "model", "n", "target_cv"}
#: ... and the ones that apply to one kind of data only.
_ZONE_ONLY = {"relative_humidity", "shape", "spacing", "model"}
_BANK_ONLY = {"protocol", "patch_length"}

_WHAT = {
    "sample": "a sample of the adhesive energy",
    "beams": "simulated beams (rs.beam.simulate)",
    "psd": "a PSD",
    "bank": "a bank of patch laws",
}
_INTERVALS = ("wilson", "clopper-pearson", "exact")


def _kind(data) -> str:
    """What ``data`` is: "sample", "beams", "psd", "bank" or "unknown"."""
    if isinstance(data, xr.Dataset):
        if "stuck" in data:
            return "beams"
        return "sample" if "adhesive_energy" in data else "unknown"
    if isinstance(data, xr.DataArray):
        dims = set(data.dims)
        if "law" in dims:
            return "bank"
        if dims and dims <= {"q", "qx", "qy"}:
            return "psd"
        return "sample"
    return "psd" if callable(data) else "unknown"


def _check_combination(method, kind, given, options, data):
    """Refuse a method, data and keywords that do not go together, naming the fix."""
    if method in _INTERVALS:
        raise ValueError(f"method={method!r} is a binomial interval: write interval={method!r} "
                         f"(method= picks how P(stuck) is estimated: {', '.join(METHODS)}).")
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}.")
    fixes = {
        ("count", "psd"): "a PSD has no sample to count: pass method='subset' (or 'monte_carlo') with "
                          "relative_humidity=, shape= and spacing= (the zone), or count a sample of Γ "
                          "(rs.stiction.predict_adhesive_energy)",
        ("count", "bank"): "a bank of patch laws is not a sample: pass method='beam' (simulate n beams on it) "
                           "or method='subset' (small probabilities)",
        ("beam", "sample"): "method='beam' releases beams on a bank of patch laws "
                            "(rs.beam.build_patch_bank); count a sample of Γ with method='count'",
        ("beam", "psd"): "method='beam' releases beams on a bank of patch laws: build one from the PSD "
                         "with rs.beam.build_patch_bank, or pass method='subset' for the zone model",
        ("beam", "beams"): "these beams are simulated already: method='count' counts them",
        ("front", "psd"): "method='front' reads the Γ of strips of the beam: draw them with "
                          "rs.stiction.strip_adhesive_energy(psd, ...) and pass their adhesive_energy",
        ("front", "beams"): "these beams are simulated already: method='count' counts them",
        ("subset", "sample"): "subset simulation draws its own surfaces: pass the PSD (zone model) or a "
                              "bank of patch laws (beam model), or count this sample with method='count'",
        ("subset", "beams"): "subset simulation draws its own beams: pass the bank of patch laws, or count "
                             "these beams with method='count'",
    }
    fixes.update({("monte_carlo", k): v.replace("subset simulation", "method='monte_carlo'")
                  for (m, k), v in list(fixes.items()) if m == "subset"})
    fixes.update({("strips", k): "method='strips' draws the sub-zones of the beam's zone from a PSD: pass the PSD "
                                 "(rs.datasets.family_psd, rs.topography.fit_psd)" for k in ("sample", "beams", "bank")})
    if kind == "unknown":
        raise TypeError(f"data must be an xarray.DataArray or Dataset (a sample of Γ with units 'J m-2', "
                        f"simulated beams of rs.beam.simulate, a PSD, a bank of patch laws of "
                        f"rs.beam.build_patch_bank) or a callable PSD; got {type(data).__name__}. Wrap a plain "
                        "sample as xr.DataArray(values, dims='realization', attrs={'units': 'J m-2'}).")
    if (method, kind) in fixes:
        raise ValueError(f"stuck_probability(method={method!r}) on {_WHAT[kind]}: {fixes[method, kind]}.")
    wrong = sorted(k for k in given if k not in _TAKES[method])
    if kind == "beams":
        wrong += ["beam_length"] * ("beam_length" in given)
    elif kind == "psd":
        wrong += sorted(given & _BANK_ONLY)
    elif kind == "bank":
        wrong += sorted(given & _ZONE_ONLY)
    if method == "count" and options:
        wrong += sorted(options)
    if wrong:
        users = {k: [m for m in METHODS if k in _TAKES[m]] for k in wrong}
        why = "; ".join(f"{k}= is for method {' / '.join(map(repr, users[k]))}" if users[k] else
                        f"{k}= is not a keyword of stuck_probability" for k in dict.fromkeys(wrong))
        if kind == "beams" and "beam_length" in wrong:
            why += " (the beam lengths of simulated beams are theirs: select with .sel(beam_length=...))"
        raise TypeError(f"stuck_probability(method={method!r}) on {_WHAT[kind]} does not take "
                        f"{', '.join(dict.fromkeys(wrong))}: {why}.")
    if method == "strips":
        missing = [k for k in ("relative_humidity", "beam_length") if k not in given]
        if missing:
            raise TypeError(f"stuck_probability(psd, method='strips') needs {', '.join(f'{k}=' for k in missing)} "
                            "(e.g. relative_humidity=[0.7, 0.8], beam_length=[200e-6, 300e-6]); the zone is the "
                            "beam's own (beam=)")
    elif kind == "psd":
        missing = [k for k in ("relative_humidity", "shape", "spacing") if k not in given]
        if missing:
            raise TypeError(f"stuck_probability(psd, method={method!r}) needs the zone: "
                            f"{', '.join(f'{k}=' for k in missing)} (e.g. relative_humidity=[0.5, 0.7], "
                            "shape=(128, 128), spacing=5e-9)")
    if method == "front" and kind == "sample" and "beam_length" not in given:
        raise TypeError("stuck_probability(sample, method='front') needs beam_length= (every length is "
                        "composed from the strips' Γ CCDF, e.g. np.linspace(100e-6, 2e-3, 100))")
    if kind == "bank" and method != "count" and "beam_length" not in given:
        raise TypeError(f"stuck_probability(bank, method={method!r}) needs beam_length= (the beams "
                        "released on the bank, e.g. [200e-6, 400e-6])")


@renamed_keywords(length="beam_length", samples_per_level="n_per_level", n_realization="n",
                  contact_model="model")
@check_numbers(confidence="fraction", n="count", seed="seed", patch_length="length?", spacing="length?",
               target_cv="positive?", max_evaluations="count?", n_per_level="count")
def stuck_probability(
    data,
    *,
    method: str = "count",
    beam_length=None,
    beam: Cantilever = PAPER_CANTILEVER,
    confidence: float = 0.95,
    dim: str = "realization",
    interval: str = "wilson",
    n: int = 100,
    seed=0,
    protocol: str = "release",
    beam_model: str = "sharp_front",
    patch_length: float | None = None,
    relative_humidity=None,
    shape=None,
    spacing: float | None = None,
    model: str = "auto",
    target_cv: float | None = 0.3,
    max_evaluations: int | None = 20_000,
    n_per_level: int = 1000,
    **options,
) -> xr.Dataset:
    r"""Probability that a cantilever stays stuck, with its confidence interval.

    ``method`` says how it is estimated and ``data`` what from; each reads these keywords:

    - ``"count"`` on a sample of Γ [J m-2] along ``dim`` (the §5 proxy, P(Γ > Γ_crit), Eq. 36):
      ``beam_length``, ``dim``, ``interval``; on the beams of :func:`roughstick.beam.simulate`
      (the fraction stuck): ``interval``.
    - ``"beam"`` on a bank of patch laws (:func:`roughstick.beam.build_patch_bank`): releases
      ``n`` beams per length on it (:func:`roughstick.beam.simulate`) and counts them:
      ``beam_length`` (required), ``n``, ``seed``, ``protocol``, ``beam_model``,
      ``patch_length``, ``interval``.
    - ``"front"`` on a sample of the Γ of strips of the beam (patch length × width, e.g.
      :func:`roughstick.stiction.strip_adhesive_energy`) along ``dim``, or on a bank: the
      released sharp-front beam in closed form from their CCDF, every length at once
      (:func:`roughstick.beam.stuck_probability_from_ccdf`): ``beam_length`` (required),
      ``patch_length``, ``dim``; the interval is the CCDF's simultaneous band carried through.
    - ``"subset"`` (subset simulation: small probabilities) or ``"monte_carlo"`` (crude Monte
      Carlo, its reference), to ``target_cv``: on a PSD (the zone model, the §5.2 proxy)
      ``relative_humidity``, ``shape``, ``spacing`` (required), one ``beam_length``, ``model``,
      ``seed``, ``target_cv``, ``max_evaluations``, ``n_per_level`` (and the keywords of
      :func:`roughstick.reliability.failure_probability`: ``accurate_model="fft_bem"`` corrects
      an Eq. 16 run by the boundary-element model, one run, no ``target_cv``); on a bank of patch laws
      (the sharp-front beam) ``beam_length`` (required), ``protocol``, ``patch_length``,
      ``seed``, ``target_cv``, ``max_evaluations``, ``n_per_level``.

    - ``"strips"`` on a PSD: the beam's own interaction zone :math:`\Delta s \times w`, composed
      of independent sub-zones, small probabilities included
      (:func:`roughstick.stiction.strip_stuck_probability`: ``n`` Eq. 16 sub-zones, default
      12,000, recombined; with ``model="auto"`` the first ``n_accurate`` through fft_bem correct
      them, doubled up to twice where their ratios hold a cv above 0.6 × ``target_cv``): ``relative_humidity`` and
      ``beam_length`` (required), ``n``, ``seed``, ``spacing``, ``model``, ``target_cv`` (and
      ``n_accurate``, ``max_accurate``, ``accurate_model``, ``model_band``, ``refine_crossing``, ``n_combinations``,
      ``n_boot``).

    A keyword the method does not read, or data it cannot use, is refused with the fix.

    Parameters
    ----------
    data : xarray.DataArray, xarray.Dataset or callable
        What P(stuck) is estimated from (above).
    method : {"count", "beam", "front", "subset", "monte_carlo", "strips"}
        ``"count"``: count a given sample; ``"beam"``: release ``n`` beams per length on the bank
        (:func:`roughstick.beam.simulate`) and count them; ``"front"``: the sharp-front beam in
        closed form from the sample's (or bank's) Γ CCDF; ``"subset"``: subset simulation to
        ``target_cv`` (small probabilities: 1e-3 and below); ``"monte_carlo"``: crude Monte Carlo
        of the same model to ``target_cv`` (its reference); ``"strips"``: the beam's whole zone
        from recombined sub-zone laws, all lengths and humidities in one call.
    beam_length : float or sequence, optional
        Beam length(s) [m]; default ``beam.length`` (count on a sample, subset on a PSD).
    beam : Cantilever
        Geometry and modulus of the beams (their length is ``beam_length``).
    confidence : float, default 0.95
        Level of the interval.
    dim : str, default "realization"
        The sample dimension (count on a sample).
    interval : {"wilson", "clopper-pearson"}
        Binomial interval of a count.
    n : int, default 100
        Beams per length (beam).
    seed : int or numpy.random.SeedSequence, default 0
        Root seed (beam, subset, monte_carlo).
    protocol : {"release", "step_up"}
        Beams released afresh at every RH, or RH stepped up with the beam in place (on a bank).
    beam_model : {"sharp_front", "cohesive"}
        The beam model of ``"beam"`` (subset simulation is sharp-front only).
    patch_length : float, optional
        Patch length [m] on a bank; default the beam thickness.
    relative_humidity, shape, spacing
        The zones of the zone model: humidities (fractions), pixels and pixel size [m].
    model : {"auto", "modified_dmt", "fft_bem"}, default "auto"
        The contact model of the zones (``"auto"``: the cheaper one measured within 10 % on
        these zones, :func:`roughstick.reliability.failure_probability`).
    target_cv : float or None, default 0.3
        Stop when the estimate's coefficient of variation is at most this (None: one run);
        subset simulation stops only after at least 3 runs whose spread agrees with their cv;
        ``"strips"``: more accurate sub-zones where the cv is above it (None: ``n_accurate``).
    max_evaluations : int or None, default 20000
        Budget of model evaluations per estimate (per humidity and length).
    n_per_level : int, default 1000
        Samples per level of subset simulation (first batch of Monte Carlo). More when a run is
        flagged for few final lineages (``few_lineages``): its cv is then not to be trusted.
    **options
        Further keywords of the engine: :func:`roughstick.beam.simulate` (beam),
        :func:`failure_probability` (on a PSD: ``output``, ``adsorbed_layer``, ``scheduler`` ...)
        or :func:`subset_simulation` (on a bank).

    Returns
    -------
    xarray.Dataset
        On a sample or a PSD: ``stiction_probability`` with ``stiction_probability_lower`` /
        ``_upper``; on beams or a bank with ``"beam"``: ``stuck_probability`` with
        ``stuck_probability_lower`` / ``_upper``, ``n_stuck`` and ``n_solved``; by subset
        simulation on a bank: ``stiction_probability`` ... and ``bank_stiction_probability``
        (the closed form on the bank). Subset and Monte Carlo add ``coefficient_of_variation``,
        ``n_evaluations`` and ``converged``. :func:`roughstick.stiction.crossing_humidity` reads
        all of them.

    Notes
    -----
    The proxy of paper §5: a beam of length :math:`l` stays stuck when the interaction zone's
    adhesive energy exceeds :math:`\Gamma_{crit}(l) = \tfrac32 E h^2 t^3 / l^4` (Eq. 36 at
    :math:`s = l`). The beam-scale model releases the beam on patches of random laws and stops
    the crack front at the first patch able to hold it (docs/beam.md). Subset simulation runs in
    the white-noise space of the surfaces or of the patch draws (docs/rare_events.md).

    Examples
    --------
    >>> g = xr.DataArray([1e-4, 5e-4, 2e-3, 8e-3], dims="realization", attrs={"units": "J m-2"})
    >>> p = rs.reliability.stuck_probability(g, beam_length=[200e-6, 400e-6, 800e-6])
    >>> p.stiction_probability.values
    array([0. , 0.5, 1. ])
    """
    kind = _kind(data)
    passed = dict(beam_length=beam_length, dim=dim, interval=interval, n=n, seed=seed,
                  protocol=protocol, beam_model=beam_model, patch_length=patch_length,
                  relative_humidity=relative_humidity, shape=shape, spacing=spacing, model=model,
                  target_cv=target_cv, max_evaluations=max_evaluations, n_per_level=n_per_level)
    defaults = inspect.signature(stuck_probability).parameters  # follows the decorators
    given = {k for k, v in passed.items() if not _same(v, defaults[k].default)}
    _check_combination(method, kind, given, options, data)
    if method == "count":
        if kind == "beams":
            return stuck_probability_from_beams(data, confidence=confidence, interval=interval)
        return stuck_probability_from_sample(data, beam_length=beam_length, beam=beam, dim=dim,
                                             confidence=confidence, interval=interval)
    if method == "front":
        ccdf = adhesive_energy_ccdf(data, dim="law" if kind == "bank" else dim, confidence=confidence)
        return stuck_probability_from_ccdf(ccdf, beam_length=beam_length, beam=beam, patch_length=patch_length)
    if method == "strips":
        return _strips_stuck_probability(data, relative_humidity=relative_humidity, beam_length=beam_length,
                                         beam=beam, spacing=5e-9 if spacing is None else spacing, model=model,
                                         n=n if "n" in given else 12_000, seed=seed, confidence=confidence,
                                         target_cv=target_cv, **options)
    if method == "beam":
        beams = simulate(data, beam_length=beam_length, n=n, seed=seed, protocol=protocol, beam=beam,
                         patch_length=patch_length, beam_model=beam_model, **options)
        return stuck_probability_from_beams(beams, confidence=confidence, interval=interval)
    if options.get("accurate_model") is not None and "target_cv" not in given:
        target_cv = None  # two fidelities: one corrected subset run (failure_probability's accurate_model)
    common = dict(method=method, beam_length=beam_length, beam=beam, target_cv=target_cv,
                  max_evaluations=max_evaluations, n_per_level=n_per_level, seed=seed,
                  confidence=confidence)
    if kind == "bank":
        return _bank_stuck_probability(data, protocol=protocol, patch_length=patch_length, **common,
                                       **options)
    _warn_if_smaller_than_the_zone(shape, spacing, beam)
    return _zone_stuck_probability(data, relative_humidity=relative_humidity, shape=shape,
                                   spacing=spacing, model=model, **common, **options)


def _strips_stuck_probability(psd, *, model, **kw):
    """method='strips': model "auto" is Eq. 16 corrected by fft_bem; a named model alone unless
    ``accurate_model=`` names a second one."""
    if model == "auto":
        model, kw["accurate_model"] = "modified_dmt", kw.get("accurate_model", "fft_bem")
    else:
        kw.setdefault("accurate_model", None)
    return strip_stuck_probability(psd, model=model, **kw)


def _warn_if_smaller_than_the_zone(shape, spacing, beam) -> None:
    """Zones smaller than the beam's Δs × w carry a larger Γ: say so, with what it costs."""
    ny, nx = (int(v) for v in np.broadcast_to(shape, 2))
    zone = (beam.interaction_zone_length, beam.width)
    if ny * spacing >= 0.99 * zone[0] and nx * spacing >= 0.99 * zone[1]:
        return
    warnings.warn(
        f"zones of {ny} x {nx} px ({ny * spacing * 1e6:.3g} x {nx * spacing * 1e6:.3g} µm) are smaller than "
        f"the beam's interaction zone Δs × w ({zone[0] * 1e6:.3g} x {zone[1] * 1e6:.3g} µm): a smaller zone rests "
        "on lower summits and carries a larger Γ (Table-4 surfaces, Eq. 16: 0.64 µm squares 130-170 x the "
        "strip's median at 30-50 % RH; docs/zone_size.md), so this P(stuck) is that of the smaller zone "
        "and overstates the beam's. The whole zone is shape="
        f"{(round(zone[0] / spacing), round(zone[1] / spacing))}; or compose it from sub-zones "
        "(rs.stiction.strip_adhesive_energy, method='front').", UserWarning, stacklevel=external_stacklevel())


def _same(value, default) -> bool:
    """Whether an argument is its default (None, strings and numbers; an array never is)."""
    if value is default:
        return True
    try:
        return bool(value == default)
    except (TypeError, ValueError):
        return False
