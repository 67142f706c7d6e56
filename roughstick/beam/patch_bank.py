r"""Banks of patch laws: random surface patches computed once (and cached) for the beam models.

Each law is one random periodic patch (:func:`roughstick.surface.generate_surfaces` on a PSD,
Eqs. 33-35) put through the contact model at every requested RH and reduced to its adhesive
energy (Eq. 13; :func:`build_patch_bank`, cached on disk under a name hashing every input) or
kept as its pressure-distance curve (:func:`pressure_law_bank`, for the cohesive beam). Law
``k`` is the same patch at every RH.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import warnings
from pathlib import Path

import dask
import numpy as np
import xarray as xr

from .._core.api import renamed_keywords
from .._core.arguments import check_numbers
from .._core.conventions import append_history, dataset_attrs
from .._core.intervals import median_interval
from .._core.materials import POLYSILICON
from .._core.remedy import argument, spell, spelled
from .._core.validate import as_length, external_stacklevel, relative_humidity_array
from ..contact import (
    ValidityWarning,
    contact_distance_grid,
    expected_surface_groups,
    select_model,
    warn_if_outside_validity,
    warn_if_unresolved,
)
from ..contact import curves as contact_curves
from ..contact import summary as adhesion_summary
from ..ensemble.pipeline import distance_grid
from ..io.netcdf import publish
from ..stiction.cantilever import PAPER_CANTILEVER, Cantilever
from ..stiction.zone import compose_zone_law, subzone_shape
from ..surface import generate_surfaces

__all__ = ["build_patch_bank", "pressure_law_bank"]


def _key(psd, rh, n_law, shape, spacing, seed, model, material=POLYSILICON, subzones=1,
         gen_kw=None):
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(psd.values, dtype=float).tobytes())
    for c in psd.coords:
        h.update(np.asarray(psd[c].values, dtype=float).tobytes())
    h.update(json.dumps([list(map(float, rh)), int(n_law), list(shape), float(spacing), seed,
                         model]).encode())
    if material != POLYSILICON:  # poly-silicon banks keep the names they were cached under
        h.update(repr(material).encode())
    if subzones != 1:  # single-patch banks keep their names too
        h.update(f"subzones={int(subzones)}".encode())
    if gen_kw:  # Gaussian banks keep their names
        dist = gen_kw["height_distribution"]
        for v in sorted(dist.variables):
            h.update(v.encode() + np.ascontiguousarray(dist[v].values, dtype=float).tobytes())
        h.update(str(gen_kw["distribution_method"]).encode())
    return h.hexdigest()[:16]


#: How build_patch_bank's warnings spell their remedies (:mod:`roughstick._core.remedy`).
_SPELLING = {"contact_model": argument("model", call="build_patch_bank")}


#: median BEM/Eq. 16 ratio of the bank's largest laws below which it warns (docs/beam.md)
TAIL_RATIO_WARN = 0.8

#: laws per part: a part is computed by one dask task and, with a cache, stored on its own so an
#: interrupted bank resumes from its finished parts
_LAWS_PER_PART = 25


def _law_energies(psd, laws, rh, shape, spacing, seed, model, material=POLYSILICON,
                  composition=None, gen_kw=None) -> np.ndarray:
    """Adhesive energies (Eq. 13) of the patches ``laws`` at the humidities ``rh``: (law, rh).

    ``composition``: ``(subzones, distance)``: law ``k`` is the zone of sub-zones
    ``k*subzones ... (k+1)*subzones - 1`` (each of ``shape``) composed on the grid ``distance``
    (:func:`roughstick.stiction.compose_zone_law`); None: law ``k`` is one patch of ``shape``.
    ``gen_kw``: the height distribution of the surfaces (keywords of generate_surfaces)."""
    gen_kw = gen_kw or {}
    laws = np.asarray(laws)
    if composition is not None:
        m, distance = composition
        subs = (laws[:, None] * m + np.arange(m)[None, :]).ravel()
        surf = generate_surfaces(psd, realizations=subs, shape=shape, spacing=spacing,
                                 seed=seed, **gen_kw).compute(scheduler="sync")
        curves = contact_curves(surf, relative_humidity=list(rh), model=model, material=material,
                                distance=distance, check_validity=False)
        law = compose_zone_law(curves[["pressure", "wet_fraction"]].compute(scheduler="sync"), subzones=m)
        return np.asarray(law["adhesive_energy"].transpose("realization", "rh").values)
    # realization k always comes from SeedSequence child k: the same law whatever the parts
    surf = generate_surfaces(psd, realizations=laws, shape=shape, spacing=spacing,
                             seed=seed, **gen_kw).compute(scheduler="sync")
    values = np.empty((len(laws), len(rh)))
    for k in range(len(laws)):
        curves = contact_curves(surf.isel(realization=k), relative_humidity=list(rh),
                                model=model, material=material, check_validity=False)
        values[k] = adhesion_summary(curves)["adhesive_energy"].transpose("rh").values
    return values


def _set_aside(file: Path, why: BaseException, what: str, *, keep: bool = True) -> None:
    """Move an unreadable cache file out of the way (``<name>.corrupt``; a part of an unfinished
    bank, an intermediate, is deleted), saying so."""
    reason = (str(why).strip().splitlines() or [type(why).__name__])[0][:160]
    aside = file.with_name(file.name + ".corrupt")
    if keep:
        os.replace(file, aside)
        done = f"moved it to {aside.name} and {what} (delete {aside.name} when you no longer need it)"
    else:
        file.unlink()
        done = f"deleted it and {what}"
    warnings.warn(f"the patch-bank cache file {str(file)!r} could not be read ({reason}); {done}.",
                  UserWarning, stacklevel=4)


def _part(psd, start, stop, rh, shape, spacing, seed, model, parts_dir, material=POLYSILICON,
          composition=None, gen_kw=None):
    """Adhesive energies of laws [start, stop) (read back from its part file when cached)."""
    file = None if parts_dir is None else parts_dir / f"laws_{start:07d}_{stop:07d}.npy"
    if file is not None and file.exists():
        try:
            values = np.load(file)
            if values.shape != (stop - start, len(rh)):
                raise ValueError(f"it holds an array of shape {values.shape}, not {(stop - start, len(rh))}")
            return values
        except (OSError, ValueError, EOFError) as exc:
            _set_aside(file, exc, f"recomputing laws {start}-{stop - 1}", keep=False)
    values = _law_energies(psd, np.arange(start, stop), rh, shape, spacing, seed, model, material,
                           composition, gen_kw)
    if file is not None:
        parts_dir.mkdir(parents=True, exist_ok=True)
        tmp = file.with_suffix(".tmp.npy")
        np.save(tmp, values)
        publish(tmp, file)
    return values


def _tail_check(bank: xr.DataArray, psd, shape, spacing, seed, n_check: int,
                material=POLYSILICON, composition=None, gen_kw=None) -> xr.DataArray:
    """Re-evaluate the ``n_check`` laws of largest Eq. 16 energy at each RH with the FFT-BEM.

    Sets ``attrs["tail_bem_ratio"]`` (per RH, the median over those laws of BEM Γ / Eq. 16 Γ),
    its 95 % order-statistic interval ``tail_bem_ratio_low`` / ``_high`` (NaN with 5 laws or
    fewer, :func:`roughstick.median_interval`) and ``attrs["tail_checked"]``, and warns (ValidityWarning) where the ratio is below
    :data:`TAIL_RATIO_WARN`.
    The largest laws set the beam's small P(stuck) (the front stops at the first patch able to
    hold it), and the modified DMT's tail is where it is least reliable (docs/beam.md).
    """
    values = bank.values
    k = min(int(n_check), values.shape[0])
    ratio, lo, hi = (np.full(values.shape[1], np.nan) for _ in range(3))
    for j, rh in enumerate(bank.rh.values):
        top = np.argsort(values[:, j], kind="stable")[::-1][:k]
        bem = _law_energies(psd, top, [float(rh)], shape, spacing, seed, "fft_bem", material,
                            composition, gen_kw)[:, 0]
        ratio[j], lo[j], hi[j] = median_interval(bem / values[top, j], confidence=0.95)
    bank.attrs.update(tail_bem_ratio=ratio, tail_bem_ratio_low=lo, tail_bem_ratio_high=hi, tail_checked=k)
    low = bank.rh.values[ratio < TAIL_RATIO_WARN]
    if low.size:
        with spelled(**_SPELLING):
            fix = spell("contact_model", "fft_bem")
        warnings.warn(
            f"the {k} largest patch energies of the modified-DMT bank are {1 / np.nanmin(ratio):.1f} x "
            f"their boundary-element values at RH {', '.join(f'{v:g}' for v in low)} (median BEM/Eq. 16 "
            f"{np.nanmin(ratio):.2f}): the bank's upper tail, which decides P(stuck) of short beams, is "
            "too high there, so such P(stuck) is overestimated (example bank, 30 % RH, 250 µm beams: 0.043 "
            "against 0.001). Build "
            f"the bank with {fix} (about 10 x the cost; docs/beam.md).", ValidityWarning, stacklevel=external_stacklevel())
    return bank


def _read_cached(path: Path, n_law: int, rh) -> xr.DataArray | None:
    """The bank cached in ``path``; None, after moving it aside with a warning, when it cannot be
    read or does not hold this bank (a damaged, truncated or foreign file)."""
    try:
        out = xr.load_dataarray(path)
        if out.dims != ("law", "rh") or out.sizes["law"] != n_law or not np.array_equal(out["rh"].values, rh):
            raise ValueError(f"it holds {dict(out.sizes)}, not {n_law} laws at RH {list(map(float, rh))}")
        return out
    except (OSError, ValueError, KeyError, RuntimeError, TypeError) as exc:
        _set_aside(path, exc, "rebuilding the bank")
        return None


def _check_cache_writable(folder: Path) -> None:
    """Refuse a cache folder the bank cannot be stored in, before computing it."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / f".probe-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        raise PermissionError(
            f"cannot write the patch-bank cache folder {str(folder)!r} ({exc.strerror or exc}); pass a "
            "writable cache_dir= (or cache_dir=None to compute the bank without caching it)."
        ) from exc


