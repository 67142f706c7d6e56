"""Kernels of the FFT boundary-element model (:mod:`roughstick.contact.fft_bem`).

Numpy/scipy/numba only (no xarray, no Tamaas), thread-safe (each curve owns its grid and arrays;
an :class:`FFTGrid` holds scratch buffers, so one grid serves one thread; the numba loops release
the GIL). Units inside: lengths in nm, pressures in units of E* (the elastic half-space has
plane-strain modulus 1), so heights, gaps and tolerances are all of order one.

The problem is the one the Tamaas reference solves (:mod:`roughstick.contact.bem`): a rigid rough
profile ``z`` against an elastic half-space on a periodic grid, the flat at mean gap
``d - mean(z)`` (zero-mean elastic displacement), and a Dugdale cohesive zone: tension
``sigma0`` wherever the gap is below ``h0`` (contact pixels included). For a fixed wet set ``W``
the adhesive tension is a known load, so the contact pressure ``p >= 0`` solves the non-adhesive
problem on the shifted gap ``h' = d - z - sigma0 G[1_W]``:

    minimise 1/2 p.G p + p.h'   over p >= 0     (gradient: the gap g = G p + h'),

by the projected conjugate gradient of Polonsky & Keer (1999) in displacement control. ``W`` is
then updated from the deformed gap, ``W = {g < h0}``, and the two steps alternate until ``W``
stops changing. A state warm-started from a neighbour (the retraction path) starts from that
state's pressure and from its gaps opened by the move of the flat; a state whose predecessor had
no hard contact starts from the undeformed wet set ``{d - z < h0}`` (the Tamaas reference's
convention for states with water but no contact).

What makes it cheap (the speed-up; docs/evidence/fft_bem_speed.md):

- every state carries its exact gap g = G[p - sigma0 1_W] + d - z, and the next one starts from
  it plus the displacement of the change of traction, not of the whole traction;
- the kernel is applied by an FFT pair only when more than ``SPARSE_PER_LOG2 * log2(N)`` pixels
  are loaded; fewer (the contact set of a stiff rough map, a clamp, a change of the wet set) are
  summed from the real-space kernel directly;
- within a conjugate-gradient step the clamp of the pressure and the change of the wet set are
  one correction, applied by one transform (except where the wet set is bistable, see
  ``SEQUENTIAL_WET``);
- a state whose two predecessors are in contact starts from their secant extrapolation;
- the approach, which only brackets the equilibrium, goes no deeper than needed and is solved
  loosely.
"""

from __future__ import annotations

import numba
import numpy as np
import scipy.fft as sfft

from ..adhesion import equilibrium_crossings

__all__ = ["FFTGrid", "pk_solve", "solve_state", "curve_on_grid", "auto_curve"]

# threads of the FFTs (scipy.fft ``workers``) from THREADS_MIN_PIXELS pixels up. Fixed rather than
# taken from the machine: scipy's FFT differs in the last bit with the number of workers. On the
# 2-core machine, quiet, an FFT pair is 1.6x faster with two at 1024² and 1.15x at 512²; with the
# other core busy, no faster (and a run of several maps in parallel would oversubscribe): so
# from 1024² only
THREADS = 2
# threads of the direct sums (numba ``prange`` on bands of rows; the same bits for any number):
# one, because the parallel loops waited for descheduled threads on the shared machine (512² S1A,
# six RH: 1.5-2.2 s with one thread, 4.9-6.8 s with two, load 4 on 2 cores)
SUM_THREADS = 1
THREADS_MIN_PIXELS = 1024 * 1024
# loaded pixels per log2(pixels) up to which FFTGrid.displacement sums the real-space kernel instead
# of an FFT pair (break-even measured at about 3.5 log2 N at 512² and 1024², single precision)
SPARSE_PER_LOG2 = 2.5


