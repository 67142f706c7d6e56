"""P(stuck) of every beam from the strips' exceedance probabilities: the patch thresholds K/x⁴ of
Eq. 36, the product over a beam's patches, and the same at both ends of the models' band."""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from scipy.stats import norm

from .._core.conventions import append_history, set_attrs
from .risk import crossing_humidity

#: Relative error of a strip's Γ from the strips route's models, (below, above), measured on the
#: Table 4 PSD at 77 % RH: whole 524 × 6000 px strips solved by fft_bem hold 0.75 % [−0.1, +1.6]
#: more than their composed law on strong strips (+2.8 % [+1.5, +4.1] on random ones; the
#: composition leaves out the sub-zones' elastic interaction), the two-fidelity hybrid puts
#: unseen strong strips 0.8-1.3 % below their fft_bem Γ, and fft_bem itself agrees with an
#: independent boundary-element solver to 0.4 %. On the S1 PSD whole strips hold 0.41 %
#: [0.20, 0.61] more than their composed law on strong strips; on Table 4 at 70 % RH 1.8 %
#: [0.5, 3.1] (at most 3.9 % on one strip).
MODEL_BAND = (-0.005, 0.045)


def model_band_problem(band):
    """What is wrong with a model band, (below, above) relative errors of the strips' Γ, as a
    sentence ending in the rule it breaks; None where it is a band (``-1 < below <= 0 <= above``)."""
    rule = "give (below, above), two relative errors of the strips' Γ with -1 < below <= 0 <= above"
    try:
        lo, hi = (float(v) for v in band)
    except (TypeError, ValueError):
        return rule
    return None if math.isfinite(lo) and math.isfinite(hi) and -1 < lo <= 0 <= hi else rule


def _model_band(band, two_fidelities):
    """The model band as (below, above) relative errors, None where there is none."""
    if band is None:
        return MODEL_BAND if two_fidelities else None
    problem = model_band_problem(band)
    if problem is not None:
        raise ValueError(f"model_band={band!r}: {problem}, e.g. model_band={MODEL_BAND}")
    return tuple(float(v) for v in band)


def _patch_thresholds(lengths, beam, patch_length):
    """The thresholds K/x_{j+1}^4 of every patch of every beam (Eq. 36), as one sorted array and,
    per beam, the indices of its patches in it."""
    per = []
    for length in lengths:
        hi = np.minimum((np.arange(int(np.ceil(length / patch_length - 1e-9))) + 1) * patch_length, length)
        per.append(beam.stiffness_term / hi**4)
    allt = np.unique(np.concatenate(per))
    return allt, [np.searchsorted(allt, t) for t in per]


def _beam_probability(est, sd, patches):
    """P(stuck) = 1 - prod_j (1 - C_j) over a beam's patches, and its sd bounded as if the C_j
    were fully correlated (they are nested exceedances of one estimate): sum_j g_j sd_j."""
    c, s = np.clip(est[patches], 0.0, 1.0), sd[patches]
    p = float(-np.expm1(np.sum(np.log1p(-np.minimum(c, 1.0 - 1e-16))))) + 0.0  # no -0.0
    keep = np.prod(1.0 - c)
    g = np.where(c < 1, keep / np.maximum(1.0 - c, 1e-300), 0.0)
    return p, float(np.sum(g * s))


def _beam_rows(ccdf, k, block, per_beam, z):
    """P(stuck), its sd and interval per beam at humidity ``k`` from one block of the ccdf's
    thresholds (``block`` slices the patch thresholds of that block)."""
    est = ccdf["exceedance_probability"].values[k][block]
    sd = np.where(est > 0, np.nan_to_num(ccdf["coefficient_of_variation"].values[k][block]) * est, 0.0)
    rows = []
    for patches in per_beam:
        p, s = _beam_probability(est, sd, patches)
        cv = s / p if p > 0 else np.nan
        lo = p * math.exp(-min(z * cv, 700.0)) if p > 0 else 0.0
        hi = min(1.0, p * math.exp(min(z * cv, 700.0))) if p > 0 else np.nan
        rows.append((p, cv, lo, hi))
    return np.array(rows)