def _native_spacing(psd, spacing) -> float:
    """The pixel of the bank: ``spacing``, else the PSD's own (``spacing_x`` of a measured PSD)."""
    if spacing is not None:
        return float(as_length(spacing, name="spacing"))
    native = psd.attrs.get("spacing_x") if isinstance(psd, xr.DataArray) else None
    if native is None:
        raise ValueError("this PSD does not say its pixel (no attrs['spacing_x']): pass spacing= (e.g. "
                         "spacing=5e-9, the pixel that resolves the water necks of nm-rough films)")
    return float(native)


def _patch_plan(psd, shape, subzones, spacing, beam) -> tuple[tuple[int, int], int]:
    """(sub-zone shape, sub-zones per law) of a bank: the beam's Δx × w zone by default
    (:func:`roughstick.stiction.subzone_shape`), else what was asked, warning when a law is
    narrower than the beam (what that costs is the zone-size law, docs/zone_size.md)."""
    if shape is None:
        zone = (int(round(beam.interaction_zone_length / spacing)), int(round(beam.width / spacing)))
        sub, m = subzone_shape(beam, spacing=spacing, shape=zone)
        return sub, (m if subzones is None else int(subzones))
    shape = tuple(int(v) for v in np.broadcast_to(shape, 2))
    m = 1 if subzones is None else int(subzones)
    width = shape[1] * m * spacing
    if width < 0.99 * beam.width:
        warnings.warn(
            f"each law is a patch {shape[0] * spacing * 1e6:.3g} x {width * 1e6:.3g} µm, narrower than the "
            f"beam ({beam.width * 1e6:.3g} µm): a strip of the beam holds more summits, so its Γ is smaller, "
            "by about two orders of magnitude at 30-50 % RH on nm-rough films (Table-4 PSD, Eq. 16: the median "
            "Γ of 0.64 µm squares is 130-170 x that of 2.62 x 30 µm strips; docs/zone_size.md), and "
            "P(stuck) is overstated. Leave shape=None (the beam's Δx × w strip, composed of sub-zones) or "
            "pass subzones= so that the law spans the beam.", UserWarning, stacklevel=external_stacklevel())
    return shape, m


