"""Measured validity of the rough-surface models, per surface, from dimensionless groups.

The paper validates the modified DMT (Eq. 16) on a single sphere only (Table 1). The table
``roughstick/data/validity_map.csv`` holds the relative error of the models (Greenwood-Williamson,
Eq. 14; modified DMT, Eq. 16; the FFT boundary-element model) against the boundary-element
reference on seeded maps of five surface families, two contact moduli and four humidities
(docs/accuracy.md: how it was measured, and its command).

A surface is placed in that table by its dimensionless groups (:func:`surface_groups`). The
study found (docs/accuracy.md) that the modified DMT's error is decided by

- the capillary pressure over the elastic stiffness of the roughness, :math:`|\\Delta P| /
  (E^* \\sqrt{\\langle|\\nabla z|^2\\rangle})` (how far the tension pulls the surfaces into
  contact: the contact fraction at equilibrium scales with it);
- the Maugis parameter of the mean summit, :math:`\\lambda = 2\\sigma_0 (R/(\\pi\\omega K^2))^{1/3}`
  with :math:`\\sigma_0 = |\\Delta P|`, :math:`\\omega = |\\Delta P| h_{water}`, :math:`R` from
  :math:`m_4` (Table 4): how much the tension deforms the asperities (assumption i of Eq. 16);
- the water height over the rms roughness, :math:`h_{water}/\\sigma`.

:func:`model_error` bounds a model's error at a surface by its measured errors at the nearest
measured cases in those groups; :func:`select_model` picks the cheapest registered model whose
bound meets an accuracy; :func:`warn_if_outside_validity` warns where a model's bound exceeds it.
The pipeline (:func:`roughstick.contact.curves`, :mod:`.report`) uses them; the models do not.
"""

from __future__ import annotations

import contextlib
import contextvars
import csv
import functools
import warnings
from typing import NamedTuple

import numba as nb
import numpy as np
import xarray as xr

from ..._core.api import renamed_keywords
from ..._core.arguments import check_numbers
from ..._core.materials import POLYSILICON, Material, reduced_modulus
from ..._core.remedy import spell
from ..._core.validate import (
    MIN_MAP_PIXELS,
    ValidityWarning,
    as_length,
    check_has_roughness,
    external_stacklevel,
    grid_spacing,
    height_in_si,
)
from ...datasets import validity_map_path
from ...surface.generate import surface_filter
from .._model import MODELS, model_names
from ..meniscus import as_relative_humidity, laplace_pressure, water_height

__all__ = [
    "ValidityWarning",
    "ErrorBound",
    "surface_groups",
    "expected_surface_groups",
    "validity_map",
    "model_error",
    "select_model",
    "warn_if_outside_validity",
    "VALIDITY_BOUND",
]

#: Default accepted relative error (10 %).
VALIDITY_BOUND = 0.10
#: Groups that locate a surface in the validity table (log10, scaled by their spread there).
GROUP_FEATURES = ("pressure_ratio", "maugis_lambda", "hw_over_sigma")
#: Nearest measured cases whose largest error bounds a new case: for exchangeable cases the
#: largest of 19 exceeds a 20th with probability 19/20 (a one-sided 95 % prediction bound).
N_NEIGHBOURS = 19
_QUANTITIES = ("adhesive_energy", "pull_off_pressure", "equilibrium_distance")


class ErrorBound(NamedTuple):
    """Measured relative error of a model near a surface (see :func:`model_error`)."""

    median: float
    upper: float
    n: int
    reason: str


# ---------------------------------------------------------------------------------------------
# dimensionless groups


@nb.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _c(z, i, j, mean, dense):  # pragma: no cover - compiled
    return z[i, j] - mean if dense or np.isfinite(z[i, j]) else 0.0


