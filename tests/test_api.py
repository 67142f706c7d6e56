"""The public API: every name public before the issue-11 restructure is still ``rs.<name>``."""

import warnings

import pytest

import roughstick as rs
from roughstick._renamed import RENAMED

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
    """Still ``rs.<name>``: public, or an old name that says its new home (roughstick._renamed)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        missing = [n for n in PUBLIC_BEFORE_RESTRUCTURE if not hasattr(rs, n)]
    assert not missing, f"rs.<name> no longer works for {missing}"
    # public, or served from its new home with a DeprecationWarning (roughstick/_renamed.py)
    assert set(PUBLIC_BEFORE_RESTRUCTURE) <= set(rs.__all__) | set(RENAMED)


def test_all_is_unique_and_resolvable():
    """``__all__`` lists each name once, in the order of the data flow, and each one resolves."""
    assert len(rs.__all__) == len(set(rs.__all__))
    for name in rs.__all__:
        assert getattr(rs, name) is not None, name


def test_public_namespaces():
    for ns in ("io", "testing", "conventions", "constants", "materials"):
        assert hasattr(rs, ns), ns


#: ``roughstick.__all__`` of the release before the front door (133 names, flat).
PUBLIC_BEFORE_FRONT_DOOR = [
    'CONTACT_MODELS', 'Cantilever', 'CohesiveRelease', 'CurveGridWarning', 'ErrorBound',
    'ExtrapolatedPSDWarning', 'GROUP_FEATURES', 'MODEL_COST_ORDER', 'Material', 'PAPER_CANTILEVER',
    'PAPER_HUMIDITIES', 'POLYSILICON', 'PatchLaws', 'PixelResolutionWarning',
    'RESOLVED_NECK_PIXELS', 'SPHERE_MODELS', 'TABLE4', 'VALIDITY_BOUND', 'ValidityWarning',
    'adhesion_summary', 'adhesion_summary_kernel', 'adhesive_energy_from_crack_length',
    'adhesive_energy_kernel', 'adsorbed_layer', 'as_relative_humidity', 'asperity_statistics',
    'average_psd', 'average_psd_common', 'band_summary', 'beam_crack_length',
    'beam_stiction_probability_subset', 'bem_contact_curves', 'binomial_interval',
    'build_patch_bank', 'cantilever_distance_grid', 'cantilever_moments', 'cantilever_psd',
    'check_cf', 'choose_cutoff', 'confidence_band', 'contact_distance_grid',
    'crack_length_from_adhesive_energy', 'critical_adhesive_energy', 'crossing_humidity',
    'crossing_length', 'ensemble_distance_grid', 'ensemble_ecdf', 'ensemble_histogram',
    'expected_surface_groups', 'failure_probability', 'fft_bem_contact_curves', 'fit_self_affine',
    'generate_surfaces', 'gw_contact_curves', 'gw_cutoff_study', 'hertz_modulus',
    'interaction_zone_psd', 'interaction_zone_shape', 'interpolate_psd', 'interval_method',
    'isotropic_to_2d', 'kelvin_radius', 'laplace_pressure', 'level', 'level_profile',
    'measured_adhesion', 'median_interval', 'meniscus_height', 'min_samples_to_bound',
    'model_error', 'modified_dmt_curves', 'modified_dmt_kernel', 'moments_from_asperities',
    'moments_si', 'no_adsorbed_layer', 'open_dataset', 'open_ensemble', 'order_statistic_ranks',
    'periodic_offset_coefficient', 'plasticity_index', 'power_spectrum', 'predict_adhesive_energy',
    'pressure_law_bank', 'profile_moments', 'profile_psd', 'progress_bar', 'project_psd',
    'psd_isotropic', 'psd_moments', 'psd_summary', 'quantile_interval', 'read_afm',
    'reduced_modulus', 'release_cohesive_beam', 'resample_pixels', 'resolution_study',
    'rough_contact_curves', 'roughness_moments', 'roughness_statistics', 'run_ensemble',
    'select_model', 'self_affine_moments', 'self_affine_psd', 'short_range_pressure_law',
    'simulate_beams', 'sphere_adhesive_energy', 'sphere_contact', 'sphere_force',
    'step_adsorbed_layer', 'step_cohesive_beam', 'stiction_probability',
    'stiction_probability_subset', 'stiction_risk', 'stuck_probability', 'submap_psd',
    'submap_variance_check', 'subset_simulation', 'summit_density', 'summit_joint_density',
    'surface_filter', 'surface_from_noise', 'surface_groups', 'surface_shape',
    'surface_size_study', 'transition_parameter', 'validate_height', 'validate_profile',
    'validity_map', 'warn_if_outside_validity', 'warn_if_unresolved', 'water_height',
    'weakest_link', 'write',
]


def test_every_name_of_the_flat_api_still_works_or_names_its_new_home():
    """The top level is small now; every name it had still resolves: kept, or served from its
    new home with a DeprecationWarning that names it."""
    assert len(rs.__all__) <= 40
    for name in PUBLIC_BEFORE_FRONT_DOOR:
        if name in vars(rs):
            continue
        assert name in RENAMED, f"rs.{name} is gone without a forwarding entry in roughstick/_renamed.py"
        with pytest.warns(DeprecationWarning, match=r"is now roughstick\." + RENAMED[name].replace(".", r"\.")):
            obj = getattr(rs, name)
        assert obj is not None


def test_readme_docs_and_notebooks_use_only_the_new_names():
    """What a newcomer reads calls the namespaced API, not an old name that only forwards."""
    import pathlib
    import re

    root = pathlib.Path(__file__).resolve().parents[1]
    forwarded = sorted((n for n in RENAMED if n not in vars(rs)), key=len, reverse=True)
    pattern = re.compile(r"\brs\.(" + "|".join(forwarded) + r")\b")
    places = [root / "README.md", *sorted((root / "docs").rglob("*.md")),
              *sorted((root / "notebooks").glob("_build_*.py")), *sorted((root / "examples").glob("*.py"))]
    found = [f"{p.relative_to(root)}:{i}: rs.{m.group(1)}"
             for p in places if "_build" not in p.parent.name
             for i, line in enumerate(p.read_text().splitlines(), 1) for m in pattern.finditer(line)]
    assert not found, "old names (use the new home, roughstick/_renamed.py):\n" + "\n".join(found)
