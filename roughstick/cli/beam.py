"""``roughstick beam CONFIG.toml``: cantilevers on random patch laws (beam-scale stochastic model).

Builds (or reads back from its on-disk cache) a bank of patch laws for the PSD and RH of the file,
runs the beam-scale model of :mod:`roughstick.beam` on ``n`` beams per length and RH, and writes
``beam.nc`` (crack length, stuck flag, apparent Γ by Eq. 36, P(stuck) with its Wilson interval
over (realization, rh, beam_length)). With ``method = "subset"`` in [ensemble] (sharp front only)
it estimates P(stuck) on the bank by subset simulation to ``target_cv`` instead
(:func:`roughstick.stuck_probability` with ``method="subset"``; ``beam.nc`` over (rh,
beam_length) with interval, cv, evaluations and the bank's closed-form value). The file follows
the one configuration schema of every command (docs/configuration.md); see
``examples/beam.toml`` and ``examples/beam_subset.toml``.
"""

from __future__ import annotations

import pathlib
import time

import numpy as np
import xarray as xr

import roughstick as rs

from .._core.conventions import append_history, dataset_attrs
from .._core.materials import POLYSILICON, material_attrs
from .._core.progress import staged_progress
from .._core.references import PAPER, cite
from .._core.validate import adhesive_energy_values
from ..io.netcdf import write as write_netcdf
from ._common import LOG, claim_folder, config_spellings, finish_folder, small_p_problems
from ._config import ConfigError, check_memory, config_material, johnson_problems, parse, read_toml
from .risk import _heights

__all__ = ["register"]


def register(sub):
    p = sub.add_parser("beam", help="beam-scale stochastic stiction: crack length and P(stuck) "
                       "from random patch laws (paper §5); NetCDF", description=__doc__)
    p.add_argument("config", help="TOML configuration (`roughstick examples --out examples` writes examples/beam.toml)")
    p.add_argument("--out", default=None,
                   help="output folder (default: [output] folder, else ./beam-output)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace results of another run in the output folder")
    p.set_defaults(func=_run, remedies=lambda args: config_spellings(contact_model="bank", key="model",
                                                                                     samples="ensemble"))


def _psd(surface: dict):
    if surface.get("psd") is not None:
        return rs.io.open_dataset(surface["psd"])["psd"]
    c = rs.stiction.cantilever_psd()
    q = np.geomspace(1e5, 4e9, 400)
    return rs.surface.self_affine_psd(q, s0=float(c.s0), s1=float(c.s1), q0=float(c.q0), qmax=float(c.qmax))


def _beside(config: pathlib.Path, folder) -> pathlib.Path:
    """A relative folder of the config (defaults included) is taken beside the config file."""
    folder = pathlib.Path(folder)
    return folder if folder.is_absolute() else config.parent / folder


