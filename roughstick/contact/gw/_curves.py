r"""Greenwood–Williamson statistical rough contact from (m0, m2, m4) (paper §3.2, Eq. 14).

An isotropic Gaussian surface with Nayak's one-direction spectral moments :math:`m_0, m_2, m_4`
has :math:`N = m_4 / (6\pi\sqrt3\, m_2)` summits (local maxima) per unit area. Each summit is
replaced by a sphere of radius :math:`R = 1/\kappa` (:math:`\kappa` its geometric-mean curvature)
and the summit forces are summed with the joint density of summit height and curvature
(no interaction between summits, no merging of menisci):

.. math:: F^S(d) = N \int_{-\infty}^{h_{\max}} \int_{\kappa_{\min}}^{\kappa_{\max}}
          F^a(h - d, 1/\kappa)\, \rho(h, \kappa)\, d\kappa\, dh .   \qquad (14)

Functions
---------
:func:`roughstick.surface.summit_density`
    :math:`N` from a moments Dataset (in :mod:`roughstick.surface.moments`).
:func:`summit_joint_density`
    The joint density :math:`\rho(h, \kappa)` of summit height and curvature.
:func:`gw_curves`
    Force–distance curves over ``(..., rh, distance)`` in the layout of the rough-surface
    modified DMT (:func:`roughstick.contact.curves`), so both plot side by side and
    :func:`roughstick.contact.summary` applies to either.
:func:`gw_cutoff_study`
    The same curves for a list of height cutoffs (the paper's Fig. 9).

References
----------
Nayak, P. R. (1971). Random process model of rough surfaces. J. Lubr. Technol. 93, 398-407.
https://doi.org/10.1115/1.3451608

Greenwood, J. A., Williamson, J. B. P. (1966). Contact of nominally flat surfaces.
Proc. R. Soc. Lond. A 295, 300-319. https://doi.org/10.1098/rspa.1966.0242

Greenwood, J. A. (2006). A simplified elliptic model of rough surface contact. Wear 261, 191-200.
https://doi.org/10.1016/j.wear.2005.09.031
"""

from __future__ import annotations

import numbers

import numpy as np
import xarray as xr

from ..._core.arguments import check_numbers
from ..._core.dask import is_lazy
from ..._core.materials import POLYSILICON, Material
from ..._core.progress import estimate_model_seconds
from ..._core.references import PAPER, cite
from ..._core.validate import height_in_si, moments_si
from ...surface.moments import roughness_moments, summit_density
from .._model import ContactModel, Grid, options_of, register_model
from .._pipeline import apply
from ._kernels import (
    _VARS,
    _XI_BOTTOM,
    _XI_TOP,
    CURVATURE_MEASURES,
    _check_moments_np,
    _gauss,
    _gw_block,
    _log_density,
)

__all__ = ["summit_joint_density", "gw_curves", "gw_cutoff_study", "MODEL"]

REFERENCES = cite("nayak1971", "greenwood1966", "greenwood2006", (PAPER, "Eq. 14"))

#: Sphere models accepted per summit (``force_kernel`` of :mod:`roughstick.contact.sphere`).
SPHERE_MODELS = ("modified_dmt", "dmt", "maugis", "hertz")


