r"""Multi-fidelity estimates: a cheap model on every realization, an accurate one on a few.

Every realization of an ensemble goes through a cheap model (the modified DMT of Eq. 16), a
random subset of them through the accurate one (the FFT boundary-element model), and the two are
combined by a *difference estimator* (two-phase sampling with model assistance: Särndal, Swensson
& Wretman 1992, ch. 9; the control-variate view of multifidelity Monte Carlo: Peherstorfer,
Willcox & Gunzburger 2018). For the accurate model's CDF at a threshold :math:`t`,

.. math::

    \hat F(t) = \frac1{|P|}\sum_{j\in P}\tilde F_j(t)
              + \frac1{|S_k|}\sum_{i\in S_k}\big(\mathbf 1[y_i\le t] - \tilde F_i(t)\big),

where :math:`\tilde F_j` is the predicted distribution of realization :math:`j`'s accurate value
from its cheap one (a line in log-log space fitted on the other folds of the subset, with their
residuals), :math:`S_k` one fold of the accurate subset and :math:`P` the realizations outside
the fitting folds; the fitting folds' own realizations enter with their accurate values (weight
:math:`1 - |P|/N`, the formula above weight :math:`|P|/N`), so that exact predictions give
exactly the distribution of the N accurate values. Each fold's estimate is unbiased whatever the predictor (cross-fitting: the
predictor never sees the fold it is corrected on); the predictor only sets the variance. The
estimate is averaged over folds; its variance is the two-phase one,

.. math:: V(t) = \frac{F(1-F)}{N} + \Big(\frac1n - \frac1N\Big)s_d^2(t),

the ensemble's own sampling (N realizations) plus the model correction (n accurate ones, the
spread :math:`s_d^2` of the corrections :math:`\mathbf 1[y_i\le t]-\tilde F_i(t)`). Quantiles
invert the monotone rearrangement of :math:`\hat F`; their intervals invert the CDF's interval
(Woodruff 1952). The mean is the same difference estimator on the values.

The subset is drawn from the root seed alone (a permutation of the realizations; its first
``n`` entries), so it does not depend on any computed value, and a larger ``n`` contains the
smaller subset.
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from scipy import stats

from .._core.arguments import check_numbers
from .._core.conventions import append_history
from .._core.dask import as_seed_sequence
from .._core.references import cite

__all__ = ["accurate_subset", "multifidelity_band", "accurate_subset_size"]

#: Factor on the corrections' variance expected from a pilot: it leaves out the error of the
#: fitted line and of the cross-fitting (measured on synthetic log-normal ensembles: with 1 the
#: band edges were within the accuracy in 70-90 % of 40 seeds, with 2 in 90-100 %).
PILOT_MARGIN = 2.0
#: Spawn key of the subset's generator (apart from the realizations' own streams).
_SUBSET_KEY = 0x6D66  # "mf"
_REFERENCES = cite("peherstorfer2018", "sarndal1992", "woodruff1952")


@check_numbers(n_total="count", n="count", seed="seed")
def accurate_subset(n_total: int, n: int, *, seed: int = 0) -> np.ndarray:
    """Indices (ascending) of the ``n`` realizations of ``n_total`` that get the accurate model.

    They depend on ``seed`` alone, and the subset of a larger ``n`` contains that of a smaller
    one (both are the first entries of one seeded permutation).

    Examples
    --------
    >>> from roughstick.ensemble.multifidelity import accurate_subset
    >>> a, b = accurate_subset(100, 5, seed=1), accurate_subset(100, 10, seed=1)
    >>> bool(np.isin(a, b).all()), a.size
    (True, 5)
    """
    if n > n_total:
        raise ValueError(f"n={n} accurate evaluations of n_total={n_total} realizations: pass n <= n_total.")
    ss = as_seed_sequence(seed)
    rng = np.random.default_rng(np.random.SeedSequence(ss.entropy, spawn_key=(*ss.spawn_key, _SUBSET_KEY)))
    return np.sort(rng.permutation(int(n_total))[: int(n)])


# ----------------------------------------------------------------------------- numpy kernels


def _transform(lo, hi):
    """log of both when every value is positive (Γ spans decades), else the identity."""
    if np.all(lo > 0) and np.all(hi[np.isfinite(hi)] > 0):
        return np.log(lo), np.log(hi), np.exp
    return lo.astype(float), hi.astype(float), (lambda v: v)


def _folds(m: int, k: int) -> list[np.ndarray]:
    k = max(2, min(int(k), m))
    return [np.arange(m)[i::k] for i in range(k)]


def _line(x, y):
    """Least-squares line y ~ a + b x and its residuals (b = 0 when x does not vary)."""
    xm, ym = x.mean(), y.mean()
    sxx = float(((x - xm) ** 2).sum())
    b = float(((x - xm) * (y - ym)).sum() / sxx) if sxx > 0 else 0.0
    a = ym - b * xm
    return a, b, y - (a + b * x)


def _ecdf(sorted_values: np.ndarray, t: np.ndarray) -> np.ndarray:
    return np.searchsorted(sorted_values, t, side="right") / max(sorted_values.size, 1)


def _fold_parts(x, z, sub, k):
    """Per fold: (population mask outside the training folds, fold members, a, b, residuals)."""
    parts = []
    for fold in _folds(sub.size, k):
        train = np.setdiff1d(np.arange(sub.size), fold)
        a, b, e = _line(x[sub[train]], z[sub[train]])
        pop = np.ones(x.size, bool)
        pop[sub[train]] = False
        parts.append((pop, sub[fold], a, b, np.sort(e)))
    return parts


def _cdf(x, z, parts, grid):
    """Cross-fitted difference estimate of the CDF on ``grid`` and the corrections d_i(t)."""
    F = np.zeros(grid.size)
    bern = np.zeros(grid.size)
    d = []
    for pop, members, a, b, e in parts:
        pooled = np.sort((a + b * x[pop])[:, None] + e[None, :], axis=None)
        # the model's own variance of a correction, mean of F~_j (1 - F~_j) over the population
        # (a floor for the corrections' sample variance, which a few accurate values in a tail
        # cannot estimate)
        cj = np.searchsorted(e, grid[None, :] - (a + b * x[pop])[::max(1, x[pop].size // 150), None],
                             side="right") / e.size
        bern += (cj * (1 - cj)).mean(axis=0)
        pred_fold = np.sort((a + b * x[members])[:, None] + e[None, :], axis=None)
        hi_fold = np.sort(z[members])
        # the training members count with their own accurate values, the others with their
        # predictions corrected by the fold: exact when the predictions are (no subsample of the
        # realizations stands in for all of them)
        w = pop.sum() / pop.size
        train = np.sort(z[~pop])
        F += (1 - w) * _ecdf(train, grid) + w * (_ecdf(pooled, grid) + _ecdf(hi_fold, grid)
                                                 - _ecdf(pred_fold, grid))
        # each member's correction 1[z_i <= t] - F~_i(t)
        shift = grid[None, :] - (a + b * x[members])[:, None]
        Fi = np.searchsorted(e, shift, side="right") / e.size
        d.append((z[members][:, None] <= grid[None, :]) - Fi)
    return F / len(parts), np.concatenate(d, axis=0), bern / len(parts)


def _mean(x, y, parts, logged: bool):
    """Cross-fitted difference estimate of the mean of the accurate values ``y``, the
    corrections y_i - y^_i (prediction: the line, back-transformed with its residuals' spread)
    and the variance of one accurate value (of the predictions over the population plus that of
    the corrections: steadier than the few accurate values' own)."""
    est, spread, resid = 0.0, 0.0, []
    for pop, members, a, b, e in parts:
        if logged:
            smear = float(np.exp(e).mean())  # Duan's smearing: E[exp(residual)]

            def predict(v, a=a, b=b, smear=smear):
                return np.exp(a + b * v) * smear
        else:
            def predict(v, a=a, b=b):
                return a + b * v
        r = y[members] - predict(x[members])
        pred = predict(x[pop])
        w = pop.sum() / pop.size  # the training members count with their own accurate values
        est += (1 - w) * y[~pop].mean() + w * (pred.mean() + r.mean())
        spread += pred.var(ddof=1) + r.var(ddof=1)
        resid.append(r)
    return est / len(parts), np.concatenate(resid), spread / len(parts)


def multifidelity_kernel(cheap, accurate, *, probabilities, confidence=0.95, folds=5, grid_size=1500):
    """Estimates of one quantity (numpy, last axis = realizations).

    ``cheap``: (N,) values of the cheap model on every realization; ``accurate``: (N,) with the
    accurate values on the subset and NaN elsewhere. Returns a dict of arrays: ``quantile``,
    ``quantile_lower``, ``quantile_upper`` (total interval) and ``correction_lower``,
    ``correction_upper`` (the model correction alone: the interval for the all-accurate
    ensemble on the same N realizations), per probability; ``mean``, ``mean_lower``,
    ``mean_upper``; ``n_accurate``.
    """
    lo = np.asarray(cheap, dtype=float)
    hi = np.asarray(accurate, dtype=float)
    probs = np.asarray(probabilities, dtype=float)
    sub = np.flatnonzero(np.isfinite(hi))
    keep = np.isfinite(lo)
    nan = {k: np.full(probs.size, np.nan) for k in ("quantile", "quantile_lower", "quantile_upper",
                                                     "correction_lower", "correction_upper")}
    out = {**nan, "mean": np.nan, "mean_lower": np.nan, "mean_upper": np.nan, "n_accurate": sub.size}
    if sub.size < 4 or not keep[sub].all() or keep.sum() < sub.size:
        return out
    lo, hi = lo[keep], hi[keep]
    sub = np.flatnonzero(np.isfinite(hi))
    N, n = lo.size, sub.size
    x, z, inverse = _transform(lo, hi)
    parts = _fold_parts(x, z, sub, folds)
    grid = _grid(x, z, sub, parts, grid_size)
    F, d, floor = _cdf(x, z, parts, grid)
    Fm = np.clip(np.maximum.accumulate(np.sort(F)), 0.0, 1.0)  # monotone rearrangement
    s2d = np.maximum(d.var(axis=0, ddof=1), floor)
    zq = stats.norm.ppf(0.5 + confidence / 2.0)
    # the thresholds in the data's units; an accurate value itself where the grid holds one (not
    # exp(log v), which can miss v by a rounding error: an interval would miss an atom it holds)
    values = inverse(grid)
    values[np.searchsorted(grid, z[sub])] = hi[sub]
    for i, p in enumerate(probs):
        q_idx = min(int(np.searchsorted(Fm, p, side="left")), grid.size - 1)
        Fq = Fm[q_idx]
        corr_var = max(1.0 / n - 1.0 / N, 0.0) * s2d[q_idx]
        tot_var = Fq * (1 - Fq) / N + corr_var
        out["quantile"][i] = values[q_idx]
        for key, var in (("quantile", tot_var), ("correction", corr_var)):
            half = zq * np.sqrt(var)
            lo_i = min(int(np.searchsorted(Fm, p - half, side="left")), grid.size - 1)
            hi_i = min(int(np.searchsorted(Fm, p + half, side="left")), grid.size - 1)
            out[f"{key}_lower"][i] = values[lo_i] if p - half > Fm[0] else np.nan
            out[f"{key}_upper"][i] = values[hi_i] if p + half <= Fm[-1] else np.nan
    mean, resid, s2y = _mean(x, hi, parts, inverse is np.exp)
    mv = s2y / N + max(1.0 / n - 1.0 / N, 0.0) * resid.var(ddof=1)
    out.update(mean=mean, mean_lower=mean - zq * np.sqrt(mv), mean_upper=mean + zq * np.sqrt(mv))
    return out


def _grid(x, z, sub, parts, size):
    """Thresholds: every accurate value, every realization's central prediction and quantiles
    of the pooled predictions (with residuals)."""
    pop, _, a, b, e = parts[0]
    pooled = (a + b * x[pop])[:, None] + e[None, :]
    qs = np.quantile(pooled, np.linspace(0, 1, size))
    return np.unique(np.concatenate([qs, z[sub], a + b * x]))


# ----------------------------------------------------------------------------- xarray layer


@check_numbers(confidence="fraction", folds="count")
def multifidelity_band(cheap: xr.DataArray, accurate: xr.DataArray, *, dim: str = "realization",
                       quantiles=(0.025, 0.5, 0.975), confidence: float = 0.95,
                       folds: int = 5) -> xr.Dataset:
    r"""Quantiles and mean of the accurate model's values from a cheap model plus a few accurate runs.

    Parameters
    ----------
    cheap : xarray.DataArray
        The cheap model's values on every realization, dims ``(dim, ...)``.
    accurate : xarray.DataArray
        The accurate model's values on the subset (:func:`accurate_subset`), NaN elsewhere, same
        dims and coordinate ``dim`` as ``cheap`` (a DataArray over the subset alone is
        reindexed).
    dim : str
        The realization dimension.
    quantiles : sequence of float
        Probabilities of the quantiles (default the 95 % band edges and the median).
    confidence : float
        Level of the intervals.
    folds : int
        Cross-fitting folds of the accurate subset.

    Returns
    -------
    xarray.Dataset
        Over ``(quantile, ...)``: ``value`` (the quantile of the accurate model), ``lower`` /
        ``upper`` (its interval: sampling of the ensemble and model correction together) and
        ``correction_lower`` / ``correction_upper`` (the correction alone: where the quantile of
        the same realizations all run with the accurate model lies); over ``(...)``: ``mean``,
        ``mean_lower``, ``mean_upper``, ``n_accurate``. Units and attrs of ``cheap``.

    Notes
    -----
    The cross-fitted difference estimator of the module docstring: unbiased for the accurate
    model's mean and CDF whatever the relation between the models; a strong relation (Eq. 16 and
    the FFT boundary-element model are rank-correlated in the bulk) makes the correction small.

    References
    ----------
    .. [1] Peherstorfer, B., Willcox, K., Gunzburger, M. (2018). SIAM Rev. 60, 550-591.
       https://doi.org/10.1137/16M1082469

    Examples
    --------
    >>> from roughstick.ensemble.multifidelity import accurate_subset, multifidelity_band
    >>> rng = np.random.default_rng(0)
    >>> lo = xr.DataArray(rng.lognormal(size=400), dims="realization")
    >>> hi = (0.8 * lo ** 1.1 * np.exp(0.05 * rng.normal(size=400))).where(
    ...     lo.realization.isin(accurate_subset(400, 60, seed=0)))
    >>> band = multifidelity_band(lo, hi)
    >>> band["value"].sizes["quantile"], int(band["n_accurate"])
    (3, 60)
    """
    if dim not in cheap.dims:
        raise ValueError(f"cheap has no dimension {dim!r} (dims {cheap.dims}); pass dim=.")
    if dim not in accurate.dims:
        raise ValueError(f"accurate has no dimension {dim!r} (dims {accurate.dims}); pass dim=.")
    if dim in cheap.coords and dim in accurate.coords and accurate.sizes[dim] != cheap.sizes[dim]:
        accurate = accurate.reindex({dim: cheap[dim]})
        if accurate.chunks is not None:  # reindexing split the core dimension: one chunk again
            accurate = accurate.chunk({dim: -1})
    probs = np.asarray(quantiles, dtype=float)
    names = ("quantile", "quantile_lower", "quantile_upper", "correction_lower", "correction_upper")

    def kernel(lo, hi):
        r = multifidelity_kernel(lo, hi, probabilities=probs, confidence=confidence, folds=folds)
        return (*[r[k] for k in names], np.float64(r["mean"]), np.float64(r["mean_lower"]),
                np.float64(r["mean_upper"]), np.float64(r["n_accurate"]))

    outs = xr.apply_ufunc(
        kernel, cheap, accurate, input_core_dims=[[dim], [dim]],
        output_core_dims=[["quantile"]] * 5 + [[]] * 4, vectorize=True, dask="parallelized",
        output_dtypes=[float] * 9, dask_gufunc_kwargs={"output_sizes": {"quantile": probs.size}},
    )
    ds = xr.Dataset(coords={"quantile": probs})
    for key, arr in zip(("value", "lower", "upper", "correction_lower", "correction_upper", "mean",
                         "mean_lower", "mean_upper", "n_accurate"), outs, strict=True):
        arr = arr.assign_coords(quantile=probs) if "quantile" in arr.dims else arr
        arr.attrs = dict(cheap.attrs) if key != "n_accurate" else {
            "long_name": "realizations run with the accurate model", "units": "1"}
        ds[key] = arr
    ds["quantile"].attrs = {"long_name": "probability of the quantile", "units": "1"}
    ds.attrs.update(method="cross-fitted two-phase difference estimator (log-log line)",
                    confidence=confidence, folds=folds, references=_REFERENCES)
    return append_history(ds, f"multifidelity_band(confidence={confidence}, folds={folds})")


@check_numbers(n_total="count", accuracy="positive", confidence="fraction", folds="count")
def accurate_subset_size(cheap, accurate, *, n_total: int, accuracy: float,
                         probabilities=(0.025, 0.5, 0.975), confidence: float = 0.95,
                         folds: int = 5) -> int:
    """How many of ``n_total`` realizations must run the accurate model for the model correction
    of every quantile to lie within ``accuracy`` (relative, at ``confidence``).

    ``cheap``, ``accurate``: a pilot, both models on the same realizations (numpy, 1-D). The
    spread of the corrections and the density at each quantile come from the pilot; the result is
    at least the pilot's size and at most ``n_total`` (then every realization runs the accurate
    model).

    Examples
    --------
    >>> from roughstick.ensemble.multifidelity import accurate_subset_size
    >>> rng = np.random.default_rng(0)
    >>> lo = rng.lognormal(size=40)
    >>> hi = lo * np.exp(0.02 * rng.normal(size=40))
    >>> accurate_subset_size(lo, hi, n_total=3000, accuracy=0.05) < 3000
    True
    """
    lo = np.asarray(cheap, dtype=float)
    hi = np.asarray(accurate, dtype=float)
    ok = np.isfinite(lo) & np.isfinite(hi)
    lo, hi = lo[ok], hi[ok]
    N = int(n_total)
    if lo.size < 2 * max(int(folds), 2):
        return N  # too small a pilot to learn the relation: run everything accurately
    x, z, inverse = _transform(lo, hi)
    parts = _fold_parts(x, z, np.arange(lo.size), folds)
    grid = _grid(x, z, np.arange(lo.size), parts, 1500)
    F, _, _ = _cdf(x, z, parts, grid)
    Fm = np.clip(np.maximum.accumulate(np.sort(F)), 0.0, 1.0)
    # the corrections' variance at t expected under the fitted line, smooth in t (in a tail a few
    # pilot values show it only as 0 or 1/n): density of the central predictions at t x residual
    # spread / sqrt(pi) (Gaussian residuals); the final intervals use the corrections' own spread
    a, b, e = _line(x, z)
    spread = float(e.std(ddof=2)) if e.size > 2 else 0.0
    pred = a + b * x
    model_var = (stats.gaussian_kde(pred)(grid) * spread / np.sqrt(np.pi)
                 if spread > 0 and np.ptp(pred) > 0 else np.zeros(grid.size))
    s2d = PILOT_MARGIN * model_var
    zq = stats.norm.ppf(0.5 + confidence / 2.0)
    need = lo.size
    logged = inverse is np.exp
    for p in np.asarray(probabilities, dtype=float):
        i = min(int(np.searchsorted(Fm, p)), grid.size - 1)
        # the density of the transformed values at the quantile (log Γ: a relative error is an
        # error in log), from the rearranged CDF over +-5 % of probability inside (0, 1)
        lo_p, hi_p = max(p - 0.05, Fm[0] + 1e-9), min(p + 0.05, 1.0)
        j0 = min(int(np.searchsorted(Fm, lo_p)), grid.size - 1)
        j1 = min(int(np.searchsorted(Fm, hi_p)), grid.size - 1)
        dz = grid[j1] - grid[j0]
        density = (Fm[j1] - Fm[j0]) / dz if dz > 0 else np.inf
        scale = 1.0 if logged else abs(float(grid[i]))  # relative error of the quantile
        allowed = (accuracy * scale * density / zq) ** 2  # variance of F^ the target allows
        if not (s2d[i] > 0 and np.isfinite(allowed) and allowed > 0):
            continue
        need = max(need, int(np.ceil(1.0 / (allowed / s2d[i] + 1.0 / N))))
    return int(min(need, N))
