r"""Sphere-on-flat contact models: Hertz, JKR, DMT, Maugis-Dugdale (+ Kim) and modified DMT.

Public xarray layer over the numpy kernels of :mod:`._kernels` (paper §2.2,
Eqs. 7-11, Table 1, Fig. 3). Adhesion is either capillary (``relative_humidity``: Dugdale
stress :math:`\sigma_0 = |\Delta P|` over the range :math:`h_0 = h_{water}`, Eqs. 2 and 6,
:math:`w = \sigma_0 h_0`) or given directly (``work_of_adhesion`` and, for the Dugdale models,
``adhesive_stress``). Forces are positive when repulsive; ``interference`` :math:`\delta > 0` is
the overlap of the undeformed profiles, :math:`\delta < 0` a gap.

Every numeric argument may be a float (SI), a 1-D sequence (``interference``/``radius``/``rh``
dims) or a DataArray with ``units``; DataArrays broadcast and dask-backed inputs stay lazy.
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from ..._core.api import renamed_keywords
from ..._core.conventions import ATTRS, dataset_attrs, set_attrs
from ..._core.materials import POLYSILICON, Material, hertz_modulus
from ..._core.references import PAPER, cite
from ..._core.units import require
from ..._core.validate import ValidityWarning, external_stacklevel, positive
from ..meniscus import as_relative_humidity, laplace_pressure, water_height
from . import _energy
from . import _kernels as K_

__all__ = [
    "SPHERE_MODELS",
    "sphere_force",
    "sphere_contact",
    "sphere_adhesive_energy",
    "transition_parameter",
]

#: Names accepted by ``sphere_model``.
SPHERE_MODELS = K_.MODELS

_REFERENCES = {
    "hertz": cite("hertz1882"),
    "jkr": cite("jkr1971"),
    "dmt": cite("dmt1975"),
    "maugis": cite("maugis1992", "kim1998"),
    "modified_dmt": cite((PAPER, "Eqs. 8-11")),
}


# ------------------------------------------------------------------------------------------
# input handling
# ------------------------------------------------------------------------------------------
def _check_model(model):
    if model not in SPHERE_MODELS:
        raise ValueError(
            f"unknown sphere contact model {model!r}; valid names are "
            f"{', '.join(map(repr, SPHERE_MODELS))}."
        )


def _interference(interference):
    if isinstance(interference, xr.DataArray):
        return require(interference, "length", name="interference")
    arr = np.asarray(interference, dtype=float)
    if arr.ndim == 0:
        return xr.DataArray(arr)
    if arr.ndim == 1:
        da = xr.DataArray(arr, dims=("interference",), coords={"interference": arr})
        return set_attrs(da, "interference")
    raise ValueError(
        f"interference must be a scalar, a 1-D sequence or a DataArray; got shape {arr.shape}. "
        "Wrap it in xarray.DataArray(..., dims=...) with units='m'."
    )


def _modulus(material, material2, reduced_modulus):
    """The paper's K = 4/3 E* [Pa] (float or DataArray)."""
    if reduced_modulus is not None:
        e = positive(
            reduced_modulus, "pressure", "reduced_modulus",
            "Pass E* in Pa (two poly-silicon bodies: 86.6e9).",
        )
        return 4.0 / 3.0 * e
    for m, nm in ((material, "material"), (material2, "material2")):
        if m is not None and not isinstance(m, Material):
            raise TypeError(f"{nm} must be a roughstick.Material, got {type(m).__name__}.")
    return hertz_modulus(material, material2)


