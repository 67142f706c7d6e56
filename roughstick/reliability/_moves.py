"""Markov-chain moves of :mod:`roughstick.stiction.rare_events` (private, plain numpy).

Every move is a callable ``move(z, rng) -> z'`` whose proposal kernel is reversible with respect
to the standard-normal prior N(0, I) of the white noise, so a chain conditioned on
``{Y(z) > b}`` accepts a proposal iff ``Y(z') > b`` (no Metropolis ratio). A move draws exactly
one standard-normal array of the noise's shape from ``rng``, so a chain is replayed bit for bit
from its seed, its acceptance flags and the moves of its steps.

- :class:`PCNMove`: preconditioned Crank-Nicolson, ``rho z + sigma xi`` per coordinate.
- :class:`ShellMove`: keeps the norm of the white noise in each *shell* of Fourier modes (modes of
  equal wavevector magnitude and equal PSD amplitude) and moves its direction only. With an
  isotropic PSD every mode of a shell has the same amplitude, so the move keeps the zone's
  periodogram per shell (its rms and spectrum) exactly and changes its shape (phases, peaks).
"""

from __future__ import annotations

import numpy as np
import scipy.fft

from ._kernels import proposal_scales

__all__: list[str] = []

#: pCN step sigma of the shell-direction rounds of ``proposal="shell"`` (docs/rare_events.md)
SHELL_SCALE = 1.0
#: None: every shell moves; K: one shell, drawn uniformly among the K of lowest |q| (experiment)
SHELL_ONE_OF = None
#: "direction": keep each shell's norm, move its direction; "radius": the converse (experiment)
SHELL_MODE = "direction"


def check_proposal(proposal, model):
    if proposal == "shell" and getattr(model, "shell_labels", None) is None:
        raise ValueError("proposal='shell' needs a limit state with a shell_labels attribute (the "
                         "surface limit states of failure_probability have one); use 'adaptive'.")


def round_move(proposal, k, model, noise_shape, spread, scale):
    """The move of round ``k`` of a level: with ``proposal="shell"`` even rounds are a
    :class:`ShellMove` and odd rounds the adaptive pCN; otherwise pCN in every round."""
    if proposal == "shell" and k % 2 == 0:
        return ShellMove(model.shell_labels, noise_shape, SHELL_SCALE, one_of=SHELL_ONE_OF, mode=SHELL_MODE)
    return PCNMove(*proposal_scales(spread, scale))


class PCNMove:
    """pCN proposal ``rho z + sigma xi`` (per-coordinate ``rho``, ``sigma``; rho² + sigma² = 1)."""

    def __init__(self, rho, sigma):
        self.rho, self.sigma = rho, sigma

    def __call__(self, z, rng):
        return self.rho * z + self.sigma * rng.standard_normal(np.shape(z))


def shell_labels(amplitude, *, shape, spacing) -> np.ndarray:
    """Label the ``rfft2`` modes of a white-noise field by shell (``-1``: zero amplitude).

    ``amplitude`` is the filter on the ``rfft2`` grid of an ``(ny, nx)`` field (shape
    ``(ny, nx // 2 + 1)``), ``shape`` ``(ny, nx)``, ``spacing`` ``(dy, dx)``. A shell is the set of modes of one
    wavevector magnitude |q| whose amplitudes agree to 1e-9 relative (on a discrete grid an
    isotropic PSD can differ in the last bits inside a shell; modes of different amplitude are
    never grouped). Hermitian partners (columns 0 and nx/2) always share a label.
    """
    a = np.asarray(amplitude, dtype=float)
    ny, nx = (int(v) for v in shape)
    nh = nx // 2 + 1
    if a.shape != (ny, nh):
        raise ValueError(f"amplitude of shape {a.shape} is not the rfft2 grid {(ny, nh)} of {(ny, nx)}.")
    dy, dx = spacing
    qy = np.fft.fftfreq(ny, dy)
    qx = np.arange(nh) / (nx * dx)
    q2 = qy[:, None] ** 2 + qx[None, :] ** 2
    on = a > 0
    qv, av = q2[on], a[on]
    order = np.lexsort((av, qv))
    qs, as_ = qv[order], av[order]
    new = np.r_[True, (np.diff(qs) > 1e-9 * qs[1:]) | (np.diff(as_) > 1e-9 * as_[1:])]
    lab = np.empty(qv.size, dtype=np.int64)
    lab[order] = np.cumsum(new) - 1
    out = np.full(a.shape, -1, dtype=np.int64)
    out[on] = lab
    return out


