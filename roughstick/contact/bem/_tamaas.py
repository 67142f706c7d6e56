"""The Tamaas adapter: one map's curves by Tamaas' Polonsky-Keer solver with Maugis adhesion.

Lengths are handed to Tamaas in nm (heights and gaps of order one) and pressures in units of
:math:`E^*`. Tamaas keeps global state (FFT plans, its own thread pool) and crashed the
interpreter when two dask threads solved at once; its solver is serial C++ anyway, so maps are
solved one at a time per process (:data:`TAMAAS_LOCK`; dask *processes* or a distributed
cluster run BEM maps in parallel).
"""

from __future__ import annotations

import threading
import time

import numpy as np

from ..._core.conventions import CURVE_VARIABLES
from ..._core.validate import check_has_roughness
from .._shared import count_periodic_clusters, merge_humidity_grids, periodic_offset_coefficient

__all__ = ["import_tamaas", "solve_map", "TAMAAS_LOCK", "VARIABLES"]

#: Internal length unit handed to Tamaas (nm): keeps heights and gaps of order one.
LENGTH_UNIT = 1e-9
#: What the solver loop fills per (rh, distance); fit_error is NaN by construction (no fits).
VARIABLES = (*(v for v in CURVE_VARIABLES if v != "fit_error"), "distance_offset", "solver_residual")
#: A pixel is in hard contact where its gap is below this fraction of max(h_water, 1 nm).
_CONTACT_GAP = 1e-9
#: Maps are solved one at a time per process (module docstring).
TAMAAS_LOCK = threading.Lock()


def import_tamaas():
    try:
        import tamaas
    except ImportError as err:  # pragma: no cover - exercised only without the extra
        raise ImportError(
            "bem_curves needs the optional boundary-element solver Tamaas, which is not "
            "installed. Install the extra: pip install roughstick[bem]  (or: pip install tamaas)."
        ) from err
    return tamaas


class _Solver:
    """One Tamaas model + Polonsky-Keer solver with Maugis adhesion, in nm and E* units."""

    def __init__(self, tm, z, size, sigma0, h0, tolerance, max_iterations):
        self.tm, self.z, self.size = tm, z, size
        self.args = (sigma0, h0, tolerance, max_iterations)
        self.fresh()

    def fresh(self):
        tm = self.tm
        sigma0, h0, tolerance, max_iterations = self.args
        ny, nx = self.z.shape
        self.model = tm.ModelFactory.createModel(tm.model_type.basic_2d, list(self.size), [ny, nx])
        # Contact of a rigid rough surface with an elastic half-space of plane-strain modulus
        # E/(1 - nu^2) = 1: the E* of the pair (lengths in nm, pressures in units of E*).
        self.model.E = 1.0
        self.model.nu = 0.0
        self.solver = tm.PolonskyKeerRey(
            self.model, self.z, tolerance, tm.PolonskyKeerRey.gap, tm.PolonskyKeerRey.gap
        )
        self.solver.max_iter = int(max_iterations)
        if sigma0 > 0 and h0 > 0:
            self.adhesion = tm.MaugisAdhesionFunctional(self.z)
            # Dugdale cohesive zone: stress surface_energy / rho over gaps below rho.
            self.adhesion.parameters = {"rho": float(h0), "surface_energy": float(sigma0 * h0)}
            self.solver.addFunctionalTerm(self.adhesion)

    def solve(self, mean_gap):
        err = float(self.solver.solve(float(mean_gap)))
        return (
            err,
            np.array(self.model.traction, copy=True).reshape(self.z.shape),
            np.array(self.model["gap"], copy=True).reshape(self.z.shape),
        )


