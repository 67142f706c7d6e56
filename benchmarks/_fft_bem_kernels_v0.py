"""Frozen copy of roughstick/contact/fft_bem/_kernels.py before the speed-up (commit 768b963): the
"old default" and the tight reference of benchmarks/bench_fft_bem_speed.py. Not imported by the
package; do not edit.
"""

from __future__ import annotations

import numba
import numpy as np
import scipy.fft as sfft

from roughstick.contact.adhesion import equilibrium_crossings

__all__ = ["FFTGrid", "pk_solve", "solve_state", "curve_on_grid", "auto_curve"]


class FFTGrid:
    """Periodic grid with the Boussinesq kernel of the half-space, :math:`\\tilde G = 2/q` (E* = 1).

    Parameters
    ----------
    shape : (int, int)
        Pixels (ny, nx).
    spacing : (float, float)
        Pixel sizes (dy, dx) in the internal length unit.
    dtype : numpy dtype
        float32 (default of the public model: twice as fast, gaps resolved to ~1e-6 of the
        heights) or float64.
    """

    def __init__(self, shape, spacing, dtype=np.float32):
        ny, nx = shape
        dy, dx = spacing
        qy = 2 * np.pi * np.fft.fftfreq(ny, d=dy)
        qx = 2 * np.pi * np.fft.rfftfreq(nx, d=dx)
        q = np.sqrt(qy[:, None] ** 2 + qx[None, :] ** 2)
        q[0, 0] = np.inf  # zero-mean displacement: the periodic convention of the reference
        self.kernel = (2.0 / q).astype(dtype)
        self.shape = (ny, nx)
        self.dtype = np.dtype(dtype)
        self.calls = 0

    def displacement(self, traction):
        """Zero-mean surface displacement caused by ``traction`` (compressive > 0 opens the gap)."""
        self.calls += 1
        spec = sfft.rfft2(traction.astype(self.dtype, copy=False), workers=1)
        spec *= self.kernel
        return sfft.irfft2(spec, s=self.shape, workers=1).astype(self.dtype, copy=False)


@numba.njit(cache=True, nogil=True)
def _direction(p, g, t, beta):
    pf, gf, tf = p.ravel(), g.ravel(), t.ravel()
    for i in range(pf.size):
        tf[i] = gf[i] + beta * tf[i] if pf[i] > 0 else 0.0


@numba.njit(cache=True, nogil=True)
def _step_length(p, g, t, r):
    pf, gf, tf, rf = p.ravel(), g.ravel(), t.ravel(), r.ravel()
    num = 0.0
    den = 0.0
    for i in range(pf.size):
        if pf[i] > 0:
            num += gf[i] * tf[i]
            den += rf[i] * tf[i]
    return num, den


@numba.njit(cache=True, nogil=True)
def _update(p, g, t, r, tau):
    """p <- max(p - tau t, 0); pixels at p = 0 with g < 0 enter the contact; g <- g - tau r.

    Returns (changed, entered): ``changed`` if a pixel was clamped or entered (then the gap
    update is not exact and the caller recomputes it), ``entered`` if one entered (the conjugate
    directions restart, as in Polonsky & Keer).
    """
    pf, gf, tf, rf = p.ravel(), g.ravel(), t.ravel(), r.ravel()
    tau = pf.dtype.type(tau)
    zero = pf.dtype.type(0.0)
    changed = False
    entered = False
    for i in range(pf.size):
        gi = gf[i]
        pn = pf[i] - tau * tf[i]
        gf[i] = gi - tau * rf[i]
        if pn <= zero:
            if gi < zero:
                pn = -tau * gi
                entered = True
                changed = True
            else:
                if pn < zero:
                    changed = True
                pn = zero
        pf[i] = pn
    return changed, entered


@numba.njit(cache=True, nogil=True)
def _residual(p, g):
    """(sum of g^2 on the contact set, sum of g^2 where g < 0, contact pixels)."""
    pf, gf = p.ravel(), g.ravel()
    s1 = 0.0
    s2 = 0.0
    n = 0
    for i in range(pf.size):
        gi = np.float64(gf[i])
        c = pf[i] > 0
        s1 += gi * gi if c else 0.0
        n += 1 if c else 0
        s2 += gi * gi if gi < 0 else 0.0
    return s1, s2, n


