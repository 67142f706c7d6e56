"""Old top-level names of roughstick and where they live now (``rs.<old>`` still works, with a
``DeprecationWarning`` naming the new name: see ``roughstick.__getattr__``).

Each value is a dotted path below ``roughstick`` (``"contact.curves"``). One section per area of
the package; add a line to your own section only.
"""

RENAMED: dict[str, str] = {}

# ---------------------------------------------------------------------------- _core, io, surface
RENAMED.update({
    "read_afm": "io.read_afm",
    "write": "io.write",
    "open_dataset": "io.open_dataset",
    "check_cf": "io.check_cf",
    "validate_height": "surface.validate_height",
    "level": "surface.level",
    "power_spectrum": "surface.power_spectrum",
    "psd_isotropic": "surface.psd_isotropic",
    "average_psd": "surface.average_psd",
    "submap_psd": "surface.submap_psd",
    "submap_variance_check": "surface.submap_variance_check",
    "interpolate_psd": "surface.interpolate_psd",
    "isotropic_to_2d": "surface.isotropic_to_2d",
    "average_psd_common": "surface.average_psd_common",
    "summit_density": "surface.summit_density",
    "roughness_moments": "surface.roughness_moments",
    "psd_moments": "surface.psd_moments",
    "self_affine_moments": "surface.self_affine_moments",
    "moments_from_asperities": "surface.moments_from_asperities",
    "choose_cutoff": "surface.choose_cutoff",
    "asperity_statistics": "surface.asperity_statistics",
    "plasticity_index": "surface.plasticity_index",
    "validate_profile": "surface.validate_profile",
    "level_profile": "surface.level_profile",
    "profile_psd": "surface.profile_psd",
    "project_psd": "surface.project_psd",
    "profile_moments": "surface.profile_moments",
    "self_affine_psd": "surface.self_affine_psd",
    "fit_self_affine": "surface.fit_self_affine",
    "generate_surfaces": "surface.generate_surfaces",
    "surface_filter": "surface.surface_filter",
    "ExtrapolatedPSDWarning": "surface.ExtrapolatedPSDWarning",
    "roughness_statistics": "surface.roughness_statistics",
    "psd_summary": "surface.psd_summary",
    "moments_si": "_core.validate.moments_si",  # plumbing: checks a moments Dataset
    "reduced_modulus": "materials.reduced_modulus",
    "hertz_modulus": "materials.hertz_modulus",
    "as_relative_humidity": "contact.as_relative_humidity",
})


# --------------------------------------------------------------------------------------- contact
RENAMED.update({
    # renamed, or plumbing out of the public namespace
    "rough_contact_curves": "contact.curves",
    "adhesion_summary": "contact.summary",
    "gw_contact_curves": "contact.gw_curves",
    "fft_bem_contact_curves": "contact.fft_bem_curves",
    "bem_contact_curves": "contact.bem_curves",
    "modified_dmt_kernel": "contact.modified_dmt.kernel",
    "adhesion_summary_kernel": "contact.adhesion.summary_kernel",
    "adhesive_energy_kernel": "contact.adhesion.adhesive_energy_kernel",
    "periodic_offset_coefficient": "contact.fft_bem.periodic_offset_coefficient",
    "MODEL_COST_ORDER": "contact.MODELS",
    "CONTACT_MODELS": "contact.MODELS",
    "GROUP_FEATURES": "contact.trust.validity.GROUP_FEATURES",
    # moved, same name
    **{name: f"contact.{name}" for name in (
        "CurveGridWarning", "ValidityWarning", "ErrorBound", "FINE_PIXEL", "PixelResolutionWarning",
        "RESOLVED_NECK_PIXELS", "SPHERE_MODELS", "VALIDITY_BOUND", "adsorbed_layer",
        "contact_distance_grid", "expected_surface_groups", "gw_cutoff_study", "kelvin_radius",
        "laplace_pressure", "meniscus_height", "model_error", "modified_dmt_curves",
        "no_adsorbed_layer", "resample_pixels", "resolution_study", "select_model",
        "sphere_adhesive_energy", "sphere_contact", "sphere_force", "step_adsorbed_layer",
        "summit_joint_density", "surface_groups", "transition_parameter", "validity_map",
        "warn_if_outside_validity", "warn_if_unresolved", "water_height")},
})


# ------------------------------------------------------------------------ ensemble, paper, misc
RENAMED.update({
    "run_ensemble": "ensemble.run",
    "ensemble_distance_grid": "ensemble.distance_grid",
    "ensemble_histogram": "ensemble.histogram",
    "ensemble_ecdf": "ensemble.ecdf",
    "surface_size_study": "ensemble.surface_size_study",
    "open_ensemble": "ensemble.open_ensemble",
    "confidence_band": "ensemble.confidence_band",
    "quantile_interval": "ensemble.quantile_interval",
    "band_summary": "ensemble.band_summary",
    "min_samples_to_bound": "ensemble.min_samples_to_bound",
    "binomial_interval": "ensemble.binomial_interval",
    # plumbing shared by the stages, no longer public
    "progress_bar": "_core.progress.progress_bar",
    "surface_shape": "_core.validate.surface_shape",
    "order_statistic_ranks": "_core.intervals.order_statistic_ranks",
    "interval_method": "_core.intervals.interval_method",
    "median_interval": "_core.intervals.median_interval",
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
