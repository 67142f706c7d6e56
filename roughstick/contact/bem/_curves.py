"""Boundary-element reference for humid rough contact (optional, via Tamaas).

:func:`bem_contact_curves` solves the full elastic contact of a rough surface against a rigid flat
with Dugdale (Maugis) capillary adhesion, on a periodic FFT boundary-element grid, with the
Polonsky-Keer solver of Tamaas [1]_ [2]_. It returns the same curves layout as the modified DMT
(Eq. 16, :func:`roughstick.rough_contact_curves`), so the two can be compared number by number.

Tamaas is an optional dependency: ``pip install roughstick[bem]``.
"""

from __future__ import annotations

import threading
import time
import warnings

import numpy as np
import xarray as xr

from ..._core.arguments import check_numbers
from ..._core.conventions import (
    ATTRS,
    CURVE_VARIABLES,
    append_history,
    dataset_attrs,
    set_attrs,
    set_coord_attrs,
)
from ..._core.materials import POLYSILICON, Material, reduced_modulus
from ..._core.memory import check_map_fits_in_memory
from ..._core.progress import WorkProgress, estimate_seconds
from ..._core.references import cite
from ..._core.validate import (
    MIN_MAP_PIXELS,
    check_core_not_chunked,
    check_has_roughness,
    grid_spacing,
    height_in_si,
    relative_humidity_coordinate,
)
from ..fft_bem._curves import (
    SOLVED_ATTRS,
    automatic_grid_counts,
    fft_bem_contact_curves,
    merge_humidity_grids,
)
from ..meniscus import laplace_pressure, water_height
from .._shared import count_periodic_clusters, periodic_offset_coefficient

__all__ = ["bem_contact_curves", "periodic_offset_coefficient"]

_REFERENCES = cite("frerot2020", "polonsky1999", "rey2017", "maugis1992")

#: Internal length unit handed to Tamaas (nm): keeps heights and gaps of order one.
_LENGTH_UNIT = 1e-9
#: what the solver loop fills per (rh, distance); fit_error is NaN by construction (no fits)
_BEM_VARS = (*(v for v in CURVE_VARIABLES if v != "fit_error"), "distance_offset", "solver_residual")


