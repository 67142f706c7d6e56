"""Elastic materials and the combined moduli of two bodies in contact."""

from __future__ import annotations

from dataclasses import dataclass

from .constants import POLYSILICON_POISSON_RATIO, POLYSILICON_YOUNGS_MODULUS
from .validate import PLAUSIBLE_MODULUS, check_plausible_value, check_positive_block

__all__ = ["Material", "POLYSILICON", "MATERIALS", "material_from", "material_attrs",
           "reduced_modulus", "hertz_modulus"]


@dataclass(frozen=True)
class Material:
    """An isotropic elastic solid.

    Parameters
    ----------
    youngs_modulus : float
        Young's modulus E [Pa], 0.1 MPa-2 TPa (a value outside, e.g. 164 meant as GPa, is
        refused as a unit slip), or >= 1e18 for a rigid body.
    poisson_ratio : float
        Poisson ratio nu, in (-1, 0.5].
    hardness : float, optional
        Indentation hardness H [Pa], used by the plasticity index (Eq. 15); same range.
    name : str
        Label recorded in output attributes.
    """

    youngs_modulus: float = POLYSILICON_YOUNGS_MODULUS
    poisson_ratio: float = POLYSILICON_POISSON_RATIO
    hardness: float | None = None
    name: str = "poly-silicon"

    def __post_init__(self):
        check_positive_block(self.youngs_modulus, "youngs_modulus",
                             "Pass SI units (Pa): poly-silicon is 164e9.", finite=True)
        if not -1 < self.poisson_ratio <= 0.5:
            raise ValueError(f"poisson_ratio must lie in (-1, 0.5], got {self.poisson_ratio!r}.")
        check_plausible_value(self.youngs_modulus, name="youngs_modulus", kind="pressure",
                              bounds=PLAUSIBLE_MODULUS, what="a solid")
        if self.hardness is not None:
            check_positive_block(self.hardness, "hardness", "Pass SI units (Pa).", finite=True)
            check_plausible_value(self.hardness, name="hardness", kind="pressure",
                                  bounds=PLAUSIBLE_MODULUS, what="a solid's hardness")


#: Poly-silicon, E = 164 GPa, nu = 0.23 (paper §2.2.5).
POLYSILICON = Material()

#: Materials known by name (``material_from(name)``, the [material] table of the configuration
#: files, ``roughstick curves --material``); another film is given by its elastic constants.
MATERIALS = {"polysilicon": POLYSILICON}


def _known(name: str) -> Material | None:
    key = "".join(c for c in name.lower() if c.isalnum())
    return MATERIALS.get({"polysi": "polysilicon"}.get(key, key))


def material_from(name: str | None = None, *, youngs_modulus: float | None = None,
                  poisson_ratio: float | None = None) -> Material:
    """A material by name, or by its elastic constants.

    Parameters
    ----------
    name : str, optional
        A name of :data:`MATERIALS` (spelling and case are free: ``"poly-Si"``,
        ``"polysilicon"``), whose constants the two keywords may replace; or, with both
        keywords, the label of a film roughstick does not know by name. None: poly-silicon,
        unless both constants are given.
    youngs_modulus : float, optional
        Young's modulus [Pa].
    poisson_ratio : float, optional
        Poisson ratio.

    Returns
    -------
    Material

    Raises
    ------
    ValueError
        An unknown name without both constants, or one constant without a known name (naming
        the known materials and the constants to give).

    Examples
    --------
    >>> material_from("poly-Si").youngs_modulus
    164000000000.0
    >>> material_from("silicon nitride", youngs_modulus=250e9, poisson_ratio=0.23).name
    'silicon nitride'
    """
    base = None if name is None else _known(name)
    both = youngs_modulus is not None and poisson_ratio is not None
    if base is None and not both:
        if name is None and youngs_modulus is None and poisson_ratio is None:
            return POLYSILICON
        what = (f"no material named {name!r} is known (known: {sorted(MATERIALS)})" if name is not None
                and base is None else "one elastic constant alone does not make a material")
        raise ValueError(f"{what}; for another film give both youngs_modulus (e.g. 250 GPa) and "
                         "poisson_ratio (e.g. 0.23), with the name as its label.")
    base = POLYSILICON if base is None else base
    if not both and youngs_modulus is None and poisson_ratio is None:
        return base
    if name is None:
        label = "custom"
    elif _known(name) is None:
        label = name
    else:
        label = f"{base.name} (modified)"
    new = Material(youngs_modulus=base.youngs_modulus if youngs_modulus is None else float(youngs_modulus),
                    poisson_ratio=base.poisson_ratio if poisson_ratio is None else float(poisson_ratio),
                    name=label)
    same = (new.youngs_modulus, new.poisson_ratio) == (base.youngs_modulus, base.poisson_ratio)
    return base if same and name is not None and _known(name) is not None else new