@nb.njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc"})
def _centred_moments_kernel(z, dy, dx):  # pragma: no cover - compiled
    """``(mean, sigma, rms slope, m4)`` of one map (mean NaN: no finite pixel), two passes.

    Heights minus their mean over the finite pixels (NaN pixels: the mean); forward differences;
    m4 the mean of the squared second differences along x and y (halved sum); sigma the
    population rms. Sums reassociated (vectorised): the last bits may differ across CPUs.
    """
    ny, nx = z.shape
    total = 0.0
    count = 0
    for i in range(ny):
        for j in range(nx):
            if np.isfinite(z[i, j]):
                total += z[i, j]
                count += 1
    if count == 0:
        return np.nan, 0.0, 0.0, 0.0
    mean = total / count
    if count == ny * nx:
        return _moments_pass(z, mean, dy, dx, True)
    return _moments_pass(z, mean, dy, dx, False)


@nb.njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc"})
def _moments_pass(z, mean, dy, dx, dense):  # pragma: no cover - compiled
    ny, nx = z.shape
    s2 = gx2 = gy2 = cx2 = cy2 = 0.0
    for i in range(ny):
        for j in range(nx):
            a = _c(z, i, j, mean, dense)
            s2 += a * a
            if j + 1 < nx:
                b = _c(z, i, j + 1, mean, dense)
                gx2 += (b - a) * (b - a)
                if j + 2 < nx:
                    c = _c(z, i, j + 2, mean, dense) - 2.0 * b + a
                    cx2 += c * c
            if i + 1 < ny:
                b = _c(z, i + 1, j, mean, dense)
                gy2 += (b - a) * (b - a)
                if i + 2 < ny:
                    c = _c(z, i + 2, j, mean, dense) - 2.0 * b + a
                    cy2 += c * c
    sigma = np.sqrt(s2 / (ny * nx))
    slope = np.sqrt(gx2 / (ny * (nx - 1)) / dx**2 + gy2 / ((ny - 1) * nx) / dy**2)
    m4 = 0.5 * (cx2 / (ny * (nx - 2)) / dx**4 + cy2 / ((ny - 2) * nx) / dy**4)
    return mean, sigma, slope, m4