def _stuck_dataset(ccdf, rh, lengths, per_beam, allt, confidence, band=None):
    z = float(norm.ppf(0.5 + confidence / 2))
    shape = (rh.size, lengths.size)
    base = slice(0, allt.size)
    p, lo, hi, cv, pair_cv, beyond, margin = (np.zeros(shape) for _ in range(7))
    model_lo, model_hi = np.full(shape, np.nan), np.full(shape, np.nan)
    for k in range(rh.size):
        rows = _beam_rows(ccdf, k, base, per_beam, z)
        p[k], cv[k], lo[k], hi[k] = rows.T
        est = ccdf["exceedance_probability"].values[k][base]
        sd_pairs = np.where(est > 0, np.nan_to_num(ccdf["emulator_cv"].values[k][base]) * est, 0.0)
        top = float(ccdf["largest_strip_energy"].values[k])
        for b, patches in enumerate(per_beam):
            margin[k, b] = float(allt[patches].min()) / top if top > 0 else np.inf
            beyond[k, b] = p[k, b] == 0
            pair_cv[k, b] = _beam_probability(est, sd_pairs, patches)[1] / p[k, b] if p[k, b] > 0 else np.nan
        if band is not None:
            # the strips' Γ scaled by (1 + band[1]) (thresholds allt / (1 + band[1])) and by (1 + band[0])
            model_hi[k] = _beam_rows(ccdf, k, slice(allt.size, 2 * allt.size), per_beam, z)[:, 3]
            model_lo[k] = _beam_rows(ccdf, k, slice(2 * allt.size, 3 * allt.size), per_beam, z)[:, 2]
            # the band holds the sampling interval (exceedance is monotone in the threshold; the
            # bounds' cvs are estimated separately and may not be)
            model_lo[k] = np.fmin(model_lo[k], lo[k])
            model_hi[k] = np.where(np.isnan(model_hi[k]), np.nan, np.fmax(model_hi[k], hi[k]))
    dims = ("rh", "beam_length")
    ds = xr.Dataset({
        "stiction_probability": (dims, p, {"units": "1", "long_name": "P(stuck), sharp front on the beam's strips",
                                           "comment": "S-shaped stiction of the sharp front (Eq. 36); beams the "
                                                      "cohesive beam leaves as arcs held by the tip are not counted"}),
        "stiction_probability_lower": (dims, lo, {"units": "1", "long_name": "lower bound of P(stuck)"}),
        "stiction_probability_upper": (dims, hi, {"units": "1", "long_name": "upper bound of P(stuck) (NaN beyond reach)"}),
        "coefficient_of_variation": (dims, cv, {"units": "1", "long_name": "coefficient of variation of P(stuck)"}),
        "emulator_cv": (dims, pair_cv, {"units": "1", "long_name": "its part from the random pairs' ratios"}),
        "beyond_reach": (dims, beyond.astype(bool), {"units": "1", "long_name": "no combination of the sample fails"}),
        "reach_margin": (dims, margin, {"units": "1", "long_name": "threshold over the largest strip Γ found"}),
    }, coords={"rh": rh, "beam_length": ("beam_length", lengths, {"units": "m"})})
    if band is not None:
        ds["stiction_probability_model_lower"] = (dims, model_lo, {
            "units": "1", "long_name": "lower bound of P(stuck), sampling and model band",
            "comment": f"lower bound of P(stuck) with every strip's Γ scaled by {1 + band[0]:g}"})
        ds["stiction_probability_model_upper"] = (dims, model_hi, {
            "units": "1", "long_name": "upper bound of P(stuck), sampling and model band (NaN beyond reach)",
            "comment": f"upper bound of P(stuck) with every strip's Γ scaled by {1 + band[1]:g}"})
    first = [patches[np.argmin(allt[patches])] for patches in per_beam]
    for v in ("effective_subzones", "few_subzones", "accurate_share"):
        ds[v] = (dims, ccdf[v].values[:, first], ccdf[v].attrs)
    for v in ("accurate_ratio", "ratio_check_rms_z", "ratio_check_within_2sd", "ratio_check_strips"):
        ds[v] = ccdf[v].assign_coords(rh=rh)
    ds["rh"].attrs = set_attrs(ds["rh"], "rh").attrs
    ds["beam_length"].attrs.update(long_name="beam length")
    ds.attrs.update(confidence=float(confidence), estimator=ccdf.attrs["estimator"],
                    model="sharp_front", references="paper Eq. 13, Eq. 36, §5.2 (zone Δs × w)")
    if band is not None:
        ds.attrs["model_band"] = [float(band[0]), float(band[1])]
    return ds


#: Most further calls ``refine_crossing`` makes, each at the crossings not yet held by an estimate.
REFINE_CALLS = 3