def _run(args) -> int:
    path = pathlib.Path(args.config)
    c = parse(read_toml(path), "beam", base=path.parent, source=path.name)
    b, s, ens, bank_cfg, o = (c[k] for k in ("beam", "surface", "ensemble", "bank", "output"))
    shape = s.get("shape")
    shape = None if shape is None else ((shape, shape) if np.ndim(shape) == 0 else tuple(shape))
    if shape is not None:
        check_memory(shape, where=f"{path.name} [surface] shape")
    material = config_material(c["material"], path.name)
    b.setdefault("youngs_modulus", material.youngs_modulus)  # the beam is made of the film
    beam = rs.Cantilever(width=b["width"], thickness=b["thickness"], gap=b["gap"],
                         youngs_modulus=b["youngs_modulus"],
                         **({"interaction_length": b["patch_length"]} if b.get("patch_length") else {}))
    rh = np.asarray(ens["relative_humidity"], dtype=float)
    _check_method(ens, path.name)
    _check_patch(b, path.name)
    _check_heights(s, path.name)
    out = pathlib.Path(args.out) if args.out else _beside(path, o.get("folder") or "beam-output")
    claim_folder(out, command="beam", params={k: v for k, v in c.items() if k != "output"
                                              and not (k == "material" and not v)},
                 overwrite=args.overwrite or o["overwrite"], keep=[path],
                 legacy_params={"config": path.read_text()})
    t0 = time.perf_counter()
    psd, cache = _psd(s), _beside(path, bank_cfg["cache"])
    heights = _heights(s)  # said before the work; None: Gaussian
    try:
        bank = rs.beam.build_patch_bank(psd, relative_humidity=rh, n=bank_cfg["laws"], shape=shape,
                                        spacing=s["spacing"], seed=bank_cfg["seed"], model=bank_cfg["model"],
                                        cache_dir=cache, beam=beam,
                                        **({} if material == POLYSILICON else {"material": material}),
                                        **({} if heights is None else {"height_distribution": heights}))
    except OSError as exc:  # the bank writes only into its cache folder
        cause = exc.__cause__ if isinstance(exc.__cause__, OSError) else exc
        raise ConfigError(
            f"{path.name}: cannot write the patch-bank cache folder {str(cache)!r} "
            f"({cause.strerror or cause}); set [bank] cache in {path.name} to a writable folder "
            "(relative to the file), e.g. cache = \"~/roughstick-bank-cache\".") from None
    _check_bank(bank, path.name)
    t1 = time.perf_counter()
    if ens["method"] != "count":
        return _run_subset(bank, b, ens, beam, out, t0, t1, overwrite=args.overwrite or o["overwrite"],
                           provenance=lambda ds: _provenance(ds, c, path, bank), spacing=s["spacing"])
    ds = rs.beam.simulate(bank, beam_length=np.asarray(b["lengths"], dtype=float), n=ens["n"],
                          seed=ens["seed"], protocol=ens["protocol"], beam=beam,
                          patch_length=b.get("patch_length"), beam_model=ens["beam_model"])
    t2 = time.perf_counter()
    closed = None
    if ens["beam_model"] == "sharp_front" and ens["protocol"] == "release":
        # the same beams in closed form from the bank's CCDF (every length from one tail)
        closed = rs.beam.stuck_probability_from_ccdf(
            rs.beam.adhesive_energy_ccdf(bank, dim="law"), beam_length=ds.beam_length.values, beam=beam,
            patch_length=b.get("patch_length")).stuck_probability.transpose("rh", "beam_length")
        ds["stuck_probability_closed_form"] = xr.DataArray(closed.values, dims=("rh", "beam_length"), attrs={
            "units": "1", "long_name": "P(stuck) of the sharp front in closed form on the bank's CCDF"})
    write_netcdf(_provenance(ds, c, path, bank), out / "beam.nc", compute=True, overwrite=True)
    finish_folder(out)
    src = "read from cache" if bank.attrs.get("from_cache") else "computed"
    LOG.info(f"bank: {bank.sizes['law']} laws x {bank.sizes['rh']} RH {src} in {t1 - t0:.1f} s "
             f"({bank.attrs.get('cache_file')}); {_patch_words(bank, c['surface']['spacing'])}")
    _log_tail_check(bank)
    LOG.info(f"beams: {ds.sizes['realization']} x {ds.sizes['beam_length']} lengths x {len(rh)} RH "
             f"in {t2 - t1:.2f} s")
    for r in ds.rh.values:
        for length in ds.beam_length.values:
            sel = dict(rh=r, beam_length=length)
            LOG.info(f"RH {r:.2f}  l {length * 1e6:7.1f} um  P(stuck) "
                     f"{float(ds.stuck_probability.sel(sel)):.3f} "
                     f"[{float(ds.stuck_probability_lower.sel(sel)):.3f}, "
                     f"{float(ds.stuck_probability_upper.sel(sel)):.3f}] "
                     f"(95 % Wilson interval, n = {ds.sizes['realization']})"
                     + ("" if closed is None else
                        f"; closed form on the bank {float(closed.sel(sel)):.3g}"))
    LOG.info(f"wrote {out / 'beam.nc'}")
    return 0