@renamed_keywords(n_law="n")
@check_numbers(n="count", spacing="length?", seed="seed", check_tail="count0?", subzones="count?")
def build_patch_bank(psd: xr.DataArray, *, relative_humidity, n: int = 1000, shape=None,
                     spacing=None, seed: int = 0, model: str = "modified_dmt",
                     cache_dir=None, check_tail: int | None = None, material=None,
                     beam: Cantilever = PAPER_CANTILEVER, subzones: int | None = None,
                     height_distribution=None, distribution_method: str = "translation") -> xr.DataArray:
    r"""Adhesive energies of ``n`` random patches at each RH: the law bank of the beam model.

    By default a law is the beam's own patch, the strip :math:`\Delta x \times w` (interaction
    length by beam width, §5.2) at ``spacing``, composed of the sub-zones that tile it
    (:func:`roughstick.stiction.subzone_shape`; the strip's law is the area mean of theirs,
    :func:`roughstick.stiction.compose_zone_law`). A smaller ``shape`` is a different zone: its Γ
    is larger (fewer summits to rest on), so a law narrower than the beam warns.

    Parameters
    ----------
    psd : xarray.DataArray
        Power spectral density of the patches (as :func:`roughstick.surface.generate_surfaces`
        takes).
    relative_humidity : float or sequence
        RH fractions in (0, 1).
    n : int
        Number of patches (laws).
    shape : (int, int), optional
        Pixels of one sub-zone (with ``subzones`` 1: of one patch). None: the sub-zones of the
        beam's strip.
    spacing : float or str, optional
        Pixel size [m], or with its unit (``"5 nm"``); None: the PSD's own (``attrs["spacing_x"]``).
    seed : int
        Root seed of the patches (one SeedSequence child per sub-zone, as generate_surfaces does).
    model : str, default "modified_dmt"
        Contact model of :func:`roughstick.contact.curves`; ``"auto"``: the cheaper of
        ``"modified_dmt"`` and ``"fft_bem"`` whose measured error bound at the surface groups
        expected from the PSD on these patches meets 10 % at every humidity
        (``attrs["contact_model"]`` says which; on the beam's strips the FFT-BEM costs about
        10 min per law).
    cache_dir : path-like, optional
        Directory of the on-disk cache; ``None`` computes without caching. The laws are computed
        in parts of 25 by dask's threads (both cores; a law is the same whatever the parts);
        with a cache each finished part is stored, so an interrupted bank resumes where it
        stopped. A cache file that cannot be read (damaged, truncated, not this bank) is moved
        aside to ``<name>.corrupt`` with a warning and the bank rebuilt (a damaged part is
        deleted and recomputed). A folder that cannot be written is refused before any law is
        computed (``PermissionError``).
    check_tail : int, optional
        With ``model="modified_dmt"``: re-evaluate this many laws of largest energy at each RH
        with the FFT-BEM (``attrs["tail_bem_ratio"]``, the median BEM/Eq. 16 ratio; a
        ValidityWarning below :data:`TAIL_RATIO_WARN`); 0 skips the check. None: 8 for a bank of
        single patches, 0 for composed strips (a strip costs about 10 min of FFT-BEM).
    material : roughstick.Material, optional
        Both bodies' material (default poly-silicon); part of the cache key.
    beam : Cantilever
        The beam whose strip is the default patch.
    subzones : int, optional
        Sub-zones of ``shape`` per law (composed); None: the number that tiles the beam's width
        when ``shape`` is None, else 1.
    height_distribution : xarray.Dataset, optional
        Heights of the patches other than Gaussian (:func:`roughstick.surface.height_distribution`:
        a measured film's own, or a Johnson one), imposed by ``distribution_method`` as
        :func:`roughstick.surface.generate_surfaces` does; part of the cache key.
    distribution_method : {"translation", "iaaft"}
        How ``height_distribution`` is imposed.

    Returns
    -------
    xarray.DataArray
        ``adhesive_energy`` [J m-2] over ``(law, rh)``; ``attrs["cache_file"]`` when cached and
        ``attrs["from_cache"]`` telling whether it was read back; ``tail_bem_ratio`` and
        ``tail_checked`` (see ``check_tail``); ``patch_area``, ``subzones``.

    Examples
    --------
    >>> import numpy as np
    >>> psd = rs.surface.self_affine_psd(np.geomspace(1e5, 4e9, 400), **rs.datasets.family_parameters("table4"))
    >>> bank = rs.beam.build_patch_bank(psd, relative_humidity=[0.5, 0.7], n=2, shape=(32, 32),
    ...                                 spacing=20e-9, check_tail=0, beam=rs.Cantilever(width=0.64e-6))
    >>> bank.dims, (bank.values * 1e3).round(2)  # mJ m-2 over (law, rh)
    (('law', 'rh'), array([[ 0.71,  6.43],
           [ 2.05, 18.49]]))
    """
    rh = relative_humidity_array(relative_humidity)
    if not isinstance(psd, xr.DataArray):
        raise TypeError("psd must be an xarray.DataArray (e.g. roughstick.surface.self_affine_psd(q, ...)) "
                        f"so the cache can key on its values, got {type(psd).__name__}")
    spacing = _native_spacing(psd, spacing)
    shape, m = _patch_plan(psd, shape, subzones, spacing, beam)
    gen_kw = (None if height_distribution is None else
              {"height_distribution": height_distribution, "distribution_method": distribution_method})
    material = POLYSILICON if material is None else material
    groups = expected_surface_groups(psd, shape=shape, spacing=float(spacing),
                                     relative_humidity=list(rh), material=material)
    if model == "auto":  # the cheaper of Eq. 16 and fft_bem measured within 10 % on these patches
        model, _ = select_model(None, relative_humidity=list(rh), groups=groups,
                                candidates=("modified_dmt", "fft_bem"))
    check = (8 if m == 1 else 0) if check_tail is None else int(check_tail)
    check = check if model == "modified_dmt" else 0
    corr = float(groups["corr_over_L"]) * shape[1] * float(spacing)
    patch = min(shape) * float(spacing)
    if patch < 4 * corr:
        what = "sub-zones" if m > 1 else "patches"
        warnings.warn(
            f"{what} of {patch:.3g} m are shorter than 4 correlation lengths of the PSD "
            f"({corr:.3g} m, 1/e of the autocorrelation): neighbouring {what} of a real "
            "interface would not be independent, as the beam model assumes. Use a larger shape "
            "or spacing (a patch >= 4 correlation lengths).", UserWarning, stacklevel=external_stacklevel())
    with spelled(**_SPELLING):
        # the pixel against the water necks (a coarser pixel sets Γ as much as the model does)
        warn_if_unresolved(groups=groups, spacing=float(spacing))
        if model == "modified_dmt":
            # once for the bank (expected groups of the PSD), not once per law
            warn_if_outside_validity(None, relative_humidity=list(rh), groups=groups, material=material)
    composition = None
    if m > 1:
        composition = (m, distance_grid(psd, shape=shape, n=int(n) * m, relative_humidity=rh,
                                        height_distribution=height_distribution).values)
    path = None
    if cache_dir is not None:
        key = _key(psd, rh, n, shape, spacing, seed, model, material, m, gen_kw)
        path = Path(cache_dir) / f"patch_bank_{key}.nc"
        out = _read_cached(path, int(n), rh) if path.exists() else None
        if out is not None:
            if check and int(out.attrs.get("tail_checked", -1)) != min(check, int(n)):
                out = _tail_check(out, psd, shape, float(spacing), seed, check, material, composition, gen_kw)
            out.attrs.update(cache_file=str(path), from_cache=1)
            return out
        _check_cache_writable(path.parent)  # before any law is computed
    parts_dir = None if path is None else path.with_name(path.stem + ".parts")
    blocks = [(a, min(a + _LAWS_PER_PART, int(n))) for a in range(0, int(n), _LAWS_PER_PART)]
    tasks = [dask.delayed(_part)(psd, a, b, rh, shape, float(spacing), seed, model, parts_dir, material,
                                 composition, gen_kw) for a, b in blocks]
    values = np.concatenate(dask.compute(*tasks, scheduler="threads"), axis=0)
    out = xr.DataArray(values, {"law": np.arange(int(n)), "rh": rh}, ("law", "rh"),
                       name="adhesive_energy",
                       attrs={"units": "J m-2", "long_name": "adhesive energy of a patch (Eq. 13)",
                              "contact_model": model, "seed": int(seed),
                              "material": repr(material),
                              "correlation_length": corr,
                              "subzones": m, "subzone_shape": list(shape),
                              "height_distribution": "gaussian" if gen_kw is None else
                              f"{height_distribution.attrs.get('family', 'given')} "
                              f"({distribution_method})",
                              "patch_area": float(m * shape[0] * shape[1] * spacing**2),
                              "independence": "patch laws drawn independently; checked: "
                                              f"{'sub-zone' if m > 1 else 'patch'} "
                                              f"{patch:.3g} m vs 4 correlation lengths "
                                              f"{4 * corr:.3g} m"})
    if check:
        out = _tail_check(out, psd, shape, float(spacing), seed, check, material, composition, gen_kw)
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".tmp")
        # a cache file read on its own says what it is (global CF attributes and history)
        file = out.to_dataset().assign_attrs(dataset_attrs(
            "roughstick patch bank: adhesive energies of random surface patches (Eq. 13)",
            patch_shape=list(shape), spacing_m=float(spacing), n_law=int(n), seed=int(seed),
            contact_model=model, cache_key=key, subzones=m))
        append_history(file, f"build_patch_bank(n={int(n)}, shape={list(shape)}, spacing={float(spacing)!r}, "
                             f"relative_humidity={[float(r) for r in rh]}, seed={int(seed)}, model={model!r}, "
                             f"subzones={m})")
        file.to_netcdf(tmp)
        publish(tmp, path)
        if parts_dir.exists():
            for f in parts_dir.glob("laws_*.npy"):
                f.unlink()
            parts_dir.rmdir()
        out.attrs.update(cache_file=str(path), from_cache=0)
    return out


