"""Compiled kernels of the rough-surface modified DMT (Eqs. 16-23), plain numpy/numba on SI floats.

One pass over the heights in descending order with a union-find gives the asperities (connected
components of ``{z >= d}``) at every distance level ``d`` (DESIGN.md §4). Each asperity is fitted
with the constrained sphere of Eqs. 19-21 by a projected Levenberg-Marquardt iteration with an
analytic Jacobian; Hertz (Eqs. 10-11) gives its repulsive force and contact area. The water term
(the area ``A{z >= d - h_water}``) is a complementary cumulative count of the heights, done once
for all distances and all humidities.

Conventions shared with :mod:`roughstick.contact._rough_reference` (the literal slow implementation):

* heights are referred to their mean over the valid (non-NaN) pixels: ``d`` is the distance from
  the flat to the mean plane; NaN pixels are never part of an asperity nor of the wetted area,
  and the apparent area is the area of the valid pixels;
* a pixel belongs to the footprint when ``z >= d`` (ties included);
* 4-connectivity (pixels sharing an edge) by default, 8-connectivity on request; periodic maps
  connect across their edges and their asperities are unwrapped;
* the fit's unknowns are the centre (x0, y0) and the cap height ``t = delta / a_f`` in
  ``[0, 1]``, where ``a_f = sqrt(A / pi)`` is the footprint radius and ``delta`` the Hertz
  interference; ``R = a_f (1 + t^2) / (2 t)`` and ``z0`` follow from Eq. 20. ``t = 0`` is a
  plateau (``R`` infinite, zero force, Hertz area A/2), ``t = 1`` the hemisphere ``R = a_f``,
  the largest cap Eq. 20 allows. This parametrisation of Eq. 21 is smooth on the whole closed
  interval (``R`` or ``1/R`` are not: their derivatives blow up at the hemisphere). The start
  is the footprint centroid and ``t = min(2 mean(h) / a_f, 0.999)`` (a paraboloid cap's mean
  height is half its height);
* where a pixel lies outside the sphere's projection (``r > R``) the profile is taken at ``r = R``;
* footprints of one or two pixels (under-determined fits) use the sphere centred on the
  footprint centroid whose height at the pixels equals their mean height above ``d``.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from .._core.conventions import CURVE_VARIABLES
from ._rough_fit import _WS_ROWS, _fit_level, _fit_sphere, fit_workspace  # noqa: F401  (tests use them here)

__all__: list[str] = []


@nb.njit(cache=True, nogil=True)
def _find(parent, vx, vy, stack, i):  # pragma: no cover - compiled
    """Root of ``i`` with path compression; ``vx, vy`` become displacements to the root."""
    top = 0
    r = i
    while parent[r] != r:
        stack[top] = r
        top += 1
        r = parent[r]
    # compress, nearest-to-root first so the parent's displacement is already to the root
    for t in range(top - 1, -1, -1):
        u = stack[t]
        p = parent[u]
        if p != r:
            vx[u] += vx[p]
            vy[u] += vy[p]
            parent[u] = r
    return r


@nb.njit(cache=True, nogil=True)
def _hertz_levels(
    zflat, ny, nx, order, levels, dx, dy, K, periodic, connectivity, warm=False
):  # pragma: no cover
    """Hertz part of Eq. 16 at every level, in one descending pass with a union-find.

    Parameters
    ----------
    zflat : (ny*nx,) float64, mean-referred heights (NaN allowed).
    order : (T,) int64, raster indices of the pixels with ``z >= levels[-1]``, by descending
        height (ties in raster order).
    levels : (D,) float64, strictly descending distances.
    warm : bool
        Start the fit of an asperity whose pixels did not change since the previous level from
        that level's solution (one local refinement instead of two starts; falls back to the
        two cold starts if it does not converge). False: every fit from the two cold starts,
        so the values at a distance do not depend on the other distances of the grid.

    Returns
    -------
    force, hertz_area, foot_area, err2_area, n_comp, wraps : (D,) arrays
        Sum over asperities of the Hertz force [N], Hertz contact area [m2], footprint area [m2],
        squared fit error times footprint area [m4], number of asperities, and the number of
        asperities that wrap all the way round a periodic map.
    """
    T = order.size
    D = levels.size
    pos = np.full(ny * nx, -1, np.int64)
    for k in range(T):
        pos[order[k]] = k
    parent = np.arange(T)
    vx = np.zeros(T, np.int64)
    vy = np.zeros(T, np.int64)
    wrap = np.zeros(T, np.bool_)
    stack = np.empty(T, np.int64)
    count = np.zeros(T, np.int64)
    start = np.zeros(T + 1, np.int64)
    members = np.empty(T, np.int64)
    xs = np.empty(T)
    ys = np.empty(T)
    hs = np.empty(T)
    ws = np.empty((_WS_ROWS, 5))
    iw = np.empty(3, np.int64)
    free = np.empty(3, np.bool_)
    roots = np.empty(T, np.int64)
    fit = np.empty((T, 2))
    # warm starts: pixel count of each root's component at its last fit (0: never fitted) and
    # that fit's solution (x0, y0, t) in the footprint's units
    pm = np.zeros(T, np.int64)
    sol = np.zeros((T, 3))
    if connectivity == 8:
        ndir = 4
    else:
        ndir = 2
    # half of the neighbourhood is enough: each pair is met once, from the later pixel
    drs = np.array([0, 1, 0, -1, 1, 1, -1, -1])
    dcs = np.array([1, 0, -1, 0, 1, -1, 1, -1])
    nd = 2 * ndir
    force = np.zeros(D)
    harea = np.zeros(D)
    farea = np.zeros(D)
    e2a = np.zeros(D)
    ncomp = np.zeros(D, np.int64)
    nwrap = np.zeros(D, np.int64)
    pix = dx * dy
    added = 0
    for li in range(D):
        d = levels[li]
        while added < T and zflat[order[added]] >= d:
            k = added
            idx = order[k]
            r0 = idx // nx
            c0 = idx - r0 * nx
            for t in range(nd):
                rr = r0 + drs[t]
                cc = c0 + dcs[t]
                if periodic:
                    rr = rr % ny
                    cc = cc % nx
                elif rr < 0 or rr >= ny or cc < 0 or cc >= nx:
                    continue
                q = pos[rr * nx + cc]
                if q < 0 or q >= k:
                    continue
                rp = _find(parent, vx, vy, stack, k)
                vpx = vx[k] if rp != k else 0
                vpy = vy[k] if rp != k else 0
                rq = _find(parent, vx, vy, stack, q)
                vqx = vx[q] if rq != q else 0
                vqy = vy[q] if rq != q else 0
                sx = dcs[t]
                sy = drs[t]
                if rp != rq:
                    if rq < rp:  # the root is the higher (earlier) pixel
                        parent[rp] = rq
                        vx[rp] = -sx - vpx + vqx
                        vy[rp] = -sy - vpy + vqy
                        wrap[rq] = wrap[rq] or wrap[rp]
                    else:
                        parent[rq] = rp
                        vx[rq] = sx - vqx + vpx
                        vy[rq] = sy - vqy + vpy
                        wrap[rp] = wrap[rp] or wrap[rq]
                elif vqx - vpx != sx or vqy - vpy != sy:
                    wrap[rp] = True
            added += 1
        n_act = added
        if n_act == 0:
            continue
        # group the active pixels by root (counting sort)
        for j in range(n_act):
            count[j] = 0
        for j in range(n_act):
            r = _find(parent, vx, vy, stack, j)
            count[r] += 1
        start[0] = 0
        for j in range(n_act):
            start[j + 1] = start[j] + count[j]
        for j in range(n_act):
            count[j] = 0
        for j in range(n_act):
            r = parent[j]
            members[start[r] + count[r]] = j
            count[r] += 1
        nr = 0
        for r in range(n_act):
            if start[r + 1] > start[r]:
                roots[nr] = r
                nr += 1
        _fit_level(
            roots[:nr], start, members, vx, vy, zflat, order, d, dx, dy, xs, ys, hs, warm, pm,
            sol, fit, ws, iw, free,
        )
        # sums over the asperities in root order
        for c in range(nr):
            r = roots[c]
            m = start[r + 1] - start[r]
            area = m * pix
            af = math.sqrt(area / math.pi)
            tt = fit[c, 0]
            cost = fit[c, 1]
            # Hertz (Eqs. 10-11) with delta = t a_f, R = a_f (1 + t^2) / (2 t):
            # F = K sqrt(R) delta^1.5 = K a_f^2 t sqrt((1 + t^2) / 2), area pi R delta
            force[li] += K * af * af * tt * math.sqrt(0.5 * (1.0 + tt * tt))
            harea[li] += 0.5 * math.pi * af * af * (1.0 + tt * tt)
            farea[li] += area
            e2a[li] += cost / m * af * af * area
            ncomp[li] += 1
            if wrap[r]:
                nwrap[li] += 1
    return force, harea, farea, e2a, ncomp, nwrap


@nb.njit(cache=True, nogil=True)
def _count_above(zflat, thresholds):  # pragma: no cover - compiled
    """Number of valid pixels with ``z >= t`` for every ``t`` of ascending ``thresholds``.

    Each height is placed among the thresholds by a lookup in uniform buckets over
    ``[thresholds[0], thresholds[-1]]`` (about four per threshold) followed by exact comparisons
    in both directions, so the bin is exactly ``bisect_right(thresholds, z)`` whatever the
    rounding of the bucket index, in O(1) per pixel for well-spread thresholds.
    """
    m = thresholds.size
    out = np.zeros(m, np.int64)
    if m == 0:
        return out
    hist = np.zeros(m + 1, np.int64)
    t0 = thresholds[0]
    span = thresholds[m - 1] - t0
    nb_ = 4 * m
    inv = nb_ / span if span > 0.0 else 0.0
    # first[b] = number of thresholds below the lower edge of bucket b (approximately: fixed below)
    first = np.zeros(nb_ + 1, np.int64)
    j = 0
    for bk in range(nb_ + 1):
        while j < m and (thresholds[j] - t0) * inv < bk:
            j += 1
        first[bk] = j
    for z in zflat:
        if not (z >= t0):  # NaN, or below every threshold
            continue
        x = (z - t0) * inv
        bk = int(x) if x < nb_ else nb_  # (inf * 0 = NaN also lands in the last bucket)
        lo = first[bk]
        while lo > 0 and thresholds[lo - 1] > z:
            lo -= 1
        while lo < m and thresholds[lo] <= z:
            lo += 1
        hist[lo] += 1
    acc = 0
    for j in range(m, 0, -1):
        acc += hist[j]
        out[j - 1] = acc
    return out


def prepare_heights(z):
    """Mean-referred float64 heights and the number of valid pixels (shared with the reference)."""
    z = np.asarray(z, dtype=np.float64)
    valid = np.isfinite(z)
    nvalid = int(valid.sum())
    if nvalid == 0:
        raise ValueError(
            "the height map has no finite pixel (all NaN/inf): nothing to put in contact. "
            "Check the input or fill the dropouts first."
        )
    if nvalid == z.size:  # no masked copy (same mean bit for bit: the same values in the same order)
        return np.ascontiguousarray(z - np.ascontiguousarray(z).ravel().mean()), nvalid
    mean = z[valid].mean()
    out = np.where(valid, z - mean, np.nan)
    return np.ascontiguousarray(out), nvalid


#: names and order of the kernel's outputs
OUTPUTS = CURVE_VARIABLES


def curves_kernel(
    z,
    distance,
    water_height,
    laplace_pressure,
    *,
    dx,
    dy,
    K,
    periodic,
    connectivity,
    warm_start=False,
):
    """Force-distance curves of one map (Eq. 16) at every distance and humidity.

    Parameters
    ----------
    z : (ny, nx) array
        Heights [m] (NaN = missing pixel).
    distance : (D,) array
        Distances [m], any order, no duplicates.
    water_height, laplace_pressure : (R,) arrays
        h_water [m] and Delta P [Pa] (< 0) per humidity.
    dx, dy : float
        Pixel spacing [m].
    K : float
        Hertz modulus 4/3 E* [Pa].
    periodic : bool
        Connect across the map edges.
    connectivity : {4, 8}
    warm_start : bool
        Refine the fit of an asperity whose pixels did not change since the next higher
        distance from that distance's solution (faster; see :func:`_hertz_levels`).

    Returns
    -------
    tuple of (R, D) float64 arrays, in the order of :data:`OUTPUTS`.
    """
    z, nvalid = prepare_heights(z)
    ny, nx = z.shape
    distance = np.asarray(distance, dtype=np.float64)
    hw = np.atleast_1d(np.asarray(water_height, dtype=np.float64))
    dp = np.atleast_1d(np.asarray(laplace_pressure, dtype=np.float64))
    D = distance.size
    R = hw.size
    zflat = z.ravel()
    apparent = nvalid * dx * dy
    desc = np.argsort(-distance, kind="stable")
    levels = distance[desc]
    # the top tail: only pixels at or above the lowest level can touch the flat
    tail = np.flatnonzero(zflat >= levels[-1]) if D else np.empty(0, np.int64)
    order = tail[np.argsort(-zflat[tail], kind="stable")].astype(np.int64)
    f, ha, _fa, e2a, nc, _nw = _hertz_levels(
        zflat,
        ny,
        nx,
        order,
        levels,
        float(dx),
        float(dy),
        float(K),
        bool(periodic),
        int(connectivity),
        bool(warm_start),
    )
    inv = np.empty(D, np.int64)
    inv[desc] = np.arange(D)
    f, ha, e2a, fa, nc = f[inv], ha[inv], e2a[inv], _fa[inv], nc[inv]
    # water: complementary cumulative count at every d - h_water (one pass for all d and rh)
    thr = (distance[None, :] - hw[:, None]).ravel()
    srt = np.argsort(thr, kind="stable")
    counts = np.empty(thr.size, np.int64)
    counts[srt] = _count_above(zflat, np.ascontiguousarray(thr[srt]))
    wet_area = counts.reshape(R, D) * (dx * dy)
    net_wet = (wet_area - ha[None, :]) / apparent
    rep = f / apparent
    pressure = rep[None, :] + dp[:, None] * net_wet
    with np.errstate(invalid="ignore", divide="ignore"):
        fit_error = np.where(nc > 0, np.sqrt(e2a / np.where(fa > 0, fa, 1.0)), np.nan)
    zmax = np.nanmax(zflat)
    shape = (R, D)
    return (
        pressure,
        np.broadcast_to(rep, shape).copy(),
        net_wet,
        np.broadcast_to(ha / apparent, shape).copy(),
        np.broadcast_to(nc.astype(np.float64), shape).copy(),
        np.broadcast_to(fit_error, shape).copy(),
        np.broadcast_to(zmax - distance, shape).copy(),
    )