def _provenance(ds, c: dict, path: pathlib.Path, bank):
    """``ds`` with the CF global attributes, history and provenance of its patch bank (which PSD,
    humidities, patch surfaces, seeds, contact model, cache file) and the configuration file."""
    s, ens, bk = c["surface"], c["ensemble"], c["bank"]
    attrs = dataset_attrs("beam-scale stochastic stiction",
                          references=cite((PAPER, "section 5, Eqs. 13, 16, 36")))
    attrs.update(ds.attrs)  # the model's own (title, protocol, seed of the beams, beam, references)
    attrs.update(
        psd=str(s["psd"]) if s.get("psd") is not None else "paper Table 4 (Eq. 37, roughstick.stiction.cantilever_psd)",
        relative_humidity=[float(v) for v in bank.rh.values],
        patch_shape=[int(v) for v in np.broadcast_to(bank.attrs.get("subzone_shape", s.get("shape", 0)), 2)],
        patch_subzones=int(bank.attrs.get("subzones", 1)),
        patch_spacing=float(s["spacing"]), bank_laws=int(bank.sizes["law"]), bank_seed=int(bk["seed"]),
        bank_model=str(bank.attrs.get("contact_model", bk["model"])), bank_cache_file=str(bank.attrs.get("cache_file", "")),
        beam_seed=int(ens["seed"]), method=str(ens["method"]), beam_model=str(ens["beam_model"]),
        configuration=path.read_text(), **material_attrs(config_material(c["material"])))
    ds.attrs = attrs
    return append_history(ds, f"roughstick beam {path.name} (method={ens['method']})")


def _log_tail_check(bank) -> None:
    """The FFT-BEM re-check of the bank's largest Eq. 16 energies (rs.beam.build_patch_bank), per
    RH (below 0.8 build_patch_bank's ValidityWarning, logged as a warning line, names the fix)."""
    if "tail_bem_ratio" not in bank.attrs:
        return
    ratio = np.atleast_1d(bank.attrs["tail_bem_ratio"])
    lo, hi = (np.atleast_1d(bank.attrs.get(f"tail_bem_ratio_{s}", np.full(ratio.shape, np.nan))) for s in ("low", "high"))
    LOG.info(f"bank tail: the {int(bank.attrs['tail_checked'])} largest Eq. 16 energies against the FFT-BEM, "
             "median BEM/Eq. 16 per RH (95 % order-statistic interval): " + ", ".join(
                 f"{r:g}: {v:.2f} " + (f"[{a:.2f}, {b:.2f}]" if np.isfinite(a) and np.isfinite(b) else
                                       "(too few laws checked to bound it)" if "tail_bem_ratio_low" in bank.attrs
                                       else "(no interval: a bank cached before intervals were kept)")
                 for r, v, a, b in zip(bank.rh.values, ratio, lo, hi, strict=True)))


def _check_patch(b: dict, source: str) -> None:
    """The patch (default: the beam thickness) must fit on the shortest beam, checked before any work."""
    given = b.get("patch_length") is not None
    patch = float(b["patch_length"] if given else b["thickness"])
    shortest = float(np.min(b["lengths"]))
    if patch > shortest * (1 + 1e-9):
        key = "[beam] patch_length" if given else "[beam] thickness (the default patch_length)"
        raise ConfigError(
            f"{source}: {key} = {patch * 1e6:g} um is longer than the shortest beam ([beam] lengths: "
            f"{shortest * 1e6:g} um): the interface under a beam is cut into patches of that length. "
            f"Set [beam] patch_length to at most '{shortest * 1e6:g} um', or remove the shorter "
            "lengths from [beam] lengths."
        )


def _check_bank(bank, source: str) -> None:
    """The bank's energies, checked (units, sign, physical bound) before the beams: a cached bank
    that fails names its file and how to rebuild it."""
    where = bank.attrs.get("cache_file")
    try:
        adhesive_energy_values(bank, name="the patch bank", units_fix=(
            f"delete {where} (or set [bank] cache to another folder) to rebuild it" if where else
            "report it: a bank built by roughstick is in J m-2"))
    except ValueError as err:
        raise ConfigError(f"{source}: [bank] {err}") from None


def _check_heights(s: dict, source: str) -> None:
    """[surface] height_distribution, maps, skewness and kurtosis agree, before any work."""
    problems = johnson_problems(s)
    if s["height_distribution"] == "maps" and not s.get("maps"):
        problems.append('[surface] height_distribution = "maps" needs the maps: maps = ["scan1.tiff", ...]')
    if s["height_distribution"] != "maps" and s.get("maps"):
        problems.append('[surface] maps only apply with height_distribution = "maps"')
    if problems:
        raise ConfigError(f"{source}: " + "; ".join(problems) + ".")


