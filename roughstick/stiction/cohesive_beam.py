r"""Cohesive beam model: an Euler-Bernoulli cantilever released onto the patches' pressure laws.

The finite-range counterpart of the sharp-front model of :mod:`.beam_model` (issue 14). The
cantilever (length l, width w, thickness t, modulus E, gap h; the §5.1 beams by default) is
clamped at the support and loaded along its length by the interface pressure :math:`p_k(g)` of
the patch k under each point, g the local distance between the mean planes. Patches of length
Δx along the beam each carry one law of a bank:

- a bank of pressure-distance laws over ``(law, rh, gap)`` (:func:`pressure_law_bank`: the
  modified-DMT curves of independent patch surfaces, Eqs. 33-35 and 13), or
- main's bank of adhesive energies over ``(law, rh)`` (:func:`roughstick.build_patch_bank`):
  each energy :math:`\Gamma_k` is given the short-range shape of
  :func:`short_range_pressure_law` (stiff repulsion, a cubic well of work :math:`\Gamma_k` and
  range ``law_range``) — the law's shape is then assumed, only its energy is random.

Protocol (release): the beam is held in contact by a uniform load (the electrostatic pull-in)
that is slowly released. The equilibrium path is followed by continuation of the crack front
(the point where the gap crosses a marker level above the range of every law), the load being
the unknown; the first front position where the holding load reaches zero is where the beam
rests (a load-controlled snap lands there too). No zero before the tip: the beam comes free.
The start state is solved directly at a front where every law is overloaded; when that Newton
solve fails it is found by load control (:func:`._cohesive_kernels.pull_in`: pull-in load from
an S-shaped guess, energy descent, load doubled/halved). A release that still fails raises
:class:`SolverError`; the Monte-Carlo driver records it as ``solver_failed``.

The crack length reported is the zero-slope point of the free span's cubic (the s of Eq. 36);
the apparent Γ is Eq. 36 applied to it, as an experimenter would. Internal units: µm along the
beam, nm for gaps (:mod:`._cohesive_kernels`). RH stepping (state carried from one RH to the
next): :func:`step_cohesive_beam`.
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace

import numpy as np
import xarray as xr

from .._core.arguments import check_numbers
from .._core.validate import adhesive_energy_values
from ..contact import contact_distance_grid
from ..contact import curves as contact_curves
from ..surface import generate_surfaces
from . import _cohesive_kernels as K
from .beam import PAPER_CANTILEVER, Cantilever

__all__ = ["PatchLaws", "CohesiveRelease", "release_cohesive_beam", "step_cohesive_beam",
           "short_range_pressure_law", "pressure_law_bank"]

SolverError = K.SolverError
_PA_TO_HAT = 1e-9  # p_hat = p[Pa] * 1e-9  (pJ µm^-2 nm^-1)


@check_numbers(law_range="length", contact_gap="length", stiffness="positive", gap_step="length")
def short_range_pressure_law(adhesive_energy, *, law_range=2e-9, contact_gap=5e-9,
                             stiffness=1e17, gap_step=1e-11):
    r"""A short-range pressure law of work of separation ``adhesive_energy``: (pressure, gap).

    Stiff linear repulsion ``stiffness (g0 - g)`` below ``contact_gap`` = g0, and above it the
    cubic well :math:`p = -\tfrac{16\Gamma}{9\delta}\tfrac{27}{4} u (1-u)^2`,
    :math:`u = (g-g_0)/\delta`, whose work from g0 to g0 + δ is Γ (δ = ``law_range`` ≪ h).

    Parameters
    ----------
    adhesive_energy : float or array-like
        Γ [J m-2]; an array gives one law per value (leading axis).
    law_range, contact_gap, stiffness, gap_step : float
        δ [m], g0 [m], repulsive stiffness [Pa m-1] and grid step [m].

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        Pressure [Pa] (positive repulsive, 0 at the top of the grid) and the uniform gap grid [m].
    """
    gamma = np.asarray(adhesive_energy, dtype=float)
    g = np.arange(0.0, contact_gap + law_range + gap_step / 2, gap_step)
    u = (g - contact_gap) / law_range
    sigma = 16 * gamma[..., None] / (9 * law_range)
    p = np.where(g < contact_gap, stiffness * (contact_gap - g), -sigma * 27 / 4 * u * (1 - u) ** 2)
    p[..., -1] = 0.0
    return p, g


class PatchLaws:
    """Tabulated pressure-distance laws of the interface patches at one RH, for the kernel.

    Parameters
    ----------
    pressure : xarray.DataArray
        Mean pressure [Pa] (positive repulsive), dims ``("law", "gap")`` with a uniform ascending
        ``gap`` coordinate [m]. The last column is set to 0 (the law vanishes above the grid;
        the largest magnitude dropped is kept in ``top_pressure``); below the grid the last
        segment is extrapolated (stiff repulsion).
    """

    def __init__(self, pressure: xr.DataArray):
        if tuple(pressure.dims) != ("law", "gap"):
            raise ValueError(f"pressure must have dims ('law', 'gap'), got {pressure.dims}; "
                             "select one rh first (bank.sel(rh=...)).")
        g = np.asarray(pressure["gap"].values, dtype=float) * 1e9
        if g.size < 3 or not np.all(np.diff(g) > 0):
            raise ValueError("the gap coordinate must be ascending with at least 3 points")
        dg = (g[-1] - g[0]) / (g.size - 1)
        if not np.allclose(np.diff(g), dg, rtol=1e-6, atol=0):
            raise ValueError("the gap grid must be uniform (resample the laws, e.g. with .interp)")
        p = np.array(pressure.values, dtype=float)
        if not np.all(np.isfinite(p)):
            raise ValueError("patch laws contain NaN/inf pressures; drop those laws first")
        self.top_pressure = float(np.max(np.abs(p[:, -1])))
        p[:, -1] = 0.0
        self.P = np.ascontiguousarray(p * _PA_TO_HAT)
        self.g_lo, self.dg, self.g_hi = float(g[0]), float(dg), float(g[-1])
        self.PHI, self.S = K.tabulate_laws(self.P, self.g_lo, self.dg)
        self.n_laws = p.shape[0]
        #: work of separation from the equilibrium gap [J m-2] (the depth of each law's potential)
        self.adhesive_energy = -self.PHI.min(axis=1)
        self.equilibrium_gap = self.g_lo + self.dg * np.argmin(self.PHI, axis=1)  # nm

    @classmethod
    def uniform(cls, pressure_1d, gap) -> PatchLaws:
        """One law for every patch (the deterministic limit)."""
        return cls(xr.DataArray(np.asarray(pressure_1d)[None, :], dims=("law", "gap"),
                                coords={"gap": np.asarray(gap)}))

    @classmethod
    def from_energy(cls, adhesive_energy, **law_kwargs) -> PatchLaws:
        """One :func:`short_range_pressure_law` per adhesive energy [J m-2] (main's bank format)."""
        gamma = np.atleast_1d(np.asarray(adhesive_energy, dtype=float))
        if gamma.ndim != 1 or not np.all(np.isfinite(gamma)) or np.any(gamma < 0):
            raise ValueError("adhesive energies must be a 1-D array of finite values >= 0 J m-2")
        p, g = short_range_pressure_law(gamma, **law_kwargs)
        return cls(xr.DataArray(p, dims=("law", "gap"), coords={"gap": g}))


@dataclass(frozen=True)
class CohesiveRelease:
    """Outcome of one release (SI): stuck flag, crack length s, attached length, apparent Γ.

    ``arc``: the front ran to the tip and the tip, inside the range of its law, holds the beam
    bent as an arc — a state held by the tip's cohesive strength only; not counted as stuck.
    """

    stuck: bool
    crack_length: float
    attached_length: float
    apparent_adhesive_energy: float
    front: float
    clamp_moment: float
    n_steps: int
    arc: bool = False
    #: deflection dofs (internal units) and mesh refinement start of the state reached, for
    #: :func:`step_cohesive_beam`; None when free
    state: np.ndarray | None = field(default=None, repr=False, compare=False)
    x_fine: float = math.nan


def _mesh(laws: PatchLaws, patch_law, beam: Cantilever, patch_length, element_size, x_fine):
    EI_hat = beam.youngs_modulus * beam.width * beam.thickness**3 / 12.0 * 1e12
    return K.BeamMesh(beam.length * 1e6, beam.width * 1e6, EI_hat, beam.gap * 1e9, patch_law,
                      patch_length * 1e6, element_size * 1e6, x_fine, laws.P, laws.S, laws.PHI,
                      laws.g_lo, laws.dg)


@check_numbers(patch_length="length?", element_size="length", step="length")
def release_cohesive_beam(laws: PatchLaws, patch_law, *, beam: Cantilever = PAPER_CANTILEVER,
                          patch_length: float | None = None, element_size: float = 0.5e-6,
                          step: float = 1e-6) -> CohesiveRelease:
    r"""Release one pulled-in cantilever onto its patch laws: stuck or free, and the crack length.

    Parameters
    ----------
    laws : PatchLaws
        The tabulated patch laws (one RH).
    patch_law : array of int
        Law index of each patch from the clamp (at least ``ceil(l / patch_length)`` entries).
    beam : Cantilever
        Geometry and material (SI); ``beam.length`` is l.
    patch_length : float, optional
        Δx [m]; default the beam's interaction-zone length (its thickness, §5.2).
    element_size : float
        Largest Hermite element [m] (elements never straddle a patch boundary).
    step : float
        Largest continuation step of the front [m] (capped at Δx/2 so no patch is stepped over).

    Returns
    -------
    CohesiveRelease
        SI values; ``crack_length`` and ``apparent_adhesive_energy`` (Eq. 36) NaN when free.

    Raises
    ------
    SolverError
        The equilibrium path could not be followed (recorded as ``solver_failed`` by
        :func:`roughstick.simulate_beams`).

    Notes
    -----
    The continuation starts at the front where the energy release rate of Eq. 36 is
    1/0.8⁴ ≈ 2.4 times the strongest law used, so every front behind it needs a positive
    holding load; a beam shorter than that start comes free.
    """
    patch_length = float(beam.interaction_zone_length if patch_length is None else patch_length)
    if not (patch_length > 0 and element_size > 0 and step > 0):
        raise ValueError("patch_length, element_size and step must be positive lengths in m")
    patch_law = np.asarray(patch_law, dtype=np.int64)
    n_patch = int(math.ceil(beam.length / patch_length - 1e-9))
    if patch_law.shape[0] < n_patch:
        raise ValueError(f"need {n_patch} patch laws for a {beam.length:.4g} m beam, "
                         f"got {patch_law.shape[0]}")
    used = patch_law[:n_patch]
    if used.min() < 0 or used.max() >= laws.n_laws:
        raise ValueError(f"patch law indices must be in [0, {laws.n_laws})")
    gamma_max = float(laws.adhesive_energy[used].max())
    nan = math.nan
    free = CohesiveRelease(False, nan, 0.0, nan, nan, nan, 0)
    if gamma_max <= 0:
        return free
    start = 0.8 * (beam.stiffness_term / gamma_max) ** 0.25 * 1e6  # µm
    contact_gap = float(np.median(laws.equilibrium_gap[used]))
    marker_gap = laws.g_hi + max(10.0, 0.5 * (laws.g_hi - laws.g_lo))
    if start >= beam.length * 1e6 - 2 * element_size * 1e6 or marker_gap >= beam.gap * 1e9:
        return free
    mesh = _mesh(laws, patch_law, beam, patch_length, element_size, 0.8 * start)
    r = K.release(mesh, start=start, marker_gap=marker_gap, contact_gap=contact_gap,
                  step=min(step, 0.5 * patch_length) * 1e6)
    if not r.stuck:
        return CohesiveRelease(False, nan, 0.0, nan, nan, nan, r.n_steps)
    s = r.crack_length * 1e-6
    if not s < beam.length:
        return CohesiveRelease(False, nan, r.attached_length * 1e-6, nan, r.front * 1e-6,
                               r.clamp_moment * 1e-9, r.n_steps, arc=True, state=r.u,
                               x_fine=0.8 * start)
    return CohesiveRelease(True, s, r.attached_length * 1e-6, beam.stiffness_term / s**4,
                           r.front * 1e-6, r.clamp_moment * 1e-9, r.n_steps, state=r.u,
                           x_fine=0.8 * start)


@check_numbers(patch_length="length?", element_size="length")
def step_cohesive_beam(laws: PatchLaws, patch_law, previous: CohesiveRelease, *,
                       beam: Cantilever = PAPER_CANTILEVER, patch_length: float | None = None,
                       element_size: float = 0.5e-6) -> CohesiveRelease:
    r"""The beam left in place while RH changes: its state carried onto the new patch laws.

    The protocol of DelRio et al. (2007), RH stepped up with no pull-in in between: a free beam
    stays free (no load brings it down); a stuck one relaxes, at zero load, to the stable state
    reached by energy descent from its previous deflection under the new laws. With stronger
    laws the front zips towards the clamp through its cohesive zone (on a uniform interface to
    the Eq. 36 crack length of the new law) and stops at the first stable place, so
    heterogeneity can pin it further out than a fresh release; a beam free at a lower RH stays
    free even where a fresh release would leave it stuck — adhesion hysteresis.

    Parameters
    ----------
    laws, patch_law, beam, patch_length, element_size
        As in :func:`release_cohesive_beam` (same patches, same mesh parameters as ``previous``).
    previous : CohesiveRelease
        The state at the previous RH (from :func:`release_cohesive_beam` or this function).

    Returns
    -------
    CohesiveRelease
    """
    nan = math.nan
    if previous.state is None:
        return CohesiveRelease(False, nan, 0.0, nan, nan, nan, 0)
    patch_length = float(beam.interaction_zone_length if patch_length is None else patch_length)
    patch_law = np.asarray(patch_law, dtype=np.int64)
    mesh = _mesh(laws, patch_law, beam, patch_length, element_size, previous.x_fine)
    if mesh.ndof != previous.state.size:
        raise ValueError("previous state is of another mesh: use the same beam, patch_length "
                         "and element_size at every RH")
    marker_gap = laws.g_hi + max(10.0, 0.5 * (laws.g_hi - laws.g_lo))
    u, n = mesh.minimize(previous.state, 0.0)
    a = mesh.front_position(u, marker_gap)
    if not a < mesh.length:
        return CohesiveRelease(False, nan, 0.0, nan, nan, nan, n)
    s = mesh.zero_slope_point(u, a) * 1e-6
    keep = dict(n_steps=n, state=u, x_fine=previous.x_fine, front=a * 1e-6,
                clamp_moment=mesh.clamp_moment(u) * 1e-9, attached_length=(mesh.length - a) * 1e-6)
    if not s < beam.length:
        return CohesiveRelease(False, nan, apparent_adhesive_energy=nan, arc=True, **keep)
    return CohesiveRelease(True, s, apparent_adhesive_energy=beam.stiffness_term / s**4, **keep)


def laws_by_rh(bank: xr.DataArray, **law_kwargs) -> list[PatchLaws]:
    """PatchLaws per RH from a ``(law, rh, gap)`` pressure bank or a ``(law, rh)`` energy bank."""
    if set(bank.dims) == {"law", "rh", "gap"}:
        return [PatchLaws(bank.isel(rh=i).transpose("law", "gap").load())
                for i in range(bank.sizes["rh"])]
    if set(bank.dims) == {"law", "rh"}:
        e = adhesive_energy_values(bank.transpose("law", "rh"))
        return [PatchLaws.from_energy(e[:, i], **law_kwargs) for i in range(e.shape[1])]
    raise ValueError(f"bank must have dims ('law', 'rh') (adhesive energy, build_patch_bank) or "
                     f"('law', 'rh', 'gap') (pressure, pressure_law_bank), got {bank.dims}")


def release_many(laws: list[PatchLaws], idx, lengths, beam: Cantilever, patch_length, *,
                 element_size=0.5e-6, step=1e-6, protocol="release", threads: int | None = None):
    """Every (realization, rh, length): arrays s [m] (inf free), failed, attached, arc.

    ``protocol="step_up"`` releases at the first RH and carries each beam's state through the
    next ones (:func:`step_cohesive_beam`); a failure there fails the later RH of that beam.
    Realizations are independent and solved on ``threads`` threads (default: one per core; the
    compiled assembly and solves release the GIL), each writing only its own rows, so the result
    does not depend on the number of threads.
    """
    shape = (idx.shape[0], len(laws), len(lengths))
    s = np.full(shape, np.inf)
    failed = np.zeros(shape, bool)
    arc = np.zeros(shape, bool)
    attached = np.zeros(shape)

    def one(i):
        for b, length in enumerate(lengths):
            geom = replace(beam, length=float(length))
            prev = None
            for j, law in enumerate(laws):
                try:
                    if protocol == "release" or j == 0:
                        r = release_cohesive_beam(law, idx[i], beam=geom, patch_length=patch_length,
                                                  element_size=element_size, step=step)
                    elif prev is None:
                        raise K.SolverError("the state at the previous RH was not solved")
                    else:
                        r = step_cohesive_beam(law, idx[i], prev, beam=geom,
                                               patch_length=patch_length,
                                               element_size=element_size)
                except K.SolverError:
                    failed[i, j, b] = True
                    s[i, j, b] = np.nan
                    prev = None
                    continue
                prev = r
                if r.stuck:
                    s[i, j, b] = r.crack_length
                arc[i, j, b] = r.arc
                attached[i, j, b] = r.attached_length

    workers = max(1, min(int(threads or os.cpu_count() or 1), idx.shape[0]))
    if workers == 1:
        for i in range(idx.shape[0]):
            one(i)
    else:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            list(pool.map(one, range(idx.shape[0])))  # list(): re-raises a worker's exception
    return s, failed, attached, arc


@check_numbers(n_law="count", spacing="length", seed="seed", n_gap="count")
def pressure_law_bank(psd: xr.DataArray, *, relative_humidity, n_law: int = 100, shape=(64, 64),
                      spacing: float, seed: int = 0, model: str = "modified_dmt",
                      n_gap: int = 400) -> xr.DataArray:
    r"""Pressure-distance laws of ``n_law`` random patches per RH on one uniform gap grid.

    The same patches as :func:`roughstick.build_patch_bank` with the same arguments (law k is
    realization k of :func:`roughstick.generate_surfaces`), kept as full curves (Eqs. 33-35,
    13) for the cohesive model instead of their adhesive energies. Patches are assumed
    independent; a ``ValueError`` is raised when the patch is not at least four correlation
    lengths of the first surface long (autocorrelation falling below 1/e).

    Returns
    -------
    xarray.DataArray
        ``pressure`` [Pa] (positive repulsive) over ``(law, rh, gap)``, gap [m] between mean planes.
    """
    rh = np.atleast_1d(np.asarray(relative_humidity, dtype=float))
    if np.any((rh <= 0) | (rh >= 1)):
        raise ValueError("relative_humidity must be fractions in (0, 1), e.g. 0.6 not 60")
    if int(n_law) < 1 or int(n_gap) < 8:
        raise ValueError("n_law must be >= 1 and n_gap >= 8")
    surf = generate_surfaces(psd, n=int(n_law), shape=tuple(shape), spacing=float(spacing),
                             seed=seed).load()
    first = np.asarray(surf.isel(realization=0).values, dtype=float)
    z = first - first.mean()
    acf = np.fft.ifft2(np.abs(np.fft.fft2(z)) ** 2).real[0] / np.sum(z * z)
    corr = spacing * int(np.argmax(acf[: z.shape[1] // 2] < math.exp(-1)))
    if not 0 < corr <= spacing * z.shape[1] / 4:
        raise ValueError(f"patch of {spacing * z.shape[1]:.3g} m is not >= 4 correlation lengths "
                         f"({corr:.3g} m): patch laws would not be independent; use longer patches")
    grid = np.asarray(contact_distance_grid(surf.isel(realization=0), relative_humidity=list(rh)).values)
    rms = float(z.std())
    lo, hi = grid.min() - 0.5 * (grid.max() - grid.min()), grid.max() + 4 * rms
    gap = np.linspace(lo, hi, int(n_gap))
    out = np.empty((int(n_law), len(rh), gap.size))
    for k in range(int(n_law)):
        c = contact_curves(surf.isel(realization=k), relative_humidity=list(rh), distance=gap,
                           model=model)
        out[k] = c["pressure"].transpose("rh", "distance").values
    bank = xr.DataArray(out, {"law": np.arange(int(n_law)), "rh": rh, "gap": gap},
                        ("law", "rh", "gap"), name="pressure",
                        attrs={"units": "Pa", "long_name": "mean pressure of a patch law (positive repulsive)",
                               "contact_model": model, "seed": int(seed), "correlation_length": corr,
                               "independence": "patch laws independent (patch >= 4 correlation lengths)"})
    bank["gap"].attrs.update(units="m", long_name="distance between the mean planes")
    return bank