def summit_joint_density(height, curvature, *, moments: xr.Dataset, curvature_measure="geometric"):
    r"""Joint probability density :math:`\rho(h, \kappa)` of summit height and curvature.

    Normalised so that :math:`\int_{-\infty}^{\infty}\int_0^\infty \rho\, d\kappa\, dh = 1`;
    :math:`N\rho` is the number of summits per unit area, height and curvature (Eq. 14).

    Parameters
    ----------
    height : float, array or xarray.DataArray
        Summit height h above the mean plane [m] (DataArrays need length ``units``).
    curvature : float, array or xarray.DataArray
        Summit curvature :math:`\kappa` [m-1] (plain values, SI).
    moments : xarray.Dataset
        ``m0``, ``m2``, ``m4`` (eager; the density is for plotting and checks).
    curvature_measure : {"geometric", "mean"}, default "geometric"
        :math:`\kappa = \sqrt{\kappa_1 \kappa_2}` (the sphere of equal Hertz load, Greenwood 2006,
        used by the paper) or Nayak's mean curvature :math:`(\kappa_1 + \kappa_2)/2`.

    Returns
    -------
    xarray.DataArray
        :math:`\rho` per unit height [m-1] and per unit curvature [m], so units "1";
        broadcast over the inputs' dims.

    Notes
    -----
    With :math:`\xi = h/\sqrt{m_0}`, :math:`t = \kappa/\sqrt{m_4}` and the bandwidth
    :math:`\alpha = m_0 m_4/m_2^2`, the geometric-curvature density is

    .. math:: \rho = \frac{9\sqrt3\, t^3\, \phi(\xi)}{\sqrt{m_0 m_4}\sqrt{3 - 3/\alpha}}
              \exp\!\Big(\frac{3t^2}{2} - \frac{\xi^2}{2(\alpha-1)}\Big)
              \Phi\big((\mu' - t)\sqrt P\big),

    derived from the Kac–Rice count of local maxima as in Nayak (1971) (see the docs page
    ``docs/greenwood_williamson.md`` for the steps). Its height marginal has Nayak's mean
    :math:`4\sqrt{m_0/(\pi\alpha)}` and variance :math:`m_0(1 - 0.8968/\alpha)`.

    References
    ----------
    Nayak (1971), https://doi.org/10.1115/1.3451608;
    Greenwood (2006), https://doi.org/10.1016/j.wear.2005.09.031
    """
    m0, m2, m4 = moments_si(moments)
    if is_lazy(moments):
        raise ValueError("summit_joint_density needs eager moments: call moments.compute() first.")
    h = height_in_si(height) if isinstance(height, xr.DataArray) else xr.DataArray(
        np.asarray(height, dtype=float)
    )
    k = curvature if isinstance(curvature, xr.DataArray) else xr.DataArray(np.asarray(curvature, float))

    def kern(h_, k_, m0_, m2_, m4_):
        out = np.empty(np.broadcast(h_, k_, m0_, m2_, m4_).shape)
        hb, kb, a0, a2, a4 = np.broadcast_arrays(h_, k_, m0_, m2_, m4_)
        alpha = _check_moments_np(a0, a2, a4)
        for a in np.unique(alpha):
            sel = alpha == a
            out[sel] = np.exp(
                _log_density(hb[sel] / np.sqrt(a0[sel]), kb[sel] / np.sqrt(a4[sel]), a, curvature_measure)
            ) / np.sqrt(a0[sel] * a4[sel])
        return out

    out = xr.apply_ufunc(kern, h, k, m0, m2, m4)
    out.attrs = {"units": "1", "long_name": "joint density of summit height and curvature"}
    return out


# --------------------------------------------------------------------------------------------
# automatic distance grid
# --------------------------------------------------------------------------------------------

# Walk step and margin below the equilibrium, in units of the smallest sqrt(m0): 1/16 resolves
# the narrowest attractive range met (RH 1e-6, water height ~0.1 nm on sqrt(m0) = 0.4 nm).
_AUTO_STEP = 1.0 / 16.0
_AUTO_MARGIN = 1.0
# |p| below this fraction of a curve's largest attraction counts as zero at the top of the grid
_AUTO_ZERO = 1e-6
# chord tolerances of the refinement, relative to the curve's largest attraction (intervals with
# an attractive end: Eq. 13, pull-off, equilibrium) or to its largest |p| (repulsive intervals)
_AUTO_CHORD = 2e-3
_AUTO_CHORD_REPULSIVE = 2e-2
_AUTO_MAX_POINTS = 2000


def _gw_pressure(args, distance, kw):
    """Mean pressure of every (moment set, humidity) at ``distance``: (n_curves, n_distance)."""
    out = _gw_block(*args, distance=distance, **kw)
    return out[..., 0].reshape(-1, np.size(distance))


def _split_widest(d, n):
    """Add midpoints of the widest intervals until ``d`` has ``n`` points (strictly increasing)."""
    while d.size < n:
        mids = 0.5 * (d[:-1] + d[1:])
        ok = np.flatnonzero((mids > d[:-1]) & (mids < d[1:]))
        if ok.size == 0:
            break
        pick = ok[np.argsort(-np.diff(d)[ok], kind="stable")[: n - d.size]]
        d = np.sort(np.concatenate([d, mids[pick]]))
    return d