class FFTGrid:
    """Periodic grid with the Boussinesq kernel of the half-space, :math:`\\tilde G = 2/q` (E* = 1).

    :meth:`displacement` applies the kernel by a real FFT pair (``calls`` counts them), or, for a
    traction on at most ``sparse_max`` pixels, by summing the real-space kernel shifted to each
    loaded pixel (``sparse_calls``, ``sparse_sources``): the same operator, about 1/60 of an FFT
    pair per loaded pixel at 512² (single thread). The choice depends only on the number of
    loaded pixels, so results do not depend on the machine.

    Parameters
    ----------
    shape : (int, int)
        Pixels (ny, nx).
    spacing : (float, float)
        Pixel sizes (dy, dx) in the internal length unit.
    dtype : numpy dtype
        float32 (default of the public model: twice as fast, gaps resolved to ~1e-6 of the
        heights) or float64.
    sparse_max : int, optional
        Most loaded pixels summed directly (default ``SPARSE_PER_LOG2 * log2(ny nx)``; 0: FFTs
        only).
    workers : int, optional
        Threads of the FFTs (default ``THREADS`` from ``THREADS_MIN_PIXELS`` pixels up, else 1;
        scipy's FFT differs in the last bit with it).
    """

    def __init__(self, shape, spacing, dtype=np.float32, *, sparse_max=None, workers=None):
        ny, nx = shape
        dy, dx = spacing
        qy = 2 * np.pi * np.fft.fftfreq(ny, d=dy)
        qx = 2 * np.pi * np.fft.rfftfreq(nx, d=dx)
        q = np.sqrt(qy[:, None] ** 2 + qx[None, :] ** 2)
        q[0, 0] = np.inf  # zero-mean displacement: the periodic convention of the reference
        kernel = 2.0 / q
        self.kernel = kernel.astype(dtype)
        self.shape = (ny, nx)
        self.dtype = np.dtype(dtype)
        self.calls = 0
        self.sparse_calls = 0
        self.sparse_sources = 0
        if workers is None:
            workers = THREADS if ny * nx >= THREADS_MIN_PIXELS else 1
        self.workers = max(int(workers), 1)
        self.sum_threads = SUM_THREADS if ny * nx >= THREADS_MIN_PIXELS else 1
        self._buffers = {}
        if sparse_max is None:
            sparse_max = int(SPARSE_PER_LOG2 * np.log2(ny * nx))
        self.sparse_max = int(sparse_max)
        self._real = None
        self._idx = np.empty(max(self.sparse_max, 0), dtype=np.int64)
        if self.sparse_max > 0:
            # the displacement of a unit load on pixel (0, 0), twice along x so that the row of
            # any shifted copy is one contiguous slice
            real = sfft.irfft2(kernel, s=self.shape).astype(dtype)
            self._real = np.ascontiguousarray(np.concatenate([real, real], axis=1))
        # the displacement of a pixel under its own unit load
        self.self_displacement = float(np.sum(kernel[:, 1:-1]) * 2 + np.sum(kernel[:, [0, -1]])
                                       if nx % 2 == 0 else
                                       np.sum(kernel[:, 1:]) * 2 + np.sum(kernel[:, 0])) / (ny * nx)

    def buffer(self, name, dtype=None):
        """A scratch array of the grid's shape, reused between calls (its content is undefined)."""
        dtype = self.dtype if dtype is None else np.dtype(dtype)
        key = (name, dtype)
        buf = self._buffers.get(key)
        if buf is None:
            buf = self._buffers[key] = np.empty(self.shape, dtype)
        return buf

    def displacement(self, traction):
        """Zero-mean surface displacement caused by ``traction`` (compressive > 0 opens the gap)."""
        return self.apply(traction, np.empty(self.shape, self.dtype))

    def add_displacement(self, traction, out):
        """``out += displacement(traction)`` (in place; no temporary for a sparse traction)."""
        return self.apply(traction, out, add=True)

    def apply(self, traction, out, *, add=False, defer=False, loaded=None):
        """``out = displacement(traction)``, or ``out += ...`` with ``add``; returns ``out``.
        With ``defer`` (and ``add``), a displacement computed by FFT is returned instead of added
        (the caller adds it in its next pass), and None when it was added. ``loaded``: the
        number of non-zero pixels of ``traction``, if known."""
        traction = traction.astype(self.dtype, copy=False)
        if self.sparse_max <= 0 or (loaded is not None and loaded > self.sparse_max):
            n = -1
        else:
            n = _gather(traction, self._idx, -1 if loaded is None else loaded)
        if n >= 0:
            self.sparse_calls += 1
            self.sparse_sources += n
            idx = self._idx[:n]
            if self.sum_threads > 1:
                _sparse_displacement_threads(idx, traction.ravel()[idx], self._real, out, add,
                                             4 * self.sum_threads)
            else:
                _sparse_displacement(idx, traction.ravel()[idx], self._real, out, add)
            return None if defer else out
        self.calls += 1
        spec = sfft.rfft2(traction, workers=self.workers)
        spec *= self.kernel
        u = sfft.irfft2(spec, s=self.shape, workers=self.workers, overwrite_x=True)
        if defer:
            return u.astype(self.dtype, copy=False)
        if add:
            out += u
        else:
            out[...] = u
        return out


# The elementwise passes: written branch-free over flat arrays so that LLVM vectorises them
# (fastmath: reductions may be reassociated; the same binary gives the same bits). Boolean sets
# are read as uint8.
_JIT = dict(cache=True, nogil=True, fastmath=True)


@numba.njit(**_JIT)
def _gather(a, idx, known):
    """Flat indices of the non-zero entries of ``a`` into ``idx``; their number, or -1 when
    there are more than ``idx.size``. ``known``: their number if known (>= 0), else -1."""
    af = a.ravel()
    most = idx.size
    zero = af.dtype.type(0)
    m = af.size
    n = known
    if n < 0:
        n = 0
        for b in range(0, m, 4096):  # count by blocks, stopping as soon as there are too many
            e = min(b + 4096, m)
            for i in range(b, e):
                n += af[i] != zero
            if n > most:
                return -1
    if n > most:
        return -1
    if n == 0:
        return 0
    n = 0
    for b in range(0, m, 64):  # blocks: skip the empty ones with a vectorised test
        e = min(b + 64, m)
        k = 0
        for i in range(b, e):
            k += af[i] != zero
        if k:
            for i in range(b, e):
                if af[i] != zero:
                    idx[n] = i
                    n += 1
    return n


@numba.njit(**_JIT)
def _direction(p, g, t, beta, W, h0, sigma0, c, wet):
    """t <- g + beta t on the contact set (0 elsewhere); with ``wet``, also W <- {g < h0} and
    c <- -sigma0 (change of 1_W), else c <- 0. Returns (pixels whose wet state changed, non-zero
    entries of t)."""
    pf, gf, tf, cf = p.ravel(), g.ravel(), t.ravel(), c.ravel()
    wf = W.view(np.uint8).ravel()
    zero = pf.dtype.type(0)
    b = pf.dtype.type(beta)
    s0 = pf.dtype.type(sigma0)
    hw = pf.dtype.type(h0)
    n = 0
    nt = 0
    if wet:
        for i in range(pf.size):
            gi = gf[i]
            ti = (gi + b * tf[i] if b != zero else gi) if pf[i] > zero else zero
            tf[i] = ti
            nt += ti != zero
            wn = np.uint8(gi < hw)
            ch = wn != wf[i]
            cf[i] = (-s0 if wn else s0) if ch else zero
            wf[i] = wn
            n += ch
    elif b == zero:  # a restart: t is not read (the scratch buffer may hold anything)
        for i in range(pf.size):
            ti = gf[i] if pf[i] > zero else zero
            tf[i] = ti
            nt += ti != zero
            cf[i] = zero
    else:
        for i in range(pf.size):
            ti = gf[i] + b * tf[i] if pf[i] > zero else zero
            tf[i] = ti
            nt += ti != zero
            cf[i] = zero
    return n, nt


@numba.njit(**_JIT)
def _step_length(p, g, t, r):
    pf, gf, tf, rf = p.ravel(), g.ravel(), t.ravel(), r.ravel()
    zero = pf.dtype.type(0)
    num = 0.0
    den = 0.0
    for i in range(pf.size):
        c = pf[i] > zero
        num += np.float64(gf[i] * tf[i]) if c else 0.0
        den += np.float64(rf[i] * tf[i]) if c else 0.0
    return num, den


