r"""Beam-scale stochastic stiction: a crack front running along a cantilever on random patches (§5).

The interface under an S-shaped stuck cantilever (Fig. 18b) is cut into patches of length
``patch_length`` (the interaction-zone length :math:`\Delta s` of §5.2); each patch carries the
adhesive energy :math:`\Gamma_j` of one law drawn from a bank (:func:`build_patch_bank`). The front
(crack length :math:`s`) feels the energy release rate of the Euler-Bernoulli beam,
:math:`G(s) = \frac32 E t^3 h^2/s^4` (the derivative of the S-shape's bending energy, the
relation of Eq. 36), and moves only while that lowers the total energy
:math:`\Pi(s) = E t^3 h^2/(2s^3) - \int_s^l \Gamma`. It stops at the first local minimum in the
direction it moves, so heterogeneity pins the front and two protocols differ:

- ``"release"``: the beam is pressed down and released at each RH; the front opens from the
  clamp and stops at the first patch able to hold it (the smallest stable :math:`s`);
- ``"step_up"``: released at the first RH, then RH is raised step by step with the beam left in
  place; the front can only close towards the clamp (adhesion rises with RH) and stays pinned
  where the release protocol would have put it further out: adhesion hysteresis.

With a uniform law :math:`\Gamma_0` the front stops at :math:`s = (3Eh^2t^3/2\Gamma_0)^{1/4}`,
Eq. 36, or frees the beam when that exceeds its length.

Scope: by default (``beam_model="sharp_front"``) the patches are treated in the short-range
limit, each law reduced to its work of separation. ``beam_model="cohesive"`` resolves the finite
range of the laws instead: an Euler-Bernoulli finite-element cantilever loaded by each patch's
pressure law and released by continuation (:mod:`.cohesive`).
"""

from __future__ import annotations

from dataclasses import replace
from typing import NamedTuple

import numpy as np
import xarray as xr

from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.validate import PLAUSIBLE_BEAM_LENGTH, adhesive_energy_values, check_plausible_value
from ..ensemble.statistics import binomial_interval
from ..stiction.cantilever import PAPER_CANTILEVER, Cantilever, adhesive_energy_from_crack_length
from . import _front_kernels as K
from . import cohesive as CB

__all__ = ["crack_length", "simulate"]

#: The protocols of :func:`simulate`: a fresh release at every RH, or RH stepped up in place.
PROTOCOLS = ("release", "step_up")
#: The beam models of :func:`simulate`.
BEAM_MODELS = ("sharp_front", "cohesive")


def _check_patch_length(patch_length):
    patch_length = float(patch_length)
    if not np.isfinite(patch_length) or patch_length <= 0:
        raise ValueError(f"patch_length must be a positive length in m, got {patch_length!r}")
    if patch_length > 1e-3:
        raise ValueError(f"patch_length={patch_length!r} m is over 1 mm: pass metres, not µm")
    return patch_length


def n_patches(length, patch_length) -> int:
    """Number of patches under a beam of ``length`` (the last one may be cut short)."""
    return int(np.ceil(length / patch_length - 1e-9))


def lengths_and_patch(beam_length, patch_length, beam):
    """(beam lengths, patch length) of a run, checked: lengths positive and plausible in m, the
    patch no longer than the shortest beam (a beam holds at least one whole patch); the patch
    defaults to the beam's interaction-zone length."""
    lengths = np.atleast_1d(np.asarray(beam_length, dtype=float))
    if lengths.ndim != 1 or lengths.size == 0 or np.any(~np.isfinite(lengths)) or np.any(lengths <= 0):
        raise ValueError(f"beam_length must be positive lengths in m, got {beam_length!r}")
    check_plausible_value(lengths, name="beam_length", kind="length", bounds=PLAUSIBLE_BEAM_LENGTH,
                          what="a MEMS beam")
    patch_length = _check_patch_length(beam.interaction_zone_length if patch_length is None
                                       else patch_length)
    if patch_length > lengths.min() * (1 + 1e-9):
        raise ValueError(
            f"patch_length={patch_length:g} m is longer than the shortest beam (beam_length="
            f"{lengths.min():g} m): the interface under a beam is cut into patches of that length, "
            "so a beam shorter than one patch is not modelled. Pass a shorter patch_length (default: "
            "the beam thickness, paper §5.2) or drop the beams shorter than the patch."
        )
    return lengths, patch_length