def material_attrs(material: Material) -> dict:
    """The attributes an output records for the material of both bodies (SI; prefixed, so a
    beam's own ``youngs_modulus`` beside them keeps its meaning)."""
    return {"material": material.name, "material_youngs_modulus": float(material.youngs_modulus),
            "material_poisson_ratio": float(material.poisson_ratio)}


def as_material(material, *, name: str = "material") -> Material:
    """A :class:`Material`, or a name of :data:`MATERIALS` (spelling and case free: ``"poly-Si"``,
    ``"polysilicon"``, ``"poly-silicon"``), as a :class:`Material`; anything else is refused
    naming the known names and how to build one.

    Examples
    --------
    >>> from roughstick._core.materials import as_material
    >>> as_material("poly-Si").youngs_modulus
    164000000000.0
    """
    if isinstance(material, Material):
        return material
    build = ("for another solid build one, e.g. roughstick.Material(youngs_modulus=70e9, "
             "poisson_ratio=0.17, name='fused silica') (SI units)")
    if isinstance(material, str):
        known = _known(material)
        if known is not None:
            return known
        hint = ""
        if material.strip().lower() in ("silicon", "si", "c-si", "mono-si", "single-crystal silicon"):
            hint = (" Single-crystal silicon is anisotropic (E from 130 to 188 GPa with the direction): "
                    "give a Material for your orientation, e.g. roughstick.Material(youngs_modulus=169e9, "
                    "poisson_ratio=0.064, name='Si [110]'), or 'poly-silicon' for a polycrystalline film.")
        raise ValueError(f"{name}={material!r} is not a material roughstick knows; known names: "
                         "'poly-silicon' (also 'polysilicon', 'poly-Si': E = 164 GPa, nu = 0.23); "
                         f"{build}.{hint}")
    raise TypeError(f"{name} must be a roughstick.Material or a known name ('poly-silicon'), got "
                    f"{type(material).__name__}; {build}.")


def reduced_modulus(material1: Material = POLYSILICON, material2: Material | None = None) -> float:
    r"""Contact modulus :math:`E^* = [(1-\nu_1^2)/E_1 + (1-\nu_2^2)/E_2]^{-1}` [Pa].

    Two poly-silicon bodies give 86.6 GPa. ``material2=None`` means the same as ``material1``.
    Either may be a :class:`Material` or a known name (:data:`MATERIAL_NAMES`).
    """
    material1 = as_material(material1)
    m2 = material1 if material2 is None else as_material(material2, name="material2")
    return 1.0 / (
        (1 - material1.poisson_ratio**2) / material1.youngs_modulus
        + (1 - m2.poisson_ratio**2) / m2.youngs_modulus
    )


def hertz_modulus(material1: Material = POLYSILICON, material2: Material | None = None) -> float:
    r"""The paper's :math:`K = \tfrac{4}{3} E^*` of Eq. 7 and Eq. 10 [Pa] (115.4 GPa for poly-Si)."""
    return 4.0 / 3.0 * reduced_modulus(material1, material2)
