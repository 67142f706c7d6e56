"""The union-find over the sorted tail that moves both ways, and the Hertz sums of a level.

The union-find adds the tail's pixels (:mod:`._tail`) in descending order and logs every merge
so that a level above the current one is reached by undoing the log (levels may come in any
order, and the result of a level does not depend on the order: tested). Each component keeps its
pixel list in one segment of a pool (int32 coordinates, unwrapped across periodic edges) so
:func:`eval_level` fits each asperity from its own pixels only: the cost grows with the number of
tail pixels, not with levels x contacting pixels. Its state is named: a :class:`UnionFind` of
record arrays (:data:`PIXEL`, :data:`COMPONENT`, :data:`LOG_ENTRY`, :data:`UNION_FIND_STATE`)
and a :class:`Pool`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba as nb
import numpy as np

from ._fit import _SIMD, fit_sphere

__all__ = ["UnionFind", "Pool", "FitScratch", "Geometry", "PIXEL", "COMPONENT", "LOG_ENTRY",
           "NEIGHBOUR", "UNION_FIND_STATE", "seek", "eval_level"]

_NJ0 = dict(cache=True, nogil=True, error_model="numpy", _nrt=False)

#: Per added pixel: its component and its coordinates in that component's (unwrapped) frame.
PIXEL = np.dtype([("comp", np.int32), ("x", np.int32), ("y", np.int32)], align=True)
#: Per component: pixels, segment of the pool and its capacity, windings round the torus, sums
#: of the coordinates, position in the list of live components.
COMPONENT = np.dtype([(f, np.int64) for f in ("size", "seg", "cap", "wrap", "sumx", "sumy", "livepos")],
                     align=True)
#: One logged change: its kind (_JOIN, _MERGE, _WRAP), the target component, the merged one, the
#: frame offset, the target's previous segment and capacity, the merged one's live position and
#: the live component moved into it.
LOG_ENTRY = np.dtype([(f, np.int64) for f in ("kind", "target", "other", "ox", "oy", "seg", "cap", "pos",
                                               "last")], align=True)
#: A neighbour of the pixel being added: its component, k's coordinates in that component's
#: frame, and the neighbour's tail position.
NEIGHBOUR = np.dtype([(f, np.int64) for f in ("comp", "x", "y", "q")], align=True)
#: Pixels added, live components, log entries and pool entries used, pixels added in all.
UNION_FIND_STATE = np.dtype([(f, np.int64) for f in ("k", "nlive", "log", "pool", "added")], align=True)
# log kinds
_MERGE, _WRAP, _JOIN = 1, 2, 3


class UnionFind(NamedTuple):
    """The components of the added tail pixels, with the log that undoes them."""

    pixels: np.ndarray  # PIXEL per tail position
    components: np.ndarray  # COMPONENT per root (a component is named by its first pixel)
    live: np.ndarray  # the live components (the asperities), any order
    log: np.ndarray  # LOG_ENTRY rows (grown by the caller when full)
    logstart: np.ndarray  # first log row of each added pixel
    pooltop: np.ndarray  # pool top before each added pixel
    state: np.ndarray  # one UNION_FIND_STATE record


class Pool(NamedTuple):
    """The components' pixel lists, one segment each (grown by the caller when full)."""

    index: np.ndarray  # tail position
    x: np.ndarray  # coordinates in the component's frame
    y: np.ndarray
    z: np.ndarray  # height


class FitScratch(NamedTuple):
    """Work arrays of the sphere fits of one level (at least the largest component + SIMD)."""

    xs: np.ndarray
    ys: np.ndarray
    hs: np.ndarray
    wt: np.ndarray
    work: np.ndarray  # (4, GRID_KEEP) of the grid search


class Geometry(NamedTuple):
    """The map's grid and contact settings."""

    ny: int
    nx: int
    dx: float
    dy: float
    K: float  # Hertz modulus 4E*/3 [Pa]
    periodic: bool
    connectivity: int


