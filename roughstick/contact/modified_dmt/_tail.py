"""Height buckets and the lazily sorted top tail of the heights: the pixels a level reaches.

The asperities at a level ``d`` are the connected components of ``{z >= d}``. Pixels are
counting-sorted into uniform height buckets once (:func:`bucket_sort`); only the top tail (the
pixels a level has reached) is sorted, bucket by bucket, when a level first needs it
(:func:`sort_until`). A :class:`Tail` holds the buckets, the sorted tail and its state (a
:data:`TAIL_STATE` record); the union-find (:mod:`._unionfind`) adds the tail's pixels in order.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba as nb
import numpy as np

__all__ = ["Tail", "TAIL_STATE", "bucket_sort", "count_ge", "successor", "sort_until", "n_above",
           "wet_count", "wet_event_above", "contact_event_above", "max_tie_bound", "prepare_heights"]

_NJ = dict(cache=True, nogil=True, error_model="numpy")
# no reference counting in kernels that never allocate: numba's NRT incref/decref (atomic) on
# every array passed or sliced cost ~180 ns per added pixel and much of a small fit
_NJ0 = dict(cache=True, nogil=True, error_model="numpy", _nrt=False)

#: The tail's state: pixels sorted so far, and the next bucket (downwards) still unsorted.
TAIL_STATE = np.dtype([("nsorted", np.int64), ("nextb", np.int64)], align=True)


class Tail(NamedTuple):
    """The buckets of the valid pixels and their sorted top tail (one map)."""

    start: np.ndarray  # bucket b holds entries start[b]:start[b+1] of idx and zb
    idx: np.ndarray  # raster index of each bucketed pixel
    zb: np.ndarray  # its height
    zmin: float  # the bucket of z is min(int((z - zmin) * scale), nbuck - 1)
    scale: float
    order: np.ndarray  # raster index of the k-th highest pixel (the sorted tail)
    ztail: np.ndarray  # its height
    pos: np.ndarray  # position in the tail of each raster index (-1: not sorted yet)
    state: np.ndarray  # one TAIL_STATE record


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
def sort_until(tail, d):  # pragma: no cover - compiled
    """Extend the tail order (descending height, ties in raster order) until it holds every
    pixel with z >= d: the buckets from the next unsorted one down to d's, plus at least as many
    pixels again below (fewer, larger sorts), sorted in one go."""
    start, zb, state = tail.start, tail.zb, tail.state[0]
    nbuck = start.size - 1
    b0 = state.nextb
    if b0 < 0:
        return
    bd = _bucket_of(d, tail.zmin, tail.scale, nbuck)
    if bd > b0:
        return  # every unsorted pixel has z < d
    b1 = max(bd, 0)
    need = start[b0 + 1] - start[b1]
    # take more buckets below (doubling the batch) so the next steps need no sort
    while b1 > 0 and start[b0 + 1] - start[b1] < 2 * need + 256:
        b1 -= 1
    a = start[b1]
    m = start[b0 + 1] - a
    n0 = state.nsorted
    vals = np.empty(m)
    for j in range(m):
        vals[j] = -zb[a + j]
    # stable sort by height; within equal heights the bucket order is raster order only within one
    # bucket, and equal heights share a bucket, so ties stay in raster order
    srt = np.argsort(vals, kind="mergesort")
    for j in range(m):
        q = a + srt[j]
        i = tail.idx[q]
        tail.order[n0 + j] = i
        tail.ztail[n0 + j] = zb[q]
        tail.pos[i] = n0 + j
    state.nsorted = n0 + m
    state.nextb = b1 - 1


@nb.njit(**_NJ0)
def n_above(tail, d):  # pragma: no cover - compiled
    """Number of sorted tail pixels with z >= d."""
    ztail = tail.ztail
    lo = 0
    hi = tail.state[0].nsorted
    while lo < hi:
        mid = (lo + hi) >> 1
        if ztail[mid] >= d:
            lo = mid + 1
        else:
            hi = mid
    return lo


@nb.njit(**_NJ0)
def wet_count(tail, thr):  # pragma: no cover - compiled
    """Exact number of valid pixels with ``z >= thr`` (the wetted ones at d = thr + h_water)."""
    return count_ge(tail.start, tail.zb, tail.zmin, tail.scale, thr)


@nb.njit(**_NJ0)
def wet_event_above(tail, x, hwj):  # pragma: no cover - compiled
    """Smallest distance d > x at which a pixel becomes wet (d = z + h_water for the smallest
    height z with z + h_water > x; rounded so that the pixel counts as wet at d); inf if none."""
    start, zb, zmin, scale = tail.start, tail.zb, tail.zmin, tail.scale
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
def max_tie_bound(tail, lo, hi):  # pragma: no cover - compiled
    """Upper bound on the number of valid pixels sharing one height in ``(lo, hi]``: the fullest
    bucket overlapping that range (equal heights share a bucket)."""
    start = tail.start
    nbuck = start.size - 1
    b0 = max(_bucket_of(lo, tail.zmin, tail.scale, nbuck), 0)
    b1 = _bucket_of(hi, tail.zmin, tail.scale, nbuck)
    best = 0
    for b in range(b0, b1 + 1):
        best = max(best, start[b + 1] - start[b])
    return best


@nb.njit(**_NJ0)
def contact_event_above(tail, x):  # pragma: no cover - compiled
    """Smallest tail height > x (a pixel enters contact at d = z); inf if none."""
    k = n_above(tail, np.nextafter(x, np.inf))
    if k == 0:
        return np.inf
    return tail.ztail[k - 1]


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