@numba.njit(**_JIT)
def _update(p, g, t, r, tau, c):
    """One projected step: p <- max(p - tau t, 0), pixels at p = 0 with g < 0 entering the
    contact (Polonsky & Keer); g <- g - tau r (exact for the unclamped step); c += the traction
    the clamp and the entries add, so that the exact gap is g + G[c]. Returns (pixels entered,
    pixels with c != 0)."""
    pf, gf, tf, rf, cf = p.ravel(), g.ravel(), t.ravel(), r.ravel(), c.ravel()
    tau = pf.dtype.type(tau)
    zero = pf.dtype.type(0.0)
    entered = 0
    ncorr = 0
    for i in range(pf.size):
        gi = gf[i]
        step = pf[i] - tau * tf[i]
        gf[i] = gi - tau * rf[i]
        neg = step <= zero
        enter = neg and gi < zero
        pn = (-tau * gi if enter else zero) if neg else step
        pf[i] = pn
        entered += enter
        ci = cf[i] + (pn - step)
        cf[i] = ci
        ncorr += ci != zero
    return entered, ncorr


@numba.njit(**_JIT)
def _wet_update(g, W, h0, sigma0, c):
    """W <- {g < h0}, c <- -sigma0 (change of 1_W); returns the number of changed pixels."""
    gf, cf = g.ravel(), c.ravel()
    wf = W.view(np.uint8).ravel()
    zero = gf.dtype.type(0)
    s0 = gf.dtype.type(sigma0)
    hw = gf.dtype.type(h0)
    n = 0
    for i in range(gf.size):
        wn = np.uint8(gf[i] < hw)
        ch = wn != wf[i]
        cf[i] = (-s0 if wn else s0) if ch else zero
        wf[i] = wn
        n += ch
    return n


@numba.njit(**_JIT)
def _residual(p, g, W, h0, adhesive):
    """(sum of g^2 on the contact set, sum of g^2 where g < 0, contact pixels, pixels whose wet
    state disagrees with the gap, sum of p, wet pixels, wet contact pixels)."""
    pf, gf = p.ravel(), g.ravel()
    wf = W.view(np.uint8).ravel()
    hw = gf.dtype.type(h0)
    zero = gf.dtype.type(0)
    s1 = 0.0
    s2 = 0.0
    psum = 0.0
    n = 0
    bad = 0
    nw = 0
    nwc = 0
    for i in range(pf.size):
        gi = gf[i]
        g2 = np.float64(gi) * np.float64(gi)
        c = pf[i] > zero
        s1 += g2 if c else 0.0
        n += c
        s2 += g2 if gi < zero else 0.0
        bad += np.uint8(gi < hw) != wf[i]
        psum += np.float64(pf[i])
        nw += wf[i]
        nwc += c & wf[i]
    return s1, s2, n, (bad if adhesive else 0), psum, nw, nwc


@numba.njit(**_JIT)
def _add_residual(g, u, p, W, h0, adhesive):
    """g += u, then :func:`_residual`, in one pass."""
    pf, gf, uf = p.ravel(), g.ravel(), u.ravel()
    wf = W.view(np.uint8).ravel()
    hw = gf.dtype.type(h0)
    zero = gf.dtype.type(0)
    s1 = 0.0
    s2 = 0.0
    psum = 0.0
    n = 0
    bad = 0
    nw = 0
    nwc = 0
    for i in range(pf.size):
        gi = gf[i] + uf[i]
        gf[i] = gi
        g2 = np.float64(gi) * np.float64(gi)
        c = pf[i] > zero
        s1 += g2 if c else 0.0
        n += c
        s2 += g2 if gi < zero else 0.0
        bad += np.uint8(gi < hw) != wf[i]
        psum += np.float64(pf[i])
        nw += wf[i]
        nwc += c & wf[i]
    return s1, s2, n, (bad if adhesive else 0), psum, nw, nwc


@numba.njit(**_JIT)
def _wet_change(Wn, Wr, sigma0, q):
    """q <- -sigma0 (1_Wn - 1_Wr); returns the number of changed pixels."""
    wn, wr, qf = Wn.view(np.uint8).ravel(), Wr.view(np.uint8).ravel(), q.ravel()
    s0 = qf.dtype.type(sigma0)
    zero = qf.dtype.type(0.0)
    n = 0
    for i in range(qf.size):
        a, b = wn[i], wr[i]
        qf[i] = ((-s0 if a else s0) if a != b else zero)
        n += a != b
    return n


@numba.njit(**_JIT)
def _fixpoint(hp, W, Wn, h0, sigma0, q):
    """One step of the wet set on an open gap: (closed, changed). ``closed``: a pixel has hp <= 0;
    else Wn <- {hp < h0} and q <- -sigma0 (1_Wn - 1_W)."""
    hf = hp.ravel()
    zero = hf.dtype.type(0.0)
    hw = hf.dtype.type(h0)
    closed = 0
    for i in range(hf.size):
        closed += not hf[i] > zero
    if closed:
        return True, 0
    wn = Wn.view(np.uint8).ravel()
    for i in range(hf.size):
        wn[i] = hf[i] < hw
    return False, _wet_change(Wn, W, sigma0, q)


@numba.njit(**_JIT)
def _extrapolate(pa, pb, ga, gb, Wa, Wb, r, h0, sigma0, p0, g0, W0, c):
    """Secant predictor from states a and b to the flat position b + r (b - a): the traction
    q = p - sigma0 1_W and the gap extrapolated linearly (the gap is then exact for that
    traction), p0 = max(p, 0), W0 = {g0 < h0}, and c = the traction that turns the extrapolated
    one into (p0, W0). Returns the number of pixels with c != 0."""
    paf, pbf, gaf, gbf, p0f, g0f, cf = (pa.ravel(), pb.ravel(), ga.ravel(), gb.ravel(),
                                         p0.ravel(), g0.ravel(), c.ravel())
    waf, wbf, w0f = Wa.view(np.uint8).ravel(), Wb.view(np.uint8).ravel(), W0.view(np.uint8).ravel()
    zero = p0f.dtype.type(0)
    one = p0f.dtype.type(1)
    r = p0f.dtype.type(r)
    s0 = p0f.dtype.type(sigma0)
    hw = p0f.dtype.type(h0)
    n = 0
    for i in range(p0f.size):
        pl = pbf[i] + r * (pbf[i] - paf[i])
        gl = gbf[i] + r * (gbf[i] - gaf[i])
        wb = one if wbf[i] else zero
        wl = wb + r * (wb - (one if waf[i] else zero))
        pn = pl if pl > zero else zero
        wn = gl < hw
        ci = (pn - pl) - s0 * ((one if wn else zero) - wl)
        p0f[i] = pn
        g0f[i] = gl
        w0f[i] = wn
        cf[i] = ci
        n += ci != zero
    return n