@nb.njit(**_NJ0)
def _live_remove(uf, c):  # pragma: no cover - compiled
    C, live, st = uf.components, uf.live, uf.state[0]
    p = C[c].livepos
    n = st.nlive - 1
    last = live[n]
    live[p] = last
    C[last].livepos = p
    st.nlive = n
    return p, last


@nb.njit(**_NJ0)
def _reserve(uf, pool, c, extra):  # pragma: no cover - compiled
    """Make room for ``extra`` more members in component c's segment (moving it to a new
    segment of twice the size at the pool top when full; the old one is kept for the undo).
    Returns the old (seg, cap)."""
    C, st = uf.components, uf.state[0]
    pi, px, py, pz = pool.index, pool.x, pool.y, pool.z
    seg = C[c].seg
    cap = C[c].cap
    size = C[c].size
    if size + extra > cap:
        ncap = 2 * (size + extra)
        top = st.pool
        for u in range(size):
            pi[top + u] = pi[seg + u]
            px[top + u] = px[seg + u]
            py[top + u] = py[seg + u]
            pz[top + u] = pz[seg + u]
        C[c].seg = top
        C[c].cap = ncap
        st.pool = top + ncap
    return seg, cap


@nb.njit(**_NJ0)
def _add_pixel(k, uf, pool, tail, geo, nbuf):  # pragma: no cover - compiled
    """Add tail pixel ``k``: a new component, or joined to the largest neighbouring component
    with the others merged into it (all logged). The caller guarantees room in the log and the
    pool (:func:`seek`)."""
    P, C, live, LOG, st = uf.pixels, uf.components, uf.live, uf.log, uf.state[0]
    pi, px, py, pz = pool.index, pool.x, pool.y, pool.z
    order, ztail, pos = tail.order, tail.ztail, tail.pos
    nx, ny, periodic, connectivity = geo.nx, geo.ny, geo.periodic, geo.connectivity
    idx = order[k]
    r0 = idx // nx
    c0 = idx - r0 * nx
    nd = 8 if connectivity == 8 else 4
    nn = 0
    for t in range(nd):
        if t == 0:
            sy, sx = 0, 1
        elif t == 1:
            sy, sx = 1, 0
        elif t == 2:
            sy, sx = 0, -1
        elif t == 3:
            sy, sx = -1, 0
        elif t == 4:
            sy, sx = 1, 1
        elif t == 5:
            sy, sx = 1, -1
        elif t == 6:
            sy, sx = -1, 1
        else:
            sy, sx = -1, -1
        rr = r0 + sy
        cc = c0 + sx
        if periodic:
            if rr < 0:
                rr += ny
            elif rr >= ny:
                rr -= ny
            if cc < 0:
                cc += nx
            elif cc >= nx:
                cc -= nx
        elif rr < 0 or rr >= ny or cc < 0 or cc >= nx:
            continue
        q = pos[rr * nx + cc]
        if q < 0 or q >= k:
            continue
        # k's coordinates in q's component frame: q's minus the step from k to q
        nbuf[nn].q = q
        nbuf[nn].comp = P[q].comp
        nbuf[nn].x = P[q].x - sx
        nbuf[nn].y = P[q].y - sy
        nn += 1
    lt = st.log
    z = ztail[k]
    if nn == 0:
        top = st.pool
        P[k].comp = k
        P[k].x = 0
        P[k].y = 0
        C[k].size = 1
        C[k].seg = top
        C[k].cap = 4
        C[k].wrap = 0
        C[k].sumx = 0
        C[k].sumy = 0
        pi[top] = k
        px[top] = 0
        py[top] = 0
        pz[top] = z
        st.pool = top + 4
        n = st.nlive
        live[n] = k
        C[k].livepos = n
        st.nlive = n + 1
        return
    # target: the largest neighbouring component (ties: the smaller id)
    tgt = nbuf[0].comp
    ti = 0
    for u in range(1, nn):
        b = nbuf[u].comp
        if C[b].size > C[tgt].size or (C[b].size == C[tgt].size and b < tgt):
            tgt = b
            ti = u
    ux = nbuf[ti].x
    uy = nbuf[ti].y
    oseg, ocap = _reserve(uf, pool, tgt, 1)
    s = C[tgt].size
    sg = C[tgt].seg
    pi[sg + s] = k
    px[sg + s] = ux
    py[sg + s] = uy
    pz[sg + s] = z
    C[tgt].size = s + 1
    C[tgt].sumx += ux
    C[tgt].sumy += uy
    P[k].comp = tgt
    P[k].x = ux
    P[k].y = uy
    LOG[lt].kind = _JOIN
    LOG[lt].target = tgt
    LOG[lt].seg = oseg
    LOG[lt].cap = ocap
    lt += 1
    # merge the other neighbouring components into the target (each once)
    for u in range(nn):
        b = nbuf[u].comp
        if b == tgt:
            continue
        if P[nbuf[u].q].comp != b:
            continue  # already merged through an earlier neighbour
        # b's frame -> tgt's frame: k sits at (ux, uy) in tgt's and at nb_u[u] in b's
        ox = ux - nbuf[u].x
        oy = uy - nbuf[u].y
        ss = C[b].size
        oseg, ocap = _reserve(uf, pool, tgt, ss)
        bs = C[tgt].size
        sg = C[tgt].seg
        s0 = C[b].seg
        for v in range(ss):
            j = pi[s0 + v]
            vx = px[s0 + v] + ox
            vy = py[s0 + v] + oy
            pi[sg + bs + v] = j
            px[sg + bs + v] = vx
            py[sg + bs + v] = vy
            pz[sg + bs + v] = pz[s0 + v]
            P[j].comp = tgt
            P[j].x = vx
            P[j].y = vy
        C[tgt].size = bs + ss
        C[tgt].wrap += C[b].wrap
        C[tgt].sumx += C[b].sumx + ox * ss
        C[tgt].sumy += C[b].sumy + oy * ss
        p, last = _live_remove(uf, b)
        LOG[lt].kind = _MERGE
        LOG[lt].target = tgt
        LOG[lt].other = b
        LOG[lt].ox = ox
        LOG[lt].oy = oy
        LOG[lt].seg = oseg
        LOG[lt].cap = ocap
        LOG[lt].pos = p
        LOG[lt].last = last
        lt += 1
    # cycles: a neighbour now in tgt whose coordinates disagree with k's + step winds round the
    # torus (periodic maps only)
    for u in range(nn):
        q = nbuf[u].q
        if P[q].comp == tgt and nbuf[u].comp == tgt and (nbuf[u].x != ux or nbuf[u].y != uy):
            C[tgt].wrap += 1
            LOG[lt].kind = _WRAP
            LOG[lt].target = tgt
            lt += 1
        elif nbuf[u].comp != tgt:
            # merged component: its other edges to k were checked through the offset, except
            # a second edge into the same component (two neighbours of k in one component b)
            for w in range(u):
                if nbuf[w].comp == nbuf[u].comp and (nbuf[w].x != nbuf[u].x or nbuf[w].y != nbuf[u].y):
                    C[tgt].wrap += 1
                    LOG[lt].kind = _WRAP
                    LOG[lt].target = tgt
                    lt += 1
                    break
    st.log = lt


