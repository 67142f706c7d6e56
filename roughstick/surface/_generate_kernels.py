r"""The per-block numpy kernel of :func:`roughstick.surface.generate_surfaces` (Eqs. 33-35).

Hermitian complex amplitudes on the support box of the amplitude filter, one inverse real FFT per
surface; realization k draws from its own ``SeedSequence`` child, so a block gives the same
surfaces whatever the chunking.
"""

from __future__ import annotations

import numpy as np
import scipy.fft

from .._core.dask import realization_rng

__all__: list[str] = []


def _symmetrise(P: np.ndarray, nx: int) -> np.ndarray:
    """Make the self-conjugate columns (qx = 0 and, for even nx, qx = Nyquist) even in qy."""
    P = np.array(P, dtype=float, copy=True)
    cols = [0] + ([nx // 2] if nx % 2 == 0 else [])
    for c in cols:
        P[1:, c] = 0.5 * (P[1:, c] + P[1:, c][::-1])
    return P


def _filter(P, nx, amplitude):
    """Amplitudes sqrt(P) on the bounding box of the PSD support: (A_box, rows, ncols).

    ``A_box`` is scaled for the draw of ``amplitude``: a Gaussian draw n1 + i n2 has
    E|.|^2 = 2, hence the sqrt(1/2) for "rayleigh"."""
    P = _symmetrise(P, nx)
    A = np.sqrt(P)
    rows = np.flatnonzero(A.any(axis=1))
    cols_any = np.flatnonzero(A.any(axis=0))
    ncols = int(cols_any[-1]) + 1 if cols_any.size else 0
    scale = np.sqrt(0.5) if amplitude == "rayleigh" else 1.0
    A_box = np.ascontiguousarray(A[rows, :ncols]) * scale
    return A_box, rows, ncols


def _centred_full(P, nx, dq2):
    return np.fft.fftshift(_full_plane(_symmetrise(P, nx), nx=nx)) / dq2


def _full_plane(half: np.ndarray, *, nx: int) -> np.ndarray:
    """Hermitian completion of an rfft-layout power array (ny, nx//2+1) to (ny, nx), fft order."""
    ny = half.shape[0]
    full = np.empty((ny, nx))
    m = half.shape[1]
    full[:, :m] = half
    neg = np.arange(m, nx)  # columns qx < 0: P(qy, qx) = P(-qy, -qx)
    full[:, neg] = half[(-np.arange(ny)) % ny][:, nx - neg]
    return full


class _Kernel:
    """Per-block state: the amplitude filter on its support box and a reusable spectrum buffer."""

    def __init__(self, filt, ny, nx, amplitude, out_dtype):
        self.A_box, rows, ncols = filt
        self.ny, self.nx, self.amplitude, self.out_dtype = ny, nx, amplitude, out_dtype
        self.rows, self.ncols = rows, ncols
        self.full_rows = rows.size == ny
        ctype = np.complex64 if out_dtype == np.float32 else np.complex128
        self.xi = np.zeros((ny, nx // 2 + 1), dtype=ctype)
        self.work = np.zeros((ny, nx // 2 + 1), dtype=ctype)
        h = (ny - 1) // 2
        self.h = h
        self.mirror = ny - np.arange(1, h + 1)
        self.self_rows = [0] + ([ny // 2] if ny % 2 == 0 else [])
        self.self_cols = [c for c in [0] + ([nx // 2] if nx % 2 == 0 else []) if c < ncols]
        self.in_place = self.full_rows and ncols == nx // 2 + 1 and ctype == np.complex128
        self.draw = np.empty((rows.size, ncols, 2)) if amplitude == "rayleigh" else None

    def __call__(self, rng):
        """One surface: Hermitian amplitudes on the support box, one inverse real FFT (Eq. 34)."""
        xi, rows, ncols = self.xi, self.rows, self.ncols
        if ncols:
            shape = (rows.size, ncols)
            if self.amplitude == "rayleigh" and self.in_place:
                # the box is the whole spectrum: draw straight into it (same stream as below)
                rng.standard_normal(out=xi.view(np.float64))
                xi *= self.A_box
            else:
                if self.amplitude == "rayleigh":
                    # complex Gaussian: Rayleigh modulus (zeta of Eq. 33) with uniform phase
                    rng.standard_normal(out=self.draw)
                    box = self.draw.view(np.complex128)[..., 0]
                else:
                    box = np.exp(1j * (2 * np.pi) * rng.random(shape))
                box *= self.A_box
                if self.full_rows:
                    xi[:, :ncols] = box
                else:
                    xi[rows, :ncols] = box
            # self-conjugate columns (qx = 0, Nyquist): Hermitian symmetry inside the column
            for c in self.self_cols:
                col = xi[:, c]
                for r in self.self_rows:  # real modes, E[xi^2] = 1
                    v = col[r]
                    if self.amplitude == "rayleigh":
                        col[r] = np.sqrt(2.0) * v.real
                    else:
                        col[r] = np.copysign(abs(v), v.real)
                col[self.mirror] = np.conj(col[1 : self.h + 1])
        # Eq. 34 as two 1-D passes: the complex inverse FFT along y only over the columns that
        # hold power (the support box), then the real inverse FFT along x of every row
        if 0 < ncols < xi.shape[1]:
            work = self.work
            work[:, :ncols] = scipy.fft.ifft(xi[:, :ncols], axis=0, norm="forward", workers=1)
            return scipy.fft.irfft(work, n=self.nx, axis=1, norm="forward", workers=1)
        return scipy.fft.irfft2(xi, s=(self.ny, self.nx), norm="forward", workers=1)


def _generate_block(indices, *, filt, entropy, spawn_key, ny, nx, amplitude, out_dtype):
    kernel = _Kernel(filt, ny, nx, amplitude, out_dtype)
    root = np.random.SeedSequence(entropy, spawn_key=spawn_key)
    out = np.empty((len(indices), ny, nx), dtype=out_dtype)
    for i, k in enumerate(indices):
        out[i] = kernel(realization_rng(root, int(k)))
    return out