def pk_solve(grid, base, p0=None, *, wet=None, sigma0=0.0, h0=0.0, tolerance=1e-3,
             max_iterations=2000, scale=1.0):
    """Polonsky-Keer CG in displacement control, with the Dugdale wet set updated as it goes.

    Solves p >= 0, g = G p + base - sigma0 G[1_W] >= 0, p g = 0, with W = {g < h0} (contact
    included): the conjugate-gradient iterations of the non-adhesive problem on the shifted gap,
    the wet set refreshed from the exact gap after every iteration (a change shifts the gap by
    -sigma0 G[dW] and restarts the conjugate directions). ``sigma0 = 0``: dry contact.

    Parameters
    ----------
    grid : FFTGrid
    base : numpy.ndarray
        Rigid gap d - z (internal units).
    p0 : numpy.ndarray, optional
        Warm start of the contact pressure.
    wet : numpy.ndarray of bool, optional
        First guess of the wet set (default: {base < h0}).
    tolerance : float
        Stop when the rms gap on the contact set and the rms of negative gaps, over ``scale``,
        are both below it and the wet set did not change.
    scale : float
        Length the residual is measured against (the rms height of the map).

    Returns
    -------
    (p, g, W, residual, iterations) ; p is None when the gap stays open with no pressure.
    """
    dt = grid.dtype
    base = base.astype(dt, copy=False)
    adhesive = sigma0 > 0
    W = (base < h0) if wet is None else wet
    hp = base - dt.type(sigma0) * grid.displacement(W.astype(dt)) if adhesive else base
    if p0 is None or not np.any(p0 > 0):
        if adhesive:  # no contact yet: iterate the wet set on the open gap (jump-in if it closes)
            for _ in range(100):
                if not np.all(hp > 0):
                    break
                Wn = hp < h0
                if np.array_equal(Wn, W):
                    return None, hp, W, 0.0, 0
                W = Wn
                hp = base - dt.type(sigma0) * grid.displacement(W.astype(dt))
        elif np.all(hp > 0):
            return None, hp, W, 0.0, 0
        p = np.where(hp < 0, -1e-3 * hp, 0).astype(dt)  # seed: the interpenetrating pixels
    else:
        p = p0.astype(dt, copy=True)
    g = grid.displacement(p) + hp
    t = np.zeros_like(g)
    s1, s2, n = _residual(p, g)
    gold = 1.0
    delta = 0.0
    err = np.inf
    it = 0
    for it in range(1, int(max_iterations) + 1):  # noqa: B007 - the count is returned
        _direction(p, g, t, (delta * s1 / gold) if gold > 0 else 0.0)
        gold = s1
        r = grid.displacement(t)
        num, den = _step_length(p, g, t, r)
        if not den > 0:  # no direction left: the residual is that of the current state
            err = max(np.sqrt(s1 / max(n, 1)), np.sqrt(s2 / max(n, 1))) / scale
            break
        changed, entered = _update(p, g, t, r, num / den)
        delta = 0.0 if entered else 1.0
        if changed:
            g = grid.displacement(p) + hp
        moved = False
        if adhesive:
            Wn = g < h0
            if not np.array_equal(Wn, W):
                shift = -dt.type(sigma0) * grid.displacement(Wn.astype(dt) - W.astype(dt))
                hp = hp + shift
                g = g + shift
                W = Wn
                delta = 0.0
                moved = True
        s1, s2, n = _residual(p, g)
        err = max(np.sqrt(s1 / max(n, 1)), np.sqrt(s2 / max(n, 1))) / scale
        if err < tolerance and not moved:
            break
    return p, g, W, float(err), it


def solve_state(grid, z, d, sigma0, h0, *, state=None, tolerance=1e-3, max_iterations=2000,
                scale=1.0):
    """Adhesive contact state at one flat position ``d`` (internal units).

    Returns a dict: ``p`` contact pressure (>= 0), ``g`` gap, ``W`` wet set (gap < h0, contact
    included), ``d``, ``pbar`` mean pressure (contact pressure minus the Dugdale tension, over
    the apparent area), ``repulsive`` (traction on the contact set, tension included, as in the
    reference), ``contact_fraction``, ``wet_fraction`` (wet and not in contact), ``residual``,
    ``iterations``, ``converged``.
    """
    base = (d - z).astype(grid.dtype)
    warm = state is not None and state["p"] is not None and np.any(state["p"] > 0)
    if warm:
        # continuation: the flat moved by d - d_prev, so the gaps open by that much before the
        # surface relaxes; the wet set starts from those gaps (this follows the Tamaas reference
        # more closely than keeping the previous wet set: Gamma within 2 % instead of 5 % on soft
        # maps at low humidity, where the Dugdale zone has several equilibria)
        wet = (state["g"] + (d - state["d"])) < h0
        p0 = state["p"]
    else:
        wet, p0 = None, None
    p, g, W, err, it = pk_solve(grid, base, p0, wet=wet, sigma0=sigma0, h0=h0,
                                tolerance=tolerance, max_iterations=max_iterations, scale=scale)
    if warm and (p is None or not np.any(p > 0)):
        # the neck broke: a state without hard contact is taken from the undeformed wet set, as
        # the reference does (wet pixels can hold themselves by their own deflection: without
        # this the two would differ by a pixel or two of water at low humidity)
        return solve_state(grid, z, d, sigma0, h0, state=None, tolerance=tolerance,
                           max_iterations=max_iterations, scale=scale)
    if p is None:
        p = np.zeros_like(base)
    N = z.size
    contact = p > 0
    nc = int(contact.sum())
    psum = float(p.sum(dtype=np.float64))
    nw = int(W.sum()) if sigma0 > 0 else 0
    return dict(
        p=p, g=g, W=W, d=d,
        pbar=(psum - sigma0 * nw) / N,
        repulsive=(psum - sigma0 * nc) / N if sigma0 > 0 else psum / N,
        contact_fraction=nc / N,
        wet_fraction=(nw - int((W & contact).sum())) / N if sigma0 > 0 else 0.0,
        residual=err, iterations=it,
        converged=bool(err < 10 * tolerance),
    )


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
# halvings of the retraction step, each after a step lost the last hard contact, before a loss is
# accepted as the neck letting go (step 2 of auto_curve): the break is located to 1/64 of the step
BREAK_HALVINGS = 6


