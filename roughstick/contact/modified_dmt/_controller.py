"""Compiled kernels of the rough-surface modified DMT (Eqs. 16-23): the one-pass adaptive grid.

:func:`auto_pass` visits distance levels in one pass over the top tail of the height
distribution (:mod:`._rough_tail`): it walks down from the first water contact, refines where a
curve turns, bisects the zero crossings of the mean pressure (equilibrium), the pull-off
extremum and the wetting events, and stops once every humidity's curve is past its outermost
stable crossing. Each level's asperities are fitted with Eq. 21 (:mod:`._rough_fit`); water
areas come from the height buckets. With ``fixed`` levels it evaluates just those (any order).

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

import threading

import numba as nb
import numpy as np

from ..._core.conventions import CURVE_VARIABLES
from ._search import GRID_KEEP
from ._tail import (
    _NEXTB,
    _NJ,
    _NSORTED,
    _contact_event_above,
    _find,
    _grow1,
    _grow2,
    _n_above,
    _seek,
    _sort_until,
    _wet_event_above,
    bucket_sort,
    count_ge,
    eval_level,
    max_tie_bound,
    prepare_heights,
)

__all__ = ["OUTPUTS", "DEFAULT_PARAMS", "auto_pass", "curves", "curves_kernel", "hertz_levels", "prepare_heights", "grid_params"]

OUTPUTS = CURVE_VARIABLES

# parameters (index in the params array)
EPS, ETA, FINE, ZERO_BAND, PULL_BAND, PULL_STOP, MARGIN, WFLOOR_REL, MAXP, DEQ_TOL, PULL_FINE, PULL_SMOOTH, TIE, ZCAP, DEQ_EST, DEQ_MAXW = range(16)
DEFAULT_PARAMS = np.array([0.02, 0.02, 0.1, 0.03, 0.003, 0.0, 0.03, 1e-5, 4000.0, 0.004, 2.0, 0.002, 1.0, 3.0, 0.25, 2.0])


@nb.njit(**_NJ)
def _level(d, li, Dv, HZ, WET, hw, start, idx, zb, zmin, scale, scal, order, ztail, pos, P, Cc, live, LOG,
           logstart, pooltop, pi, px, py, pz, nx, ny, periodic, connectivity, nbuf, dx, dy, K, xs, ys, hs, wt,
           M):  # pragma: no cover - compiled
    """Move the union-find to level d (growing the log and pixel pool as needed), evaluate it
    into slot li; returns the (possibly grown) log and pool arrays."""
    _sort_until(start, idx, zb, zmin, scale, scal, order, ztail, pos, d)
    k = _n_above(ztail, scal[_NSORTED], d)
    while True:
        r = _seek(k, P, Cc, live, scal, LOG, logstart, pooltop, order, ztail, pos, pi, px, py, pz, nx, ny,
                  periodic, connectivity, nbuf)
        if r == 0:
            break
        if r == 1:
            LOG = _grow2(LOG, 2 * LOG.shape[0])
        else:
            n2 = 2 * pi.size
            pi, px, py, pz = _grow1(pi, n2), _grow1(px, n2), _grow1(py, n2), _grow1(pz, n2)
    f, ha, fa, e2, nc, nw = eval_level(Cc, live, scal, px, py, pz, d, dx, dy, K, xs, ys, hs, wt, M)
    Dv[li] = d
    HZ[li, 0], HZ[li, 1], HZ[li, 2], HZ[li, 3], HZ[li, 4], HZ[li, 5] = f, ha, fa, e2, nc, nw
    for j in range(hw.size):
        WET[li, j] = count_ge(start, zb, zmin, scale, d - hw[j])
    return LOG, pi, px, py, pz


@nb.njit(**_NJ)
def auto_pass(zflat, ny, nx, periodic, connectivity, dx, dy, K, hw, dp, mask, params, fixed, ws_start, ws_idx, ws_zb,
              ws_pos, P, Cc, live, order, ztail, logstart, pooltop, LOG, pi, px, py, pz, xs, ys, hs, wt):  # pragma: no cover
    """Evaluate the levels of the adaptive grids (or the ``fixed`` levels if given, any order).

    Returns ``(D, HZ, WET, MEM, n, crossed)``: level distances, Hertz sums per level
    ``(force, hertz_area, foot_area, err2_area, n_comp, n_wrap)``, wet pixel counts per humidity,
    membership of each level in each controller's grid, the number of levels, and each
    controller's outermost stable crossing per humidity (NaN: none found).
    """
    R = hw.size
    C = mask.shape[0]
    start = ws_start
    idx = ws_idx
    zb = ws_zb
    nbuck = start.size - 1
    zmin, zmax, scale, nvalid, sigma = bucket_sort(zflat, start, idx, zb)
    span = max(zmax - zmin, 1e-300)
    pix = dx * dy
    apparent = nvalid * pix
    # union-find state (capacities: every valid pixel; pages never touched cost nothing)
    pos = ws_pos
    pos[:] = -1
    scal = np.zeros(8, np.int64)
    scal[_NEXTB] = nbuck - 1
    nbuf = np.empty((4, 8), np.int64)
    M = np.zeros((4, GRID_KEEP))  # the sphere fits' work array
    # levels
    maxp = int(params[MAXP]) if fixed.size == 0 else fixed.size
    Dv = np.empty(maxp)
    HZ = np.empty((maxp, 6))
    WET = np.empty((maxp, R), np.int64)
    MEM = np.zeros((maxp, C), np.bool_)
    ordd = np.empty(maxp, np.int64)
    nlev = 0

    if fixed.size > 0:
        desc = np.argsort(-fixed)
        for t in range(fixed.size):
            d = fixed[desc[t]]
            LOG, pi, px, py, pz = _level(d, desc[t], Dv, HZ, WET, hw, start, idx, zb, zmin, scale, scal, order,
                                         ztail, pos, P, Cc, live, LOG, logstart, pooltop, pi, px, py, pz, nx,
                                         ny, periodic, connectivity, nbuf, dx, dy, K, xs, ys, hs, wt, M)
        return Dv, HZ, WET, MEM, fixed.size, np.full((C, R), np.nan), LOG, pi, px, py, pz, scal, np.zeros(maxp, np.int64)

    eps = params[EPS]
    eta = params[ETA]
    fine = params[FINE]
    deq_tol = params[DEQ_TOL]
    pull_fine = params[PULL_FINE]
    pull_smooth = params[PULL_SMOOTH]
    tie_factor = params[TIE]
    zcap = params[ZCAP]
    deq_est = params[DEQ_EST]
    deq_maxw = params[DEQ_MAXW]
    zero_band = params[ZERO_BAND]
    pull_band = params[PULL_BAND]
    pull_stop = params[PULL_STOP]
    margin = params[MARGIN]
    wfloor = params[WFLOOR_REL] * span
    # each controller's grid starts above the first wetting of its own humidities
    topc = np.empty(C)
    for c in range(C):
        hwmax = 0.0
        for j in range(R):
            if mask[c, j]:
                hwmax = max(hwmax, hw[j])
        topc[c] = zmax + hwmax + 1e-4 * span
    dfloor = zmin - 1e-3 * span
    dtop = np.empty(R)
    for j in range(R):
        dtop[j] = zmax + hw[j]
    # controllers
    S = np.zeros((C, R))
    # the pull-off is at least the water term just above the first contact (no Hertz there)
    for j in range(R):
        w0 = count_ge(start, zb, zmin, scale, np.nextafter(zmax, np.inf) - hw[j])
        for c in range(C):
            S[c, j] = abs(dp[j]) * w0 * pix / apparent
    crossed = np.full((C, R), np.nan)
    pmin = np.zeros((C, R))
    phase = np.zeros(C, np.int64)
    dcur = topc.copy()
    wstep = (topc - zmax) / 4
    stopat = np.full(C, np.nan)
    SD = 256
    stk = np.empty((C, SD, 2))
    sp = np.zeros(C, np.int64)
    nacc = np.zeros(C, np.int64)
    lastw = np.zeros(C)
    dnext = np.zeros(C)
    # pull refinement state
    jj = np.zeros(C, np.int64)
    rnd = np.zeros(C, np.int64)
    best = np.zeros(C)
    REQ = np.empty((C, maxp))
    SREQ = np.zeros((C, maxp), np.int64)
    SDEPTH = np.zeros((maxp, R), np.int64)
    SRC = np.zeros((maxp, R), np.bool_)
    PH = np.zeros(maxp, np.int64)
    wantph = 0
    nreq = np.zeros(C, np.int64)
    # start: each controller tests [top - w, top]
    for c in range(C):
        dnext[c] = max(topc[c] - wstep[c], dfloor)
        stk[c, 0, 0] = dnext[c]
        stk[c, 0, 1] = topc[c]
        sp[c] = 1
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
                    if sp[c] == 0:
                        # interval done: next step of the descent, or stop
                        dcur[c] = dnext[c]
                        if nacc[c] > 1:
                            wstep[c] = 2.0 * lastw[c]
                        else:
                            wstep[c] = 2.0 * wstep[c]
                        nacc[c] = 0
                        allx = True
                        lowest = np.inf
                        for j in range(R):
                            if mask[c, j]:
                                if np.isnan(crossed[c, j]):
                                    allx = False
                                else:
                                    lowest = min(lowest, crossed[c, j])
                        if allx and np.isnan(stopat[c]):
                            stopat[c] = lowest - margin * sigma
                        if (allx and dcur[c] <= stopat[c]) or dcur[c] <= dfloor or full:
                            phase[c] = 1
                            jj[c] = -1
                            nreq[c] = 0
                            progressed = True
                            continue
                        dnext[c] = max(dcur[c] - wstep[c], dfloor)
                        stk[c, 0, 0] = dnext[c]
                        stk[c, 0, 1] = dcur[c]
                        sp[c] = 1
                    a = stk[c, sp[c] - 1, 0]
                    b = stk[c, sp[c] - 1, 1]
                    m = 0.5 * (a + b)
                    below = True  # wholly below every humidity's crossing: nothing to test there
                    for j in range(R):
                        if mask[c, j] and (np.isnan(crossed[c, j]) or b > crossed[c, j]):
                            below = False
                    if below and _find(Dv, ordd, nlev, a) >= 0 and _find(Dv, ordd, nlev, b) >= 0:
                        sp[c] -= 1
                        progressed = True
                        continue
                    ia = _find(Dv, ordd, nlev, a)
                    ib = _find(Dv, ordd, nlev, b)
                    im = _find(Dv, ordd, nlev, m)
                    if ib < 0:
                        if b > want:
                            want = b
                            wantph = 0
                        continue
                    if im < 0:
                        if m > want:
                            want = m
                            wantph = 0
                        continue
                    if ia < 0:
                        if a > want:
                            want = a
                            wantph = 0
                        continue
                    MEM[ia, c] = True
                    MEM[ib, c] = True
                    MEM[im, c] = True
                    # the midpoint test (see auto_proto): accept, or split (upper half first)
                    w = b - a
                    ok = True
                    if w > 2 * wfloor and not full:
                        for j in range(R):
                            if not mask[c, j]:
                                continue
                            if not (np.isnan(crossed[c, j]) or b > crossed[c, j]):
                                continue
                            va = (HZ[ia, 0] + dp[j] * (WET[ia, j] * pix - HZ[ia, 1])) / apparent
                            vb = (HZ[ib, 0] + dp[j] * (WET[ib, j] * pix - HZ[ib, 1])) / apparent
                            vm = (HZ[im, 0] + dp[j] * (WET[im, j] * pix - HZ[im, 1])) / apparent
                            err = abs(vm - 0.5 * (va + vb))
                            lo3 = min(min(va, vb), vm)
                            hi3 = max(max(va, vb), vm)
                            f = 1.0
                            cap = eta * sigma
                            if np.isnan(crossed[c, j]):
                                if hi3 > 0.0 and lo3 < 0.0:
                                    # the crossing: a finer grid moves d_eq within its interval only;
                                    # wider intervals pass when the root of the chord and that of
                                    # the half holding the (stable) crossing agree
                                    tol_d = deq_tol * max(abs(a), sigma)
                                    if w > tol_d:
                                        if not (w <= deq_maxw * tol_d and va >= 0.0 and vb < 0.0):
                                            ok = False
                                            break
                                        r_ab = a + w * va / (va - vb)
                                        if vm >= 0.0:
                                            r_h = m + 0.5 * w * vm / (vm - vb)
                                        else:
                                            r_h = a + 0.5 * w * va / (va - vm)
                                        if not (abs(r_ab - r_h) <= deq_est * tol_d):
                                            ok = False
                                            break
                                    continue
                                if min(min(abs(va), abs(vb)), abs(vm)) <= zero_band * S[c, j]:
                                    f = fine
                                    cap = zcap * eta * sigma
                            fl = min(eta * max(dtop[j] - a, 0.0), cap)
                            if not (err <= f * eps * S[c, j] or w <= f * fl):
                                ok = False
                                break
                    if ok:
                        sp[c] -= 1
                        # advance over (b, m) then (m, a)
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
                            for j in range(R):
                                if not mask[c, j]:
                                    continue
                                ph = (HZ[ih, 0] + dp[j] * (WET[ih, j] * pix - HZ[ih, 1])) / apparent
                                pl = (HZ[il, 0] + dp[j] * (WET[il, j] * pix - HZ[il, 1])) / apparent
                                S[c, j] = max(S[c, j], max(abs(ph), abs(pl)))
                                if np.isnan(crossed[c, j]):
                                    if pl < pmin[c, j]:
                                        pmin[c, j] = pl
                                    if pl >= 0.0 and ph < 0.0:
                                        crossed[c, j] = dh - (dh - dl) * ph / (ph - pl)
                        nacc[c] += 1
                        lastw[c] = w
                    else:
                        if sp[c] + 2 > SD:
                            sp[c] -= 1  # (cannot happen: depth <= log2(span / wfloor))
                        else:
                            stk[c, sp[c] - 1, 0] = a
                            stk[c, sp[c] - 1, 1] = m
                            stk[c, sp[c], 0] = m
                            stk[c, sp[c], 1] = b
                            sp[c] += 1
                    progressed = True
                    continue
                # ---- phase 1: pull-off refinement, one humidity of the mask after the other
                if phase[c] == 1 and nreq[c] > 0:
                    # requests pending: the highest missing one
                    missing = False
                    for q in range(nreq[c]):
                        if _find(Dv, ordd, nlev, REQ[c, q]) < 0:
                            if REQ[c, q] > want:
                                want = REQ[c, q]
                                wantph = 1
                            missing = True
                    if missing:
                        continue
                    after = np.inf
                    j = jj[c]
                    for q in range(nreq[c]):
                        il = _find(Dv, ordd, nlev, REQ[c, q])
                        MEM[il, c] = True
                        if SREQ[c, q] > 0 and SDEPTH[il, j] == 0:
                            SDEPTH[il, j] = SREQ[c, q]
                        after = min(after, (HZ[il, 0] + dp[j] * (WET[il, j] * pix - HZ[il, 1])) / apparent)
                    nreq[c] = 0
                    if pull_stop > 0.0 and not (after < best[c] * (1.0 + pull_stop)):
                        rnd[c] = 99  # no improvement: next humidity
                    progressed = True
                    continue
                if phase[c] == 1:
                    # next round for humidity jj (or the next humidity)
                    if jj[c] < 0 or rnd[c] >= 40:
                        jj[c] += 1
                        while jj[c] < R and not mask[c, jj[c]]:
                            jj[c] += 1
                        rnd[c] = 0
                        if jj[c] >= R:
                            phase[c] = 3
                            progressed = True
                            continue
                    j = jj[c]
                    # this controller's grid, sorted
                    cnt = 0
                    for q in range(nlev):
                        if MEM[ordd[q], c]:
                            cnt += 1
                    gl = np.empty(cnt, np.int64)
                    cnt = 0
                    for q in range(nlev):
                        if MEM[ordd[q], c]:
                            gl[cnt] = ordd[q]
                            cnt += 1
                    xc = crossed[c, j] if not np.isnan(crossed[c, j]) else -np.inf
                    bi = -1
                    bv = 0.0
                    for q in range(cnt):
                        if Dv[gl[q]] >= xc:
                            v = (HZ[gl[q], 0] + dp[j] * (WET[gl[q], j] * pix - HZ[gl[q], 1])) / apparent
                            if v < bv:
                                bv = v
                                bi = q
                    if bi < 0:
                        rnd[c] = 99
                        progressed = True
                        continue
                    best[c] = bv
                    rnd[c] += 1
                    nr = 0
                    for q in range(cnt - 1):
                        d0 = Dv[gl[q]]
                        d1 = Dv[gl[q + 1]]
                        if d0 < xc:
                            continue
                        v0 = (HZ[gl[q], 0] + dp[j] * (WET[gl[q], j] * pix - HZ[gl[q], 1])) / apparent
                        v1 = (HZ[gl[q + 1], 0] + dp[j] * (WET[gl[q + 1], j] * pix - HZ[gl[q + 1], 1])) / apparent
                        # a tooth can hide inside the interval: the pixels drying at one height
                        # in it (at most the fullest bucket, at most those drying in it) drop
                        # the curve by up to their water term below its ends
                        ndry = WET[gl[q], j] - WET[gl[q + 1], j]
                        tie = 0.0
                        if ndry > 0:
                            tie = abs(dp[j]) * pix / apparent * min(
                                ndry, max_tie_bound(start, zmin, scale, d0 - hw[j], d1 - hw[j]))
                        if not (min(v0, v1 - tie_factor * tie) <= bv * (1.0 - pull_band)):
                            continue
                        L = min(max(dtop[j] - d0, 0.0), sigma)
                        if d1 - d0 <= max(pull_fine * eta * L, 2 * wfloor):
                            # resolved: once, the most tensile points of the teeth just above d0
                            # (the wetting and the contact event there: water and Hertz jumps)
                            # (each point is the source of these snaps once, and snapped points
                            # up to depth 2: the chain of events stops)
                            src = gl[q]
                            if SRC[src, j] or SDEPTH[src, j] >= 2:
                                continue
                            SRC[src, j] = True
                            de = _wet_event_above(d0, hw[j], start, zb, zmin, scale)
                            if d0 < de < d1 and nr < maxp:
                                REQ[c, nr] = de
                                SREQ[c, nr] = SDEPTH[src, j] + 1
                                nr += 1
                            dcx = _contact_event_above(d0, ztail, scal[_NSORTED])
                            if d0 < dcx < d1 and dcx != de and nr < maxp:
                                REQ[c, nr] = dcx
                                SREQ[c, nr] = SDEPTH[src, j] + 1
                                nr += 1
                            continue
                        # smooth here (each end on the chord of its neighbours within
                        # pull_smooth): a finer grid finds nothing deeper, no need to bisect
                        # (neighbours at least half the interval away: not the other point of
                        # a snapped pair)
                        qa = q - 1
                        while qa >= 0 and d0 - Dv[gl[qa]] < 0.5 * (d1 - d0):
                            qa -= 1
                        qb = q + 2
                        while qb < cnt and Dv[gl[qb]] - d1 < 0.5 * (d1 - d0):
                            qb += 1
                        if qa >= 0 and qb < cnt:
                            vm1 = (HZ[gl[qa], 0] + dp[j] * (WET[gl[qa], j] * pix - HZ[gl[qa], 1])) / apparent
                            v2 = (HZ[gl[qb], 0] + dp[j] * (WET[gl[qb], j] * pix - HZ[gl[qb], 1])) / apparent
                            dm1 = Dv[gl[qa]]
                            d2 = Dv[gl[qb]]
                            e0 = abs(v0 - (vm1 + (v1 - vm1) * (d0 - dm1) / (d1 - dm1)))
                            e1 = abs(v1 - (v0 + (v2 - v0) * (d1 - d0) / (d2 - d0)))
                            if max(e0, e1) <= pull_smooth * abs(bv) and tie <= pull_smooth * abs(bv):
                                continue
                        m = 0.5 * (d0 + d1)
                        if nr < maxp:
                            REQ[c, nr] = m
                            SREQ[c, nr] = 0
                            nr += 1
                        de = _wet_event_above(m, hw[j], start, zb, zmin, scale)
                        if m < de < d1 and nr < maxp:
                            REQ[c, nr] = de
                            SREQ[c, nr] = 0
                            nr += 1
                    if nr == 0 or nlev + nr > maxp:
                        rnd[c] = 99
                    else:
                        nreq[c] = nr
                    progressed = True
                    continue
        if alldone:
            break
        if want == -np.inf:
            continue
        # ---- evaluate the highest request
        d = want
        if nlev >= maxp:
            full = True
            # serve no more levels: the controllers finish with what they have
            for c in range(C):
                if phase[c] == 0:
                    phase[c] = 1
                    jj[c] = -1
                    nreq[c] = 0
                elif phase[c] == 1:
                    nreq[c] = 0
                    rnd[c] = 99
                    jj[c] = R
            continue
        li = nlev
        PH[li] = wantph
        LOG, pi, px, py, pz = _level(d, li, Dv, HZ, WET, hw, start, idx, zb, zmin, scale, scal, order, ztail, pos,
                                     P, Cc, live, LOG, logstart, pooltop, pi, px, py, pz, nx, ny, periodic,
                                     connectivity, nbuf, dx, dy, K, xs, ys, hs, wt, M)
        # insert into the sorted order
        q = nlev
        while q > 0 and Dv[ordd[q - 1]] > d:
            ordd[q] = ordd[q - 1]
            q -= 1
        ordd[q] = li
        nlev += 1
    return Dv, HZ, WET, MEM, nlev, crossed, LOG, pi, px, py, pz, scal, PH



_WS = threading.local()
LAST_STATS = np.zeros(8, np.int64)  # counters of the last call in this process (benchmarks only)


def workspace(n):
    """Per-thread reusable arrays for maps of n pixels.

    Every array the kernel needs, sized for the whole map (pages never touched cost nothing);
    reused from call to call, because touching fresh memory costs page faults (~1.7 ms per MB on
    the development machine) and ensembles call the kernel thousands of times per thread.
    """
    ws = getattr(_WS, "arrays", None)
    if ws is None or ws["n"] != n:
        nbuck = max(1024, n // 8)
        cap = n + 1
        ws = dict(
            n=n,
            start=np.empty(nbuck + 1, np.int64), idx=np.empty(n, np.int32), zb=np.empty(n),
            pos=np.empty(n, np.int32), P=np.empty((cap, 3), np.int32), C=np.empty((cap, 8), np.int64),
            live=np.empty(cap, np.int32), order=np.empty(cap, np.int64), ztail=np.empty(cap),
            logstart=np.empty(cap + 1, np.int64), pooltop=np.empty(cap + 1, np.int64),
            LOG=np.empty((1024, 10), np.int64), pi=np.empty(4096, np.int32), px=np.empty(4096, np.int32),
            py=np.empty(4096, np.int32), pz=np.empty(4096), xs=np.empty(cap + 8), ys=np.empty(cap + 8),
            hs=np.empty(cap + 8), wt=np.empty(cap + 8),
        )
        _WS.arrays = ws
    return ws


_WS_ORDER = ("start", "idx", "zb", "pos", "P", "C", "live", "order", "ztail", "logstart", "pooltop", "LOG", "pi",
             "px", "py", "pz", "xs", "ys", "hs", "wt")


def grid_params(npix):
    """Controller parameters for a map of ``npix`` pixels: the tolerances on the curves' shape
    scale with sqrt(npix / 1024^2) between 0.25 and 1. Small maps have few contacting pixels, so
    their curves are staircases of large jumps that need a finer grid, and each level is cheap."""
    p = DEFAULT_PARAMS.copy()
    f = min(1.0, max(0.25, (npix / 1024.0**2) ** 0.5))
    p[EPS] *= f
    p[ETA] *= f
    p[PULL_SMOOTH] *= f
    return p


def curves(z, hw, dp, *, dx, dy, K, periodic, connectivity, distance=None, per_rh=False, params=None):
    """Curves (CURVE_VARIABLES order, over (rh, distance) ascending) on an automatic or given grid.
    ``per_rh``: one controller per humidity (its levels do not depend on the other humidities):
    a list of per-humidity tuples; ``"union"``: all humidities on the union, and the membership."""
    zc, nvalid = prepare_heights(z)
    ny, nx = zc.shape
    zflat = zc.ravel()
    hw = np.atleast_1d(np.asarray(hw, float))
    dp = np.atleast_1d(np.asarray(dp, float))
    R = hw.size
    p = grid_params(zflat.size) if params is None else np.asarray(params, float)
    if distance is None and not np.nanmax(zflat) > np.nanmin(zflat):
        # a flat map has no height scale: a uniform grid over the water range (contact at d <= 0)
        distance = np.linspace(0.0, 1.05 * max(float(np.max(hw)), 1e-10), 65)
        per_rh = False
    fixed = np.empty(0) if distance is None else np.asarray(distance, float)
    mask = np.eye(R, dtype=bool) if per_rh else np.ones((1, R), bool)
    ws = workspace(zflat.size)
    out = auto_pass(zflat, ny, nx, bool(periodic), int(connectivity), float(dx), float(dy), float(K), hw, dp,
                    mask, p, fixed, *(ws[k] for k in _WS_ORDER))
    Dv, HZ, WET, MEM, n, crossed = out[:6]
    ws["LOG"], ws["pi"], ws["px"], ws["py"], ws["pz"] = out[6:11]
    LAST_STATS[:] = out[11]
    Dv, HZ, WET, MEM = Dv[:n], HZ[:n], WET[:n], MEM[:n]
    zmax = float(np.nanmax(zflat))
    apparent = nvalid * dx * dy

    def build(sel, rows):
        o = np.argsort(Dv[sel], kind="stable")
        d = Dv[sel][o]
        hz = HZ[sel][o]
        wet = WET[sel][o][:, rows].T * (dx * dy)
        f, ha, fa, e2, nc = hz[:, 0], hz[:, 1], hz[:, 2], hz[:, 3], hz[:, 4]
        net = (wet - ha[None, :]) / apparent
        rep = f / apparent
        pres = rep[None, :] + dp[rows][:, None] * net
        with np.errstate(invalid="ignore", divide="ignore"):
            fe = np.where(nc > 0, np.sqrt(e2 / np.where(fa > 0, fa, 1.0)), np.nan)
        shape = (len(rows), d.size)
        return d, (pres, np.broadcast_to(rep, shape).copy(), net, np.broadcast_to(ha / apparent, shape).copy(),
                   np.broadcast_to(nc, shape).copy(), np.broadcast_to(fe, shape).copy(),
                   np.broadcast_to(zmax - d, shape).copy())

    if distance is not None:
        return build(np.ones(n, bool), np.arange(R))
    if not per_rh:
        return build(MEM[:, 0], np.arange(R))
    if per_rh == "union":
        u = MEM.any(axis=1)
        return (*build(u, np.arange(R)), MEM[u][np.argsort(Dv[u], kind="stable")].T)
    return [build(MEM[:, j], np.array([j])) for j in range(R)]


def hertz_levels(z, distance, *, dx, dy, K, periodic, connectivity):
    """Hertz sums per distance (any order): columns (force, hertz_area, foot_area, err2_area,
    n_comp, n_wrap), in the order of ``distance``."""
    zc, _ = prepare_heights(z)
    ny, nx = zc.shape
    zflat = zc.ravel()
    fixed = np.asarray(distance, float)
    ws = workspace(zflat.size)
    out = auto_pass(zflat, ny, nx, bool(periodic), int(connectivity), float(dx), float(dy), float(K),
                    np.zeros(1), np.zeros(1), np.ones((1, 1), bool), DEFAULT_PARAMS, fixed,
                    *(ws[k] for k in _WS_ORDER))
    ws["LOG"], ws["pi"], ws["px"], ws["py"], ws["pz"] = out[6:11]
    return out[1][: fixed.size]


def curves_kernel(z, distance, water_height, laplace_pressure, *, dx, dy, K, periodic, connectivity):
    """Same contract as the base kernel: outputs in CURVE_VARIABLES order over (rh, distance),
    distance in the given order."""
    d = np.asarray(distance, float)
    ds, outs = curves(z, water_height, laplace_pressure, dx=dx, dy=dy, K=K, periodic=periodic,
                      connectivity=connectivity, distance=d)
    inv = np.argsort(np.argsort(d, kind="stable"), kind="stable")
    return tuple(o[:, inv] for o in outs)
