"""Elastic materials and the combined moduli of two bodies in contact."""

from __future__ import annotations

from dataclasses import dataclass

from .constants import POLYSILICON_POISSON_RATIO, POLYSILICON_YOUNGS_MODULUS
from .validate import PLAUSIBLE_MODULUS, check_plausible_value, check_positive_block

__all__ = ["Material", "POLYSILICON", "reduced_modulus", "hertz_modulus"]


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


def reduced_modulus(material1: Material = POLYSILICON, material2: Material | None = None) -> float:
    r"""Contact modulus :math:`E^* = [(1-\nu_1^2)/E_1 + (1-\nu_2^2)/E_2]^{-1}` [Pa].

    Two poly-silicon bodies give 86.6 GPa. ``material2=None`` means the same as ``material1``.
    """
    m2 = material1 if material2 is None else material2
    return 1.0 / (
        (1 - material1.poisson_ratio**2) / material1.youngs_modulus
        + (1 - m2.poisson_ratio**2) / m2.youngs_modulus
    )


def hertz_modulus(material1: Material = POLYSILICON, material2: Material | None = None) -> float:
    r"""The paper's :math:`K = \tfrac{4}{3} E^*` of Eq. 7 and Eq. 10 [Pa] (115.4 GPa for poly-Si)."""
    return 4.0 / 3.0 * reduced_modulus(material1, material2)