@nb.njit(**_NJ0)
def _undo_pixel(k, uf, pool):  # pragma: no cover - compiled
    """Undo the addition of tail pixel ``k`` (the last one added): its log rows in reverse."""
    P, C, live, LOG, st = uf.pixels, uf.components, uf.live, uf.log, uf.state[0]
    logstart, pooltop = uf.logstart, uf.pooltop
    pi, px, py = pool.index, pool.x, pool.y
    lt = st.log
    created = lt == logstart[k]
    while lt > logstart[k]:
        lt -= 1
        kind = LOG[lt].kind
        if kind == _WRAP:
            C[LOG[lt].target].wrap -= 1
            continue
        if kind == _JOIN:
            tgt = LOG[lt].target
            s = C[tgt].size - 1
            sg = C[tgt].seg
            C[tgt].sumx -= px[sg + s]
            C[tgt].sumy -= py[sg + s]
            C[tgt].size = s
            C[tgt].seg = LOG[lt].seg
            C[tgt].cap = LOG[lt].cap
            continue
        big = LOG[lt].target
        small = LOG[lt].other
        ox = LOG[lt].ox
        oy = LOG[lt].oy
        p = LOG[lt].pos
        last = LOG[lt].last
        ss = C[small].size
        C[big].size -= ss
        C[big].wrap -= C[small].wrap
        C[big].sumx -= C[small].sumx + ox * ss
        C[big].sumy -= C[small].sumy + oy * ss
        C[big].seg = LOG[lt].seg
        C[big].cap = LOG[lt].cap
        s0 = C[small].seg
        for u in range(ss):
            j = pi[s0 + u]
            P[j].comp = small
            P[j].x = px[s0 + u]
            P[j].y = py[s0 + u]
        n = st.nlive
        live[n] = last
        C[last].livepos = n
        live[p] = small
        C[small].livepos = p
        st.nlive = n + 1
    st.log = lt
    st.pool = pooltop[k]
    if created:
        st.nlive -= 1  # k's own component is the last live one