def _gw_auto_distance(m0, m2, m4, dP, hw, kw, n=None):
    """Automatic distance grid of :func:`gw_contact_curves` (eager numpy inputs, SI).

    Walks down in steps of ``(sqrt(m0) + h_water)/16`` from ``xi_top sqrt(m0) + h_water`` (no
    summit is wet above it: the pressure is exactly zero) until every curve has turned repulsive
    below its attraction (its equilibrium) and ``sqrt(m0)`` further (a curve without attraction:
    down to the mean plane at least); drops the top points where every
    curve is still below 1e-6 of its largest attraction (the Gaussian tail of the summit
    heights); then halves every interval whose midpoint is off the chord of its ends.
    """
    args = [np.asarray(v, dtype=float) for v in np.broadcast_arrays(m0, m2, m4, dP, hw)]
    _check_moments_np(*args[:3])
    sig = np.sqrt(args[0])
    hw = np.maximum(args[4], 0.0)
    # the pressure varies on the scale of the summit heights and of the water height
    top = kw["xi_top"] * float(sig.max()) + float(hw.max())
    floor = _XI_BOTTOM * float(sig.max())
    # (moment sets of very different sqrt(m0): at most _AUTO_MAX_POINTS steps over the range)
    step = max(_AUTO_STEP * (float(sig.min()) + float(hw.min())), (top - floor) / _AUTO_MAX_POINTS)
    margin = _AUTO_MARGIN * float(sig.max())

    def bottom(dw, pw):
        """Lowest distance the grid needs, or None while a curve has not turned repulsive."""
        rep = pw > 0  # repulsive: below the equilibrium (or in contact without any attraction)
        if not rep.any(axis=1).all():
            return None
        first = np.argmax(rep, axis=1)
        attracted = np.array([(pw[i, :j] < 0).any() for i, j in enumerate(first)])
        # past the equilibrium by the margin; a curve with no attraction at all (e.g. "hertz")
        # down to the mean plane, so that its contact is not only the summits' far tail
        return float(np.min(np.where(attracted, dw[first] - margin,
                                     np.minimum(dw[first] - margin, 0.0))))

    d_walk, p_walk, k, batch = [], [], 0, 64
    while True:
        dd = top - step * np.arange(k, k + batch)
        dd = dd[dd >= floor]
        if dd.size == 0:
            break
        d_walk.append(dd)
        p_walk.append(_gw_pressure(args, dd, kw))
        k += batch
        dw, pw = np.concatenate(d_walk), np.concatenate(p_walk, axis=1)
        low = bottom(dw, pw)
        if low is not None and dw[-1] <= low:
            break
    dw, pw = np.concatenate(d_walk), np.concatenate(p_walk, axis=1)
    low = bottom(dw, pw)
    if low is not None:  # drop the walk below what the grid needs
        last = int(np.searchsorted(-dw, -low, side="right")) + 1
        dw, pw = dw[: max(last, 2)], pw[:, : max(last, 2)]
    attraction = np.maximum(-pw.min(axis=1), 0.0)
    magnitude = np.abs(pw).max(axis=1)
    scale = np.where(attraction > 0, attraction, magnitude)[:, None]
    nonzero = (np.abs(pw) > _AUTO_ZERO * scale).any(axis=0)
    if nonzero.any():
        start = max(int(np.argmax(nonzero)) - 1, 0)
        dw, pw = dw[start:], pw[:, start:]
    d, p = dw[::-1].copy(), pw[:, ::-1].copy()
    # chord refinement: candidates are the intervals created by the last split
    cand = np.arange(d.size - 1)
    tol_att = _AUTO_CHORD * np.where(attraction > 0, attraction, magnitude)[:, None]
    tol_rep = _AUTO_CHORD_REPULSIVE * magnitude[:, None]
    while cand.size and d.size < _AUTO_MAX_POINTS:
        mids = 0.5 * (d[cand] + d[cand + 1])
        ok = (mids > d[cand]) & (mids < d[cand + 1])
        cand, mids = cand[ok], mids[ok]
        cand, mids = cand[: _AUTO_MAX_POINTS - d.size], mids[: _AUTO_MAX_POINTS - d.size]
        if cand.size == 0:
            break
        pm = _gw_pressure(args, mids, kw)
        pa, pb = p[:, cand], p[:, cand + 1]
        err = np.abs(pm - 0.5 * (pa + pb))
        attractive = np.minimum(np.minimum(pa, pb), pm) < 0
        bad = (err > np.where(attractive, tol_att, tol_rep)).any(axis=0)
        order = np.argsort(np.concatenate([d, mids]), kind="stable")
        pos = np.empty(order.size, dtype=int)
        pos[order] = np.arange(order.size)
        d = np.concatenate([d, mids])[order]
        p = np.concatenate([p, pm], axis=1)[:, order]
        # the two halves of every interval off the chord are the next candidates
        at = pos[d.size - mids.size:][bad]  # positions of the new midpoints in the merged grid
        cand = np.sort(np.concatenate([at - 1, at]))
    if n is not None:
        d = _split_widest(d, int(n))
    return d


