r"""Height distributions of rough surfaces: the marginal of measured maps, or a Johnson system
fitted to a skewness and a kurtosis.

A height distribution :math:`F` is held as its *translation* from a standard normal score,

.. math::

    T(u) = F^{-1}\bigl(\Phi(u)\bigr), \qquad u \sim N(0, 1) \;\Rightarrow\; T(u) \sim F,

tabulated on a uniform grid of normal scores :math:`u \in [-8, 8]` (probabilities
:math:`6\cdot10^{-16}` to :math:`1 - 6\cdot10^{-16}`), in units of the rms height. A Gaussian
is :math:`T(u) = u`. The Johnson systems (Johnson 1949) are translations in closed form,

.. math::

    S_U:\; T(u) = \xi + \lambda \sinh\frac{u - \gamma}{\delta}, \qquad
    S_B:\; T(u) = \xi + \frac{\lambda}{1 + e^{-(u - \gamma)/\delta}},

and one of them has any (skewness, kurtosis) pair of a distribution: :math:`S_U` above the
lognormal line of the (skewness², kurtosis) plane, :math:`S_B` below it. The empirical
distribution of measured maps is their pooled quantile function (each map standardised by its
own mean and rms), continued beyond the data's reach (the outermost pixel on either side) by a
straight line in :math:`u` with the slope of the data's last unit of :math:`u` on that side, and
smoothed over 0.05 in :math:`u` (the sample quantile function of correlated pixels is noisy on
smaller scales).

:func:`roughstick.surface.generate_surfaces` imposes such a distribution on surfaces of a given
PSD (``height_distribution=``); the PSD sets their rms height, the distribution their shape.
"""

from __future__ import annotations

import functools

import numpy as np
import xarray as xr
from scipy import ndimage, optimize, special

from .._core.arguments import check_numbers
from .._core.conventions import append_history, dataset_attrs
from .._core.references import cite
from .._core.validate import as_length
from .topography import level_unless_periodic

__all__ = ["height_distribution"]

REFERENCES = cite("johnson1949")

#: The normal scores on which every translation is tabulated.
SCORE = np.linspace(-8.0, 8.0, 1601)
#: Width (in normal score) of the Gaussian smoothing of an empirical quantile function.
SMOOTHING = 0.05
#: Families of :func:`height_distribution`.
FAMILIES = ("normal", "empirical", "johnson_su", "johnson_sb")


@functools.lru_cache(maxsize=4)
def gauss_hermite(n: int = 200):
    """Nodes and weights (summing to 1) of the ``n``-point Gauss-Hermite rule for E[g(u)],
    u ~ N(0, 1) (probabilists' Hermite polynomials)."""
    x, w = np.polynomial.hermite_e.hermegauss(n)
    return x, w / w.sum()


@functools.lru_cache(maxsize=1)
def normal_grid(step: float = 0.0025, reach: float = 12.0):
    """A fine uniform grid of normal scores and its weights (summing to 1) for E[g(u)],
    u ~ N(0, 1), of piecewise-linear g (a tabulated translation and its Hermite coefficients)."""
    u = np.arange(-reach, reach + step / 2, step)
    w = np.exp(-0.5 * u * u)
    return u, w / w.sum()


def standard_moments(values: np.ndarray, weights: np.ndarray) -> tuple[float, float, float, float]:
    """Mean, standard deviation, skewness and kurtosis of ``values`` under ``weights`` (sum 1)."""
    mean = float(weights @ values)
    c = values - mean
    var = float(weights @ c**2)
    return mean, var**0.5, float(weights @ c**3) / var**1.5, float(weights @ c**4) / var**2


def evaluate(table: np.ndarray, u) -> np.ndarray:
    """The tabulated translation at normal scores ``u``: linear between the grid points of
    :data:`SCORE`, continued linearly beyond its ends (the slope of the last interval)."""
    u = np.asarray(u, dtype=float)
    step = SCORE[1] - SCORE[0]
    out = np.interp(u, SCORE, table)
    lo, hi = u < SCORE[0], u > SCORE[-1]
    out[lo] = table[0] + (u[lo] - SCORE[0]) * (table[1] - table[0]) / step
    out[hi] = table[-1] + (u[hi] - SCORE[-1]) * (table[-1] - table[-2]) / step
    return out


