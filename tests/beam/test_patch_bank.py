"""The patch-law bank: one patch per law at every RH, cached on disk and reused."""

import pathlib
import re
import warnings

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.beam.patch_bank import build_patch_bank


def _psd():
    c = rs.stiction.cantilever_psd()
    q = np.geomspace(1e5, 4e9, 200)
    return rs.surface.self_affine_psd(q, s0=float(c.s0), s1=float(c.s1), q0=float(c.q0), qmax=float(c.qmax))


def test_bank_cached_and_reused(tmp_path):
    kwargs = dict(model="modified_dmt", relative_humidity=[0.3, 0.9], n=2, shape=(16, 16), spacing=10e-9, seed=4,
                  cache_dir=tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        first = build_patch_bank(_psd(), **kwargs)
        again = build_patch_bank(_psd(), **kwargs)
        other = build_patch_bank(_psd(), **{**kwargs, "seed": 5})
    assert first.dims == ("law", "rh") and first.attrs["units"] == "J m-2"
    assert first.attrs["from_cache"] == 0 and again.attrs["from_cache"] == 1
    np.testing.assert_array_equal(first.values, again.values)
    assert other.attrs["cache_file"] != first.attrs["cache_file"]
    on_disk = xr.open_dataset(first.attrs["cache_file"])  # the cache file says what it is
    assert on_disk.attrs["Conventions"].startswith("CF") and "patch_bank(n=2" in on_disk.attrs["history"]
    assert on_disk.attrs["seed"] == 4 and list(on_disk.attrs["patch_shape"]) == [16, 16]
    on_disk.close()
    assert bool((first.isel(rh=1) > first.isel(rh=0)).all())  # capillary adhesion rises with RH
    ds = rs.beam.simulate(first, beam_length=1500e-6, n=5)
    assert ds.crack_length.dims == ("realization", "rh", "beam_length")


def test_a_damaged_cache_file_is_named_set_aside_and_rebuilt(tmp_path):
    kwargs = dict(model="modified_dmt", relative_humidity=[0.5], n=2, shape=(16, 16), spacing=40e-9, seed=4,
                  cache_dir=tmp_path, check_tail=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        first = build_patch_bank(_psd(), **kwargs)
        path = pathlib.Path(first.attrs["cache_file"])
        path.write_bytes(b"CDF\x01 truncated by a full disk")
        with pytest.warns(UserWarning, match=rf"cache file '{re.escape(str(path))}' could not be read.*"
                                             rf"moved it to {path.name}.corrupt and rebuilding"):
            rebuilt = build_patch_bank(_psd(), **kwargs)
        again = build_patch_bank(_psd(), **kwargs)  # the next run reads the rebuilt file
    assert rebuilt.attrs["from_cache"] == 0 and again.attrs["from_cache"] == 1
    np.testing.assert_array_equal(rebuilt.values, first.values)
    np.testing.assert_array_equal(again.values, first.values)
    assert (tmp_path / f"{path.name}.corrupt").read_bytes().startswith(b"CDF\x01")
    # a damaged part of an interrupted bank is recomputed too
    other = {**kwargs, "seed": 5}
    from roughstick.beam import patch_bank as pb

    key = pb._key(_psd(), np.array([0.5]), 2, (16, 16), 40e-9, 5, "modified_dmt")
    parts = tmp_path / f"patch_bank_{key}.parts"
    parts.mkdir()
    (parts / "laws_0000000_0000002.npy").write_bytes(b"\x93NUMPY truncated")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        with pytest.warns(UserWarning, match=r"laws_0000000_0000002.npy' could not be read.*recomputing laws 0-1"):
            resumed = build_patch_bank(_psd(), **other)
        plain = build_patch_bank(_psd(), **{**other, "cache_dir": None})
    np.testing.assert_array_equal(resumed.values, plain.values)


def test_a_cache_folder_that_cannot_be_written_is_refused_before_any_law(tmp_path, monkeypatch):
    from roughstick.beam import patch_bank as pb

    def no_work(*args, **kwargs):
        raise AssertionError("a law was computed before the cache folder was checked")

    monkeypatch.setattr(pb, "_law_energies", no_work)
    (tmp_path / "a-file").write_text("")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        with pytest.raises(PermissionError, match=r"cannot write the patch-bank cache folder .*a-file/cache.*"
                                                  r"pass a writable cache_dir="):
            build_patch_bank(_psd(), relative_humidity=[0.5], n=2, shape=(16, 16), spacing=40e-9,
                             cache_dir=tmp_path / "a-file" / "cache", model="modified_dmt")


def test_bank_bad_input():
    with pytest.raises(ValueError, match=r"did you mean 0.6\?"):
        build_patch_bank(_psd(), relative_humidity=60, spacing=1e-8, model="modified_dmt")
    with pytest.raises(TypeError, match="DataArray"):
        build_patch_bank(lambda q: q, relative_humidity=0.5, spacing=1e-8, model="modified_dmt")


def test_patches_shorter_than_four_correlation_lengths_are_flagged():
    """The independence assumption is checked against the PSD's correlation length (expected
    from the PSD, no surface needed) and recorded in the bank's attributes."""
    kw = dict(model="modified_dmt", relative_humidity=[0.5], n=1, seed=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        with pytest.warns(UserWarning, match="shorter than 4 correlation lengths"):
            small = build_patch_bank(_psd(), shape=(8, 8), spacing=5e-9, **kw)
        warnings.simplefilter("error", UserWarning)
        warnings.simplefilter("ignore", rs.ValidityWarning)
        large = build_patch_bank(_psd(), shape=(32, 32), spacing=40e-9, beam=rs.Cantilever(width=1.28e-6), **kw)
    corr = small.attrs["correlation_length"]
    assert 8 * 5e-9 < 4 * corr <= 32 * 40e-9
    assert "independent" in large.attrs["independence"]


def test_bank_parts_independent_and_resumed(tmp_path):
    """A law is the same whatever the parts (25 laws per dask task); an interrupted cached bank
    resumes from its finished parts (here a finished part planted on disk is read, not redone)."""
    from roughstick.beam import patch_bank as pb

    kw = dict(model="modified_dmt", relative_humidity=[0.5], n=27, shape=(16, 16), spacing=40e-9, seed=3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plain = build_patch_bank(_psd(), **kw)
        # law 26 alone, computed as its own part
        alone = pb._part(_psd(), 26, 27, np.array([0.5]), (16, 16), 40e-9, 3, "modified_dmt", None)
        np.testing.assert_array_equal(plain.values[26:], alone)
        key = pb._key(_psd(), np.array([0.5]), 27, (16, 16), 40e-9, 3, "modified_dmt")
        parts = tmp_path / f"patch_bank_{key}.parts"
        parts.mkdir()
        np.save(parts / "laws_0000000_0000025.npy", np.full((25, 1), 7.0))  # "finished" part
        resumed = build_patch_bank(_psd(), cache_dir=tmp_path, **kw)
    np.testing.assert_array_equal(resumed.values[:25], 7.0)
    np.testing.assert_array_equal(resumed.values[25:], plain.values[25:])
    assert not parts.exists()  # parts removed once the bank file is complete


def test_the_bank_tail_is_rechecked_with_the_boundary_element_model(tmp_path):
    """The largest Eq. 16 energies of a bank of 64² Table-4 patches at 50 % RH are artefacts: the
    FFT-BEM gives them less than half (ValidityWarning naming model='fft_bem'), while on typical
    laws (around the median) the two models agree within a factor 0.6 (independent BEM calls)."""
    kw = dict(model="modified_dmt", relative_humidity=[0.5], n=600, shape=(64, 64), spacing=5e-9, seed=2)
    with pytest.warns(rs.ValidityWarning, match="model='fft_bem'"):
        bank = build_patch_bank(_psd(), cache_dir=tmp_path, **kw)
    assert bank.attrs["tail_checked"] == 8
    assert np.atleast_1d(bank.attrs["tail_bem_ratio"])[0] < 0.5
    g = bank.values[:, 0]
    typical = np.argsort(g, kind="stable")[296:304]
    surf = rs.generate_surfaces(_psd(), realizations=typical, shape=(64, 64), spacing=5e-9, seed=2).compute()
    bem = [float(rs.contact.summary(rs.contact.curves(surf.isel(realization=i), relative_humidity=[0.5],
                                                             model="fft_bem", check_validity=False))
                 ["adhesive_energy"].squeeze()) for i in range(8)]
    assert np.median(np.asarray(bem) / g[typical]) > 0.6
    # a bank cached without the check (check_tail=0) gets it when read back; the BEM bank has none
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plain = build_patch_bank(_psd(), check_tail=0, **{**kw, "n": 50, "seed": 3}, cache_dir=tmp_path)
        assert "tail_bem_ratio" not in plain.attrs
        again = build_patch_bank(_psd(), **{**kw, "n": 50, "seed": 3}, cache_dir=tmp_path)
        assert again.attrs["from_cache"] == 1 and again.attrs["tail_checked"] == 8
        bem_bank = build_patch_bank(_psd(), **{**kw, "n": 4, "model": "fft_bem"})
    assert "tail_bem_ratio" not in bem_bank.attrs
    with pytest.raises(ValueError, match="check_tail=-1: must be an integer >= 0"):
        build_patch_bank(_psd(), check_tail=-1, **kw)


def test_the_default_law_is_the_beams_strip_composed_of_sub_zones():
    """shape=None: a law is the beam's Δx × w strip, the area mean of the sub-zones that tile it
    (rs.stiction.strip_adhesive_energy gives the same strips), not a square nobody asked for."""
    beam = rs.Cantilever(width=5.24e-6)  # 131 x 262 px at 20 nm: two 131 x 131 sub-zones
    kw = dict(relative_humidity=[0.5, 0.9], n=3, spacing=20e-9, seed=2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)  # nothing to warn about: the law is the strip
        warnings.simplefilter("ignore", rs.ValidityWarning)
        bank = build_patch_bank(_psd(), beam=beam, **kw)
        strips = rs.stiction.strip_adhesive_energy(_psd(), beam=beam, **kw)
    assert bank.attrs["subzones"] == 2 and "tail_bem_ratio" not in bank.attrs  # no BEM strip by default
    assert bank.attrs["patch_area"] == pytest.approx(131 * 262 * 20e-9**2)
    np.testing.assert_allclose(bank.values, strips.adhesive_energy.transpose("realization", "rh").values,
                               rtol=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        with pytest.warns(UserWarning, match=r"narrower than the beam.*shape=None"):
            build_patch_bank(_psd(), beam=beam, shape=(131, 131), **kw)
    with pytest.raises(ValueError, match="pass spacing="):
        build_patch_bank(_psd(), relative_humidity=[0.5], n=1)


def test_the_pressure_bank_composes_the_same_strips():
    """pressure_law_bank's default law is the beam's strip too: the area mean of the pressures
    of the sub-zones that build_patch_bank composes (the same realizations), and its Eq. 13
    energy is the energy bank's within the grids' difference."""
    beam = rs.Cantilever(width=5.24e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.ValidityWarning)
        laws = rs.beam.pressure_law_bank(_psd(), relative_humidity=[0.9], n=2, spacing=20e-9, seed=2,
                                         beam=beam, n_gap=800)
        energies = build_patch_bank(_psd(), relative_humidity=[0.9], n=2, spacing=20e-9, seed=2, beam=beam)
        subs = rs.generate_surfaces(_psd(), n=4, shape=(131, 131), spacing=20e-9, seed=2).compute()
        c = rs.contact.curves(subs, relative_humidity=[0.9], distance=laws.gap.values, model="modified_dmt").compute()
    assert laws.attrs["subzones"] == 2
    mean = c.pressure.isel(rh=0).values.reshape(2, 2, -1).mean(axis=1)
    np.testing.assert_allclose(laws.isel(rh=0).values, mean, rtol=1e-10, atol=1e-6)
    curves = xr.Dataset({"pressure": laws.rename(gap="distance")})
    g = rs.contact.summary(curves, check_grid=False).adhesive_energy.transpose("law", "rh").values
    np.testing.assert_allclose(g, energies.values, rtol=0.1)


def test_a_pixel_coarser_than_the_water_necks_warns_before_the_laws():
    """Table-4 patches at 20 nm: the ring wetted around a summit spans < 3 pixels at 30 % RH (1.7),
    so the pixel sets Γ; at 5 nm (5.5 pixels) the bank is quiet about it."""
    kw = dict(relative_humidity=[0.3], n=1, shape=(64, 64), beam=rs.Cantilever(width=1.28e-6), check_tail=0)
    with pytest.warns(rs.contact.PixelResolutionWarning, match="does not resolve the water necks"):
        build_patch_bank(_psd(), spacing=20e-9, **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.contact.PixelResolutionWarning)
        warnings.simplefilter("ignore", UserWarning)
        warnings.filterwarnings("error", category=rs.contact.PixelResolutionWarning)
        build_patch_bank(_psd(), spacing=5e-9, **{**kw, "beam": rs.Cantilever(width=0.32e-6)})


def test_a_bank_of_non_gaussian_patches_is_the_film_generated_with_its_heights(tmp_path):
    """height_distribution= gives the laws of the surfaces generate_surfaces makes with it (the
    same seeds), is cached under its own key, and a skewed film's patches differ from the
    Gaussian twin's."""
    hd = rs.surface.height_distribution(skewness=1.0, kurtosis=4.5, rms=1.0)
    kw = dict(relative_humidity=[0.5], n=3, shape=(32, 32), spacing=20e-9, check_tail=0, seed=4,
              beam=rs.Cantilever(width=0.64e-6), model="modified_dmt", cache_dir=tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        skewed = build_patch_bank(_psd(), height_distribution=hd, **kw)
        gaussian = build_patch_bank(_psd(), **kw)
        surf = rs.generate_surfaces(_psd(), n=3, shape=(32, 32), spacing=20e-9, seed=4,
                                    height_distribution=hd).compute()
        by_hand = [float(rs.contact.summary(rs.contact.curves(
            surf.isel(realization=k), relative_humidity=[0.5], model="modified_dmt",
            check_validity=False)).adhesive_energy.squeeze()) for k in range(3)]
    np.testing.assert_allclose(skewed.values[:, 0], by_hand, rtol=1e-12)
    assert skewed.attrs["cache_file"] != gaussian.attrs["cache_file"]
    assert skewed.attrs["height_distribution"].startswith("johnson")
    assert not np.allclose(skewed.values, gaussian.values)