# --------------------------------------------------------------------------------------------
# public API
# --------------------------------------------------------------------------------------------


def _as_moments(moments, moment_method, qmax) -> xr.Dataset:
    if isinstance(moments, xr.DataArray):
        return roughness_moments(moments, method=moment_method, qmax=qmax)
    if isinstance(moments, xr.Dataset):
        if moment_method != "spline" or qmax is not None:
            raise ValueError(
                "moment_method and qmax choose how the moments of a height map are estimated; "
                "moments were given as a Dataset, so drop them."
            )
        return moments
    raise TypeError(
        "moments must be an xarray.Dataset with m0, m2, m4 (e.g. from roughstick.surface.fit_self_affine) "
        f"or a height DataArray (y, x); got {type(moments).__name__}."
    )


def _check_sphere_model(value):
    if value not in SPHERE_MODELS:
        raise ValueError(f"sphere_model must be one of {SPHERE_MODELS}, got {value!r}.")
    return value


def _check_curvature_measure(value):
    if value not in CURVATURE_MEASURES:
        raise ValueError(f"curvature_measure must be one of {CURVATURE_MEASURES}, got {value!r}.")
    return value


def _check_curvature_limits(value):
    try:
        k_lo, k_hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(
            f"curvature_limits must be two numbers (units of sqrt(m4)), got {value!r}."
        ) from None
    if not (np.isfinite(k_lo) and np.isfinite(k_hi) and 0 <= k_lo < k_hi):
        raise ValueError(
            f"curvature_limits must satisfy 0 <= low < high < inf (units of sqrt(m4)), got "
            f"{value!r}; the paper uses (0.1, 2.5)."
        )
    return value


def _check_height_cutoff(value):
    if value is not None and (not isinstance(value, numbers.Real) or not (0 < float(value) < np.inf)):
        raise ValueError(
            f"height_cutoff must be a positive number of standard deviations sqrt(m0) or None, "
            f"got {value!r}; Fig. 9 of the paper uses 2.5 to 6."
        )
    return value


def _check_nodes(name):
    def check(value):
        if not isinstance(value, numbers.Integral) or value < 2:
            raise ValueError(f"{name} must be an integer >= 2, got {value!r}.")
        return value
    return check


def _check_force_table(value):
    if value is not None and (not isinstance(value, numbers.Integral) or (value != 0 and value < 16)):
        raise ValueError(f"force_table must be 0 (no table) or an integer >= 16, got {value!r}.")
    return value


def _check_apparent_area(value):
    if value is not None and not (isinstance(value, numbers.Real) and value > 0):
        raise ValueError(f"apparent_area must be a positive area in m2 or None, got {value!r}.")
    return value


# --------------------------------------------------------------------------------------------
# the model's entry: moments, default grid and the quadrature over them


