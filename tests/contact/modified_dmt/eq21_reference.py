"""Literal, slow reference of the rough-surface modified DMT (Eqs. 16-23).

It follows the paper step by step, one distance at a time, with generic library tools and no
cleverness, so that the fast path in :mod:`roughstick.contact.modified_dmt._controller` can be tested against it:

1. flood the map at level ``d``: ``scipy.ndimage.label`` of ``{z >= d}``; on a periodic map the
   labels touching opposite edges are merged, and each asperity is unwrapped by a breadth-first
   walk over its pixels;
2. fit every asperity with the constrained sphere of Eqs. 19-21 using the generic optimiser
   ``scipy.optimize.least_squares`` (finite-difference Jacobian, bounds), from the same
   documented starts as the fast path (footprint centroid with the cap of twice the mean height,
   and the least-squares paraboloid) and from the fast path's plateau escape (a cap centred at
   the h-weighted centroid; the fast path tries it only when it has stopped on the plateau
   t = 0, the reference always, so it is the stricter yardstick), keeping the best; where that
   fit leaves pixels outside its sphere or puts its centre on the bound, from the 5 best points
   of a 7 x 7 x 8 grid too (the first of the fast path's three grids; the cost is not smooth
   there and has several minima); the
   plateau t = 0 is always a candidate; one- and
   two-pixel footprints use the same rule as the fast path but solved by ``scipy.optimize.brentq``;
3. Hertz force and contact area of each sphere (Eqs. 10-11), fit error (Eq. 23), and Eq. 16 with
   the wetted area ``(z >= d - h_water).sum()`` counted directly.

The conventions (mean plane, NaN pixels, connectivity, parametrisation by the cap height) are
those listed in :mod:`roughstick.contact.modified_dmt._controller`.
"""

from __future__ import annotations

import collections
import math

import numpy as np
from scipy import linalg, ndimage, optimize

from roughstick.contact.modified_dmt._controller import prepare_heights

__all__: list[str] = []


def _structure(connectivity):
    if connectivity == 4:
        return ndimage.generate_binary_structure(2, 1)
    if connectivity == 8:
        return ndimage.generate_binary_structure(2, 2)
    raise ValueError(f"connectivity must be 4 or 8, got {connectivity!r}.")


def _label(mask, connectivity, periodic):
    """Labels of ``mask`` (0 = background), merged across the edges when ``periodic``."""
    labels, n = ndimage.label(mask, structure=_structure(connectivity))
    if not periodic or n == 0:
        return labels, n
    parent = list(range(n + 1))

    def find(a):
        while parent[a] != a:
            a = parent[a]
        return a

    ny, nx = mask.shape
    steps = [(0, 1), (1, 0)] if connectivity == 4 else [(0, 1), (1, 0), (1, 1), (1, -1)]
    for r in range(ny):
        for c in range(nx):
            if not labels[r, c]:
                continue
            for dr, dc in steps:
                rr, cc = r + dr, c + dc
                if 0 <= rr < ny and 0 <= cc < nx:
                    continue  # interior neighbours are already labelled together
                rr, cc = rr % ny, cc % nx
                if labels[rr, cc]:
                    a, b = find(labels[r, c]), find(labels[rr, cc])
                    if a != b:
                        parent[max(a, b)] = min(a, b)
    roots = np.array([find(i) for i in range(n + 1)])
    uniq, new = np.unique(roots, return_inverse=True)
    return new[labels], len(uniq) - 1