def _weights(ny, nx, nh):
    """Weight of each rfft2 coefficient in the norm of the real field (2 where its Hermitian
    partner is not stored, 1 in column 0 and, for even nx, column nx/2)."""
    w = np.full((ny, nh), 2.0)
    w[:, 0] = 1.0
    if nx % 2 == 0:
        w[:, -1] = 1.0
    return w


def _shell_norm2(c, lab, w, n):
    """Squared norm of the real field in each shell, from its stored rfft2 coefficients ``c``
    (labels ``lab``, Hermitian weights ``w``; at least ``n`` shells)."""
    return np.bincount(lab, weights=w * (c.real**2 + c.imag**2), minlength=n)


class ShellMove:
    r"""Direction move inside shells of Fourier modes, reversible for N(0, I).

    With :math:`W = \mathcal F_{\rm ortho}[z]` and :math:`X = \mathcal F_{\rm ortho}[\xi]`,
    :math:`\xi \sim N(0, I)`, each shell :math:`g` gets

    .. math:: W'_g = \|W_g\|\,\frac{\rho W_g + \sigma X_g}{\|\rho W_g + \sigma X_g\|},

    the pCN proposal of the shell's component rescaled to the shell's norm; modes of no shell
    (label ``-1``) are kept. Why it keeps N(0, I): the component of z in a shell (a subspace with
    real orthonormal coordinates) is its norm times an independent uniform direction; the move
    keeps the norm, and for that norm the new direction's density depends only on its angle to
    the old one: a symmetric kernel, reversible for the uniform direction.
    """

    def __init__(self, labels, shape, sigma, one_of=None, mode="direction"):
        ny, nx = (int(v) for v in shape)
        self.labels = np.asarray(labels, dtype=np.int64)
        if self.labels.shape != (ny, nx // 2 + 1):
            raise ValueError(f"shell labels of shape {self.labels.shape} do not match the rfft2 grid "
                             f"{(ny, nx // 2 + 1)} of the white noise {(ny, nx)}.")
        self.shape = (ny, nx)
        self.sigma = float(sigma)
        self.rho = float(np.sqrt(1.0 - self.sigma**2))
        self.on = self.labels >= 0
        self.lab = self.labels[self.on]
        self.w = _weights(ny, nx, nx // 2 + 1)[self.on]
        self.n = int(self.lab.max()) + 1 if self.lab.size else 0
        self.mode = mode
        self.one_of = None if one_of is None else min(int(one_of), self.n)

    def _norm2(self, c):
        return _shell_norm2(c, self.lab, self.w, self.n)

    def __call__(self, z, rng):
        xi = rng.standard_normal(np.shape(z))
        W = scipy.fft.rfft2(np.reshape(z, self.shape), norm="ortho", workers=1)
        X = scipy.fft.rfft2(np.reshape(xi, self.shape), norm="ortho", workers=1)
        wg = W[self.on]
        v = self.rho * wg + self.sigma * X[self.on]
        if self.one_of is not None:  # only one shell moves (labels are sorted by |q|)
            v = np.where(self.lab == rng.integers(self.one_of), v, wg)
        nv, nw = self._norm2(v), self._norm2(wg)
        if self.mode == "radius":  # keep the direction, take the norm of the pCN proposal
            f = np.sqrt(np.divide(nv, nw, out=np.zeros(self.n), where=nw > 0))
            W[self.on] = f[self.lab] * wg
        else:
            f = np.sqrt(np.divide(nw, nv, out=np.zeros(self.n), where=nv > 0))
            W[self.on] = f[self.lab] * v
        out = scipy.fft.irfft2(W, s=self.shape, norm="ortho", workers=1)
        return out.reshape(np.shape(z))


def shell_energies(z, labels):
    """Squared norm of the white noise ``z`` (2-D) in each shell of ``labels`` (diagnostics, tests)."""
    ny, nx = np.shape(z)
    W = scipy.fft.rfft2(z, norm="ortho", workers=1)
    on = labels >= 0
    return _shell_norm2(W[on], labels[on], _weights(ny, nx, nx // 2 + 1)[on], 0)