def auto_curve(z, spacing, sigma0, h0, *, tolerance=1e-3, n_contact=12, n_free=24, refine=2,
               dtype=np.float32, max_iterations=2000, keep=lambda st: st):
    """States on an automatic grid concentrated where Eq. 13, the pull-off and d_eq are decided.

    1. approach from max z in growing steps until the mean pressure is repulsive; the zero of
       the mean pressure, interpolated in that last step, estimates the equilibrium;
    2. retract from a quarter step below that estimate (deeper while the state there is not
       repulsive), ``n_contact`` uniform steps up to max z, going on by the same step while a
       neck stays in contact; a step that loses the last contact is retried from the attached
       state with half the step (the step stays shortened) until it is 2^-``BREAK_HALVINGS`` of
       the nominal one; only then does the neck count as broken;
    3. ``n_free`` points from there to just beyond max z + h0 (water, no hard contact: one or
       two FFTs each; the last one is dry);
    4. ``refine`` rounds bisecting the two intervals around the most tensile point and the
       interval holding the equilibrium, each new state warm-started from its closer neighbour;
       then (if ``refine`` > 0) ``EXTRA_PULL_OFF_ROUNDS`` more around the most tensile point.

    Returns (distances ascending, states, grid). ``keep(state)`` may add derived values to a
    state (e.g. a cluster count); it must leave ``p``, ``g`` and ``d`` (warm starts of later
    points).
    """
    grid = FFTGrid(z.shape, spacing, dtype)
    zmax = float(np.max(z))
    scale = _scale(z)
    floor = float(np.mean(z)) + 0.05 * scale
    full = {}
    kw = dict(tolerance=tolerance, max_iterations=max_iterations, scale=scale)

    def solve(d, state):
        st = solve_state(grid, z, d, sigma0, h0, state=state, **kw)
        full[d] = keep(st)
        return st

    # 1. approach: bracket the equilibrium (a 10x looser tolerance: only the sign of the mean
    #    pressure matters here)
    rough = dict(kw, tolerance=10 * tolerance)
    step = max(0.05 * h0, 0.02)
    d = zmax
    st = solve_state(grid, z, d, sigma0, h0, **rough)
    prev, p_prev = d, st["pbar"]
    while st["pbar"] <= 0 and d > floor:
        prev, p_prev = d, st["pbar"]
        d = max(d - step, floor)
        st = solve_state(grid, z, d, sigma0, h0, state=st, **rough)
        step *= 1.6
    width = max(prev - d, 1e-3)
    if st["pbar"] > 0 and p_prev <= 0:
        estimate = d + width * st["pbar"] / (st["pbar"] - p_prev)
    else:
        estimate = d
    # 2. retract from below the estimate, first making sure the start is repulsive
    start = max(estimate - 0.25 * width, floor)
    st = solve_state(grid, z, start, sigma0, h0, state=st, **kw)
    while st["pbar"] <= 0 and start > floor:
        start = max(start - 0.5 * width, floor)
        st = solve_state(grid, z, start, sigma0, h0, state=st, **kw)
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
        new = solve_state(grid, z, d, sigma0, h0, state=st, **kw)
        if (new["contact_fraction"] == 0 and st["contact_fraction"] > 0
                and shrink > 0.5 ** BREAK_HALVINGS):
            # the contact was lost in this step: retry from the attached state with half the step.
            # Warm-started one step away, the solver can land on the detached branch while the
            # attached one still exists (a one-pixel neck at RH 1e-3, 50 GPa: lost at max z +
            # 3.6 h0 in a step of 0.6 h0, held to 4.8 h0 in steps of 0.16 h0; Γ 0.56 x)
            shrink *= 0.5
            continue
        st = new
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
            solve(float(x), full[below[-1]] if below.size else None)
    dd = np.array(sorted(full))
    return dd, [full[x] for x in dd], grid