def _unwrap(mask_component, connectivity, periodic):
    """Unwrapped (row, col) of the pixels of one component by breadth-first search."""
    ny, nx = mask_component.shape
    pix = np.argwhere(mask_component)
    seen = {}
    start = (int(pix[0, 0]), int(pix[0, 1]))
    seen[start] = start
    queue = collections.deque([start])
    if connectivity == 4:
        steps = [(0, 1), (1, 0), (0, -1), (-1, 0)]
    else:
        steps = [(dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if (dr, dc) != (0, 0)]
    wraps = False
    while queue:
        r, c = queue.popleft()
        ur, uc = seen[(r, c)]
        for dr, dc in steps:
            rr, cc = r + dr, c + dc
            if periodic:
                rr, cc = rr % ny, cc % nx
            elif not (0 <= rr < ny and 0 <= cc < nx):
                continue
            if not mask_component[rr, cc]:
                continue
            u = (ur + dr, uc + dc)
            if (rr, cc) in seen:
                if seen[(rr, cc)] != u:
                    wraps = True
                continue
            seen[(rr, cc)] = u
            queue.append((rr, cc))
    rows = np.array([seen[(int(r), int(c))][0] for r, c in pix], dtype=float)
    cols = np.array([seen[(int(r), int(c))][1] for r, c in pix], dtype=float)
    return pix, rows, cols, wraps


def footprints(z, d, *, dx, dy, periodic, connectivity):
    """The asperities of ``z`` (heights as given: refer them to the mean plane first) at level d.

    Yields ``(x, y, h)`` per asperity, in label order: unwrapped pixel centres [m] and heights [m].
    """
    with np.errstate(invalid="ignore"):
        mask = z >= d
    labels, n = _label(mask, connectivity, periodic)
    for lab in range(1, n + 1):
        pix, rows, cols, _wraps = _unwrap(labels == lab, connectivity, periodic)
        yield cols * dx, rows * dy, z[pix[:, 0], pix[:, 1]]


def sphere_profile(x, y, x0, y0, R, d, area):
    """Height of the constrained sphere of Eqs. 20-21 at (x, y), literally.

    ``sqrt(R^2 - r^2) + z0`` with ``z0 = d - sqrt(R^2 - A / pi)`` (Eq. 20); outside the
    projection of the sphere (r > R) the profile is taken at r = R. Written as
    ``d + (A/pi - r^2) / (sqrt(R^2 - r^2) + sqrt(R^2 - A/pi))``, the same number without the
    cancellation of two nearly equal square roots when R is large.
    """
    return d + above_level(x, y, x0, y0, R, area)


def above_level(x, y, x0, y0, R, area):
    """The sphere's height above the level d, ``sphere_profile - d``, without adding d."""
    if math.isinf(R):
        return np.zeros(np.shape(x))
    r2 = np.minimum((x - x0) ** 2 + (y - y0) ** 2, R * R)
    a2 = area / math.pi
    s = np.sqrt(R * R - r2)
    c = math.sqrt(max(R * R - a2, 0.0))
    if s.size and np.any(s + c == 0):
        return np.where(s + c == 0, 0.0, (a2 - r2) / np.where(s + c == 0, 1.0, s + c))
    return (a2 - r2) / (s + c)


def radius_from_cap(t, af):
    """Sphere radius with footprint radius ``af`` and cap height ``t * af`` (inf for t = 0)."""
    return af * (1.0 + t * t) / (2.0 * t) if t > 0 else math.inf


def fit_asperity(x, y, z, d, area, dx, dy):
    """Constrained sphere fit of one asperity (Eq. 21). Returns ``(R, E)`` [m].

    ``x, y`` are unwrapped pixel centres [m], ``z`` heights [m], ``d`` the level, ``area`` the
    footprint area A, ``dx, dy`` the pixel size. The unknowns are the centre (x0, y0), within the
    footprint's bounding box, and the cap height ``t = delta / a_f`` in [0, 1]
    (a smooth parametrisation of R, see :mod:`roughstick.contact.modified_dmt._controller`).
    """
    af = math.sqrt(area / math.pi)
    x = x - x.mean()
    y = y - y.mean()
    h = z - d
    n = x.size

    def residual(p):
        R = radius_from_cap(p[2], af)
        return (z - sphere_profile(x, y, p[0] * af, p[1] * af, R, d, area)) / af

    if n <= 2:
        rho = 0.0 if n == 1 else 0.5 * math.hypot(x[1] - x[0], y[1] - y[0]) / af
        H = h.mean() / af
        if H <= 0:
            t = 0.0
        elif _cap(1.0, rho) <= H:
            t = 1.0
        else:
            # the root can be as small as H ~ 1e-15 (a pixel just above the level): a relative
            # tolerance only (an absolute 1e-15 made R 1e6 times too small there)
            t = optimize.brentq(lambda t: H - _cap(t, rho), 0.0, 1.0, xtol=1e-300, rtol=4 * np.finfo(float).eps)
        p = (0.0, 0.0, t)
    else:
        H = 2.0 * h.mean() / af
        if H <= 0:
            return math.inf, 0.0
        # the centre stays in the footprint (X in Omega, Eq. 21): its bounding box
        lo = [(x.min() - dx / 2) / af, (y.min() - dy / 2) / af, 0.0]
        hi = [(x.max() + dx / 2) / af, (y.max() + dy / 2) / af, 1.0]
        starts = [[0.0, 0.0, min(H, 0.999)]]
        if n >= 5:
            second = _paraboloid_start(x / af, y / af, h / af)
            if second is not None:
                starts.append(second)
        third = _plateau_start(x / af, y / af, h / af)
        if third is not None:  # tried always here (the fast path: only when it ends on t = 0)
            starts.append(third)

        def excess(p):
            # cost minus the plateau's, sum Hm (Hm - 2 h): near the plateau the two costs differ
            # by less than their rounding (t ~ 1e-6), this difference does not
            hm = above_level(x, y, p[0] * af, p[1] * af, radius_from_cap(p[2], af), area) / af
            return float(np.sum(hm * (hm - 2 * h / af)))

        def solve(x0, best):
            sol = optimize.least_squares(
                residual,
                x0=np.clip(x0, lo, hi),
                bounds=(lo, hi),
                jac="3-point",
                method="trf",
                xtol=1e-15,
                ftol=1e-15,
                gtol=1e-15,
                max_nfev=2000,
            )
            cost = excess(sol.x)
            return (cost, sol.x) if best is None or cost < best[0] else best

        best = None
        for x0 in starts:
            best = solve(x0, best)
        p = best[1]
        R = radius_from_cap(p[2], 1.0)
        on_bound = p[0] <= lo[0] or p[0] >= hi[0] or p[1] <= lo[1] or p[1] >= hi[1]
        if p[2] > 0 and (np.any(np.hypot(x / af - p[0], y / af - p[1]) > R) or on_bound):
            # a pixel outside the sphere or the centre on its bound: the first grid search of
            # the fast path (7 x 7 centres over the box, 8 cap heights, the 5 best polished)
            grid = [(float(np.sum(residual((gx, gy, gt)) ** 2)), (gx, gy, gt))
                    for gx in np.linspace(lo[0], hi[0], 7) for gy in np.linspace(lo[1], hi[1], 7)
                    for gt in np.arange(1, 9) / 8]
            grid.sort(key=lambda g: g[0])
            for _c, x0 in grid[:5]:
                best = solve(x0, best)
        p = best[1] if best[0] < 0 else np.zeros(3)  # the plateau is always admissible
    E = math.sqrt(np.mean(residual(p) ** 2)) * af
    return radius_from_cap(p[2], af), E


def _paraboloid_start(x, y, h):
    """Apex and cap height of the least-squares paraboloid (the fast path's second start)."""
    G = np.stack([np.ones_like(x), x, y, -(x * x + y * y)], axis=1)
    M = G.T @ G
    lu, _piv = linalg.lu_factor(M, check_finite=False)
    if np.min(np.abs(np.diag(lu))) <= 1e-10 * np.max(np.diag(M)):
        return None
    w, u, v, q = linalg.lu_solve((lu, _piv), G.T @ h)
    if not q > 1e-9 * abs(h.mean()):  # flat (as the fast path: a curvature at rounding level)
        return None
    R = 1.0 / (2.0 * q)
    t0 = 1.0 if R <= 1.0 else 1.0 / (R + math.sqrt(R * R - 1.0))
    return [float(u / (2 * q)), float(v / (2 * q)), min(t0, 0.999)]


def _plateau_start(x, y, h):
    """The plateau-escape start (the fast path's ``plateau_escape``), or None.

    Near t = 0 the cost is ``sum h^2 - 2 t g(c) + O(t^2)`` with ``g(c) = sum h (1 - |x - c|^2)``,
    largest at the h-weighted centroid; if ``g > 0`` there, start at that centre with the
    Gauss-Newton cap height ``g / sum (1 - |x - c|^2)^2`` (the fast path's third start).
    """
    s = h.sum()
    if not s > 0:
        return None
    cx, cy = (h * x).sum() / s, (h * y).sum() / s
    j = 1.0 - (x - cx) ** 2 - (y - cy) ** 2
    g, a = float((j * h).sum()), float((j * j).sum())
    if not (g > 0 and a > 0):
        return None
    return [float(cx), float(cy), min(g / a, 0.999)]


def _cap(t, rho):
    """Dimensionless height above the plane, at distance rho from the centre, of the cap t.

    ``sqrt(R^2 - rho^2) - sqrt(R^2 - 1)``, written without the cancellation of the two square
    roots (R ~ 1e15 for a pixel just above the level).
    """
    if t == 0:
        return 0.0
    R = (1.0 + t * t) / (2.0 * t)
    if rho > R:
        return -math.sqrt(max(R * R - 1.0, 0.0))
    return (1.0 - rho * rho) / (math.sqrt(R * R - rho * rho) + math.sqrt(max(R * R - 1.0, 0.0)))


def hertz(R, area, K):
    """Hertz force [N] and contact area [m2] of a sphere of radius R cut by the plane (Eqs. 10-11)."""
    a2 = area / math.pi
    if math.isinf(R):
        return 0.0, math.pi * a2 / 2
    delta = a2 / (R + math.sqrt(max(R * R - a2, 0.0)))  # = R - sqrt(R^2 - a2): z0 + R - d
    return K * math.sqrt(R) * delta**1.5, math.pi * R * delta


def reference_curves(z, distance, water_height, laplace_pressure, *, dx, dy, K, periodic, connectivity):
    """Same contract as :func:`roughstick.contact._rough_kernels.curves_kernel`, computed literally."""
    z, nvalid = prepare_heights(z)
    ny, nx = z.shape
    distance = np.asarray(distance, dtype=float)
    hw = np.atleast_1d(np.asarray(water_height, dtype=float))
    dp = np.atleast_1d(np.asarray(laplace_pressure, dtype=float))
    A_S = nvalid * dx * dy
    D, NR = distance.size, hw.size
    out = {k: np.zeros((NR, D)) for k in ("p", "rep", "wet", "cf", "nc", "fe", "dm")}
    for j, d in enumerate(distance):
        n = 0
        F = Ah = Af = E2A = 0.0
        for x, y, h in footprints(z, d, dx=dx, dy=dy, periodic=periodic, connectivity=connectivity):
            n += 1
            area = x.size * dx * dy
            R, E = fit_asperity(x, y, h, d, area, dx, dy)
            f, a = hertz(R, area, K)
            F += f
            Ah += a
            Af += area
            E2A += E * E * area
        for i in range(NR):
            with np.errstate(invalid="ignore"):
                wet = np.count_nonzero(z >= d - hw[i]) * dx * dy
            out["wet"][i, j] = (wet - Ah) / A_S
            out["p"][i, j] = (F + dp[i] * (wet - Ah)) / A_S
        out["rep"][:, j] = F / A_S
        out["cf"][:, j] = Ah / A_S
        out["nc"][:, j] = n
        out["fe"][:, j] = math.sqrt(E2A / Af) if n else np.nan
        out["dm"][:, j] = np.nanmax(z) - d
    return tuple(out[k] for k in ("p", "rep", "wet", "cf", "nc", "fe", "dm"))
