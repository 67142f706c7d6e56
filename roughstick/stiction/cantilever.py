r"""Cantilever beams stuck by adhesion: Eq. 36 both ways and the critical adhesive energy (§5.1).

An S-shaped cantilever stuck to its landing pad (Fig. 18b) detaches at the crack length
:math:`s`; its apparent adhesive energy follows from the beam geometry (Eq. 36, per unit width):

.. math:: \Gamma = \frac{3}{2} E \frac{h^2 t^3}{s^4},
   \qquad s = \left(\frac{3 E h^2 t^3}{2\Gamma}\right)^{1/4}.

A beam of length :math:`l` cannot have a crack longer than itself: it stays stuck when the
adhesive energy of the interaction zone exceeds :math:`\Gamma_{crit} = \Gamma(s = l)`
(:func:`critical_adhesive_energy`). The probabilities built on it are :mod:`.risk`; the model of
the interaction zone is :mod:`.interaction_zone`; the beam-scale stochastic model (Hoang et al.
2017) is :mod:`roughstick.beam`.

References
----------
Mastrangelo and Hsu (1993), doi:10.1109/84.232594; de Boer et al. (1998), doi:10.1557/PROC-518-131;
paper Eq. 36.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from .._core import constants as C
from .._core.api import renamed_keywords
from .._core.conventions import set_attrs
from .._core.references import PAPER, cite
from .._core.units import as_si, require
from .._core.validate import (
    PLAUSIBLE_BEAM_DIMENSION,
    PLAUSIBLE_BEAM_LENGTH,
    PLAUSIBLE_MODULUS,
    check_plausible_value,
    positive,
)

__all__ = [
    "Cantilever",
    "PAPER_CANTILEVER",
    "adhesive_energy_from_crack_length",
    "crack_length_from_adhesive_energy",
    "critical_adhesive_energy",
]

REFERENCES = cite((PAPER, "Eq. 36, Table 4, Eq. 37"), ("deboer1998", "cantilever tests"),
                  ("mastrangelo1993", "S-shaped beam energy"))


@dataclass(frozen=True)
class Cantilever:
    """Geometry and material of a cantilever beam over a landing pad (Fig. 18a).

    All values SI. The defaults are the beams of de Boer et al. used in paper §5.1.

    Parameters
    ----------
    length : float
        Beam length l [m] (1500 µm).
    width : float
        Beam width w [m] (30 µm); sets the width of the interaction zone.
    thickness : float
        Beam thickness t [m] (2.62 µm).
    gap : float
        Gap h between the beam's lower side and the landing pad [m] (1.9 µm).
    youngs_modulus : float
        Young's modulus E of the beam [Pa] (poly-silicon, 164 GPa).
    interaction_length : float or None
        Length :math:`\\Delta s` of the interaction zone behind the crack front [m]; None means
        the beam thickness, the paper's first approximation (§5.2).

    Examples
    --------
    >>> beam = rs.stiction.Cantilever(length=400e-6)
    >>> beam.interaction_area * 1e12  # µm², Δs × w
    78.6...
    """

    length: float = 1500e-6
    width: float = 30e-6
    thickness: float = 2.62e-6
    gap: float = 1.9e-6
    youngs_modulus: float = C.POLYSILICON_YOUNGS_MODULUS
    interaction_length: float | None = None

    def __post_init__(self):
        for name in ("length", "width", "thickness", "gap", "youngs_modulus", "interaction_length"):
            v = getattr(self, name)
            if name == "interaction_length" and v is None:
                continue
            if not (isinstance(v, (int, float, np.floating, np.integer)) and math.isfinite(v) and v > 0):
                unit = "Pa (poly-silicon: 164e9)" if name == "youngs_modulus" else "m (e.g. 2.62e-6)"
                raise ValueError(f"Cantilever.{name} must be a positive finite number in {unit}, got {v!r}.")
            kind, bounds = (("pressure", PLAUSIBLE_MODULUS) if name == "youngs_modulus" else
                            ("length", PLAUSIBLE_BEAM_LENGTH if name == "length" else PLAUSIBLE_BEAM_DIMENSION))
            check_plausible_value(v, name=f"Cantilever.{name}", kind=kind, bounds=bounds,
                                  what="a solid" if kind == "pressure" else "a MEMS beam")

    @property
    def interaction_zone_length(self) -> float:
        """:math:`\\Delta s` [m]: ``interaction_length`` or, if None, the beam thickness."""
        return self.thickness if self.interaction_length is None else self.interaction_length

    @property
    def interaction_area(self) -> float:
        """Area :math:`\\Delta s \\times w` of the interaction zone [m²]."""
        return self.interaction_zone_length * self.width

    @property
    def stiffness_term(self) -> float:
        """:math:`\\tfrac{3}{2} E h^2 t^3` [J m² = N m²], so that Γ = stiffness_term / s⁴."""
        return 1.5 * self.youngs_modulus * self.gap**2 * self.thickness**3

    def attrs(self) -> dict:
        """The beam parameters as NetCDF-friendly attributes (SI floats)."""
        return {
            "beam_width": self.width,
            "beam_thickness": self.thickness,
            "beam_gap": self.gap,
            "beam_youngs_modulus": self.youngs_modulus,
            "beam_interaction_length": self.interaction_zone_length,
        }

#: The cantilevers of paper §5.1 (de Boer et al.): w = 30 µm, t = 2.62 µm, l = 1500 µm,
#: h = 1.9 µm, E = 164 GPa.
PAPER_CANTILEVER = Cantilever()

_MAGNITUDES = "Adhesive energies and crack lengths are magnitudes in SI units (J m-2, m)."


def _nonnegative(value, kind, name):
    """``value`` in SI, checked >= 0 (NaN allowed: it propagates). Lazy data are checked lazily."""
    if isinstance(value, xr.Dataset):
        key = {"energy_per_area": "adhesive_energy", "length": "crack_length"}[kind]
        if key not in value:
            raise ValueError(
                f"{name}: the Dataset has no {key!r} variable (has {list(value.data_vars)}). "
                f"Pass the DataArray, e.g. ds[{key!r}]."
            )
        value = value[key]
    return positive(value, kind, name, _MAGNITUDES, allow_zero=True, arrays=True)


def adhesive_energy_from_crack_length(crack_length, *, beam: Cantilever = PAPER_CANTILEVER):
    r"""Apparent adhesive energy of an S-shaped stuck cantilever from its crack length (Eq. 36).

    Parameters
    ----------
    crack_length : float, array or xarray.DataArray
        Crack length :math:`s` (Fig. 18b): distance from the anchor to where the beam lands;
        SI metres, or a DataArray with length ``units`` (µm, nm, ... are converted).
    beam : Cantilever
        Beam thickness, gap and modulus (the length is not used).

    Returns
    -------
    float, numpy.ndarray or xarray.DataArray
        :math:`\Gamma` [J m-2], the same kind as the input (DataArrays get CF attrs).
        ``s = 0`` gives ``inf``; NaN propagates.

    Raises
    ------
    ValueError
        If a crack length is negative.

    Notes
    -----
    .. math:: \Gamma = \frac{3}{2} E \frac{h^2 t^3}{s^4}

    Euler-Bernoulli beam, clamped at the anchor, S-shaped (zero slope where it lands), small
    deflection; valid for :math:`s \gg t` and :math:`h \ll s`.

    References
    ----------
    Mastrangelo and Hsu (1993), doi:10.1109/84.232594; paper Eq. 36.

    Examples
    --------
    >>> round(rs.stiction.adhesive_energy_from_crack_length(1500e-6) * 1e6, 3)  # µJ m-2, s = l
    3.155
    """
    s = _nonnegative(crack_length, "length", "crack_length")
    if not isinstance(s, xr.DataArray):
        s = np.float64(s) if np.ndim(s) == 0 else s
    with np.errstate(divide="ignore"):
        out = beam.stiffness_term / s**4
    if np.ndim(out) == 0 and not isinstance(out, xr.DataArray):
        out = float(out)
    if isinstance(out, xr.DataArray):
        out = set_attrs(out.rename("adhesive_energy"), "surface_adhesive_energy")
        out.attrs["long_name"] = "apparent adhesive energy (Eq. 36, from the crack length)"
    return out


def crack_length_from_adhesive_energy(adhesive_energy, *, beam: Cantilever = PAPER_CANTILEVER):
    r"""Crack length :math:`s` at which an S-shaped cantilever settles, from Γ (inverse of Eq. 36).

    Applied to a Monte-Carlo sample of Γ (dims ``(realization, rh)``) it gives the distribution
    of the predicted crack length.

    Parameters
    ----------
    adhesive_energy : float, array, xarray.DataArray or xarray.Dataset
        :math:`\Gamma` [J m-2] (a Dataset must hold ``adhesive_energy``, e.g. the output of
        :func:`roughstick.contact.summary`). DataArrays need ``units`` (``J m-2``).
    beam : Cantilever
        Beam thickness, gap and modulus.

    Returns
    -------
    float, numpy.ndarray or xarray.DataArray
        :math:`s` [m]; ``Γ = 0`` (no adhesion) gives ``inf``: such a beam is free at any length.

    Raises
    ------
    ValueError
        If an adhesive energy is negative.

    Notes
    -----
    .. math:: s = \left(\frac{3 E h^2 t^3}{2\Gamma}\right)^{1/4}

    Examples
    --------
    >>> round(rs.stiction.crack_length_from_adhesive_energy(1e-3) * 1e6, 1)  # µm, Γ = 1 mJ m-2
    355.5
    """
    g = _nonnegative(adhesive_energy, "energy_per_area", "adhesive_energy")
    if not isinstance(g, xr.DataArray):
        g = np.float64(g) if np.ndim(g) == 0 else g
    with np.errstate(divide="ignore"):
        out = (beam.stiffness_term / g) ** 0.25
    if np.ndim(out) == 0 and not isinstance(out, xr.DataArray):
        out = float(out)
    if isinstance(out, xr.DataArray):
        out = set_attrs(out.rename("crack_length"), "crack_length")
    return out


def _beam_lengths(beam_length, beam: Cantilever):
    """Beam length(s) as float or a DataArray along ``beam_length`` (SI, validated > 0)."""
    if beam_length is None:
        return beam.length
    if isinstance(beam_length, xr.DataArray):
        v = require(beam_length, "length", name="beam_length")
        if v.chunks is not None:
            raise ValueError("beam lengths must be in memory (they are coordinates): pass beam_length.compute().")
    else:
        arr = np.asarray(as_si(beam_length, "length", name="beam_length"), dtype=float)
        if arr.ndim == 0:
            v = float(arr)
        elif arr.ndim == 1:
            v = xr.DataArray(arr, dims=("beam_length",), coords={"beam_length": arr})
        else:
            raise ValueError(f"beam_length must be a scalar or a 1-D sequence of beam lengths [m], got shape {arr.shape}.")
    data = v.data if isinstance(v, xr.DataArray) else v
    if not isinstance(data, np.ndarray | float) or np.any(~(np.asarray(data) > 0)) or np.any(~np.isfinite(data)):
        raise ValueError(f"beam lengths must be positive finite numbers in m (e.g. 400e-6), got {beam_length!r}.")
    if isinstance(v, xr.DataArray):
        v = set_attrs(v.rename("beam_length"), "beam_length")
    else:
        v = float(v)
    return v


@renamed_keywords(length="beam_length")
def critical_adhesive_energy(*, beam_length=None, beam: Cantilever = PAPER_CANTILEVER):
    r"""Adhesive energy above which a beam of length :math:`l` stays stuck: Eq. 36 at :math:`s = l`.

    Parameters
    ----------
    beam_length : float, sequence or xarray.DataArray, optional
        Beam length(s) [m]; default ``beam.length``. A sequence gives a ``beam_length`` dimension.
    beam : Cantilever
        Beam thickness, gap and modulus.

    Returns
    -------
    float or xarray.DataArray
        :math:`\Gamma_{crit} = \tfrac32 E h^2 t^3 / l^4` [J m-2].

    Examples
    --------
    >>> g = rs.stiction.critical_adhesive_energy(beam_length=[250e-6, 500e-6, 1500e-6])
    >>> (g.values * 1e6).round(3)  # µJ m-2
    array([4.088708e+03, 2.555440e+02, 3.155000e+00])
    """
    lengths = _beam_lengths(beam_length, beam)
    out = beam.stiffness_term / lengths**4
    if isinstance(out, xr.DataArray):
        out = set_attrs(out.rename("critical_adhesive_energy"), "critical_adhesive_energy")
    return out