def _adhesion(model, relative_humidity, work_of_adhesion, adhesive_stress, adsorbed_layer, meniscus_kwargs):
    """Return (sigma0, h0, info) in SI: Dugdale stress and range (w = sigma0 h0)."""
    if relative_humidity is not None:
        if work_of_adhesion is not None or adhesive_stress is not None:
            raise ValueError(
                "give either relative_humidity (capillary adhesion) or work_of_adhesion/"
                "adhesive_stress (given adhesion), not both."
            )
        rh = as_relative_humidity(relative_humidity)
        lp_kw = {k: v for k, v in meniscus_kwargs.items() if k in ("temperature", "molar_volume")}
        sigma0 = -laplace_pressure(rh, **lp_kw)
        h0 = water_height(rh, adsorbed_layer=adsorbed_layer, **meniscus_kwargs)
        return sigma0, h0, "capillary"
    if meniscus_kwargs:
        raise TypeError(f"unexpected arguments {sorted(meniscus_kwargs)} without relative_humidity.")
    if model == "hertz":
        return 0.0, 0.0, "none"
    if work_of_adhesion is None:
        raise ValueError(
            f"model {model!r} needs adhesion: pass relative_humidity (capillary) or "
            "work_of_adhesion [J m-2] (and adhesive_stress [Pa] for 'dmt', 'maugis', 'modified_dmt')."
        )
    w = positive(work_of_adhesion, "energy_per_area", "work_of_adhesion", "Pass w in J m-2, e.g. 0.1.")
    if adhesive_stress is None:
        if model == "jkr":
            return w, 1.0, "given"  # JKR uses only w = sigma0 * h0
        raise ValueError(
            f"model {model!r} needs the Dugdale adhesive stress besides work_of_adhesion: pass "
            "adhesive_stress [Pa] (the range is w / adhesive_stress), or use sphere_model='jkr'."
        )
    s0 = positive(adhesive_stress, "pressure", "adhesive_stress", "Pass sigma0 in Pa, e.g. 1e8.")
    return s0, w / s0, "given"


#: contact radius / sphere radius beyond which the small-strain models are not trusted: Hertz,
#: JKR, DMT and Maugis neglect terms of order (a/R)^2, about 10 % at a = 0.3 R
SMALL_STRAIN_LIMIT = 0.3


def _warn_if_large_strain(R, Kmod, s0, h0, kind, contact_radius=None):
    r"""ValidityWarning when the adhesion alone (the JKR contact radius at zero load,
    :math:`a_0^3 = 6\pi w R^2/K`) or the given interferences deform the sphere beyond
    ``SMALL_STRAIN_LIMIT`` of its radius: a soft material, or a modulus typed in the wrong unit."""
    R, Kmod = _as_da(R), _as_da(Kmod)
    if any(x.chunks is not None for x in (R, Kmod, _as_da(s0), _as_da(h0))):
        return  # lazy inputs: checked nowhere rather than computed twice
    ratio = 0.0
    if kind != "none":
        a0 = np.cbrt(6.0 * np.pi * (_as_da(s0) * _as_da(h0)) * R**2 / Kmod)
        ratio = float((a0 / R).max(skipna=True).fillna(0.0)) if a0.size else 0.0
    source = "the adhesion alone (zero-load JKR contact radius)"
    if contact_radius is not None and contact_radius.chunks is None and contact_radius.size:
        loaded = float((contact_radius / R).max(skipna=True).fillna(0.0))
        if loaded > ratio:
            ratio, source = loaded, "the given interferences"
    if ratio > SMALL_STRAIN_LIMIT:
        warnings.warn(
            f"{source} give a contact radius of {ratio:.2g} sphere radii on E* = "
            f"{0.75 * float(Kmod.min()):.3g} Pa: the sphere models assume small strain "
            f"(a < {SMALL_STRAIN_LIMIT} R; errors of order (a/R)^2), so these forces, interferences "
            "and energies are not trustworthy. Check that the modulus is in Pa (two poly-silicon "
            "bodies: E* = 86.6e9) and the radius in m; for a soft material use a finite-deformation "
            "model.",
            ValidityWarning, stacklevel=external_stacklevel(),
        )


def _prepare(model, radius, relative_humidity, work_of_adhesion, adhesive_stress, material,
             material2, reduced_modulus, adsorbed_layer, meniscus_kwargs):
    _check_model(model)
    R = positive(radius, "length", "radius", "Pass the sphere radius in m (e.g. 100e-9).", dim="radius")
    Kmod = _modulus(material, material2, reduced_modulus)
    s0, h0, kind = _adhesion(model, relative_humidity, work_of_adhesion, adhesive_stress,
                             adsorbed_layer, meniscus_kwargs)
    return R, Kmod, s0, h0, kind


