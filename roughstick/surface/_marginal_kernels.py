r"""Non-Gaussian surfaces of :func:`roughstick.surface.generate_surfaces`: a given PSD and a given
height distribution, by a translation process or by IAAFT.

Both start from the Gaussian surface of realization k (its own ``SeedSequence`` child, one inverse
FFT, :mod:`._generate_kernels`), so a block gives the same surfaces whatever the chunking.

*Translation with spectral pre-correction* (Grigoriu's translation process; the iterative
pre-correction of Shields, Deodatis & Bocchini 2011). The surface is :math:`z = \sigma\,T(g)`
with :math:`T` the standardised translation of the height distribution and :math:`g` a unit
Gaussian field. If :math:`g` has correlation :math:`\rho_g`, :math:`z` has

.. math::

    \rho_z = f(\rho_g) = \sum_{k \ge 1} a_k^2 \rho_g^k, \qquad
    a_k = E[T(u)\,\mathrm{He}_k(u)] / \sqrt{k!},

(Mehler's expansion, :math:`\sum a_k^2 = 1`), so :math:`g` is drawn with the pre-distorted
spectrum whose image through :math:`f` is the target: first :math:`\rho_g = f^{-1}(\rho_z)`,
then :math:`S_g \leftarrow S_g\,S_T / S_z` until the spectrum of :math:`f(\rho_g)` matches
:math:`S_T`. Once per PSD; then one Gaussian surface and one table look-up per pixel.

*IAAFT* (Schreiber & Schmitz 1996; Pérez-Ràfols & Almqvist 2019 for surfaces): alternately give
the surface the Fourier amplitudes of its Gaussian start and rank-remap its heights onto the
target's quantiles at :math:`(i + 1/2)/N`, ending on the remap (the histogram exact). Every
surface then has the same sorted heights.
"""

from __future__ import annotations

import hashlib
import threading

import numpy as np
import scipy.fft
from numba import njit
from scipy import special

from .._core.dask import realization_rng
from ._generate_kernels import _filter, _full_plane, _Kernel, _symmetrise
from .distribution import SCORE, evaluate, normal_grid, standardised

__all__: list[str] = []

#: IAAFT: alternations of amplitude imposition and rank remapping per surface.
IAAFT_ITERATIONS = 10
#: Translation: most iterative pre-correction steps after the inverse map, and the least relative
#: gain in spectral mismatch that is worth another.
PRECORRECTION_STEPS = 10
PRECORRECTION_GAIN = 0.05
#: Hermite terms of the correlation map f (the rest of sum a_k^2 = 1 goes to the last power).
HERMITE_TERMS = 256


def hermite_coefficients(table: np.ndarray, terms: int = HERMITE_TERMS) -> np.ndarray:
    """``a_k`` (k = 1 .. terms) of a standardised translation: E[T(u) He_k(u)] / sqrt(k!)."""
    x, w = normal_grid()
    t = evaluate(table, x) * w
    prev, cur = np.ones_like(x), x.copy()
    out = np.empty(terms)
    for k in range(1, terms + 1):
        out[k - 1] = t @ cur
        prev, cur = cur, (x * cur - np.sqrt(k) * prev) / np.sqrt(k + 1)
    return out


def _correlation_map(a: np.ndarray):
    """f(rho) = sum a_k^2 rho^k (+ the remainder of sum a_k^2 = 1 at the next power) and its
    monotone inverse, both tabulated on [-1, 1] densely near 1 (the short lags)."""
    c = np.concatenate([[0.0], a**2, [max(0.0, 1.0 - float(np.sum(a**2)))]])
    grid = np.unique(np.concatenate([np.linspace(-1, 0.99, 4000), 1 - np.geomspace(1e-2, 1e-13, 1200), [1.0]]))
    image = np.maximum.accumulate(np.polynomial.polynomial.polyval(grid, c))
    return (lambda rho: np.interp(rho, grid, image)), (lambda rho: np.interp(rho, image, grid))


