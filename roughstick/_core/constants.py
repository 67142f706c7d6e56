"""Physical constants and material defaults, SI floats (cf. MetPy ``constants/nounit.py``)."""

__all__ = [
    "GAS_CONSTANT",
    "WATER_MOLAR_VOLUME",
    "WATER_SURFACE_TENSION",
    "DEFAULT_TEMPERATURE",
    "KELVIN_LENGTH",
    "POLYSILICON_YOUNGS_MODULUS",
    "POLYSILICON_POISSON_RATIO",
    "SILICON_UNIT_CELL",
    "ADSORBED_LAYER_THICKNESS",
    "ADSORBED_LAYER_ONSET_RH",
]

#: Universal gas constant R [J mol-1 K-1].
GAS_CONSTANT = 8.314462618
#: Molar volume of liquid water V_m [m3 mol-1] (paper: 0.018 L/mol).
WATER_MOLAR_VOLUME = 18.0e-6
#: Liquid-vapour surface energy of water gamma_LG [N m-1] (paper: 0.072 N/m).
WATER_SURFACE_TENSION = 0.072
#: Temperature used by the paper [K].
DEFAULT_TEMPERATURE = 300.0
#: Kelvin length gamma V_m / (R T) as printed in the paper's Eq. 3 [m]: r_K = 0.53 nm / ln RH.
#: (The constants above give 0.5196 nm at 300 K; the paper's tables use 0.53 nm, so that is the
#: default; pass ``kelvin_length=None`` to compute it from gamma, V_m and T.)
KELVIN_LENGTH = 0.53e-9
#: Young's modulus of poly-silicon [Pa] (paper §2.2.5).
POLYSILICON_YOUNGS_MODULUS = 164e9
#: Poisson ratio of poly-silicon (paper §2.2.5).
POLYSILICON_POISSON_RATIO = 0.23
#: Lattice constant of silicon [m], the yardstick of the asperity-fit error (Eq. 23).
SILICON_UNIT_CELL = 0.543e-9
#: Adsorbed water layer on each surface above the onset humidity [m] (paper §2.1).
ADSORBED_LAYER_THICKNESS = 0.9e-9
#: Relative humidity above which the adsorbed layer is present (paper §2.1).
ADSORBED_LAYER_ONSET_RH = 0.65