def _refine_points(result, levels):
    """The humidities where the next call sharpens a crossing of one of ``levels``: where the
    estimate crosses while neither grid point next to it has an interval holding the level; once
    one does, where the interval's ends cross (the upper bound of P, the lower bound) while the
    grid points next to an end are further apart than the interval is wide. Each point by
    :func:`_inverse_quadratic` between two values inside (0, 1), the middle of the two grid points
    next to a 0 or a 1; rounded to 0.001 and kept 0.002 from the grid points (none between
    points closer than 0.005) and from each other."""
    grid = result["rh"].values
    dims = result["stiction_probability"].dims[1:]
    curves = {e: result[f"stiction_probability{e}"] for e in ("", "_upper", "_lower")}
    values = {e: c.transpose("rh", *dims).values.reshape(grid.size, -1) for e, c in curves.items()}
    points = set()
    for level in levels:
        x = {e: np.ravel(crossing_humidity(c.fillna(0.0), probability=float(level))["crossing_humidity"]
                         .transpose(*dims).values) for e, c in curves.items()}
        for b in range(x[""].size):
            c = x[""][b]
            if not np.isfinite(c) or np.min(np.abs(grid - c)) < 1e-9:
                continue
            k = int(np.searchsorted(grid, c))
            held = np.any((values["_lower"][k - 1:k + 1, b] <= level) & (level <= values["_upper"][k - 1:k + 1, b]))
            width = x["_lower"][b] - x["_upper"][b]  # the crossing's interval: upper bound of P crosses first
            for e in ("",) if not held else ("_upper", "_lower"):
                c = x[e][b]
                if not np.isfinite(c) or np.min(np.abs(grid - c)) < 1e-9:
                    continue
                k = int(np.searchsorted(grid, c))
                lo, hi = grid[k - 1], grid[k]
                if hi - lo < 5e-3 or (e and not hi - lo > width):
                    continue
                v = values[e][:, b]
                inside = 0 < v[k - 1] < 1 and 0 < v[k] < 1
                c = _inverse_quadratic(grid, v, k, level, c) if inside else (lo + hi) / 2
                c = float(np.clip(round(float(c), 3), lo + 2e-3, hi - 2e-3))
                if all(abs(c - q) > 1.5e-3 for q in points):  # one point serves crossings 0.001 apart
                    points.add(c)
    return sorted(points)


def _inverse_quadratic(grid, p, k, level, secant):
    """RH where logit P reaches logit ``level`` by the quadratic in logit P through the crossing's
    two grid points ``k - 1``, ``k`` and the next one inside (0, 1) beyond the nearer end (the
    curvature a straight line between two points misses), as in Brent's root finder; the secant
    ``secant`` where there is no third point or the quadratic leaves the bracket."""
    third = [j for j in (k - 2, k + 1) if 0 <= j < grid.size and 0 < p[j] < 1]
    if not third:
        return secant
    j = min(third, key=lambda j: min(abs(grid[j] - grid[k - 1]), abs(grid[j] - grid[k])))
    idx = [k - 1, k, j]
    y = np.log(p[idx] / (1 - p[idx]))
    if np.unique(y).size < 3:
        return secant
    target = math.log(level / (1 - level))
    x = sum(grid[a] * np.prod([(target - y[q]) / (y[i] - y[q]) for q in range(3) if q != i])
            for i, a in enumerate(idx))
    return float(x) if grid[k - 1] < x < grid[k] else secant


def _refined(call, args, levels):
    """``call(**args)`` on its grid, then up to :data:`REFINE_CALLS` more at the humidities where a
    beam crosses one of ``levels`` (:func:`_refine_points`), all merged over ``rh``."""
    given = levels
    try:
        levels = np.atleast_1d(np.asarray(levels, dtype=float))
    except (TypeError, ValueError):
        levels = np.array([np.nan])
    if levels.ndim != 1 or levels.size == 0 or not np.all((levels > 0) & (levels < 1)):
        raise ValueError(f"refine_crossing={given!r}: pass P(stuck) levels strictly between 0 and 1, "
                         "e.g. refine_crossing=1e-3")
    out, added = call(**args), []
    for _ in range(REFINE_CALLS):
        new = _refine_points(out, levels)
        if not new:
            break
        more = call(**{**args, "relative_humidity": new})
        merged = xr.concat([out, more], "rh", data_vars="minimal", combine_attrs="override").sortby("rh")
        for key in ("seconds_cheap", "seconds_accurate", "seconds_estimator"):
            merged.attrs[key] = out.attrs[key] + more.attrs[key]
        for key in ("n_accurate_subzones", "n_random_pairs", "accurate_zone_equivalents"):
            merged.attrs[key] = max(out.attrs[key], more.attrs[key])
        out, added = merged, added + new
        append_history(out, f"refined at RH {', '.join(f'{v:.3f}' for v in new)} (crossings of "
                            f"{', '.join(f'{v:g}' for v in levels)})")
    out.attrs["refined_humidities"] = added
    return out