def crack_length(patch_energy, *, beam: Cantilever = PAPER_CANTILEVER, patch_length=None,
                 start=None, protocol: str = "release"):
    r"""Crack length of cantilevers whose interface patches have the given adhesive energies.

    The per-sample function of the beam model (Eq. 36 on a heterogeneous interface): no
    randomness inside, so a rare-event sampler can call it on its own draws.

    Parameters
    ----------
    patch_energy : array-like, shape (..., n_patch)
        Adhesive energy :math:`\Gamma_j` [J m-2] of patch ``j`` counted from the clamp; at
        least ``ceil(beam.length / patch_length)`` patches (extra ones are ignored).
    beam : Cantilever
        Geometry and modulus (length, thickness, gap, E).
    patch_length : float, optional
        Patch length [m]; default the beam's interaction-zone length (its thickness).
    start : array-like, optional
        Crack length before this step [m], ``inf`` for a free beam. ``None``: fresh release.
    protocol : {"release", "step_up"}
        ``"release"`` opens the front from ``start`` (default 0, the beam pressed down);
        ``"step_up"`` lets a stuck front at ``start`` open or close to its nearest stable place.

    Returns
    -------
    numpy.ndarray, shape (...)
        Crack length :math:`s` [m]; ``inf`` where the beam is free (not stuck).

    Examples
    --------
    >>> import numpy as np
    >>> s = rs.beam.crack_length(np.full(600, 0.1))  # uniform 0.1 J m-2
    >>> round(float(s) * 1e6, 1)  # µm, Eq. 36
    112.4
    """
    if protocol not in PROTOCOLS:
        raise ValueError(f"protocol must be one of {PROTOCOLS}, got {protocol!r}")
    patch_length = _check_patch_length(beam.interaction_zone_length if patch_length is None
                                       else patch_length)
    energy = np.asarray(patch_energy, dtype=float)
    if energy.ndim == 0:
        raise ValueError("patch_energy needs a last axis of patches along the beam")
    m = n_patches(beam.length, patch_length)
    if energy.shape[-1] < m:
        raise ValueError(f"beam of {beam.length:g} m with patches of {patch_length:g} m needs "
                         f"{m} patch energies on the last axis, got {energy.shape[-1]}")
    if np.isnan(energy[..., :m]).any():
        raise ValueError("patch_energy has NaN: drop or fill the failed laws of the bank first")
    if patch_length > beam.length * (1 + 1e-9):
        raise ValueError(f"patch_length={patch_length:g} m is longer than the beam ({beam.length:g} m): "
                         "pass a patch_length of at most the beam length (default: its thickness)")
    if (~np.isfinite(energy[..., :m]) | (energy[..., :m] < 0)).any():
        raise ValueError("patch_energy must be finite and >= 0 (adhesive energies in J m-2)")
    lead = energy.shape[:-1]
    flat = energy[..., :m].reshape(-1, m)
    st = np.zeros(flat.shape[0]) if start is None else \
        np.broadcast_to(np.asarray(start, dtype=float), lead).reshape(-1)
    kterm = beam.stiffness_term
    s = K.open_front(flat, kterm, patch_length, beam.length, st)
    if protocol == "step_up":
        s = K.close_front(flat, kterm, patch_length, beam.length, s)
    return s.reshape(lead)


def _draw_indices(seed, realizations, n_law, n_patch):
    """Law index of every patch; one SeedSequence child per realization (chunk-independent)."""
    out = np.empty((len(realizations), n_patch), dtype=np.int64)
    for i, r in enumerate(realizations):
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(int(r),)))
        out[i] = rng.integers(0, n_law, size=n_patch)
    return out