def _import_tamaas():
    try:
        import tamaas
    except ImportError as err:  # pragma: no cover - exercised only without the extra
        raise ImportError(
            "bem_contact_curves needs the optional boundary-element solver Tamaas, which is not "
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


#: Tamaas keeps global state (FFT plans, its own thread pool) and crashed the interpreter when two
#: dask threads solved at once; its solver is serial C++ anyway, so maps are solved one at a time
#: per process (use dask *processes* or a distributed cluster to run BEM maps in parallel).
_TAMAAS_LOCK = threading.Lock()


def _bem_kernel(*args, **kwargs):
    """:func:`_bem_kernel_unlocked` under the process-wide Tamaas lock."""
    with _TAMAAS_LOCK:
        return _bem_kernel_unlocked(*args, **kwargs)


def _bem_kernel_unlocked(
    z,
    *,
    spacing,
    distances,
    sigma0s,
    h_waters,
    e_star,
    tolerance,
    max_iterations,
    path,
    retries,
    stats,
    on_solve=None,
):
    """Curves of one map (numpy, SI in and out): arrays of shape (n_rh, n_distance).

    ``on_solve()`` is called after each Tamaas solve, retries included (progress: the solves are
    the cost; a state without contact costs a few FFTs)."""
    tm = _import_tamaas()
    L = _LENGTH_UNIT
    z = np.asarray(z, dtype=float)
    check_has_roughness(z)  # a flat or (almost) all-NaN map: nothing to model
    if not np.all(np.isfinite(z)):
        raise ValueError(
            "height contains NaN or inf; the boundary-element solver needs a complete map. "
            "Fill or crop the missing pixels first."
        )
    ny, nx = z.shape
    dy, dx = spacing
    size = (ny * dy / L, nx * dx / L)
    zn = np.ascontiguousarray(z / L)
    zbar, zmax = float(zn.mean()), float(zn.max())
    per_rh = isinstance(distances, list)  # one grid per humidity (the automatic grids)
    grids = [np.asarray(g, dtype=float) / L for g in distances] if per_rh else None
    dn_all = np.concatenate(grids) if per_rh else np.asarray(distances, dtype=float) / L
    if np.any(dn_all - zbar <= 0):
        bad = float(dn_all[dn_all - zbar <= 0][0] * L)
        raise ValueError(
            f"distance {bad!r} m lies at or below the mean plane of the heights "
            f"({zbar * L!r} m): the mean gap would be <= 0 (full contact), which the "
            "boundary-element solver cannot impose. Pass distances above the mean plane."
        )
    # d_local - d_t = F Z / (pi E*) with F = pbar * area: the periodic (zero-mean displacement)
    # convention differs from the isolated-contact one by this constant (lengths in nm).
    offset_per_pressure = size[0] * size[1] * periodic_offset_coefficient(size[1], size[0]) / np.pi
    npix = zn.size
    q = np.sqrt(
        (2 * np.pi * np.fft.fftfreq(ny, d=dy / L))[:, None] ** 2
        + (2 * np.pi * np.fft.rfftfreq(nx, d=dx / L))[None, :] ** 2
    )
    q[0, 0] = np.inf
    nr = len(sigma0s)
    if not per_rh:
        grids = [dn_all] * nr
    out_rh = [{k: np.full(len(g), np.nan) for k in _BEM_VARS} for g in grids]
    contact_tol = 1e-9

    def noncontact(d, s0n, hn):
        """Dugdale tension on the deformed gap without hard contact (FFT fixed point).

        Returns the state, or None when the surface jumps into contact.
        """
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
            w = np.fft.irfft2(np.fft.rfft2(trac) * 2 / q, s=zn.shape)
        pbar = -s0n * float(wet.mean())
        stats["max_noncontact_deflection"] = max(
            stats["max_noncontact_deflection"], float(-w[wet].min()) * L if wet.any() else 0.0
        )
        dloc = d + offset_per_pressure * pbar
        return dict(
            pressure=pbar * e_star,
            repulsive_pressure=0.0,
            wet_fraction=float(wet.mean()),
            contact_fraction=0.0,
            n_contacts=0,
            max_interference=(zmax - dloc) * L,
            distance_offset=(dloc - d) * L,
            solver_residual=0.0,
        )

    for ir, (s0, h) in enumerate(zip(sigma0s, h_waters, strict=True)):
        s0n, hn = s0 / e_star, h / L
        solver = None
        in_contact = False
        dn = grids[ir]
        order = np.argsort(dn) if path == "retract" else np.argsort(dn)[::-1]
        for k in order:
            d = dn[k]
            vals = None
            if d >= zmax and not in_contact:
                # Water but no hard contact: the solver's relative error is 0/0 there, so the
                # state is solved directly (None: the adhesive pull closes the gap: jump-in).
                vals = noncontact(d, s0n, hn)
            if vals is None:
                if solver is None:
                    solver = _Solver(tm, zn, size, s0n, hn, tolerance, max_iterations)
                t0 = time.perf_counter()
                err, p, g = solver.solve(d - zbar)
                if on_solve is not None:
                    on_solve()
                attempt = 0
                while not (err <= 10 * tolerance) and attempt < retries and d < zmax:
                    # stalls happen now and then: retry from a fresh (cold) solver
                    attempt += 1
                    stats["retries"] += 1
                    trial = _Solver(tm, zn, size, s0n, hn, tolerance, max_iterations)
                    err2, p2, g2 = trial.solve(d - zbar)
                    if on_solve is not None:
                        on_solve()
                    if err2 < err or not np.isfinite(err):
                        err, p, g, solver = err2, p2, g2, trial
                stats["solves"] += 1
                stats["solve_seconds"] += time.perf_counter() - t0
                contact = g <= contact_tol * max(hn, 1.0)
                if d >= zmax and not (contact.any() and err <= 10 * tolerance):
                    # the neck held by adhesion has broken: no contact from here on
                    in_contact = False
                    solver = None
                    vals = noncontact(d, s0n, hn)
                    if vals is None:  # pragma: no cover - contradictory state, keep solver's
                        vals = {}
                if not vals:
                    if not (err <= 10 * tolerance):
                        stats["unconverged"] += 1
                    in_contact = bool(contact.any())
                    pbar = float(p.mean())
                    adhesive = (~contact) & (g < hn) if s0n > 0 else np.zeros_like(contact)
                    dloc = d + offset_per_pressure * pbar
                    vals = dict(
                        pressure=pbar * e_star,
                        repulsive_pressure=float(p[contact].sum()) / npix * e_star,
                        wet_fraction=float(adhesive.mean()),
                        contact_fraction=float(contact.mean()),
                        n_contacts=count_periodic_clusters(contact),
                        max_interference=(zmax - dloc) * L,
                        distance_offset=(dloc - d) * L,
                        solver_residual=err,
                    )
            for name, v in vals.items():
                out_rh[ir][name][k] = v
    # a state where Tamaas stalled (residual above 10 x its tolerance after the retries) is not
    # a solution: it is interpolated between its humidity's solved neighbours, solved = 0 (one
    # such state, +131 MPa amid -7.7 MPa, took 69 % of Γ on a 64² Table-4 map at RH 0.05)
    kept = [(g[o["solver_residual"] <= 10 * tolerance], {k: v[o["solver_residual"] <= 10 * tolerance]
                                                         for k, v in o.items()})
            for g, o in zip(grids, out_rh, strict=True)]
    onto = np.unique(dn_all) if per_rh else dn_all
    return merge_humidity_grids(kept, zmax, (*_BEM_VARS, "solved"), L, onto=onto)[1]


def _automatic_grids(height, rh_values, *, material, material2, adsorbed_layer, adhesion,
                     n_distances) -> tuple[list[np.ndarray], int]:
    """Per humidity, the distances [m] that fft_bem's automatic grid solves on this map: from a
    quarter step below the equilibrium, through the water range and on while a neck holds,
    refined around the pull-off (docs/fft_bem.md). A fixed span misses all of that on a rough,
    stiff map at low humidity, where the water range is a fraction of a nanometre at max z.
    Also the number of those states in contact in fft_bem, the Tamaas solves to expect (states
    above the highest summit held by a water neck included)."""
    counts = {} if n_distances is None else automatic_grid_counts(n_distances)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # about fft_bem's own values, not about its grid
        f = fft_bem_contact_curves(height, relative_humidity=list(rh_values), material=material,
                                   material2=material2, adsorbed_layer=adsorbed_layer,
                                   adhesion=adhesion, progress=False, **counts)
    solved = np.asarray(f["solved"].transpose("rh", "distance").values) > 0
    touching = np.asarray(f["contact_fraction"].transpose("rh", "distance").values) > 0
    below = f.distance.values < float(height.max())
    return [f.distance.values[row] for row in solved], int(np.sum(solved & (touching | below)))


@check_numbers(tolerance="positive", max_iterations="count", retries="count0",
               n_distances="count?")
def bem_contact_curves(
    height: xr.DataArray,
    *,
    relative_humidity,
    distance=None,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    adsorbed_layer="paper",
    tolerance: float = 1e-6,
    max_iterations: int = 1000,
    path: str = "retract",
    retries: int = 1,
    n_distances: int | None = None,
    adhesion: bool = True,
    progress: bool | None = None,
) -> xr.Dataset:
    r"""Humid adhesive contact of a rough surface and a flat by the boundary-element method.

    The reference for the modified DMT (Eq. 16): the full elastic contact of the rough surface with
    a rigid flat, with the capillary adhesion modelled as a Dugdale (Maugis) cohesive zone of
    strength :math:`\sigma_0 = |\Delta P|` (Eq. 2) and range :math:`h_{water}` (Eq. 6), solved on
    the pixel grid by an FFT boundary-element method (Polonsky-Keer with Maugis adhesion,
    Tamaas [1]_ [2]_ [3]_). Unlike Eq. 16 it keeps the deformation caused by the adhesive
    tension, the elastic interaction between asperities and the exact contact shapes; it does
    not fit spheres, so ``fit_error`` is NaN.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, at least 8 x 8 pixels, units length (converted to m),
        uniform spacing. Treated
        as periodic (the FFT solver wraps it around): for a measured map (``periodic=0``) the
        wrap-around step is part of the solved geometry.
    relative_humidity : float, sequence or xarray.DataArray
        RH as a fraction in (0, 1); a sequence gives dimension ``rh``.
    distance : array_like, optional
        Positions :math:`d` of the flat above the mean plane [m] (see Notes for the convention),
        all above the mean plane of every map. Default (one eager (y, x) map): per humidity,
        the grid that :func:`roughstick.fft_bem_contact_curves`' automatic march solves on the
        same map (from just below the equilibrium through the water range and on while a neck
        holds, refined at the pull-off; on the maps of benchmarks/untuned_surfaces.py that
        call took 0.6-5 % of the BEM's time, 63-82 % on soft maps at RH 1e-3). Several
        humidities are then reported on the union of their grids, as fft_bem does (linear
        interpolation between a humidity's own points, NaN below its first, dry above its
        last; ``solved`` marks the computed points). A fixed span from ``max(z) - 0.5 std(z)``,
        as before, missed the whole adhesive range of a rough, stiff map at low humidity
        (σ 28 nm, RH 0.05: Γ = 0 against 8.6e-6 J/m² on this grid).
    material, material2 : Material
        The two bodies (``material2=None``: same as ``material``); only
        :math:`E^* = [(1-\nu_1^2)/E_1 + (1-\nu_2^2)/E_2]^{-1}` enters (86.6 GPa for poly-Si).
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-layer model of :func:`roughstick.water_height`.
    tolerance : float, default 1e-6
        Relative tolerance of the Polonsky-Keer iterations.
    max_iterations : int, default 1000
        Iteration cap per solve.
    path : {"retract", "approach"}
        Order in which the distances are marched (the solver is warm-started from the previous
        distance, and adhesive contact is path dependent): ``"retract"`` (default) starts from
        the closest distance and pulls the flat away, the branch that decides stiction;
        ``"approach"`` comes in from far.
    retries : int, default 1
        A solve whose residual stays above ``10 * tolerance`` is retried this many times from a
        fresh solver; the best residual is kept and reported in ``solver_residual``.
    n_distances : int, optional
        About this many points per humidity on the default grid (as ``n_distance`` of
        :func:`roughstick.rough_contact_curves` for fft_bem); None: fft_bem's defaults.
    adhesion : bool, default True
        ``False`` switches the capillary tension off (dry Hertz-type contact, used for
        validation); ``wet_fraction`` is then zero.
    progress : bool or None, default None
        Before it starts, the run logs (logger ``roughstick``, INFO) its size, the Tamaas solves
        to expect (on the default grid: the states fft_bem found in contact, those above the
        highest summit held by a water neck included) and an estimate of its time
        (:mod:`roughstick._core.progress`, within a factor ~3); runs estimated at 5 s or more
        then show their progress in solves, the cost, as a bar (terminal; a widget in Jupyter
        with ipywidgets) or INFO lines every 30 s (no terminal), the time left at the measured
        rate; a run measured outside a factor 3 of its estimate says so once, and shows its
        progress from then on. ``True`` always shows it, ``False`` never.

    Returns
    -------
    xarray.Dataset
        Over ``(..., rh, distance)`` (``rh`` dropped for a scalar humidity, as in
        :func:`roughstick.rough_contact_curves`), coordinates ``water_height`` and
        ``laplace_pressure`` along ``rh``: ``pressure`` (mean pressure, Pa, + repulsive),
        ``repulsive_pressure`` (Pa, the traction carried by the contact area),
        ``wet_fraction`` (adhesive zone: gap below :math:`h_{water}` and not in contact),
        ``contact_fraction``, ``n_contacts`` (periodic 4-connected contact clusters),
        ``fit_error`` (NaN), ``max_interference`` (:math:`\max z - d_{local}`),
        ``distance_offset`` (:math:`d_{local} - d`, m), ``solver_residual`` and ``solved`` (1
        where this humidity was solved; 0 where interpolated: on the default grid's union, or
        where Tamaas stalled, residual above 10 × ``tolerance`` after the retries, counted in
        the attribute ``bem_unconverged``).
        Attributes record the model, ``max_noncontact_deflection`` (m) and solver statistics.

    Raises
    ------
    ImportError
        If Tamaas is not installed (``pip install roughstick[bem]``).
    ValueError
        If a distance lies at or below the mean plane, the map has NaN, or ``path`` is unknown.

    Notes
    -----
    *Distance convention.* The solver imposes the mean gap :math:`\bar g`; the output coordinate
    is :math:`d = \bar g + \bar z`, the flat position in the periodic convention where the
    elastic displacement has zero mean. Eq. 16 measures :math:`d` with no displacement away from
    the contacts; for a periodic cell of area :math:`A` the two differ by
    :math:`d_{local} - d = \bar p A Z/(\pi E^*)` (:func:`periodic_offset_coefficient`,
    :math:`\approx -1.24\,\bar p L/E^*` for a square of side :math:`L`), stored as
    ``distance_offset``; with it a single sphere follows Hertz (tested). The offset is
    proportional to :math:`\bar p`, so it vanishes at the equilibrium distance and
    :math:`\oint \bar p\, d\bar p = 0` along the adhesive branch: the apparent adhesive energy
    (Eq. 13), the pull-off pressure and the equilibrium distance are the same in either
    convention.

    *States with water but no hard contact* (:math:`d \ge \max z`) are not passed to the solver
    (its relative error is 0/0 there and it runs to the iteration cap). They are evaluated as a
    Dugdale tension :math:`\Delta P` on :math:`\{z \ge d_{local} - h_{water}\}` of the undeformed
    surface: the adhesive deflection is neglected, as in Eq. 16. The largest deflection this
    tension would cause is reported in the attribute ``max_noncontact_deflection``; it is a few
    pm for poly-silicon, but it is not small for soft materials, where jump-in to contact is
    missed.

    Costs (DESIGN.md §7): about 28 s per curve of 40 separations at 256², 4.5 min at 512² on one
    core, tolerance 1e-6. Tamaas is serial; dask input parallelises over the leading dimensions.

    References
    ----------
    .. [1] Frérot, L., Anciaux, G., Rey, V., Pham-Ba, S., Molinari, J.-F. (2020). Tamaas: a
       library for elastic-plastic contact of periodic rough surfaces. J. Open Source Softw. 5,
       2121. https://doi.org/10.21105/joss.02121
    .. [2] Polonsky, I. A., Keer, L. M. (1999). A numerical method for solving rough contact
       problems based on the multi-level multi-summation and conjugate gradient techniques.
       Wear 231, 206-219. https://doi.org/10.1016/S0043-1648(99)00113-1
    .. [3] Rey, V., Anciaux, G., Molinari, J.-F. (2017). Normal adhesive contact on rough
       surfaces: efficient algorithm for FFT-based BEM resolution. Comput. Mech. 60, 69-81.
       https://doi.org/10.1007/s00466-017-1392-5
    .. [4] Maugis, D. (1992). Adhesion of spheres: the JKR-DMT transition using a Dugdale model.
       J. Colloid Interface Sci. 150, 243-269. https://doi.org/10.1016/0021-9797(92)90285-T
    """
    tm = _import_tamaas()
    if not isinstance(height, xr.DataArray):
        raise TypeError(
            "height must be an xarray.DataArray with dims (..., y, x) and units; wrap a numpy "
            "array with roughstick.testing.make_topography(values, spacing=...)."
        )
    if path not in ("retract", "approach"):
        raise ValueError(f"path must be 'retract' or 'approach', got {path!r}.")
    check_map_fits_in_memory(height, model="bem")
    height = height_in_si(height)
    spacing = [grid_spacing(height, dim, min_pixels=MIN_MAP_PIXELS, purpose="the boundary-element solver")
               for dim in ("y", "x")]
    if height.chunks is not None:
        check_core_not_chunked(height, ("y", "x"))

    rh = relative_humidity_coordinate(relative_humidity)
    rh1 = rh if rh.ndim == 1 else rh.expand_dims(rh=[float(rh.values)])
    rh_values = np.asarray(rh1.values, dtype=float)
    dp = np.asarray(laplace_pressure(rh1).values, dtype=float)
    hw = np.asarray(water_height(rh1, adsorbed_layer=adsorbed_layer).values, dtype=float)
    if np.any(hw <= 0):
        raise ValueError(
            "water height must be positive at every humidity for the adhesive zone; got "
            f"{hw.tolist()} m. Check the adsorbed_layer model and contact angles."
        )
    e_star = reduced_modulus(material, material2)

    grids = None
    if distance is None:
        # per humidity, the grid fft_bem's automatic march solves for the same problem (cost:
        # see the docstring); its own message refuses stacks and dask maps
        grids, in_contact = _automatic_grids(height, rh_values, material=material, material2=material2,
                                             adsorbed_layer=adsorbed_layer, adhesion=adhesion,
                                             n_distances=n_distances)
        distance = np.concatenate(grids)
    dist = np.sort(np.unique(np.asarray(distance, dtype=float).ravel()))
    if dist.size < 2 or not np.all(np.isfinite(dist)):
        raise ValueError("distance must hold at least two finite values [m].")

    stats = {
        "solves": 0,
        "retries": 0,
        "unconverged": 0,
        "solve_seconds": 0.0,
        "max_noncontact_deflection": 0.0,
    }
    names = (
        "pressure",
        "repulsive_pressure",
        "wet_fraction",
        "contact_fraction",
        "n_contacts",
        "max_interference",
        "distance_offset",
        "solver_residual",
        "solved",
    )

    def kernel(z):
        res = _bem_kernel(
            z,
            spacing=tuple(spacing),
            distances=dist if grids is None else grids,
            sigma0s=np.abs(dp) if adhesion else np.zeros_like(dp),
            h_waters=hw,
            e_star=e_star,
            tolerance=tolerance,
            max_iterations=max_iterations,
            path=path,
            retries=retries,
            stats=stats,
            on_solve=bar.update,
        )
        return tuple(res[n] for n in names)

    # cost estimate before the work starts (issue 16): solves = points below the highest summit
    # (above it the non-contact state is solved directly, at the cost of a few FFTs)
    n_maps = int(np.prod([height.sizes[d] for d in height.dims if d not in ("y", "x")]))
    per_rh = grids if grids is not None else [dist] * len(rh_values)
    points = n_maps * sum(g.size for g in per_rh)
    below = n_maps * (sum(int(np.sum(g < float(height.max()))) for g in per_rh)
                      if height.chunks is None else len(rh_values) * dist.size)
    if grids is not None:  # the states fft_bem found in contact: those above the summit included
        below = max(below, in_contact)
    ny, nx = height.sizes["y"], height.sizes["x"]
    # progress counts the solves (the cost), not the points: states without contact, marched
    # after (retract) or before (approach) the solves, cost a few FFTs each; the time left is
    # re-estimated from the measured seconds per solve
    bar = WorkProgress(
        below,
        what=(f"bem: {n_maps} map(s) of {ny} x {nx} pixels x {len(rh_values)} humidities x "
              f"{dist.size} distances ({points} points, {below} Tamaas solves)"),
        estimate=estimate_seconds("bem", (ny, nx), below),
        progress=progress,
        unit="Tamaas solves",
    )

    log_level = tm.get_log_level()
    tm.set_log_level(tm.LogLevel.error)
    try:
        results = xr.apply_ufunc(
            kernel,
            height,
            input_core_dims=[["y", "x"]],
            output_core_dims=[["rh", "distance"]] * len(names),
            vectorize=True,
            dask="parallelized",
            output_dtypes=[float] * len(names),
            dask_gufunc_kwargs={"output_sizes": {"rh": len(rh_values), "distance": len(dist)}},
        )
    finally:
        tm.set_log_level(log_level)
        bar.close()
    ds = xr.Dataset(coords={"rh": rh_values, "distance": dist})
    for n, r in zip(names, results, strict=True):
        r = r.assign_coords(rh=rh_values, distance=dist)
        if n == "solved":
            ds[n] = r.assign_attrs(SOLVED_ATTRS)
            continue
        key = {"distance_offset": "distance_offset", "solver_residual": "solver_residual"}.get(n, n)
        ds[n] = set_attrs(r, key)
    ds["fit_error"] = set_attrs(xr.full_like(ds["pressure"], np.nan), "fit_error")
    ds = ds[[*CURVE_VARIABLES, "distance_offset", "solver_residual", "solved"]]
    ds = ds.assign_coords(
        water_height=("rh", hw, ATTRS["water_height"]),
        laplace_pressure=("rh", dp, ATTRS["laplace_pressure"]),
    )
    set_coord_attrs(ds)
    if rh.ndim == 0:
        ds = ds.squeeze("rh")
    ds.attrs = dataset_attrs(
        "Humid adhesive contact of a rough surface and a flat: boundary-element reference",
        references=_REFERENCES,
        contact_model="bem",
        solver=f"tamaas {getattr(tm, '__version__', '?')} PolonskyKeerRey + MaugisAdhesionFunctional",
        reduced_modulus=e_star,
        adsorbed_layer=str(getattr(adsorbed_layer, "__name__", adsorbed_layer)),
        tolerance=tolerance,
        path=path,
        adhesion=int(bool(adhesion)),
        distance_convention="mean gap + mean height (zero-mean elastic displacement); "
        "add distance_offset for the isolated-contact convention of Eq. 16",
        periodic=1,
    )
    if height.chunks is None:
        ds.attrs.update(
            bem_solves=stats["solves"],
            bem_retries=stats["retries"],
            bem_unconverged=stats["unconverged"],
            bem_solve_seconds=round(stats["solve_seconds"], 3),
            max_noncontact_deflection=stats["max_noncontact_deflection"],
        )
    append_history(
        ds,
        f"bem_contact_curves(tolerance={tolerance}, path={path!r}, "
        f"n_rh={len(rh_values)}, n_distance={len(dist)}"
        + (", automatic grid of fft_bem)" if grids is not None else ")")
        + (
            "; height not periodic: solved as if it wrapped around"
            if int(height.attrs.get("periodic", 1)) == 0
            else ""
        ),
    )
    return ds