def standardised(table: np.ndarray) -> np.ndarray:
    """The translation table with mean 0 and variance 1 under u ~ N(0, 1), as interpolated by
    :func:`evaluate` (the generators scale it by the PSD's rms height)."""
    x, w = normal_grid()
    mean, sd, _, _ = standard_moments(evaluate(table, x), w)
    return (np.asarray(table, dtype=float) - mean) / sd


# ------------------------------------------------------------------------------ Johnson systems
def _johnson(family: str, a: float, b: float, u):
    t = (np.asarray(u, dtype=float) - a) / b
    return np.sinh(t) if family == "johnson_su" else special.expit(t)


def _lognormal_kurtosis(skewness: float) -> float:
    """Kurtosis of the lognormal with this skewness: the line between the S_U and S_B regions."""
    s2 = skewness * skewness
    w = optimize.brentq(lambda w: (w - 1) * (w + 2) ** 2 - s2, 1.0, 1e3)
    return w**4 + 2 * w**3 + 3 * w**2 - 3


def johnson_fit(skewness: float, kurtosis: float) -> tuple[str, float, float]:
    """``(family, a, b)`` of the Johnson distribution with this skewness and kurtosis (moments
    matched to 1e-9 by Gauss-Hermite quadrature): ``scipy.stats.johnsonsu(a, b)`` or
    ``johnsonsb(a, b)`` up to location and scale; ``("normal", 0, 1)`` for (0, 3)."""
    if not kurtosis > 1 + skewness**2:
        raise ValueError(
            f"no distribution has skewness {skewness:g} and kurtosis {kurtosis:g}: every "
            f"distribution has kurtosis > 1 + skewness**2 = {1 + skewness**2:g} (kurtosis is the "
            "fourth standardised moment, 3 for a Gaussian; not the excess kurtosis).")
    if abs(skewness) < 1e-12 and abs(kurtosis - 3) < 1e-12:
        return "normal", 0.0, 1.0
    s = abs(skewness)
    family = "johnson_su" if kurtosis >= _lognormal_kurtosis(s) else "johnson_sb"
    x, w = gauss_hermite()

    def residual(p):
        return np.subtract(standard_moments(_johnson(family, p[0], np.exp(p[1]), x), w)[2:], (s, kurtosis))

    best = None
    starts = [(-0.5, 0.0), (-2.0, 0.7), (-5.0, 1.4), (0.0, -0.7)]
    for a0, lb0 in starts if family == "johnson_su" else [(-a, lb) for a, lb in starts]:
        fit = optimize.least_squares(residual, [a0, lb0], xtol=1e-15, ftol=1e-15, gtol=1e-15)
        if best is None or fit.cost < best.cost:
            best = fit
        if best.cost < 1e-20:
            break
    if best.cost > 1e-16:
        raise ValueError(f"no Johnson {family[-2:].upper()} distribution found with skewness "
                         f"{skewness:g} and kurtosis {kurtosis:g} (closest: residual "
                         f"{np.sqrt(2 * best.cost):.2g}).")
    a, b = float(best.x[0]), float(np.exp(best.x[1]))
    return family, (-a if skewness < 0 else a), b


def _johnson_table(skewness: float, kurtosis: float) -> tuple[np.ndarray, dict]:
    family, a, b = johnson_fit(skewness, kurtosis)
    if family == "normal":
        return SCORE.copy(), {"family": "normal"}
    x, w = gauss_hermite()
    mean, sd, _, _ = standard_moments(_johnson(family, a, b, x), w)
    table = (_johnson(family, a, b, SCORE) - mean) / sd
    # scipy.stats.johnsonsu(a, b, loc, scale) in units of the rms height
    return table, {"family": family, "johnson_a": a, "johnson_b": b,
                   "johnson_loc": -mean / sd, "johnson_scale": 1.0 / sd}