@numba.njit(**_JIT)
def _base(z, d, out):
    """out <- d - z (in the precision of ``out``)."""
    zf, of = z.ravel(), out.ravel()
    for i in range(zf.size):
        of[i] = d - zf[i]


@numba.njit(**_JIT)
def _opened(g, dd, h0, out, W, Wr, sigma0, q):
    """out <- g + dd, W <- {out < h0}, q <- -sigma0 (1_W - 1_Wr); returns the number of pixels
    whose wet state changed."""
    gf, of, qf = g.ravel(), out.ravel(), q.ravel()
    wf, wr = W.view(np.uint8).ravel(), Wr.view(np.uint8).ravel()
    dd = of.dtype.type(dd)
    hw = of.dtype.type(h0)
    s0 = of.dtype.type(sigma0)
    zero = of.dtype.type(0)
    n = 0
    for i in range(gf.size):
        o = gf[i] + dd
        of[i] = o
        wn = np.uint8(o < hw)
        wf[i] = wn
        ch = wn != wr[i]
        qf[i] = (-s0 if wn else s0) if ch else zero
        n += ch
    return n


@numba.njit(**_JIT)
def _sums(p, W):
    """(sum of p, contact pixels, wet pixels, wet contact pixels)."""
    pf = p.ravel()
    wf = W.view(np.uint8).ravel()
    zero = pf.dtype.type(0)
    psum = 0.0
    nc = 0
    nw = 0
    nwc = 0
    for i in range(pf.size):
        c = pf[i] > zero
        psum += np.float64(pf[i])
        nc += c
        nw += wf[i]
        nwc += c & wf[i]
    return psum, nc, nw, nwc


def _sparse_rows(y0, y1, iy, ix, v, real2, out, add):
    """Rows y0..y1-1 of out (+)= sum_j v_j G(. - (iy_j, ix_j)), G the real-space kernel doubled
    along x (real2): each row's sum in the same order whatever the split into rows."""
    ny, nx = out.shape
    m = v.size
    for y in range(y0, y1):
        orow = out[y]
        if not add:
            for x in range(nx):
                orow[x] = 0
        j = 0
        while j < m:  # four loads per sweep of the row
            if j + 4 <= m:
                r0 = y - iy[j] + (ny if y < iy[j] else 0)
                r1 = y - iy[j + 1] + (ny if y < iy[j + 1] else 0)
                r2 = y - iy[j + 2] + (ny if y < iy[j + 2] else 0)
                r3 = y - iy[j + 3] + (ny if y < iy[j + 3] else 0)
                k0 = real2[r0, nx - ix[j]:2 * nx - ix[j]]
                k1 = real2[r1, nx - ix[j + 1]:2 * nx - ix[j + 1]]
                k2 = real2[r2, nx - ix[j + 2]:2 * nx - ix[j + 2]]
                k3 = real2[r3, nx - ix[j + 3]:2 * nx - ix[j + 3]]
                a0, a1, a2, a3 = v[j], v[j + 1], v[j + 2], v[j + 3]
                for x in range(nx):
                    orow[x] += a0 * k0[x] + a1 * k1[x] + a2 * k2[x] + a3 * k3[x]
                j += 4
            else:
                r0 = y - iy[j] + (ny if y < iy[j] else 0)
                k0 = real2[r0, nx - ix[j]:2 * nx - ix[j]]
                a0 = v[j]
                for x in range(nx):
                    orow[x] += a0 * k0[x]
                j += 1


_sparse_rows_jit = numba.njit(cache=True, nogil=True, fastmath=True)(_sparse_rows)


@numba.njit(cache=True, nogil=True, fastmath=True)
def _sparse_displacement(idx, v, real2, out, add):
    """out (+)= sum_j v_j G(. - pixel idx_j), one thread."""
    nx = out.shape[1]
    iy = idx // nx
    _sparse_rows_jit(0, out.shape[0], iy, idx - iy * nx, v, real2, out, add)


