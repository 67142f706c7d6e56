r"""Cantilever beams and the risk of stiction (paper §5, Eq. 36, Table 4, Eq. 37, Figs. 18-20).

An S-shaped cantilever stuck to its landing pad (Fig. 18b) detaches at the crack length
:math:`s`; its apparent adhesive energy follows from the beam geometry (Eq. 36, per unit width):

.. math:: \Gamma = \frac{3}{2} E \frac{h^2 t^3}{s^4},
   \qquad s = \left(\frac{3 E h^2 t^3}{2\Gamma}\right)^{1/4}.

A beam of length :math:`l` cannot have a crack longer than itself: it stays stuck when the
adhesive energy of the interaction zone exceeds :math:`\Gamma_{crit} = \Gamma(s = l)`. Given a
Monte-Carlo sample of :math:`\Gamma` (one value per generated interaction-zone surface, from
:func:`roughstick.adhesion_summary`), the stiction probability is the fraction of the sample above
:math:`\Gamma_{crit}`; equivalently it is the empirical CDF of the predicted crack length at
:math:`l`. Its Monte-Carlo uncertainty is a binomial confidence interval (Wilson or
Clopper-Pearson).

The §5.2 model of the cantilever's interaction zone (an equivalent surface of roughness
:math:`\sqrt{m_{01} + m_{02}}`, Table 4 moments, the self-affine PSD of Eq. 37, a rectangular
domain :math:`\Delta s \times w`) is :func:`cantilever_moments`, :func:`cantilever_psd` and
:func:`predict_adhesive_energy`.

References
----------
Hoang, T.-V., Wu, L., Paquay, S., Obreja, A.C., Voicu, R.C., Müller, R., Golinval, J.-C., Noels,
L., "A probabilistic model for predicting the uncertainties of the humid stiction phenomenon on
hard materials", J. Comput. Appl. Math. 289 (2015) 173-195, doi:10.1016/j.cam.2015.02.022.

de Boer, M. P., Clews, P. J., Smith, B. K., Michalske, T. A., "Adhesion of polysilicon
microbeams in controlled humidity ambients", MRS Proc. 518 (1998), doi:10.1557/PROC-518-131.

Mastrangelo, C. H., Hsu, C. H., "Mechanical stability and adhesion of microstructures under
capillary forces. II. Experiments", J. Microelectromech. Syst. 2 (1993) 44-55,
doi:10.1109/84.232594.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ._core import constants as C
from ._core.conventions import append_history, dataset_attrs, set_attrs
from ._core.references import PAPER, cite
from ._core.units import as_si, require
from ._core.validate import check_positive_block, positive

__all__ = [
    "Cantilever",
    "PAPER_CANTILEVER",
    "adhesive_energy_from_crack_length",
    "crack_length_from_adhesive_energy",
    "critical_adhesive_energy",
    "binomial_interval",
    "stiction_probability",
    "crossing_humidity",
    "crossing_length",
    "measured_adhesion",
    "stiction_risk",
    "cantilever_moments",
    "cantilever_psd",
    "TABLE4",
    "PAPER_HUMIDITIES",
    "predict_adhesive_energy",
    "interaction_zone_shape",
    "cantilever_distance_grid",
    "interaction_zone_psd",
]

REFERENCES = cite((PAPER, "Eq. 36, Table 4, Eq. 37"), ("deboer1998", "cantilever tests"),
                  ("mastrangelo1993", "S-shaped beam energy"))


# ----------------------------------------------------------------------------- beam geometry
@dataclass(frozen=True)
class Cantilever:
    """Geometry and material of a cantilever beam over a landing pad (Fig. 18a).

    All values SI. The defaults are the beams of de Boer et al. used in paper §5.1.

    Parameters
    ----------
    length : float
        Beam length l [m] (1500 µm).
    width : float
        Beam width w [m] (30 µm); sets the width of the interaction zone.
    thickness : float
        Beam thickness t [m] (2.62 µm).
    gap : float
        Gap h between the beam's lower side and the landing pad [m] (1.9 µm).
    youngs_modulus : float
        Young's modulus E of the beam [Pa] (poly-silicon, 164 GPa).
    interaction_length : float or None
        Length :math:`\\Delta s` of the interaction zone behind the crack front [m]; None means
        the beam thickness, the paper's first approximation (§5.2).

    Examples
    --------
    >>> beam = rs.Cantilever(length=400e-6)
    >>> beam.interaction_area * 1e12  # µm², Δs × w
    78.6...
    """

    length: float = 1500e-6
    width: float = 30e-6
    thickness: float = 2.62e-6
    gap: float = 1.9e-6
    youngs_modulus: float = C.POLYSILICON_YOUNGS_MODULUS
    interaction_length: float | None = None

    def __post_init__(self):
        for name in ("length", "width", "thickness", "gap", "youngs_modulus", "interaction_length"):
            v = getattr(self, name)
            if name == "interaction_length" and v is None:
                continue
            if not (isinstance(v, (int, float, np.floating, np.integer)) and math.isfinite(v) and v > 0):
                unit = "Pa (poly-silicon: 164e9)" if name == "youngs_modulus" else "m (e.g. 2.62e-6)"
                raise ValueError(f"Cantilever.{name} must be a positive finite number in {unit}, got {v!r}.")

    @property
    def interaction_zone_length(self) -> float:
        """:math:`\\Delta s` [m]: ``interaction_length`` or, if None, the beam thickness."""
        return self.thickness if self.interaction_length is None else self.interaction_length

    @property
    def interaction_area(self) -> float:
        """Area :math:`\\Delta s \\times w` of the interaction zone [m²]."""
        return self.interaction_zone_length * self.width

    @property
    def stiffness_term(self) -> float:
        """:math:`\\tfrac{3}{2} E h^2 t^3` [J m² = N m²], so that Γ = stiffness_term / s⁴."""
        return 1.5 * self.youngs_modulus * self.gap**2 * self.thickness**3

    def attrs(self) -> dict:
        """The beam parameters as NetCDF-friendly attributes (SI floats)."""
        return {
            "beam_width": self.width,
            "beam_thickness": self.thickness,
            "beam_gap": self.gap,
            "beam_youngs_modulus": self.youngs_modulus,
            "beam_interaction_length": self.interaction_zone_length,
        }


#: The cantilevers of paper §5.1 (de Boer et al.): w = 30 µm, t = 2.62 µm, l = 1500 µm,
#: h = 1.9 µm, E = 164 GPa.
PAPER_CANTILEVER = Cantilever()


# ----------------------------------------------------------------------------- Eq. 36
_MAGNITUDES = "Adhesive energies and crack lengths are magnitudes in SI units (J m-2, m)."


def _nonnegative(value, kind, name):
    """``value`` in SI, checked >= 0 (NaN allowed: it propagates). Lazy data are checked lazily."""
    if isinstance(value, xr.Dataset):
        key = {"energy_per_area": "adhesive_energy", "length": "crack_length"}[kind]
        if key not in value:
            raise ValueError(
                f"{name}: the Dataset has no {key!r} variable (has {list(value.data_vars)}). "
                f"Pass the DataArray, e.g. ds[{key!r}]."
            )
        value = value[key]
    return positive(value, kind, name, _MAGNITUDES, allow_zero=True, arrays=True)


def adhesive_energy_from_crack_length(crack_length, *, beam: Cantilever = PAPER_CANTILEVER):
    r"""Apparent adhesive energy of an S-shaped stuck cantilever from its crack length (Eq. 36).

    Parameters
    ----------
    crack_length : float, array or xarray.DataArray
        Crack length :math:`s` (Fig. 18b): distance from the anchor to where the beam lands;
        SI metres, or a DataArray with length ``units`` (µm, nm, ... are converted).
    beam : Cantilever
        Beam thickness, gap and modulus (the length is not used).

    Returns
    -------
    float, numpy.ndarray or xarray.DataArray
        :math:`\Gamma` [J m-2], the same kind as the input (DataArrays get CF attrs).
        ``s = 0`` gives ``inf``; NaN propagates.

    Raises
    ------
    ValueError
        If a crack length is negative.

    Notes
    -----
    .. math:: \Gamma = \frac{3}{2} E \frac{h^2 t^3}{s^4}

    Euler-Bernoulli beam, clamped at the anchor, S-shaped (zero slope where it lands), small
    deflection; valid for :math:`s \gg t` and :math:`h \ll s`.

    References
    ----------
    Mastrangelo and Hsu (1993), doi:10.1109/84.232594; paper Eq. 36.

    Examples
    --------
    >>> round(rs.adhesive_energy_from_crack_length(1500e-6) * 1e6, 3)  # µJ m-2, s = l = 1500 µm
    3.155
    """
    s = _nonnegative(crack_length, "length", "crack_length")
    if not isinstance(s, xr.DataArray):
        s = np.float64(s) if np.ndim(s) == 0 else s
    with np.errstate(divide="ignore"):
        out = beam.stiffness_term / s**4
    if np.ndim(out) == 0 and not isinstance(out, xr.DataArray):
        out = float(out)
    if isinstance(out, xr.DataArray):
        out = set_attrs(out.rename("adhesive_energy"), "surface_adhesive_energy")
        out.attrs["long_name"] = "apparent adhesive energy (Eq. 36, from the crack length)"
    return out


def crack_length_from_adhesive_energy(adhesive_energy, *, beam: Cantilever = PAPER_CANTILEVER):
    r"""Crack length :math:`s` at which an S-shaped cantilever settles, from Γ (inverse of Eq. 36).

    Applied to a Monte-Carlo sample of Γ (dims ``(realization, rh)``) it gives the distribution
    of the predicted crack length.

    Parameters
    ----------
    adhesive_energy : float, array, xarray.DataArray or xarray.Dataset
        :math:`\Gamma` [J m-2] (a Dataset must hold ``adhesive_energy``, e.g. the output of
        :func:`roughstick.adhesion_summary`). DataArrays need ``units`` (``J m-2``).
    beam : Cantilever
        Beam thickness, gap and modulus.

    Returns
    -------
    float, numpy.ndarray or xarray.DataArray
        :math:`s` [m]; ``Γ = 0`` (no adhesion) gives ``inf``: such a beam is free at any length.

    Raises
    ------
    ValueError
        If an adhesive energy is negative.

    Notes
    -----
    .. math:: s = \left(\frac{3 E h^2 t^3}{2\Gamma}\right)^{1/4}

    Examples
    --------
    >>> round(rs.crack_length_from_adhesive_energy(1e-3) * 1e6, 1)  # µm, Γ = 1 mJ m-2
    355.5
    """
    g = _nonnegative(adhesive_energy, "energy_per_area", "adhesive_energy")
    if not isinstance(g, xr.DataArray):
        g = np.float64(g) if np.ndim(g) == 0 else g
    with np.errstate(divide="ignore"):
        out = (beam.stiffness_term / g) ** 0.25
    if np.ndim(out) == 0 and not isinstance(out, xr.DataArray):
        out = float(out)
    if isinstance(out, xr.DataArray):
        out = set_attrs(out.rename("crack_length"), "crack_length")
    return out


def _beam_lengths(length, beam: Cantilever):
    """Beam length(s) as float or a DataArray along ``beam_length`` (SI, validated > 0)."""
    if length is None:
        return beam.length
    if isinstance(length, xr.DataArray):
        v = require(length, "length", name="length")
        if v.chunks is not None:
            raise ValueError("beam lengths must be in memory (they are coordinates): pass length.compute().")
    else:
        arr = np.asarray(as_si(length, "length", name="length"), dtype=float)
        if arr.ndim == 0:
            v = float(arr)
        elif arr.ndim == 1:
            v = xr.DataArray(arr, dims=("beam_length",), coords={"beam_length": arr})
        else:
            raise ValueError(f"length must be a scalar or a 1-D sequence of beam lengths [m], got shape {arr.shape}.")
    data = v.data if isinstance(v, xr.DataArray) else v
    if not isinstance(data, np.ndarray | float) or np.any(~(np.asarray(data) > 0)) or np.any(~np.isfinite(data)):
        raise ValueError(f"beam lengths must be positive finite numbers in m (e.g. 400e-6), got {length!r}.")
    if isinstance(v, xr.DataArray):
        v = set_attrs(v.rename("beam_length"), "beam_length")
    else:
        v = float(v)
    return v


def critical_adhesive_energy(*, length=None, beam: Cantilever = PAPER_CANTILEVER):
    r"""Adhesive energy above which a beam of length :math:`l` stays stuck: Eq. 36 at :math:`s = l`.

    Parameters
    ----------
    length : float, sequence or xarray.DataArray, optional
        Beam length(s) [m]; default ``beam.length``. A sequence gives a ``beam_length`` dimension.
    beam : Cantilever
        Beam thickness, gap and modulus.

    Returns
    -------
    float or xarray.DataArray
        :math:`\Gamma_{crit} = \tfrac32 E h^2 t^3 / l^4` [J m-2].

    Examples
    --------
    >>> g = rs.critical_adhesive_energy(length=[250e-6, 500e-6, 1500e-6])
    >>> (g.values * 1e6).round(3)  # µJ m-2
    array([4.088708e+03, 2.555440e+02, 3.155000e+00])
    """
    lengths = _beam_lengths(length, beam)
    out = beam.stiffness_term / lengths**4
    if isinstance(out, xr.DataArray):
        out = set_attrs(out.rename("critical_adhesive_energy"), "critical_adhesive_energy")
    return out


# ----------------------------------------------------------------------------- binomial CI
def _interval_kernel(k, n, confidence, method):
    from scipy import special, stats

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


_METHODS = {"wilson": "wilson", "clopper-pearson": "clopper-pearson", "exact": "clopper-pearson"}


def _check_interval_args(confidence, method):
    if not (isinstance(confidence, float | int) and 0 < confidence < 1):
        raise ValueError(f"confidence must lie strictly between 0 and 1 (e.g. 0.95), got {confidence!r}.")
    if method not in _METHODS:
        raise ValueError(f"interval must be 'wilson' or 'clopper-pearson' (alias 'exact'), got {method!r}.")
    return _METHODS[method]


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
    >>> lo, hi = rs.binomial_interval(3, 20)
    >>> round(float(lo), 4), round(float(hi), 4)
    (0.0524, 0.3604)
    """
    method = _check_interval_args(confidence, method)
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