def translation_setup(P: np.ndarray, nx: int, table: np.ndarray, amplitude: str):
    """Pre-corrected Gaussian filter and the scaled translation for :func:`marginal_block`.

    Returns ``(filt, scale, table, info)``: ``filt`` draws unit-variance Gaussian surfaces whose
    translation has the spectrum ``P``; ``scale`` is sqrt(sum P), the rms height."""
    F = _full_plane(_symmetrise(P, nx), nx=nx)
    m0 = float(F.sum())
    target = F / m0
    inside = target > 0
    table = standardised(table)
    forward, inverse = _correlation_map(hermite_coefficients(table))
    G = np.clip(np.fft.ifft2(inverse(np.clip(np.fft.fft2(target).real, -1, 1))).real, 0, None)
    G[~inside] = 0.0
    G /= G.sum()
    mismatch, steps = np.inf, 0
    while True:
        Sz = np.fft.ifft2(forward(np.clip(np.fft.fft2(G).real, -1, 1))).real
        before, mismatch = mismatch, float(np.abs(Sz[inside] - target[inside]).sum())
        if steps == PRECORRECTION_STEPS or mismatch > (1 - PRECORRECTION_GAIN) * before:
            break
        steps += 1  # one more iterative step (the first one is the inverse map itself)
        G[inside] *= target[inside] / np.where(Sz[inside] > 0, Sz[inside], target[inside])
        G /= G.sum()
    leak = float(np.clip(Sz[~inside], 0, None).sum())
    info = (f"translation process, spectrum pre-corrected (f^-1 and {steps} iterative steps; "
            f"expected spectral mismatch {mismatch:.1e} of the power inside the PSD's support, "
            f"{leak:.1e} outside it)")
    return _filter(G[:, : nx // 2 + 1], nx, amplitude), np.sqrt(m0), table, info


def iaaft_setup(P: np.ndarray, nx: int, ny: int, table: np.ndarray, amplitude: str):
    """Gaussian filter of ``P`` and the sorted target heights (quantiles at (i + 1/2)/N)."""
    m0 = float(_full_plane(_symmetrise(P, nx), nx=nx).sum())
    n = ny * nx
    target = np.sqrt(m0) * evaluate(standardised(table), special.ndtri((np.arange(n) + 0.5) / n))
    info = f"IAAFT, {IAAFT_ITERATIONS} iterations, ending on the rank remap"
    return _filter(P, nx, amplitude), target, info


_SETUPS: dict = {}
_SETUPS_LOCK = threading.Lock()


def cached_setup(method: str, P: np.ndarray, nx: int, ny: int, table: np.ndarray, amplitude: str):
    """:func:`translation_setup` or :func:`iaaft_setup`, kept for the next call with the same
    spectrum, grid, table and amplitude (an ensemble asks once per block)."""
    key = (method, nx, ny, amplitude, IAAFT_ITERATIONS,
           *(hashlib.sha1(np.ascontiguousarray(a, dtype=float)).hexdigest() for a in (P, table)))
    with _SETUPS_LOCK:
        hit = _SETUPS.get(key)
    if hit is not None:
        return hit
    out = (translation_setup(P, nx, table, amplitude) if method == "translation"
           else iaaft_setup(P, nx, ny, table, amplitude))
    with _SETUPS_LOCK:
        _SETUPS[key] = out
        while len(_SETUPS) > 4:
            _SETUPS.pop(next(iter(_SETUPS)))
    return out


@njit(cache=True, nogil=True)
def _translate(g, u0, inverse_step, table, scale, out):  # pragma: no cover - compiled
    """out = scale * T(g), T linear between the table's points and beyond its ends."""
    last = table.size - 2
    for i in range(g.size):
        t = (g[i] - u0) * inverse_step
        j = 0 if t <= 0 else (last if t >= last + 1 else int(t))
        f = t - j
        out[i] = scale * (table[j] + f * (table[j + 1] - table[j]))


def _remap(s: np.ndarray, target: np.ndarray) -> np.ndarray:
    out = np.empty_like(target)
    out[np.argsort(s, axis=None)] = target
    return out.reshape(s.shape)


def _iaaft(g: np.ndarray, target: np.ndarray) -> np.ndarray:
    ny, nx = g.shape
    amplitude = np.abs(scipy.fft.rfft2(g, workers=1))
    s = g
    for _ in range(IAAFT_ITERATIONS):
        spectrum = scipy.fft.rfft2(_remap(s, target), workers=1)
        modulus = np.abs(spectrum)
        spectrum *= np.divide(amplitude, modulus, out=np.zeros_like(modulus), where=modulus > 0)
        s = scipy.fft.irfft2(spectrum, s=(ny, nx), workers=1)
    return _remap(s, target)


def marginal_block(indices, *, setup, method, entropy, spawn_key, ny, nx, amplitude, out_dtype):
    """Realizations ``indices``: the Gaussian surface of each, then its translation or IAAFT."""
    root = np.random.SeedSequence(entropy, spawn_key=spawn_key)
    out = np.empty((len(indices), ny, nx), dtype=out_dtype)
    if method == "translation":
        filt, scale, table, _ = setup
        kernel = _Kernel(filt, ny, nx, amplitude, out_dtype)
        step = SCORE[1] - SCORE[0]
        for i, k in enumerate(indices):
            g = kernel(realization_rng(root, int(k)))
            _translate(g.ravel(), SCORE[0], 1.0 / step, table, scale, out[i].reshape(-1))
        return out
    filt, target, _ = setup
    kernel = _Kernel(filt, ny, nx, amplitude, np.float64)
    for i, k in enumerate(indices):
        out[i] = _iaaft(kernel(realization_rng(root, int(k))), target)
    return out