# ------------------------------------------------------------------------------ measured maps
def _levelled(height) -> list:
    """The maps (a stack ``(..., y, x)`` or a list of 2-D maps), levelled by a plane unless periodic, as a list
    of 2-D arrays."""
    maps = height if isinstance(height, (list, tuple)) else [height]
    out = []
    for m in maps:
        h = level_unless_periodic(m)
        out.extend(np.asarray(h.values, dtype=float).reshape((-1, h.sizes["y"], h.sizes["x"])))
    if not all(np.all(np.isfinite(z)) for z in out):
        raise ValueError("the maps have NaN pixels; level them with rs.surface.level(height, "
                         "nan='fill') first.")
    return out


def _pooled(maps: list) -> np.ndarray:
    """Every pixel of the maps, each map standardised by its own mean and rms, sorted."""
    return np.sort(np.concatenate([((z - z.mean()) / z.std()).ravel() for z in maps]))


def _empirical_table(values: np.ndarray) -> tuple[np.ndarray, dict]:
    """The translation of a sorted sample: its quantiles at Hazen positions Φ(u) N - 1/2 where
    the data reach; beyond, a line in u through the outermost quantile whose slope is fitted to
    the last unit of u of the data (at most its outer 1 %) on each side."""
    n = values.size
    position = special.ndtr(SCORE) * n - 0.5
    inside = (position >= 0) & (position <= n - 1)
    table = np.interp(position, np.arange(n), values)
    u_data = float(special.ndtri(1 - 0.5 / n))
    u_fit = max(float(special.ndtri(0.99)), u_data - 1.0)
    for side in (1, -1):
        grid = side * SCORE
        fit = inside & (grid >= min(u_fit, u_data - 0.5))
        slope = max(np.polyfit(grid[fit], side * table[fit], 1)[0], 0.0)
        edge = np.flatnonzero(inside & (grid > 0))[np.argmax(grid[inside & (grid > 0)])]
        out = ~inside & (grid > 0)
        table[out] = table[edge] + side * slope * (grid[out] - grid[edge])
    # the sample quantile function of correlated pixels is noisy on small scales of u; that
    # noise would become white noise in generated surfaces (a translation's slope is their
    # high-q gain): smoothed over SMOOTHING in u, which leaves the linear tails as they are
    pad = int(np.ceil(6 * SMOOTHING / (SCORE[1] - SCORE[0])))
    wide = evaluate(table, SCORE[0] + (SCORE[1] - SCORE[0]) * np.arange(-pad, SCORE.size + pad))
    table = ndimage.gaussian_filter1d(wide, SMOOTHING / (SCORE[1] - SCORE[0]), mode="nearest")[pad:-pad]
    return table, {"family": "empirical", "data_normal_score": u_data, "smoothing_normal_score": SMOOTHING}


