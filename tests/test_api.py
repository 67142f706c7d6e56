"""The public API: every name public before the issue-11 restructure is still ``rs.<name>``."""

import roughstick as rs

#: ``roughstick.__all__`` at the start of round 2 (frozen copy /work/base).
PUBLIC_BEFORE_RESTRUCTURE = [
    'Cantilever', 'Material', 'PAPER_CANTILEVER', 'PAPER_HUMIDITIES', 'POLYSILICON', 'SPHERE_MODELS',
    'TABLE4', 'VALIDITY_BOUND', 'ValidityWarning', 'adhesion_summary',
    'adhesive_energy_from_crack_length', 'adhesive_energy_kernel', 'adsorbed_layer',
    'as_relative_humidity', 'asperity_statistics', 'average_psd', 'bem_contact_curves',
    'binomial_interval', 'cantilever_distance_grid', 'cantilever_moments', 'cantilever_psd',
    'check_cf', 'choose_cutoff', 'confidence_band', 'contact_distance_grid',
    'crack_length_from_adhesive_energy', 'critical_adhesive_energy', 'crossing_humidity',
    'crossing_length', 'ensemble_distance_grid', 'ensemble_ecdf', 'ensemble_histogram',
    'fit_self_affine', 'generate_surfaces', 'gw_contact_curves', 'gw_cutoff_study', 'hertz_modulus',
    'interaction_zone_psd', 'interaction_zone_shape', 'interpolate_psd', 'isotropic_to_2d',
    'kelvin_radius', 'laplace_pressure', 'level', 'measured_adhesion', 'meniscus_height',
    'model_error', 'moments_from_asperities', 'no_adsorbed_layer', 'open_dataset', 'open_ensemble',
    'periodic_offset_coefficient', 'plasticity_index', 'power_spectrum', 'predict_adhesive_energy',
    'progress_bar', 'psd_isotropic', 'psd_moments', 'psd_summary', 'quantile_interval', 'read_afm',
    'reduced_modulus', 'rough_contact_curves', 'roughness_moments', 'roughness_statistics',
    'run_ensemble', 'select_model', 'self_affine_moments', 'self_affine_psd',
    'sphere_adhesive_energy', 'sphere_contact', 'sphere_force', 'step_adsorbed_layer',
    'stiction_probability', 'stiction_risk', 'submap_psd', 'submap_variance_check',
    'summit_density', 'summit_joint_density', 'surface_filter', 'surface_size_study',
    'transition_parameter', 'validate_height', 'validity_map', 'warn_if_outside_validity',
    'water_height', 'write',
]


def test_every_public_name_of_round_one_is_still_there():
    from roughstick._renamed import RENAMED

    missing = [n for n in PUBLIC_BEFORE_RESTRUCTURE if not hasattr(rs, n)]
    assert not missing, f"rs.<name> no longer works for {missing}"
    # each is public at the top level, or served from its new home with a DeprecationWarning
    assert set(PUBLIC_BEFORE_RESTRUCTURE) <= set(rs.__all__) | set(RENAMED)


def test_all_is_sorted_unique_and_resolvable():
    assert list(rs.__all__) == sorted(set(rs.__all__))
    for name in rs.__all__:
        assert getattr(rs, name) is not None, name


def test_public_namespaces():
    for ns in ("io", "testing", "conventions", "constants", "materials"):
        assert hasattr(rs, ns), ns