@renamed_keywords(n_realization="n", model="beam_model")
@check_numbers(n="count", seed="seed", shape_points="count0", element_size="length")
def simulate(bank: xr.DataArray, *, beam_length, n: int = 100, seed: int = 0,
             protocol: str = "release", beam: Cantilever = PAPER_CANTILEVER,
             patch_length=None, realizations=None, shape_points: int = 0,
             beam_model: str = "sharp_front", element_size: float = 0.5e-6,
             law_kwargs=None) -> xr.Dataset:
    r"""Monte-Carlo cantilevers on random patches drawn from a bank of patch laws.

    Parameters
    ----------
    bank : xarray.DataArray
        Adhesive energy over ``(law, rh)`` (:func:`build_patch_bank`, or any DataArray with
        those dims), in its ``units`` (J m-2 without them). Law ``k`` is one surface patch at
        every RH, so a patch keeps its identity when RH changes. NaN, negative or infinite
        energies are refused, and so are energies above 0.5 J m-2, more than a water meniscus
        holds (mJ m-2 labelled J m-2). With ``beam_model="cohesive"`` also a pressure bank [Pa]
        over ``(law, rh, gap)`` (:func:`pressure_law_bank`).
    beam_length : float or sequence
        Beam lengths [m], 1 µm to 10 mm (a value outside, e.g. 300 meant as µm, is refused as
        a unit slip); all lengths share the patches of a realization (common random numbers),
        counted from the clamp.
    n : int
        Number of beams per length, >= 1 (ignored when ``realizations`` is given).
    seed : int
        Root seed; realization ``r`` draws from ``SeedSequence(seed, spawn_key=(r,))``, so any
        subset/chunking of realizations gives bit-identical beams.
    protocol : {"release", "step_up"}
        Fresh release at every RH, or release at the first RH and RH stepped up in the order of
        the ``rh`` coordinate (which must then increase).
    beam : Cantilever
        Thickness, gap, width and modulus (its length is replaced by ``beam_length``).
    patch_length : float, optional
        Patch length [m], default the beam thickness (§5.2); at most the shortest beam.
    realizations : sequence of int, optional
        Realization numbers to simulate (for chunked / distributed runs).
    shape_points : int
        If > 0, also return the deflection ``shape`` [m] on that many points of ``x/l``
        (the S-shape of the crack length; sharp-front shape for both models).
    beam_model : {"sharp_front", "cohesive"}
        Sharp front on each patch's work of separation (fast, default) or the Euler-Bernoulli
        beam on each patch's pressure law (:func:`release_cohesive`; an energy bank gets the
        short-range law shape of :func:`short_range_pressure_law`). Both draw the same patches
        for the same seed. With ``"cohesive"``, ``"step_up"`` carries each beam's deflection
        from one RH to the next (:func:`step_cohesive`).
    element_size : float
        Largest finite element [m] of the cohesive model.
    law_kwargs : dict, optional
        Keywords of :func:`short_range_pressure_law` for an energy bank (cohesive).

    Returns
    -------
    xarray.Dataset
        Over ``(realization, rh, beam_length)``: ``crack_length`` [m] (NaN when free or not
        solved), ``stuck`` (bool), ``solver_failed`` (bool: the cohesive release could not be
        followed; such beams are excluded from the trials of P(stuck), ``n_solved``),
        ``apparent_adhesive_energy`` [J m-2] from Eq. 36; ``stuck_probability`` with its 95 %
        Wilson interval over ``(rh, beam_length)``; optional ``shape``.

    Examples
    --------
    >>> bank = xr.DataArray([[1e-3], [2e-2]], dims=("law", "rh"), coords={"rh": [0.5]},
    ...                     attrs={"units": "J m-2"})
    >>> beams = rs.beam.simulate(bank, beam_length=[150e-6, 170e-6, 180e-6], n=50, seed=1)
    >>> beams.stuck_probability.values  # over (rh, beam_length)
    array([[0.  , 0.5 , 0.96]])
    """
    if beam_model not in BEAM_MODELS:
        raise ValueError(f"beam_model must be one of {BEAM_MODELS}, got {beam_model!r}")
    if beam_model == "cohesive":
        return _simulate_cohesive(bank, beam_length=beam_length, n=n, seed=seed, protocol=protocol,
                                  beam=beam, patch_length=patch_length, realizations=realizations,
                                  shape_points=shape_points, element_size=element_size,
                                  law_kwargs=law_kwargs or {})
    if protocol not in PROTOCOLS:
        raise ValueError(f"protocol must be one of {PROTOCOLS}, got {protocol!r}")
    if set(bank.dims) != {"law", "rh"}:
        raise ValueError(f"bank must have dims ('law', 'rh'), got {bank.dims}")
    bank = bank.transpose("law", "rh")
    axes = _run_axes(bank, beam_length, n, protocol, beam, patch_length, realizations)
    energy_bank = adhesive_energy_values(bank)
    idx = _draw_indices(seed, axes.realizations, energy_bank.shape[0],
                        n_patches(axes.lengths.max(), axes.patch_length))
    s = np.empty((len(axes.realizations), len(axes.rh), len(axes.lengths)))
    for b, length in enumerate(axes.lengths):
        geom = replace(beam, length=float(length))
        prev = None
        for k in range(len(axes.rh)):
            gam = energy_bank[idx, k]
            if protocol == "release" or prev is None:
                s[:, k, b] = crack_length(gam, beam=geom, patch_length=axes.patch_length)
            else:
                s[:, k, b] = crack_length(gam, beam=geom, patch_length=axes.patch_length,
                                          start=prev, protocol="step_up")
            prev = s[:, k, b]
    return _dataset(s, axes, beam, protocol=protocol, seed=seed, shape_points=shape_points)