def _prepare(ctx):
    o = ctx.options
    k_lo, k_hi = (float(v) for v in o["curvature_limits"])
    xi_top = _XI_TOP if o["height_cutoff"] is None else min(float(o["height_cutoff"]), _XI_TOP)
    table = o["force_table"]
    if table is None:
        table = 0 if o["sphere_model"] in ("hertz", "modified_dmt") else 256
    moments = _as_moments(ctx.source if ctx.height is None else ctx.height, o["moment_method"], o["qmax"])
    area = o["apparent_area"]
    if area is None and ctx.height is not None:  # a map: its own area
        area = ctx.height.sizes["x"] * ctx.height.sizes["y"] * ctx.spacing[1] * ctx.spacing[0]
    t_nodes, t_weights = _gauss(int(o["n_curvature"]))
    ctx.state.update(
        moments=moments, moments_si=moments_si(moments), curvature_limits=(k_lo, k_hi),
        xi_top=xi_top, force_table=int(table), apparent_area=area,
        quadrature=dict(model=o["sphere_model"], K=ctx.hertz_modulus,
                        t_nodes=k_lo + (k_hi - k_lo) * t_nodes, t_weights=(k_hi - k_lo) * t_weights,
                        xi_top=xi_top, n_height=int(o["n_height"]), measure=o["curvature_measure"],
                        table=int(table)))


def _inputs(ctx):
    m0, m2, m4 = ctx.state["moments_si"]
    return m0, m2, m4, ctx.humidity["laplace_pressure"], ctx.humidity["water_height"]


def _default_grid(_, ctx):
    if ctx.n_distance is not None and ctx.n_distance < 2:
        raise ValueError(f"n_distance must be an integer >= 2 or None, got {ctx.n_distance!r}.")
    inputs = _inputs(ctx)
    if any(is_lazy(v) for v in inputs):
        raise ValueError(
            "the automatic distance grid needs eager moments and humidities: pass distance= "
            "explicitly, e.g. distance=roughstick.contact.gw_curves(moments.isel(realization=0)"
            ".compute(), relative_humidity=...).distance, or compute the moments first."
        )
    d = _gw_auto_distance(*(np.asarray(v.values, dtype=float) for v in xr.broadcast(*inputs)),
                          ctx.state["quadrature"], n=ctx.n_distance)
    return Grid(d)


def _run(ctx, grid):
    """Eq. 14 over every moment set and humidity (one broadcast ``apply_ufunc``)."""
    d = grid.distance
    res = xr.apply_ufunc(
        _gw_block, *_inputs(ctx),
        kwargs={"distance": d, **ctx.state["quadrature"]},
        output_core_dims=[["distance", "_variable"]],
        dask="parallelized",
        output_dtypes=[float],
        dask_gufunc_kwargs={"output_sizes": {"distance": d.size, "_variable": len(_VARS)}},
    )
    lead = [dim for dim in res.dims if dim not in ("rh", "distance", "_variable")]
    res = res.transpose(*lead, *(["rh"] if "rh" in res.dims else []), "distance", "_variable")
    out = {name: res.isel(_variable=i, drop=True) for i, name in enumerate(_VARS)}
    if ctx.state["apparent_area"] is not None:
        out["n_contacts"] = out["n_contacts"] * float(ctx.state["apparent_area"])
    out["summit_density"] = summit_density(ctx.state["moments"])
    return out


def _variable_attrs(ctx):
    count = ({"long_name": "expected number of contacting summits on the apparent area"}
             if ctx.state["apparent_area"] is not None else
             {"units": "m-2", "long_name": "number of contacting summits per unit apparent area"})
    return {
        "n_contacts": count,
        "max_interference": {"long_name": "interference of the highest summit integrated (h_max - d)"},
        "wet_fraction": {"long_name": "sum of the summits' wetted annuli per apparent area "
                                      "(menisci not merged; can exceed 1)"},
        "fit_error": {"comment": "not applicable to Greenwood-Williamson (no asperity fit)"},
    }


