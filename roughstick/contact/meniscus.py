"""Meniscus physics: Kelvin radius, Laplace pressure, adsorbed layers and water height (Eqs. 1-6).

All functions accept the relative humidity as a float, a sequence (becomes an ``rh`` dimension)
or a DataArray (fraction in (0, 1), ``units`` "1" or "%"); DataArray parameters broadcast, and
dask-backed inputs stay lazy. Values outside (0, 1) raise (at compute time for lazy inputs).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import xarray as xr

from .._core import constants as C
from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.conventions import set_attrs
from .._core.units import as_si
from .._core.validate import (
    MAX_LAYER_THICKNESS,
    as_relative_humidity,
    check_layer_thickness,
    check_plausible_value,
    positive,
)

__all__ = [
    "kelvin_radius",
    "laplace_pressure",
    "meniscus_height",
    "adsorbed_layer",
    "step_adsorbed_layer",
    "no_adsorbed_layer",
    "water_height",
    "as_relative_humidity",
]


@check_numbers(temperature="positive", kelvin_length="length?", surface_tension="positive",
               molar_volume="positive")
def kelvin_radius(
    relative_humidity,
    *,
    temperature=C.DEFAULT_TEMPERATURE,
    kelvin_length: float | None = C.KELVIN_LENGTH,
    surface_tension=C.WATER_SURFACE_TENSION,
    molar_volume=C.WATER_MOLAR_VOLUME,
) -> xr.DataArray:
    r"""Kelvin radius :math:`r_K` (Eqs. 1 and 3), negative below saturation.

    Parameters
    ----------
    relative_humidity : float, sequence or xarray.DataArray
        RH as a fraction in (0, 1).
    temperature : float or xarray.DataArray, default 300
        Absolute temperature [K]; used only when ``kelvin_length`` is None.
    kelvin_length : float or None, default 0.53e-9
        :math:`\gamma V_m/(\mathcal{R}T)` [m]. The default is the 0.53 nm printed in Eq. 3,
        which the paper's tables use; ``None`` computes it from the other arguments
        (0.5196 nm at 300 K).
    surface_tension, molar_volume : float
        :math:`\gamma_{LG}` [N m-1] and :math:`V_m` [m3 mol-1] of water.

    Returns
    -------
    xarray.DataArray
        :math:`r_K` [m].

    Notes
    -----
    .. math:: r_K = \frac{\gamma_{LG} V_m}{\mathcal{R} T \ln RH}

    Examples
    --------
    >>> float(rs.contact.kelvin_radius(0.5)) * 1e9
    -0.7646...
    """
    rh = as_relative_humidity(relative_humidity)
    if kelvin_length is None:
        T = positive(temperature, "temperature", "temperature")
        length = surface_tension * molar_volume / (C.GAS_CONSTANT * T)
    else:
        length = positive(kelvin_length, "length", "kelvin_length")
    out = length / np.log(rh)
    return set_attrs(out, "kelvin_radius")


@check_numbers(temperature="positive", molar_volume="positive")
def laplace_pressure(
    relative_humidity, *, temperature=C.DEFAULT_TEMPERATURE, molar_volume=C.WATER_MOLAR_VOLUME
) -> xr.DataArray:
    r"""Laplace pressure inside the meniscus, :math:`\Delta P = \mathcal{R}T\ln RH / V_m` (Eq. 2).

    Negative (tension): -166.8, -96.05, -49.43 and -14.6 MPa at RH 30, 50, 70 and 90 % (300 K).

    Parameters
    ----------
    relative_humidity : float, sequence or xarray.DataArray
        RH as a fraction in (0, 1).
    temperature : float or xarray.DataArray, default 300
        Absolute temperature [K].
    molar_volume : float, default 18e-6
        Molar volume of water [m3 mol-1].

    Returns
    -------
    xarray.DataArray
        :math:`\Delta P` [Pa].

    Examples
    --------
    >>> float(rs.contact.laplace_pressure(0.3)) / 1e6
    -166.8...
    """
    rh = as_relative_humidity(relative_humidity)
    T = positive(temperature, "temperature", "temperature")
    out = C.GAS_CONSTANT * T * np.log(rh) / molar_volume
    return set_attrs(out, "laplace_pressure")


@check_numbers(contact_angle_1="angle", contact_angle_2="angle", subtended_angle="angle")
def meniscus_height(
    relative_humidity,
    *,
    contact_angle_1=0.0,
    contact_angle_2=0.0,
    subtended_angle=0.0,
    **kelvin_kwargs,
) -> xr.DataArray:
    r"""Meniscus height between a sphere and a half-space (Eq. 5).

    .. math:: h_{men} = -r_K\,(\cos(\theta_1 + \psi) + \cos\theta_2)

    With the default :math:`\theta_1 = \theta_2 = \psi = 0`, :math:`h_{men} = -2 r_K`.

    Parameters
    ----------
    relative_humidity : float, sequence or xarray.DataArray
        RH as a fraction in (0, 1).
    contact_angle_1, contact_angle_2 : float or xarray.DataArray
        Water contact angles on the two bodies [rad] (DataArrays may carry ``deg``).
    subtended_angle : float or xarray.DataArray
        :math:`\psi` [rad]; 0 for spheres much larger than :math:`|r_K|`.
    **kelvin_kwargs
        Passed to :func:`kelvin_radius`.

    Returns
    -------
    xarray.DataArray
        :math:`h_{men}` [m].
    """
    rk = kelvin_radius(relative_humidity, **kelvin_kwargs)
    t1 = as_si(contact_angle_1, "angle", name="contact_angle_1")
    t2 = as_si(contact_angle_2, "angle", name="contact_angle_2")
    psi = as_si(subtended_angle, "angle", name="subtended_angle")
    out = -rk * (np.cos(t1 + psi) + np.cos(t2))
    return set_attrs(out, "meniscus_height")


@check_numbers(thickness="nonnegative", onset="fraction0", surfaces=(1, 2))
def step_adsorbed_layer(
    thickness: float = C.ADSORBED_LAYER_THICKNESS,
    onset: float = C.ADSORBED_LAYER_ONSET_RH,
    surfaces: int = 2,
) -> Callable:
    """Adsorbed-layer model: ``thickness`` on each of ``surfaces`` surfaces for RH > ``onset``.

    The paper's default (§2.1) is ``step_adsorbed_layer()``: 0.9 nm on each surface above 65 % RH,
    none below, so :math:`h_{a1} + h_{a2} = 1.8` nm above the onset.
    """
    check_plausible_value(thickness, name="thickness", kind="length", what="an adsorbed water layer",
                          bounds=(1e-12, MAX_LAYER_THICKNESS / 2, C.ADSORBED_LAYER_THICKNESS))

    def model(rh):
        return xr.where(rh > onset, surfaces * thickness, 0.0)

    model.__name__ = f"step_adsorbed_layer(thickness={thickness!r}, onset={onset!r}, surfaces={surfaces})"
    return model


@renamed_keywords(rh="relative_humidity")
def no_adsorbed_layer(relative_humidity):
    """Adsorbed-layer model with no layer at any humidity (the paper's Fig. 20a)."""
    return xr.zeros_like(relative_humidity)


_LAYER_MODELS = {"paper": step_adsorbed_layer, "none": lambda: no_adsorbed_layer}


def _layer_thickness(adsorbed_layer, rh: xr.DataArray):
    """The model's total layer thickness [m] at ``rh``, checked: finite, >= 0 and not nm."""
    model = _layer_model(adsorbed_layer)
    out = model(rh)
    name = getattr(model, "__name__", repr(model))
    check_layer_thickness(out, name=name if name.startswith("step_") else f"{name!r}",
                          rh=rh)
    return out


def _layer_model(adsorbed_layer) -> Callable:
    if callable(adsorbed_layer):
        return adsorbed_layer
    if adsorbed_layer in _LAYER_MODELS:
        return _LAYER_MODELS[adsorbed_layer]()
    raise ValueError(
        f"adsorbed_layer must be 'paper', 'none' or a callable rh -> total thickness [m]; "
        f"got {adsorbed_layer!r}."
    )


@renamed_keywords(model="layer_model")
def adsorbed_layer(relative_humidity, *, layer_model="paper") -> xr.DataArray:
    """Total adsorbed layer thickness :math:`h_{a1} + h_{a2}` [m] (Eq. 6).

    Parameters
    ----------
    relative_humidity : float, sequence or xarray.DataArray
        RH as a fraction in (0, 1).
    layer_model : {"paper", "none"} or callable
        ``"paper"``: 0.9 nm per surface above 65 % RH; ``"none"``: no layer; or a callable taking
        the RH DataArray and returning the total thickness in metres (checked: finite, >= 0 and
        at most 1e-7 m; more is nm returned as m, refused naming the callable).
    """
    rh = as_relative_humidity(relative_humidity)
    out = _layer_thickness(layer_model, rh)
    if not isinstance(out, xr.DataArray):
        out = xr.zeros_like(rh) + out
    return set_attrs(out, "adsorbed_layer",
                     model=getattr(_layer_model(layer_model), "__name__", str(layer_model)))


@check_numbers(contact_angle_1="angle", contact_angle_2="angle", subtended_angle="angle")
def water_height(
    relative_humidity,
    *,
    adsorbed_layer="paper",
    contact_angle_1=0.0,
    contact_angle_2=0.0,
    subtended_angle=0.0,
    **kelvin_kwargs,
) -> xr.DataArray:
    r"""Height of the condensed water, :math:`h_{water} = h_{men} + h_{a1} + h_{a2}` (Eq. 6).

    0.880, 1.529 and 4.772 nm at RH 30, 50 and 70 % with the paper's defaults.

    Parameters
    ----------
    relative_humidity : float, sequence or xarray.DataArray
        RH as a fraction in (0, 1).
    adsorbed_layer : {"paper", "none"} or callable, default "paper"
        Adsorbed-layer model, see :func:`adsorbed_layer`.
    contact_angle_1, contact_angle_2, subtended_angle : float or xarray.DataArray
        See :func:`meniscus_height`.
    **kelvin_kwargs
        Passed to :func:`kelvin_radius`.

    Returns
    -------
    xarray.DataArray
        :math:`h_{water}` [m].

    Examples
    --------
    >>> rs.contact.water_height([0.3, 0.5, 0.7]).values * 1e9
    array([0.880..., 1.529..., 4.772...])
    """
    h_men = meniscus_height(
        relative_humidity,
        contact_angle_1=contact_angle_1,
        contact_angle_2=contact_angle_2,
        subtended_angle=subtended_angle,
        **kelvin_kwargs,
    )
    layer = _layer_thickness(adsorbed_layer, as_relative_humidity(relative_humidity))
    out = h_men + layer
    return set_attrs(out, "water_height")
