"""The tables and keys of every ``roughstick`` command's TOML file: one :class:`Field` per key.

The dialect (units in values, fractions for humidity, refusal of unknown keys) is applied by
:mod:`roughstick.cli._config`; docs/configuration.md lists these tables (tests/test_docs.py checks
it against :data:`SCHEMAS`).
"""

from __future__ import annotations

import dataclasses
from typing import Any

from ..contact import MODEL_CHOICES

__all__ = ["Field", "SCHEMAS"]


@dataclasses.dataclass(frozen=True)
class Field:
    """One key of a table: its kind, whether required, its default and a one-line description.

    ``kind`` is a kind of quantity of :data:`roughstick._core.units.KINDS` (a unit string is then
    required) or one of ``int``, ``number``, ``fraction``, ``bool``, ``str``, ``choice``,
    ``path``, ``map`` (a path, or ``"bundled:S1A"`` for a sample map shipped with roughstick),
    ``n`` (an integer >= 1 or "auto"), ``shape`` (an integer or [ny, nx]),
    ``relative_humidity``; ``many`` makes it a list of those. For a ``fraction``, ``percent``
    says whether a number from 1 to 100 may be a percentage typed for it (a probability, a
    confidence); False for a ratio (a coefficient of variation, a tolerance). ``replaces`` names
    the old keys of this one: a file that still writes one is refused, naming this key.
    """

    kind: str
    doc: str
    default: Any = None
    required: bool = False
    many: bool = False
    minimum: float | None = None
    choices: tuple = ()
    power: int = 1
    percent: bool = True
    replaces: tuple = ()


F = Field
_SMALL_P = {  # the small-probability methods' stopping rule: [risk] of risk, [ensemble] of beam
    "target_cv": F("fraction", "method 'subset'/'monte_carlo': stop when the cv of P(stuck) is at most this (subset: after >= 3 runs that agree)", default=0.3,
                   percent=False),
    "max_evaluations": F("int", "method 'subset'/'monte_carlo': evaluations allowed per length, RH (and layer)", default=20000, minimum=10),
    "n_per_level": F("int", "method 'subset': samples per level (a multiple of 5: p0 = 0.2)", default=1000, minimum=10)}
#: The contact model's choices (its key: ``model`` in [risk] of risk and [bank] of beam, as the
#: Python keyword; ``contact_model`` in [ensemble] of run): ``model``.
_CONTACT_MODEL = ("contact model of roughstick.contact.curves: 'modified_dmt' (Eq. 16), 'gw', 'fft_bem', "
                  "'bem' or 'auto' (the cheapest model measured within 10 % on these surfaces)")
_COMMON = {
    "material": {
        "name": F("str", "material of both bodies: a name roughstick knows ('polysilicon', the "
                  "default), or the label of the constants below"),
        "youngs_modulus": F("pressure", "Young's modulus of both bodies, e.g. '250 GPa' (with "
                            "poisson_ratio for a film roughstick does not know by name)"),
        "poisson_ratio": F("number", "Poisson ratio of both bodies, e.g. 0.23", minimum=-1.0),
    },
    "surface": {
        "spacing": F("length", "pixel size of the generated surfaces", required=True),
        "size": F("length", "side of the generated surfaces (or [y, x]); or give shape", many=True),
        "shape": F("shape", "pixels of the generated surfaces: n or [ny, nx]; or give size"),
    },
    "output": {
        "folder": F("path", "output folder (relative to the config file)"),
        "figures": F("bool", "write PNG figures", default=True),
        "overwrite": F("bool", "replace a run with other parameters in the folder", default=False),
    },
    "run": {
        "scheduler": F("str", "'threads', 'sync', 'processes' or tcp://host:port of a dask cluster"),
        "connect_timeout": F("number", "seconds to wait for a distributed scheduler", default=5.0,
                             minimum=0.0),
        "progress": F("bool", "show a progress bar (default: when on a terminal)"),
    },
}