# ----------------------------------------------------------------------------- stiction probability
def _gamma_sample(adhesive_energy, dim):
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


def stiction_probability(
    adhesive_energy,
    *,
    length=None,
    beam: Cantilever = PAPER_CANTILEVER,
    dim: str = "realization",
    confidence: float = 0.95,
    interval: str = "wilson",
) -> xr.Dataset:
    r"""Probability that a cantilever stays stuck, :math:`P(\Gamma > \Gamma_{crit}(l))`, with its
    Monte-Carlo confidence interval.

    Parameters
    ----------
    adhesive_energy : xarray.DataArray or xarray.Dataset
        Monte-Carlo sample of the interaction-zone adhesive energy :math:`\Gamma` [J m-2] along
        ``dim`` (e.g. ``adhesion_summary(curves)``, dims ``(realization, rh)``). NaN members are
        left out of both counts (``n_samples`` records how many were used).
    length : float, sequence or xarray.DataArray, optional
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
    >>> g = xr.DataArray([1e-4, 5e-4, 2e-3, 8e-3], dims="realization", attrs={"units": "J m-2"})
    >>> p = rs.stiction_probability(g, length=[200e-6, 400e-6, 800e-6])
    >>> p.stiction_probability.values
    array([0. , 0.5, 1. ])
    """
    _check_interval_args(confidence, interval)
    g = _gamma_sample(adhesive_energy, dim)
    gcrit = critical_adhesive_energy(length=length, beam=beam)
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
    lengths = _beam_lengths(length, beam)
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
            interval_method=_METHODS[interval],
            sample_dimension=dim,
            **beam.attrs(),
        )
    )
    if not isinstance(lengths, xr.DataArray):
        ds.attrs["beam_length"] = float(lengths)
    append_history(ds, f"roughstick.stiction_probability(dim={dim!r}, confidence={confidence}, interval={interval!r})")
    return ds


