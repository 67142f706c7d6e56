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
})


# ---------------------------------------------------------------- stiction, beam, reliability
RENAMED.update({
})
