"""Compiled kernels of the rough-surface modified DMT (Eqs. 16-23): the one-pass adaptive grid.

:func:`auto_pass` visits distance levels in one pass over the top tail of the height
distribution (:mod:`._tail`, :mod:`._unionfind`): each controller (one per humidity, or one for
all) walks down from the first water contact, refines where its curve turns (:func:`_descent`),
bisects the zero crossings of the mean pressure (equilibrium), then refines the pull-off extremum
and the wetting events next to it (:func:`_pull_round`), and stops once its humidities' curves are
past their outermost stable crossing. Each level's asperities are fitted with Eq. 21
(:mod:`._fit`); water areas come from the height buckets. With ``fixed`` levels it evaluates just
those (any order). Its settings are a :class:`._policy.GridPolicy`; its state is named: the
:class:`Levels` evaluated, the :class:`Controllers`, the :class:`Workspace` of arrays reused from
call to call.

Conventions shared with the literal Eq. 21 reference (``tests/contact/modified_dmt/eq21_reference.py``):

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

import threading
from typing import NamedTuple

import numba as nb
import numpy as np

from ..._core.conventions import CURVE_VARIABLES
from ._policy import DEFAULT_POLICY, policy_for
from ._search import GRID_KEEP
from ._tail import (
    TAIL_STATE,
    Tail,
    bucket_sort,
    contact_event_above,
    max_tie_bound,
    n_above,
    prepare_heights,
    sort_until,
    wet_count,
    wet_event_above,
)
from ._unionfind import (
    COMPONENT,
    LOG_ENTRY,
    NEIGHBOUR,
    PIXEL,
    UNION_FIND_STATE,
    FitScratch,
    Geometry,
    Pool,
    UnionFind,
    eval_level,
    seek,
)

__all__ = ["OUTPUTS", "LEVEL_SUMS", "MoreLevels", "auto_pass", "curves", "curves_kernel", "hertz_levels",
           "more_levels", "prepare_heights", "workspace"]

OUTPUTS = CURVE_VARIABLES
_NJ = dict(cache=True, nogil=True, error_model="numpy")
# no reference counting in the steps that never allocate: with it, every access to a field of
# the named state (an array) is an atomic incref/decref, twice the cost of a 256² map's pass
_NJ0 = dict(_NJ, _nrt=False)

#: The Hertz sums of one level over its asperities (:func:`._unionfind.eval_level`).
LEVEL_SUMS = np.dtype([(f, np.float64) for f in ("force", "hertz_area", "foot_area", "err2_area",
                                                 "n_comp", "n_wrap")], align=True)
#: Depth of each controller's stack of intervals (depth <= log2(span / floor width) < 256).
_STACK = 256
#: Pull-off rounds per humidity at most.
_ROUNDS = 40


class Workspace(NamedTuple):
    """Every array the kernel needs, sized for the whole map (:func:`workspace`)."""

    start: np.ndarray
    idx: np.ndarray
    zb: np.ndarray
    pos: np.ndarray
    order: np.ndarray
    ztail: np.ndarray
    tail_state: np.ndarray
    pixels: np.ndarray
    components: np.ndarray
    live: np.ndarray
    logstart: np.ndarray
    pooltop: np.ndarray
    log: np.ndarray
    pool_index: np.ndarray
    pool_x: np.ndarray
    pool_y: np.ndarray
    pool_z: np.ndarray
    union_find_state: np.ndarray
    xs: np.ndarray
    ys: np.ndarray
    hs: np.ndarray
    wt: np.ndarray


class Humidities(NamedTuple):
    """Per humidity: h_water [m] and Delta P [Pa]; ``mask[c, j]``: controller c serves humidity j."""

    water_height: np.ndarray
    laplace_pressure: np.ndarray
    mask: np.ndarray


class Levels(NamedTuple):
    """The levels evaluated so far, in evaluation order (``order``: sorted by distance)."""

    distance: np.ndarray
    sums: np.ndarray  # LEVEL_SUMS per level
    wet: np.ndarray  # wet pixels per (level, humidity)
    member: np.ndarray  # (level, controller): part of that controller's grid
    order: np.ndarray
    depth: np.ndarray  # (level, humidity): depth of the chain of event snaps that placed it
    source: np.ndarray  # (level, humidity): already the source of its snaps
    phase: np.ndarray  # 0: placed by the descent, 1: by the pull-off refinement


class Controllers(NamedTuple):
    """The state of each controller c (and of its humidities j)."""

    phase: np.ndarray  # 0: descent, 1: pull-off refinement, 3: done
    top: np.ndarray  # its first level, above the first wetting of its humidities
    current: np.ndarray  # top of the descent step being tested
    step: np.ndarray  # width of the next descent step
    next: np.ndarray  # bottom of the descent step being tested
    stop: np.ndarray  # where the descent stops (NaN until every crossing is known)
    stack: np.ndarray  # (c, depth, 2): intervals still to test, ends (a, b)
    depth: np.ndarray  # stack depth
    accepted: np.ndarray  # intervals accepted in this step
    last_width: np.ndarray
    scale: np.ndarray  # (c, j): largest |p| so far, at least the water term at first contact
    crossed: np.ndarray  # (c, j): outermost stable zero crossing (NaN: not found yet)
    lowest: np.ndarray  # (c, j): most tensile pressure met above the crossing
    humidity: np.ndarray  # pull-off refinement: the humidity j being refined
    rounds: np.ndarray  # its rounds so far
    best: np.ndarray  # its most tensile pressure at the start of the round
    requests: np.ndarray  # (c, level): the levels asked for by the round
    request_depth: np.ndarray  # (c, level): their snap depth
    n_requests: np.ndarray


class Constants(NamedTuple):
    """Numbers of one map that every step of the controllers uses."""

    pix: float  # pixel area [m2]
    apparent: float  # area of the valid pixels [m2]
    sigma: float  # rms height [m]
    wfloor: float  # narrowest interval split [m]
    dfloor: float  # lowest level [m]
    dtop: np.ndarray  # per humidity: first wetting z_max + h_water [m]


@nb.njit(**_NJ0)
def _find(levels, n, d):  # pragma: no cover - compiled
    """Index (into the level arrays) of level d, or -1; ``levels.order[:n]`` sorts them by d."""
    D, order = levels.distance, levels.order
    lo = 0
    hi = n
    while lo < hi:
        mid = (lo + hi) >> 1
        if D[order[mid]] < d:
            lo = mid + 1
        else:
            hi = mid
    if lo < n and D[order[lo]] == d:
        return order[lo]
    return -1


@nb.njit(**_NJ0)
def _pressure(levels, i, j, dp, k):  # pragma: no cover - compiled
    """Mean pressure of level i at humidity j (Eq. 16): Hertz + Delta P (wet - contact area)."""
    s = levels.sums[i]
    return (s.force + dp[j] * (levels.wet[i, j] * k.pix - s.hertz_area)) / k.apparent


@nb.njit(**_NJ)
def _grow_log(a, n):  # pragma: no cover - compiled
    b = np.empty(n, a.dtype)
    b[: a.size] = a
    return b


@nb.njit(**_NJ)
def _grow(a, n):  # pragma: no cover - compiled
    b = np.empty(n, a.dtype)
    b[: a.size] = a
    return b


@nb.njit(**_NJ)
def _level(d, li, levels, tail, uf, pool, geo, fit, nbuf, hw):  # pragma: no cover - compiled
    """Move the union-find to level d (growing the log and pixel pool as needed), evaluate it
    into slot li; returns the (possibly grown) union-find and pool."""
    sort_until(tail, d)
    k = n_above(tail, d)
    while True:
        r = seek(k, uf, pool, tail, geo, nbuf)
        if r == 0:
            break
        if r == 1:
            uf = UnionFind(uf.pixels, uf.components, uf.live, _grow_log(uf.log, 2 * uf.log.shape[0]),
                           uf.logstart, uf.pooltop, uf.state)
        else:
            n2 = 2 * pool.index.size
            pool = Pool(_grow(pool.index, n2), _grow(pool.x, n2), _grow(pool.y, n2), _grow(pool.z, n2))
    f, ha, fa, e2, nc, nw = eval_level(uf, pool, d, geo, fit)
    levels.distance[li] = d
    s = levels.sums[li]
    s.force, s.hertz_area, s.foot_area, s.err2_area, s.n_comp, s.n_wrap = f, ha, fa, e2, nc, nw
    for j in range(hw.size):
        levels.wet[li, j] = wet_count(tail, d - hw[j])
    return uf, pool


@nb.njit(**_NJ0)
def _descent(c, ctl, levels, nlev, hum, pol, k, full):  # pragma: no cover - compiled
    """One step of controller c's descent: ``(True, -inf)`` when it moved on by itself, else
    ``(False, d)`` with the level d it needs next."""
    hw, dp, mask = hum
    R = hw.size
    sp = ctl.depth
    stk = ctl.stack
    crossed = ctl.crossed
    if sp[c] == 0:
        # interval done: next step of the descent, or stop
        ctl.current[c] = ctl.next[c]
        if ctl.accepted[c] > 1:
            ctl.step[c] = 2.0 * ctl.last_width[c]
        else:
            ctl.step[c] = 2.0 * ctl.step[c]
        ctl.accepted[c] = 0
        allx = True
        lowest = np.inf
        for j in range(R):
            if mask[c, j]:
                if np.isnan(crossed[c, j]):
                    allx = False
                else:
                    lowest = min(lowest, crossed[c, j])
        if allx and np.isnan(ctl.stop[c]):
            ctl.stop[c] = lowest - pol.margin * k.sigma
        if (allx and ctl.current[c] <= ctl.stop[c]) or ctl.current[c] <= k.dfloor or full:
            ctl.phase[c] = 1
            ctl.humidity[c] = -1
            ctl.n_requests[c] = 0
            return True, -np.inf
        ctl.next[c] = max(ctl.current[c] - ctl.step[c], k.dfloor)
        stk[c, 0, 0] = ctl.next[c]
        stk[c, 0, 1] = ctl.current[c]
        sp[c] = 1
    a = stk[c, sp[c] - 1, 0]
    b = stk[c, sp[c] - 1, 1]
    m = 0.5 * (a + b)
    below = True  # wholly below every humidity's crossing: nothing to test there
    for j in range(R):
        if mask[c, j] and (np.isnan(crossed[c, j]) or b > crossed[c, j]):
            below = False
    if below and _find(levels, nlev, a) >= 0 and _find(levels, nlev, b) >= 0:
        sp[c] -= 1
        return True, -np.inf
    ia = _find(levels, nlev, a)
    ib = _find(levels, nlev, b)
    im = _find(levels, nlev, m)
    if ib < 0:
        return False, b
    if im < 0:
        return False, m
    if ia < 0:
        return False, a
    MEM = levels.member
    MEM[ia, c] = True
    MEM[ib, c] = True
    MEM[im, c] = True
    # the midpoint test: accept, or split (upper half first)
    w = b - a
    ok = True
    if w > 2 * k.wfloor and not full:
        for j in range(R):
            if not mask[c, j]:
                continue
            if not (np.isnan(crossed[c, j]) or b > crossed[c, j]):
                continue
            va = _pressure(levels, ia, j, dp, k)
            vb = _pressure(levels, ib, j, dp, k)
            vm = _pressure(levels, im, j, dp, k)
            err = abs(vm - 0.5 * (va + vb))
            lo3 = min(min(va, vb), vm)
            hi3 = max(max(va, vb), vm)
            f = 1.0
            cap = pol.eta * k.sigma
            if np.isnan(crossed[c, j]):
                if hi3 > 0.0 and lo3 < 0.0:
                    # the crossing: a finer grid moves d_eq within its interval only; wider
                    # intervals pass when the root of the chord and that of the half holding the
                    # (stable) crossing agree
                    tol_d = pol.deq_tol * max(abs(a), k.sigma)
                    if w > tol_d:
                        if not (w <= pol.deq_maxw * tol_d and va >= 0.0 and vb < 0.0):
                            ok = False
                            break
                        r_ab = a + w * va / (va - vb)
                        if vm >= 0.0:
                            r_h = m + 0.5 * w * vm / (vm - vb)
                        else:
                            r_h = a + 0.5 * w * va / (va - vm)
                        if not (abs(r_ab - r_h) <= pol.deq_est * tol_d):
                            ok = False
                            break
                    continue
                if min(min(abs(va), abs(vb)), abs(vm)) <= pol.zero_band * ctl.scale[c, j]:
                    f = pol.fine
                    cap = pol.zcap * pol.eta * k.sigma
            fl = min(pol.eta * max(k.dtop[j] - a, 0.0), cap)
            if not (err <= f * pol.eps * ctl.scale[c, j] or w <= f * fl):
                ok = False
                break
    if ok:
        sp[c] -= 1
        _accept(c, ctl, levels, ia, ib, im, a, b, m, hum, k)
        ctl.accepted[c] += 1
        ctl.last_width[c] = w
    elif sp[c] + 2 > _STACK:
        sp[c] -= 1  # (cannot happen: depth <= log2(span / wfloor))
    else:
        stk[c, sp[c] - 1, 0] = a
        stk[c, sp[c] - 1, 1] = m
        stk[c, sp[c], 0] = m
        stk[c, sp[c], 1] = b
        sp[c] += 1
    return True, -np.inf


@nb.njit(**_NJ0)
def _accept(c, ctl, levels, ia, ib, im, a, b, m, hum, k):  # pragma: no cover - compiled
    """Advance controller c over an accepted interval, (b, m) then (m, a): its curves' scale,
    most tensile pressure and the crossing where the pressure turns attractive going up."""
    hw, dp, mask = hum
    crossed = ctl.crossed
    for half in range(2):
        if half == 0:
            ih = ib
            il = im
            dh = b
            dl = m
        else:
            ih = im
            il = ia
            dh = m
            dl = a
        for j in range(hw.size):
            if not mask[c, j]:
                continue
            ph = _pressure(levels, ih, j, dp, k)
            pl = _pressure(levels, il, j, dp, k)
            ctl.scale[c, j] = max(ctl.scale[c, j], max(abs(ph), abs(pl)))
            if np.isnan(crossed[c, j]):
                if pl < ctl.lowest[c, j]:
                    ctl.lowest[c, j] = pl
                if pl >= 0.0 and ph < 0.0:
                    crossed[c, j] = dh - (dh - dl) * ph / (ph - pl)


@nb.njit(**_NJ0)
def _pull_pending(c, ctl, levels, nlev, hum, pol, k):  # pragma: no cover - compiled
    """Controller c's pull-off round waits for its requested levels: ``(False, d)`` with the
    highest missing one, else ``(True, -inf)`` once their results are recorded."""
    dp = hum.laplace_pressure
    REQ = ctl.requests
    want = -np.inf
    missing = False
    for q in range(ctl.n_requests[c]):
        if _find(levels, nlev, REQ[c, q]) < 0:
            want = max(want, REQ[c, q])
            missing = True
    if missing:
        return False, want
    after = np.inf
    j = ctl.humidity[c]
    for q in range(ctl.n_requests[c]):
        il = _find(levels, nlev, REQ[c, q])
        levels.member[il, c] = True
        if ctl.request_depth[c, q] > 0 and levels.depth[il, j] == 0:
            levels.depth[il, j] = ctl.request_depth[c, q]
        after = min(after, _pressure(levels, il, j, dp, k))
    ctl.n_requests[c] = 0
    if pol.pull_stop > 0.0 and not (after < ctl.best[c] * (1.0 + pol.pull_stop)):
        ctl.rounds[c] = 99  # no improvement: next humidity
    return True, -np.inf


@nb.njit(**_NJ)
def _pull_round(c, ctl, levels, nlev, tail, hum, pol, k):  # pragma: no cover - compiled
    """The next pull-off round of controller c: the intervals of its grid that may hide a more
    tensile point than its best, bisected, or snapped to the wetting and contact events in them
    once resolved. Always moves on by itself."""
    hw, dp, mask = hum
    R = hw.size
    # the fields used in the loops, once (an access to a field is a reference count here)
    D, member, order, wet = levels.distance, levels.member, levels.order, levels.wet
    depth, source = levels.depth, levels.source
    maxp = D.size
    if ctl.humidity[c] < 0 or ctl.rounds[c] >= _ROUNDS:
        ctl.humidity[c] += 1
        while ctl.humidity[c] < R and not mask[c, ctl.humidity[c]]:
            ctl.humidity[c] += 1
        ctl.rounds[c] = 0
        if ctl.humidity[c] >= R:
            ctl.phase[c] = 3
            return
    j = ctl.humidity[c]
    # this controller's grid, sorted
    cnt = 0
    for q in range(nlev):
        if member[order[q], c]:
            cnt += 1
    gl = np.empty(cnt, np.int64)
    cnt = 0
    for q in range(nlev):
        if member[order[q], c]:
            gl[cnt] = order[q]
            cnt += 1
    xc = ctl.crossed[c, j] if not np.isnan(ctl.crossed[c, j]) else -np.inf
    bi = -1
    bv = 0.0
    for q in range(cnt):
        if D[gl[q]] >= xc:
            v = _pressure(levels, gl[q], j, dp, k)
            if v < bv:
                bv = v
                bi = q
    if bi < 0:
        ctl.rounds[c] = 99
        return
    ctl.best[c] = bv
    ctl.rounds[c] += 1
    REQ, SREQ = ctl.requests, ctl.request_depth
    nr = 0
    for q in range(cnt - 1):
        d0 = D[gl[q]]
        d1 = D[gl[q + 1]]
        if d0 < xc:
            continue
        v0 = _pressure(levels, gl[q], j, dp, k)
        v1 = _pressure(levels, gl[q + 1], j, dp, k)
        # a tooth can hide inside the interval: the pixels drying at one height in it (at most
        # the fullest bucket, at most those drying in it) drop the curve by up to their water
        # term below its ends
        ndry = wet[gl[q], j] - wet[gl[q + 1], j]
        tie = 0.0
        if ndry > 0:
            tie = abs(dp[j]) * k.pix / k.apparent * min(
                ndry, max_tie_bound(tail, d0 - hw[j], d1 - hw[j]))
        if not (min(v0, v1 - pol.tie * tie) <= bv * (1.0 - pol.pull_band)):
            continue
        L = min(max(k.dtop[j] - d0, 0.0), k.sigma)
        if d1 - d0 <= max(pol.pull_fine * pol.eta * L, 2 * k.wfloor):
            # resolved: once, the most tensile points of the teeth just above d0 (the wetting
            # and the contact event there: water and Hertz jumps) (each point is the source of
            # these snaps once, and snapped points up to depth 2: the chain of events stops)
            src = gl[q]
            if source[src, j] or depth[src, j] >= 2:
                continue
            source[src, j] = True
            de = wet_event_above(tail, d0, hw[j])
            if d0 < de < d1 and nr < maxp:
                REQ[c, nr] = de
                SREQ[c, nr] = depth[src, j] + 1
                nr += 1
            dcx = contact_event_above(tail, d0)
            if d0 < dcx < d1 and dcx != de and nr < maxp:
                REQ[c, nr] = dcx
                SREQ[c, nr] = depth[src, j] + 1
                nr += 1
            continue
        # smooth here (each end on the chord of its neighbours within pull_smooth): a finer grid
        # finds nothing deeper, no need to bisect (neighbours at least half the interval away:
        # not the other point of a snapped pair)
        qa = q - 1
        while qa >= 0 and d0 - D[gl[qa]] < 0.5 * (d1 - d0):
            qa -= 1
        qb = q + 2
        while qb < cnt and D[gl[qb]] - d1 < 0.5 * (d1 - d0):
            qb += 1
        if qa >= 0 and qb < cnt:
            vm1 = _pressure(levels, gl[qa], j, dp, k)
            v2 = _pressure(levels, gl[qb], j, dp, k)
            dm1 = D[gl[qa]]
            d2 = D[gl[qb]]
            e0 = abs(v0 - (vm1 + (v1 - vm1) * (d0 - dm1) / (d1 - dm1)))
            e1 = abs(v1 - (v0 + (v2 - v0) * (d1 - d0) / (d2 - d0)))
            if max(e0, e1) <= pol.pull_smooth * abs(bv) and tie <= pol.pull_smooth * abs(bv):
                continue
        m = 0.5 * (d0 + d1)
        if nr < maxp:
            REQ[c, nr] = m
            SREQ[c, nr] = 0
            nr += 1
        de = wet_event_above(tail, m, hw[j])
        if m < de < d1 and nr < maxp:
            REQ[c, nr] = de
            SREQ[c, nr] = 0
            nr += 1
    if nr == 0 or nlev + nr > maxp:
        ctl.rounds[c] = 99
    else:
        ctl.n_requests[c] = nr


@nb.njit(**_NJ)
def _controllers(hum, tail, zmax, span, k, maxp):  # pragma: no cover - compiled
    """Each controller's start: its grid begins above the first wetting of its humidities, and
    tests [top - w, top] first."""
    hw, dp, mask = hum
    C, R = mask.shape
    top = np.empty(C)
    for c in range(C):
        hwmax = 0.0
        for j in range(R):
            if mask[c, j]:
                hwmax = max(hwmax, hw[j])
        top[c] = zmax + hwmax + 1e-4 * span
    scale = np.zeros((C, R))
    # the pull-off is at least the water term just above the first contact (no Hertz there)
    for j in range(R):
        w0 = wet_count(tail, np.nextafter(zmax, np.inf) - hw[j])
        for c in range(C):
            scale[c, j] = abs(dp[j]) * w0 * k.pix / k.apparent
    ctl = Controllers(
        phase=np.zeros(C, np.int64), top=top, current=top.copy(), step=(top - zmax) / 4,
        next=np.zeros(C), stop=np.full(C, np.nan), stack=np.empty((C, _STACK, 2)),
        depth=np.zeros(C, np.int64), accepted=np.zeros(C, np.int64), last_width=np.zeros(C),
        scale=scale, crossed=np.full((C, R), np.nan), lowest=np.zeros((C, R)),
        humidity=np.zeros(C, np.int64), rounds=np.zeros(C, np.int64), best=np.zeros(C),
        requests=np.empty((C, maxp)), request_depth=np.zeros((C, maxp), np.int64),
        n_requests=np.zeros(C, np.int64))
    for c in range(C):
        ctl.next[c] = max(top[c] - ctl.step[c], k.dfloor)
        ctl.stack[c, 0, 0] = ctl.next[c]
        ctl.stack[c, 0, 1] = top[c]
        ctl.depth[c] = 1
    return ctl


@nb.njit(**_NJ)
def auto_pass(zflat, geo, hum, pol, fixed, ws):  # pragma: no cover - compiled
    """Evaluate the levels of the adaptive grids (or the ``fixed`` levels if given, any order).

    ``geo``: the map's :class:`._unionfind.Geometry`; ``hum``: :class:`Humidities`; ``pol``: a
    :class:`._policy.GridPolicy`; ``ws``: a :class:`Workspace`. Returns ``(levels, n, crossed,
    ws)``: the :class:`Levels` (their first ``n``), each controller's outermost stable crossing
    per humidity (NaN: none found) and the workspace (its log and pool possibly grown).
    """
    hw, dp, mask = hum
    R = hw.size
    C = mask.shape[0]
    nbuck = ws.start.size - 1
    zmin, zmax, scale, nvalid, sigma = bucket_sort(zflat, ws.start, ws.idx, ws.zb)
    span = max(zmax - zmin, 1e-300)
    pix = geo.dx * geo.dy
    # the tail and the union-find (capacities: every valid pixel; pages never touched cost nothing)
    ws.pos[:] = -1
    ts = ws.tail_state[0]
    ts.nsorted = 0
    ts.nextb = nbuck - 1
    us = ws.union_find_state[0]
    us.k = 0
    us.nlive = 0
    us.log = 0
    us.pool = 0
    us.added = 0
    tail = Tail(ws.start, ws.idx, ws.zb, zmin, scale, ws.order, ws.ztail, ws.pos, ws.tail_state)
    uf = UnionFind(ws.pixels, ws.components, ws.live, ws.log, ws.logstart, ws.pooltop,
                   ws.union_find_state)
    pool = Pool(ws.pool_index, ws.pool_x, ws.pool_y, ws.pool_z)
    fit = FitScratch(ws.xs, ws.ys, ws.hs, ws.wt, np.zeros((4, GRID_KEEP)))
    nbuf = np.empty(8, NEIGHBOUR)
    # levels
    maxp = pol.max_points if fixed.size == 0 else fixed.size
    levels = _new_levels(maxp, R, C)
    if fixed.size > 0:
        uf, pool = _fixed(fixed, levels, tail, uf, pool, geo, fit, nbuf, hw)
        return levels, fixed.size, np.full((C, R), np.nan), _workspace(ws, uf, pool), zmin, scale

    dtop = np.empty(R)
    for j in range(R):
        dtop[j] = zmax + hw[j]
    k = Constants(pix, nvalid * pix, sigma, pol.wfloor_rel * span, zmin - 1e-3 * span, dtop)
    ctl = _controllers(hum, tail, zmax, span, k, maxp)
    phase, n_requests, order, distance = ctl.phase, ctl.n_requests, levels.order, levels.distance
    nlev = 0
    wantph = 0
    full = False
    while True:
        # ---- collect each controller's next request; progress controllers that need none
        want = -np.inf
        alldone = True
        progressed = True
        while progressed:
            progressed = False
            want = -np.inf
            alldone = True
            for c in range(C):
                if phase[c] == 3:
                    continue
                alldone = False
                if phase[c] == 0:
                    moved, request = _descent(c, ctl, levels, nlev, hum, pol, k, full)
                    ph = 0
                elif n_requests[c] > 0:
                    moved, request = _pull_pending(c, ctl, levels, nlev, hum, pol, k)
                    ph = 1
                else:
                    _pull_round(c, ctl, levels, nlev, tail, hum, pol, k)
                    moved, request, ph = True, -np.inf, 1
                if moved:
                    progressed = True
                elif (ph < wantph or want == -np.inf) or (ph == wantph and request > want):
                    # the descents first (the union-find walks down once), then the pull-off
                    # rounds; the highest request of each kind first
                    want = request
                    wantph = ph
        if alldone:
            break
        if want == -np.inf:
            continue
        # ---- evaluate the request chosen (any order gives the same levels and values here: each
        # controller waits for its own request; descents first moves the union-find less)
        d = want
        if nlev >= maxp:
            full = True
            # serve no more levels: the controllers finish with what they have
            for c in range(C):
                if phase[c] == 0:
                    phase[c] = 1
                    ctl.humidity[c] = -1
                    n_requests[c] = 0
                elif phase[c] == 1:
                    n_requests[c] = 0
                    ctl.rounds[c] = 99
                    ctl.humidity[c] = R
            continue
        li = nlev
        levels.phase[li] = wantph
        uf, pool = _level(d, li, levels, tail, uf, pool, geo, fit, nbuf, hw)
        # insert into the sorted order
        q = nlev
        while q > 0 and distance[order[q - 1]] > d:
            order[q] = order[q - 1]
            q -= 1
        order[q] = li
        nlev += 1
    return levels, nlev, ctl.crossed, _workspace(ws, uf, pool), zmin, scale


@nb.njit(**_NJ)
def _new_levels(maxp, R, C):  # pragma: no cover - compiled
    return Levels(np.empty(maxp), np.empty(maxp, LEVEL_SUMS), np.empty((maxp, R), np.int64),
                  np.zeros((maxp, C), np.bool_), np.empty(maxp, np.int64),
                  np.zeros((maxp, R), np.int64), np.zeros((maxp, R), np.bool_),
                  np.zeros(maxp, np.int64))


@nb.njit(**_NJ)
def _fixed(fixed, levels, tail, uf, pool, geo, fit, nbuf, hw):  # pragma: no cover - compiled
    """Evaluate the ``fixed`` levels into their slots: from the union-find's level towards the
    farther end (each level's values depend on that level only, not on the path)."""
    n = fixed.size
    srt = np.argsort(fixed)  # upwards
    if not (n > 0 and uf.state[0].k > n_above(tail, fixed[srt[n // 2]])):
        srt = srt[::-1]  # downwards, unless the union-find is below most of them
    for t in range(n):
        uf, pool = _level(fixed[srt[t]], srt[t], levels, tail, uf, pool, geo, fit, nbuf, hw)
    return uf, pool


@nb.njit(**_NJ)
def more_levels(geo, hw, fixed, ws, zmin, scale):  # pragma: no cover - compiled
    """Evaluate the ``fixed`` levels (any order) of the map whose :func:`auto_pass` left its
    state in ``ws`` (``zmin``, ``scale``: what that pass returned), without sorting the map
    again: the union-find moves from where the pass left it. Returns ``(levels, ws)``."""
    tail = Tail(ws.start, ws.idx, ws.zb, zmin, scale, ws.order, ws.ztail, ws.pos, ws.tail_state)
    uf = UnionFind(ws.pixels, ws.components, ws.live, ws.log, ws.logstart, ws.pooltop,
                   ws.union_find_state)
    pool = Pool(ws.pool_index, ws.pool_x, ws.pool_y, ws.pool_z)
    fit = FitScratch(ws.xs, ws.ys, ws.hs, ws.wt, np.zeros((4, GRID_KEEP)))
    nbuf = np.empty(8, NEIGHBOUR)
    levels = _new_levels(fixed.size, hw.size, 1)
    uf, pool = _fixed(fixed, levels, tail, uf, pool, geo, fit, nbuf, hw)
    return levels, _workspace(ws, uf, pool)


@nb.njit(**_NJ)
def _workspace(ws, uf, pool):  # pragma: no cover - compiled
    """The workspace with the (possibly grown) log and pool."""
    return Workspace(ws.start, ws.idx, ws.zb, ws.pos, ws.order, ws.ztail, ws.tail_state, ws.pixels,
                     ws.components, ws.live, ws.logstart, ws.pooltop, uf.log, pool.index, pool.x,
                     pool.y, pool.z, ws.union_find_state, ws.xs, ws.ys, ws.hs, ws.wt)


_WS = threading.local()


def workspace(n):
    """Per-thread reusable arrays for maps of n pixels.

    Every array the kernel needs, sized for the whole map (pages never touched cost nothing);
    reused from call to call, because touching fresh memory costs page faults (~1.7 ms per MB on
    the development machine) and ensembles call the kernel thousands of times per thread.
    """
    ws = getattr(_WS, "arrays", None)
    if ws is None or getattr(_WS, "n", None) != n:
        nbuck = max(1024, n // 8)
        cap = n + 1
        ws = Workspace(
            start=np.empty(nbuck + 1, np.int64), idx=np.empty(n, np.int32), zb=np.empty(n),
            pos=np.empty(n, np.int32), order=np.empty(cap, np.int64), ztail=np.empty(cap),
            tail_state=np.zeros(1, TAIL_STATE), pixels=np.empty(cap, PIXEL),
            components=np.empty(cap, COMPONENT), live=np.empty(cap, np.int32),
            logstart=np.empty(cap + 1, np.int64), pooltop=np.empty(cap + 1, np.int64),
            log=np.empty(1024, LOG_ENTRY), pool_index=np.empty(4096, np.int32),
            pool_x=np.empty(4096, np.int32), pool_y=np.empty(4096, np.int32),
            pool_z=np.empty(4096), union_find_state=np.zeros(1, UNION_FIND_STATE),
            xs=np.empty(cap + 8), ys=np.empty(cap + 8), hs=np.empty(cap + 8), wt=np.empty(cap + 8),
        )
        _WS.arrays, _WS.n = ws, n
    return ws


def _pass(zflat, ny, nx, dx, dy, K, periodic, connectivity, hw, dp, mask, policy, fixed):
    ws = workspace(zflat.size)
    geo = Geometry(int(ny), int(nx), float(dx), float(dy), float(K), bool(periodic), int(connectivity))
    levels, n, crossed, _WS.arrays, zmin, scale = auto_pass(zflat, geo, Humidities(hw, dp, mask), policy,
                                                            fixed, ws)
    _WS.owner = object()  # who left the state in this thread's workspace
    return levels, n, crossed, (geo, _WS.owner, zmin, scale)


def _outputs(d, sums, wet_pixels, dp, *, pix, apparent, zmax):
    """The curves (CURVE_VARIABLES order, over (rh, distance)) from the levels' Hertz sums and
    wet pixel counts (Eq. 16)."""
    wet = wet_pixels.T * pix
    f, ha, fa, e2, nc = (sums[k] for k in ("force", "hertz_area", "foot_area", "err2_area", "n_comp"))
    net = (wet - ha[None, :]) / apparent
    rep = f / apparent
    pres = rep[None, :] + dp[:, None] * net
    with np.errstate(invalid="ignore", divide="ignore"):
        fe = np.where(nc > 0, np.sqrt(e2 / np.where(fa > 0, fa, 1.0)), np.nan)
    shape = (dp.size, d.size)
    return (pres, np.broadcast_to(rep, shape).copy(), net, np.broadcast_to(ha / apparent, shape).copy(),
            np.broadcast_to(nc, shape).copy(), np.broadcast_to(fe, shape).copy(),
            np.broadcast_to(zmax - d, shape).copy())


class MoreLevels:
    """More levels of the map of one :func:`curves` call, in any order: ``more(distance)`` gives
    the curves (CURVE_VARIABLES order, over (rh, distance), distance in the given order), the
    same numbers as :func:`curves_kernel` (each level's values depend on that level only). While
    the thread's workspace still holds that call's state, the union-find goes on from where it
    stopped, without sorting the map again; otherwise the map is evaluated afresh."""

    def __init__(self, z, hw, dp, kw, state, *, apparent, zmax):
        self.z, self.hw, self.dp, self.kw, self.state = z, hw, dp, kw, state
        self.apparent, self.zmax = apparent, zmax

    def __call__(self, distance):
        d = np.asarray(distance, float)
        if self.state is None or getattr(_WS, "owner", None) is not self.state[1]:
            return curves_kernel(self.z, d, self.hw, self.dp, **self.kw)
        geo, _, zmin, scale = self.state
        levels, _WS.arrays = more_levels(geo, self.hw, d, _WS.arrays, zmin, scale)
        return _outputs(d, levels.sums, levels.wet, self.dp, pix=geo.dx * geo.dy,
                        apparent=self.apparent, zmax=self.zmax)


def curves(z, hw, dp, *, dx, dy, K, periodic, connectivity, distance=None, per_rh=False, params=None):
    """Curves (CURVE_VARIABLES order, over (rh, distance) ascending) on an automatic or given grid.
    ``per_rh``: one controller per humidity (its levels do not depend on the other humidities):
    a list of per-humidity tuples; ``"union"``: all humidities on the union, the membership and
    a :class:`MoreLevels` to evaluate more levels of the same map (None for a flat map, whose
    grid is uniform: then only ``(d, outputs)``).
    ``params``: a :class:`._policy.GridPolicy` (default: :func:`._policy.policy_for` the map)."""
    zc, nvalid = prepare_heights(z)
    ny, nx = zc.shape
    zflat = zc.ravel()
    hw = np.atleast_1d(np.asarray(hw, float))
    dp = np.atleast_1d(np.asarray(dp, float))
    R = hw.size
    policy = policy_for(zflat.size) if params is None else params
    if distance is None and not np.nanmax(zflat) > np.nanmin(zflat):
        # a flat map has no height scale: a uniform grid over the water range (contact at d <= 0)
        distance = np.linspace(0.0, 1.05 * max(float(np.max(hw)), 1e-10), 65)
        per_rh = False
    fixed = np.empty(0) if distance is None else np.asarray(distance, float)
    mask = np.eye(R, dtype=bool) if per_rh else np.ones((1, R), bool)
    levels, n, _, state = _pass(zflat, ny, nx, dx, dy, K, periodic, connectivity, hw, dp, mask, policy,
                                fixed)
    Dv, sums, WET, MEM = levels.distance[:n], levels.sums[:n], levels.wet[:n], levels.member[:n]
    zmax = float(np.nanmax(zflat))
    apparent = nvalid * dx * dy

    def build(sel, rows):
        o = np.argsort(Dv[sel], kind="stable")
        d = Dv[sel][o]
        return d, _outputs(d, sums[sel][o], WET[sel][o][:, rows], dp[rows], pix=dx * dy,
                           apparent=apparent, zmax=zmax)

    if distance is not None:
        return build(np.ones(n, bool), np.arange(R))
    if not per_rh:
        return build(MEM[:, 0], np.arange(R))
    if per_rh == "union":
        u = MEM.any(axis=1)
        more = MoreLevels(z, hw, dp, dict(dx=dx, dy=dy, K=K, periodic=periodic, connectivity=connectivity),
                          state, apparent=apparent, zmax=zmax)
        return (*build(u, np.arange(R)), MEM[u][np.argsort(Dv[u], kind="stable")].T, more)
    return [build(MEM[:, j], np.array([j])) for j in range(R)]


def hertz_levels(z, distance, *, dx, dy, K, periodic, connectivity):
    """Hertz sums per distance (any order): columns (force, hertz_area, foot_area, err2_area,
    n_comp, n_wrap), in the order of ``distance``."""
    zc, _ = prepare_heights(z)
    ny, nx = zc.shape
    fixed = np.asarray(distance, float)
    levels, n, _, _ = _pass(zc.ravel(), ny, nx, dx, dy, K, periodic, connectivity, np.zeros(1),
                            np.zeros(1), np.ones((1, 1), bool), DEFAULT_POLICY, fixed)
    sums = levels.sums[:n]
    return np.column_stack([sums[f] for f in LEVEL_SUMS.names])


def curves_kernel(z, distance, water_height, laplace_pressure, *, dx, dy, K, periodic, connectivity):
    """Same contract as the base kernel: outputs in CURVE_VARIABLES order over (rh, distance),
    distance in the given order."""
    d = np.asarray(distance, float)
    ds, outs = curves(z, water_height, laplace_pressure, dx=dx, dy=dy, K=K, periodic=periodic,
                      connectivity=connectivity, distance=d)
    inv = np.argsort(np.argsort(d, kind="stable"), kind="stable")
    return tuple(o[:, inv] for o in outs)
