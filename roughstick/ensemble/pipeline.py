r"""The Monte Carlo pipeline of one ensemble (paper §4.3): surfaces → curves → summaries, per block.

A run is described by a :class:`Spec` (the PSD, the surface grid, the humidities, the common
distance grid, the root seed, the chunking and the three stage functions). One block, realizations
``[a, b)`` at humidities ``rh[lo:hi]``, is the pure function :func:`compute_block`: realization
``k`` always comes from the ``SeedSequence`` child ``k`` and is computed alone, so a block gives the
same numbers whatever the chunking, the scheduler or the number of workers, and a recomputed
block is bit-identical. :func:`lazy_ensemble` lays the blocks out as one dask-backed Dataset with
``xarray.map_blocks``. Executing blocks (threads, a cluster, streaming, auto-n) is
:mod:`.execute`; the entry point is :func:`roughstick.ensemble.run` (:mod:`.run`).
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import inspect
import json
import math
import threading
from collections.abc import Callable

import dask.array as dsa
import numpy as np
import xarray as xr
from scipy.stats import norm

from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.conventions import ATTRS, dataset_attrs
from .._core.references import PAPER, cite
from .._core.validate import relative_humidity_array
from .._core.version import __version__
from ..contact import MODELS
from ..contact import curves as contact_curves
from ..contact import summary as contact_summary
from ..contact.adhesion import equilibrium_crossings
from ..contact.meniscus import as_relative_humidity, water_height
from ..surface.distribution import as_height_distribution, evaluate, standardised
from ..surface.generate import extrapolation_said_once
from ..surface.moments import psd_moments
from ..testing import make_topography

__all__ = ["distance_grid"]

REFERENCES = cite((PAPER, "sections 4.2-4.3, Eqs. 13, 16-23, 33-34"))
_CURVE_DIMS = ("realization", "rh", "distance")


# ============================================================================ helpers
def _psd_m0(psd: xr.DataArray) -> float:
    """Height variance m0 [m2] of a 2-D ``(qy, qx)`` or isotropic ``(q)`` PSD, averaged over any
    leading dims, by :func:`roughstick.surface.psd_moments` (the PSD is small: read eagerly on purpose)."""
    if ("qx" in psd.dims and "qy" in psd.dims) or "q" in psd.dims:
        return float(psd_moments(psd).m0.mean())
    raise ValueError(
        f"psd must have dims ('qy', 'qx') or ('q',); got {psd.dims}. Build one with "
        "roughstick.surface.power_spectrum / average_psd or roughstick.surface.fit_self_affine."
    )


def _water_heights(rh: np.ndarray, adsorbed_layer) -> np.ndarray:
    return np.asarray(water_height(rh, adsorbed_layer=adsorbed_layer).values, float)


@renamed_keywords(num="n_distance")
@check_numbers(n="count", m0="positive?", n_distance="count?", lower="finite", exceedance="fraction",
               points_per_water_height="positive")
def distance_grid(
    psd=None,
    *,
    shape,
    n: int,
    relative_humidity,
    adsorbed_layer="paper",
    m0: float | None = None,
    n_distance: int | None = None,
    lower: float = 1.5,
    exceedance: float = 1e-6,
    points_per_water_height: float = 10.0,
    height_distribution=None,
) -> xr.DataArray:
    r"""A distance grid common to every realization of an ensemble.

    The top of the grid is first water contact of the highest surface one can expect in the whole
    ensemble: a union (Bonferroni) bound over all ``n * ny * nx`` Gaussian heights gives a height
    :math:`z_\max = \sqrt{m_0}\,\Phi^{-1}(1 - \epsilon / (n\,n_y n_x))` that any pixel exceeds with
    probability below ``exceedance`` :math:`\epsilon`, and :math:`d_\max = z_\max + \max h_{water}`.
    The bottom, ``lower`` :math:`\sqrt{m_0}`, lies below the equilibrium distances the paper reports
    (2.6 to 6.2 :math:`\sqrt{m_0}`, §4.3.2). The grid is uniform; by default its step is the
    smallest water height divided by ``points_per_water_height`` (the attractive part of a curve at
    low RH is about one water height wide), with 100 to 2000 points. Γ (Eq. 13) converges as the
    step shrinks. :func:`run` extends the grid of a realization whose highest point pokes above
    the top, or whose curve is still attractive at the bottom.

    Parameters
    ----------
    psd : xarray.DataArray, optional
        PSD (2-D or isotropic) giving :math:`m_0`; or pass ``m0``.
    shape : tuple of int
        Surface shape (ny, nx).
    n : int
        Number of realizations.
    relative_humidity : sequence of float
        Humidities (fractions) of the run.
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-layer model (:func:`roughstick.contact.water_height`).
    m0 : float, optional
        Height variance [m2], instead of ``psd``.
    n_distance : int, optional
        Number of grid points (overrides ``points_per_water_height``).
    lower : float, default 1.5
        Bottom of the grid in units of :math:`\sqrt{m_0}`.
    exceedance : float, default 1e-6
        Probability that some pixel of the ensemble exceeds the grid's top.
    points_per_water_height : float, default 10
        Grid points per smallest water height :math:`h_{water}` of the run (when ``n_distance``
        is None).
    height_distribution : xarray.Dataset, optional
        The surfaces' height distribution (:func:`roughstick.surface.height_distribution`):
        the top is then its quantile at the same probability, :math:`\sqrt{m_0}\,T(u)` with
        :math:`u = \Phi^{-1}(1 - \epsilon / (n\,n_y n_x))` (a skewed film's tallest summits
        stand higher than a Gaussian's).

    Returns
    -------
    xarray.DataArray
        ``distance`` coordinate [m], ascending.

    Examples
    --------
    >>> d = rs.ensemble.distance_grid(m0=16e-18, shape=(64, 64), n=10, relative_humidity=[0.5])
    >>> d.sizes["distance"], round(float(d[0]) * 1e9, 2), round(float(d[-1]) * 1e9, 2)
    (144, 6.0, 27.83)
    """
    if m0 is None:
        if psd is None:
            raise ValueError("give psd= or m0= to distance_grid.")
        m0 = _psd_m0(psd)
    if not (m0 > 0 and np.isfinite(m0)):
        raise ValueError(f"height variance m0 must be positive and finite, got {m0!r}.")
    if n_distance is not None and int(n_distance) < 2:
        raise ValueError(f"n_distance must be >= 2, got {n_distance!r}.")
    rh = relative_humidity_array(relative_humidity)
    sigma = math.sqrt(m0)
    npix = int(np.prod(shape)) * max(int(n), 1)
    u_top = float(norm.isf(exceedance / npix))
    z_top = sigma * (u_top if height_distribution is None else
                     float(evaluate(standardised(as_height_distribution(height_distribution)["height"].values),
                                    [u_top])[0]))
    hw = _water_heights(rh, adsorbed_layer)
    d_max = z_top + float(np.max(hw))
    d_min = lower * sigma
    if d_min >= d_max:
        raise ValueError(f"lower={lower} sqrt(m0) is above the grid's top; use a smaller lower.")
    if n_distance is None:
        step = float(np.min(hw)) / float(points_per_water_height)
        n_distance = int(np.clip(math.ceil((d_max - d_min) / step) + 1, 100, 2000))
    d = np.linspace(d_min, d_max, int(n_distance))
    return xr.DataArray(
        d, dims="distance", coords={"distance": d}, name="distance", attrs=dict(ATTRS["distance"])
    ).pipe(lambda a: a.assign_coords(distance=a.distance.assign_attrs(ATTRS["distance"])))


# ============================================================================ the spec
@dataclasses.dataclass(frozen=True, eq=False)
class Spec:
    psd: xr.DataArray
    shape: tuple[int, int]
    spacing: float
    rh: np.ndarray
    distance: np.ndarray
    seed: np.random.SeedSequence
    chunk: int
    rh_chunk: int
    adsorbed_layer: object
    material: object
    generate: Callable
    curves: Callable
    summary: Callable
    generate_kwargs: dict
    curves_kwargs: dict
    water_max: float
    token: str
    own_grid: bool = False  # summaries on each map's own automatic grid (distance=None)
    # multi-fidelity: (accurate model, frozenset of the realizations it runs on); () when not used
    accurate: tuple = ()

    def rh_blocks(self):
        r = self.rh.size
        return [(j, lo, min(lo + self.rh_chunk, r)) for j, lo in enumerate(range(0, r, self.rh_chunk))]

    def realization_blocks(self, start, stop):
        """Blocks [a, b) aligned on multiples of ``chunk`` (index i = a // chunk)."""
        out = []
        a = start
        while a < stop:
            b = min((a // self.chunk + 1) * self.chunk, stop)
            out.append((a // self.chunk, a, b))
            a = b
        return out


def _callable_id(f) -> str:
    """A name of ``f`` that is the same in every process (no memory address): a resumed run in a
    new process must find the same parameter hash (a ``functools.partial`` has no qualname and
    its repr holds the address of the wrapped function)."""
    if isinstance(f, functools.partial):
        args = ", ".join([repr(a) for a in f.args] + [f"{k}={v!r}" for k, v in sorted(f.keywords.items())])
        return f"partial({_callable_id(f.func)}, {args})"
    if hasattr(f, "__qualname__"):
        return f"{getattr(f, '__module__', '?')}.{f.__qualname__}"
    # a callable object: its own repr if it has one (its parameters), else its type
    own = type(f).__repr__ is not object.__repr__
    return f"{type(f).__module__}.{type(f).__qualname__}" + (f"({f!r})" if own else "")


def _kwarg_id(value):
    """A keyword argument as the parameter hash sees it: a Dataset (a height distribution) by
    the digest of its values and its family (its repr holds a time-stamped history)."""
    if isinstance(value, xr.Dataset):
        digest = hashlib.sha256()
        for name in sorted(value.data_vars):
            digest.update(np.ascontiguousarray(np.asarray(value[name].values, dtype=float)).tobytes())
        return f"Dataset({value.attrs.get('family', '')}, {digest.hexdigest()[:16]})"
    return value


def _hash_params(spec_fields: dict) -> str:
    h = hashlib.sha256()
    psd = spec_fields["psd"]
    h.update(np.ascontiguousarray(np.asarray(psd.data, dtype=float)).tobytes())
    for c in sorted(psd.coords):
        h.update(c.encode())
        h.update(np.ascontiguousarray(np.asarray(psd[c].values, dtype=float)).tobytes())
    h.update(np.ascontiguousarray(spec_fields["distance"]).tobytes())
    h.update(np.ascontiguousarray(spec_fields["rh"]).tobytes())
    rest = {
        k: spec_fields[k]
        for k in ("shape", "spacing", "chunk", "rh_chunk", "seed_entropy", "seed_spawn_key")
    }
    rest["own_grid"] = bool(spec_fields.get("own_grid", False))
    if spec_fields.get("accurate"):  # absent from single-model runs: their hash is unchanged
        model, members = spec_fields["accurate"]
        digest = hashlib.sha256(np.asarray(sorted(members), dtype=np.int64).tobytes()).hexdigest()
        rest["accurate"] = [str(model), digest]
    rest["version"] = __version__
    rest["adsorbed_layer"] = (
        spec_fields["adsorbed_layer"]
        if isinstance(spec_fields["adsorbed_layer"], str)
        else _callable_id(spec_fields["adsorbed_layer"])
    )
    rest["material"] = repr(spec_fields["material"])
    rest["functions"] = [_callable_id(spec_fields[k]) for k in ("generate", "curves", "summary")]
    rest["kwargs"] = repr(sorted((k, _kwarg_id(v)) for k, v in spec_fields["generate_kwargs"].items())) + repr(
        sorted(spec_fields["curves_kwargs"].items())
    )
    h.update(json.dumps(rest, sort_keys=True, default=str).encode())
    return h.hexdigest()[:24]


# ============================================================================ one block
def _surfaces(spec: Spec, start: int, stop: int) -> xr.DataArray:
    gen = spec.generate
    try:
        params = inspect.signature(gen).parameters
    except (TypeError, ValueError):  # pragma: no cover
        params = {}
    kw = dict(spec.generate_kwargs)
    with extrapolation_said_once():  # said by run() before the graph, not once per block
        h = _generate(gen, params, spec, start, stop, kw)
    if h.chunks is not None:
        h = h.compute(scheduler="sync")
    return h


def _generate(gen, params, spec, start, stop, kw):
    if "realizations" in params:
        h = gen(spec.psd, realizations=np.arange(start, stop), shape=spec.shape,
                spacing=spec.spacing, seed=spec.seed, **kw)
    else:
        # realizations [start, stop) form exactly the last chunk of an n=stop ensemble chunked by
        # (stop - start) when start is a multiple of it; else generate [0, stop) and slice.
        c = stop - start
        chunks = c if start % c == 0 else stop
        h = gen(spec.psd, n=stop, shape=spec.shape, spacing=spec.spacing, seed=spec.seed,
                chunks=chunks, **kw)
        h = h.isel(realization=slice(start, stop))
    return h


def _crossing(p):
    """Per (realization, rh): does the curve cross from repulsive (below) to attractive (above)?"""
    return np.any(equilibrium_crossings(p), axis=-1)


def _curves_self_extending(spec, hk, rh, grid, top, bottom, *, extend=True):
    """Curves of one realization on the common grid, extended where that grid is too short.

    Above: if the highest point plus the water height pokes above the grid's top, levels are added
    up to it (Γ of Eq. 13 integrates the attraction from there). Below: if a humidity's curve has
    no stable zero crossing (repulsive below, attractive above) on the grid, levels are added down
    to the lowest pixel. Equilibrium and Γ are then decided on the separation path (the outermost
    stable crossing, :func:`roughstick.contact.summary`); a curve attractive again deep in
    contact is reported (``attractive_at_floor``), not an error; so is a curve that never turns
    repulsive even at the lowest pixel (the surfaces would collapse into full contact: no
    equilibrium, ``equilibrium_distance`` NaN, Γ a lower bound). With ``extend=False`` (summaries
    on each map's own grid, which need nothing from this one) the common grid is used as it is.
    Returns ``(curves, flag)`` with flag bit 1 = extended below, bit 2 = extended above.
    """
    flag = 0
    if not extend:
        grid, top, bottom = np.asarray(grid), -np.inf, np.inf
    step = float(np.min(np.diff(grid))) if grid.size > 1 else max(abs(top - bottom) / 100, 1e-12)
    d = grid
    if top > grid[-1] * (1 + 1e-12):
        n_up = min(max(int(np.ceil((top + step - grid[-1]) / step)), 1), 400)
        d = np.concatenate([d, np.linspace(grid[-1], top + step, n_up + 1)[1:]])
        flag |= 2

    def run(dist):
        kept = dist[dist > _mean_plane(spec, hk)]
        da = xr.DataArray(kept, dims="distance", coords={"distance": kept}, attrs=dict(ATTRS["distance"]))
        c = spec.curves(hk, relative_humidity=rh, distance=da, material=spec.material,
                        adsorbed_layer=spec.adsorbed_layer, **spec.curves_kwargs)
        c = c.to_dataset(name=c.name or "pressure") if isinstance(c, xr.DataArray) else c
        return c if kept.size == dist.size else c.reindex(distance=dist)  # NaN: no solution there

    curves = run(d)
    if "pressure" not in curves:
        return curves, flag
    p = np.asarray(curves["pressure"].transpose(..., "distance").values)
    if not np.all(_crossing(p)) and bottom < d[0]:
        # the grid's own step (capped at 2000 levels): the crossing is resolved as finely as on it
        n_down = min(max(int(np.ceil((d[0] - bottom + step) / step)), 1), 2000)
        down = d[0] - step * np.arange(n_down, 0, -1) if n_down * step >= d[0] - bottom else \
            np.linspace(bottom - step, d[0], n_down + 1)[:-1]
        d = np.concatenate([down, d])
        flag |= 1
        curves = run(d)
        p = np.asarray(curves["pressure"].transpose(..., "distance").values)
    return curves, flag


def _mean_plane(spec: Spec, hk: xr.DataArray) -> float:
    """The distance at and below which the ensemble's contact model has no solution on ``hk``:
    its mean plane for a model with ``positive_mean_gap`` (the periodic boundary-element
    models), else minus infinity."""
    model = MODELS.get(spec.curves_kwargs.get("model", ""))
    if model is None or not model.positive_mean_gap:
        return -np.inf
    return float(hk.mean(skipna=True))


OWN_GRID_NOTE = (
    "adhesive_energy, pull_off_pressure, equilibrium_distance and the other summaries of each "
    "(realization, rh) come from that map's own automatic distance grid at that humidity alone "
    "(roughstick.contact.contact_distance_grid), so they do not depend on the other humidities, on n or "
    "on the chunks; the stored curves are on the common distance grid (extended per realization "
    "where it fell short: grid_extension)")


def _own_grid_capable(spec: Spec) -> bool:
    """Summaries on each map's own grid: asked for (no ``distance=`` given) and possible (the
    default contact stage, rough_contact_curves, builds its own grid from ``distance=None``)."""
    f = spec.curves
    return spec.own_grid and isinstance(f, functools.partial) and f.func is contact_curves


def _own_grid_summary(spec: Spec, h2d: xr.DataArray, rh: xr.DataArray) -> xr.Dataset:
    """Summaries of one map, each humidity on its own automatic grid (one call per humidity)."""
    parts = []
    for r in np.atleast_1d(rh.values):
        c = spec.curves(h2d, relative_humidity=[float(r)], distance=None, material=spec.material,
                        adsorbed_layer=spec.adsorbed_layer, **spec.curves_kwargs)
        # the automatic grid reaches the lowest pixel: a curve that is attractive there has no
        # equilibrium (equilibrium_distance NaN, Γ a lower bound), which the grid cannot fix
        s = spec.summary(c, check_grid=False) if spec.summary is contact_summary else spec.summary(c)
        parts.append(s.drop_vars([v for v in s.coords if v != "rh"], errors="ignore"))
    return parts[0] if len(parts) == 1 else xr.concat(parts, "rh", combine_attrs="drop_conflicts")


#: The summaries the accurate model adds on its subset of a multi-fidelity ensemble.
ACCURATE_VARIABLES = ("adhesive_energy", "pull_off_pressure", "equilibrium_distance")


#: The accurate summaries of the maps this process computed last (map bytes, grid, model,
#: humidity, materials): a multi-fidelity pilot's maps are the first of the run's subset, which
#: then reads them instead of solving them again (the same numbers: the same computation).
_ACCURATE_DONE: dict = {}
_ACCURATE_DONE_SIZE = 2048
_ACCURATE_LOCK = threading.Lock()


def _accurate_one(spec: Spec, h2d: xr.DataArray, r: float, model: str) -> xr.Dataset:
    """The accurate model's summaries of one map at one humidity (kept for the next asker)."""
    values = np.ascontiguousarray(h2d.values)
    key = (model, hashlib.sha1(values.tobytes()).hexdigest(), values.shape, str(values.dtype),
           tuple(float(h2d[d][i]) for d in ("y", "x") for i in (0, -1)), float(r),
           repr(spec.material), repr(spec.adsorbed_layer))
    with _ACCURATE_LOCK:
        hit = _ACCURATE_DONE.get(key)
    if hit is not None:
        return hit.copy(deep=True)
    c = contact_curves(h2d, relative_humidity=[float(r)], model=model, material=spec.material,
                       adsorbed_layer=spec.adsorbed_layer, check_validity=False)
    s = contact_summary(c, check_grid=False)[list(ACCURATE_VARIABLES)]
    s = s.drop_vars([v for v in s.coords if v != "rh"], errors="ignore").compute()
    with _ACCURATE_LOCK:
        _ACCURATE_DONE[key] = s
        while len(_ACCURATE_DONE) > _ACCURATE_DONE_SIZE:
            _ACCURATE_DONE.pop(next(iter(_ACCURATE_DONE)))
    return s.copy(deep=True)


def accurate_summary(spec: Spec, h2d: xr.DataArray, rh: xr.DataArray) -> xr.Dataset:
    """The accurate model's summaries of one map (``<name>_accurate``), each humidity alone on
    the model's own automatic grid (so they do not depend on the humidity blocks)."""
    model = spec.accurate[0]
    parts = [_accurate_one(spec, h2d, float(r), model) for r in np.atleast_1d(rh.values)]
    s = parts[0] if len(parts) == 1 else xr.concat(parts, "rh", combine_attrs="drop_conflicts")
    return _accurate_names(s, model)


def _accurate_names(s: xr.Dataset, model: str) -> xr.Dataset:
    out = s.rename({v: f"{v}_accurate" for v in ACCURATE_VARIABLES})
    for v in ACCURATE_VARIABLES:
        a = s[v].attrs
        out[f"{v}_accurate"].attrs = {**a, "long_name": f"{a.get('long_name', v)} by the accurate "
                                      f"model ({model}) on the seeded subset (NaN elsewhere)",
                                      "contact_model": model}
    return out


def _no_accurate(summary: xr.Dataset, model: str) -> xr.Dataset:
    """NaN ``<name>_accurate`` variables shaped like ``summary``'s (a realization off the subset)."""
    s = xr.Dataset({v: xr.full_like(summary[v], np.nan, dtype=float) for v in ACCURATE_VARIABLES})
    return _accurate_names(s, model)


def compute_block(spec: Spec, start: int, stop: int, rh_lo: int, rh_hi: int) -> xr.Dataset:
    """Compute realizations [start, stop) at humidities rh[rh_lo:rh_hi] (numpy in, numpy out)."""
    h = _surfaces(spec, start, stop)
    mean = h.mean(("y", "x"))
    top = h.max(("y", "x")) - mean  # d is measured from the mean plane (Eq. 16)
    bottom = h.min(("y", "x")) - mean
    hw = spec.water_max
    rh = as_relative_humidity(spec.rh[rh_lo:rh_hi])
    grid = np.asarray(spec.distance, dtype=float)
    own_grid = _own_grid_capable(spec)
    parts, extended, deep = [], [], []
    for k in range(h.sizes["realization"]):
        # one realization at a time: its numbers cannot depend on which block it falls in
        hk = h.isel(realization=[k])
        curves, flag = _curves_self_extending(spec, hk, rh, grid, float(top[k]) + hw, float(bottom[k]),
                                              extend=not own_grid)
        if own_grid:
            # each humidity alone on this map's own automatic grid (OWN_GRID_NOTE)
            own = _own_grid_summary(spec, h.isel(realization=k, drop=True), rh)
            summary = own.expand_dims(realization=hk["realization"].values).transpose(
                "realization", ...)
        else:
            summary = spec.summary(curves)
        if spec.accurate:  # multi-fidelity: the accurate model on its seeded subset only
            member = start + k in spec.accurate[1]
            acc = (accurate_summary(spec, h.isel(realization=k, drop=True), rh).expand_dims(
                       realization=hk["realization"].values).transpose("realization", ...)
                   if member else _no_accurate(summary, spec.accurate[0]))
            summary = xr.merge([summary, acc], compat="override", combine_attrs="drop_conflicts")
        if flag:  # the summary saw the extended grid; the stored curves stay on the common grid
            keep = np.isin(curves.distance.values, grid)
            curves = curves.isel(distance=np.flatnonzero(keep))
        if "pressure" in curves:
            deep.append(np.asarray(curves["pressure"].isel(distance=0).transpose("realization", "rh").values < 0)[0])
        parts.append(xr.merge([curves, summary], compat="override", combine_attrs="drop_conflicts"))
        extended.append(flag)
    ds = parts[0] if len(parts) == 1 else xr.concat(
        parts, "realization", data_vars="minimal", coords="minimal", compat="override",
        combine_attrs="drop_conflicts")
    ds["max_height"] = top.assign_attrs(ATTRS["max_height"])
    ds["grid_extension"] = xr.DataArray(
        np.array(extended, dtype=np.int8), dims="realization",
        attrs={"long_name": "distance grid extended for this realization (Γ, pull-off, d_eq)",
               "units": "1", "flag_masks": np.array([1, 2], dtype=np.int8),
               "flag_meanings": "extended_below_the_floor extended_above_the_top"})
    if deep:
        ds["attractive_at_floor"] = xr.DataArray(
            np.array(deep), dims=("realization", "rh"),
            attrs={"long_name": "mean pressure attractive again at the bottom of the grid, below "
                                "the outermost stable equilibrium (deep contact of merged asperities)",
                   "units": "1"})
    out = {}
    for name, var in ds.data_vars.items():
        order = [d for d in _CURVE_DIMS if d in var.dims] + [d for d in var.dims if d not in _CURVE_DIMS]
        out[name] = var.transpose(*order)
    res = xr.Dataset(out).drop_vars([c for c in ds.coords if c not in ("realization", "rh", "distance")],
                                    errors="ignore")
    res = res.assign_coords(realization=np.arange(start, stop), rh=spec.rh[rh_lo:rh_hi],
                            distance=spec.distance)
    for c in ("realization", "rh", "distance"):
        res[c].attrs = dict(ATTRS[c])
    return res


# ============================================================================ lazy assembly
def _template(spec: Spec) -> xr.Dataset:
    """One block of the pipeline run on a tiny synthetic egg-box surface: the variables, their dims
    and dtypes that the stage functions return (they may be user-supplied, so they are probed).

    The egg-box is no surface of the run and a model may refuse it (GW: its single ring of
    wavevectors is below Nayak's bandwidth bound on a 16-pixel map), which says nothing about the
    user's input: then realization 0 of the run itself is the probe (the same model on the same
    kind of surface, so the same variables), and only its errors reach the user.
    """
    n = 16
    x = np.arange(n) * 2 * np.pi / 8
    sigma = math.sqrt(max(_psd_m0(spec.psd), 1e-30))
    z = 2 * sigma * np.sin(x)[None, :] * np.sin(x)[:, None]
    h = make_topography(z, spacing=spec.spacing, periodic=True).expand_dims(realization=[0])
    h.attrs["periodic"] = 1
    probe = dataclasses.replace(spec, generate=lambda *a, **k: h)
    for attempt in (probe, dataclasses.replace(probe, distance=spec.distance + 10 * sigma)):
        try:
            return compute_block(attempt, 0, 1, 0, 1)
        except Exception:  # noqa: BLE001 - a synthetic surface's failure is not the user's
            continue
    return compute_block(spec, 0, 1, 0, 1)


def _map_block(index: xr.Dataset, spec: Spec) -> xr.Dataset:
    """``xarray.map_blocks`` kernel: the block of the realizations and humidities of ``index``."""
    r = index["realization"].values
    lo = int(np.flatnonzero(spec.rh == index["rh"].values[0])[0])
    return compute_block(spec, int(r[0]), int(r[-1]) + 1, lo, lo + index.sizes["rh"])


def lazy_ensemble(spec: Spec, start: int, stop: int) -> xr.Dataset:
    """Realizations ``[start, stop)`` of ``spec`` as one lazy Dataset: ``xarray.map_blocks`` of
    :func:`compute_block` over the (realization, rh) blocks, with a template whose variables come
    from :func:`_template` and whose coordinates carry the attributes of
    :data:`roughstick._core.conventions.ATTRS`."""
    probe = _template(spec)
    rchunks = tuple(b - a for _, a, b in spec.realization_blocks(start, stop))
    hchunks = tuple(hi - lo for _, lo, hi in spec.rh_blocks())
    chunks = {"realization": rchunks, "rh": hchunks}
    sizes = {"realization": stop - start, "rh": spec.rh.size, "distance": spec.distance.size}
    coords = {
        "realization": ("realization", np.arange(start, stop), dict(ATTRS["realization"])),
        "rh": ("rh", spec.rh, dict(ATTRS["rh"])),
        "distance": ("distance", spec.distance, dict(ATTRS["distance"])),
    }
    template = xr.Dataset(
        {name: xr.Variable(var.dims,
                           dsa.zeros(tuple(sizes.get(d, var.sizes[d]) for d in var.dims),
                                     chunks=tuple(chunks.get(d, -1) for d in var.dims), dtype=var.dtype),
                           attrs=dict(var.attrs))
         for name, var in probe.data_vars.items()},
        coords=coords,
    )
    index = xr.Dataset(
        {"block": (("realization", "rh"), dsa.zeros((stop - start, spec.rh.size), chunks=(rchunks, hchunks)))},
        coords={k: v for k, v in coords.items() if k != "distance"},
    )
    return xr.map_blocks(_map_block, index, args=[spec], template=template)


def _attrs(spec: Spec, n) -> dict:
    layer = spec.adsorbed_layer if isinstance(spec.adsorbed_layer, str) else _callable_id(spec.adsorbed_layer)
    return dataset_attrs(
        "Monte Carlo ensemble of rough-surface humid adhesive contact (paper section 4.3)",
        references=REFERENCES,
        seed=str(spec.seed.entropy),
        seed_spawn_key=json.dumps(list(spec.seed.spawn_key)),
        n_realizations=int(n),
        surface_shape=json.dumps(list(spec.shape)),
        surface_size_m=json.dumps([s * spec.spacing for s in spec.shape]),
        spacing_m=spec.spacing,
        psd_m0_m2=_psd_m0(spec.psd),
        adsorbed_layer=layer,
        material=repr(spec.material),
        contact_function=_callable_id(spec.curves),
        surface_function=_callable_id(spec.generate),
        summary_function=_callable_id(spec.summary),
        realization_chunk=spec.chunk,
        rh_chunk=spec.rh_chunk,
        params_hash=spec.token,
        summary_grid=(OWN_GRID_NOTE if _own_grid_capable(spec) else
                      "summaries on the common distance grid (given distances or a custom "
                      "contact function)"),
        **({} if not spec.accurate else {
            "accurate_model": spec.accurate[0], "n_accurate": len(spec.accurate[1]),
            "multifidelity": MULTIFIDELITY_NOTE.format(model=spec.accurate[0],
                                                       n=len(spec.accurate[1]), total=int(n))}),
    )


MULTIFIDELITY_NOTE = (
    "every realization runs the cheap contact model (contact_function); the {n} of {total} "
    "realizations of a permutation drawn from the seed alone also run the accurate model "
    "({model}): <name>_accurate, NaN elsewhere. roughstick.ensemble.confidence_band combines them "
    "into the accurate model's band (cross-fitted two-phase difference estimator, "
    "roughstick.ensemble.multifidelity)")