#: Tables and keys of each command's configuration file.
SCHEMAS: dict[str, dict[str, dict[str, Field]]] = {
    "run": {
        "": {"title": F("str", "title of the run (figures, NetCDF)")},
        "psd": {
            "source": F("choice", "where the PSD comes from", required=True,
                        choices=("samples", "moments", "file")),
            "files": F("map", "height maps (source = 'samples'): paths, or 'bundled:S1A' ... 'bundled:S2C' "
                       "for the sample maps shipped with roughstick", many=True),
            "submaps": F("int", "sub-maps per map (paper scheme 3)", default=16, minimum=1),
            "level": F("choice", "what is removed from each map as it is read (source = 'samples'): "
                       "auto = its least-squares plane unless the map is periodic or levelled "
                       "already, as roughstick psd and curves do", default="auto",
                       choices=("auto", "plane", "mean", "line", "none")),
            "window": F("choice", "FFT window of the PSD (source = 'samples'): auto = Hann on "
                        "measured maps (docs/topography_psd.md), none = the paper's", default="auto",
                        choices=("auto", "hann", "none")),
            "qmax": F("wavevector", "high-wavevector cutoff (Table 3)"),
            "m0": F("area", "height variance (source = 'moments'), e.g. '15.7 nm2'"),
            "m2": F("number", "slope variance (dimensionless, source = 'moments')", minimum=0.0),
            "m4": F("inverse_area", "curvature variance (source = 'moments'), e.g. '5.08e-4 nm-2'"),
            "path": F("path", "NetCDF PSD (source = 'file')"),
            "variable": F("str", "variable of the PSD file", default="psd"),
            "num_q": F("int", "wavevector points of the Eq. 37 PSD", default=4096, minimum=16),
        },
        "surface": {
            **_COMMON["surface"],
            "height_distribution": F(
                "choice", "height distribution of the generated surfaces: 'auto' = the maps' own "
                "when [psd] source = 'samples' and they are not Gaussian within their sampling "
                "error, else Gaussian; 'maps' (their own), 'gaussian', or 'johnson' (from "
                "skewness and kurtosis)", default="auto", choices=("auto", "maps", "gaussian", "johnson")),
            "skewness": F("number", "height skewness of height_distribution = 'johnson'"),
            "kurtosis": F("number", "height kurtosis (3 for a Gaussian) of height_distribution = "
                          "'johnson'", minimum=1.0),
            "distribution_method": F("choice", "how a height distribution is imposed: 'translation' "
                                     "(a transformed Gaussian surface, pre-corrected PSD) or "
                                     "'iaaft' (docs/generation.md)", default="translation",
                                     choices=("translation", "iaaft")),
        },
        "ensemble": {
            "n": F("n", "number of surfaces (>= 1) or 'auto'", required=True),
            "relative_humidity": F("relative_humidity", "humidities as fractions", required=True,
                                   many=True),
            "seed": F("int", "root seed", default=0, minimum=0),
            "chunks": F("int", "realizations per block (one NetCDF file each)", minimum=1),
            "adsorbed_layer": F("choice", "adsorbed water layer model", default="paper",
                                choices=("paper", "none")),
            "batch": F("int", "n = 'auto': surfaces added per batch", minimum=1),
            "tolerance": F("fraction", "n = 'auto': relative change of the band that stops it", percent=False),
            "n_max": F("int", "n = 'auto': at most this many surfaces", minimum=1),
            "patience": F("int", "n = 'auto': consecutive stable batches", minimum=1),
            "distance_points": F("int", "points of the distance grid", default=200, minimum=8),
            "distance_lower": F("number", "bottom of the distance grid in units of the rms height",
                                default=1.5, minimum=0.0),
            "model": F("choice", _CONTACT_MODEL + "; 'auto' from n = 200 on: the modified DMT on "
                       "every surface and the chosen model on a subset sized by a pilot "
                       "(multi-fidelity)", default="auto",
                       choices=MODEL_CHOICES,
                       replaces=("contact_model",)),
        },
        "material": _COMMON["material"],
        "output": _COMMON["output"],
        "run": _COMMON["run"],
    },
    "risk": {
        "beam": {
            "width": F("length", "beam width", default=30e-6),
            "thickness": F("length", "beam thickness", default=2.62e-6),
            "gap": F("length", "beam underside to landing pad", default=1.9e-6),
            "youngs_modulus": F("pressure", "Young's modulus of the beam (default: the [material]'s, "
                                "164 GPa for poly-silicon)"),
            "interaction_length": F("length", "Δs of the interaction zone (default: thickness)"),
            "lengths": F("length", "the beam lengths to assess", many=True),
        },
        "surface": {
            "roughness": F("length", "rms of the beam underside and of the landing pad", many=True),
            "asperity_radius": F("length", "mean asperity radius of the equivalent surface"),
            "asperity_density": F("inverse_area", "asperities per area, e.g. '80.1 um-2'"),
            "qmax": F("wavevector", "high-wavevector cutoff"),
            "spacing": F("length", "pixel size", default=5e-9),
            "shape": F("shape", "pixels (along, across the beam); default the whole zone"),
            "psd": F("path", "a NetCDF PSD measured on your films (variable 'psd')"),
            "height_distribution": F(
                "choice", "height distribution of the zones' surfaces (every method): "
                "'gaussian' (the paper's), 'maps' (that of the measured maps of [surface] maps) or "
                "'johnson' (from skewness and kurtosis)", default="gaussian",
                choices=("gaussian", "maps", "johnson")),
            "maps": F("map", "measured height maps of your film (height_distribution = 'maps')",
                      many=True),
            "skewness": F("number", "height skewness of height_distribution = 'johnson'"),
            "kurtosis": F("number", "height kurtosis (3 for a Gaussian) of height_distribution = "
                          "'johnson'", minimum=1.0),
        },
        "ensemble": {
            "n": F("n", "surfaces per adsorbed-layer model (>= 1) or 'auto'", default=20),
            "relative_humidity": F("relative_humidity", "humidities as fractions", many=True,
                                   default=[round(0.30 + 0.05 * k, 2) for k in range(14)]),
            "adsorbed_layer": F("choice", "adsorbed water layer model(s)", many=True,
                                default=["none", "paper"], choices=("paper", "none")),
            "seed": F("int", "root seed", default=0, minimum=0),
            "chunks": F("int", "realizations per block", minimum=1),
            "stream": F("bool", "stream blocks to disk (a re-run resumes)", default=True),
            "adhesive_energy": F("path", "skip the simulation: a Γ sample (realization, rh)"),
        },
        "risk": {
            "levels": F("fraction", "P(stuck) levels for the crossing humidity/length", many=True,
                        default=[0.05, 0.5, 0.95]),
            "confidence": F("fraction", "coverage of the interval on P(stuck)", default=0.95),
            "interval": F("choice", "binomial interval", default="wilson",
                          choices=("wilson", "clopper-pearson", "exact")),
            "quantiles": F("fraction", "quantiles of Γ saved", many=True,
                           default=[0.025, 0.5, 0.975]),
            "method": F("choice", "'count': count stuck surfaces of [ensemble]; 'subset': subset "
                                  "simulation of P(stuck) on zones of [surface] shape (small "
                                  "probabilities); 'monte_carlo': crude Monte Carlo on those zones; "
                                  "'strips': released beams on the strips of their own zone, small "
                                  "probabilities included (sub-zones recombined)",
                        default="count", choices=("count", "subset", "monte_carlo", "strips")), **_SMALL_P,
            "n_subzones": F("int", "method 'strips': Eq. 16 sub-zones recombined into strips",
                            default=12000, minimum=48),
            "n_accurate": F("int", "method 'strips' with model 'auto': of them, through fft_bem where the "
                                   "answer depends on the model (doubled, up to twice, at humidities where the "
                                   "pairs hold a cv of P(stuck) above 0.6 x target_cv)", default=240, minimum=8),
            "refine_crossing": F("bool", "method 'strips': up to 3 more calls at the humidities where a beam's "
                                         "P(stuck) crosses one of levels, so that each crossing's interval rests "
                                         "on estimates near it, not on the interpolation between distant "
                                         "humidities (each point costs one humidity of the models; they join rh)",
                                 default=False),
            "model_band": F("number", "method 'strips': relative error of the strips' Γ from the models, "
                                      "[below, above] (default [-0.005, 0.045] with model 'auto', none with "
                                      "one model alone); P(stuck) is also bounded at both ends", many=True),
            "model": F("choice", "contact model: method 'count', that of the ensemble's "
                               "surfaces (" + _CONTACT_MODEL.split(": ", 1)[1] + "); 'subset'/"
                               "'monte_carlo', that of each zone: 'modified_dmt' (Eq. 16, ~1 ms per 128 x "
                               "128 zone; its failure states re-checked by the BEM), 'fft_bem' (~45 "
                               "ms; needed where Eq. 16's tail is an artefact, docs/rare_events.md) or "
                               "'auto' (the cheaper of the two measured within 10 % on these zones)",
                               default="auto",
                               replaces=("contact_model",),
                               choices=MODEL_CHOICES),
        },
        "material": _COMMON["material"],
        "measured": {  # an array of tables: [[measured]]
            "label": F("str", "legend label", default="measured"),
            "file": F("path", "CSV: header 'relative_humidity,crack_length [um]' "
                              "(or 'adhesive_energy [mJ m-2]')"),
            "relative_humidity": F("relative_humidity", "humidities as fractions", many=True),
            "crack_length": F("length", "measured crack lengths", many=True),
            "adhesive_energy": F("energy_per_area", "measured adhesive energies", many=True),
        },
        "output": _COMMON["output"],
        "run": {"scheduler": _COMMON["run"]["scheduler"]},
    },
    "beam": {
        "beam": {
            "lengths": F("length", "the beam lengths to simulate", many=True, required=True),
            "width": F("length", "beam width", default=30e-6),
            "thickness": F("length", "beam thickness", default=2.62e-6),
            "gap": F("length", "beam underside to landing pad", default=1.9e-6),
            "youngs_modulus": F("pressure", "Young's modulus of the beam (default: the [material]'s, "
                                "164 GPa for poly-silicon)"),
            "patch_length": F("length", "length of one patch along the beam (default: thickness); at most "
                              "the shortest of lengths"),
        },
        "surface": {
            "spacing": F("length", "pixel size of the patch surfaces", required=True),
            "shape": F("shape", "pixels of one patch surface: n or [ny, nx]; default the beam's own patch, "
                       "patch_length x width, composed of sub-zones that tile it (a smaller patch warns)"),
            "psd": F("path", "a NetCDF PSD (variable 'psd'); default the paper's Table 4 (Eq. 37)"),
            "height_distribution": F(
                "choice", "height distribution of the patch surfaces: 'gaussian' (the paper's), "
                "'maps' (that of the measured maps of [surface] maps) or 'johnson' (from skewness "
                "and kurtosis)", default="gaussian", choices=("gaussian", "maps", "johnson")),
            "maps": F("map", "measured height maps of your film (height_distribution = 'maps')",
                      many=True),
            "skewness": F("number", "height skewness of height_distribution = 'johnson'"),
            "kurtosis": F("number", "height kurtosis (3 for a Gaussian) of height_distribution = "
                          "'johnson'", minimum=1.0),
        },
        "ensemble": {
            "n": F("int", "beams per length and RH", default=1000, minimum=1),
            "relative_humidity": F("relative_humidity", "humidities as fractions", many=True,
                                   required=True),
            "protocol": F("choice", "release afresh at each RH, or RH stepped up with the beam in place",
                          default="release", choices=("release", "step_up")),
            "beam_model": F("choice", "structural model: sharp-front energy balance (fast) or the "
                            "cohesive Euler-Bernoulli beam on each patch's law (~0.5 s per beam)",
                            default="sharp_front", choices=("sharp_front", "cohesive")),
            "seed": F("int", "root seed of the beams", default=0, minimum=0),
            "method": F("choice", "'count': count stuck beams among n; 'subset'/'monte_carlo': P(stuck) on the bank to target_cv (sharp front; down to 1/laws)",
                        default="count", choices=("count", "subset", "monte_carlo")), **_SMALL_P,
        },
        "bank": {
            "laws": F("int", "patch laws in the bank (surfaces computed once per RH)", default=1000,
                      minimum=1),
            "seed": F("int", "root seed of the patch surfaces", default=0, minimum=0),
            "model": F("choice", "contact model of the patch laws (default 'modified_dmt': on the "
                               "beam's strips the FFT-BEM costs about 10 min per law): "
                               + _CONTACT_MODEL.split(": ", 1)[1],
                               default="modified_dmt",
                               replaces=("contact_model",),
                               choices=MODEL_CHOICES),
            "cache": F("path", "folder of the bank cache (relative to the file)",
                       default="beam-bank-cache"),
        },
        "material": _COMMON["material"],
        "output": _COMMON["output"],
    },
}
