r"""Numba kernels of the cohesive beam model (plain numpy, no xarray; public side: :mod:`.cohesive`).

Internal units (all kernels): length along the beam in µm, deflection and gap in nm, energy in pJ,
pressure as ``p_hat = p[Pa] * 1e-9`` (pJ µm⁻² nm⁻¹), adhesion energy per area in J m⁻² (= pJ µm⁻²).
With these, the bending stiffness is ``EI_hat = EI[N m²] * 1e12`` and every matrix entry is O(1e-4 ..
1e3), which keeps the banded factorisation well scaled.

Discretisation: Euler-Bernoulli Hermite-cubic elements (deflection ``v`` and slope ``v'`` per
node), node 0 clamped (both dofs removed), free tip. Unknown vector ``u = [v1, v1', v2, v2', ...]``
(half-bandwidth 3). Interface energy ``w * sum_q wq * phi_k(g_q)`` with 3-point Gauss per element;
every element lies inside one patch (the mesh is aligned on patch boundaries), so the patch law of
element ``e`` is ``law_index[e]``. The kernels take their state as two named tuples:
:class:`LawTable` (the tabulated laws) and :class:`MeshArrays` (the mesh and the beam).

The driver at the end (:class:`BeamMesh`, :func:`release`) follows the release protocol by a
front-controlled continuation (the unknown is the uniform load, the control the position of the
point of the beam at the marker gap), in plain numpy around the kernels.

Laws are tabulated on one uniform gap grid ``g_i = g_lo + i*dg`` (nm): ``P[k, i]`` the pressure,
``PHI[k, i] = int_{g_i}^{inf} p`` the potential (exact for the piecewise-linear ``p``). Above the
grid ``p = phi = 0``; below it the last segment is extrapolated linearly (stiff repulsion).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit

__all__ = ["LawTable", "MeshArrays", "tabulate_laws", "law_eval", "assemble", "ldl_factor",
           "ldl_solve", "load_vector", "point_interp", "marker_vector", "BeamMesh", "release",
           "SolverError", "ReleaseResult", "pull_in"]

GAUSS_XI = np.array([0.5 - 0.5 * math.sqrt(0.6), 0.5, 0.5 + 0.5 * math.sqrt(0.6)])
GAUSS_W = np.array([5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0])


# ----------------------------------------------------------------------------- laws
class LawTable(NamedTuple):
    """The patch laws on one uniform gap grid ``g_i = g_lo + i dg`` (nm): pressure ``P[k, i]``
    (p_hat), its slope ``S[k, i]`` on segment i and the potential ``PHI[k, i]``."""

    P: np.ndarray
    S: np.ndarray
    PHI: np.ndarray
    g_lo: float
    dg: float


class MeshArrays(NamedTuple):
    """What the assembly needs of a mesh and its beam: node positions (µm), the law of each
    element, the gap (nm), the bending stiffness EI_hat, the width (µm) and the unit load vector."""

    xnode: np.ndarray
    law_index: np.ndarray
    gap: float
    EI: float
    width: float
    F: np.ndarray


def tabulate_laws(pressure_hat: np.ndarray, g_lo: float, dg: float) -> tuple[np.ndarray, np.ndarray]:
    """Potential table ``PHI`` and slopes ``S`` of tabulated pressures ``P`` (last axis = gap grid).

    ``P[..., -1]`` must be 0 (the law vanishes at the top of the grid).
    """
    P = np.ascontiguousarray(pressure_hat, dtype=np.float64)
    seg = 0.5 * (P[..., 1:] + P[..., :-1]) * dg          # int over each segment
    phi = np.zeros_like(P)
    phi[..., :-1] = np.cumsum(seg[..., ::-1], axis=-1)[..., ::-1]
    S = np.empty_like(P)
    S[..., :-1] = np.diff(P, axis=-1) / dg
    S[..., -1] = 0.0
    return phi, S


@njit(cache=True, nogil=True)
def law_eval(laws, k, g):
    """(p, dp/dg, phi) of law ``k`` of the :class:`LawTable` at gap ``g`` (nm); piecewise-linear
    p, exact phi."""
    n = laws.P.shape[1]
    t = (g - laws.g_lo) / laws.dg
    if t >= n - 1:
        return 0.0, 0.0, 0.0
    if t < 0.0:
        i = 0
    else:
        i = int(t)
    d = g - (laws.g_lo + i * laws.dg)
    s = laws.S[k, i]
    p = laws.P[k, i] + s * d
    phi = laws.PHI[k, i] - (laws.P[k, i] * d + 0.5 * s * d * d)
    return p, s, phi


# ----------------------------------------------------------------------------- element data
@njit(cache=True, nogil=True)
def _shape(xi, L, N, dN):
    x2 = xi * xi
    x3 = x2 * xi
    N[0] = 1.0 - 3.0 * x2 + 2.0 * x3
    N[1] = L * (xi - 2.0 * x2 + x3)
    N[2] = 3.0 * x2 - 2.0 * x3
    N[3] = L * (-x2 + x3)
    dN[0] = (-6.0 * xi + 6.0 * x2) / L
    dN[1] = 1.0 - 4.0 * xi + 3.0 * x2
    dN[2] = (6.0 * xi - 6.0 * x2) / L
    dN[3] = -2.0 * xi + 3.0 * x2


@njit(cache=True, nogil=True)
def _elem_dofs(e, dofs):
    # element e joins nodes e and e+1; node i >= 1 has dofs 2(i-1), 2(i-1)+1; node 0 is clamped (-1)
    for a in range(2):
        node = e + a
        if node == 0:
            dofs[2 * a] = -1
            dofs[2 * a + 1] = -1
        else:
            dofs[2 * a] = 2 * (node - 1)
            dofs[2 * a + 1] = 2 * (node - 1) + 1


@njit(cache=True, nogil=True)
def load_vector(xnode, width):
    """Consistent nodal vector of a unit uniform pressure over the whole beam (times width)."""
    ne = xnode.shape[0] - 1
    F = np.zeros(2 * ne)
    dofs = np.empty(4, np.int64)
    for e in range(ne):
        L = xnode[e + 1] - xnode[e]
        fe = (0.5 * L, L * L / 12.0, 0.5 * L, -L * L / 12.0)
        _elem_dofs(e, dofs)
        for a in range(4):
            if dofs[a] >= 0:
                F[dofs[a]] += width * fe[a]
    return F


@njit(cache=True, nogil=True)
def assemble(u, mesh, laws, lam, band, r):
    """Energy, residual and banded Hessian of the total potential energy.

    ``Pi = 1/2 u K u + w sum_q wq phi(g_q) - lam F.u`` with ``g = gap - v`` on the
    :class:`MeshArrays` ``mesh`` with the :class:`LawTable` ``laws``.
    ``band[d, j] = K[j + d, j]`` (lower band, d = 0..3). Returns Pi; fills ``r`` and ``band``.
    """
    xnode, law_index, gap, EI, width, F = mesh.xnode, mesh.law_index, mesh.gap, mesh.EI, mesh.width, mesh.F
    ne = xnode.shape[0] - 1
    band[:, :] = 0.0
    r[:] = 0.0
    dofs = np.empty(4, np.int64)
    N = np.empty(4)
    dN = np.empty(4)
    ue = np.empty(4)
    ke = np.empty((4, 4))
    fe = np.empty(4)
    energy = 0.0
    for e in range(ne):
        L = xnode[e + 1] - xnode[e]
        _elem_dofs(e, dofs)
        for a in range(4):
            ue[a] = u[dofs[a]] if dofs[a] >= 0 else 0.0
        c = EI / (L * L * L)
        ke[0, 0] = 12 * c
        ke[0, 1] = 6 * L * c
        ke[0, 2] = -12 * c
        ke[0, 3] = 6 * L * c
        ke[1, 1] = 4 * L * L * c
        ke[1, 2] = -6 * L * c
        ke[1, 3] = 2 * L * L * c
        ke[2, 2] = 12 * c
        ke[2, 3] = -6 * L * c
        ke[3, 3] = 4 * L * L * c
        for a in range(4):
            for b in range(a):
                ke[a, b] = ke[b, a]
        for a in range(4):
            s = 0.0
            for b in range(4):
                s += ke[a, b] * ue[b]
            fe[a] = s
            energy += 0.5 * ue[a] * s
        k = law_index[e]
        for q in range(3):
            _shape(GAUSS_XI[q], L, N, dN)
            v = N[0] * ue[0] + N[1] * ue[1] + N[2] * ue[2] + N[3] * ue[3]
            p, sp, phi = law_eval(laws, k, gap - v)
            wq = width * GAUSS_W[q] * L
            energy += wq * phi
            for a in range(4):
                fe[a] += wq * p * N[a]
                for b in range(4):
                    ke[a, b] -= wq * sp * N[a] * N[b]
        for a in range(4):
            da = dofs[a]
            if da < 0:
                continue
            r[da] += fe[a]
            for b in range(4):
                db = dofs[b]
                if db >= 0 and db <= da:
                    band[da - db, db] += ke[a, b]
    for j in range(r.shape[0]):
        energy -= lam * F[j] * u[j]
        r[j] -= lam * F[j]
    return energy


@njit(cache=True, nogil=True)
def ldl_factor(band):
    """In-place banded LDL^T (no pivoting) of a symmetric matrix in lower band storage.

    Returns the number of negative pivots (the Hessian's negative eigenvalues, Sylvester) or -1 on
    a zero pivot. ``band[0]`` becomes D, ``band[d, j]`` the unit-lower factor L[j+d, j].
    """
    n = band.shape[1]
    m = band.shape[0] - 1
    neg = 0
    for j in range(n):
        # d_j = a_jj - sum_k L[j,k]^2 d_k
        dj = band[0, j]
        for k in range(max(0, j - m), j):
            ljk = band[j - k, k]
            dj -= ljk * ljk * band[0, k]
        if dj == 0.0 or not math.isfinite(dj):
            return -1
        band[0, j] = dj
        if dj < 0:
            neg += 1
        for i in range(j + 1, min(n, j + m + 1)):
            s = band[i - j, j]
            for k in range(max(0, i - m), j):
                s -= band[i - k, k] * band[j - k, k] * band[0, k]
            band[i - j, j] = s / dj
    return neg


@njit(cache=True, nogil=True)
def ldl_solve(band, b, out):
    n = band.shape[1]
    m = band.shape[0] - 1
    for i in range(n):
        s = b[i]
        for k in range(max(0, i - m), i):
            s -= band[i - k, k] * out[k]
        out[i] = s
    for i in range(n):
        out[i] /= band[0, i]
    for i in range(n - 1, -1, -1):
        s = out[i]
        for k in range(i + 1, min(n, i + m + 1)):
            s -= band[k - i, i] * out[k]
        out[i] = s


@njit(cache=True, nogil=True)
def element_of(xnode, x):
    """Index of the element of the sorted node positions ``xnode`` that holds ``x``."""
    lo = 0
    hi = xnode.shape[0] - 2
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if xnode[mid] <= x:
            lo = mid
        else:
            hi = mid - 1
    return lo


@njit(cache=True, nogil=True)
def point_interp(u, xnode, x):
    """(v, v', v'') at position x (µm) from the Hermite field."""
    e = element_of(xnode, x)
    L = xnode[e + 1] - xnode[e]
    xi = (x - xnode[e]) / L
    dofs = np.empty(4, np.int64)
    _elem_dofs(e, dofs)
    ue = np.empty(4)
    for a in range(4):
        ue[a] = u[dofs[a]] if dofs[a] >= 0 else 0.0
    N = np.empty(4)
    dN = np.empty(4)
    _shape(xi, L, N, dN)
    v = 0.0
    dv = 0.0
    for a in range(4):
        v += N[a] * ue[a]
        dv += dN[a] * ue[a]
    # second derivative of the Hermite cubic
    d2 = np.empty(4)
    d2[0] = (-6.0 + 12.0 * xi) / (L * L)
    d2[1] = (-4.0 + 6.0 * xi) / L
    d2[2] = (6.0 - 12.0 * xi) / (L * L)
    d2[3] = (-2.0 + 6.0 * xi) / L
    d2v = 0.0
    for a in range(4):
        d2v += d2[a] * ue[a]
    return v, dv, d2v, e


@njit(cache=True, nogil=True)
def marker_vector(xnode, x, ndof):
    """Row vector e with e.u = v(x) (the constraint of the front-controlled continuation)."""
    e = element_of(xnode, x)
    L = xnode[e + 1] - xnode[e]
    xi = (x - xnode[e]) / L
    N = np.empty(4)
    dN = np.empty(4)
    _shape(xi, L, N, dN)
    dofs = np.empty(4, np.int64)
    _elem_dofs(e, dofs)
    vec = np.zeros(ndof)
    for a in range(4):
        if dofs[a] >= 0:
            vec[dofs[a]] = N[a]
    return vec


# ----------------------------------------------------------------------------- driver
class SolverError(RuntimeError):
    """Newton or continuation failure of the beam solver."""


class BeamMesh:
    """Hermite mesh of a cantilever (µm, nm, pJ) aligned with the patch boundaries.

    One element spans ``[0, x_fine]`` (the free span: exact nodal values for a uniform load);
    beyond, elements of at most ``element_size`` inside every patch of length ``patch_length``.
    """

    def __init__(self, length, width, EI, gap, patch_law, patch_length, element_size, x_fine,
                 laws: LawTable):
        self.length, self.width, self.EI, self.gap = length, width, EI, gap
        self.laws = laws
        n_patch = int(math.ceil(length / patch_length - 1e-9))
        patch_law = np.asarray(patch_law, dtype=np.int64)
        if patch_law.shape[0] < n_patch:
            raise ValueError(f"need {n_patch} patch laws for this beam, got {patch_law.shape[0]}")
        bounds = np.minimum(np.arange(n_patch + 1) * patch_length, length)
        first = max(0, min(int(math.floor(x_fine / patch_length)), n_patch - 1))
        nodes = [0.0]
        laws_e = []
        if first > 0:
            nodes.append(bounds[first])
            laws_e.append(patch_law[first - 1])
        for j in range(first, n_patch):
            a, b = bounds[j], bounds[j + 1]
            if b - a <= 1e-9:
                continue
            m = max(1, int(math.ceil((b - a) / element_size - 1e-9)))
            nodes.extend(list(a + (b - a) * np.arange(1, m + 1) / m))
            laws_e.extend([patch_law[j]] * m)
        self.x = np.array(nodes)
        self.law_index = np.array(laws_e, dtype=np.int64)
        self.ndof = 2 * (self.x.size - 1)
        self.F = load_vector(self.x, width)
        self.arrays = MeshArrays(self.x, self.law_index, float(gap), float(EI), float(width), self.F)
        self._band = np.zeros((4, self.ndof))
        self._r = np.zeros(self.ndof)

    def assemble(self, u, lam):
        e = assemble(u, self.arrays, self.laws, lam, self._band, self._r)
        return e, self._r, self._band

    def guess(self, front, contact_gap):
        """S-shape with zero slope at ``front``, flat beyond at ``contact_gap``."""
        V = self.gap - contact_gap
        xs = self.x[1:]
        xi = np.minimum(xs / front, 1.0)
        u = np.empty(self.ndof)
        u[0::2] = V * (3 * xi**2 - 2 * xi**3)
        u[1::2] = np.where(xs < front, V * (6 * xi - 6 * xi**2) / front, 0.0)
        return u

    def interp(self, u, x):
        v, dv, d2v, _ = point_interp(u, self.x, float(x))
        return v, dv, d2v

    def solve_constrained(self, u, lam, marker_x, marker_gap, *, tol=1e-6, max_iter=40,
                          max_step=None):
        """Equilibrium with v(marker_x) = gap - marker_gap; the uniform load lam is the unknown."""
        e = marker_vector(self.x, float(marker_x), self.ndof)
        target = self.gap - marker_gap
        u = u.copy()
        z1 = np.empty(self.ndof)
        z2 = np.empty(self.ndof)
        step = math.inf
        best = math.inf
        for it in range(max_iter):
            _, r, band = self.assemble(u, lam)
            c = e @ u - target
            if ldl_factor(band) < 0:
                raise SolverError("singular tangent")
            ldl_solve(band, self.F, z1)
            ldl_solve(band, -r, z2)
            dlam = (-c - e @ z2) / (e @ z1)
            du = z2 + dlam * z1
            step = float(np.max(np.abs(du[0::2])))
            alpha = 1.0
            if max_step is not None and step > max_step:
                alpha = max_step / step
            u += alpha * du
            lam += alpha * dlam
            if alpha == 1.0 and step < tol:
                return u, lam, it + 1
            best = min(best, step)
        # piecewise-linear laws can make Newton cycle between two segments at round-off level
        if step < 1e3 * tol:
            return u, lam, max_iter
        raise SolverError(f"constrained Newton did not converge (last step {step:.3g} nm)")

    def minimize(self, u, lam, *, tol=1e-6, max_iter=400, max_step=50.0):
        """Equilibrium at the fixed uniform load ``lam`` by descent on the total energy.

        Newton steps on the banded Hessian, shifted (``K + mu I``, mu grown tenfold until the
        LDL has no negative pivot) where it is not positive definite, capped at ``max_step``
        nm and halved until the energy decreases: every accepted step lowers the energy, so
        the iteration cannot cycle and reaches a local minimum (a stable state) from any guess.
        """
        u = u.copy()
        du = np.empty(self.ndof)
        for it in range(max_iter):
            e0, r, band = self.assemble(u, lam)
            r = r.copy()
            diag = band[0].copy()
            scale = float(np.max(np.abs(diag)))
            mu = 0.0
            while True:
                b = band.copy()
                b[0] += mu
                if ldl_factor(b) == 0:
                    break
                mu = 1e-8 * scale if mu == 0.0 else mu * 10.0
                if mu > 1e3 * scale:
                    raise SolverError("pull-in: no positive-definite shift of the Hessian")
            ldl_solve(b, -r, du)
            step = float(np.max(np.abs(du[0::2])))
            if step < tol:
                return u, it + 1
            alpha = min(1.0, max_step / step)
            for _ in range(60):
                e1 = self.assemble(u + alpha * du, lam)[0]
                if e1 <= e0:
                    break
                alpha *= 0.5
            else:
                if step < 1e3 * tol:  # piecewise-linear law: round-off level, accept
                    return u, it + 1
                raise SolverError(f"pull-in: no descent along the Newton direction (step {step:.3g} nm)")
            u += alpha * du
            if alpha * step < 1e-3 * tol:
                return u, it + 1
        raise SolverError("pull-in: energy descent did not converge")

    def front_position(self, u, marker_gap):
        """First x from the clamp where the gap falls to ``marker_gap`` (nan: nowhere)."""
        target = self.gap - marker_gap
        v = np.concatenate(([0.0], u[0::2]))
        hit = np.nonzero(v >= target)[0]
        if hit.size == 0:
            return math.nan
        i = int(hit[0])
        lo, hi = self.x[i - 1], self.x[i]
        for _ in range(60):  # bisection on the Hermite field inside the element
            mid = 0.5 * (lo + hi)
            if self.interp(u, mid)[0] >= target:
                hi = mid
            else:
                lo = mid
        return hi

    def clamp_moment(self, u):
        """Bending moment EI v''(0) at the clamp (internal units; times 1e-9 gives N m)."""
        return self.EI * self.interp(u, 0.0)[2]

    def zero_slope_point(self, u, x_at):
        """Zero-slope point of the free cubic ``c2 x² + c3 x³`` through (v, v') at ``x_at``."""
        v, dv, _ = self.interp(u, x_at)
        A = np.array([[x_at * x_at, x_at**3], [2 * x_at, 3 * x_at * x_at]])
        c2, c3 = np.linalg.solve(A, [v, dv])
        return math.inf if c3 >= 0 else -2 * c2 / (3 * c3)


@dataclass
class ReleaseResult:
    """Outcome of :func:`release` in internal units (µm, nm): stuck flag, crack length, front,
    attached length, clamp moment, final deflection ``u``, continuation steps and the path."""

    stuck: bool
    crack_length: float
    front: float
    attached_length: float
    clamp_moment: float = None
    u: np.ndarray = None
    n_steps: int = None
    path: list = None


def pull_in(mesh: BeamMesh, *, start, marker_gap, contact_gap, max_tries=8):
    """Pulled-in state by load control: the fallback start of :func:`release`.

    The uniform load ``lam`` (the electrostatic pull-in) that would bend a free cantilever of
    length ``start`` down by the gap is applied, and the equilibrium is found by energy descent
    (:meth:`BeamMesh.minimize`) from the S-shaped guess, then from the last state found when
    that fails; the load is doubled until the front (where the gap crosses ``marker_gap``)
    lies at or before ``start``. Returns ``(u, lam, a)``, the constrained equilibrium at the
    front ``a`` found.
    """
    V = mesh.gap - contact_gap
    lam = 8.0 * mesh.EI * V / (mesh.width * start**4)
    guess = mesh.guess(start, contact_gap)
    last = None
    for _ in range(max_tries):
        u = None
        for g0 in (guess, last):
            if g0 is None:
                continue
            try:
                u, _ = mesh.minimize(g0, lam)
                break
            except SolverError:
                u = None
        if u is not None:
            last = u
            a = mesh.front_position(u, marker_gap)
            if a <= start:
                u, lam_c, _ = mesh.solve_constrained(u, lam, a, marker_gap, max_iter=100)
                return u, lam_c, a
        lam *= 2.0
    raise SolverError(f"pull-in: no load in {max_tries} doublings puts the front before {start:.4g} µm")


def release(mesh: BeamMesh, *, start, marker_gap, contact_gap, step, min_step=None,
            record_path=False):
    """Release of a pulled-in beam, by continuation of the front from ``start`` to the tip.

    The marker point (gap ``marker_gap``, above the range of every law) moves from ``start``
    towards the tip in steps of at most ``step``; at each position the uniform load holding the
    beam in equilibrium is solved for. The load decreases as the front advances; the first
    position where it reaches zero is the state the beam is left in when the pull-in load is
    released slowly (a load-controlled snap jumps over positions where the load is higher, so
    it lands on that same first zero). No zero before the tip: the beam comes free.
    """
    min_step = step / 64 if min_step is None else min_step
    a = float(start)
    u = mesh.guess(a / (1 - math.sqrt((marker_gap - contact_gap) / (3 * (mesh.gap - contact_gap)))),
                   contact_gap)
    try:
        u, lam, _ = mesh.solve_constrained(u, 0.0, a, marker_gap, max_step=50.0, max_iter=400)
    except SolverError:
        u, lam, a = pull_in(mesh, start=a, marker_gap=marker_gap, contact_gap=contact_gap)
    lam_start = lam
    if lam <= 0:
        raise SolverError(f"the load at the start front {start:.4g} µm is already <= 0: start earlier")
    end = mesh.length - 0.5 * min(step, mesh.x[-1] - mesh.x[-2])
    up, ap = u, a
    path = [(a, lam)] if record_path else None
    n = 0
    n_snap = 0
    da = step
    while a < end:
        a_new = min(a + da, end)
        snapped = False
        pred = u + (u - up) * ((a_new - a) / (a - ap)) if a > ap else u
        try:
            un, lamn, _ = mesh.solve_constrained(pred, lam, a_new, marker_gap, max_step=20.0)
        except SolverError:
            if da > min_step:
                da = max(da / 2, min_step)
                continue
            # a fold of the front-controlled path (a patch law with several wells snaps inside
            # the cohesive zone): go on in load control, as under the slowly released pull-in
            # load, until the front jumps ahead; then resume front control from there
            un, lamn, a_jump = _load_steps(mesh, u, lam, a, lam_start, marker_gap, min_step)
            n_snap += 1
            if lamn <= 0.0 or a_jump >= end:  # came to rest at zero load, or jumped free
                u, lam, a = un, lamn, min(a_jump, end)
                break
            a_new, snapped = a_jump, True
            un, lamn, _ = mesh.solve_constrained(un, lamn, a_new, marker_gap, max_step=20.0)
        n += 1
        if lamn <= 0:  # first zero of the load: refine by bisection/secant on the front position
            lo, hi, ulo, llo, lhi, uhi = a, a_new, u, lam, lamn, un
            for _ in range(30):
                if hi - lo < 1e-4:
                    break
                t = llo / (llo - lhi)
                am = lo + min(max(t, 0.1), 0.9) * (hi - lo)
                um, lm, _ = mesh.solve_constrained(ulo + (uhi - ulo) * (am - lo) / (hi - lo), llo,
                                                   am, marker_gap)
                if lm > 0:
                    lo, ulo, llo = am, um, lm
                else:
                    hi, uhi, lhi = am, um, lm
            t = llo / (llo - lhi)
            af = lo + t * (hi - lo)
            uf, lf, _ = mesh.solve_constrained(ulo + (uhi - ulo) * t, llo, af, marker_gap)
            if path is not None:
                path.append((af, lf))
            s = mesh.zero_slope_point(uf, af)
            return ReleaseResult(stuck=True, crack_length=s, front=af,
                                 attached_length=mesh.length - af, clamp_moment=mesh.clamp_moment(uf),
                                 u=uf, n_steps=n, path=path)
        up, ap, u, lam, a = (un, a_new, un, lamn, a_new) if snapped else (u, a, un, lamn, a_new)
        if path is not None:
            path.append((a, lam))
        da = min(step, da * 2)
    if lam <= 0.0 and a < end:  # came to rest by load control at zero load
        return ReleaseResult(stuck=True, crack_length=mesh.zero_slope_point(u, a), front=a,
                             attached_length=mesh.length - a, clamp_moment=mesh.clamp_moment(u),
                             u=u, n_steps=n, path=path)
    return ReleaseResult(stuck=False, crack_length=math.nan, front=math.nan, attached_length=0.0,
                         clamp_moment=math.nan, u=u, n_steps=n, path=path)


def _load_steps(mesh, u, lam, a, lam_start, marker_gap, min_step, max_steps=400):
    """Load-controlled release from the equilibrium ``(u, lam)`` with its front at ``a``.

    The load is lowered by 5 % of itself (at least 1 % of the start load) per step, each
    equilibrium found by energy descent from the previous one (a stable state, the one a slowly
    unloaded beam follows), until the front has moved ahead by more than ``min_step`` or the
    load is zero. Returns ``(u, lam, front)``.
    """
    for _ in range(max_steps):
        lam = lam - max(0.05 * lam, 0.01 * lam_start)
        lam = max(lam, 0.0)
        u, _ = mesh.minimize(u, lam)
        front = mesh.front_position(u, marker_gap)
        if not front == front:  # nowhere at the marker gap: free
            return u, lam, math.inf
        if front > a + min_step or lam == 0.0:
            return u, lam, front
    raise SolverError("load-controlled release: front did not move")