class _Axes(NamedTuple):
    """The axes of a run: humidities, beam lengths, patch length, realization indices."""

    rh: np.ndarray
    lengths: np.ndarray
    patch_length: float
    realizations: np.ndarray


def _run_axes(bank, beam_length, n, protocol, beam, patch_length, realizations) -> _Axes:
    """The :class:`_Axes` of a run, checked."""
    rh = bank["rh"].values if "rh" in bank.coords else np.arange(bank.sizes["rh"])
    if protocol == "step_up" and np.any(np.diff(rh) <= 0):
        raise ValueError("protocol='step_up' needs the bank's rh coordinate increasing")
    lengths, patch_length = lengths_and_patch(beam_length, patch_length, beam)
    reals = np.arange(int(n)) if realizations is None else np.asarray(realizations, dtype=np.int64)
    if reals.ndim != 1 or reals.size == 0:
        raise ValueError(f"realizations must be a non-empty 1-D list of indices, got {realizations!r}; "
                         "or pass n=100")
    return _Axes(rh, lengths, patch_length, reals)


def _simulate_cohesive(bank, *, beam_length, n, seed, protocol, beam, patch_length,
                       realizations, shape_points, element_size, law_kwargs):
    if protocol not in PROTOCOLS:
        raise ValueError(f"protocol must be one of {PROTOCOLS}, got {protocol!r}")
    if not {"law", "rh"} <= set(bank.dims):
        raise ValueError(f"bank must have dims ('law', 'rh'[, 'gap']), got {bank.dims}")
    axes = _run_axes(bank, beam_length, n, protocol, beam, patch_length, realizations)
    laws = CB.laws_by_rh(bank, **law_kwargs)
    idx = _draw_indices(seed, axes.realizations, bank.sizes["law"],
                        n_patches(axes.lengths.max(), axes.patch_length))
    s, failed, attached, arc = CB.release_many(laws, idx, axes.lengths, beam, axes.patch_length,
                                               element_size=element_size, protocol=protocol)
    ds = _dataset(s, axes, beam, protocol=protocol, seed=seed, shape_points=shape_points, failed=failed)
    dims = ("realization", "rh", "beam_length")
    ds["attached_length"] = xr.DataArray(attached, ds["stuck"].coords, dims, attrs={
        "units": "m", "long_name": "length of beam beyond the crack front (cohesive model)"})
    ds["arc"] = xr.DataArray(arc, ds["stuck"].coords, dims, attrs={
        "units": "1", "long_name": "beam left as an arc held by its tip (not counted as stuck)"})
    ds.attrs.update(model="cohesive", element_size=element_size)
    return ds


def s_shape(crack_length, gap, x):
    """Deflection below the rest position: S-shape on [0, s], flat on the pad beyond."""
    xi = np.clip(x / crack_length, 0.0, 1.0)
    return gap * (3 * xi**2 - 2 * xi**3)