def _as_da(x):
    return x if isinstance(x, xr.DataArray) else xr.DataArray(x)


def _strip(x):
    """Drop attrs so apply_ufunc outputs get only canonical attrs."""
    x = _as_da(x)
    out = x.copy(deep=False)
    out.attrs = {}
    return out


def _state_block(delta, R, Kmod, s0, h0, *, model, branch, dmt_outer):
    f, a, c = K_.sphere_state_kernel(model, delta, R, Kmod, s0, h0, branch=branch, dmt_outer=dmt_outer)
    shape = np.broadcast_shapes(*(np.shape(v) for v in (delta, R, Kmod, s0, h0)))
    return (np.broadcast_to(f, shape).copy(), np.broadcast_to(a, shape).copy(),
            np.broadcast_to(c, shape).copy())


def _attrs_common(model, kind, branch):
    out = {"contact_model": model, "adhesion": kind, "references": _REFERENCES[model]}
    if model in ("jkr", "maugis"):
        out["branch"] = branch
    return out


# ------------------------------------------------------------------------------------------
# public API
# ------------------------------------------------------------------------------------------
def transition_parameter(
    *,
    radius,
    relative_humidity=None,
    work_of_adhesion=None,
    adhesive_stress=None,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    reduced_modulus=None,
    adsorbed_layer="paper",
    **meniscus_kwargs,
) -> xr.DataArray:
    r"""Maugis transition parameter :math:`\lambda` (Eq. 7).

    .. math:: \lambda = \frac{2\sigma_0}{(\pi\omega K^2/R)^{1/3}},\qquad \omega = \sigma_0 h_0

    For capillary adhesion :math:`\sigma_0 = |\Delta P|` and :math:`h_0 = h_{water}`; the
    paper's Table 1 cases lie between 0.021 (RH 70 %, R = 100 nm) and 0.169 (RH 30 %,
    R = 800 nm): all near the DMT limit (:math:`\lambda \to 0`); JKR is :math:`\lambda \to \infty`.

    Parameters
    ----------
    radius : float, sequence or xarray.DataArray
        Sphere radius R [m] (> 0).
    relative_humidity : float, sequence or xarray.DataArray, optional
        RH fraction in (0, 1) for capillary adhesion.
    work_of_adhesion, adhesive_stress : float or xarray.DataArray, optional
        :math:`\omega` [J m-2] and :math:`\sigma_0` [Pa] when adhesion is given directly.
    material, material2 : Material
        The two bodies (default poly-silicon on poly-silicon, K = 115.4 GPa).
    reduced_modulus : float or xarray.DataArray, optional
        :math:`E^*` [Pa], overrides the materials (:math:`K = 4E^*/3`).
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-layer model of :func:`roughstick.contact.water_height`.
    **meniscus_kwargs
        Passed to :func:`roughstick.contact.water_height` (``temperature``, contact angles, ...).

    Returns
    -------
    xarray.DataArray
        :math:`\lambda` (units "1").

    Examples
    --------
    >>> lam = rs.contact.transition_parameter(radius=[100e-9, 800e-9], relative_humidity=[0.3, 0.5, 0.7])
    >>> lam.round(3).values
    array([[0.085, 0.049, 0.021],
           [0.169, 0.097, 0.043]])
    """
    if work_of_adhesion is not None and adhesive_stress is None:
        raise ValueError("transition_parameter needs adhesive_stress [Pa] with work_of_adhesion.")
    R, Kmod, s0, h0, kind = _prepare(
        "maugis", radius, relative_humidity, work_of_adhesion, adhesive_stress, material, material2,
        reduced_modulus, adsorbed_layer, meniscus_kwargs,
    )
    out = xr.apply_ufunc(
        K_.transition_parameter_kernel, _strip(R), _strip(Kmod), _strip(s0), _strip(h0),
        dask="parallelized", output_dtypes=[float],
    )
    return set_attrs(out.rename("transition_parameter"), "transition_parameter")