def _describe(ctx, grid):
    o, st = ctx.options, ctx.state
    k_lo, k_hi = st["curvature_limits"]
    attrs = dict(
        sphere_model=o["sphere_model"], curvature_measure=o["curvature_measure"],
        curvature_limits=np.array([k_lo, k_hi]),
        height_cutoff=float(o["height_cutoff"]) if o["height_cutoff"] is not None else "none",
        height_integration_top=st["xi_top"], reduced_modulus=ctx.hertz_modulus * 3.0 / 4.0,
        n_height=int(o["n_height"]), n_curvature=int(o["n_curvature"]),
        force_table=st["force_table"])
    return attrs, (
        f"gw_curves(sphere_model={o['sphere_model']!r}, curvature_limits=({k_lo}, {k_hi}), "
        f"height_cutoff={o['height_cutoff']!r}, n_height={o['n_height']}, "
        f"n_curvature={o['n_curvature']}"
        + (f", automatic grid of {grid.distance.size} distances)" if grid.automatic else ")"))


# --------------------------------------------------------------------------------------------
# public functions


@check_numbers(n_height="count", n_curvature="count", n_distance="count?", qmax="positive?",
               apparent_area="positive?")
def gw_curves(
    moments,
    *,
    relative_humidity,
    distance=None,
    sphere_model: str = "modified_dmt",
    curvature_limits=(0.1, 2.5),
    height_cutoff: float | None = None,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    adsorbed_layer="paper",
    curvature_measure: str = "geometric",
    apparent_area: float | None = None,
    n_height: int = 32,
    n_curvature: int = 24,
    force_table: int | None = None,
    moment_method: str = "spline",
    qmax=None,
    n_distance: int | None = None,
) -> xr.Dataset:
    r"""Greenwood–Williamson force–distance curves of a rough surface on a flat (Eq. 14).

    Parameters
    ----------
    moments : xarray.Dataset or xarray.DataArray
        Dataset with ``m0`` (m2), ``m2`` (1), ``m4`` (m-2), any leading dims (e.g.
        ``realization``), numpy or dask; or a ``height`` DataArray ``(..., y, x)`` whose moments
        are measured by ``roughness_moments(height, method=moment_method, qmax=qmax)``
        (one-direction moments averaged over x and y). :func:`roughstick.contact.curves`
        with ``model="gw"`` does the same, so both entry points give the same curves.
    relative_humidity : float, sequence or xarray.DataArray
        RH as a fraction in (0, 1); a sequence becomes the ``rh`` dimension.
    distance : array-like or xarray.DataArray, optional
        Distances d from the flat to the mean plane [m], 1-D; stored ascending. Default (None):
        an automatic grid set by the summit-height distribution, not by the map's highest pixel
        (GW integrates summits up to ``xi_top`` √m0, and its contact onset and equilibrium lie
        in that Gaussian tail, often above the highest pixel): from where the pressure of every
        curve is below 1e-6 of its largest attraction down to √m0 below the outermost
        equilibrium, chord-refined where Eq. 13, the pull-off and the equilibrium are decided
        (eager moments only; ``attrs["distance_grid"]`` is ``"automatic"``, else ``"given"``).
    sphere_model : {"modified_dmt", "dmt", "maugis", "hertz"}, default "modified_dmt"
        Force of one summit (``roughstick.contact.sphere.force_kernel``, retraction
        branch) with the Laplace pressure :math:`\sigma_0 = |\Delta P|` acting over the water
        height :math:`h_0 = h_{water}`. ``"hertz"`` ignores the water. (JKR is not offered: it
        has no adhesion outside the contact, so it misses every meniscus that does not touch.)
    curvature_limits : (float, float), default (0.1, 2.5)
        :math:`[\kappa_{\min}, \kappa_{\max}]` in units of :math:`\sqrt{m_4}` (the paper's §3.4.2
        choice, radii 1/(2.5√m4) to 1/(0.1√m4)).
    height_cutoff : float or None, default None
        Highest summit height :math:`h_{\max}` in units of :math:`\sqrt{m_0}` (Fig. 9; ref. [1]
        of the paper used 2.5). None integrates to 10√m0, beyond which the density is < 1e-16
        of its peak.
    material, material2 : Material
        The two bodies (``material2=None``: same as ``material``); the summits use
        :math:`K = \tfrac43 E^*`.
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-layer model of :func:`roughstick.contact.water_height`.
    curvature_measure : {"geometric", "mean"}, default "geometric"
        Summit radius :math:`1/\sqrt{\kappa_1\kappa_2}` (Greenwood 2006, the paper) or
        :math:`2/(\kappa_1+\kappa_2)` (Nayak's mean curvature).
    apparent_area : float, optional
        Apparent area [m2]. If given, ``n_contacts`` is the expected number of contacting
        summits on it (units 1, comparable with the count of the modified DMT on a map of that
        size); otherwise it is their number per unit area (m-2).
    n_height, n_curvature : int
        Gauss–Legendre nodes per height sub-interval and over the curvature range (the defaults'
        error, far below a distance grid's: docs/greenwood_williamson.md).
    force_table : int or None
        Number of points of a per-curvature table of the summit force (cubic spline in
        :math:`\sqrt\delta` on the contact side, in :math:`\delta` on the meniscus side) used
        instead of calling the sphere kernel at every quadrature node; 0 calls the kernel
        directly. None: direct for the closed forms ("hertz", "modified_dmt"), 256 for the
        models that solve equations per point ("dmt", "maugis"), at a relative error of about
        1e-4 in the adhesive energy.
    moment_method : {"spline", "spectral"}, default "spline"
        Estimator of the moments of a height map (:func:`roughstick.surface.roughness_moments`):
        ``"spline"``, the variances of cubic-spline derivatives of the paper's Table 2, which its
        §3.4.2 feeds to GW (Fig. 10); or ``"spectral"``, the periodogram moments of Table 3.
        A moments Dataset takes neither this nor ``qmax`` (``ValueError``).
    qmax : float, optional
        With ``moment_method="spectral"``: cutoff wave number [rad m-1] of the periodogram (Table 3
        uses 289 rad/µm). Without a cutoff the periodogram of a non-periodic map carries the
        edge discontinuity up to the Nyquist wave number, which inflates m4.
    n_distance : int, optional
        With ``distance=None``: at least this many distances (the widest intervals are split).

    Returns
    -------
    xarray.Dataset
        Over ``(..., rh, distance)``: ``pressure`` (Pa, positive repulsive), ``repulsive_pressure``
        (Pa, the Hertz part), ``wet_fraction`` (sum of the summits' wetted annuli, Eq. 8 minus the
        Hertz contact discs, not merged: it can exceed 1), ``contact_fraction`` (sum of Hertz
        contact discs :math:`\pi R\delta`), ``n_contacts``, ``fit_error`` (NaN: no fit in GW),
        ``max_interference`` (:math:`h_{\max} - d`, the top of the height integral), and
        ``summit_density`` (m-2).

    Raises
    ------
    ValueError
        Non-positive moments, bandwidth :math:`\alpha = m_0 m_4/m_2^2 \le 1.5`, reversed or
        negative curvature limits, a non-positive height cutoff, unknown model, bad distances.

    Notes
    -----
    The height integral of Eq. 14 is split at the two kinks of the summit force, first water
    contact :math:`h = d - h_{water}` and first solid contact :math:`h = d`; each part gets
    ``n_height`` Gauss–Legendre nodes, the contact part in :math:`s` with
    :math:`h = d + (h_{\max} - d)s^2` so that :math:`\delta^{3/2}` becomes smooth. The
    curvature integral has ``n_curvature`` nodes on the limits. Interference of a summit of
    height h: :math:`\delta = h - d`. All (distance × height × curvature) nodes are one numpy
    broadcast; the Hertz part and the densities of the contact part are computed once per
    moment set and reused for every humidity.

    References
    ----------
    Greenwood and Williamson (1966), https://doi.org/10.1098/rspa.1966.0242;
    Nayak (1971), https://doi.org/10.1115/1.3451608;
    Greenwood (2006), https://doi.org/10.1016/j.wear.2005.09.031

    Examples
    --------
    >>> ds = xr.Dataset({"m0": ((), 15.7, {"units": "nm2"}), "m2": ((), 0.040, {"units": "1"}),
    ...                  "m4": ((), 5.08e-4, {"units": "nm-2"})})
    >>> c = rs.contact.gw_curves(ds, relative_humidity=[0.3, 0.9],
    ...                         distance=np.linspace(0, 30e-9, 61))
    >>> c.pressure.dims
    ('rh', 'distance')
    """
    if distance is not None and n_distance is not None:
        raise ValueError("n_distance sizes the automatic grid; with distance= given, drop it.")
    return apply(MODEL, moments, relative_humidity=relative_humidity, distance=distance,
                 material=material, material2=material2, adsorbed_layer=adsorbed_layer,
                 n_distance=n_distance, sphere_model=sphere_model,
                 curvature_limits=curvature_limits, height_cutoff=height_cutoff,
                 curvature_measure=curvature_measure, apparent_area=apparent_area,
                 n_height=n_height, n_curvature=n_curvature, force_table=force_table,
                 moment_method=moment_method, qmax=qmax)