def _dataset(s, axes: _Axes, beam, *, protocol, seed, shape_points, failed=None):
    coords = {"realization": axes.realizations, "rh": axes.rh, "beam_length": axes.lengths}
    dims = ("realization", "rh", "beam_length")
    failed = np.zeros(s.shape, bool) if failed is None else failed
    stuck = np.isfinite(s) & ~failed
    crack = xr.DataArray(np.where(stuck, s, np.nan), coords, dims,
                         attrs={"units": "m", "long_name": "crack length (NaN: beam free)"})
    gamma = adhesive_energy_from_crack_length(np.where(stuck, s, np.nan), beam=beam)
    ds = xr.Dataset({
        "crack_length": crack,
        "stuck": xr.DataArray(stuck, coords, dims, attrs={"units": "1", "long_name": "beam stuck to its pad"}),
        "solver_failed": xr.DataArray(failed, coords, dims, attrs={
            "units": "1", "long_name": "release not solved (excluded from the trials of P(stuck))"}),
        "apparent_adhesive_energy": xr.DataArray(
            np.asarray(gamma), coords, dims,
            attrs={"units": "J m-2", "long_name": "apparent adhesive energy from the crack length (Eq. 36)"}),
    })
    ds["rh"].attrs.update(units="1", long_name="relative humidity")
    ds["realization"].attrs.update(units="1", long_name="realization index", standard_name="realization")
    ds["beam_length"].attrs.update(units="m", long_name="beam length")
    if shape_points:
        xr_ = np.linspace(0.0, 1.0, int(shape_points))
        x = xr_[None, None, None, :] * axes.lengths[None, None, :, None]
        w = np.where(stuck[..., None], s_shape(np.where(stuck, s, 1.0)[..., None], beam.gap, x), 0.0)
        ds["shape"] = xr.DataArray(w, {**coords, "x_over_length": xr_}, dims + ("x_over_length",),
                                   attrs={"units": "m", "long_name": "deflection towards the pad"})
    ds = xr.merge([ds, stuck_probability_from_beams(ds)])
    ds.attrs.update(title="beam-scale stochastic stiction", protocol=protocol, seed=int(seed),
                    model="sharp_front",
                    patch_length=axes.patch_length, thickness=beam.thickness, gap=beam.gap,
                    youngs_modulus=beam.youngs_modulus,
                    references="paper Eq. 36, §5; Hoang et al. 2017 (beam-scale model)")
    return ds


@check_numbers(confidence="fraction")
def stuck_probability_from_beams(result: xr.Dataset, *, confidence: float = 0.95,
                                 interval: str = "wilson") -> xr.Dataset:
    """P(stuck) of simulated beams over ``realization`` with its binomial interval (Wilson by
    default): what ``roughstick.stuck_probability(beams)`` returns for :func:`simulate`'s output.

    Beams flagged ``solver_failed`` are not trials: ``n_solved`` counts the rest.
    """
    k = result["stuck"].sum("realization")
    n = result.sizes["realization"]
    if "solver_failed" in result:
        n = n - result["solver_failed"].sum("realization")
    lo, hi = binomial_interval(k, n, confidence=confidence, method=interval)
    out = xr.Dataset({"stuck_probability": k / n, "stuck_probability_lower": lo,
                      "stuck_probability_upper": hi, "n_stuck": k,
                      "n_solved": n if isinstance(n, xr.DataArray) else xr.full_like(k, n)})
    out["stuck_probability"].attrs.update(units="1", long_name="probability that the beam stays stuck")
    level = f"{100 * confidence:g} % {interval}"
    out["stuck_probability_lower"].attrs.update(units="1", long_name=f"lower bound of P(stuck), {level} interval")
    out["stuck_probability_upper"].attrs.update(units="1", long_name=f"upper bound of P(stuck), {level} interval")
    out["n_stuck"].attrs.update(units="1", long_name="number of stuck beams")
    out["n_solved"].attrs.update(units="1", long_name="beams solved (the trials of P(stuck))")
    out.attrs["n_samples"] = result.sizes["realization"]
    return out