@renamed_keywords(model="sphere_model")
def sphere_contact(
    interference,
    *,
    sphere_model: str,
    radius,
    relative_humidity=None,
    work_of_adhesion=None,
    adhesive_stress=None,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    reduced_modulus=None,
    adsorbed_layer="paper",
    branch: str = "retraction",
    dmt_outer: str = "sphere",
    **meniscus_kwargs,
) -> xr.Dataset:
    r"""Force, contact radius and adhesive radius of a sphere on a flat (Dataset form).

    Same parameters as :func:`sphere_force`. The Dataset holds ``force`` [N], ``contact_radius``
    ``a`` [m], ``adhesive_radius`` ``c`` [m] (outer radius of the wetted / Dugdale zone),
    ``transition_parameter`` :math:`\lambda`, ``work_of_adhesion`` [J m-2] and the model
    parameters in its attributes.
    """
    model = sphere_model
    if branch not in K_.BRANCHES:
        raise ValueError(f"branch must be one of {K_.BRANCHES}, got {branch!r}.")
    if dmt_outer not in ("sphere", "paraboloid"):
        raise ValueError(f"dmt_outer must be 'sphere' or 'paraboloid', got {dmt_outer!r}.")
    delta = _interference(interference)
    R, Kmod, s0, h0, kind = _prepare(
        model, radius, relative_humidity, work_of_adhesion, adhesive_stress, material, material2,
        reduced_modulus, adsorbed_layer, meniscus_kwargs,
    )
    f, a, c = xr.apply_ufunc(
        _state_block, _strip(delta), _strip(R), _strip(Kmod), _strip(s0), _strip(h0),
        kwargs={"model": model, "branch": branch, "dmt_outer": dmt_outer},
        dask="parallelized", output_dtypes=[float, float, float], output_core_dims=[[], [], []],
    )
    common = _attrs_common(model, kind, branch)
    ds = xr.Dataset(
        {
            "force": set_attrs(f, "force", **common),
            "contact_radius": set_attrs(a, "contact_radius"),
            "adhesive_radius": set_attrs(c, "adhesive_radius"),
        }
    )
    if kind != "none":
        w = _as_da(s0) * _as_da(h0)
        ds["work_of_adhesion"] = set_attrs(w, "work_of_adhesion")
        lam = xr.apply_ufunc(
            K_.transition_parameter_kernel, _strip(R), _strip(Kmod), _strip(s0), _strip(h0),
            dask="parallelized", output_dtypes=[float],
        )
        ds["transition_parameter"] = set_attrs(lam, "transition_parameter")
    ds.attrs = dataset_attrs(f"sphere on flat, {model} model", references=_REFERENCES[model],
                             contact_model=model, adhesion=kind)
    if model in ("jkr", "maugis"):
        ds.attrs["branch"] = branch
    for cname in ds.coords:
        if cname in ATTRS:
            ds[cname].attrs = dict(ATTRS[cname])
    _warn_if_large_strain(R, Kmod, s0, h0, kind, ds["contact_radius"])
    return ds