@check_numbers(skewness="finite?", kurtosis="positive?")
def height_distribution(height=None, *, skewness=None, kurtosis=None, rms=None) -> xr.Dataset:
    r"""A height distribution to impose on generated surfaces: measured or Johnson.

    From measured maps: their empirical distribution (the maps levelled by a least-squares plane
    unless periodic,
    each standardised by its own mean and rms, pooled). From moments: the Johnson :math:`S_U` or
    :math:`S_B` distribution with that ``skewness`` and ``kurtosis`` (Johnson 1949), or the
    Gaussian for (0, 3). Either way the distribution is held as its translation
    :math:`T(u) = F^{-1}(\Phi(u))` from a standard normal score (module docstring) in units of
    the rms height.

    Parameters
    ----------
    height : xarray.DataArray or list of xarray.DataArray, optional
        Measured height maps ``(..., y, x)``, or a list of maps of any sizes; every map is
        pooled.
    skewness, kurtosis : float, optional
        Third and fourth standardised moments (kurtosis 3 for a Gaussian, not the excess);
        instead of ``height``.
    rms : float or str, optional
        Rms height [m] (or ``"4 nm"``) the distribution describes; recorded, and compared with the
        PSD's by :func:`generate_surfaces` (the surfaces take the PSD's). Measured maps record
        their own.

    Returns
    -------
    xarray.Dataset
        ``height`` [1] (heights over the rms height) over ``normal_score`` :math:`u`, with
        coordinate ``probability`` :math:`\Phi(u)`; attrs ``family`` (``"empirical"``,
        ``"johnson_su"``, ``"johnson_sb"``, ``"normal"``), ``skewness``, ``kurtosis``,
        ``rms_height`` [m] (NaN when not known), and for a Johnson family ``johnson_a``,
        ``johnson_b``, ``johnson_loc``, ``johnson_scale``: ``scipy.stats.johnsonsu(a, b, loc,
        scale)`` is the distribution in units of the rms height.

    Examples
    --------
    >>> d = rs.surface.height_distribution(skewness=0.4, kurtosis=3.8, rms="4 nm")
    >>> d.attrs["family"], round(d.attrs["skewness"], 6), round(d.attrs["kurtosis"], 6)
    ('johnson_su', 0.4, 3.8)
    >>> round(float(d.height.interp(normal_score=3.09)), 2)  # the 99.9th percentile, in rms
    4.01
    """
    if (height is None) == (skewness is None and kurtosis is None):
        raise ValueError("give measured maps (height) or skewness= and kurtosis=, not both.")
    x, w = gauss_hermite()
    if height is not None:
        if rms is not None:
            raise ValueError("rms= is for a Johnson distribution; measured maps carry their own.")
        maps = _levelled(height)
        values = _pooled(maps)
        table, attrs = _empirical_table(values)
        attrs.update(n_maps=len(maps), n_pixels=int(values.size),
                     rms_height=float(np.sqrt(np.mean([z.var() for z in maps]))),
                     skewness=float(np.mean(values**3)), kurtosis=float(np.mean(values**4)))
        what = f"empirical, {len(maps)} map(s), {values.size} pixels"
    else:
        if skewness is None or kurtosis is None:
            raise ValueError("give both skewness= and kurtosis= (3 for a Gaussian).")
        table, attrs = _johnson_table(float(skewness), float(kurtosis))
        s, k = 0.0, 3.0  # the fitted law's own moments (the table is it interpolated)
        if attrs["family"] != "normal":
            _, _, s, k = standard_moments(_johnson(attrs["family"], attrs["johnson_a"],
                                                   attrs["johnson_b"], x), w)
        attrs.update(skewness=s, kurtosis=k,
                     rms_height=np.nan if rms is None else as_length(rms, name="rms"))
        what = f"{attrs['family']} with skewness {skewness:g}, kurtosis {kurtosis:g}"
    ds = xr.Dataset(
        {"height": ("normal_score", table, {"units": "1", "long_name": "height over the rms "
                                                                       "height, T(u) = F^-1(Phi(u))"})},
        coords={"normal_score": ("normal_score", SCORE, {"units": "1", "long_name": "standard "
                                                                                    "normal score u"}),
                "probability": ("normal_score", special.ndtr(SCORE),
                                {"units": "1", "long_name": "cumulative probability Phi(u)"})},
    )
    ds.attrs = dataset_attrs("height distribution of a rough surface", references=REFERENCES,
                             kind="height_distribution", **attrs)
    return append_history(ds, f"height_distribution: {what}")


def as_height_distribution(value) -> xr.Dataset:
    """Check a ``height_distribution=`` argument: a Dataset of :func:`height_distribution`."""
    if not (isinstance(value, xr.Dataset) and value.attrs.get("kind") == "height_distribution"
            and "height" in value and value["height"].dims == ("normal_score",)):
        raise TypeError(
            "height_distribution must be a Dataset of rs.surface.height_distribution(maps) or "
            f"rs.surface.height_distribution(skewness=..., kurtosis=...), got {type(value).__name__}.")
    if value.sizes["normal_score"] != SCORE.size or not np.allclose(value.normal_score, SCORE):
        raise ValueError("height_distribution's normal_score grid is not roughstick's; build it "
                         "with rs.surface.height_distribution.")
    table = np.asarray(value["height"].values, dtype=float)
    if not (np.all(np.isfinite(table)) and np.all(np.diff(table) >= 0)):
        raise ValueError("height_distribution's heights must be finite and non-decreasing in "
                         "normal_score (a quantile function).")
    return value
