r"""The beam-scale limit state of :mod:`roughstick.stiction.rare_events` (private).

The sharp-front model of :mod:`.beam_model` on a bank of patch laws, driven by white noise: patch
``j`` of a beam takes law :math:`k_j = \lfloor \Phi(z_j)\,n_{law} \rfloor` (:math:`\Phi` the
standard-normal CDF), so :math:`z \sim N(0, I)` draws the laws uniformly and independently, as
:func:`roughstick.simulate_beams` does (equal in law, not the same draws for the same seed).

A front released from the clamp stops at the first patch :math:`j` whose equilibrium
:math:`s_j = (K/\Gamma_j)^{1/4}` lies before its far edge :math:`x_{j+1}`
(``_beam_kernels.open_front``), i.e. :math:`\Gamma_j > K/x_{j+1}^4`. So the beam is stuck
exactly when the margin :math:`R(z) = \max_j \Gamma_{k_j} x_{j+1}^4 / K` exceeds 1, and
:math:`P(\text{stuck}) = 1 - \prod_j (1 - q_j)`, :math:`q_j` the fraction of the bank's laws
with :math:`\Gamma > K/x_{j+1}^4`: the exact value on the bank, which the subset estimate is
checked against.
"""

from __future__ import annotations

import hashlib

import numpy as np
from scipy.special import ndtr

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
        # the response jump at every small move: acceptance 1-5 % measured)
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
