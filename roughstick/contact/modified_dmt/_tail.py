"""Height buckets, the lazily sorted top tail, and the union-find that moves both ways.

The asperities at a level ``d`` are the connected components of ``{z >= d}``. Pixels are
counting-sorted into uniform height buckets once; only the top tail (the pixels a level has
reached) is sorted, bucket by bucket, when a level first needs it. The union-find adds the tail's
pixels in descending order and logs every merge so that a level above the current one is reached
by undoing the log (levels may come in any order, and the result of a level does not depend on
the order: tested). Each component keeps its pixel list in one segment of a pool (int32
coordinates, unwrapped across periodic edges) so :func:`eval_level` fits each asperity from its
own pixels only: the cost grows with the number of tail pixels, not with levels x contacting
pixels.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ._fit import _SIMD, fit_sphere

__all__ = ["bucket_sort", "count_ge", "successor", "eval_level", "prepare_heights"]

# scalar state slots
_K, _NLIVE, _LOG, _NSORTED, _NEXTB, _POOL = range(6)
# per-component columns of C (int64)
_SIZE, _SEG, _CAP, _WRAP, _SUMX, _SUMY, _LIVEPOS = range(7)
# log kinds
_L_MERGE, _L_WRAP, _L_JOIN = 1, 2, 3
_NJ = dict(cache=True, nogil=True, error_model="numpy")
# no reference counting in kernels that never allocate: numba's NRT incref/decref (atomic) on
# every array passed or sliced cost ~180 ns per added pixel and much of a small fit
_NJ0 = dict(cache=True, nogil=True, error_model="numpy", _nrt=False)


@nb.njit(**_NJ)
def bucket_sort(zflat, start, idx, zb):  # pragma: no cover - compiled
    """Counting sort of the valid pixels into ``start.size - 1`` uniform height buckets.

    Fills ``start`` (bucket b holds entries ``start[b]:start[b+1]``), ``idx`` (raster index,
    raster order within a bucket) and ``zb`` (their heights). Returns ``(zmin, zmax, scale,
    nvalid, sigma)``; the bucket of z is ``min(int((z - zmin) * scale), nbuck - 1)``, monotone.
    """
    n = zflat.size
    nbuck = start.size - 1
    zmin = np.inf
    zmax = -np.inf
    s1 = 0.0
    nv = 0
    for i in range(n):
        z = zflat[i]
        if z == z:
            zmin = min(zmin, z)
            zmax = max(zmax, z)
            s1 += z
            nv += 1
    mean = s1 / max(nv, 1)
    s2 = 0.0
    for i in range(n):
        z = zflat[i]
        if z == z:
            s2 += (z - mean) * (z - mean)
    sigma = math.sqrt(s2 / max(nv, 1))
    span = zmax - zmin
    scale = nbuck / span if span > 0.0 else 0.0
    start[:] = 0
    for i in range(n):
        z = zflat[i]
        if z == z:
            b = min(int((z - zmin) * scale), nbuck - 1)
            start[b + 1] += 1
    for b in range(nbuck):
        start[b + 1] += start[b]
    # scatter, using start[b] as the cursor of bucket b, then shift back
    for i in range(n):
        z = zflat[i]
        if z == z:
            b = min(int((z - zmin) * scale), nbuck - 1)
            j = start[b]
            idx[j] = i
            zb[j] = z
            start[b] = j + 1
    for b in range(nbuck, 0, -1):
        start[b] = start[b - 1]
    start[0] = 0
    return zmin, zmax, scale, nv, sigma


@nb.njit(**_NJ0)
def _bucket_of(z, zmin, scale, nbuck):  # pragma: no cover - compiled
    if not (z >= zmin):
        return -1
    x = (z - zmin) * scale
    if x >= nbuck:
        return nbuck - 1
    return int(x)


@nb.njit(**_NJ0)
def count_ge(start, zb, zmin, scale, thr):  # pragma: no cover - compiled
    """Exact number of valid pixels with ``z >= thr`` (NaN thr: 0)."""
    nbuck = start.size - 1
    if thr != thr:
        return 0
    b = _bucket_of(thr, zmin, scale, nbuck)
    if b < 0:
        return start[nbuck]
    c = start[nbuck] - start[b + 1]
    for j in range(start[b], start[b + 1]):
        if zb[j] >= thr:
            c += 1
    return c


@nb.njit(**_NJ0)
def successor(start, zb, zmin, scale, thr):  # pragma: no cover - compiled
    """Smallest valid height >= thr (inf if none)."""
    nbuck = start.size - 1
    b = max(_bucket_of(thr, zmin, scale, nbuck), 0)
    best = np.inf
    while b < nbuck:
        for j in range(start[b], start[b + 1]):
            z = zb[j]
            if z >= thr and z < best:
                best = z
        if best < np.inf:
            return best
        b += 1
    return best


@nb.njit(**_NJ)
def _sort_until(start, idx, zb, zmin, scale, scal, order, ztail, pos, d):  # pragma: no cover - compiled
    """Extend the tail order (descending height, ties in raster order) until it holds every
    pixel with z >= d: the buckets from the next unsorted one down to d's, plus at least as many
    pixels again below (fewer, larger sorts), sorted in one go."""
    nbuck = start.size - 1
    b0 = scal[_NEXTB]
    if b0 < 0:
        return
    bd = _bucket_of(d, zmin, scale, nbuck)
    if bd > b0:
        return  # every unsorted pixel has z < d
    b1 = max(bd, 0)
    need = start[b0 + 1] - start[b1]
    # take more buckets below (doubling the batch) so the next steps need no sort
    while b1 > 0 and start[b0 + 1] - start[b1] < 2 * need + 256:
        b1 -= 1
    a = start[b1]
    m = start[b0 + 1] - a
    n0 = scal[_NSORTED]
    vals = np.empty(m)
    for j in range(m):
        vals[j] = -zb[a + j]
    # stable sort by height; within equal heights the bucket order is raster order only within one
    # bucket, and equal heights share a bucket, so ties stay in raster order
    srt = np.argsort(vals, kind="mergesort")
    for j in range(m):
        q = a + srt[j]
        i = idx[q]
        order[n0 + j] = i
        ztail[n0 + j] = zb[q]
        pos[i] = n0 + j
    scal[_NSORTED] = n0 + m
    scal[_NEXTB] = b1 - 1


@nb.njit(**_NJ0)
def _n_above(ztail, nsorted, d):  # pragma: no cover - compiled
    """Number of sorted tail pixels with z >= d."""
    lo = 0
    hi = nsorted
    while lo < hi:
        mid = (lo + hi) >> 1
        if ztail[mid] >= d:
            lo = mid + 1
        else:
            hi = mid
    return lo


# ------------------------------------------------------------------------------------------
# union-find over the tail that moves both ways (logged merges, undone LIFO)


@nb.njit(**_NJ0)
def _live_remove(C, live, scal, c):  # pragma: no cover - compiled
    p = C[c, _LIVEPOS]
    n = scal[_NLIVE] - 1
    last = live[n]
    live[p] = last
    C[last, _LIVEPOS] = p
    scal[_NLIVE] = n
    return p, last


@nb.njit(**_NJ0)
def _reserve(C, c, extra, scal, pi, px, py, pz):  # pragma: no cover - compiled
    """Make room for ``extra`` more members in component c's segment (moving it to a new
    segment of twice the size at the pool top when full; the old one is kept for the undo).
    Returns the old (seg, cap)."""
    seg = C[c, _SEG]
    cap = C[c, _CAP]
    size = C[c, _SIZE]
    if size + extra > cap:
        ncap = 2 * (size + extra)
        top = scal[_POOL]
        for u in range(size):
            pi[top + u] = pi[seg + u]
            px[top + u] = px[seg + u]
            py[top + u] = py[seg + u]
            pz[top + u] = pz[seg + u]
        C[c, _SEG] = top
        C[c, _CAP] = ncap
        scal[_POOL] = top + ncap
    return seg, cap


@nb.njit(**_NJ0)
def _add_pixel(k, P, C, live, scal, LOG, order, ztail, pos, pi, px, py, pz, nx, ny, periodic,
               connectivity, nbuf):  # pragma: no cover - compiled
    """Add tail pixel ``k``: a new component, or joined to the largest neighbouring component
    with the others merged into it (all logged). The caller guarantees room in the log and the
    pool (see :func:`_pool_need`)."""
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
        nbuf[3, nn] = q
        nbuf[0, nn] = P[q, 0]
        nbuf[1, nn] = P[q, 1] - sx
        nbuf[2, nn] = P[q, 2] - sy
        nn += 1
    lt = scal[_LOG]
    z = ztail[k]
    if nn == 0:
        top = scal[_POOL]
        P[k, 0] = k
        P[k, 1] = 0
        P[k, 2] = 0
        C[k, _SIZE] = 1
        C[k, _SEG] = top
        C[k, _CAP] = 4
        C[k, _WRAP] = 0
        C[k, _SUMX] = 0
        C[k, _SUMY] = 0
        pi[top] = k
        px[top] = 0
        py[top] = 0
        pz[top] = z
        scal[_POOL] = top + 4
        n = scal[_NLIVE]
        live[n] = k
        C[k, _LIVEPOS] = n
        scal[_NLIVE] = n + 1
        return
    # target: the largest neighbouring component (ties: the smaller id)
    tgt = nbuf[0, 0]
    ti = 0
    for u in range(1, nn):
        b = nbuf[0, u]
        if C[b, _SIZE] > C[tgt, _SIZE] or (C[b, _SIZE] == C[tgt, _SIZE] and b < tgt):
            tgt = b
            ti = u
    ux = nbuf[1, ti]
    uy = nbuf[2, ti]
    oseg, ocap = _reserve(C, tgt, 1, scal, pi, px, py, pz)
    s = C[tgt, _SIZE]
    sg = C[tgt, _SEG]
    pi[sg + s] = k
    px[sg + s] = ux
    py[sg + s] = uy
    pz[sg + s] = z
    C[tgt, _SIZE] = s + 1
    C[tgt, _SUMX] += ux
    C[tgt, _SUMY] += uy
    P[k, 0] = tgt
    P[k, 1] = ux
    P[k, 2] = uy
    LOG[lt, 0] = _L_JOIN
    LOG[lt, 1] = tgt
    LOG[lt, 5] = oseg
    LOG[lt, 6] = ocap
    lt += 1
    # merge the other neighbouring components into the target (each once)
    for u in range(nn):
        b = nbuf[0, u]
        if b == tgt:
            continue
        if P[nbuf[3, u], 0] != b:
            continue  # already merged through an earlier neighbour
        # b's frame -> tgt's frame: k sits at (ux, uy) in tgt's and at nb_u[u] in b's
        ox = ux - nbuf[1, u]
        oy = uy - nbuf[2, u]
        ss = C[b, _SIZE]
        oseg, ocap = _reserve(C, tgt, ss, scal, pi, px, py, pz)
        bs = C[tgt, _SIZE]
        sg = C[tgt, _SEG]
        s0 = C[b, _SEG]
        for v in range(ss):
            j = pi[s0 + v]
            vx = px[s0 + v] + ox
            vy = py[s0 + v] + oy
            pi[sg + bs + v] = j
            px[sg + bs + v] = vx
            py[sg + bs + v] = vy
            pz[sg + bs + v] = pz[s0 + v]
            P[j, 0] = tgt
            P[j, 1] = vx
            P[j, 2] = vy
        C[tgt, _SIZE] = bs + ss
        C[tgt, _WRAP] += C[b, _WRAP]
        C[tgt, _SUMX] += C[b, _SUMX] + ox * ss
        C[tgt, _SUMY] += C[b, _SUMY] + oy * ss
        p, last = _live_remove(C, live, scal, b)
        LOG[lt, 0] = _L_MERGE
        LOG[lt, 1] = tgt
        LOG[lt, 2] = b
        LOG[lt, 3] = ox
        LOG[lt, 4] = oy
        LOG[lt, 5] = oseg
        LOG[lt, 6] = ocap
        LOG[lt, 7] = p
        LOG[lt, 8] = last
        lt += 1
    # cycles: a neighbour now in tgt whose coordinates disagree with k's + step winds round the
    # torus (periodic maps only)
    for u in range(nn):
        q = nbuf[3, u]
        if P[q, 0] == tgt and nbuf[0, u] == tgt and (nbuf[1, u] != ux or nbuf[2, u] != uy):
            C[tgt, _WRAP] += 1
            LOG[lt, 0] = _L_WRAP
            LOG[lt, 1] = tgt
            lt += 1
        elif nbuf[0, u] != tgt:
            # merged component: its other edges to k were checked through the offset, except
            # a second edge into the same component (two neighbours of k in one component b)
            for w in range(u):
                if nbuf[0, w] == nbuf[0, u] and (nbuf[1, w] != nbuf[1, u] or nbuf[2, w] != nbuf[2, u]):
                    C[tgt, _WRAP] += 1
                    LOG[lt, 0] = _L_WRAP
                    LOG[lt, 1] = tgt
                    lt += 1
                    break
    scal[_LOG] = lt


@nb.njit(**_NJ0)
def _undo_pixel(k, P, C, live, scal, LOG, logstart, pooltop, pi, px, py):  # pragma: no cover
    """Undo the addition of tail pixel ``k`` (the last one added): its log rows in reverse."""
    lt = scal[_LOG]
    created = lt == logstart[k]
    while lt > logstart[k]:
        lt -= 1
        kind = LOG[lt, 0]
        if kind == _L_WRAP:
            C[LOG[lt, 1], _WRAP] -= 1
            continue
        if kind == _L_JOIN:
            tgt = LOG[lt, 1]
            s = C[tgt, _SIZE] - 1
            sg = C[tgt, _SEG]
            C[tgt, _SUMX] -= px[sg + s]
            C[tgt, _SUMY] -= py[sg + s]
            C[tgt, _SIZE] = s
            C[tgt, _SEG] = LOG[lt, 5]
            C[tgt, _CAP] = LOG[lt, 6]
            continue
        big = LOG[lt, 1]
        small = LOG[lt, 2]
        ox = LOG[lt, 3]
        oy = LOG[lt, 4]
        p = LOG[lt, 7]
        last = LOG[lt, 8]
        ss = C[small, _SIZE]
        C[big, _SIZE] -= ss
        C[big, _WRAP] -= C[small, _WRAP]
        C[big, _SUMX] -= C[small, _SUMX] + ox * ss
        C[big, _SUMY] -= C[small, _SUMY] + oy * ss
        C[big, _SEG] = LOG[lt, 5]
        C[big, _CAP] = LOG[lt, 6]
        s0 = C[small, _SEG]
        for u in range(ss):
            j = pi[s0 + u]
            P[j, 0] = small
            P[j, 1] = px[s0 + u]
            P[j, 2] = py[s0 + u]
        n = scal[_NLIVE]
        live[n] = last
        C[last, _LIVEPOS] = n
        live[p] = small
        C[small, _LIVEPOS] = p
        scal[_NLIVE] = n + 1
    scal[_LOG] = lt
    scal[_POOL] = pooltop[k]
    if created:
        scal[_NLIVE] -= 1  # k's own component is the last live one


@nb.njit(**_NJ0)
def _pool_need(k, P, C, order, pos, nx, ny, periodic):  # pragma: no cover - compiled
    """Upper bound of the pool entries adding pixel ``k`` can take: a new segment of twice the
    merged size per join or merge (at most 9), i.e. 18 x (1 + the neighbours' sizes), + 4."""
    idx = order[k]
    r0 = idx // nx
    c0 = idx - r0 * nx
    S = 1
    for rr in range(r0 - 1, r0 + 2):
        for cc in range(c0 - 1, c0 + 2):
            r1 = rr
            c1 = cc
            if periodic:
                r1 = r1 % ny
                c1 = c1 % nx
            elif r1 < 0 or r1 >= ny or c1 < 0 or c1 >= nx:
                continue
            q = pos[r1 * nx + c1]
            if q >= 0 and q < k:
                S += C[P[q, 0], _SIZE]
    return 18 * S + 4


@nb.njit(**_NJ0)
def _seek(target, P, C, live, scal, LOG, logstart, pooltop, order, ztail, pos, pi, px, py, pz, nx, ny,
          periodic, connectivity, nbuf):  # pragma: no cover - compiled
    """Move the state to ``target`` added pixels. Returns 0, 1 (log full) or 2 (pool full)."""
    k = scal[_K]
    while k > target:
        k -= 1
        _undo_pixel(k, P, C, live, scal, LOG, logstart, pooltop, pi, px, py)
    while k < target:
        if scal[_LOG] + 20 > LOG.shape[0]:
            scal[_K] = k
            return 1
        # room for the worst case of one pixel: 9 segments of twice the merged size (<= k + 1)
        if scal[_POOL] + 18 * (k + 1) + 4 > pi.size:
            scal[_K] = k
            return 2
        logstart[k] = scal[_LOG]
        pooltop[k] = scal[_POOL]
        scal[7] += 1
        _add_pixel(k, P, C, live, scal, LOG, order, ztail, pos, pi, px, py, pz, nx, ny, periodic,
                   connectivity, nbuf)
        k += 1
    scal[_K] = k
    return 0


@nb.njit(cache=True, nogil=True, error_model="numpy", _nrt=False)
def eval_level(C, live, scal, px, py, pz, d, dx, dy, K, xs, ys, hs, wt, M):  # pragma: no cover
    """Sums over the asperities (live components, in live order) at distance d.

    ``xs, ys, hs, wt`` are scratch arrays of at least (largest component + SIMD) entries.
    Returns (force, hertz_area, foot_area, err2_area, n_comp, n_wrap).
    """
    nlive = scal[_NLIVE]
    force = 0.0
    harea = 0.0
    farea = 0.0
    e2a = 0.0
    nwrap = 0
    pix = dx * dy
    for ci in range(nlive):
        c = live[ci]
        m = C[c, _SIZE]
        af = math.sqrt(m * pix / math.pi)
        mx = C[c, _SUMX] * dx / m
        my = C[c, _SUMY] * dy / m
        s0 = C[c, _SEG]
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
        if C[c, _WRAP] > 0:
            nwrap += 1
    return force, harea, farea, e2a, nlive, nwrap


@nb.njit(**_NJ)
def _grow2(a, n):  # pragma: no cover - compiled
    b = np.empty((n, a.shape[1]), a.dtype)
    b[: a.shape[0]] = a
    return b


@nb.njit(**_NJ)
def _grow1(a, n):  # pragma: no cover - compiled
    b = np.empty(n, a.dtype)
    b[: a.size] = a
    return b


@nb.njit(**_NJ)
def _find(Dv, ordd, n, d):  # pragma: no cover - compiled
    """Index (into the level arrays) of level d, or -1; ``ordd[:n]`` sorts the levels by d."""
    lo = 0
    hi = n
    while lo < hi:
        mid = (lo + hi) >> 1
        if Dv[ordd[mid]] < d:
            lo = mid + 1
        else:
            hi = mid
    if lo < n and Dv[ordd[lo]] == d:
        return ordd[lo]
    return -1


@nb.njit(**_NJ0)
def _wet_event_above(x, hwj, start, zb, zmin, scale):  # pragma: no cover - compiled
    """Smallest distance d > x at which a pixel becomes wet (d = z + h_water for the smallest
    height z with z + h_water > x; rounded so that the pixel counts as wet at d); inf if none."""
    ze = successor(start, zb, zmin, scale, x - hwj)
    for _ in range(4):
        if not (ze < np.inf):
            return np.inf
        de = ze + hwj
        while de - hwj > ze:
            de = np.nextafter(de, -np.inf)
        if de > x:
            return de
        ze = successor(start, zb, zmin, scale, np.nextafter(ze, np.inf))
    return np.inf


@nb.njit(**_NJ0)
def max_tie_bound(start, zmin, scale, lo, hi):  # pragma: no cover - compiled
    """Upper bound on the number of valid pixels sharing one height in ``(lo, hi]``: the fullest
    bucket overlapping that range (equal heights share a bucket)."""
    nbuck = start.size - 1
    b0 = max(_bucket_of(lo, zmin, scale, nbuck), 0)
    b1 = _bucket_of(hi, zmin, scale, nbuck)
    best = 0
    for b in range(b0, b1 + 1):
        best = max(best, start[b + 1] - start[b])
    return best


@nb.njit(**_NJ0)
def _contact_event_above(x, ztail, nsorted):  # pragma: no cover - compiled
    """Smallest tail height > x (a pixel enters contact at d = z); inf if none."""
    k = _n_above(ztail, nsorted, np.nextafter(x, np.inf))
    if k == 0:
        return np.inf
    return ztail[k - 1]


def prepare_heights(z):
    """Mean-referred float64 heights (NaN kept) and the number of valid pixels."""
    z = np.ascontiguousarray(z, dtype=np.float64)
    mean = z.ravel().mean()
    if np.isfinite(mean):  # then every pixel is finite
        return z - mean, z.size
    valid = np.isfinite(z)
    nvalid = int(valid.sum())
    if nvalid == 0:
        raise ValueError("the height map has no finite pixel (all NaN/inf).")
    mean = z[valid].mean()
    return np.ascontiguousarray(np.where(valid, z - mean, np.nan)), nvalid