@nb.njit(**_NJ0)
def seek(target, uf, pool, tail, geo, nbuf):  # pragma: no cover - compiled
    """Move the state to ``target`` added pixels. Returns 0, 1 (log full) or 2 (pool full)."""
    LOG, st, logstart, pooltop, pi = uf.log, uf.state[0], uf.logstart, uf.pooltop, pool.index
    k = st.k
    while k > target:
        k -= 1
        _undo_pixel(k, uf, pool)
    while k < target:
        if st.log + 20 > LOG.shape[0]:
            st.k = k
            return 1
        # room for the worst case of one pixel: 9 segments of twice the merged size (<= k + 1)
        if st.pool + 18 * (k + 1) + 4 > pi.size:
            st.k = k
            return 2
        logstart[k] = st.log
        pooltop[k] = st.pool
        st.added += 1
        _add_pixel(k, uf, pool, tail, geo, nbuf)
        k += 1
    st.k = k
    return 0


@nb.njit(**_NJ0)
def eval_level(uf, pool, d, geo, fit):  # pragma: no cover - compiled
    """Sums over the asperities (live components, in live order) at distance d.

    ``fit``'s ``xs, ys, hs, wt`` are scratch arrays of at least (largest component + SIMD)
    entries. Returns (force, hertz_area, foot_area, err2_area, n_comp, n_wrap).
    """
    C, live, st = uf.components, uf.live, uf.state[0]
    px, py, pz = pool.x, pool.y, pool.z
    dx, dy, K = geo.dx, geo.dy, geo.K
    xs, ys, hs, wt, M = fit.xs, fit.ys, fit.hs, fit.wt, fit.work
    nlive = st.nlive
    force = 0.0
    harea = 0.0
    farea = 0.0
    e2a = 0.0
    nwrap = 0
    pix = dx * dy
    for ci in range(nlive):
        c = live[ci]
        m = C[c].size
        af = math.sqrt(m * pix / math.pi)
        mx = C[c].sumx * dx / m
        my = C[c].sumy * dy / m
        s0 = C[c].seg
        for t in range(m):
            xs[t] = (px[s0 + t] * dx - mx) / af
            ys[t] = (py[s0 + t] * dy - my) / af
            hs[t] = (pz[s0 + t] - d) / af
            wt[t] = 1.0
        mp = (m + _SIMD - 1) // _SIMD * _SIMD
        for t in range(m, mp):
            xs[t] = 0.0
            ys[t] = 0.0
            hs[t] = 0.0
            wt[t] = 0.0
        tt, cost, x0, y0 = fit_sphere(xs[:mp], ys[:mp], hs[:mp], wt[:mp], m, 0.5 * dx / af,
                                          0.5 * dy / af, M)
        area = m * pix
        force += K * af * af * tt * math.sqrt(0.5 * (1.0 + tt * tt))
        harea += 0.5 * math.pi * af * af * (1.0 + tt * tt)
        farea += area
        e2a += cost / m * af * af * area
        if C[c].wrap > 0:
            nwrap += 1
    return force, harea, farea, e2a, nlive, nwrap