def _check_method(ens: dict, source: str) -> None:
    """[ensemble] method settings, checked before anything is computed."""
    if ens["method"] == "count":
        return
    problems = []
    if ens["beam_model"] != "sharp_front":
        problems.append(f"[ensemble] method = {ens['method']!r} needs beam_model = 'sharp_front' (the cohesive "
                        "beam has no stuck margin to condition on; use method = 'count' for it)")
    problems += small_p_problems("ensemble", ens)
    if problems:
        raise ConfigError(f"{source}: " + "; ".join(problems) + ".")


def _patch_words(bank, spacing: float) -> str:
    """What one law of the bank is: its patch, its sub-zones and its contact model."""
    ny, nx = (int(v) for v in np.atleast_1d(bank.attrs.get("subzone_shape", (0, 0)))[:2])
    m = int(bank.attrs.get("subzones", 1))
    words = f"each law a patch of {ny * spacing * 1e6:.3g} x {m * nx * spacing * 1e6:.3g} um at {spacing * 1e9:g} nm"
    if m > 1:
        words += f" ({m} sub-zones of {ny} x {nx} px composed)"
    return words + f", contact model {bank.attrs.get('contact_model', '?')}"


def _run_subset(bank, b, ens, beam, out, t0, t1, *, overwrite, provenance, spacing) -> int:
    """P(stuck)(rh, beam_length) on the bank by subset simulation (or crude Monte Carlo)."""
    method = ens["method"]
    points = bank.sizes["rh"] * len(b["lengths"])  # one line per level, the time left over all
    with staged_progress(points, what=f"{method} (RH x length)", budget=ens["max_evaluations"]):
        ds = rs.stuck_probability(
            bank, method=method, beam_length=np.asarray(b["lengths"], dtype=float), protocol=ens["protocol"],
            beam=beam, patch_length=b.get("patch_length"), target_cv=ens["target_cv"],
            max_evaluations=ens["max_evaluations"], n_per_level=ens["n_per_level"],
            seed=ens["seed"], output=out / "levels", overwrite=overwrite)
    t2 = time.perf_counter()
    write_netcdf(provenance(ds), out / "beam.nc", compute=True, overwrite=True)
    finish_folder(out)
    src = "read from cache" if bank.attrs.get("from_cache") else "computed"
    n_law = int(ds.attrs["n_law"])
    LOG.info(f"bank: {n_law} laws x {bank.sizes['rh']} RH {src} in {t1 - t0:.1f} s "
             f"({bank.attrs.get('cache_file')}); {_patch_words(bank, spacing)}")
    _log_tail_check(bank)
    LOG.info(f"{method}: P(stuck) [95 % interval], cv, beams evaluated, in {t2 - t1:.2f} s; "
             "'bank' = closed form on the same bank")
    for r in ds.rh.values:
        for length in ds.beam_length.values:
            d = ds.sel(rh=r, beam_length=length)
            LOG.info(f"RH {r:.2f}  l {length * 1e6:7.1f} um  P(stuck) {float(d.stiction_probability):.3g} "
                     f"[{float(d.stiction_probability_lower):.3g}, {float(d.stiction_probability_upper):.3g}] "
                     f"cv {float(d.coefficient_of_variation):.2f}, {int(d.n_evaluations)} beams"
                     + ("" if int(d.converged) else " (target cv not met)")
                     + (" (few final lineages: cv unreliable)" if int(d.few_lineages) else "")
                     + f"; bank (exact on its {n_law} laws) {float(d.bank_stiction_probability):.3g}")
    if float(ds.bank_stiction_probability.min()) < 1.0 / n_law:
        LOG.info(f"note: P(stuck) below 1/{n_law} is not resolved by a bank of {n_law} laws (0 on the bank "
                 "means no law holds the beam's last patch); for smaller risks use `roughstick risk` "
                 "with method = 'subset' (zone model) or a larger bank (docs/rare_events.md)")
    LOG.info(f"wrote {out / 'beam.nc'}")
    return 0