@renamed_keywords(n_law="n")
@check_numbers(n="count", spacing="length", seed="seed", n_gap="count", subzones="count?")
def pressure_law_bank(psd: xr.DataArray, *, relative_humidity, n: int = 100, shape=None,
                      spacing: float, seed: int = 0, model: str = "modified_dmt",
                      n_gap: int = 400, beam: Cantilever = PAPER_CANTILEVER,
                      subzones: int | None = None) -> xr.DataArray:
    r"""Pressure-distance laws of ``n`` random patches per RH on one uniform gap grid.

    The same patches as :func:`build_patch_bank` with the same arguments (by default the beam's
    own strips, patch length × width, each the area mean of the ``subzones`` sub-zones of
    ``shape`` that tile it, :func:`roughstick.stiction.compose_zone_law`; with ``shape`` and no
    ``subzones`` law k is realization k of :func:`roughstick.surface.generate_surfaces`), kept
    as full curves (Eqs. 33-35, 13) for the cohesive model instead of their adhesive energies.
    Patches are assumed independent; a ``ValueError`` is raised when a (sub-)patch is not at
    least four correlation lengths of the first surface long (autocorrelation falling below 1/e),
    and a patch narrower than the beam warns (its Γ is too large, docs/zone_size.md).

    Parameters
    ----------
    psd : xarray.DataArray
        Power spectral density of the patches.
    relative_humidity : float or sequence
        RH fractions in (0, 1).
    n : int
        Number of patches (laws).
    shape : (int, int), optional
        Pixels of a sub-zone (with ``subzones`` None: of a patch); None: the sub-zones of the
        beam's strip (:func:`roughstick.stiction.subzone_shape`).
    spacing : float
        Pixel size [m].
    seed : int
        Root seed of the patches.
    model : str
        Contact model of :func:`roughstick.contact.curves`.
    n_gap : int
        Points of the uniform gap grid.
    beam : Cantilever
        The beam whose strip is the default patch.
    subzones : int, optional
        Sub-zones per law; None: those that tile the beam's width when ``shape`` is None, else 1.

    Returns
    -------
    xarray.DataArray
        ``pressure`` [Pa] (positive repulsive) over ``(law, rh, gap)``, gap [m] between mean planes.

    Examples
    --------
    >>> import numpy as np
    >>> psd = rs.surface.self_affine_psd(np.geomspace(1e5, 4e9, 400), **rs.datasets.family_parameters("table4"))
    >>> bank = rs.beam.pressure_law_bank(psd, relative_humidity=[0.5], n=2, shape=(32, 32),
    ...                                  spacing=20e-9, n_gap=50, beam=rs.Cantilever(width=0.64e-6))
    >>> bank.dims, bank.shape
    (('law', 'rh', 'gap'), (2, 1, 50))
    """
    rh = np.atleast_1d(np.asarray(relative_humidity, dtype=float))
    if np.any((rh <= 0) | (rh >= 1)):
        raise ValueError("relative_humidity must be fractions in (0, 1), e.g. 0.6 not 60")
    if int(n) < 1 or int(n_gap) < 8:
        raise ValueError("n must be >= 1 and n_gap >= 8")
    spacing = float(spacing)
    shape, m = _patch_plan(psd, shape, subzones, spacing, beam)

    def law_surfaces(k):
        return generate_surfaces(psd, realizations=np.arange(k * m, (k + 1) * m), shape=shape,
                                 spacing=spacing, seed=seed).compute(scheduler="sync")

    surf = law_surfaces(0)
    first = np.asarray(surf.isel(realization=0).values, dtype=float)
    z = first - first.mean()
    acf = np.fft.ifft2(np.abs(np.fft.fft2(z)) ** 2).real[0] / np.sum(z * z)
    corr = spacing * int(np.argmax(acf[: z.shape[1] // 2] < math.exp(-1)))
    if not 0 < corr <= spacing * z.shape[1] / 4:
        raise ValueError(f"patch of {spacing * z.shape[1]:.3g} m is not >= 4 correlation lengths "
                         f"({corr:.3g} m): patch laws would not be independent; use longer patches")
    grid = np.asarray(contact_distance_grid(surf.isel(realization=0), relative_humidity=list(rh)).values)
    rms = float(z.std())
    lo, hi = grid.min() - 0.5 * (grid.max() - grid.min()), grid.max() + 4 * rms
    if m > 1:  # the tallest summit of all the sub-zones of the bank lies below the top
        hi = max(hi, float(distance_grid(m0=rms**2, shape=shape, n=int(n) * m, relative_humidity=rh)[-1]))
    gap = np.linspace(lo, hi, int(n_gap))
    out = np.empty((int(n), len(rh), gap.size))
    for k in range(int(n)):
        surf = surf if k == 0 else law_surfaces(k)
        c = contact_curves(surf, relative_humidity=list(rh), distance=gap, model=model)
        out[k] = c["pressure"].mean("realization").transpose("rh", "distance").values
    bank = xr.DataArray(out, {"law": np.arange(int(n)), "rh": rh, "gap": gap},
                        ("law", "rh", "gap"), name="pressure",
                        attrs={"units": "Pa", "long_name": "mean pressure of a patch law (positive repulsive)",
                               "contact_model": model, "seed": int(seed), "correlation_length": corr,
                               "subzones": m, "subzone_shape": list(shape),
                               "independence": "patch laws independent (patch >= 4 correlation lengths)"})
    bank["gap"].attrs.update(units="m", long_name="distance between the mean planes")
    return bank
