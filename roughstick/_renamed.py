"""Old top-level names of roughstick and where they live now (``rs.<old>`` still works, with a
``DeprecationWarning`` naming the new name: see ``roughstick.__getattr__``).

Each value is a dotted path below ``roughstick`` (``"contact.curves"``). One section per area of
the package; add a line to your own section only.
"""

RENAMED: dict[str, str] = {}

# ---------------------------------------------------------------------------- _core, io, surface
RENAMED.update({
})


# --------------------------------------------------------------------------------------- contact
RENAMED.update({
})


# ------------------------------------------------------------------------ ensemble, paper, misc
RENAMED.update({
})


# ---------------------------------------------------------------- stiction, beam, reliability
RENAMED.update({
    # P(stuck): one verb, stuck_probability(data, method=...) (the top-level stuck_probability,
    # on simulated beams, is that verb with method="count")
    "stiction_probability": "reliability.stuck_probability",          # method="count"
    "stiction_probability_subset": "reliability.stuck_probability",   # method="subset" on a PSD
    "beam_stiction_probability_subset": "reliability.stuck_probability",  # method="subset" on a bank
    "stiction_risk": "stiction.risk_summary",
    "failure_probability": "reliability.failure_probability",
    "subset_simulation": "reliability.subset_simulation",
    "weakest_link": "reliability.weakest_link",
    "surface_from_noise": "reliability.surface_from_noise",
    # the beam-scale model
    "simulate_beams": "beam.simulate",
    "beam_crack_length": "beam.crack_length",
    "build_patch_bank": "beam.build_patch_bank",
    "pressure_law_bank": "beam.pressure_law_bank",
    "PatchLaws": "beam.PatchLaws",
    "CohesiveRelease": "beam.CohesiveRelease",
    "release_cohesive_beam": "beam.release_cohesive",
    "step_cohesive_beam": "beam.step_cohesive",
    "short_range_pressure_law": "beam.short_range_pressure_law",
    # stiction/ keeps its names in its namespace: served from there once the top level drops them
    **{name: f"stiction.{name}" for name in (
        "PAPER_CANTILEVER", "PAPER_HUMIDITIES", "TABLE4", "adhesive_energy_from_crack_length",
        "crack_length_from_adhesive_energy", "critical_adhesive_energy", "crossing_humidity",
        "crossing_length", "measured_adhesion", "cantilever_moments", "cantilever_psd",
        "interaction_zone_shape", "interaction_zone_psd", "cantilever_distance_grid",
        "predict_adhesive_energy")},
})
