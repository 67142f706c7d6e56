r"""A large interaction zone composed of sub-zones under one rigid flat (the zone-size law, §5.2).

The paper's interaction zone :math:`\Delta s \times w` (2.62 × 30 µm, 524 × 6000 pixels at
5 nm) is a strip far longer than the surface's correlation length. Cut it into sub-zones each
many correlation lengths wide: under one rigid flat at distance :math:`d` from the strip's mean
plane, the strip's mean pressure is the area mean of its sub-zones' pressures,

.. math:: p_{strip}(d) = \frac1m \sum_{i=1}^m p_i(d),

exactly for a model whose asperities interact only through the flat (Eq. 16) and up to the
sub-zones' elastic coupling and mean-plane offsets otherwise. The strip's adhesive energy is then
Eq. 13 of the composed law, *not* the mean of the sub-zones' energies: the composed law rests on
the strip's tallest summits, so its equilibrium lies further out and Γ per unit area falls as
the zone grows (at 30-50 % RH by one to two orders of magnitude from 0.64 µm squares to the
strip). :func:`compose_zone_law` composes laws already computed; :func:`strip_adhesive_energy`
draws the sub-zones of ``n`` strips from a PSD and returns the strips' Γ.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import xarray as xr

from .._core.arguments import check_numbers
from .._core.conventions import append_history
from .._core.validate import as_length, external_stacklevel, relative_humidity_array
from ..contact import curves as contact_curves
from ..contact import expected_surface_groups, warn_if_outside_validity, warn_if_unresolved
from ..contact import summary as adhesion_summary
from ..ensemble.pipeline import distance_grid
from ..surface import generate_surfaces
from .cantilever import PAPER_CANTILEVER, Cantilever
from .interaction_zone import interaction_zone_shape

__all__ = ["compose_zone_law", "strip_adhesive_energy", "subzone_shape", "zone_size_bias"]

#: A sub-zone shorter than this many correlation lengths (in its shorter side) is refused: the
#: composition assumes sub-zones that do not share summits and whose mean planes agree.
MIN_CORRELATION_LENGTHS = 4

#: The zone-size law measured (docs/evidence/zone_size.md, part 1): median Γ [J m-2] of 40 zones
#: per size, Table-4 PSD, 5 nm pixels, Eq. 16 with the paper's adsorbed layer (0.9 nm per surface
#: above 65 % RH), at RH 0.3 / 0.5 / 0.7 / 0.9, against the zone's area [m2] (128², 256²,
#: 524 × 500, 524 × 1500 and 524 × 6000 pixels).
ZONE_SIZE_MEDIANS = {
    "relative_humidity": (0.3, 0.5, 0.7, 0.9),
    "area": (0.4096e-12, 1.6384e-12, 6.55e-12, 19.65e-12, 78.6e-12),
    "adhesive_energy": ((562e-6, 992e-6, 16930e-6, 62310e-6),
                        (160e-6, 299e-6, 5137e-6, 44960e-6),
                        (37.8e-6, 65.6e-6, 3242e-6, 42400e-6),
                        (10.6e-6, 20.0e-6, 4158e-6, 45720e-6),
                        (3.30e-6, 7.37e-6, 3137e-6, 43960e-6)),
}


@check_numbers(subzones="count")
def compose_zone_law(curves: xr.Dataset, *, subzones: int, dim: str = "realization") -> xr.Dataset:
    r"""Pressure law and adhesive energy of zones made of ``subzones`` sub-zones each.

    Consecutive groups of ``subzones`` realizations along ``dim`` tile one zone; its law is their
    area mean on the common distance grid (all sub-zones equal in area),
    :math:`p(d) = \frac1m\sum_i p_i(d)` (and likewise the wet fraction), and its adhesive energy,
    pull-off pressure and equilibrium are Eq. 13 of that law
    (:func:`roughstick.contact.summary`), not means of the sub-zones' values.

    Parameters
    ----------
    curves : xarray.Dataset
        Sub-zone curves of :func:`roughstick.contact.curves` or :func:`roughstick.ensemble.run`:
        ``pressure`` [Pa] (and ``wet_fraction``) over ``(dim, ..., distance)``, the distance from
        the flat to each sub-zone's mean plane on one grid.
    subzones : int
        Sub-zones per zone, >= 1 (e.g. 12 sub-zones of 524 × 500 pixels tile the 524 × 6000
        strip, :func:`subzone_shape`). Realizations beyond the last whole group are dropped.
    dim : str
        The realization dimension of the sub-zones.

    Returns
    -------
    xarray.Dataset
        Over ``(dim, ..., distance)``: the composed ``pressure`` and ``wet_fraction``; over
        ``(dim, ...)`` the variables of :func:`roughstick.contact.summary` of each composed zone.
        Zone ``k`` is sub-zones ``k*subzones ... (k+1)*subzones - 1``; ``attrs["subzones"]``.

    Examples
    --------
    >>> d = np.linspace(0.0, 3e-9, 7)
    >>> p = np.array([[4e5, 0, -1e5, 0, 0, 0, 0], [4e5, 3e5, 2e5, 0, -1e5, 0, 0]])  # Pa
    >>> c = xr.Dataset({"pressure": (("realization", "distance"), p)}, coords={"distance": d})
    >>> z = rs.stiction.compose_zone_law(c, subzones=2)
    >>> z.pressure.values[0] / 1e5  # the mean law
    array([ 4. ,  1.5,  0.5,  0. , -0.5,  0. ,  0. ])
    >>> float(z.adhesive_energy[0]) * 1e6  # Eq. 13 of the mean law [µJ m-2], not the mean of each Γ
    25.0
    """
    subzones = int(subzones)
    if subzones < 1:
        raise ValueError(f"subzones must be >= 1 (sub-zones per composed zone), got {subzones}")
    if "pressure" not in curves or "distance" not in curves["pressure"].dims:
        raise ValueError("curves must hold 'pressure' over a 'distance' dimension (roughstick.contact.curves)")
    if dim not in curves["pressure"].dims:
        raise ValueError(f"curves have no {dim!r} dimension (dims {curves['pressure'].dims}); pass dim= the "
                         "dimension that lists the sub-zones")
    n_zone = curves.sizes[dim] // subzones
    if n_zone < 1:
        raise ValueError(f"{curves.sizes[dim]} sub-zones cannot make one zone of subzones={subzones}: compute "
                         f"at least {subzones} sub-zones (n * subzones for n zones)")
    names = [v for v in ("pressure", "wet_fraction") if v in curves]
    sub = curves[names].isel({dim: slice(0, n_zone * subzones)})
    zone = xr.DataArray(np.repeat(np.arange(n_zone), subzones), dims=dim)
    law = sub.drop_vars([c for c in sub.coords if dim in sub[c].dims]).groupby(zone.rename("zone")).mean()
    law = law.rename({"zone": dim}).assign_coords({dim: np.arange(n_zone)})
    law["pressure"].attrs.update(units="Pa", long_name="mean pressure of the composed zone (positive repulsive)")
    out = xr.merge([law, adhesion_summary(law, check_grid=False)])
    out.attrs.update(subzones=subzones,
                     composition="zone law = area mean of its sub-zones' laws under one rigid flat; "
                                 "Eq. 13 of the mean law")
    return out


def _callable_m0(psd, shape, spacing) -> float:
    """Height variance [m2] of surfaces of ``shape`` drawn from a callable PSD: the sum of
    ``psd(|q|)`` over their wave-vector grid, as the generator draws it (q = 0 excluded)."""
    ny, nx = shape
    qy = 2 * np.pi * np.fft.fftfreq(ny, spacing)
    qx = 2 * np.pi * np.fft.fftfreq(nx, spacing)
    q = np.hypot(qy[:, None], qx[None, :]).ravel()
    s = psd(q)
    s = np.asarray(s.values if isinstance(s, xr.DataArray) else s, dtype=float)
    return float(np.sum(np.where(q > 0, s, 0.0)) * (2 * np.pi) ** 2 / (ny * nx * spacing**2))


@check_numbers(spacing="length")
def subzone_shape(beam: Cantilever = PAPER_CANTILEVER, *, spacing: float = 5e-9,
                  shape=None) -> tuple[tuple[int, int], int]:
    r"""Sub-zones that tile the interaction zone: ``((ny, nx_sub), subzones)``.

    The zone :math:`\Delta s \times w` (``shape``, default :func:`interaction_zone_shape`) is cut
    across the beam into the whole number of sub-zones whose width is nearest its length
    :math:`\Delta s` (squares as near as the zone allows) and divides the zone's width exactly.

    Examples
    --------
    >>> rs.stiction.subzone_shape()  # 2.62 × 30 µm at 5 nm: 12 sub-zones of 524 × 500 pixels
    ((524, 500), 12)
    """
    ny, nx = interaction_zone_shape(beam, spacing=spacing) if shape is None else (int(shape[0]), int(shape[1]))
    divisors = [k for k in range(1, nx + 1) if nx % k == 0]
    k = min(divisors, key=lambda m: (abs(math.log(nx / m / ny)), m))
    return (ny, nx // k), k


@check_numbers(n="count", seed="seed", subzones="count?")
def strip_adhesive_energy(psd, *, relative_humidity, n: int, beam: Cantilever = PAPER_CANTILEVER,
                          spacing=5e-9, shape=None, subzones: int | None = None, model: str = "modified_dmt",
                          seed=0, distance=None, keep_curves: bool = False) -> xr.Dataset:
    r"""Adhesive energy of ``n`` interaction zones (strips), each composed of sub-zones.

    Strip ``k`` is sub-zones ``k*m ... (k+1)*m - 1`` of :func:`roughstick.surface.generate_surfaces`
    (Eqs. 33-35; periodic, independent, of ``shape`` pixels at ``spacing``), each through the
    contact model on one distance grid (:func:`roughstick.ensemble.distance_grid` for all
    ``n*m`` of them), composed by :func:`compose_zone_law` (the strip's law is the area mean of
    its sub-zones' laws; Γ is Eq. 13 of that law). The default cuts the beam's zone
    :math:`\Delta s \times w` by :func:`subzone_shape`; a sub-zone shorter than
    :data:`MIN_CORRELATION_LENGTHS` correlation lengths is refused (its neighbours would not be
    independent).

    Parameters
    ----------
    psd : xarray.DataArray or callable
        PSD of the zone's equivalent surface (as :func:`roughstick.surface.generate_surfaces`
        takes, e.g. ``rs.datasets.family_psd("table4")``).
    relative_humidity : float or sequence
        RH fractions in (0, 1).
    n : int
        Number of strips.
    beam : Cantilever
        Sets the zone :math:`\Delta s \times w` (paper §5.2) when ``shape`` is None.
    spacing : float or str
        Pixel size [m] (5 nm in the paper).
    shape : (int, int), optional
        Pixels of a sub-zone; with ``subzones`` the strip. Default :func:`subzone_shape`.
    subzones : int, optional
        Sub-zones per strip; default the number that tiles the beam's zone.
    model : str
        Contact model (:func:`roughstick.contact.curves`).
    seed : int
        Root seed of the sub-zones (sub-zone ``j`` is realization ``j``).
    distance : array-like, optional
        Distance grid [m]; default :func:`roughstick.ensemble.distance_grid` of all the sub-zones.
    keep_curves : bool
        Also return the composed laws (``pressure``, ``wet_fraction`` over ``distance``).

    Returns
    -------
    xarray.Dataset
        Over ``(realization, rh)``: the strips' ``adhesive_energy`` [J m-2] (Eq. 13 of the
        composed law), ``pull_off_pressure``, ``equilibrium_distance`` ...; attrs ``subzones``,
        ``subzone_shape``, ``zone_area`` [m2], ``correlation_length`` [m].

    Examples
    --------
    >>> psd = rs.datasets.family_psd("table4")
    >>> g = rs.stiction.strip_adhesive_energy(psd, relative_humidity=[0.5], n=2, shape=(128, 128),
    ...                                       subzones=4, seed=1)
    >>> g.adhesive_energy.dims, g.attrs["subzones"]
    (('realization', 'rh'), 4)
    """
    spacing = float(as_length(spacing, name="spacing"))
    rh = relative_humidity_array(relative_humidity)
    tiling, m = subzone_shape(beam, spacing=spacing)
    shape = tiling if shape is None else (int(shape[0]), int(shape[1]))
    m = m if subzones is None else int(subzones)
    groups = expected_surface_groups(psd, shape=shape, spacing=spacing, relative_humidity=list(rh))
    corr = float(groups["corr_over_L"]) * shape[1] * spacing
    short = min(shape) * spacing
    if short < MIN_CORRELATION_LENGTHS * corr:
        raise ValueError(
            f"sub-zones of {shape[0]} x {shape[1]} pixels ({short:.3g} m across) are shorter than "
            f"{MIN_CORRELATION_LENGTHS} correlation lengths of the PSD ({corr:.3g} m): neighbouring sub-zones "
            f"would share summits and the composed law would not hold. Pass a larger shape= (at least "
            f"{math.ceil(MIN_CORRELATION_LENGTHS * corr / spacing)} pixels across) or a coarser spacing=.")
    total = int(n) * m
    if distance is None:
        grid_psd = {"psd": psd} if isinstance(psd, xr.DataArray) else {"m0": _callable_m0(psd, shape, spacing)}
        distance = distance_grid(**grid_psd, shape=shape, n=total, relative_humidity=rh).values
    # the trust checks once, on the sub-zones the PSD gives (not once per sub-zone)
    warn_if_unresolved(groups=groups, spacing=spacing)
    if model == "modified_dmt":
        warn_if_outside_validity(None, relative_humidity=list(rh), groups=groups)
    surf = generate_surfaces(psd, n=total, shape=shape, spacing=spacing, seed=seed)
    c = contact_curves(surf, relative_humidity=list(rh), model=model, check_validity=False,
                       distance=np.asarray(distance, dtype=float))
    c = c[["pressure", "wet_fraction"]].compute(scheduler="threads")
    out = compose_zone_law(c, subzones=m)
    if not keep_curves:
        out = out.drop_vars(["pressure", "wet_fraction"]).drop_dims("distance", errors="ignore")
    missing = out["equilibrium_distance"].isnull()
    if bool(missing.any()):
        warnings.warn(f"{int(missing.sum())} strip laws have no equilibrium on the distance grid: their Γ is a "
                      "bound, not a value; pass a wider distance= grid.", UserWarning,
                      stacklevel=external_stacklevel())
    out.attrs.update(subzones=m, subzone_shape=list(shape), spacing=spacing, contact_model=model,
                     zone_area=float(m * shape[0] * shape[1] * spacing**2), correlation_length=corr,
                     seed=int(seed) if isinstance(seed, (int, np.integer)) else str(seed))
    append_history(out, f"strip_adhesive_energy(n={int(n)}, shape={list(shape)}, subzones={m}, "
                        f"spacing={spacing!r}, model={model!r})")
    return out


@check_numbers(spacing="length")
def zone_size_bias(shape, *, spacing: float = 5e-9, beam: Cantilever = PAPER_CANTILEVER) -> xr.DataArray:
    r"""How much larger the median Γ of a zone of ``shape`` pixels is than that of the beam's zone.

    Read off the zone-size law measured on Table-4 surfaces with Eq. 16
    (:data:`ZONE_SIZE_MEDIANS`, docs/zone_size.md): the median Γ at each humidity, interpolated
    linearly in log Γ against log area between the measured sizes (0.41 to 79 µm²), of a zone of
    ``shape`` over that of the beam's interaction zone :math:`\Delta s \times w`
    (:func:`~roughstick.stiction.interaction_zone_shape`). It is what a smaller zone costs: its
    P(stuck) is that of a Γ this many times too large. Γ of such surfaces falls with the zone's
    area because a larger zone rests on taller summits (roughly as 1/area at 30-50 % RH); other
    PSDs fall at other rates (S1: steeper), and so does Γ without the adsorbed layer at 70 % RH
    (larger bias there), so read it as the order of the error, not a correction. The ratio
    depends on the area only; narrow zones of the same area measured close to it at 30-50 %
    RH (docs/evidence/zone_size.md).

    Parameters
    ----------
    shape : (int, int)
        Pixels of the zone (along, across the beam).
    spacing : float or str
        Pixel size [m].
    beam : Cantilever
        Sets the beam's zone :math:`\Delta s \times w`.

    Returns
    -------
    xarray.DataArray
        Median Γ of the zone over that of the beam's zone, over ``rh`` (0.3, 0.5, 0.7, 0.9); NaN
        where either area lies outside the measured sizes.

    Examples
    --------
    >>> b = rs.stiction.zone_size_bias((128, 128))  # a 0.64 µm square against 2.62 x 30 µm
    >>> b.values.round(1)
    array([170.3, 134.6,   5.4,   1.4])
    >>> float(rs.stiction.zone_size_bias(rs.stiction.interaction_zone_shape()).sel(rh=0.5))
    1.0
    """
    spacing = float(as_length(spacing, name="spacing"))
    ny, nx = (int(v) for v in np.broadcast_to(shape, 2))
    zy, zx = interaction_zone_shape(beam, spacing=spacing)
    table = ZONE_SIZE_MEDIANS
    log_area = np.log(table["area"])
    log_gamma = np.log(np.asarray(table["adhesive_energy"]))

    def median(area):
        a = math.log(area)
        if not log_area[0] - 1e-6 <= a <= log_area[-1] + 1e-6:  # outside the measured sizes
            return np.full(log_gamma.shape[1], np.nan)
        return np.exp([np.interp(a, log_area, col) for col in log_gamma.T])

    ratio = median(ny * nx * spacing**2) / median(zy * zx * spacing**2)
    return xr.DataArray(ratio, dims="rh", coords={"rh": list(table["relative_humidity"])}, name="zone_size_bias",
                        attrs={"units": "1", "long_name": "median Γ of the zone over that of the beam's zone",
                               "source": "zone-size law, Table-4 PSD, Eq. 16 (docs/zone_size.md)"})