@renamed_keywords(model="sphere_model")
def sphere_force(
    interference,
    *,
    sphere_model: str,
    radius,
    relative_humidity=None,
    work_of_adhesion=None,
    adhesive_stress=None,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    reduced_modulus=None,
    adsorbed_layer="paper",
    branch: str = "retraction",
    dmt_outer: str = "sphere",
    **meniscus_kwargs,
) -> xr.DataArray:
    r"""Force-interference curve of a sphere on a flat for one of five models (paper §2.2).

    Parameters
    ----------
    interference : float, sequence or xarray.DataArray
        :math:`\delta` [m]: > 0 overlap of the undeformed profiles, < 0 gap. A 1-D sequence
        becomes dimension ``interference``; any order, NaN gives NaN, empty gives empty.
    sphere_model : {"hertz", "jkr", "dmt", "maugis", "modified_dmt"}
        ``"hertz"`` (no adhesion, Eqs. 10-11), ``"jkr"``, ``"dmt"`` (Hertz plus the Dugdale
        stress on the Hertz-deformed gap), ``"maugis"`` (Maugis-Dugdale with Kim's non-contact
        branch) or ``"modified_dmt"`` (Eqs. 8-11).
    radius : float, sequence or xarray.DataArray
        Sphere radius R [m] (> 0); a sequence becomes dimension ``radius``.
    relative_humidity : float, sequence or xarray.DataArray, optional
        Capillary adhesion: :math:`\sigma_0 = |\Delta P|` (Eq. 2), range
        :math:`h_0 = h_{water}` (Eq. 6), :math:`w = \sigma_0 h_0`. A sequence becomes ``rh``.
    work_of_adhesion : float or xarray.DataArray, optional
        Given adhesion :math:`w` [J m-2] (e.g. van der Waals), instead of ``relative_humidity``.
    adhesive_stress : float or xarray.DataArray, optional
        Dugdale stress :math:`\sigma_0` [Pa] with ``work_of_adhesion`` (range :math:`w/\sigma_0`);
        required by "dmt", "maugis" and "modified_dmt" with given adhesion.
    material, material2 : Material
        The two bodies (default poly-silicon on poly-silicon: K = 4/3 E* = 115.4 GPa).
    reduced_modulus : float or xarray.DataArray, optional
        :math:`E^*` [Pa], overrides ``material``/``material2``.
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-layer model (:func:`roughstick.contact.water_height`).
    branch : {"retraction", "approach"}
        Displacement-controlled branch for "jkr" and "maugis" (the others are single-valued).
        ``"retraction"`` (default; the path of the work to separate): the sphere stays attached
        on the stable branch down to its jump-off point, zero force below. ``"approach"``: zero
        force until first interaction (:math:`\delta = -h_0` for Maugis, 0 for JKR), then the
        same stable branch.
    dmt_outer : {"sphere", "paraboloid"}
        Profile of the undeformed sphere used for the DMT water radius out of contact.
    **meniscus_kwargs
        Passed to :func:`roughstick.contact.water_height` (``temperature``, ``kelvin_length``,
        ``contact_angle_1`` ...).

    Returns
    -------
    xarray.DataArray
        ``force`` [N] (positive repulsive) over the broadcast dims of the inputs, with
        coordinates ``contact_radius`` and ``adhesive_radius`` [m].

    Raises
    ------
    ValueError
        Unknown model, RH outside (0, 1), non-positive radius/modulus/adhesion, missing adhesion.
    roughstick._core.units.UnitsError
        A DataArray argument without (or with wrong) ``units``.

    Notes
    -----
    Equations per model (see ``docs/sphere_models.md``):

    - Hertz: :math:`F = K\sqrt R\,\delta^{3/2}`, :math:`a^2 = R\delta` (Eqs. 10-11).
    - Modified DMT: :math:`F = F_r + \Delta P\pi[R^2 - (R-\delta-h_{water})^2 - a^2]` (Eqs. 8-9).
    - DMT: :math:`F = K a^3/R - \sigma_0\pi(c^2-a^2)`, ``c`` where the Hertz-deformed gap is
      :math:`h_0`.
    - Maugis-Dugdale: Maugis (1992) Eqs. with :math:`\lambda` of Eq. 7; for :math:`a=0` Kim's
      branch :math:`F = -\sigma_0\pi c^2`.
    - JKR: :math:`F = Ka^3/R - \sqrt{6\pi wKa^3}`, :math:`\delta = a^2/R - \tfrac23\sqrt{6\pi wa/K}`.

    References
    ----------
    Hertz (1882) doi:10.1515/crll.1882.92.156; Johnson, Kendall, Roberts (1971)
    doi:10.1098/rspa.1971.0141; Derjaguin, Muller, Toporov (1975)
    doi:10.1016/0021-9797(75)90018-1; Maugis (1992) doi:10.1016/0021-9797(92)90285-T;
    Kim, McMeeking, Johnson (1998) doi:10.1016/S0022-5096(97)00070-7.

    Examples
    --------
    >>> f = rs.contact.sphere_force([-1e-9, 0.0, 1e-9], sphere_model="modified_dmt", radius=100e-9,
    ...                     relative_humidity=0.5)
    >>> (f * 1e9).round(1).values  # nN
    array([ -31.9,  -91.6, 1033.9])
    """
    model = sphere_model
    ds = sphere_contact(
        interference, sphere_model=model, radius=radius, relative_humidity=relative_humidity,
        work_of_adhesion=work_of_adhesion, adhesive_stress=adhesive_stress, material=material,
        material2=material2, reduced_modulus=reduced_modulus, adsorbed_layer=adsorbed_layer,
        branch=branch, dmt_outer=dmt_outer, **meniscus_kwargs,
    )
    out = ds["force"].assign_coords(contact_radius=ds["contact_radius"], adhesive_radius=ds["adhesive_radius"])
    return out.rename("force")


