r"""The beam-scale limit state of subset simulation (private).

The sharp-front model of :mod:`roughstick.beam` on a bank of patch laws, driven by white noise: patch
``j`` of a beam takes law :math:`k_j = \lfloor \Phi(z_j)\,n_{law} \rfloor` (:math:`\Phi` the
standard-normal CDF), so :math:`z \sim N(0, I)` draws the laws uniformly and independently, as
:func:`roughstick.beam.simulate` does (equal in law, not the same draws for the same seed).

A front released from the clamp stops at the first patch :math:`j` whose equilibrium
:math:`s_j = (K/\Gamma_j)^{1/4}` lies before its far edge :math:`x_{j+1}`
(``roughstick.beam._front_kernels.open_front``), i.e. :math:`\Gamma_j > K/x_{j+1}^4`. So the beam is stuck
exactly when the margin :math:`R(z) = \max_j \Gamma_{k_j} x_{j+1}^4 / K` exceeds 1, and
:math:`P(\text{stuck}) = 1 - \prod_j (1 - q_j)`, :math:`q_j` the fraction of the bank's laws
with :math:`\Gamma > K/x_{j+1}^4`: the exact value on the bank, which the subset estimate is
checked against.
"""

from __future__ import annotations

import hashlib
import pathlib

import numpy as np
import xarray as xr
from scipy.special import ndtr

from .._core.conventions import append_history
from .._core.validate import adhesive_energy_values
from ..beam.sharp_front import PROTOCOLS, lengths_and_patch, n_patches
from .subset import subset_simulation

__all__: list[str] = []


def edge_weights(n_patch: int, patch_length: float, length: float, stiffness_term: float) -> np.ndarray:
    """:math:`x_{j+1}^4 / K` of the ``n_patch`` patches of a beam (the last edge at its length)."""
    hi = np.minimum((np.arange(n_patch) + 1) * patch_length, length)
    return hi**4 / stiffness_term


class BeamMargin:
    """Stuck margin :math:`R(z)` of one beam length at one RH; stuck when ``R > 1``.

    ``energy``: adhesive energy of each law of the bank [J m-2] (n_law,); ``weights``:
    :func:`edge_weights`. Picklable and thread-safe (no state changes on call).
    """

    def __init__(self, energy, weights):
        # sorted: Γ of a patch rises with its z (the same uniform law draw), so the stuck set is
        # a union of half-spaces z_j > c_j that pCN chains can explore (an unsorted bank makes
        # the response jump at every small move)
        self.energy = np.sort(np.asarray(energy, dtype=float))
        self.weights = np.ascontiguousarray(weights, dtype=float)
        if self.energy.ndim != 1 or self.energy.size == 0 or np.isnan(self.energy).any():
            raise ValueError("the bank needs at least one law and no NaN energies (bank.dropna('law'))")
        self.noise_shape = (self.weights.size,)

    def laws(self, noise) -> np.ndarray:
        n = self.energy.size
        u = ndtr(np.asarray(noise, dtype=float))
        return np.minimum((u * n).astype(np.int64), n - 1)

    def __call__(self, noise) -> float:
        return float(np.max(self.energy[self.laws(noise)] * self.weights))

    def exact(self) -> float:
        """P(R > 1) on the bank: :math:`1 - \\prod_j (1 - q_j)`."""
        q = (self.energy[None, :] * self.weights[:, None] > 1.0).mean(axis=1)
        if np.any(q >= 1.0):
            return 1.0
        return float(-np.expm1(np.sum(np.log1p(-q)))) + 0.0  # never -0.0

    def token(self) -> str:
        h = hashlib.sha256(self.energy.tobytes() + self.weights.tobytes()).hexdigest()[:16]
        return f"beam-margin/1:{h}"


_BEAM_VARS = ("failure_probability", "failure_probability_lower", "failure_probability_upper",
              "coefficient_of_variation", "au_beck_cv", "n_evaluations", "converged", "few_lineages")


def _bank_stuck_probability(bank: xr.DataArray, *, beam_length, protocol, beam, patch_length, method,
                            target_cv, max_evaluations, n_per_level, seed, confidence, output=None,
                            overwrite=False, **options) -> xr.Dataset:
    """P(stuck) of the sharp-front beam on ``bank`` by subset simulation (or crude Monte Carlo):
    one :class:`BeamMargin` per (rh, beam length), the same seed at every one (common random
    numbers), with the bank's closed form ``bank_stiction_probability`` beside each estimate."""
    if protocol not in PROTOCOLS:
        raise ValueError(f"protocol must be one of {PROTOCOLS}, got {protocol!r}")
    if set(bank.dims) != {"law", "rh"}:
        raise ValueError(f"bank must have dims ('law', 'rh') (an energy bank of build_patch_bank), got "
                         f"{bank.dims}; method={method!r} works on the sharp-front model only "
                         "(method='beam' simulates the cohesive beam on a pressure bank)")
    bank = bank.transpose("law", "rh")
    energy = adhesive_energy_values(bank)
    rh = bank["rh"].values if "rh" in bank.coords else np.arange(bank.sizes["rh"])
    if protocol == "step_up" and np.any(np.diff(rh) <= 0):
        raise ValueError("protocol='step_up' needs the bank's rh coordinate increasing")
    lengths, patch_length = lengths_and_patch(beam_length, patch_length, beam)
    kterm = beam.stiffness_term  # K does not depend on the length
    options.setdefault("scheduler", "sync")  # microseconds per beam: dask tasks would cost more
    options.setdefault("chunks", 100_000)
    rows = []
    for k in range(len(rh)):
        kk = 0 if protocol == "step_up" else k
        row = []
        for length in lengths:
            w = edge_weights(n_patches(length, patch_length), patch_length, float(length), kterm)
            margin = BeamMargin(energy[:, kk], w)
            sub = None if output is None else pathlib.Path(output) / f"rh-{rh[kk]:.4f}-l-{length * 1e6:.4g}um"
            ds = subset_simulation(margin, noise_shape=margin.noise_shape, threshold=1.0, method=method,
                                   n_per_level=n_per_level, target_cv=target_cv,
                                   max_evaluations=max_evaluations, seed=seed, confidence=confidence,
                                   output=sub, overwrite=overwrite, token=margin.token(),
                                   response_attrs={"long_name": "stuck margin max_j Gamma_j x_j+1^4 / K"},
                                   **options)
            d = ds[list(_BEAM_VARS)].drop_vars([c for c in ds.coords], errors="ignore")
            d["bank_stiction_probability"] = xr.DataArray(margin.exact(), attrs={
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
    for name in ("coefficient_of_variation", "au_beck_cv", "n_evaluations", "converged", "few_lineages"):
        res[name].attrs.setdefault("units", "1")
    if np.ndim(beam_length) == 0:
        res = res.squeeze("beam_length")
    res.attrs.update({"method": method, "protocol": protocol, "patch_length": patch_length,
                      "n_law": int(energy.shape[0]), "bank_resolution": 1.0 / energy.shape[0],
                      "target_cv": float("nan") if target_cv is None else float(target_cv),
                      "probability_model": "sharp-front beam on the patch bank (beam_model), laws drawn "
                                           "uniformly by white noise; P given the bank"})
    append_history(res, f"stuck_probability(bank, method={method!r}, protocol={protocol!r}, "
                        f"n_law={energy.shape[0]})")
    return res