class _Map:
    """One map in solver units (nm, E*): its geometry and the states solved on it."""

    def __init__(self, tm, z, spacing, *, e_star, tolerance, max_iterations, retries, stats, on_solve):
        L = LENGTH_UNIT
        ny, nx = z.shape
        dy, dx = spacing
        self.tm, self.e_star, self.stats, self.on_solve = tm, e_star, stats, on_solve
        self.tolerance, self.max_iterations, self.retries = tolerance, max_iterations, retries
        self.size = (ny * dy / L, nx * dx / L)
        self.zn = np.ascontiguousarray(z / L)
        self.zbar, self.zmax = float(self.zn.mean()), float(self.zn.max())
        # d_local - d_t = F Z / (pi E*) with F = pbar * area: the periodic (zero-mean
        # displacement) convention differs from the isolated-contact one by this constant (nm)
        self.offset_per_pressure = (self.size[0] * self.size[1]
                                    * periodic_offset_coefficient(self.size[1], self.size[0]) / np.pi)
        q = np.sqrt(
            (2 * np.pi * np.fft.fftfreq(ny, d=dy / L))[:, None] ** 2
            + (2 * np.pi * np.fft.rfftfreq(nx, d=dx / L))[None, :] ** 2
        )
        q[0, 0] = np.inf
        self.q = q

    def state(self, d, pbar, **values):
        """A state's variables (SI) from its mean pressure and the rest."""
        L = LENGTH_UNIT
        dloc = d + self.offset_per_pressure * pbar
        return dict(pressure=pbar * self.e_star, **values, max_interference=(self.zmax - dloc) * L,
                    distance_offset=(dloc - d) * L)

    def noncontact(self, d, s0n, hn):
        """Dugdale tension on the deformed gap without hard contact (FFT fixed point).

        Returns the state, or None when the surface jumps into contact.
        """
        zn = self.zn
        w = np.zeros_like(zn)
        wet = np.zeros(zn.shape, dtype=bool)
        for _ in range(100 if s0n > 0 else 1):
            gap = d + w - zn
            if np.any(gap <= 0):
                return None
            new = gap < hn if s0n > 0 else wet
            if np.array_equal(new, wet) and _ > 0:
                break
            wet = new
            trac = np.where(wet, -s0n, 0.0)
            w = np.fft.irfft2(np.fft.rfft2(trac) * 2 / self.q, s=zn.shape)
        pbar = -s0n * float(wet.mean())
        self.stats["max_noncontact_deflection"] = max(
            self.stats["max_noncontact_deflection"],
            float(-w[wet].min()) * LENGTH_UNIT if wet.any() else 0.0
        )
        return self.state(d, pbar, repulsive_pressure=0.0, wet_fraction=float(wet.mean()),
                          contact_fraction=0.0, n_contacts=0, solver_residual=0.0)

    def solve(self, solver, d, s0n, hn):
        """Tamaas at mean gap ``d - mean z``, retried from a fresh solver while it stalls
        (residual above 10 x its tolerance); returns (residual, traction, gap, solver)."""
        tol = self.tolerance
        t0 = time.perf_counter()
        err, p, g = solver.solve(d - self.zbar)
        self.on_solve()
        attempt = 0
        while not (err <= 10 * tol) and attempt < self.retries and d < self.zmax:
            # stalls happen now and then: retry from a fresh (cold) solver
            attempt += 1
            self.stats["retries"] += 1
            trial = _Solver(self.tm, self.zn, self.size, s0n, hn, tol, self.max_iterations)
            err2, p2, g2 = trial.solve(d - self.zbar)
            self.on_solve()
            if err2 < err or not np.isfinite(err):
                err, p, g, solver = err2, p2, g2, trial
        self.stats["solves"] += 1
        self.stats["solve_seconds"] += time.perf_counter() - t0
        return err, p, g, solver

    def march(self, dn, s0n, hn, path):
        """One humidity's states along ``dn`` [nm], warm-started in the order of ``path``."""
        out = {k: np.full(len(dn), np.nan) for k in VARIABLES}
        solver = None
        in_contact = False
        order = np.argsort(dn) if path == "retract" else np.argsort(dn)[::-1]
        for k in order:
            d = dn[k]
            vals = None
            if d >= self.zmax and not in_contact:
                # Water but no hard contact: the solver's relative error is 0/0 there, so the
                # state is solved directly (None: the adhesive pull closes the gap: jump-in).
                vals = self.noncontact(d, s0n, hn)
            if vals is None:
                if solver is None:
                    solver = _Solver(self.tm, self.zn, self.size, s0n, hn, self.tolerance,
                                     self.max_iterations)
                err, p, g, solver = self.solve(solver, d, s0n, hn)
                contact = g <= _CONTACT_GAP * max(hn, 1.0)
                if d >= self.zmax and not (contact.any() and err <= 10 * self.tolerance):
                    # the neck held by adhesion has broken: no contact from here on
                    in_contact = False
                    solver = None
                    vals = self.noncontact(d, s0n, hn)
                    if vals is None:  # pragma: no cover - contradictory state, keep solver's
                        vals = {}
                if not vals:
                    if not (err <= 10 * self.tolerance):
                        self.stats["unconverged"] += 1
                    in_contact = bool(contact.any())
                    adhesive = (~contact) & (g < hn) if s0n > 0 else np.zeros_like(contact)
                    vals = self.state(
                        d, float(p.mean()),
                        repulsive_pressure=float(p[contact].sum()) / self.zn.size * self.e_star,
                        wet_fraction=float(adhesive.mean()), contact_fraction=float(contact.mean()),
                        n_contacts=count_periodic_clusters(contact), solver_residual=err)
            for name, v in vals.items():
                out[name][k] = v
        return out