def gw_cutoff_study(moments, *, height_cutoffs=(2.5, 3.0, 4.0, 5.0, 6.0, 7.0, None), **kwargs) -> xr.Dataset:
    r"""Greenwood–Williamson curves for several summit-height cutoffs (the paper's Fig. 9).

    Parameters
    ----------
    moments : xarray.Dataset or xarray.DataArray
        As for :func:`gw_contact_curves`.
    height_cutoffs : sequence of float or None
        :math:`h_{\max}/\sqrt{m_0}`; None means no cutoff (stored as ``inf``).
    **kwargs
        Passed to :func:`gw_contact_curves` (``relative_humidity``, ``distance``, ...). Without
        ``distance`` the curves share the union of the automatic grids of every cutoff.

    Returns
    -------
    xarray.Dataset
        The curves with a new leading dimension ``height_cutoff`` (units of √m0; ``inf`` = none).
    """
    if "height_cutoff" in kwargs:
        raise TypeError("pass the cutoffs as height_cutoffs=[...], not height_cutoff.")
    cuts = list(height_cutoffs)
    if not cuts:
        raise ValueError("height_cutoffs must list at least one cutoff.")
    automatic = kwargs.get("distance") is None
    if automatic:  # one grid for all cutoffs: the union of their automatic grids
        n_distance = kwargs.pop("n_distance", None)
        kwargs["distance"] = np.unique(np.concatenate([
            gw_curves(moments, height_cutoff=c, n_distance=n_distance,
                              **{k: v for k, v in kwargs.items() if k != "distance"}).distance.values
            for c in cuts]))
    parts = [gw_curves(moments, height_cutoff=c, **kwargs) for c in cuts]
    coord = np.array([np.inf if c is None else float(c) for c in cuts])
    out = xr.concat(parts, dim="height_cutoff", combine_attrs="drop_conflicts",
                    data_vars="all", coords="minimal", compat="override")
    out = out.assign_coords(height_cutoff=("height_cutoff", coord))
    out["height_cutoff"].attrs = {"units": "1", "long_name": "summit height cutoff h_max / sqrt(m0)"}
    out["summit_density"] = parts[0]["summit_density"]
    out.attrs = dict(parts[0].attrs)
    out.attrs["height_cutoff"] = "see coordinate height_cutoff"
    out.attrs["distance_grid"] = "automatic" if automatic else "given"
    return out


MODEL = register_model(ContactModel(
    name="gw",
    title="Greenwood-Williamson rough contact curves (Eq. 14)",
    description="Greenwood-Williamson (Eq. 14): spheres on the summits of a Gaussian surface "
                "with the map's spectral moments",
    kernel=_gw_block,
    options=options_of(gw_curves, sphere_model=_check_sphere_model,
                       curvature_limits=_check_curvature_limits, height_cutoff=_check_height_cutoff,
                       curvature_measure=_check_curvature_measure, apparent_area=_check_apparent_area,
                       n_height=_check_nodes("n_height"), n_curvature=_check_nodes("n_curvature"),
                       force_table=_check_force_table, qmax="positive?"),
    cost_rank=0.0,
    default_grid=_default_grid,
    extra_variables=("summit_density",),
    references=REFERENCES,
    checks=(),
    broadcast_humidity=True,
    accepts_moments=True,
    grid_needs_one_map=False,
    memory="gw",
    estimate_seconds=lambda shape, curves, points: estimate_model_seconds("gw", shape, curves, points),
    prepare=_prepare,
    describe=_describe,
    variable_attrs=_variable_attrs,
    run=_run,
    function=gw_curves,
))