# ----------------------------------------------------------------------------- crossings
def _first_crossing_kernel(p, coord, level):
    """First upward crossing of ``level`` along the last axis, linear interpolation.

    -inf: already >= level at the first grid point; +inf: never reaches it; NaN: NaN data.
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
        res[i] = c[j - 1] + (level - p0) / (p1 - p0) * (c[j] - c[j - 1])
    return out


def crossing_humidity(probability: xr.Dataset | xr.DataArray, *, level: float = 0.5) -> xr.Dataset:
    r"""Relative humidity at which the stiction probability first reaches ``level``.

    Parameters
    ----------
    probability : xarray.Dataset or xarray.DataArray
        Output of :func:`stiction_probability` (with an ``rh`` dimension), or a DataArray of
        probabilities over ``rh``. With the Dataset, the interval bounds give the interval of the
        crossing.
    level : float
        Probability level in (0, 1), e.g. 0.01 for "1 % of beams stuck".

    Returns
    -------
    xarray.Dataset
        ``crossing_humidity`` (from the estimate) and, for a Dataset input,
        ``crossing_humidity_lower`` (where the upper bound of the probability crosses) and
        ``crossing_humidity_upper`` (where the lower bound crosses), over the remaining dims
        (e.g. ``beam_length``). Linear interpolation between grid humidities; ``-inf`` means the
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
    >>> float(rs.crossing_humidity(p, level=0.5).crossing_humidity)
    0.475
    """
    if not 0 < level < 1:
        raise ValueError(f"level must be a probability strictly between 0 and 1, got {level!r}.")
    if isinstance(probability, xr.Dataset):
        pairs = {
            "crossing_humidity": probability["stiction_probability"],
            "crossing_humidity_lower": probability["stiction_probability_upper"],
            "crossing_humidity_upper": probability["stiction_probability_lower"],
        }
    else:
        pairs = {"crossing_humidity": probability}
    out = {}
    for name, p in pairs.items():
        if "rh" not in p.dims:
            raise ValueError(f"the stiction probability has no 'rh' dimension (dims {p.dims}); compute it on an RH sweep.")
        rh = np.asarray(p["rh"].values, dtype=float)
        if rh.size > 1 and np.any(np.diff(rh) <= 0):
            raise ValueError("the 'rh' coordinate must be strictly increasing; sort first: .sortby('rh').")
        from ._core.validate import check_core_not_chunked

        check_core_not_chunked(p, ["rh"])
        da = xr.apply_ufunc(
            _first_crossing_kernel,
            p,
            kwargs={"coord": rh, "level": float(level)},
            input_core_dims=[["rh"]],
            dask="parallelized",
            output_dtypes=[float],
        )
        out[name] = set_attrs(da, "crossing_humidity")
    if len(out) == 3:
        out["crossing_humidity_lower"].attrs["long_name"] += " (from the upper probability bound)"
        out["crossing_humidity_upper"].attrs["long_name"] += " (from the lower probability bound)"
    ds = xr.Dataset(out)
    ds.attrs = dict(probability.attrs) if isinstance(probability, xr.Dataset) else {}
    ds.attrs["probability_level"] = float(level)
    append_history(ds, f"roughstick.crossing_humidity(level={level})")
    return ds


def _quantile_ranks(n, p, confidence):
    """1-based order-statistic ranks (r, u) with P(s_(r) <= q_p <= s_(u)) >= confidence."""
    from scipy import stats

    a = (1 - confidence) / 2
    r = int(stats.binom.ppf(a, n, p))  # P(B <= r-1) <= a  -> rank r
    u = int(stats.binom.ppf(1 - a, n, p)) + 1
    return r, u


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
        r, u = _quantile_ranks(n, p, confidence)
        res[i, 1] = row[r - 1] if r >= 1 else 0.0
        res[i, 2] = row[u - 1] if u <= n else np.inf
    return out


def crossing_length(
    adhesive_energy,
    *,
    level: float = 0.5,
    beam: Cantilever = PAPER_CANTILEVER,
    dim: str = "realization",
    confidence: float = 0.95,
) -> xr.Dataset:
    r"""Beam length above which the stiction probability reaches ``level``.

    Because :math:`P(\text{stuck} \mid l) = P(s < l)`, this is the ``level``-quantile of the
    predicted crack length :math:`s` (Eq. 36 applied to the sample of Γ).

    Parameters
    ----------
    adhesive_energy : xarray.DataArray or xarray.Dataset
        Monte-Carlo sample of Γ [J m-2] along ``dim``; NaN members are left out.
    level : float
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
        empirical stiction probability, for any longer beam, is at least ``level``;
        ``crossing_length_lower`` / ``_upper``: the order statistics
        :math:`[s_{(r)}, s_{(u)}]` bracketing the true quantile with probability >= ``confidence``
        (binomial ranks; 0 or ``inf`` when the sample is too small to bound that side).

    Examples
    --------
    >>> g = xr.DataArray([1e-4, 5e-4, 2e-3, 8e-3], dims="realization", attrs={"units": "J m-2"})
    >>> round(float(rs.crossing_length(g, level=0.5).crossing_length) * 1e6, 1)  # µm
    298.9
    """
    if not 0 < level < 1:
        raise ValueError(f"level must be a probability strictly between 0 and 1, got {level!r}.")
    _check_interval_args(confidence, "wilson")
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
    append_history(ds, f"roughstick.crossing_length(level={level}, dim={dim!r})")
    return ds


# ----------------------------------------------------------------------------- measured points
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
    >>> m = rs.measured_adhesion([0.5, 0.7], crack_length=[400e-6, 350e-6])
    >>> (m.adhesive_energy.values * 1e3).round(3)  # mJ m-2
    array([0.624, 1.064])
    """
    from .contact.meniscus import as_relative_humidity

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
    append_history(ds, f"roughstick.measured_adhesion: {rh.size} points, {given} given")
    return ds


