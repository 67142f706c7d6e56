r"""Reductions of a Monte Carlo sample with their own uncertainty (Figs. 14-17, §5).

:func:`confidence_band` (mean and a quantile band over realizations, with each quantile's
sampling interval from :func:`quantile_interval`) and :func:`binomial_interval` (the uncertainty
of a probability estimated as a fraction of the sample, e.g. the stiction probability). The
distribution-free interval of a quantile has one implementation,
:func:`roughstick._core.intervals.order_statistic_ranks`.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import xarray as xr
from scipy import special, stats

from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.conventions import ATTRS, append_history, coord_attrs
from .._core.dask import as_seed_sequence
from .._core.intervals import interval_method, order_statistic_ranks
from .._core.validate import as_fraction
from .multifidelity import multifidelity_band

__all__ = [
    "confidence_band",
    "quantile_interval",
    "min_samples_to_bound",
    "band_summary",
    "binomial_interval",
]


def _labelled(obj, func: str, *, dataset: bool = True) -> None:
    ok = (xr.DataArray, xr.Dataset) if dataset else (xr.DataArray,)
    if not isinstance(obj, ok):
        raise TypeError(
            f"{func} takes a labelled xarray {'Dataset or ' if dataset else ''}DataArray with a "
            f"'realization' dimension, not {type(obj).__name__}; wrap a plain array first, e.g. "
            "xr.DataArray(a, dims=('realization', 'rh'), coords={'rh': rh}, name='adhesive_energy', "
            "attrs={'units': 'J m-2', 'long_name': '...'}).")


def min_samples_to_bound(p: float, *, confidence: float) -> int:
    r"""Smallest n whose order statistics bound the ``p``-quantile on BOTH sides at ``confidence``.

    With the two tails split equally (:math:`a = (1 - c)/2`) the lower side needs
    :math:`(1-p)^n < a` and the upper side :math:`p^n \le a`. Below this n one edge of the
    interval of :func:`quantile_interval` is NaN ("n too small to bound this edge").

    Examples
    --------
    >>> rs.ensemble.min_samples_to_bound(0.025, confidence=0.95), rs.ensemble.min_samples_to_bound(0.5, confidence=0.95)
    (146, 6)
    """
    as_fraction(p, name="p", label="p", spell_percent=False)
    as_fraction(confidence, name="confidence", label="confidence", spell_percent=False)
    a = (1.0 - confidence) / 2.0
    n = max(1, int(np.floor(np.log(a) / np.log(max(p, 1 - p)))) - 1)
    while True:  # the closed form gives a start; the ranks of order_statistic_ranks decide
        r, s = order_statistic_ranks(n, p, confidence=confidence)
        if r >= 1 and s <= n:
            return n
        n += 1


def _order_statistic_kernel(a, probs, alpha):
    """Distribution-free interval [X_(r), X_(s)] for each quantile p (last axis = samples).

    Ranks from :func:`order_statistic_ranks`; r < 1 or s > n means the sample cannot bound that
    side of the quantile: NaN there (never -inf/+inf, which read as numbers in a file).
    """
    a = np.sort(np.asarray(a, dtype=float), axis=-1)  # NaN last
    nvalid = np.sum(~np.isnan(a), axis=-1)
    lo = np.full(a.shape[:-1] + (len(probs),), np.nan)
    hi = np.full_like(lo, np.nan)
    for nv in np.unique(nvalid):
        if nv == 0:
            continue
        mask = nvalid == nv
        sub = a[mask][..., :nv]
        for k, p in enumerate(probs):
            r, s = order_statistic_ranks(nv, p, confidence=1 - alpha)
            lo[mask, k] = sub[..., r - 1] if r >= 1 else np.nan
            hi[mask, k] = sub[..., s - 1] if s <= nv else np.nan
    return lo, hi


def _bootstrap_kernel(a, probs, alpha, n_boot, entropy):
    a = np.asarray(a, dtype=float)
    n = a.shape[-1]
    rng = np.random.default_rng(np.random.SeedSequence(entropy))
    reps = np.empty((n_boot,) + a.shape[:-1] + (len(probs),))
    for b in range(n_boot):
        idx = rng.integers(0, n, size=n)
        reps[b] = np.moveaxis(np.nanquantile(a[..., idx], probs, axis=-1), 0, -1)
    lo = np.nanquantile(reps, alpha / 2, axis=0)
    hi = np.nanquantile(reps, 1 - alpha / 2, axis=0)
    return lo, hi


@renamed_keywords(rng="seed")
@check_numbers(confidence="fraction", n_bootstrap="count", seed="seed")
def quantile_interval(
    da: xr.DataArray,
    quantiles,
    *,
    dim: str = "realization",
    confidence: float = 0.95,
    method: str = "order_statistic",
    n_bootstrap: int = 500,
    seed=0,
) -> tuple[xr.DataArray, xr.DataArray]:
    r"""Confidence interval of sample quantiles: how well ``n`` realizations pin a band down.

    ``method="order_statistic"`` (default) gives the distribution-free interval
    :math:`[X_{(r)}, X_{(s)}]` whose coverage :math:`F_B(s-1) - F_B(r-1) \ge` ``confidence`` with
    :math:`F_B` the Binomial(n, p) CDF (Conover, *Practical Nonparametric Statistics*, §3.2);
    NaN on a side that n samples cannot bound (below :func:`min_samples_to_bound`; the
    attribute ``comment`` says so). ``"bootstrap"`` gives the
    percentile bootstrap interval from ``n_bootstrap`` resamples drawn with ``seed`` (the same
    resamples for every element, so chunking does not change it).

    Parameters
    ----------
    da : xarray.DataArray
        Samples along ``dim`` (NaN ignored).
    quantiles : sequence of float
        Probabilities in [0, 1].
    dim : str
        Sample dimension, rechunked to one chunk.
    confidence : float
        Coverage of the interval.
    method : {"order_statistic", "bootstrap"}
    n_bootstrap : int
    seed : int or numpy.random.SeedSequence
        Seed of the bootstrap resamples.

    Returns
    -------
    lower, upper : xarray.DataArray
        Dims ``(quantile, ...)``.

    Examples
    --------
    >>> x = xr.DataArray(np.arange(100.0), dims="realization")
    >>> lo, hi = rs.ensemble.quantile_interval(x, [0.5])
    >>> float(lo[0]), float(hi[0])
    (39.0, 60.0)
    """
    _labelled(da, "quantile_interval", dataset=False)
    probs = np.atleast_1d(np.asarray(quantiles, dtype=float))
    if np.any((probs < 0) | (probs > 1)):
        raise ValueError(f"quantiles must lie in [0, 1], got {probs.tolist()}.")
    as_fraction(confidence, name="confidence", label="confidence", spell_percent=False)
    if dim not in da.dims:
        raise ValueError(f"{da.name!r} has no dimension {dim!r} (dims {da.dims}).")
    alpha = 1 - confidence
    if da.chunks is not None:
        da = da.chunk({dim: -1})
    if method == "order_statistic":
        func, kw = _order_statistic_kernel, {"probs": probs, "alpha": alpha}
    elif method == "bootstrap":
        func = _bootstrap_kernel
        kw = {"probs": probs, "alpha": alpha, "n_boot": int(n_bootstrap),
              "entropy": as_seed_sequence(seed).entropy}
    else:
        raise ValueError(f"method must be 'order_statistic' or 'bootstrap', got {method!r}.")
    lo, hi = xr.apply_ufunc(
        func, da, kwargs=kw,
        input_core_dims=[[dim]],
        output_core_dims=[["quantile"], ["quantile"]],
        dask="parallelized",
        output_dtypes=[float, float],
        dask_gufunc_kwargs={"output_sizes": {"quantile": probs.size}},
    )
    out = []
    for x, side in ((lo, "lower"), (hi, "upper")):
        x = x.assign_coords(quantile=probs).transpose("quantile", ...)
        x.attrs = {**{k: v for k, v in da.attrs.items() if k in ("units", "standard_name")},
                   "long_name": f"{side} {confidence:.0%} confidence limit of the quantile of "
                                f"{da.attrs.get('long_name', da.name)}",
                   "method": method}
        if method == "order_statistic":
            need = {float(p): min_samples_to_bound(float(p), confidence=confidence)
                    for p in probs if 0 < p < 1}
            x.attrs["comment"] = (
                "NaN: n too small to bound this edge (distribution-free order-statistic interval; "
                "both edges bounded from n >= "
                + ", ".join(f"{m} for quantile {p:g}" for p, m in need.items()) + ")")
        x["quantile"].attrs = dict(ATTRS["quantile"])
        out.append(x.rename(f"{da.name}_ci_{side}" if da.name else None))
    return out[0], out[1]


def _old_band_keywords(func):
    """``confidence_band``'s keywords before the glossary: ``level`` (the band's) is now
    ``confidence`` and, given with it, the old ``confidence`` (the quantiles' intervals) is
    ``ci_confidence``; ``rng`` is ``seed``. A DeprecationWarning says so."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        if "level" in kwargs:
            if "confidence" in kwargs:
                if "ci_confidence" in kwargs:
                    raise TypeError("confidence_band() got level=, confidence= and ci_confidence=; "
                                    "pass confidence= (the band) and ci_confidence= only")
                kwargs["ci_confidence"] = kwargs.pop("confidence")
            kwargs["confidence"] = kwargs.pop("level")
            warnings.warn("confidence_band(level=...) is now confidence_band(confidence=...) (and its "
                          "old confidence= is ci_confidence=); the old keywords will be removed",
                          DeprecationWarning, stacklevel=2)
        if "rng" in kwargs:
            if "seed" in kwargs:
                raise TypeError("confidence_band() got both rng= (the old name) and seed=; pass seed= only")
            kwargs["seed"] = kwargs.pop("rng")
            warnings.warn("confidence_band(rng=...) is now confidence_band(seed=...); the old keyword "
                          "will be removed", DeprecationWarning, stacklevel=2)
        return func(*args, **kwargs)

    wrapper.__renamed_keywords__ = {"level": "confidence", "rng": "seed"}
    return wrapper


@_old_band_keywords
@check_numbers(confidence="fraction", ci_confidence="fraction", n_bootstrap="count", seed="seed")
def confidence_band(
    ds,
    dim: str = "realization",
    confidence: float = 0.95,
    *,
    uncertainty: str | None = "order_statistic",
    ci_confidence: float = 0.95,
    n_bootstrap: int = 500,
    seed=0,
):
    r"""Mean and ``confidence`` band over realizations, with the band's sampling uncertainty
    (Figs. 14-16).

    For every data variable with ``dim``: the quantiles :math:`(1-c)/2`, 0.5 and :math:`(1+c)/2`
    along ``dim`` (variable ``v``, new leading dim ``quantile``), the mean (``v_mean``) and its
    standard error (``v_mean_stderr``), and unless ``uncertainty=None`` a ``ci_confidence``
    interval of each quantile (``v_ci_lower``, ``v_ci_upper``, see :func:`quantile_interval`): if
    that interval is narrow compared with the band, n was enough.
    ``dim`` is rechunked to a single chunk first, so the result does not depend on the chunking;
    lazy inputs stay lazy.

    NaN members (e.g. a realization without an equilibrium) are skipped point by point, so the
    number of members actually used can vary: ``v_n_samples`` holds it at every point of ``v``
    (over the dims of ``v`` without ``dim``).

    Parameters
    ----------
    ds : xarray.Dataset or xarray.DataArray
        Ensemble, e.g. from :func:`run`.
    dim : str, default "realization"
    confidence : float, default 0.95
        Central probability of the band.
    uncertainty : {"order_statistic", "bootstrap", None}
        How to compute the quantiles' sampling intervals.
    ci_confidence : float, default 0.95
        Coverage of those intervals.
    n_bootstrap, seed
        For ``uncertainty="bootstrap"``.

    Returns
    -------
    xarray.Dataset
        Per variable ``v``: ``v``, ``v_mean``, ``v_mean_stderr``, ``v_n_samples`` (valid members
        used at each point) and ``v_ci_lower``/``v_ci_upper``. Attrs ``level`` (the band's
        ``confidence``), ``confidence`` (``ci_confidence``), ``n_members`` (the size of ``dim``) and, for an in-memory input, ``n_samples``: the
        fewest valid (non-NaN) members used at any point of any variable, which is ``n_members``
        when no member is NaN. A lazy input would have to be computed to know it, so its band has
        no ``n_samples`` attr (read ``v_n_samples``). ``band_edges_bounded`` compares
        ``n_samples`` (lazy input: ``n_members``) with ``n_samples_to_bound_band_edges``; an edge
        that its own point's members cannot bound is NaN in ``v_ci_lower``/``v_ci_upper``.

    Examples
    --------
    >>> x = xr.DataArray(np.arange(1000.0), dims="realization", name="g",
    ...                  attrs={"units": "J m-2", "long_name": "energy"})
    >>> b = rs.ensemble.confidence_band(x)
    >>> b["g"].values, float(b["g_mean"])
    (array([ 24.975, 499.5  , 974.025]), 499.5)
    """
    as_fraction(confidence, name="confidence", label="confidence", spell_percent=False)
    _labelled(ds, "confidence_band")
    if isinstance(ds, xr.DataArray):
        name = ds.name or "data"
        ds = ds.to_dataset(name=name)
    if dim not in ds.dims:
        raise ValueError(f"the input has no dimension {dim!r} (dims {tuple(ds.dims)}).")
    n = ds.sizes[dim]
    if n < 1:
        raise ValueError(f"dimension {dim!r} is empty: no realizations to reduce.")
    probs = np.round([(1 - confidence) / 2, 0.5, (1 + confidence) / 2], 12)  # exact labels for .sel
    out = {}
    lazy = False
    paired = _accurate_pairs(ds, dim)
    for v, da in ds.data_vars.items():
        if dim not in da.dims or da.dtype.kind not in "fiub" or v in paired.values():
            continue
        if v in paired:  # multi-fidelity: the accurate model's band from both models
            out.update(_multifidelity_entries(v, da, ds[paired[v]], dim, probs, ci_confidence))
            lazy = lazy or da.chunks is not None
            continue
        da = da.astype(float) if da.dtype.kind != "f" else da
        if da.chunks is not None:
            da = da.chunk({dim: -1})
        keep = {k: a for k, a in da.attrs.items() if k in ("units", "standard_name")}
        long = da.attrs.get("long_name", v)
        with warnings.catch_warnings():  # all-NaN rows (e.g. fit_error before contact) give NaN
            warnings.filterwarnings("ignore", "All-NaN slice", RuntimeWarning)
            q = da.quantile(probs, dim=dim).transpose("quantile", ...)
        q.attrs = {**keep, "long_name": f"quantiles over {dim} of {long}"}
        out[v] = q
        mean = da.mean(dim)
        mean.attrs = {**keep, "long_name": f"mean over {dim} of {long}"}
        out[f"{v}_mean"] = mean
        count = da.count(dim)
        se = da.std(dim, ddof=1) / np.sqrt(count) if n > 1 else da.isel({dim: 0}) * np.nan
        se.attrs = {**keep, "long_name": f"standard error of the mean of {long}"}
        out[f"{v}_mean_stderr"] = se.drop_vars(dim, errors="ignore")
        # the members actually used at each point: NaN members are skipped by every reduction
        count.attrs = {"units": "1", "long_name": f"number of valid (non-NaN) members over {dim} "
                                                  f"used for {long}"}
        out[f"{v}_n_samples"] = count.drop_vars(dim, errors="ignore")
        lazy = lazy or da.chunks is not None
        if uncertainty is not None:
            lo, hi = quantile_interval(da.rename(v), probs, dim=dim, confidence=ci_confidence,
                                       method=uncertainty, n_bootstrap=n_bootstrap, seed=seed)
            out[f"{v}_ci_lower"], out[f"{v}_ci_upper"] = lo, hi
    res = xr.Dataset(out)
    res["quantile"] = ("quantile", probs, dict(ATTRS["quantile"]))
    for c in res.coords:
        if c in ATTRS:
            res[c].attrs = coord_attrs(c, res[c])
    # the run's parameters (seed, shape, spacing, PSD source, auto-n state ...) travel with the band
    res.attrs = {k: v for k, v in ds.attrs.items()
                 if isinstance(v, (str, int, float, np.integer, np.floating)) and k != "incomplete"}
    res.attrs.pop("n_samples", None)  # a count of the input is not a count of this band
    # the file's attribute names: level (the band) and confidence (its quantiles' intervals)
    res.attrs.update(level=confidence, confidence=ci_confidence, n_members=int(n),
                     uncertainty_method=str(uncertainty))
    if paired:
        res.attrs["band_method"] = (
            f"multi-fidelity: {', '.join(paired)} from the cheap model on every member corrected by "
            f"{ds.attrs['accurate_model']} on {ds.attrs.get('n_accurate', '?')} of them (cross-fitted "
            "two-phase difference estimator; the intervals hold the sampling and the model "
            "correction); <name>_cheap is the cheap model's own band")
    used = n
    if not lazy:
        # the fewest members used anywhere (in memory: the counts are already known)
        counts = [int(res[f"{v}_n_samples"].min()) for v in out if f"{v}_n_samples" in out]
        used = min(counts, default=n)
        res.attrs["n_samples"] = int(used)
    if "incomplete" in ds.attrs:
        res.attrs["incomplete"] = str(ds.attrs["incomplete"])
    if uncertainty == "order_statistic":
        need = min_samples_to_bound(float(probs[0]), confidence=ci_confidence)
        res.attrs["n_samples_to_bound_band_edges"] = int(need)
        res.attrs["band_edges_bounded"] = int(used >= need)
    return append_history(res, f"confidence_band(confidence={confidence}, dim={dim!r}, n={n})")


def _accurate_pairs(ds: xr.Dataset, dim: str) -> dict:
    """``{v: v + "_accurate"}`` of a multi-fidelity ensemble (``attrs["accurate_model"]``)."""
    if "accurate_model" not in ds.attrs:
        return {}
    return {v: f"{v}_accurate" for v in ds.data_vars
            if f"{v}_accurate" in ds.data_vars and dim in ds[v].dims}


def _multifidelity_entries(v, cheap, accurate, dim, probs, ci_confidence) -> dict:
    """The band entries of ``v`` from the cheap model on every member and the accurate one on a
    subset (:func:`roughstick.ensemble.multifidelity.multifidelity_band`), in the layout of the
    single-model band, plus the model correction's own interval and the cheap model's band."""
    if cheap.chunks is not None:
        cheap, accurate = cheap.chunk({dim: -1}), accurate.chunk({dim: -1})
    mf = multifidelity_band(cheap, accurate, dim=dim, quantiles=probs, confidence=ci_confidence)
    keep = {k: a for k, a in cheap.attrs.items() if k in ("units", "standard_name")}
    long = cheap.attrs.get("long_name", v)
    model = accurate.attrs.get("contact_model", "the accurate model")
    z = stats.norm.ppf(0.5 + ci_confidence / 2)

    def labelled(a, text):
        a = a.drop_vars(dim, errors="ignore")
        a.attrs = {**keep, "long_name": text}
        return a

    out = {
        v: labelled(mf["value"].transpose("quantile", ...),
                    f"quantiles over {dim} of {long} by {model} (multi-fidelity estimate)"),
        f"{v}_mean": labelled(mf["mean"], f"mean over {dim} of {long} by {model}"),
        f"{v}_mean_stderr": labelled((mf["mean_upper"] - mf["mean_lower"]) / (2 * z),
                                     f"standard error of the mean of {long} by {model}"),
        f"{v}_ci_lower": labelled(mf["lower"].transpose("quantile", ...),
                                  f"lower {ci_confidence:g} bound of each quantile (sampling and "
                                  "model correction)"),
        f"{v}_ci_upper": labelled(mf["upper"].transpose("quantile", ...),
                                  f"upper {ci_confidence:g} bound of each quantile (sampling and "
                                  "model correction)"),
        f"{v}_correction_lower": labelled(mf["correction_lower"].transpose("quantile", ...),
                                          "lower bound of each quantile of the same members all "
                                          f"run with {model} (model correction alone)"),
        f"{v}_correction_upper": labelled(mf["correction_upper"].transpose("quantile", ...),
                                          "upper bound of each quantile of the same members all "
                                          f"run with {model} (model correction alone)"),
        f"{v}_cheap": labelled(cheap.quantile(probs, dim=dim).transpose("quantile", ...),
                               f"quantiles over {dim} of {long} by the cheap model alone"),
    }
    count = cheap.count(dim)
    count.attrs = {"units": "1", "long_name": f"number of valid members over {dim} used for {long}"}
    out[f"{v}_n_samples"] = count
    n_acc = mf["n_accurate"]
    n_acc.attrs = {"units": "1", "long_name": f"members run with {model} for {long}"}
    out[f"{v}_n_accurate"] = n_acc
    return out


def _fmt(v: float, fmt: str) -> str:
    return format(v, fmt) if np.isfinite(v) else "nan"


@check_numbers(scale="positive")
def band_summary(band: xr.Dataset, variable: str = "adhesive_energy", *, scale: float = 1e3,
                 units: str = "mJ/m²", fmt: str = ".4g", median_interval: bool = False) -> list[str]:
    """One line per humidity: median, band and each band edge's own confidence interval; then
    one footnote per reason a value could not be bounded.

    With ``median_interval`` the median carries its own interval too, "(95% CI of the median
    [a, b])", or "(95% CI of the median: not bounded [2])" (``roughstick run`` prints it).

    An edge that the sample cannot bound reads "not bounded [1]" instead of a number, so a band
    from a few surfaces is never shown as if it were reliable; the footnote after the lines says
    why once for the whole block: "[1] n too small to bound a band edge (needs n >= N
    realizations)".
    ``n`` is the number of members used at that humidity (``variable_n_samples``: NaN members
    are not counted; the fewest over any other dims).
    ``band`` is a :func:`confidence_band` result over ``(quantile, rh)``; values are multiplied by
    ``scale`` and labelled ``units``.

    Examples
    --------
    >>> x = xr.DataArray(np.arange(20.0)[:, None] * [1.0, 2.0], dims=("realization", "rh"),
    ...                  coords={"rh": [0.5, 0.9]}, name="g", attrs={"units": "J m-2", "long_name": "g"})
    >>> for line in rs.ensemble.band_summary(rs.ensemble.confidence_band(x), "g", scale=1, units="J/m²"):
    ...     print(line)
    RH 50%: median 9.5 J/m², 95% band [0.475, 18.52] from n = 20; 95% CI of the edges: not bounded [1]
    RH 90%: median 19 J/m², 95% band [0.95, 37.05] from n = 20; 95% CI of the edges: not bounded [1]
    [1] n too small to bound a band edge (needs n >= 146 realizations)
    """
    level, conf = float(band.attrs["level"]), float(band.attrs.get("confidence", 0.95))
    n = int(band.attrs.get("n_samples", band.attrs.get("n_members", 0)))
    counts = band.get(f"{variable}_n_samples")  # members used per point (NaN members skipped)
    need = min_samples_to_bound(float(band["quantile"].values[0]), confidence=conf)
    q = band[variable].transpose("quantile", ...).values * scale
    has_ci = f"{variable}_ci_lower" in band
    if has_ci:
        lo = band[f"{variable}_ci_lower"].transpose("quantile", ...).values * scale
        hi = band[f"{variable}_ci_upper"].transpose("quantile", ...).values * scale
    notes: dict[str, str] = {}  # footnote text -> its marker, numbered as they first appear

    def unbounded(why: str) -> str:
        return "not bounded " + notes.setdefault(why, f"[{len(notes) + 1}]")

    rhs = band["rh"].values if "rh" in band[variable].dims else [None]
    lines = []
    for k, r in enumerate(rhs):
        col = (slice(None), k) if r is not None else (slice(None),)
        qq = q[col]
        if counts is not None:
            c = counts.isel(rh=k) if r is not None and "rh" in counts.dims else counts
            n = int(c.min())
        med = ""
        if median_interval and has_ci:
            a, b = lo[col][1], hi[col][1]
            med = (f" ({conf:.0%} CI of the median [{_fmt(a, fmt)}, {_fmt(b, fmt)}])" if np.isfinite(a) and np.isfinite(b)
                   else f" ({conf:.0%} CI of the median: " + unbounded(
                       f"n too small to bound the median (needs n >= {min_samples_to_bound(0.5, confidence=conf)} "
                       "realizations)") + ")")
        head = (f"RH {r:.0%}: " if r is not None else "") + (
            f"median {_fmt(qq[1], fmt)} {units}{med}, {level:.0%} band [{_fmt(qq[0], fmt)}, "
            f"{_fmt(qq[2], fmt)}] from n = {n}")
        if not has_ci:
            lines.append(head + "; the band's own uncertainty was not computed")
            continue
        edge_note = f"n too small to bound a band edge (needs n >= {need} realizations)"
        bounded = [np.isfinite(lo[col][j]) and np.isfinite(hi[col][j]) for j in (0, 2)]
        if not any(bounded):
            lines.append(head + f"; {conf:.0%} CI of the edges: " + unbounded(edge_note))
            continue
        parts = []
        for j, side, ok in ((0, "lower", bounded[0]), (2, "upper", bounded[1])):
            parts.append(f"of the {side} edge [{_fmt(lo[col][j], fmt)}, {_fmt(hi[col][j], fmt)}]" if ok
                         else f"of the {side} edge: " + unbounded(edge_note))
        lines.append(head + f"; {conf:.0%} CI " + ", ".join(parts))
    return lines + [f"{marker} {why}" for why, marker in notes.items()]


# ----------------------------------------------------------------------------- proportions


def _interval_kernel(k, n, confidence, method):
    k = np.asarray(k, dtype=float)
    n = np.asarray(n, dtype=float)
    k, n = np.broadcast_arrays(k, n)
    alpha = 1.0 - confidence
    with np.errstate(invalid="ignore", divide="ignore"):
        if method == "wilson":
            z = special.ndtri(1.0 - alpha / 2.0)
            denom = n + z**2
            centre = (k + z**2 / 2.0) / denom
            half = z / denom * np.sqrt(k * (n - k) / n + z**2 / 4.0)
            lo, hi = centre - half, centre + half
            lo = np.where(k > 0, np.clip(lo, 0.0, 1.0), 0.0)
            hi = np.where(k < n, np.clip(hi, 0.0, 1.0), 1.0)
        else:  # clopper-pearson
            lo = np.where(k > 0, stats.beta.ppf(alpha / 2.0, k, n - k + 1.0), 0.0)
            hi = np.where(k < n, stats.beta.ppf(1.0 - alpha / 2.0, k + 1.0, n - k), 1.0)
    bad = ~(n > 0)
    lo = np.where(bad, np.nan, lo)
    hi = np.where(bad, np.nan, hi)
    return np.stack([lo, hi], axis=-1)

@check_numbers(confidence="fraction")
def binomial_interval(successes, trials, *, confidence: float = 0.95, method: str = "wilson"):
    r"""Confidence interval of a proportion estimated from ``successes`` out of ``trials``.

    Used for the Monte-Carlo uncertainty of the stiction probability: with :math:`n`
    realizations of which :math:`k` stay stuck, the probability is :math:`k/n` and this is the
    interval that covers the true probability with the requested confidence.

    Parameters
    ----------
    successes, trials : int, array or xarray.DataArray
        :math:`k` and :math:`n` (broadcast); ``n = 0`` gives NaN bounds.
    confidence : float, default 0.95
        Confidence level in (0, 1).
    method : {"wilson", "clopper-pearson"}
        Wilson score interval (no continuity correction; near-nominal coverage, never outside
        [0, 1]) or the exact, conservative Clopper-Pearson interval (beta quantiles; alias
        ``"exact"``).

    Returns
    -------
    tuple of (lower, upper)
        numpy arrays, or DataArrays when an input is a DataArray (lazy inputs stay lazy).

    Notes
    -----
    Wilson: :math:`\frac{k + z^2/2}{n + z^2} \pm \frac{z}{n + z^2}\sqrt{\frac{k(n-k)}{n} + \frac{z^2}{4}}`.
    Clopper-Pearson: :math:`[B(\alpha/2; k, n-k+1),\ B(1-\alpha/2; k+1, n-k)]` with :math:`B` the
    beta quantile function.

    References
    ----------
    Wilson, E. B., J. Am. Stat. Assoc. 22 (1927) 209, doi:10.1080/01621459.1927.10502953.
    Clopper, C. J., Pearson, E. S., Biometrika 26 (1934) 404, doi:10.1093/biomet/26.4.404.

    Examples
    --------
    >>> lo, hi = rs.ensemble.binomial_interval(3, 20)
    >>> round(float(lo), 4), round(float(hi), 4)
    (0.0524, 0.3604)
    """
    method = interval_method(method, confidence=confidence)
    if isinstance(successes, xr.DataArray) or isinstance(trials, xr.DataArray):
        k = successes if isinstance(successes, xr.DataArray) else xr.DataArray(successes)
        n = trials if isinstance(trials, xr.DataArray) else xr.DataArray(trials)
        both = xr.apply_ufunc(
            _interval_kernel,
            k,
            n,
            kwargs={"confidence": confidence, "method": method},
            output_core_dims=[["bound"]],
            dask="parallelized",
            output_dtypes=[float],
            dask_gufunc_kwargs={"output_sizes": {"bound": 2}},
        )
        return both.isel(bound=0, drop=True), both.isel(bound=1, drop=True)
    both = _interval_kernel(successes, trials, confidence, method)
    return both[..., 0], both[..., 1]