def _energy_block(R, Kmod, s0, h0, *, model, dmt_outer):
    return _energy.adhesive_energy_kernel(model, R, Kmod, s0, h0, dmt_outer=dmt_outer)


@renamed_keywords(model="sphere_model")
def sphere_adhesive_energy(
    *,
    sphere_model: str,
    radius,
    relative_humidity=None,
    work_of_adhesion=None,
    adhesive_stress=None,
    material: Material = POLYSILICON,
    material2: Material | None = None,
    reduced_modulus=None,
    adsorbed_layer="paper",
    dmt_outer: str = "sphere",
    **meniscus_kwargs,
) -> xr.DataArray:
    r"""Work to separate a sphere from a flat [J] (the paper's Table 1).

    .. math:: W = \int -F(\delta)\,\mathbf 1[F(\delta) < 0]\,d\delta

    along the displacement-controlled retraction path: from the equilibrium interference
    (:math:`F = 0`) out to the last attached state (:math:`\delta = -h_{water}` for DMT and the
    modified DMT, the jump-off point for JKR and Maugis); 0 for Hertz. This definition
    reproduces the 18 cells of Table 1 (docs/sphere_models.md).

    Parameters
    ----------
    sphere_model, radius, relative_humidity, work_of_adhesion, adhesive_stress, material, material2, reduced_modulus, adsorbed_layer, dmt_outer, **meniscus_kwargs
        As in :func:`sphere_force`.

    Returns
    -------
    xarray.DataArray
        ``adhesive_energy`` [J] over the broadcast dims of ``radius`` and the adhesion inputs.

    Notes
    -----
    Closed forms for the modified DMT (cap integral up to the root of Eq. 9) and JKR
    (:math:`W = 2.1023\,\pi w R\,(\pi^2 w^2 R/K^2)^{1/3}`); 64-point Gauss-Legendre for
    the contact parts of DMT and Maugis, whose non-contact parts are closed forms.

    Examples
    --------
    >>> W = rs.contact.sphere_adhesive_energy(sphere_model="modified_dmt", radius=[100e-9, 800e-9],
    ...                               relative_humidity=[0.3, 0.5, 0.7])
    >>> (W * 1e17).round(2).values
    array([[  5.17,   8.09,  37.01],
           [ 52.25,  74.63, 319.96]])
    """
    model = sphere_model
    _check_model(model)
    R, Kmod, s0, h0, kind = _prepare(
        model, radius, relative_humidity, work_of_adhesion, adhesive_stress, material, material2,
        reduced_modulus, adsorbed_layer, meniscus_kwargs,
    )
    _warn_if_large_strain(R, Kmod, s0, h0, kind)
    out = xr.apply_ufunc(
        _energy_block, _strip(R), _strip(Kmod), _strip(s0), _strip(h0),
        kwargs={"model": model, "dmt_outer": dmt_outer}, dask="parallelized", output_dtypes=[float],
    )
    return set_attrs(out.rename("adhesive_energy"), "adhesive_energy", **_attrs_common(model, kind, "retraction"))