# ----------------------------------------------------------------------------- all in one
def stiction_risk(
    adhesive_energy,
    *,
    length=None,
    beam: Cantilever = PAPER_CANTILEVER,
    levels=(0.05, 0.5, 0.95),
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
    length : float, sequence or xarray.DataArray, optional
        Beam lengths [m] (``beam_length`` dimension); default ``beam.length``.
    beam : Cantilever
        Beam geometry and modulus.
    levels : sequence of float
        Probability levels for the crossing humidity and length (``probability_level`` dim).
    dim, confidence, interval
        See :func:`stiction_probability`.
    quantiles : sequence of float
        Quantiles of Γ and of the crack length to report (default: the 95 % band and median).

    Returns
    -------
    xarray.Dataset
        The variables of :func:`stiction_probability`; ``crossing_humidity`` (+ ``_lower``,
        ``_upper``) over ``(probability_level, beam_length)`` when there is an ``rh`` dim;
        ``crossing_length`` (+ bounds) over ``(probability_level, ...)``;
        ``adhesive_energy_quantile`` and ``crack_length_quantile`` over ``(quantile, ...)``;
        ``adhesive_energy_mean``.

    Examples
    --------
    >>> g = xr.DataArray([[1e-4, 2e-4], [5e-4, 1e-3], [2e-3, 4e-3]], dims=("realization", "rh"),
    ...                  coords={"rh": [0.4, 0.8]}, attrs={"units": "J m-2"})
    >>> r = rs.stiction_risk(g, length=[300e-6, 600e-6], levels=[0.5])
    >>> r.stiction_probability.transpose("beam_length", "rh").values.round(3)
    array([[0.333, 0.333],
           [0.667, 1.   ]])
    """
    levels = [float(v) for v in np.atleast_1d(levels)]
    for v in levels:
        if not 0 < v < 1:
            raise ValueError(f"levels must be probabilities strictly between 0 and 1, got {v!r}.")
    g = _gamma_sample(adhesive_energy, dim)
    ds = stiction_probability(g, length=length, beam=beam, dim=dim, confidence=confidence, interval=interval)
    lev = xr.DataArray(levels, dims="probability_level", coords={"probability_level": levels})
    lev = set_attrs(lev, "probability_level")
    parts = [crossing_length(g, level=v, beam=beam, dim=dim, confidence=confidence) for v in levels]
    cl = xr.concat([p[list(p.data_vars)] for p in parts], dim=lev)
    for k in cl.data_vars:
        ds[k] = cl[k]
    if "rh" in ds.dims:
        parts = [crossing_humidity(ds, level=v) for v in levels]
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
    append_history(ds, f"roughstick.stiction_risk(levels={levels}, quantiles={qs})")
    return ds


# ----------------------------------------------------------------------------- §5.2 model
#: Table 4 of the paper: roughness of the two surfaces [m], mean asperity radius of the
#: equivalent surface [m], asperity density [m-2]; and the Eq. 37 cutoff of §4.1 [rad m-1].
TABLE4 = {"roughness": (2.6e-9, 2.4e-9), "asperity_radius": 220e-9, "asperity_density": 80.1e12,
          "qmax": 289e6}

_PRINTED_NOTE = (
    "The paper prints q0 = 19.4 rad/um, s0 = 6.46e3 nm^4, s1 = 6.29e-3 nm^4 for Eq. 37; solving "
    "Eq. 37 with Table 4 (N = 80.1 um^-2) gives q0 ~ 21.2 rad/um, s0 ~ 5.5e3 nm^4, "
    "s1 ~ 5.5e-3 nm^4. The printed values follow from N = 88.1 um^-2 (likely a typo in Table 4)."
)


def cantilever_moments(
    *,
    roughness=TABLE4["roughness"],
    asperity_radius: float = TABLE4["asperity_radius"],
    asperity_density: float = TABLE4["asperity_density"],
) -> xr.Dataset:
    r"""PSD moments of the equivalent surface of the cantilever tests (Table 4).

    Two rough surfaces in contact are replaced by their sum against a flat (paper §5.2), so the
    variances add: :math:`\mu_0 = m_{01} + m_{02}` (3.54 nm from 2.6 and 2.4 nm). With Nayak's
    relations, :math:`\mu_4 = (3\sqrt\pi/(8R))^2` and :math:`\mu_2 = \mu_4/(6\sqrt3\pi N)`.
    Thin wrapper over :func:`roughstick.moments_from_asperities` with the Table 4 defaults.

    Parameters
    ----------
    roughness : sequence of float
        RMS roughness of each surface [m] (Table 4: 2.6 and 2.4 nm).
    asperity_radius : float
        Mean asperity radius of the equivalent surface [m] (220 nm: 440 nm per surface).
    asperity_density : float
        Asperity density of the equivalent surface [m-2] (80.1 µm⁻²).

    Returns
    -------
    xarray.Dataset
        ``m0`` [m2], ``m2`` [1], ``m4`` [m-2].

    Examples
    --------
    >>> m = rs.cantilever_moments()
    >>> round(float(m.m0) ** 0.5 * 1e9, 2), round(float(m.m2), 4), round(float(m.m4) / 1e12, 2)
    (3.54, 0.0035, 9.13)
    """
    from .surface.moments import moments_from_asperities

    return moments_from_asperities(roughness=roughness, radius=asperity_radius, density=asperity_density)


def cantilever_psd(
    *,
    roughness=TABLE4["roughness"],
    asperity_radius: float = TABLE4["asperity_radius"],
    asperity_density: float = TABLE4["asperity_density"],
    qmax: float = TABLE4["qmax"],
) -> xr.Dataset:
    r"""The self-affine PSD (Eq. 37) of the cantilever's equivalent surface, from Table 4.

    Parameters
    ----------
    roughness, asperity_radius, asperity_density
        See :func:`cantilever_moments`.
    qmax : float
        Cutoff wave number of Eq. 37 [rad m-1]; the paper takes 289 rad/µm from its samples.

    Returns
    -------
    xarray.Dataset
        The Eq. 37 parameters ``q0``, ``s0``, ``s1``, ``qmax``, ``exponent`` and the fit residuals
        (:func:`roughstick.fit_self_affine`), plus the target moments ``m0``, ``m2``, ``m4``.
        Evaluate the PSD with ``rs.self_affine_psd(q, s0=ds.s0, s1=ds.s1, q0=ds.q0, qmax=ds.qmax)``.

    Notes
    -----
    With Table 4 (N = 80.1 µm⁻²) the solution is :math:`\xi_0 \approx 21.2` rad/µm,
    :math:`s_0 \approx 5.5\times10^3` nm⁴, :math:`s_1 \approx 5.5\times10^{-3}` nm⁴. The paper
    prints 19.4 rad/µm, 6.46e3 nm⁴ and 6.29e-3 nm⁴, which come out with N = 88.1 µm⁻²
    (``asperity_density=88.1e12``); the attribute ``note`` records this.

    Examples
    --------
    >>> p = rs.cantilever_psd()
    >>> round(float(p.q0) / 1e6, 1), round(float(p.s0) * 1e36, -2), round(float(p.s1) * 1e39, 1)
    (21.2, 5500.0, 5.5)
    """
    from .surface.self_affine import fit_self_affine

    m = cantilever_moments(roughness=roughness, asperity_radius=asperity_radius,
                           asperity_density=asperity_density)
    fit = fit_self_affine(m0=m.m0, m2=m.m2, m4=m.m4, qmax=qmax)
    ds = xr.merge([fit, m[["m0", "m2", "m4"]]], combine_attrs="override")
    ds.attrs.update(
        dataset_attrs(
            "Eq. 37 PSD of the cantilever's equivalent surface (Table 4)",
            references=REFERENCES,
            roughness=list(np.atleast_1d(np.asarray(roughness, dtype=float))),
            asperity_radius=float(asperity_radius),
            asperity_density=float(asperity_density),
            note=_PRINTED_NOTE,
        )
    )
    append_history(ds, "roughstick.cantilever_psd: Table 4 -> Nayak moments -> Eq. 37")
    return ds


#: Humidities of the cantilever tests (paper §5.1): 30 to 95 % in 5 % steps.
PAPER_HUMIDITIES = tuple(round(0.30 + 0.05 * i, 2) for i in range(14))


def interaction_zone_shape(beam: Cantilever = PAPER_CANTILEVER, *, spacing: float = 5e-9) -> tuple[int, int]:
    r"""Pixels ``(ny, nx)`` of the interaction zone :math:`\Delta s \times w` at ``spacing``.

    ``y`` runs along the beam (:math:`\Delta s`), ``x`` across it (:math:`w`).

    Examples
    --------
    >>> rs.interaction_zone_shape()  # 2.62 µm x 30 µm at 5 nm (paper §5.2)
    (524, 6000)
    """
    spacing = float(spacing)
    if not spacing > 0:
        raise ValueError(f"spacing must be a positive length in m (e.g. 5e-9), got {spacing!r}.")
    ny = int(round(beam.interaction_zone_length / spacing))
    nx = int(round(beam.width / spacing))
    if min(ny, nx) < 8:
        raise ValueError(
            f"the interaction zone {beam.interaction_zone_length:.3g} m x {beam.width:.3g} m has only "
            f"{ny} x {nx} pixels of {spacing:.3g} m; use a finer spacing."
        )
    return ny, nx


def interaction_zone_psd(fit: xr.Dataset | None = None, *, beam: Cantilever = PAPER_CANTILEVER,
                         spacing: float = 5e-9, shape=None) -> xr.DataArray:
    r"""The Eq. 37 PSD evaluated exactly on the wave-vector grid of the interaction zone.

    Parameters
    ----------
    fit : xarray.Dataset, optional
        Eq. 37 parameters (``q0``, ``s0``, ``s1``, ``qmax``); default :func:`cantilever_psd`.
    beam : Cantilever
        Sets the zone when ``shape`` is None (:func:`interaction_zone_shape`).
    spacing : float
        Pixel size [m].
    shape : (int, int), optional
        Pixels ``(ny, nx)``.

    Returns
    -------
    xarray.DataArray
        ``psd`` [m4] over ``(qy, qx)``, centred ascending coords (fftshift order) of the
        ``shape`` grid, so :func:`roughstick.generate_surfaces` uses it without interpolation.

    Examples
    --------
    >>> p = rs.interaction_zone_psd(shape=(64, 512))
    >>> p.sizes["qy"], p.sizes["qx"], p.attrs["units"]
    (64, 512, 'm4')
    """
    if fit is None:
        fit = cantilever_psd()
    shape = interaction_zone_shape(beam, spacing=spacing) if shape is None else shape
    return _psd_on_grid(fit, tuple(int(v) for v in np.broadcast_to(shape, 2)), spacing)


def _psd_on_grid(fit: xr.Dataset, shape, spacing) -> xr.DataArray:
    """The Eq. 37 PSD of ``fit`` evaluated exactly on the FFT grid of ``shape`` (no interpolation)."""
    from .surface.self_affine import self_affine_psd

    missing = [k for k in ("q0", "s0", "s1", "qmax") if k not in fit]
    if missing:
        raise ValueError(f"the PSD Dataset lacks the Eq. 37 parameters {missing}; pass rs.cantilever_psd(...).")
    ny, nx = shape
    qy = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(ny, spacing))
    qx = 2 * np.pi * np.fft.fftshift(np.fft.fftfreq(nx, spacing))
    qmag = xr.DataArray(np.hypot(qy[:, None], qx[None, :]), dims=("qy", "qx"),
                        coords={"qy": qy, "qx": qx}, attrs={"units": "rad m-1"})
    out = self_affine_psd(qmag, s0=float(fit.s0), s1=float(fit.s1), q0=float(fit.q0), qmax=float(fit.qmax))
    out = set_attrs(out.rename("psd"), "psd", spacing_x=float(spacing), spacing_y=float(spacing))
    return out.drop_vars([c for c in out.coords if c not in ("qx", "qy")])


def cantilever_distance_grid(psd, *, shape, n, relative_humidity, adsorbed_layer="paper",
                             lower: float = 1.0, num: int = 200) -> xr.DataArray:
    r"""Distance grid for the interaction-zone ensembles, shared by both adsorbed-layer models.

    :func:`roughstick.ensemble_distance_grid` with its top set by the larger of the water heights
    of ``adsorbed_layer`` and of the paper's layer, so the runs with and without the layer use the
    same grid (identical Γ below 65 % RH, same surfaces), and its bottom at ``lower``
    :math:`\sqrt{m_0}`.

    Notes
    -----
    Eq. 13 integrates every attractive part of the curve. On the Table 4 surface the modified
    DMT repulsion peaks near :math:`0.8\sqrt{m_0}` and falls again deeper down (asperities merge
    into a few huge, flat fitted spheres), so a grid reaching far below the equilibrium picks up a
    spurious second attractive region. ``lower = 1`` keeps the bottom in the repulsive range for
    the paper's cantilever zone (checked on 64 x 512 to 524 x 6000 pixel zones, 30-95 % RH,
    both layer models); :func:`roughstick.run_ensemble` raises if a curve is still attractive at
    the bottom, so a bad choice never passes silently.
    """
    from .ensemble import ensemble_distance_grid

    grids = [ensemble_distance_grid(psd, shape=shape, n=n, relative_humidity=relative_humidity,
                                    adsorbed_layer=layer, lower=lower, num=num)
             for layer in (adsorbed_layer, "paper")]
    return grids[int(np.argmax([float(g[-1]) for g in grids]))]


def predict_adhesive_energy(
    psd=None,
    *,
    beam: Cantilever = PAPER_CANTILEVER,
    relative_humidity=PAPER_HUMIDITIES,
    n: int = 20,
    spacing: float = 5e-9,
    shape=None,
    adsorbed_layer="paper",
    seed=0,
    chunks=None,
    output=None,
    **ensemble_kwargs,
) -> xr.Dataset:
    r"""Monte-Carlo prediction of Γ for the cantilever's interaction zone (paper §5.2, Fig. 20).

    Generates ``n`` equivalent surfaces of the interaction zone :math:`\Delta s \times w` from
    the PSD, computes their rough-surface modified-DMT curves at each humidity and reduces them
    to the apparent adhesive energy (Eq. 13), through :func:`roughstick.run_ensemble`.

    Parameters
    ----------
    psd : xarray.Dataset, xarray.DataArray or None
        ``None``: the Table 4 -> Eq. 37 PSD (:func:`cantilever_psd`); a Dataset of Eq. 37
        parameters (``q0``, ``s0``, ``s1``, ``qmax``, e.g. ``cantilever_psd(asperity_density=...)``),
        evaluated exactly on the surface's wave-vector grid; or any PSD DataArray accepted by
        :func:`roughstick.run_ensemble` (e.g. measured from AFM maps of the real films).
    beam : Cantilever
        Sets the interaction zone (``interaction_length`` x ``width``).
    relative_humidity : sequence of float
        Fractions in (0, 1); default 30 to 95 % in 5 % steps.
    n : int or "auto"
        Number of surfaces (see :func:`roughstick.run_ensemble`).
    spacing : float
        Pixel size [m] (5 nm in the paper).
    shape : (int, int), optional
        Pixels ``(ny, nx)``; default :func:`interaction_zone_shape` (524 x 6000 for the paper's
        beams at 5 nm). A smaller shape is a different interaction area (fewer, lower high
        asperities: Γ is biased up at low RH, paper §4.3 and Fig. 16a): use it only for quick looks.
    adsorbed_layer : {"paper", "none"} or callable
        ``"paper"``: 0.9 nm per surface above 65 % RH (Fig. 20b); ``"none"``: Fig. 20a.
    seed, chunks, output, **ensemble_kwargs
        Passed to :func:`roughstick.run_ensemble` (``output`` streams and resumes). The default
        ``distance`` grid is :func:`cantilever_distance_grid`.

    Returns
    -------
    xarray.Dataset
        The ensemble (lazy unless streamed); ``adhesive_energy`` over ``(realization, rh)`` is
        what :func:`stiction_risk` takes. Attrs record the beam and the interaction zone.
    """
    from .ensemble import run_ensemble

    shp = interaction_zone_shape(beam, spacing=spacing) if shape is None else tuple(int(v) for v in np.broadcast_to(shape, 2))
    if psd is None:
        psd = cantilever_psd()
    if isinstance(psd, xr.Dataset):
        missing = [k for k in ("q0", "s0", "s1", "qmax") if k not in psd]
        if missing:
            raise ValueError(f"psd Dataset lacks the Eq. 37 parameters {missing}; pass rs.cantilever_psd(...).")
        grid_psd = _psd_on_grid(psd, shp, spacing)
    elif isinstance(psd, xr.DataArray):
        grid_psd = psd
    else:
        raise TypeError(f"psd must be None, an Eq. 37 Dataset or a PSD DataArray, got {type(psd).__name__}.")
    rh = list(relative_humidity)
    if ensemble_kwargs.get("distance") is None:
        ensemble_kwargs["distance"] = cantilever_distance_grid(
            grid_psd, shape=shp, n=ensemble_kwargs.get("n_max", 3000) if n == "auto" else n,
            relative_humidity=rh, adsorbed_layer=adsorbed_layer)
    ds = run_ensemble(grid_psd, n=n, relative_humidity=rh, spacing=spacing, shape=shp,
                      seed=seed, chunks=chunks, adsorbed_layer=adsorbed_layer, output=output, **ensemble_kwargs)
    ds.attrs.update({**beam.attrs(), "interaction_zone_shape": list(shp),
                     "interaction_zone_area": float(shp[0] * shp[1] * spacing**2)})
    if isinstance(adsorbed_layer, str):
        ds.attrs["adsorbed_layer_model"] = adsorbed_layer
    append_history(ds, f"roughstick.predict_adhesive_energy: interaction zone {shp[0]} x {shp[1]} px at {spacing:.3g} m")
    return ds