def solve_map(z, *, spacing, distances, sigma0s, h_waters, e_star, tolerance, max_iterations,
              path, retries, stats, on_solve=lambda: None):
    """Curves of one map (numpy, SI in and out): {variable: (n_rh, n_distance)} and ``solved``.

    ``distances``: one grid for every humidity, or a list of one grid per humidity (reported on
    their union). A state where Tamaas stalled (residual above 10 x its tolerance after the
    retries) is not a solution: it is interpolated between its humidity's solved neighbours,
    ``solved = 0``. ``on_solve()`` is called after each Tamaas solve, retries included."""
    tm = import_tamaas()
    z = np.asarray(z, dtype=float)
    check_has_roughness(z)  # a flat or (almost) all-NaN map: nothing to model
    if not np.all(np.isfinite(z)):
        raise ValueError(
            "height contains NaN or inf; the boundary-element solver needs a complete map. "
            "Fill or crop the missing pixels first."
        )
    with TAMAAS_LOCK:
        level = tm.get_log_level()
        tm.set_log_level(tm.LogLevel.error)
        try:
            return _solve_map(tm, z, spacing, distances, sigma0s, h_waters, e_star, tolerance,
                              max_iterations, path, retries, stats, on_solve)
        finally:
            tm.set_log_level(level)


def _solve_map(tm, z, spacing, distances, sigma0s, h_waters, e_star, tolerance, max_iterations,
               path, retries, stats, on_solve):
    L = LENGTH_UNIT
    m = _Map(tm, z, spacing, e_star=e_star, tolerance=tolerance, max_iterations=max_iterations,
             retries=retries, stats=stats, on_solve=on_solve)
    per_rh = isinstance(distances, list)  # one grid per humidity (the automatic grids)
    grids = [np.asarray(g, dtype=float) / L for g in distances] if per_rh else None
    dn_all = np.concatenate(grids) if per_rh else np.asarray(distances, dtype=float) / L
    if np.any(dn_all - m.zbar <= 0):
        bad = float(dn_all[dn_all - m.zbar <= 0][0] * L)
        raise ValueError(
            f"distance {bad!r} m lies at or below the mean plane of the heights "
            f"({m.zbar * L!r} m): the mean gap would be <= 0 (full contact), which the "
            "boundary-element solver cannot impose. Pass distances above the mean plane."
        )
    if not per_rh:
        grids = [dn_all] * len(sigma0s)
    out_rh = [m.march(dn, s0 / e_star, h / L, path)
              for dn, s0, h in zip(grids, sigma0s, h_waters, strict=True)]
    # (one stalled state, +131 MPa amid -7.7 MPa, took 69 % of Γ on a 64² Table-4 map at RH 0.05)
    kept = [(g[o["solver_residual"] <= 10 * tolerance], {k: v[o["solver_residual"] <= 10 * tolerance]
                                                         for k, v in o.items()})
            for g, o in zip(grids, out_rh, strict=True)]
    onto = np.unique(dn_all) if per_rh else dn_all
    return merge_humidity_grids(kept, m.zmax, (*VARIABLES, "solved"), L, onto=onto)[1]