def _groups_kernel(z, dy, dx):
    """(sigma, rms slope, m4, correlation length) of one map (NaN pixels: mean-filled).

    The 1/e correlation length is read on the x-lag row of the autocorrelation, which is the
    sum over rows of each row's circular autocorrelation: one batch of 1-D real FFTs along x
    instead of a 2-D transform pair (same numbers, about a third of the cost).
    """
    z = np.ascontiguousarray(z, dtype=float)
    mean, sigma, slope, m4 = _centred_moments_kernel(z, dy, dx)
    if np.isnan(mean):
        raise ValueError("height has no finite pixel; the surface groups need heights.")
    zc = np.where(np.isfinite(z), z - mean, 0.0)
    power = (np.abs(np.fft.rfft(zc, axis=1)) ** 2).sum(axis=0)
    row = np.fft.irfft(power, n=z.shape[1])
    row = row / row[0] if row[0] > 0 else row
    row = row[: max(z.shape[1] // 2, 1)]
    below = np.nonzero(row < np.exp(-1))[0]
    corr = (below[0] if below.size else row.size) * dx
    return float(sigma), float(slope), float(m4), corr


def _maps(height):
    """Checked height, its (lead..., y, x) view (first map of a lazy stack), values, maps, lead
    dims and spacings."""
    height = height_in_si(height)
    # coordinate units other than m are converted (a map with x, y in nm has the same groups)
    dy, dx = (grid_spacing(height, c, min_pixels=MIN_MAP_PIXELS, purpose="the validity groups") for c in ("y", "x"))
    lead = [d for d in height.dims if d not in ("y", "x")]
    h = height.transpose(*lead, "y", "x")
    if h.chunks is not None:
        # a lazy stack: the groups of its first map stand for the stack (one map is computed)
        h = h.isel({d: [0] for d in lead}).compute()
    vals = np.asarray(h.values, dtype=float)
    check_has_roughness(vals)  # the groups divide by the rms height and slope
    flat = vals.reshape((-1, *vals.shape[-2:]))
    return height, h, vals, flat, lead, dy, dx


def surface_groups(
    height: xr.DataArray,
    *,
    relative_humidity,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    adsorbed_layer="paper",
) -> xr.Dataset:
    r"""Dimensionless groups that decide the modified DMT's error, per map and humidity.

    Parameters
    ----------
    height : xarray.DataArray
        Topography, dims ``(..., y, x)``, units length, uniform coordinates. For a lazy (dask)
        stack only its first map is computed, and its groups stand for the stack.
    relative_humidity : float or sequence
        RH fractions in (0, 1).
    material, material2 : Material
        The two bodies (:math:`E^*`, :math:`K = 4E^*/3`).
    adsorbed_layer : {"paper", "none"} or callable
        Water-height model of :func:`roughstick.contact.water_height`.

    Returns
    -------
    xarray.Dataset
        Over the leading dims of ``height`` and ``rh``: ``hw_over_sigma``
        (:math:`h_{water}/\sigma`), ``rms_slope`` (:math:`\sqrt{\langle|\nabla z|^2\rangle}`,
        forward differences), ``corr_over_L`` (1/e correlation length over the map side along
        x), ``dp_over_E`` (:math:`|\Delta P|/E^*`), ``pressure_ratio``
        (:math:`|\Delta P|/(E^*\,\mathrm{slope})`), ``maugis_lambda`` (Eq. 7 for the mean summit,
        :math:`R = 3\sqrt{\pi}/(8\sqrt{m_4})` as in Table 4), ``neck_pixels`` (the radius
        :math:`\sqrt{2 h_{water}/\kappa}` wetted around a summit of the rms mean curvature
        :math:`\kappa = \sqrt{2 m_4/3}`, in pixels of the larger side; below
        :data:`roughstick.contact.RESOLVED_NECK_PIXELS` the pixel does not resolve Γ,
        :func:`roughstick.contact.warn_if_unresolved`) and ``sigma`` [m].

    Examples
    --------
    >>> h = rs.testing.sphere_topography(200e-9, n=33, spacing=2e-9)
    >>> g = rs.contact.surface_groups(h, relative_humidity=[0.3, 0.9])
    >>> sorted(g.data_vars)[:3]
    ['corr_over_L', 'dp_over_E', 'hw_over_sigma']
    """
    height, h, vals, flat, lead, dy, dx = _maps(height)
    per = np.array([_groups_kernel(m, dy, dx) for m in flat])
    shape = vals.shape[:-2]
    sigma, slope, m4, corr = (per[:, i].reshape(shape) for i in range(4))
    coords = {c: h[c] for c in lead if c in h.coords}
    return _groups_dataset(sigma, slope, m4, corr / (height.sizes["x"] * dx), lead, coords,
                           relative_humidity, material, material2, adsorbed_layer, max(dx, dy))


def _group_arrays(sigma, slope, m4, rh1, material, material2, adsorbed_layer):
    """hw, |dP|, E*, pressure ratio and Maugis lambda over (maps..., rh)."""
    hw = np.asarray(water_height(rh1, adsorbed_layer=adsorbed_layer).values, dtype=float)
    dp = np.abs(np.asarray(laplace_pressure(rh1).values, dtype=float))
    e_star = reduced_modulus(material, material2)
    radius = 3 * np.sqrt(np.pi) / (8 * np.sqrt(m4))
    K = 4.0 / 3.0 * e_star
    ex = (...,) + (None,)
    lam = 2 * dp / (np.pi * dp * hw * K**2 / radius[ex]) ** (1 / 3)
    return hw, dp, e_star, dp / (e_star * slope[ex]), lam


def _neck_radius(hw, m4):
    """Wetted radius sqrt(2 h_water / kappa) [m] around a summit of the rms mean curvature
    kappa = sqrt(2 m4 / 3) (isotropic maps: m4 = 3/8 <(Laplacian z)^2>)."""
    return np.sqrt(2 * hw / np.sqrt(2 * m4 / 3))


def _groups_dataset(sigma, slope, m4, corr_over_L, lead, coords, relative_humidity, material,
                    material2, adsorbed_layer, pixel) -> xr.Dataset:
    """The groups Dataset from per-map (sigma, rms slope, m4, correlation length / side)."""
    rh = as_relative_humidity(relative_humidity)
    rh1 = rh if rh.ndim == 1 else rh.expand_dims(rh=[float(rh.values)])
    hw, dp, e_star, pressure_ratio, lam = _group_arrays(sigma, slope, m4, rh1, material, material2,
                                                    adsorbed_layer)
    ex = (...,) + (None,)
    dims = (*lead, "rh")
    coords = dict(coords)
    coords["rh"] = np.asarray(rh1.values, dtype=float)
    ds = xr.Dataset(
        {
            "hw_over_sigma": (dims, hw / sigma[ex]),
            "rms_slope": (lead, slope),
            "corr_over_L": (lead, corr_over_L),
            "dp_over_E": (("rh",), dp / e_star),
            "pressure_ratio": (dims, pressure_ratio),
            "maugis_lambda": (dims, lam),
            "neck_pixels": (dims, _neck_radius(hw, m4[ex]) / pixel),
            "sigma": (lead, sigma, {"units": "m", "long_name": "rms height"}),
        },
        coords=coords,
    )
    for v in ds.data_vars:
        ds[v].attrs.setdefault("units", "1")
    if rh.ndim == 0:
        ds = ds.squeeze("rh")
    ds.attrs["reduced_modulus"] = e_star
    return ds


def expected_surface_groups(
    psd: xr.DataArray,
    *,
    shape,
    spacing: float,
    relative_humidity,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    adsorbed_layer="paper",
) -> xr.Dataset:
    r"""The groups of :func:`surface_groups` expected over surfaces generated from a PSD.

    No surface is generated: the PSD on the target grid (:func:`roughstick.surface.surface_filter`,
    Eqs. 33-34) gives each estimator's expectation, with the forward-difference transfer
    functions the map estimators use: :math:`\sigma^2 = \sum w`,
    :math:`\langle|\nabla z|^2\rangle = \sum w\,(k_x^2 + k_y^2)`,
    :math:`m_4 = \tfrac12\sum w\,(k_x^4 + k_y^4)` with
    :math:`k = 2\sin(q\Delta/2)/\Delta` and :math:`w` the variance of each mode; the 1/e
    correlation length from :math:`\sum w\cos(q_x\ell)`. This is how an ensemble is checked
    once, before its graph is built (:func:`roughstick.ensemble.run`).

    Parameters
    ----------
    psd : xarray.DataArray
        2-D ``(qy, qx)`` or isotropic ``(q)`` PSD, as for :func:`roughstick.generate_surfaces`.
    shape : int or (int, int)
        Surface shape ``(ny, nx)`` in pixels.
    spacing : float or str
        Pixel size [m], or with its unit (``"5 nm"``).
    relative_humidity, material, material2, adsorbed_layer
        As in :func:`surface_groups`.

    Returns
    -------
    xarray.Dataset
        The variables of :func:`surface_groups` over ``rh``.
    """
    shp = (int(shape), int(shape)) if np.ndim(shape) == 0 else tuple(int(v) for v in shape)
    spacing = as_length(spacing, name="spacing")
    f = surface_filter(psd, shape=shp, spacing=spacing)
    qy = np.asarray(f["qy"].values, dtype=float)
    qx = np.asarray(f["qx"].values, dtype=float)
    dq = (2 * np.pi / (shp[0] * spacing)) * (2 * np.pi / (shp[1] * spacing))
    w = np.asarray(f.transpose("qy", "qx").values, dtype=float) * dq
    ky2 = (2 * np.sin(qy * spacing / 2) / spacing)[:, None] ** 2
    kx2 = (2 * np.sin(qx * spacing / 2) / spacing)[None, :] ** 2
    m0 = float(w.sum())
    slope = float(np.sqrt((w * (kx2 + ky2)).sum()))
    m4 = float(0.5 * (w * (kx2**2 + ky2**2)).sum())
    wx = w.sum(axis=0)
    lags = np.arange(max(shp[1] // 2, 1))
    acf = np.cos(np.outer(lags * spacing, qx)) @ wx / m0
    below = np.nonzero(acf < np.exp(-1))[0]
    corr_over_L = (below[0] if below.size else lags.size) / shp[1]
    return _groups_dataset(np.asarray(np.sqrt(m0)), np.asarray(slope), np.asarray(m4),
                           np.asarray(corr_over_L), [], {}, relative_humidity, material,
                           material2, adsorbed_layer, spacing)


# ---------------------------------------------------------------------------------------------
# the measured table


@functools.lru_cache(maxsize=1)
def validity_map() -> dict[str, np.ndarray]:
    """The measured error table (``roughstick/data/validity_map.csv``) as a dict of arrays.

    One row per (map, humidity, modulus, method): ``family``, ``map_index``, ``pixels``,
    ``reduced_modulus`` [Pa], ``rh``, ``method`` (``gw``, ``modified_dmt``, ``fft_bem``),
    ``reference`` (``bem``: Tamaas on the same grid; ``fft_bem_fine``: the FFT model at
    tolerance 1e-4, validated against Tamaas, used for the maps beyond the Tamaas runs), the
    groups of :func:`surface_groups`, the relative errors ``error_adhesive_energy``,
    ``error_pull_off_pressure``, ``error_equilibrium_distance`` and ``converged`` (0: no
    equilibrium on the grid, the error is not a number and counts as unbounded). Written by
    ``python benchmarks/bench_accuracy.py`` (docs/accuracy.md).
    """
    path = validity_map_path()
    if not path.is_file():
        raise FileNotFoundError(
            f"the measured validity map {path} is missing; regenerate it with "
            "python benchmarks/bench_accuracy.py (needs the 'bem' extra)."
        )
    with path.open("r", encoding="utf-8") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    if not rows:
        raise RuntimeError(f"{path} holds no rows; regenerate it with benchmarks/bench_accuracy.py")
    out: dict[str, np.ndarray] = {}
    for key in rows[0]:
        vals = [r[key] for r in rows]
        try:
            out[key] = np.array([float(v) if v != "" else np.nan for v in vals])
        except ValueError:
            out[key] = np.array(vals)
    return out


def _features(values: dict) -> np.ndarray:
    return np.column_stack([np.log10(np.asarray(values[f], dtype=float)) for f in GROUP_FEATURES])


def _prepare(table: dict, method: str):
    """Search structure of ``method``'s rows of a validity table (dict of arrays)."""
    sel = table["method"] == method
    if not np.any(sel):
        return None
    scale = np.nanstd(_features({f: table[f] for f in GROUP_FEATURES}), axis=0)
    scale = np.where(scale > 0, scale, 1.0)
    Xs = _features({f: table[f][sel] for f in GROUP_FEATURES}) / scale
    conv = table["converged"][sel] == 1
    errs = {}
    for q in _QUANTITIES:
        e = np.abs(np.asarray(table[f"error_{q}"][sel], dtype=float))
        errs[q] = np.where(conv & np.isfinite(e), e, np.inf)
    # typical distance from a measured case to its N_NEIGHBOURS-th neighbour: a query farther
    # than twice that from its own neighbours lies outside the measured range
    k = min(N_NEIGHBOURS, len(Xs) - 1)
    dd = np.sqrt(((Xs[:, None, :] - Xs[None, :, :]) ** 2).sum(-1))
    kth = np.sort(dd, axis=1)[:, k] if k > 0 else np.zeros(len(Xs))
    return dict(X=Xs, scale=scale, errors=errs, reach=2.0 * float(np.median(kth)),
                family=np.asarray(table["family"])[sel])


@functools.lru_cache(maxsize=8)
def _table_for(method: str):
    return _prepare(validity_map(), method)


def _bound(tab, groups, quantity="adhesive_energy") -> ErrorBound:
    """Error bound at ``groups`` from a prepared table (see :func:`model_error`)."""
    x = _features({f: [float(groups[f])] for f in GROUP_FEATURES})[0] / tab["scale"]
    if not np.all(np.isfinite(x)):
        return ErrorBound(np.nan, np.inf, 0, "groups not finite (flat map?)")
    d = np.sqrt(((tab["X"] - x) ** 2).sum(-1))
    order = np.argsort(d)[:N_NEIGHBOURS]
    qs = _QUANTITIES if quantity == "all" else (quantity,)
    e = np.max(np.stack([tab["errors"][q][order] for q in qs]), axis=0)
    fams = ", ".join(sorted(set(tab["family"][order].tolist())))
    if d[order[-1]] > tab["reach"]:
        return ErrorBound(
            float(np.median(e)), np.inf, int(order.size),
            f"outside the measured range of the groups (nearest measured cases: {fams})",
        )
    upper = float(e.max())
    what = "error of " + ("Γ, pull-off and d_eq" if quantity == "all" else quantity)
    return ErrorBound(
        float(np.median(e)), upper, int(order.size),
        f"measured {what}: median {np.median(e):.1%}, largest "
        f"{'unbounded (no equilibrium)' if np.isinf(upper) else format(upper, '.1%')} over the "
        f"{order.size} nearest measured maps ({fams}) in "
        + ", ".join(f"{f} = {float(groups[f]):.3g}" for f in GROUP_FEATURES),
    )


def model_error(method: str, groups, *, quantity: str = "adhesive_energy") -> ErrorBound:
    """Measured relative error of ``method`` at a surface with these groups.

    The error is bounded by the largest error of the :data:`N_NEIGHBOURS` measured cases nearest
    to ``groups`` (log10 of :data:`GROUP_FEATURES`, each scaled by its spread over the table):
    for exchangeable cases that is a one-sided 95 % prediction bound on the error of this one.
    A case without an equilibrium on the measurement grid counts as unbounded; a surface farther
    from its neighbours than twice the table's typical spacing is outside the measured range and
    gets an infinite bound.

    Parameters
    ----------
    method : {"gw", "modified_dmt", "fft_bem", "bem"}
        ``"bem"`` is the reference: error 0 by definition.
    groups : mapping or xarray.Dataset
        Scalar values of :data:`GROUP_FEATURES` (one map, one humidity), e.g.
        ``surface_groups(h, relative_humidity=0.7)``.
    quantity : {"adhesive_energy", "pull_off_pressure", "equilibrium_distance", "all"}
        Summary whose error is bounded (``"all"``: the largest of the three).

    Returns
    -------
    ErrorBound
        ``median`` and ``upper`` relative errors of the neighbours, their number ``n`` and a
        ``reason`` quoting the cases used.
    """
    if method not in MODELS:
        raise ValueError(f"method must be one of {model_names()}, got {method!r}.")
    if quantity not in (*_QUANTITIES, "all"):
        raise ValueError(f"quantity must be one of {(*_QUANTITIES, 'all')}, got {quantity!r}.")
    if MODELS[method].reference:
        return ErrorBound(0.0, 0.0, 0, "the boundary-element reference itself")
    try:
        tab = _table_for(method)
    except FileNotFoundError:
        return ErrorBound(np.nan, np.inf, 0, "the measured validity map is not installed")
    if tab is None:
        return ErrorBound(np.nan, np.inf, 0, f"{method} was not measured")
    return _bound(tab, groups, quantity)


_SHARED = contextvars.ContextVar("roughstick_shared_groups", default=None)


@contextlib.contextmanager
def shared_groups():
    """Within this block, the groups of a map are computed once for the trust checks that ask
    for them with the same arguments (the same objects): the checks of one contact call."""
    token = _SHARED.set({})
    try:
        yield
    finally:
        _SHARED.reset(token)


def _shared(key, args, compute):
    """``compute()``, or its result for the same ``args`` (by identity) within
    :func:`shared_groups`."""
    memo = _SHARED.get()
    if memo is None:
        return compute()
    hit = memo.get(key)
    if hit is not None and len(hit[0]) == len(args) and all(a is b for a, b in zip(hit[0], args)):
        return hit[1]
    out = compute()
    memo[key] = (args, out)  # the arguments are kept alive: their ids stay theirs
    return out


def map_moments(height):
    """:func:`_maps` of ``height`` and the ``(mean, sigma, rms slope, m4)`` of each map (rows)."""
    def compute():
        _, h, vals, flat, lead, dy, dx = _maps(height)
        per = np.array([_centred_moments_kernel(np.ascontiguousarray(m), dy, dx) for m in flat])
        return h, vals, flat, lead, dy, dx, per
    return _shared("moments", (height,), compute)


def _group_points(height, relative_humidity, material, material2, adsorbed_layer, groups=None):
    """Per-humidity list of group dicts, worst map of a stack first-class (all maps checked).
    Without ``groups``: the features of :func:`surface_groups` (same kernel and formulas, same
    bits) without its correlation length (not a feature) nor a Dataset."""
    if groups is None:
        return _shared("points", (height, relative_humidity, material, material2, adsorbed_layer),
                       lambda: _points_of_map(height, relative_humidity, material, material2,
                                              adsorbed_layer))
    return _points_of_groups(groups)


def _points_of_map(height, relative_humidity, material, material2, adsorbed_layer):
    _, vals, flat, _, dy, dx, per = map_moments(height)
    if np.isnan(per[:, 0]).any():
        raise ValueError("height has no finite pixel; the surface groups need heights.")
    sigma, slope, m4 = (per[:, i].reshape(vals.shape[:-2]) for i in (1, 2, 3))
    rh = as_relative_humidity(relative_humidity)
    rh1 = rh if rh.ndim == 1 else rh.expand_dims(rh=[float(rh.values)])
    hw, _, _, ratio, lam = _group_arrays(sigma, slope, m4, rh1, material, material2, adsorbed_layer)
    feats = {"pressure_ratio": ratio, "maugis_lambda": lam, "hw_over_sigma": hw / sigma[..., None]}
    table = [np.asarray(feats[f], dtype=float).reshape(-1, hw.size) for f in GROUP_FEATURES]
    return _points(table, np.asarray(rh1.values, dtype=float))


def _points_of_groups(g):
    if "rh" not in g.dims:
        g = g.expand_dims(rh=[float(g["rh"])] if "rh" in g.coords else [np.nan])
    arrs = xr.broadcast(*(g[f] for f in GROUP_FEATURES))
    lead = [d for d in arrs[0].dims if d != "rh"]
    table = [np.asarray(a.transpose(*lead, "rh").values, dtype=float).reshape(-1, g.sizes["rh"])
             for a in arrs]
    return _points(table, g["rh"].values)


def _points(table, rh_values):
    return [(float(r), [{f: float(t[i, j]) for f, t in zip(GROUP_FEATURES, table)}
                        for i in range(table[0].shape[0])])
            for j, r in enumerate(rh_values)]


class NoModelMeetsAccuracy(ValueError):
    """No model allowed to :func:`select_model` meets the accuracy on this surface."""


@renamed_keywords(tolerance="accuracy")
@check_numbers(accuracy="positive")
def select_model(
    height: xr.DataArray,
    *,
    relative_humidity,
    accuracy: float = VALIDITY_BOUND,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    adsorbed_layer="paper",
    quantity: str = "adhesive_energy",
    candidates=None,
    groups: xr.Dataset | None = None,
) -> tuple[str, str]:
    """Cheapest model whose measured error bound at this surface meets ``accuracy``.

    Candidates go from the cheapest (the cost ranks of the contact-model registry,
    :data:`roughstick.contact.MODELS`); each humidity and each map of a stack must pass; the
    reference (``"bem"``) always does.

    Parameters
    ----------
    height : xarray.DataArray or None
        The surface (its groups are computed, :func:`surface_groups`); ``None`` with ``groups``.
    relative_humidity : float or sequence
        RH fractions in (0, 1).
    accuracy : float, default 0.10
        Accepted relative error of ``quantity`` against the BEM, > 0.
    material, material2, adsorbed_layer
        As in :func:`roughstick.contact.curves`.
    quantity : {"adhesive_energy", "pull_off_pressure", "equilibrium_distance", "all"}
        Summary the accuracy applies to.
    candidates : sequence of str, optional
        Models allowed (default: every registered model with a cost rank).
    groups : xarray.Dataset, optional
        Precomputed groups (e.g. :func:`expected_surface_groups` of a PSD, to choose once for an
        ensemble) instead of those of ``height``.

    Returns
    -------
    (str, str)
        The model and the reason (its bound, and why the cheaper ones failed).
    """
    if not accuracy > 0:
        raise ValueError(f"accuracy must be a positive relative error, got {accuracy!r}.")
    ranked = [m for m in model_names() if MODELS[m].cost_rank is not None]
    candidates = tuple(ranked if candidates is None else candidates)
    points = _group_points(height, relative_humidity, material, material2, adsorbed_layer, groups)
    notes = []
    for method in [m for m in ranked if m in candidates]:
        worst = None
        for r, maps in points:
            for gr in maps:
                b = model_error(method, gr, quantity=quantity)
                if worst is None or not (b.upper <= worst[1].upper):
                    worst = (r, b)
        r, b = worst
        if b.upper <= accuracy:
            return method, (
                f"{method}: upper bound of the {quantity} error {b.upper:.1%} <= accuracy "
                f"{accuracy:.0%} at RH {r:.2f} ({b.reason})"
                + ("; rejected: " + "; ".join(notes) if notes else "")
            )
        notes.append(f"{method} bound "
                     f"{'unbounded' if np.isinf(b.upper) else format(b.upper, '.1%')} at RH {r:.2f}")
    raise NoModelMeetsAccuracy(
        f"no allowed model ({', '.join(candidates)}) meets the accuracy {accuracy:.0%} on "
        "this surface: " + "; ".join(notes) + ". Raise the accuracy or allow the "
        "boundary-element models."
    )


@renamed_keywords(tolerance="accuracy")
@check_numbers(accuracy="positive")
def warn_if_outside_validity(
    height: xr.DataArray,
    *,
    relative_humidity,
    model: str = "modified_dmt",
    accuracy: float = VALIDITY_BOUND,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    adsorbed_layer="paper",
    quantity: str = "adhesive_energy",
    stacklevel: int | None = None,
    groups: xr.Dataset | None = None,
) -> bool:
    """Warn if the measured error bound of ``model`` at this surface exceeds ``accuracy``.

    ``groups`` (e.g. :func:`expected_surface_groups` of an ensemble's PSD) replaces the groups of
    ``height``, which may then be None.

    The warning names the remedy that exists, ``model="auto"`` with the accuracy, spelled where
    the user is (:mod:`roughstick._core.remedy`: the argument of the function called from
    Python, ``--model auto --accuracy ...`` in ``roughstick curves``, the ``contact_model``
    key of a configuration file); it points at the first frame outside roughstick (and outside
    dask/xarray), i.e. the user's line. Python's default filter shows it once per line and
    message.

    Returns
    -------
    bool
        True when the bound exceeds the accuracy (warned).
    """
    points = _group_points(height, relative_humidity, material, material2, adsorbed_layer,
                           groups=groups)
    worst = None
    for r, maps in points:
        for gr in maps:
            b = model_error(model, gr, quantity=quantity)
            if worst is None or not (b.upper <= worst[1].upper):
                worst = (r, b)
    if worst is None or worst[1].upper <= accuracy:
        return False
    r, b = worst
    bound = ("an amount the measurements cannot bound" if np.isinf(b.upper)
             else f"up to {b.upper:.0%}")
    ranked = [m for m in model_names() if MODELS[m].cost_rank is not None]
    costlier = ranked[ranked.index(model) + 1:] if model in ranked else ranked
    better = next((m for m in costlier if all(model_error(m, gr, quantity=quantity).upper <= accuracy
                                              for _, maps in points for gr in maps)),
                  next((m for m in ranked if MODELS[m].reference), "bem"))
    warnings.warn(
        f"{model} may be off by {bound} (> accuracy {accuracy:.0%}) on the {quantity} of this "
        f"surface at RH {r:.2f}: {b.reason}. Remedy: {spell('contact_model', 'auto', accuracy=accuracy)} "
        f"picks the cheapest model measured within the accuracy (here {spell('contact_model', better)}). "
        "See docs/accuracy.md.",
        ValidityWarning,
        stacklevel=external_stacklevel() if stacklevel is None else stacklevel,
    )
    return True
