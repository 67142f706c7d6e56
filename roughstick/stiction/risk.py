r"""The risk of stiction read off a sample of Γ: P(stuck), crossing humidity and length (§5).

Given a Monte-Carlo sample of :math:`\Gamma` (one value per generated interaction-zone surface,
from :func:`roughstick.contact.summary`), the stiction probability of a beam of length
:math:`l` is the fraction of the sample above :math:`\Gamma_{crit}(l)` (Eq. 36 at
:math:`s = l`, :mod:`.cantilever`); equivalently it is the empirical CDF of the predicted crack
length at :math:`l`. Its uncertainty is a binomial interval and the interval of a crossing length
an order-statistic one. The front door is :func:`roughstick.reliability.stuck_probability`
(``method="count"``; small probabilities by subset simulation with ``method="subset"``, whose
output :func:`crossing_humidity` reads the same way).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.conventions import append_history, dataset_attrs, set_attrs
from .._core.intervals import interval_method, order_statistic_ranks
from .._core.units import as_si, require
from .._core.validate import as_relative_humidity, check_core_not_chunked, check_positive_block
from ..ensemble.statistics import binomial_interval
from .cantilever import (
    _MAGNITUDES,
    PAPER_CANTILEVER,
    REFERENCES,
    Cantilever,
    _beam_lengths,
    _nonnegative,
    adhesive_energy_from_crack_length,
    crack_length_from_adhesive_energy,
    critical_adhesive_energy,
)

__all__ = [
    "crossing_humidity",
    "crossing_length",
    "measured_adhesion",
    "risk_summary",
]


#: What a count over a multi-fidelity ensemble would count, and what to do instead.
_CHEAP_SAMPLE = (
    "this is a multi-fidelity ensemble: its adhesive_energy is the cheap model's on every surface "
    "(the accurate model's is adhesive_energy_accurate, on a subset), so counting it would give the "
    "cheap model's P(stuck). Run the sample with one model on every surface "
    "(rs.stiction.predict_adhesive_energy, or rs.ensemble.run(..., accurate_model=False)), or read the "
    "accurate model's Γ band with rs.ensemble.confidence_band.")


def _gamma_sample(adhesive_energy, dim):
    if (isinstance(adhesive_energy, xr.Dataset) and "adhesive_energy_accurate" in adhesive_energy) or (
            isinstance(adhesive_energy, xr.DataArray) and "multifidelity" in adhesive_energy.attrs):
        raise ValueError(f"adhesive_energy: {_CHEAP_SAMPLE}")
    g = _nonnegative(adhesive_energy, "energy_per_area", "adhesive_energy")
    if not isinstance(g, xr.DataArray):
        raise TypeError(
            "adhesive_energy must be an xarray.DataArray (or a Dataset holding one) with a "
            f"{dim!r} dimension and units 'J m-2'; got {type(adhesive_energy).__name__}. "
            f"Wrap a plain sample as xr.DataArray(values, dims={dim!r}, attrs={{'units': 'J m-2'}})."
        )
    if dim not in g.dims:
        raise ValueError(
            f"adhesive_energy has no {dim!r} dimension (dims {g.dims}); the stiction probability is "
            f"a fraction over the Monte-Carlo sample. Pass dim= the sample dimension."
        )
    return g


@check_numbers(confidence="fraction")
def stuck_probability_from_sample(
    adhesive_energy,
    *,
    beam_length=None,
    beam: Cantilever = PAPER_CANTILEVER,
    dim: str = "realization",
    confidence: float = 0.95,
    interval: str = "wilson",
) -> xr.Dataset:
    r"""Probability that a cantilever stays stuck, :math:`P(\Gamma > \Gamma_{crit}(l))`, counted
    on a Monte-Carlo sample of Γ, with its confidence interval.

    What ``roughstick.stuck_probability(adhesive_energy, method="count")`` returns.

    Parameters
    ----------
    adhesive_energy : xarray.DataArray or xarray.Dataset
        Monte-Carlo sample of the interaction-zone adhesive energy :math:`\Gamma` [J m-2] along
        ``dim`` (e.g. ``rs.contact.summary(curves)``, dims ``(realization, rh)``). NaN members
        are left out of both counts (``n_samples`` records how many were used).
    beam_length : float, sequence or xarray.DataArray, optional
        Beam length(s) [m]; default ``beam.length``. A sequence adds a ``beam_length`` dimension.
    beam : Cantilever
        Beam geometry and modulus.
    dim : str, default "realization"
        The sample dimension, reduced.
    confidence : float, default 0.95
        Level of the interval on the probability.
    interval : {"wilson", "clopper-pearson"}
        See :func:`binomial_interval`.

    Returns
    -------
    xarray.Dataset
        ``stiction_probability`` :math:`k/n`, ``stiction_probability_lower`` and ``_upper``
        (the interval), ``n_stuck`` (:math:`k`), ``n_samples`` (:math:`n`) and
        ``critical_adhesive_energy``, over the remaining dims of ``adhesive_energy`` and
        ``beam_length``. Lazy inputs give lazy outputs.

    Notes
    -----
    The beam stays stuck when its crack length, Eq. 36 inverted, is shorter than the beam:

    .. math:: s(\Gamma) < l \iff \Gamma > \Gamma_{crit}(l) = \frac{3}{2}E\frac{h^2 t^3}{l^4},

    so :math:`P(\text{stuck})` is the CDF of the predicted crack length at :math:`l` and never
    decreases with :math:`l`. The interaction zone is treated as one independent sample of the
    surface statistics (the paper's pull-out analogy): the beam's multiscale mechanics, several
    independent zones along the landing length and the history of contact are not modelled.

    Examples
    --------
    >>> from roughstick.stiction.risk import stuck_probability_from_sample
    >>> g = xr.DataArray([1e-4, 5e-4, 2e-3, 8e-3], dims="realization", attrs={"units": "J m-2"})
    >>> p = stuck_probability_from_sample(g, beam_length=[200e-6, 400e-6, 800e-6])
    >>> p.stiction_probability.values
    array([0. , 0.5, 1. ])
    """
    interval = interval_method(interval, confidence=confidence)
    g = _gamma_sample(adhesive_energy, dim)
    gcrit = critical_adhesive_energy(beam_length=beam_length, beam=beam)
    valid = g.notnull()
    n_stuck = (g > gcrit).sum(dim)
    n = valid.sum(dim)
    if isinstance(gcrit, xr.DataArray):
        n = n.broadcast_like(n_stuck)
    lo, hi = binomial_interval(n_stuck, n, confidence=confidence, method=interval)
    p = n_stuck / n.where(n > 0)
    ds = xr.Dataset(
        {
            "stiction_probability": set_attrs(p, "stiction_probability"),
            "stiction_probability_lower": set_attrs(
                lo, "stiction_probability",
                long_name=f"lower bound of the {confidence:.0%} {interval} interval on the stiction probability",
            ),
            "stiction_probability_upper": set_attrs(
                hi, "stiction_probability",
                long_name=f"upper bound of the {confidence:.0%} {interval} interval on the stiction probability",
            ),
            "n_stuck": set_attrs(n_stuck, "n_stuck"),
            "n_samples": set_attrs(n, "n_samples"),
        }
    )
    lengths = _beam_lengths(beam_length, beam)
    if isinstance(gcrit, xr.DataArray):
        ds["critical_adhesive_energy"] = gcrit
        if "beam_length" in ds.coords:
            ds["beam_length"].attrs = dict(gcrit["beam_length"].attrs)
    else:
        ds["critical_adhesive_energy"] = set_attrs(xr.DataArray(gcrit), "critical_adhesive_energy")
    for c in ds.coords:
        if c == "rh":
            ds["rh"].attrs = set_attrs(ds["rh"], "rh").attrs
    ds.attrs.update(
        dataset_attrs(
            "Probability that a cantilever stays stuck (Eq. 36, Monte Carlo)",
            references=REFERENCES,
            confidence_level=float(confidence),
            interval_method=interval,
            sample_dimension=dim,
            **beam.attrs(),
        )
    )
    if not isinstance(lengths, xr.DataArray):
        ds.attrs["beam_length"] = float(lengths)
    append_history(ds, f"roughstick.stuck_probability(method='count', dim={dim!r}, confidence={confidence}, "
                       f"interval={interval!r})")
    return ds


def _first_crossing_kernel(p, coord, level, late=False):
    """First upward crossing of ``level`` along the last axis, interpolated in logit(p).

    Linear in logit(p) = log(p / (1 - p)) between grid points with 0 < p < 1 (log-linear for small
    p: 1e-4 at one RH and 0.1 at the next cross 1e-3 a third of the way, not at 0.1 %), linear in
    p where a neighbour is 0 or 1 (counted probabilities), or, with ``late``, at the grid point
    where the level is reached (the latest the crossing can be: the rule for the upper end of an
    interval, from a lower probability bound of 0). -inf: already >= level at the first grid
    point; +inf: never reaches it; NaN: NaN data.
    """
    p = np.asarray(p, dtype=float)
    out = np.full(p.shape[:-1], np.inf)
    flat = p.reshape(-1, p.shape[-1])
    res = out.reshape(-1)
    for i, row in enumerate(flat):
        if np.all(np.isnan(row)):
            res[i] = np.nan
            continue
        ok = ~np.isnan(row)
        r, c = row[ok], coord[ok]
        above = r >= level
        if above[0]:
            res[i] = -np.inf
            continue
        j = np.argmax(above)
        if not above[j]:
            continue
        p0, p1 = r[j - 1], r[j]
        if 0.0 < p0 and p1 < 1.0:
            def logit(x):
                return math.log(x / (1.0 - x))
            t = (logit(level) - logit(p0)) / (logit(p1) - logit(p0))
        else:
            t = 1.0 if late else (level - p0) / (p1 - p0)
        res[i] = c[j - 1] + t * (c[j] - c[j - 1])
    return out


#: The P(stuck) variables a crossing humidity is read from: the sample and zone estimates
#: (``stiction_probability``) and the simulated beams (``stuck_probability``).
_PROBABILITY_VARIABLES = ("stiction_probability", "stuck_probability")


@renamed_keywords(level="probability")
@check_numbers(probability="fraction")
def crossing_humidity(result: xr.Dataset | xr.DataArray, *, probability: float = 0.5) -> xr.Dataset:
    r"""Relative humidity at which the stiction probability first reaches ``probability``.

    Parameters
    ----------
    result : xarray.Dataset or xarray.DataArray
        Output of :func:`roughstick.reliability.stuck_probability` (any method, with an ``rh``
        dimension), or a DataArray of probabilities over ``rh``. With the Dataset, the interval
        bounds give the interval of the crossing.
    probability : float
        Probability level in (0, 1), e.g. 0.01 for "1 % of beams stuck".

    Returns
    -------
    xarray.Dataset
        ``crossing_humidity`` (from the estimate) and, for a Dataset input,
        ``crossing_humidity_lower`` (where the upper bound of the probability crosses) and
        ``crossing_humidity_upper`` (where the lower bound crosses), over the remaining dims
        (e.g. ``beam_length``); where the result carries a model band
        (``stiction_probability_model_lower``/``_upper``), ``crossing_humidity_model_lower``
        and ``_model_upper`` from its bounds. Interpolation between grid humidities linear in logit(p) (in p
        next to a 0 or a 1; the upper end next to a 0 of the lower bound: the grid point where that
        bound reaches the level, and the estimate is kept inside its interval), so that small
        probabilities cross where a log plot shows; ``-inf`` means the
        level is already reached at the lowest RH of the grid, ``+inf`` that it is not reached at
        the highest.

    Raises
    ------
    ValueError
        If there is no ``rh`` dimension, it is not increasing, or it is split over dask chunks.

    Notes
    -----
    The probability need not be monotone in RH (the adhesive energy can saturate or drop when the
    menisci merge); this is the *first* upward crossing, the humidity a design must stay below.

    Examples
    --------
    >>> p = xr.DataArray([0.0, 0.2, 0.6, 1.0], dims="rh", coords={"rh": [0.3, 0.4, 0.5, 0.6]})
    >>> round(float(rs.stiction.crossing_humidity(p, probability=0.5).crossing_humidity), 4)
    0.4774
    """
    level = probability
    if not 0 < level < 1:
        raise ValueError(f"probability must be strictly between 0 and 1, got {level!r}.")
    if isinstance(result, xr.Dataset):
        name = next((v for v in _PROBABILITY_VARIABLES if v in result), None)
        if name is None:
            raise ValueError(f"the Dataset holds no P(stuck) ({' or '.join(_PROBABILITY_VARIABLES)}; "
                             f"it has {sorted(result.data_vars)}): pass the output of "
                             "roughstick.stuck_probability.")
        pairs = {
            "crossing_humidity": result[name],
            "crossing_humidity_lower": result[f"{name}_upper"],
            "crossing_humidity_upper": result[f"{name}_lower"],
        }
        if f"{name}_model_upper" in result and f"{name}_model_lower" in result:
            pairs.update(crossing_humidity_model_lower=result[f"{name}_model_upper"],
                         crossing_humidity_model_upper=result[f"{name}_model_lower"])
    else:
        pairs = {"crossing_humidity": result}
    out = {}
    for name, p in pairs.items():
        if "rh" not in p.dims:
            raise ValueError(f"the stiction probability has no 'rh' dimension (dims {p.dims}); compute it on an RH sweep.")
        rh = np.asarray(p["rh"].values, dtype=float)
        if rh.size > 1 and np.any(np.diff(rh) <= 0):
            raise ValueError("the 'rh' coordinate must be strictly increasing; sort first: .sortby('rh').")
        check_core_not_chunked(p, ["rh"])
        da = xr.apply_ufunc(
            _first_crossing_kernel,
            p,
            kwargs={"coord": rh, "level": float(level), "late": name.endswith("_upper")},
            input_core_dims=[["rh"]],
            dask="parallelized",
            output_dtypes=[float],
        )
        out[name] = set_attrs(da, "crossing_humidity")
    if "crossing_humidity_upper" in out:
        # next to a 0 the estimate is interpolated linearly in p, the bounds in logit(p): keep it
        # inside its interval (a 0 of subset simulation, below its resolution, crossed 1e-3 early)
        attrs = out["crossing_humidity"].attrs
        out["crossing_humidity"] = out["crossing_humidity"].clip(
            out["crossing_humidity_lower"], out["crossing_humidity_upper"]).assign_attrs(attrs)
        out["crossing_humidity_lower"].attrs["long_name"] += " (from the upper probability bound)"
        out["crossing_humidity_upper"].attrs["long_name"] += " (from the lower probability bound)"
    if "crossing_humidity_model_lower" in out:
        out["crossing_humidity_model_lower"].attrs["long_name"] += " (upper probability bound with the model band)"
        out["crossing_humidity_model_upper"].attrs["long_name"] += " (lower probability bound with the model band)"
    ds = xr.Dataset(out)
    ds.attrs = dict(result.attrs) if isinstance(result, xr.Dataset) else {}
    ds.attrs["probability_level"] = float(level)
    append_history(ds, f"roughstick.stiction.crossing_humidity(probability={level})")
    return ds


def _crossing_length_kernel(s, p, confidence):
    s = np.asarray(s, dtype=float)
    out = np.full(s.shape[:-1] + (3,), np.nan)
    flat = s.reshape(-1, s.shape[-1])
    res = out.reshape(-1, 3)
    for i, row in enumerate(flat):
        row = np.sort(row[~np.isnan(row)])
        n = row.size
        if n == 0:
            continue
        k = max(int(math.ceil(n * p - 1e-12)), 1)
        res[i, 0] = row[k - 1]
        r, u = order_statistic_ranks(n, p, confidence=confidence)
        res[i, 1] = row[r - 1] if r >= 1 else 0.0
        res[i, 2] = row[u - 1] if u <= n else np.inf
    return out


@renamed_keywords(level="probability")
@check_numbers(probability="fraction", confidence="fraction")
def crossing_length(
    adhesive_energy,
    *,
    probability: float = 0.5,
    beam: Cantilever = PAPER_CANTILEVER,
    dim: str = "realization",
    confidence: float = 0.95,
) -> xr.Dataset:
    r"""Beam length above which the stiction probability reaches ``probability``.

    Because :math:`P(\text{stuck} \mid l) = P(s < l)`, this is the ``probability``-quantile of
    the predicted crack length :math:`s` (Eq. 36 applied to the sample of Γ).

    Parameters
    ----------
    adhesive_energy : xarray.DataArray or xarray.Dataset
        Monte-Carlo sample of Γ [J m-2] along ``dim``; NaN members are left out.
    probability : float
        Probability level in (0, 1).
    beam : Cantilever
        Beam thickness, gap and modulus.
    dim : str, default "realization"
        Sample dimension, reduced (rechunked to a single chunk if lazy).
    confidence : float
        Level of the distribution-free interval on the crossing length.

    Returns
    -------
    xarray.Dataset
        ``crossing_length`` :math:`l_p = s_{(\lceil np \rceil)}`, the shortest length whose
        empirical stiction probability, for any longer beam, is at least ``probability``;
        ``crossing_length_lower`` / ``_upper``: the order statistics
        :math:`[s_{(r)}, s_{(u)}]` bracketing the true quantile with probability >= ``confidence``
        (binomial ranks; 0 or ``inf`` when the sample is too small to bound that side).

    Examples
    --------
    >>> g = xr.DataArray([1e-4, 5e-4, 2e-3, 8e-3], dims="realization", attrs={"units": "J m-2"})
    >>> round(float(rs.stiction.crossing_length(g, probability=0.5).crossing_length) * 1e6, 1)  # µm
    298.9
    """
    level = probability
    if not 0 < level < 1:
        raise ValueError(f"probability must be strictly between 0 and 1, got {level!r}.")
    interval_method("wilson", confidence=confidence)
    g = _gamma_sample(adhesive_energy, dim)
    s = crack_length_from_adhesive_energy(g, beam=beam)
    if s.chunks is not None:
        s = s.chunk({dim: -1})
    res = xr.apply_ufunc(
        _crossing_length_kernel,
        s,
        kwargs={"p": float(level), "confidence": float(confidence)},
        input_core_dims=[[dim]],
        output_core_dims=[["bound"]],
        dask="parallelized",
        output_dtypes=[float],
        dask_gufunc_kwargs={"output_sizes": {"bound": 3}},
    )
    ds = xr.Dataset(
        {
            "crossing_length": set_attrs(res.isel(bound=0, drop=True), "crossing_length"),
            "crossing_length_lower": set_attrs(
                res.isel(bound=1, drop=True), "crossing_length",
                long_name=f"lower end of the {confidence:.0%} interval on the crossing length",
            ),
            "crossing_length_upper": set_attrs(
                res.isel(bound=2, drop=True), "crossing_length",
                long_name=f"upper end of the {confidence:.0%} interval on the crossing length",
            ),
        }
    )
    ds.attrs.update(
        dataset_attrs(
            "Beam length at which the stiction probability reaches a level (Eq. 36)",
            references=REFERENCES,
            probability_level=float(level),
            confidence_level=float(confidence),
            **beam.attrs(),
        )
    )
    append_history(ds, f"roughstick.stiction.crossing_length(probability={level}, dim={dim!r})")
    return ds


def measured_adhesion(
    relative_humidity,
    *,
    crack_length=None,
    adhesive_energy=None,
    beam: Cantilever = PAPER_CANTILEVER,
    label: str = "measured",
) -> xr.Dataset:
    r"""Measured cantilever results as (RH, s, Γ) points, the missing one from Eq. 36.

    The experimental points of the paper's Fig. 20 (de Boer et al.) are not printed in its
    text, so none are bundled: pass your own.

    Parameters
    ----------
    relative_humidity : sequence or xarray.DataArray
        RH of each measurement, fractions in (0, 1) (a DataArray may carry ``units="%"``).
    crack_length : sequence or xarray.DataArray, optional
        Measured crack lengths :math:`s` [m] (DataArray units µm etc. are converted).
    adhesive_energy : sequence or xarray.DataArray, optional
        Measured :math:`\Gamma` [J m-2]. Give exactly one of the two.
    beam : Cantilever
        Geometry used to convert between them (Eq. 36).
    label : str
        Stored in the ``label`` attribute (legend text of the plots).

    Returns
    -------
    xarray.Dataset
        Dimension ``point``; variables ``rh``, ``crack_length`` [m] and ``adhesive_energy``
        [J m-2]; attr ``given`` says which one was measured.

    Examples
    --------
    >>> m = rs.stiction.measured_adhesion([0.5, 0.7], crack_length=[400e-6, 350e-6])
    >>> (m.adhesive_energy.values * 1e3).round(3)  # mJ m-2
    array([0.624, 1.064])
    """
    if (crack_length is None) == (adhesive_energy is None):
        raise ValueError("give exactly one of crack_length= (m) or adhesive_energy= (J m-2) for the measured points.")

    def _points(v, kind, name):
        if isinstance(v, xr.DataArray):
            v = require(v, kind, name=name)
            if v.ndim != 1:
                raise ValueError(f"{name} must be 1-D (one value per measurement), got dims {v.dims}.")
            return np.asarray(v.values, dtype=float)
        return np.atleast_1d(np.asarray(as_si(v, kind, name=name), dtype=float))

    if isinstance(relative_humidity, xr.DataArray):
        rh = np.atleast_1d(np.asarray(as_relative_humidity(relative_humidity).values, dtype=float))
    else:
        rh = np.atleast_1d(np.asarray(relative_humidity, dtype=float))
        as_relative_humidity(rh)
    if crack_length is not None:
        s = _points(crack_length, "length", "crack_length")
        check_positive_block(s, "crack_length", _MAGNITUDES, allow_zero=True)
        g = adhesive_energy_from_crack_length(s, beam=beam)
        given = "crack_length"
    else:
        g = _points(adhesive_energy, "energy_per_area", "adhesive_energy")
        check_positive_block(g, "adhesive_energy", _MAGNITUDES, allow_zero=True)
        s = crack_length_from_adhesive_energy(g, beam=beam)
        given = "adhesive_energy"
    if not (rh.shape == s.shape == g.shape) or rh.ndim != 1:
        raise ValueError(
            f"relative_humidity ({rh.size} values) and the measured {given} ({np.size(s)} values) "
            "must be 1-D and of equal length: one pair per measurement."
        )
    ds = xr.Dataset(
        {
            "rh": set_attrs(xr.DataArray(rh, dims="point"), "rh"),
            "crack_length": set_attrs(xr.DataArray(s, dims="point"), "crack_length"),
            "adhesive_energy": set_attrs(xr.DataArray(g, dims="point"), "surface_adhesive_energy"),
        }
    )
    ds.attrs.update(dataset_attrs("Measured cantilever adhesion (Eq. 36)", references=REFERENCES,
                                  given=given, label=label, **beam.attrs()))
    append_history(ds, f"roughstick.stiction.measured_adhesion: {rh.size} points, {given} given")
    return ds


@renamed_keywords(length="beam_length", levels="probabilities")
@check_numbers(confidence="fraction")
def risk_summary(
    adhesive_energy,
    *,
    beam_length=None,
    beam: Cantilever = PAPER_CANTILEVER,
    probabilities=(0.05, 0.5, 0.95),
    dim: str = "realization",
    confidence: float = 0.95,
    interval: str = "wilson",
    quantiles=(0.025, 0.5, 0.975),
) -> xr.Dataset:
    r"""What a designer reads off a Monte-Carlo sample of Γ: stiction probability, crossings, bands.

    Parameters
    ----------
    adhesive_energy : xarray.DataArray or xarray.Dataset
        Sample of :math:`\Gamma` [J m-2] along ``dim`` (typically dims ``(realization, rh)``).
    beam_length : float, sequence or xarray.DataArray, optional
        Beam lengths [m] (``beam_length`` dimension); default ``beam.length``.
    beam : Cantilever
        Beam geometry and modulus.
    probabilities : sequence of float
        Probability levels for the crossing humidity and length (``probability_level`` dim).
    dim, confidence, interval
        See :func:`roughstick.reliability.stuck_probability` (``method="count"``).
    quantiles : sequence of float
        Quantiles of Γ and of the crack length to report (default: the 95 % band and median).

    Returns
    -------
    xarray.Dataset
        The variables of ``stuck_probability(adhesive_energy, method="count")``;
        ``crossing_humidity`` (+ ``_lower``, ``_upper``) over ``(probability_level,
        beam_length)`` when there is an ``rh`` dim; ``crossing_length`` (+ bounds) over
        ``(probability_level, ...)``; ``adhesive_energy_quantile`` and
        ``crack_length_quantile`` over ``(quantile, ...)``; ``adhesive_energy_mean``.

    Examples
    --------
    >>> g = xr.DataArray([[1e-4, 2e-4], [5e-4, 1e-3], [2e-3, 4e-3]], dims=("realization", "rh"),
    ...                  coords={"rh": [0.4, 0.8]}, attrs={"units": "J m-2"})
    >>> r = rs.stiction.risk_summary(g, beam_length=[300e-6, 600e-6], probabilities=[0.5])
    >>> r.stiction_probability.transpose("beam_length", "rh").values.round(3)
    array([[0.333, 0.333],
           [0.667, 1.   ]])
    """
    levels = [float(v) for v in np.atleast_1d(probabilities)]
    for v in levels:
        if not 0 < v < 1:
            raise ValueError(f"probabilities must be strictly between 0 and 1, got {v!r}.")
    g = _gamma_sample(adhesive_energy, dim)
    ds = stuck_probability_from_sample(g, beam_length=beam_length, beam=beam, dim=dim,
                                       confidence=confidence, interval=interval)
    lev = xr.DataArray(levels, dims="probability_level", coords={"probability_level": levels})
    lev = set_attrs(lev, "probability_level")
    parts = [crossing_length(g, probability=v, beam=beam, dim=dim, confidence=confidence) for v in levels]
    cl = xr.concat([p[list(p.data_vars)] for p in parts], dim=lev)
    for k in cl.data_vars:
        ds[k] = cl[k]
    if "rh" in ds.dims:
        parts = [crossing_humidity(ds, probability=v) for v in levels]
        ch = xr.concat([p[list(p.data_vars)] for p in parts], dim=lev)
        for k in ch.data_vars:
            ds[k] = ch[k]
    ds["probability_level"].attrs = dict(lev.attrs)
    gq = g.chunk({dim: -1}) if g.chunks is not None else g
    qs = [float(q) for q in np.atleast_1d(quantiles)]
    ds["adhesive_energy_quantile"] = set_attrs(
        gq.quantile(qs, dim=dim, skipna=True), "surface_adhesive_energy",
        long_name="quantile of the apparent adhesive energy over the Monte-Carlo sample",
    )
    s = crack_length_from_adhesive_energy(gq, beam=beam)
    ds["crack_length_quantile"] = set_attrs(
        s.quantile(qs, dim=dim, skipna=True), "crack_length",
        long_name="quantile of the predicted crack length over the Monte-Carlo sample",
    )
    ds["adhesive_energy_mean"] = set_attrs(
        g.mean(dim, skipna=True), "surface_adhesive_energy",
        long_name="mean apparent adhesive energy over the Monte-Carlo sample",
    )
    ds["quantile"].attrs = {"units": "1", "long_name": "quantile"}
    append_history(ds, f"roughstick.stiction.risk_summary(probabilities={levels}, quantiles={qs})")
    return ds
