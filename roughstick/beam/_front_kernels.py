r"""Private numpy kernels of the beam-scale crack-front model (:mod:`.beam_model`).

A cantilever of length :math:`l`, clamped at :math:`x=0`, is stuck on :math:`[s, l]` and free
(S-shaped) on :math:`[0, s]`. Its energy per unit width is
:math:`\Pi(s) = \frac{E t^3 h^2}{2 s^3} - \int_s^l \Gamma(x)\,\mathrm dx`, so the energy release
rate of the front is :math:`G(s) = K/s^4` with :math:`K = \frac32 E t^3 h^2` (Eq. 36). The
interface is a row of patches :math:`[x_j, x_{j+1})` of constant adhesive energy
:math:`\Gamma_j`; in patch :math:`j` the front is in equilibrium at
:math:`s_j = (K/\Gamma_j)^{1/4}`. A front moves only while it lowers :math:`\Pi` and stops at the
first local minimum in the direction it moves (quasi-static, no inertia): opening stops at the
first patch whose :math:`s_j < x_{j+1}` (at :math:`\max(x_j, s_j)`, pinned on the edge when
:math:`s_j \le x_j`), closing stops at the first patch, going towards the clamp, whose
:math:`s_j > x_j`.

Arrays: ``energy`` (n, m) J/m²; lengths in m. ``inf`` crack length = the beam is free.
"""

from __future__ import annotations

import numpy as np

__all__ = ["close_front", "equilibrium_positions", "open_front"]


def equilibrium_positions(energy: np.ndarray, stiffness_term: float) -> np.ndarray:
    """s_j = (K / Γ_j)^(1/4); +inf where Γ_j <= 0 (a patch that does not adhere)."""
    with np.errstate(divide="ignore"):
        return np.where(energy > 0, (stiffness_term / np.maximum(energy, 1e-300)) ** 0.25, np.inf)


def _edges(m: int, patch_length: float, length: float):
    lo = np.arange(m) * patch_length
    hi = np.minimum(lo + patch_length, length)
    return lo, hi


def open_front(energy, stiffness_term, patch_length, length, start):
    """Front moving away from the clamp from ``start`` (n,); returns s (n,), inf when free."""
    energy = np.asarray(energy, dtype=float)
    n, m = energy.shape
    lo, hi = _edges(m, patch_length, length)
    sj = equilibrium_positions(energy, stiffness_term)
    start = np.broadcast_to(np.asarray(start, dtype=float), (n,))
    stop = (sj < hi) & (hi > start[:, None]) & (lo < length)
    found = stop.any(axis=1)
    j = np.argmax(stop, axis=1)
    rows = np.arange(n)
    s = np.maximum(np.maximum(lo[j], sj[rows, j]), start)
    s = np.where(found & (s < length), s, np.inf)
    return np.where(np.isinf(start), np.inf, s)


def close_front(energy, stiffness_term, patch_length, length, start):
    """Front moving towards the clamp from ``start`` (n,) when that lowers the energy."""
    energy = np.asarray(energy, dtype=float)
    n, m = energy.shape
    lo, hi = _edges(m, patch_length, length)
    sj = equilibrium_positions(energy, stiffness_term)
    start = np.broadcast_to(np.asarray(start, dtype=float), (n,))
    finite = np.isfinite(start)
    jstart = np.where(finite, np.floor(np.where(finite, start, 0) / patch_length), 0).astype(int)
    jstart = np.minimum(jstart, m - 1)
    # the patch just behind a front sitting on an edge x_j is j-1
    on_edge = finite & (jstart > 0) & (np.abs(start - lo[jstart]) <= 1e-12 * patch_length)
    jstart = jstart - on_edge
    allowed = np.arange(m)[None, :] <= jstart[:, None]
    stop = allowed & (sj > lo[None, :])
    rev = stop[:, ::-1]
    found = rev.any(axis=1)
    j = m - 1 - np.argmax(rev, axis=1)
    s = np.where(found, np.minimum(start, np.minimum(sj[np.arange(n), j], hi[j])), 0.0)
    return np.where(finite, s, np.inf)
