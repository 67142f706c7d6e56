"""Markov-chain moves of subset simulation (private, plain numpy).

A move is a callable ``move(z, rng) -> z'`` whose proposal kernel is reversible with respect to
the standard-normal prior N(0, I) of the white noise, so a chain conditioned on ``{Y(z) > b}``
accepts a proposal iff ``Y(z') > b`` (no Metropolis ratio). A move draws exactly one
standard-normal array of the noise's shape from ``rng``, so a chain is replayed bit for bit from
its seed, its acceptance flags and the moves of its steps (:func:`._kernels.replay_chain`).
"""

from __future__ import annotations

import numpy as np

__all__: list[str] = []


class PCNMove:
    """pCN proposal ``rho z + sigma xi`` (per-coordinate ``rho``, ``sigma``; rho² + sigma² = 1)."""

    def __init__(self, rho, sigma):
        self.rho, self.sigma = rho, sigma

    def __call__(self, z, rng):
        return self.rho * z + self.sigma * rng.standard_normal(np.shape(z))