@numba.njit(cache=True, nogil=True, fastmath=True, parallel=True)
def _sparse_displacement_threads(idx, v, real2, out, add, blocks):
    """:func:`_sparse_displacement` on ``blocks`` bands of rows in parallel (the same bits)."""
    ny, nx = out.shape
    iy = idx // nx
    ix = idx - iy * nx
    for b in numba.prange(blocks):
        _sparse_rows_jit(b * ny // blocks, (b + 1) * ny // blocks, iy, ix, v, real2, out, add)


# incremental transforms a state's gap may carry from its predecessors before it is recomputed from
# scratch (float32 rounding accumulates as a random walk: ~1e-6 of the heights after this many)
MAX_AGE = 256


def _cold_start(grid, base, W, sigma0, h0, hp=None):
    """Open gap with the Dugdale deflection of the wet set iterated to a fixed point from ``W``
    (``hp``: the gap of ``W`` without contact, if known; updated in place).

    Returns (gap, W, closed): ``closed`` when a pixel interpenetrates (jump-in)."""
    dt = grid.dtype
    if hp is None:
        hp = base - dt.type(sigma0) * grid.displacement(W)
    q = grid.buffer("q")
    Wn = np.empty(grid.shape, bool)
    for _ in range(100):
        closed, changed = _fixpoint(hp, W, Wn, h0, sigma0, q)
        if closed:
            return hp, W, True
        if not changed:
            return hp, W, False
        grid.apply(q, hp, add=True, loaded=changed)
        W, Wn = Wn, (W if W is not Wn else np.empty(grid.shape, bool))
    return hp, W, not np.all(hp > 0)


def _shift(grid, g, p_new, p_ref, W_new, W_ref, sigma0):
    """The gap ``g`` of (p_ref, W_ref) changed in place to that of (p_new, W_new)."""
    q = grid.buffer("q")
    n = _wet_change(W_new, W_ref, sigma0, q) if sigma0 > 0 else 0
    if p_new is not p_ref:
        if n == 0:
            q[...] = 0
        if p_new is not None:
            q += p_new
        if p_ref is not None:
            q -= p_ref
        n = 1
    if n:
        grid.add_displacement(q, g)
    return g


def _has_contact(p):
    return p is not None and bool(np.any(p > 0))


def _corrected(grid, c, g, p, W, h0, adhesive, loaded=None):
    """g += G[c], then :func:`_residual` (the addition of an FFT's result fused with it)."""
    u = grid.apply(c, g, add=True, defer=True, loaded=loaded)
    if u is None:
        return _residual(p, g, W, h0, adhesive)
    return _add_residual(g, u, p, W, h0, adhesive)


def pk_solve(grid, base, p0=None, *, wet=None, sigma0=0.0, h0=0.0, tolerance=1e-3,
             max_iterations=2000, scale=1.0, start=None, wet_tolerance=0.0):
    """Polonsky-Keer CG in displacement control, with the Dugdale wet set updated as it goes.

    Solves p >= 0, g = G p + base - sigma0 G[1_W] >= 0, p g = 0, with W = {g < h0} (contact
    included): the conjugate-gradient iterations of the non-adhesive problem on the shifted gap,
    the wet set refreshed from the gap after every step. The clamp of the step and the change of
    the wet set are one traction correction, applied by one transform (linearity), so an
    iteration costs one application of the kernel, two when the contact or the wet set changed;
    the conjugate directions restart when pixels enter the contact (Polonsky & Keer).
    ``sigma0 = 0``: dry contact.

    Parameters
    ----------
    grid : FFTGrid
    base : numpy.ndarray
        Rigid gap d - z (internal units); may be None with ``start``, ``p0`` and ``wet``.
    p0 : numpy.ndarray, optional
        Warm start of the contact pressure.
    wet : numpy.ndarray of bool, optional
        First guess of the wet set (default: {base < h0}).
    tolerance : float
        Stop when the rms gap on the contact set and the rms of negative gaps, over ``scale``,
        are both below it and the wet set agrees with the gap.
    scale : float
        Length the residual is measured against (the rms height of the map).
    start : (gap, p, W) or (gap, p, W, q, n), optional
        A gap known on this ``base`` (overwritten), that of pressure ``p`` (None: zero) and wet
        set ``W``: the start is then that gap plus the displacement of the change of traction
        (often a few pixels: no FFT) instead of the displacement of the whole traction; ``q``
        and ``n``: that change and its number of loaded pixels, when known.
    wet_tolerance : float
        Fraction of the wet pixels that may still disagree with the gap at convergence (0: none;
        the approach of :func:`auto_curve`, which needs only the sign of the mean pressure, uses
        ``APPROACH_WET_TOLERANCE``).

    Returns
    -------
    (p, g, W, residual, iterations) ; p is None when the gap stays open with no pressure.
    """
    return _solve(grid, base, p0, wet=wet, sigma0=sigma0, h0=h0, tolerance=tolerance,
                  max_iterations=max_iterations, scale=scale, start=start,
                  wet_tolerance=wet_tolerance)[:5]


def _solve(grid, base, p0, *, wet, sigma0, h0, tolerance, max_iterations, scale, start,
           wet_tolerance, warm=None, own_p0=False):
    """:func:`pk_solve`, plus (sum of p, contact, wet and wet contact pixels) of the result (None
    when not at hand). ``warm``: whether ``p0`` has contact, if known; ``own_p0``: ``p0`` may be
    updated in place."""
    dt = grid.dtype
    if base is not None:
        base = base.astype(dt, copy=False)
    adhesive = sigma0 > 0
    s0 = dt.type(sigma0)
    hw = dt.type(h0)
    W = (base < hw) if wet is None else wet
    if not adhesive:
        W = np.zeros(grid.shape, dtype=bool)
    if start is not None:
        g_ref, p_ref, W_ref = start[:3]
        g_ref = g_ref.astype(dt, copy=False)
        if not adhesive:
            W_ref = W
    if warm is None:
        warm = _has_contact(p0)
    if warm:
        p = p0 if own_p0 and p0.dtype == dt else p0.astype(dt, copy=True)
        if start is not None and len(start) > 3:  # the change of traction is known
            g = g_ref
            if start[4]:
                grid.apply(start[3], g, add=True, loaded=start[4])
        elif start is not None:
            g = _shift(grid, g_ref, p0, p_ref, W, W_ref, sigma0)
        else:
            g = grid.displacement(p - s0 * W if adhesive else p) + base
    else:
        if adhesive:  # no contact yet: iterate the wet set on the open gap (jump-in if it closes)
            hp = None
            if start is not None:
                hp = _shift(grid, g_ref, None, p_ref, W, W_ref, sigma0)
            hp, W, closed = _cold_start(grid, base, W, sigma0, h0, hp)
            if not closed:
                return None, hp, W, 0.0, 0, None
        else:
            hp = base
            if np.all(hp > 0):
                return None, hp, W, 0.0, 0, None
        p = np.where(hp < 0, -1e-3 * hp, 0).astype(dt)  # seed: the interpenetrating pixels
        g = grid.add_displacement(p, hp.copy())
    # Where a wet pixel's own tension can hold it wet (sigma0 G(0) > SEQUENTIAL_WET h0: low
    # humidity, soft bodies) the Dugdale zone has equilibria a pixel apart and the order of the
    # updates picks one: the wet set is then refreshed from the exact gap after the step's clamp,
    # and shifts the gap before the next direction (three transforms at most per iteration, as
    # before the speed-up). Elsewhere it follows the exact gap one step later, so that its change and
    # the next clamp share one transform.
    sequential = adhesive and sigma0 * grid.self_displacement > SEQUENTIAL_WET * h0
    t = grid.buffer("t")  # no need to clear it: the first direction is a restart
    c = grid.buffer("c")
    r = grid.buffer("r")
    s1, s2, n, bad, *sums = _residual(p, g, W, h0, adhesive)
    err = max(np.sqrt(s1 / max(n, 1)), np.sqrt(s2 / max(n, 1))) / scale
    gold = 1.0
    delta = 0.0
    it = 0
    for it in range(1, int(max_iterations) + 1):  # noqa: B007 - the count is returned
        combined = adhesive and not sequential and it > 1
        moved, loaded = _direction(p, g, t, (delta * s1 / gold) if gold > 0 else 0.0, W, h0,
                                   sigma0, c, combined)
        gold = s1
        grid.apply(t, r, loaded=loaded)
        num, den = _step_length(p, g, t, r)
        if not den > 0:  # no direction left: the residual is that of the current state
            if moved:
                s1, s2, n, bad, *sums = _corrected(grid, c, g, p, W, h0, adhesive, moved)
            err = max(np.sqrt(s1 / max(n, 1)), np.sqrt(s2 / max(n, 1))) / scale
            break
        entered, ncorr = _update(p, g, t, r, num / den, c)
        if ncorr:
            s1, s2, n, bad, *sums = _corrected(grid, c, g, p, W, h0, adhesive, ncorr)
        else:
            s1, s2, n, bad, *sums = _residual(p, g, W, h0, adhesive)
        moved = 0
        if sequential:
            moved = _wet_update(g, W, h0, sigma0, c)
            if moved:
                s1, s2, n, bad, *sums = _corrected(grid, c, g, p, W, h0, adhesive, moved)
        # pixels entering the contact restart the conjugate directions (ENTER_RESTART; all of
        # them in the sequential order, as before the speed-up); so does a change of the wet set in
        # the sequential order (elsewhere restarting there too cost 15 % more iterations)
        delta = 0.0 if (entered > (0 if sequential else ENTER_RESTART * n) or moved) else 1.0
        err = max(np.sqrt(s1 / max(n, 1)), np.sqrt(s2 / max(n, 1))) / scale
        if err < tolerance and not moved and (not bad or bad <= wet_tolerance * sums[1]):
            break
    psum, nw, nwc = sums
    return p, g, W, float(err), it, (psum, n, nw, nwc)


def solve_state(grid, z, d, sigma0, h0, *, state=None, tolerance=1e-3, max_iterations=2000,
                scale=1.0, detach="cold", before=None, wet_tolerance=0.0):
    """Adhesive contact state at one flat position ``d`` (internal units).

    Returns a dict: ``p`` contact pressure (>= 0), ``g`` gap, ``W`` wet set (gap < h0, contact
    included), ``d``, ``pbar`` mean pressure (contact pressure minus the Dugdale tension, over
    the apparent area), ``repulsive`` (traction on the contact set, tension included, as in the
    reference), ``contact_fraction``, ``wet_fraction`` (wet and not in contact), ``residual``,
    ``iterations``, ``converged``. ``state``: a neighbour; with hard contact it is the warm
    start (continuation), and in any case its gap is the start of this one's (the change of
    traction costs a transform, often a sparse one, instead of the whole traction).
    ``before``: the state before ``state`` on the path; with both in contact the start is their
    secant extrapolation (where the wet set is not bistable). ``detach="warm"``: a warm start
    that loses the last contact is returned as it is (the caller will not keep it) instead of
    being solved again from the undeformed wet set. ``wet_tolerance``: see :func:`pk_solve`.
    """
    dt = grid.dtype
    if state is not None and "contact_fraction" in state:
        warm = state["contact_fraction"] > 0
    else:
        warm = state is not None and _has_contact(state["p"])
    start = None
    wet = p0 = base = None
    own = False
    predict = (warm and before is not None and before.get("contact_fraction", 0) > 0
               and before["d"] != state["d"] and sigma0 > 0
               and not sigma0 * grid.self_displacement > SEQUENTIAL_WET * h0)
    if predict:
        ratio = (d - state["d"]) / (state["d"] - before["d"])
        predict = ratio != 0 and -1 < ratio <= PREDICT_MAX_RATIO  # (-1, 0): interpolation
    if predict:
        # secant predictor through the two previous states: contact, pressures and wet set
        # extrapolated together (the linear combination of two exact states is exact, so only
        # the clipping of the pressure and the rounding of the wet set cost a transform).
        # Smooth 512², RH 0.7, a step of 0.33 nm: 12 % of the pressure and 487 wet pixels
        # wrong instead of 52 % and 16,794 when starting from the previous state
        p0 = np.empty(grid.shape, dt)
        opened = np.empty(grid.shape, dt)
        wet = np.empty(grid.shape, bool)
        q = grid.buffer("q")
        n = _extrapolate(before["p"], state["p"], before["g"], state["g"], before["W"],
                         state["W"], ratio, h0, sigma0, p0, opened, wet, q)
        own = True
        if max(state.get("age", MAX_AGE), before.get("age", MAX_AGE)) < MAX_AGE:
            start = (opened, p0, wet, q, n)
            prior = max(state["age"], before["age"])
        else:  # the gaps carried too many increments: recomputed from the traction
            base = _rigid_gap(grid, z, d)
    elif state is not None and state.get("age", MAX_AGE) < MAX_AGE:
        # the flat moved by d - d_prev: the neighbour's gaps open by that much before the surface
        # relaxes (exact for its pressure and wet set)
        opened = np.empty(grid.shape, dt)
        wet = np.empty(grid.shape, bool)
        if warm and sigma0 > 0:
            q = grid.buffer("q")
            n = _opened(state["g"], float(d - state["d"]), h0, opened, wet, state["W"], sigma0, q)
            start = (opened, state["p"], state["W"], q, n)
        else:
            _opened(state["g"], float(d - state["d"]), h0, opened, wet, state["W"], 0.0,
                    grid.buffer("q"))
            start = (opened, state["p"] if warm else None, state["W"])
    elif warm:
        opened = state["g"] + dt.type(d - state["d"])
        wet = opened < dt.type(h0)
    if predict:
        pass
    elif warm:
        # continuation: the wet set starts from those opened gaps (this follows the Tamaas
        # reference more closely than keeping the previous wet set: Gamma within 2 % instead of 5 %
        # on soft maps at low humidity, where the Dugdale zone has several equilibria)
        p0 = state["p"]
        base = None if start is not None else _rigid_gap(grid, z, d)
    else:
        wet = None  # a state without hard contact starts from the undeformed wet set
        base = _rigid_gap(grid, z, d)
    applied = grid.calls + grid.sparse_calls
    p, g, W, err, it, sums = _solve(
        grid, base, p0, wet=wet, sigma0=sigma0, h0=h0, tolerance=tolerance,
        max_iterations=max_iterations, scale=scale, start=start, wet_tolerance=wet_tolerance,
        warm=warm, own_p0=own)
    if start is None:
        prior = -1
    elif not predict:
        prior = state["age"]
    age = grid.calls + grid.sparse_calls - applied + prior
    if sums is None:
        if p is None:
            p = np.zeros(grid.shape, dt)
        sums = _sums(p, W)
    else:
        sums = (sums[0], sums[1], sums[2], sums[3])
    psum, nc, nw, nwc = sums
    if warm and detach == "cold" and not nc:
        # the neck broke: a state without hard contact is taken from the undeformed wet set, as
        # the reference does (wet pixels can hold themselves by their own deflection: without
        # this the two would differ by a pixel or two of water at low humidity)
        return solve_state(grid, z, d, sigma0, h0, state=dict(p=None, g=g, W=W, d=d, age=age),
                           tolerance=tolerance, max_iterations=max_iterations, scale=scale)
    N = z.size
    if not sigma0 > 0:
        nw = nwc = 0
    return dict(
        p=p, g=g, W=W, d=d, age=max(age, 0),
        pbar=(psum - sigma0 * nw) / N, pbar_scale=(psum + sigma0 * nw) / N,
        repulsive=(psum - sigma0 * nc) / N if sigma0 > 0 else psum / N,
        contact_fraction=nc / N,
        wet_fraction=(nw - nwc) / N if sigma0 > 0 else 0.0,
        residual=err, iterations=it,
        converged=bool(err < 10 * tolerance),
    )


def _rigid_gap(grid, z, d):
    base = np.empty(grid.shape, grid.dtype)
    _base(z, float(d), base)
    return base


def _repulsive(st):
    """Mean pressure > 0, or zero to round-off (a one-pixel contact at max z holding its own
    water: contact pressure and tension cancel, and the sign of the difference was the rounding
    of the solver's last digit)."""
    return st["pbar"] > -1e-6 * st.get("pbar_scale", 0.0)


def _scale(z):
    s = float(np.std(z))
    return s if s > 0 else 1.0


def curve_on_grid(z, spacing, distances, sigma0, h0, *, tolerance=1e-3, path="retract",
                  dtype=np.float32, max_iterations=2000):
    """States at the given distances (internal units), marched along ``path``.

    Returns the list of states in the order of ``distances`` and the grid (for its call count).
    """
    grid = FFTGrid(z.shape, spacing, dtype)
    d = np.asarray(distances, dtype=float)
    order = np.argsort(d) if path == "retract" else np.argsort(d)[::-1]
    scale = _scale(z)
    out = [None] * d.size
    state = None
    for k in order:
        state = solve_state(grid, z, float(d[k]), sigma0, h0, state=state, tolerance=tolerance,
                            max_iterations=max_iterations, scale=scale)
        out[k] = state
    return out, grid


# bisection rounds around the pull-off after the ``refine`` rounds (step 4 of auto_curve)
EXTRA_PULL_OFF_ROUNDS = 4
# the conjugate directions restart when more than this fraction of the contact set entered it in
# a step (Polonsky & Keer restart on any entry: nearly every step on smooth maps, steepest
# descent in effect; 4 % fewer transforms at 512²)
ENTER_RESTART = 0.01
# sigma0 G(0) / h0 above which the wet set is refreshed after each transform (pk_solve)
SEQUENTIAL_WET = 0.1
# largest step, in units of the previous one, over which solve_state extrapolates the two previous
# states (secant predictor) instead of starting from the last one
PREDICT_MAX_RATIO = 2.0
# tolerance of the approach states, in units of the tolerance (step 1 of auto_curve)
APPROACH_TOLERANCE = 50
# fraction of the wet pixels whose state may disagree with the gap in an approach state (step 1
# of auto_curve: it moves the mean pressure by that fraction of the tension at most). Requiring
# none took 60 of the 70 iterations of the deepest approach state (Table 4, 1024², RH 0.9)
APPROACH_WET_TOLERANCE = 1e-2
# fraction of the wet pixels whose state may disagree with the gap in a state of the curve (the
# mean pressure moves by 0.1 % of the tension at most; the last iterations only flipped those)
CURVE_WET_TOLERANCE = 1e-3
# the approach goes no deeper than this multiple of the depth at which the secant of the last two
# mean pressures crosses zero (step 1 of auto_curve)
APPROACH_OVERSHOOT = 1.25
# halvings of the retraction step, each after a step lost the last hard contact, before a loss is
# accepted as the neck letting go (step 2 of auto_curve): the break is located to 1/64 of the step
BREAK_HALVINGS = 6


def auto_curve(z, spacing, sigma0, h0, *, tolerance=1e-3, n_contact=12, n_free=24, refine=2,
               dtype=np.float32, max_iterations=2000, keep=lambda st: st):
    """States on an automatic grid concentrated where Eq. 13, the pull-off and d_eq are decided.

    1. approach from max z in growing steps (each at most ``APPROACH_OVERSHOOT`` x as deep as
       the zero of the secant through the last two mean pressures) until the mean pressure is
       repulsive, at ``APPROACH_TOLERANCE`` x the tolerance with ``APPROACH_WET_TOLERANCE`` of
       the wet pixels undecided (only the sign matters); the zero of the mean pressure,
       interpolated in that last step, estimates the equilibrium;
    2. retract from a quarter step below that estimate (deeper while the state there is not
       repulsive), ``n_contact`` uniform steps up to max z, going on by the same step while a
       neck stays in contact; a step that loses the last contact is retried from the attached
       state with half the step (the step stays shortened) until it is 2^-``BREAK_HALVINGS`` of
       the nominal one; only then does the neck count as broken;
    3. ``n_free`` points from there to just beyond max z + h0 (water, no hard contact: one or
       two FFTs each; the last one is dry);
    4. ``refine`` rounds bisecting the two intervals around the most tensile point and the
       interval holding the equilibrium, each new state warm-started from its neighbour below;
       then (if ``refine`` > 0) ``EXTRA_PULL_OFF_ROUNDS`` more around the most tensile point.

    A state in contact whose two predecessors on the path are in contact starts from their
    secant extrapolation (:func:`solve_state`). Curve states may leave ``CURVE_WET_TOLERANCE`` of
    the wet pixels undecided.

    Returns (distances ascending, states, grid). ``keep(state)`` may add derived values to a
    state (e.g. a cluster count); it must leave ``p``, ``g``, ``W``, ``d`` and ``age`` (warm
    starts of later points).
    """
    grid = FFTGrid(z.shape, spacing, dtype)
    zmax = float(np.max(z))
    scale = _scale(z)
    floor = float(np.mean(z)) + 0.05 * scale
    full = {}
    kw = dict(tolerance=tolerance, max_iterations=max_iterations, scale=scale,
              wet_tolerance=CURVE_WET_TOLERANCE)

    def solve(d, state, before=None):
        st = solve_state(grid, z, d, sigma0, h0, state=state, before=before, **kw)
        full[d] = keep(st)
        return st

    # 1. approach: bracket the equilibrium (a 10x looser tolerance: only the sign of the mean
    #    pressure matters here)
    rough = dict(kw, tolerance=APPROACH_TOLERANCE * tolerance, wet_tolerance=APPROACH_WET_TOLERANCE)
    step = first = max(0.05 * h0, 0.02)
    d = zmax
    st = solve_state(grid, z, d, sigma0, h0, **rough)
    older = None  # the state before ``st`` on the path (secant predictor)
    prev, p_prev = d, st["pbar"]
    while not _repulsive(st) and d > floor:
        move = step
        if APPROACH_OVERSHOOT and d < prev and st["pbar"] > p_prev:
            # the mean pressure rises with depth: no deeper than APPROACH_OVERSHOOT x the zero
            # of the secant (beyond the true zero where the curve is convex). Steps growing
            # 1.6x alone went to 6.3 nm below max z for an equilibrium at 4.5 nm (smooth 1024²,
            # RH 0.7): half the map in contact, 110 iterations for one state that only brackets
            slope = (st["pbar"] - p_prev) / (prev - d)
            move = min(move, max(APPROACH_OVERSHOOT * -st["pbar"] / slope, first))
        prev, p_prev = d, st["pbar"]
        d = max(d - move, floor)
        st, older = solve_state(grid, z, d, sigma0, h0, state=st, before=older, **rough), st
        step *= 1.6
    width = max(prev - d, 1e-3)
    if st["pbar"] > 0 and p_prev <= 0:
        estimate = d + width * st["pbar"] / (st["pbar"] - p_prev)
    else:
        estimate = d
    # 2. retract from below the estimate, first making sure the start is repulsive
    start = max(estimate - 0.25 * width, floor)
    st, older = solve_state(grid, z, start, sigma0, h0, state=st, before=older, **kw), st
    while not _repulsive(st) and start > floor:
        start = max(start - 0.5 * width, floor)
        st, older = solve_state(grid, z, start, sigma0, h0, state=st, before=older, **kw), st
    full[start] = keep(st)
    hstep = (zmax - start) / max(int(n_contact), 1)
    last = start
    k = 1
    shrink = 1.0  # halved each time a step lost the last contact (below)
    while True:
        # a neck held beyond n_contact more steps: steps grow 1.5x (at RH <= 1e-4 the equilibrium
        # lies within 1e-3 nm of max z, and steps of that size took ~3,800 states to cross h0)
        grow = 1.5 ** max(k - 2 * int(n_contact), 0)
        d = start + hstep * k if k <= n_contact and shrink == 1.0 else last + hstep * grow * shrink
        new = solve_state(grid, z, d, sigma0, h0, state=st, detach="warm", before=older, **kw)
        if new["contact_fraction"] == 0 and st["contact_fraction"] > 0:
            if shrink > 0.5 ** BREAK_HALVINGS:
                # the contact was lost in this step: retry from the attached state with half the
                # step. Warm-started one step away, the solver can land on the detached branch
                # while the attached one still exists (a one-pixel neck at RH 1e-3, 50 GPa: lost
                # at max z + 3.6 h0 in a step of 0.6 h0, held to 4.8 h0 in steps of 0.16 h0;
                # Γ 0.56 x). A rejected try is not solved again from the undeformed wet set.
                shrink *= 0.5
                continue
            # the neck let go: the state is taken from the undeformed wet set (solve_state)
            new = solve_state(grid, z, d, sigma0, h0, state=new, **kw)
        st, older = new, st
        full[d] = keep(st)
        last = d
        k += 1
        # until the neck lets go (at RH 1e-6 a one-pixel neck held to max z + 3 h0: stopping at
        # max z + h0 lost 40-60 % of Γ), at most 40 growing steps
        if k > n_contact and (st["contact_fraction"] == 0 or k > 2 * int(n_contact) + 40):
            break
    # 3. water without hard contact; the last point lies just beyond max z + h0 (dry)
    for d in np.linspace(last, max(zmax + h0 * (1 + 1e-6), last + h0), int(n_free) + 1)[1:]:
        st = solve(float(d), st)
    # 4. refinement where the summaries are decided: ``refine`` rounds around the most tensile
    #    point and the equilibrium, then EXTRA_PULL_OFF_ROUNDS more around the most tensile point
    #    (it sits where a neck lets go, which bisection approaches by about a factor 2 per round;
    #    speed against error: benchmarks/fft_bem_pull_off_grid.py and docs/fft_bem.md)
    for r in range(int(refine) + (EXTRA_PULL_OFF_ROUNDS if refine > 0 else 0)):
        dd = np.array(sorted(full))
        pp = np.array([full[x]["pbar"] for x in dd])
        j = int(np.argmin(pp))
        new = {0.5 * (dd[a] + dd[a + 1]) for a in (j - 1, j) if 0 <= a < dd.size - 1}
        cross = np.nonzero(equilibrium_crossings(pp))[0]
        if cross.size and r < refine:
            a = int(cross[-1])
            new.add(0.5 * (dd[a] + dd[a + 1]))
        for x in sorted(new):
            below = dd[dd < x]
            solve(float(x), full[below[-1]] if below.size else None,
                  full[below[-2]] if below.size > 1 else None)
    dd = np.array(sorted(full))
    return dd, [full[x] for x in dd], grid
