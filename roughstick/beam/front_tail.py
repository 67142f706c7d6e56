r"""P(stuck) of every beam length in closed form from one tail: the strip's Γ CCDF (paper §5).

A released sharp front (:mod:`.sharp_front`) stops at the first patch :math:`j` whose equilibrium
:math:`(K/\Gamma_j)^{1/4}` lies before the patch's far edge :math:`x_{j+1}`, i.e. where
:math:`\Gamma_j > K/x_{j+1}^4` (Eq. 36, :math:`K = \tfrac32 E t^3 h^2`, the last edge at the beam
length :math:`l`). With the patches (strips :math:`\Delta x \times w`) independent and drawn from
one distribution of complementary CDF :math:`\bar F(g) = P(\Gamma > g)`,

.. math:: P_{stuck}(l) = 1 - \prod_{j=0}^{\lceil l/\Delta x\rceil - 1}
          \bigl(1 - \bar F(K / x_{j+1}^4)\bigr),

so one CCDF gives every beam length at no further cost: :func:`adhesive_energy_ccdf` takes it
from a sample of strip energies (with a simultaneous band), :func:`stuck_probability_from_ccdf`
composes the lengths. Drawing beams on a bank (:func:`.simulate`) is the Monte-Carlo check of
the same formula.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .._core.arguments import check_numbers
from .._core.conventions import append_history
from .._core.validate import adhesive_energy_values
from ..stiction.cantilever import PAPER_CANTILEVER, Cantilever
from .sharp_front import lengths_and_patch, n_patches

__all__ = ["adhesive_energy_ccdf", "stuck_probability_from_ccdf"]


@check_numbers(confidence="fraction")
def adhesive_energy_ccdf(sample, *, dim: str = "realization", confidence: float = 0.95) -> xr.Dataset:
    r"""Empirical complementary CDF of a sample of Γ, with a simultaneous confidence band.

    :math:`\bar F_n(g) = \#\{\Gamma_i > g\}/n` at each sample value (sorted), and the
    Dvoretzky-Kiefer-Wolfowitz band :math:`\bar F_n \pm \varepsilon`,
    :math:`\varepsilon = \sqrt{\ln(2/\alpha)/(2n)}` (Massart's constant), which holds the true
    CCDF everywhere at once with probability >= ``confidence``; so does any monotone function of
    it, e.g. :func:`stuck_probability_from_ccdf`. Distribution-free, hence wide where the CCDF is
    small: a tail below about :math:`1/n` needs a tail estimate instead (a CCDF Dataset of the
    same layout from elsewhere is accepted by :func:`stuck_probability_from_ccdf`).

    Parameters
    ----------
    sample : xarray.DataArray or Dataset
        Adhesive energies [J m-2] over ``dim`` (and e.g. ``rh``); a Dataset's ``adhesive_energy``
        (:func:`roughstick.stiction.strip_adhesive_energy`, :func:`build_patch_bank`).
    dim : str
        The sample dimension (``"law"`` for a bank).
    confidence : float
        Level of the simultaneous band.

    Returns
    -------
    xarray.Dataset
        Over ``(..., rank)``: ``adhesive_energy`` [J m-2] (ascending along ``rank``),
        ``exceedance_probability`` :math:`P(\Gamma > g)` and its band ``_lower``/``_upper``;
        the CCDF below the first point is 1 (lower band :math:`1-\varepsilon`).

    Examples
    --------
    >>> g = xr.DataArray([3e-3, 1e-3, 2e-3, 2e-3], dims="realization", attrs={"units": "J m-2"})
    >>> c = rs.beam.adhesive_energy_ccdf(g)
    >>> c.adhesive_energy.values * 1e3, c.exceedance_probability.values
    (array([1., 2., 2., 3.]), array([0.75, 0.25, 0.25, 0.  ]))
    """
    if isinstance(sample, xr.Dataset):
        if "adhesive_energy" not in sample:
            raise ValueError("sample Dataset has no 'adhesive_energy'; pass the DataArray of Γ")
        sample = sample["adhesive_energy"]
    if not isinstance(sample, xr.DataArray) or dim not in sample.dims:
        raise ValueError(f"sample must be a DataArray of Γ with a {dim!r} dimension (dim= names the sample "
                         f"dimension, 'law' for a bank); got {getattr(sample, 'dims', type(sample).__name__)}")
    sample = sample.transpose(..., dim)
    values = adhesive_energy_values(sample)
    n = values.shape[-1]
    ordered = np.sort(values, axis=-1)
    # P(Γ > g) at each sorted value: the count strictly above it (ties share the last rank's value)
    above = n - np.apply_along_axis(lambda v: np.searchsorted(v, v, side="right"), -1, ordered)
    exceed = above / n
    eps = math.sqrt(math.log(2.0 / (1.0 - float(confidence))) / (2.0 * n))
    dims = tuple(d for d in sample.dims if d != dim) + ("rank",)
    coords = {k: v for k, v in sample.coords.items() if dim not in v.dims}
    coords["rank"] = np.arange(n)
    out = xr.Dataset({
        "adhesive_energy": (dims, ordered, {"units": "J m-2", "long_name": "adhesive energy (sorted sample)"}),
        "exceedance_probability": (dims, exceed, {"units": "1", "long_name": "P(adhesive energy > value)"}),
        "exceedance_probability_lower": (dims, np.clip(exceed - eps, 0, 1), {
            "units": "1", "long_name": f"lower bound of the CCDF, {100 * confidence:g} % simultaneous (DKW) band"}),
        "exceedance_probability_upper": (dims, np.clip(exceed + eps, 0, 1), {
            "units": "1", "long_name": f"upper bound of the CCDF, {100 * confidence:g} % simultaneous (DKW) band"}),
    }, coords=coords)
    out.attrs.update(n_samples=n, confidence=float(confidence), band_halfwidth=eps,
                     below_first_point_lower=max(0.0, 1.0 - eps))
    append_history(out, f"adhesive_energy_ccdf(n={n}, confidence={confidence})")
    return out


def _ccdf_at(thresholds, energy, exceed, below):
    """The step CCDF (``exceed`` at the sorted ``energy``) at ``thresholds``: the value at the
    largest point <= t, ``below`` under the first point."""
    i = np.searchsorted(energy, thresholds, side="right") - 1
    return np.where(i >= 0, exceed[np.maximum(i, 0)], below)


def _stuck(ccdf_values, t):
    """1 - prod_j (1 - C(t_j)) for the thresholds ``t`` of one beam, in log space."""
    if np.any(ccdf_values >= 1.0):
        return 1.0
    return float(-np.expm1(np.sum(np.log1p(-ccdf_values)))) + 0.0


@check_numbers(patch_length="length?")
def stuck_probability_from_ccdf(ccdf: xr.Dataset, *, beam_length, beam: Cantilever = PAPER_CANTILEVER,
                                patch_length=None) -> xr.Dataset:
    r"""P(stuck) of released sharp-front beams of every ``beam_length`` from one Γ CCDF.

    :math:`1 - \prod_j (1 - \bar F(K/x_{j+1}^4))` over the patches of each beam (module
    docstring; Eq. 36), with the band of ``ccdf`` carried through (the product is monotone in
    every :math:`\bar F`, so a simultaneous band of the CCDF gives an interval of P(stuck) of at
    least its level, for all lengths at once).

    Parameters
    ----------
    ccdf : xarray.Dataset
        :func:`adhesive_energy_ccdf` (or the same layout: ``adhesive_energy`` ascending along
        ``rank``, ``exceedance_probability`` and optional ``_lower``/``_upper``) of one patch:
        a strip :math:`\Delta x \times w` of the beam's interface.
    beam_length : float or sequence
        Beam lengths [m].
    beam : Cantilever
        Thickness, gap, modulus (its length is replaced by ``beam_length``).
    patch_length : float, optional
        :math:`\Delta x` [m], the length of the strip the CCDF describes; default the beam's
        interaction-zone length (its thickness, §5.2).

    Returns
    -------
    xarray.Dataset
        ``stuck_probability`` with ``stuck_probability_lower``/``_upper`` over ``(..., beam_length)``.

    Examples
    --------
    >>> bank = xr.DataArray([[1e-3], [2e-2]], dims=("law", "rh"), coords={"rh": [0.5]},
    ...                     attrs={"units": "J m-2"})
    >>> c = rs.beam.adhesive_energy_ccdf(bank, dim="law")
    >>> p = rs.beam.stuck_probability_from_ccdf(c, beam_length=[150e-6, 170e-6, 180e-6])
    >>> p.stuck_probability.values.round(3)  # 50 simulated beams on this bank: 0, 0.5, 0.96
    array([[0.   , 0.5  , 0.969]])
    """
    if not isinstance(ccdf, xr.Dataset) or not {"adhesive_energy", "exceedance_probability"} <= set(ccdf) \
            or "rank" not in ccdf["adhesive_energy"].dims:
        raise ValueError("ccdf must be a Dataset of adhesive_energy and exceedance_probability over 'rank' "
                         "(rs.beam.adhesive_energy_ccdf(sample)); pass a sample of Γ through it first")
    lengths, patch_length = lengths_and_patch(beam_length, patch_length, beam)
    kterm = beam.stiffness_term
    names = [v for v in ("exceedance_probability", "exceedance_probability_lower",
                         "exceedance_probability_upper") if v in ccdf]
    below = {"exceedance_probability": 1.0, "exceedance_probability_upper": 1.0,
             "exceedance_probability_lower": float(ccdf.attrs.get("below_first_point_lower", 1.0))}
    energy = ccdf["adhesive_energy"].transpose(..., "rank")
    lead = energy.shape[:-1]
    e2 = np.asarray(energy.values, dtype=float).reshape(-1, energy.shape[-1])
    out = {}
    for name in names:
        ex = np.asarray(ccdf[name].transpose(..., "rank").values, dtype=float).reshape(e2.shape)
        p = np.empty((e2.shape[0], lengths.size))
        for b, length in enumerate(lengths):
            hi = np.minimum((np.arange(n_patches(length, patch_length)) + 1) * patch_length, length)
            t = kterm / hi**4
            for r in range(e2.shape[0]):
                p[r, b] = _stuck(_ccdf_at(t, e2[r], ex[r], below[name]), t)
        out[name.replace("exceedance_probability", "stuck_probability")] = p.reshape(lead + (lengths.size,))
    dims = tuple(d for d in energy.dims if d != "rank") + ("beam_length",)
    coords = {k: v for k, v in ccdf.coords.items() if "rank" not in v.dims}
    coords["beam_length"] = ("beam_length", lengths, {"units": "m", "long_name": "beam length"})
    ds = xr.Dataset({k: (dims, v, {"units": "1"}) for k, v in out.items()}, coords=coords)
    ds["stuck_probability"].attrs["long_name"] = "probability that the released beam stays stuck (sharp front)"
    for side in ("lower", "upper"):
        if f"stuck_probability_{side}" in ds:
            ds[f"stuck_probability_{side}"].attrs["long_name"] = f"{side} bound of P(stuck) from the CCDF's band"
    ds.attrs.update(patch_length=patch_length, model="sharp_front", protocol="release",
                    thickness=beam.thickness, gap=beam.gap, youngs_modulus=beam.youngs_modulus,
                    references="paper Eq. 36, §5 (sharp front on independent strips)")
    append_history(ds, f"stuck_probability_from_ccdf(patch_length={patch_length!r}, n_length={lengths.size})")
    return ds
