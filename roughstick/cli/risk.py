"""``roughstick risk CONFIG.toml``: stiction probability of cantilevers versus RH and length.

Reads a TOML file (see ``examples/risk.toml``), predicts the interaction-zone adhesive energy Γ
with the paper's §5.2 model (or reads a Γ sample you computed), and writes ``risk.nc`` plus PNG
plots: P(stuck) versus RH for each beam length, P versus length, the Fig. 20a/b-style Γ bands
with your measured points, and the predicted crack length. The file follows the one schema of
every command (docs/configuration.md): quantities with units in the value (``width = "30 um"``),
humidities as fractions; every value is checked before the simulation starts.
"""

from __future__ import annotations

import pathlib
import warnings

import numpy as np
import xarray as xr

import roughstick as rs

from .._core.conventions import ATTRS, append_history, coord_attrs, set_attrs
from .._core.materials import POLYSILICON, material_attrs
from .._core.progress import staged_progress
from ..paper import cantilever as figures
from ..plotting.save import save_figure
from ..reliability.surface import ARTEFACT_RATIO
from ..stiction.interaction_zone import TABLE4
from ..stiction.strip_tail import MODEL_BAND, model_band_problem
from ._common import (
    LOG,
    add_figure_options,
    check_scheduler,
    claim_folder,
    config_spellings,
    figure_options,
    finish_folder,
    run_status,
    small_p_problems,
)
from ._config import (
    ConfigError,
    Field,
    check_memory,
    config_material,
    johnson_problems,
    parse,
    read_toml,
)
from ._types import read_map


def register(sub):
    p = sub.add_parser(
        "risk",
        help="stiction probability of cantilevers vs RH and beam length (paper §5); NetCDF + plots",
        description=__doc__,
    )
    p.add_argument("config", help="TOML configuration (docs/configuration.md; `roughstick examples --out examples` writes examples/risk.toml)")
    p.add_argument("--out", default=None, help="output folder (default: [output] folder, else ./risk-output)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace the results of a run with other parameters in the output folder")
    add_figure_options(p)
    p.set_defaults(func=_run, remedies=lambda args: config_spellings(contact_model="risk", key="model",
                                                                                     samples="risk"))


def load_risk_config(path) -> dict:
    """Read and validate a ``roughstick risk`` TOML file (the one schema of
    :mod:`roughstick.cli._config`); return SI values and absolute paths. Every value, the measured
    points' files included, is checked here, before any simulation starts."""
    path = pathlib.Path(path).resolve()
    c = parse(read_toml(path), "risk", base=path.parent, source=path.name)
    problems = []
    for key in ("psd",):
        if key in c["surface"] and not c["surface"][key].is_file():
            problems.append(f"[surface] {key}: file {str(c['surface'][key])!r} not found")
    if "adhesive_energy" in c["ensemble"] and not c["ensemble"]["adhesive_energy"].exists():
        problems.append(f"[ensemble] adhesive_energy: {str(c['ensemble']['adhesive_energy'])!r} not found")
    for k, m in enumerate(c["measured"]):
        try:
            m.update(_measured_file(m))
        except (ValueError, FileNotFoundError) as exc:
            problems.append(f"[[measured]] #{k + 1}: {exc}")
            continue
        if "relative_humidity" not in m:
            problems.append(f"[[measured]] #{k + 1} needs relative_humidity = [...] (or file = 'points.csv')")
        elif not {"crack_length", "adhesive_energy"} & set(m):
            problems.append(f"[[measured]] #{k + 1} needs crack_length or adhesive_energy")
        else:
            for v in ("crack_length", "adhesive_energy"):
                if v in m and len(m[v]) != len(m["relative_humidity"]):
                    problems.append(f"[[measured]] #{k + 1}: {v} has {len(m[v])} values, "
                                    f"relative_humidity {len(m['relative_humidity'])}")
    r = c["risk"]
    problems += _height_problems(c)
    if r["method"] == "strips":
        if "shape" in c["surface"]:
            problems.append("[risk] method = 'strips' answers on the beam's own interaction zone (Δs × w, cut "
                            "into sub-zones): remove [surface] shape")
        if "adhesive_energy" in c["ensemble"]:
            problems.append("[risk] method = 'strips' simulates its own sub-zones: remove [ensemble] "
                            "adhesive_energy, or use method = 'count' to read that sample")
        if r["model"] not in ("auto", "modified_dmt", "fft_bem"):
            problems.append(f"[risk] model = {r['model']!r}: method = 'strips' runs 'auto' (Eq. 16 corrected "
                            "by fft_bem), 'modified_dmt' or 'fft_bem'")
        band = r.get("model_band")
        problem = None if band is None else model_band_problem(band)
        if problem is not None:
            problems.append(f"[risk] model_band = {list(band)}: {problem.replace('(below, above)', '[below, above]')}, "
                            f"e.g. model_band = {list(MODEL_BAND)}")
    elif r["method"] != "count":
        if "shape" not in c["surface"]:
            problems.append(f"[risk] method = {r['method']!r} evaluates one zone per model call and the "
                            "beam's whole interaction zone (524 x 6000 px at 5 nm for the paper's beam) is "
                            "out of its reach: use method = 'count' (the default), which answers on the "
                            "whole zone, or set [surface] shape, e.g. shape = [128, 128], knowing that its "
                            "P(stuck) is that of the smaller zone (a 0.64 um square carries 130-170 x the "
                            "whole zone's Γ at 30-50 % RH; docs/zone_size.md)")
        if "adhesive_energy" in c["ensemble"]:
            problems.append(f"[risk] method = {r['method']!r} simulates its own zones: remove "
                            "[ensemble] adhesive_energy, or use method = 'count' to read that sample")
        problems += small_p_problems("risk", r)
        if r["model"] not in ("auto", "modified_dmt", "fft_bem"):
            problems.append(f"[risk] model = {r['model']!r} applies to method = 'count'; the "
                            f"zones of method = {r['method']!r} run on 'auto', 'modified_dmt' or "
                            "'fft_bem'")
    elif r["model"] != "auto" and "adhesive_energy" in c["ensemble"]:
        problems.append(f"[risk] model = {r['model']!r} computes Γ, which [ensemble] "
                        "adhesive_energy gives: remove one of them")
    if problems:
        raise ConfigError(f"{path.name}: " + "; ".join(problems) + ".")
    # the beam is made of the film: its modulus is the material's unless [beam] gives one
    c["beam"].setdefault("youngs_modulus", config_material(c["material"], path.name).youngs_modulus)
    if "shape" in c["surface"]:
        check_memory(c["surface"]["shape"], chunks=c["ensemble"].get("chunks") or 1,
                     where=f"{path.name}: [surface]")
    c["path"] = path
    return c


def _height_problems(c) -> list[str]:
    """What is wrong with the height-distribution keys of [surface] (empty: nothing)."""
    s, kind = c["surface"], c["surface"]["height_distribution"]
    problems = johnson_problems(s)
    if kind == "maps" and not s.get("maps"):
        problems.append('[surface] height_distribution = "maps" needs the maps: maps = ["scan1.tiff", ...]')
    if kind != "maps" and s.get("maps"):
        problems.append('[surface] maps only apply with height_distribution = "maps"')
    if kind != "gaussian" and "adhesive_energy" in c["ensemble"]:
        problems.append("[surface] height_distribution is for the simulated surfaces, which "
                        "[ensemble] adhesive_energy replaces: remove one of them")
    return problems


def _heights(s):
    """The ``height_distribution=`` of the zones' surfaces ([surface]), said before the work:
    None for Gaussian surfaces."""
    kind = s["height_distribution"]
    if kind == "gaussian":
        return None
    if kind == "johnson":
        dist = rs.surface.height_distribution(skewness=s["skewness"], kurtosis=s["kurtosis"])
    else:
        dist = rs.surface.height_distribution([read_map(f) for f in s["maps"]])
    LOG.info(f"heights: {dist.attrs['family']} (skewness {dist.attrs['skewness']:.3g}, kurtosis "
             f"{dist.attrs['kurtosis']:.3g}; [surface] height_distribution = {kind!r}), imposed by "
             "translation")
    return dist


#: CSV columns of measured points: header name -> (config key, kind of quantity or None).
_CSV = {"relative_humidity": ("relative_humidity", None), "crack_length": ("crack_length", "length"),
        "adhesive_energy": ("adhesive_energy", "energy_per_area")}


def _measured_file(m: dict) -> dict:
    """Columns of a measured-points CSV: header ``relative_humidity,crack_length [um]`` (units in
    brackets; relative humidity as fractions)."""
    if "file" not in m:
        return {}
    path = m["file"]
    if not path.is_file():
        raise FileNotFoundError(f"measured points file {str(path)!r} not found")
    lines = [ln for ln in path.read_text().splitlines() if ln.strip() and not ln.startswith("#")]
    header = [h.strip() for h in lines[0].split(",")] if lines else []
    out = {}
    for col, name in enumerate(header):
        key, unit = (name.split("[", 1) + [""])[:2]
        key, unit = key.strip(), unit.rstrip("]").strip()
        if key not in _CSV:
            raise ValueError(f"{path.name}: unknown column {name!r}; use relative_humidity, "
                             "'crack_length [um]' or 'adhesive_energy [mJ m-2]'")
        conf_key, kind = _CSV[key]
        vals = [ln.split(",")[col].strip() for ln in lines[1:]]
        if kind is None:
            if unit:
                vals = [f"{v} {unit}" for v in vals]
            f = Field("relative_humidity", "", many=True)
            parsed = [float(v) if _isnum(v) else v for v in vals]
        else:
            if not unit:
                raise ValueError(f"{path.name}: column {name!r} needs its unit in brackets, "
                                 f"e.g. '{key} [{'um' if kind == 'length' else 'mJ m-2'}]'")
            f = Field(kind, "", many=True)
            parsed = [f"{v} {unit}" for v in vals]
        out[conf_key] = parse({"x": {"v": parsed}}, "_csv", base=path.parent, source=path.name,
                              schema={"x": {"v": f}})["x"]["v"]
    return out


def _isnum(v: str) -> bool:
    try:
        float(v)
    except ValueError:
        return False
    return True


def _beam(c):
    b = c["beam"]
    d = rs.PAPER_CANTILEVER
    beam = rs.Cantilever(
        length=d.length, width=b["width"], thickness=b["thickness"], gap=b["gap"],
        youngs_modulus=b["youngs_modulus"], interaction_length=b.get("interaction_length"),
    )
    return beam, list(b.get("lengths", [d.length]))


def _measured(c, beam):
    out = []
    for m in c["measured"]:
        kw = {k: np.asarray(m[k]) for k in ("crack_length", "adhesive_energy") if k in m}
        out.append(rs.stiction.measured_adhesion(np.asarray(m["relative_humidity"]), beam=beam,
                                                 label=m.get("label", "measured"), **kw))
    return out


def _psd(s):
    if "psd" in s:
        return rs.io.open_dataset(s["psd"])["psd"]
    d = TABLE4
    return rs.stiction.cantilever_psd(
        roughness=s.get("roughness", d["roughness"]),
        asperity_radius=s.get("asperity_radius", d["asperity_radius"]),
        asperity_density=s.get("asperity_density", d["asperity_density"]),
        qmax=s.get("qmax", d["qmax"]),
    )


def zone_of_the_answer(c, beam) -> dict:
    """The zone whose P(stuck) ``roughstick risk`` gives: [surface] shape, else the beam's whole
    interaction zone Δs × w; a smaller zone is warned about (logged, before the work) with the
    measured size law's bias of its Γ (:func:`roughstick.stiction.zone_size_bias`). Returns the
    attributes of ``risk.nc`` that say it; empty when Γ is read from [ensemble] adhesive_energy
    (the zone is that of the given sample)."""
    if "adhesive_energy" in c["ensemble"]:
        return {}
    s = c["surface"]
    whole = rs.stiction.interaction_zone_shape(beam, spacing=s["spacing"])
    shape = tuple(int(v) for v in s.get("shape", whole))
    um = s["spacing"] * 1e6
    out = {"zone_shape": list(shape), "zone_area": float(shape[0] * shape[1] * s["spacing"] ** 2),
           "zone": f"the beam's interaction zone Δs × w, {shape[0] * um:.3g} x {shape[1] * um:.3g} um"}
    if shape[0] >= 0.99 * whole[0] and shape[1] >= 0.99 * whole[1]:
        return out
    bias = rs.stiction.zone_size_bias(shape, spacing=s["spacing"], beam=beam)
    if np.all(np.isnan(bias.values)):
        cost = ("more than 130-170 at 30-50 %" if out["zone_area"] < 1e-12 else "(outside the measured sizes)")
    else:
        cost = ", ".join(f"{float(v):.3g} at {100 * float(r):g} %" for r, v in zip(bias.rh.values, bias.values))
    out["zone"] = (f"a zone of {shape[0]} x {shape[1]} px ({shape[0] * um:.3g} x {shape[1] * um:.3g} um), "
                   f"smaller than the beam's {whole[0]} x {whole[1]} px")
    out["zone_size_bias"] = f"median Γ of the zone over the beam zone's (Table 4, Eq. 16): {cost} RH"
    LOG.warning(
        f"warning: [surface] shape = [{shape[0]}, {shape[1]}] is {out['zone']} ({out['zone_area'] * 1e12:.3g} "
        f"against {whole[0] * whole[1] * s['spacing'] ** 2 * 1e12:.3g} um2): a smaller zone rests on lower summits "
        f"and carries a larger Γ. On Table-4 surfaces (Eq. 16) its median Γ is the whole zone's times {cost} RH "
        "(docs/zone_size.md), so this P(stuck) is that of the smaller zone: it overstates the beam's and its "
        "crossing humidities come too early. Remove [surface] shape to answer on the beam's zone.")
    return out


_SUBSET_VARS = ("stiction_probability", "stiction_probability_lower", "stiction_probability_upper",
                "coefficient_of_variation", "n_evaluations", "converged", "few_lineages")


def _zone_psd(s):
    """The PSD the zones are drawn from: [surface] psd, or the Eq. 37 parameters exactly on any grid."""
    import functools

    psd = _psd(s)
    if isinstance(psd, xr.Dataset):
        psd = functools.partial(rs.surface.self_affine_psd, **{k: float(psd[k]) for k in ("s0", "s1", "q0", "qmax")})
    return psd


def _subset_risk(c, beam, lengths, out, *, overwrite):
    """P(stuck)(adsorbed_layer, beam_length, rh) by subset simulation (or crude Monte Carlo) of
    the pull-out proxy on zones of [surface] shape, each to [risk] target_cv; crossing humidities."""
    ens, s, r = c["ensemble"], c["surface"], c["risk"]
    psd = _zone_psd(s)
    rh = list(ens["relative_humidity"])
    kw = {"scheduler": c["run"]["scheduler"]} if "scheduler" in c["run"] else {}
    kw["model"] = r["model"]
    material = config_material(c["material"])
    if material != POLYSILICON:  # the default is not named: earlier runs keep resuming
        kw["material"] = material
    if r["method"] == "subset":
        kw["n_per_level"] = r["n_per_level"]
    heights = _heights(s)
    if heights is not None:  # Gaussian: not named, so earlier runs keep resuming
        kw["height_distribution"] = heights
    per_layer = []
    # one line per level, with the time left over every layer, length and humidity
    points = len(ens["adsorbed_layer"]) * len(lengths) * len(rh)
    used = {}  # the zone model run ("auto" resolved by failure_probability) and why
    with staged_progress(points, what=r["method"].replace("_", " "), budget=r["max_evaluations"]) as prog, \
            warnings.catch_warnings():
        # said once, before the work, with its measured cost (zone_of_the_answer)
        warnings.filterwarnings("ignore", message="zones of .* are smaller than the beam's interaction zone")
        for layer in ens["adsorbed_layer"]:
            per_length = []
            for length in lengths:
                LOG.info(f"[{layer}] l = {length * 1e6:g} um: {r['method']} on {s['shape'][0]} x {s['shape'][1]} px "
                         f"zones ({r['model']}), {len(rh)} humidities, target cv {r['target_cv']:g} ...")
                prog.context = f"[{layer}] l = {length * 1e6:g} um"
                ds = rs.stuck_probability(
                    psd, method=r["method"], relative_humidity=rh, shape=s["shape"], spacing=s["spacing"],
                    beam_length=length, beam=beam, target_cv=r["target_cv"],
                    max_evaluations=r["max_evaluations"], seed=ens["seed"], adsorbed_layer=layer,
                    confidence=r["confidence"], output=out / f"subset-{layer}-{length * 1e6:g}um",
                    overwrite=overwrite, **kw)
                if ds.attrs.get("contact_model", r["model"]) != used.get("model"):
                    used.update(model=ds.attrs.get("contact_model", r["model"]),
                                why=ds.attrs.get("model_selection", ""))
                    if used["why"]:
                        LOG.info(f"    {used['why']}")
                if "rh" not in ds.dims:
                    ds = ds.expand_dims("rh")
                if "failures_confirmed_by_bem" in ds:  # a variable: attrs do not survive the concat below
                    conf = ds["failures_confirmed_by_bem"]  # "checked" dropped (0) where humidities differ
                    ds["failures_checked_by_bem"] = xr.full_like(conf, int(conf.attrs.get("checked", 0)), dtype=int)
                    ds["failures_checked_by_bem"].attrs = {"units": "1",
                                                           "long_name": "failure states re-checked by the FFT-BEM"}
                keep = list(_SUBSET_VARS) + [v for v in ("failures_confirmed_by_bem", "failure_bem_ratio",
                                                        "failure_bem_ratio_low", "failure_bem_ratio_high",
                                                        "failures_checked_by_bem") if v in ds]
                per_length.append(ds[keep].drop_vars("water_height", errors="ignore"))
            per_layer.append(xr.concat(per_length, dim=xr.DataArray(lengths, dims="beam_length", name="beam_length")))
    risk = xr.concat(per_layer, dim=xr.DataArray(list(ens["adsorbed_layer"]), dims="adsorbed_layer",
                                                 name="adsorbed_layer"))
    risk["beam_length"].attrs = dict(ATTRS["beam_length"])
    risk["adsorbed_layer"].attrs = coord_attrs("adsorbed_layer", risk["adsorbed_layer"])
    cross = [rs.stiction.crossing_humidity(risk, probability=lev) for lev in r["levels"]]
    cross = xr.concat(cross, dim=xr.DataArray(r["levels"], dims="probability_level", name="probability_level"))
    cross["probability_level"].attrs = dict(ATTRS["probability_level"])
    for name in cross.data_vars:
        risk[name] = cross[name]
    risk.attrs.update(material_attrs(material))
    if used.get("why"):
        risk.attrs["model_selection"] = used["why"]
    risk.attrs["height_distribution"] = "gaussian" if heights is None else heights.attrs["family"]
    risk.attrs.update({"method": r["method"], "target_cv": r["target_cv"],
                       "contact_model": used.get("model", r["model"]),
                       "zone_shape": list(s["shape"]), "spacing": s["spacing"],
                       "probability_model": "pull-out proxy P(Gamma > Gamma_crit(l)) of paper section 5.2 "
                                            "on zones of zone_shape pixels"})
    return risk


def _gamma_samples(c, beam, out, *, overwrite):
    """Γ(adsorbed_layer, realization, rh): read from a file, or simulated with the §5.2 model."""
    ens, s = c["ensemble"], c["surface"]
    layers = list(ens["adsorbed_layer"])
    if "adhesive_energy" in ens:
        path = ens["adhesive_energy"]
        ds = rs.ensemble.open_ensemble(path) if path.is_dir() else rs.io.open_dataset(path)
        if "adhesive_energy" not in ds:
            raise ValueError(f"{path}: no 'adhesive_energy' variable (has {sorted(ds.data_vars)}).")
        if "adhesive_energy_accurate" in ds:
            raise ValueError(
                f"{path}: a multi-fidelity ensemble, whose adhesive_energy is the cheap model's on "
                "every surface: counting it would give the cheap model's P(stuck). Rerun it with one "
                "model on every surface (roughstick run with [ensemble] model = \"fft_bem\"), or "
                "remove [ensemble] adhesive_energy so that risk simulates the zones itself.")
        g = ds["adhesive_energy"]
        if "adsorbed_layer" not in g.dims:
            g = g.expand_dims(adsorbed_layer=[str(ds.attrs.get("adsorbed_layer_model", "given"))])
        LOG.info(f"read the Γ sample {dict(g.sizes)} from {path}")
        return g.load()
    spacing = s["spacing"]
    psd = _psd(s)
    shape = s.get("shape")
    rh = ens["relative_humidity"]
    parts = []
    model, material = c["risk"]["model"], config_material(c["material"])
    heights = _heights(s)
    for layer in layers:
        kw = {"material": material, "model": model}
        if heights is not None:  # Gaussian: not named, so earlier ensembles keep resuming
            kw["height_distribution"] = heights
        if ens["stream"]:
            kw["output"] = out / f"ensemble-{layer}"
            kw["overwrite"] = overwrite
        if "scheduler" in c["run"]:
            kw["scheduler"] = c["run"]["scheduler"]
        shp = shape or rs.stiction.interaction_zone_shape(beam, spacing=spacing)
        LOG.info(f"[{layer}] {ens['n']} surfaces of {shp[0]} x {shp[1]} px at {spacing * 1e9:g} nm, "
                 f"{len(rh)} humidities ...")
        ds = rs.stiction.predict_adhesive_energy(psd, beam=beam, relative_humidity=rh, n=ens["n"],
                                        spacing=spacing, shape=shape, adsorbed_layer=layer,
                                        seed=ens["seed"], chunks=ens.get("chunks"), **kw)
        parts.append(ds["adhesive_energy"].load())
    g = xr.concat(parts, dim=xr.DataArray(layers, dims="adsorbed_layer", name="adsorbed_layer"))
    return g


def _run(args):
    import matplotlib

    matplotlib.use("Agg")

    c = load_risk_config(args.config)
    cfg_path = c["path"]
    out = pathlib.Path(args.out).resolve() if args.out else c["output"].get(
        "folder", cfg_path.parent / "risk-output")
    overwrite = args.overwrite or c["output"]["overwrite"]
    # an unfinished (failed or killed) earlier run never blocks this one: its ensembles are
    # resumed when the parameters match and replaced otherwise
    check_scheduler(c["run"].get("scheduler"), where="[run] scheduler")  # before any work
    unfinished = run_status(out) == "running"
    claim_folder(out, command="risk", params={k: v for k, v in c.items() if k not in ("output", "run", "path")
                                              and not (k == "material" and not v)},
                 overwrite=overwrite, keep=[cfg_path],
                 legacy_params={"config": cfg_path.read_text()})
    beam, lengths = _beam(c)
    measured = _measured(c, beam)
    r = c["risk"]
    levels = r["levels"]

    zone = zone_of_the_answer(c, beam)  # said before the work
    if r["method"] == "strips":
        return _run_strips(c, beam, lengths, out, zone=zone)
    if r["method"] != "count":
        return _run_subset(c, beam, lengths, out, overwrite=overwrite or unfinished, zone=zone)
    g = _gamma_samples(c, beam, out, overwrite=overwrite or unfinished)
    g = set_attrs(g, "surface_adhesive_energy")
    risk = rs.stiction.risk_summary(g, beam_length=lengths, beam=beam, probabilities=levels,
                                    confidence=r["confidence"], interval=r["interval"], quantiles=r["quantiles"])
    risk["adhesive_energy"] = g
    risk.attrs.update(material_attrs(config_material(c["material"])), contact_model=c["risk"]["model"], **zone)
    for name in ("adsorbed_layer", "realization"):
        if name in risk.coords:
            risk[name].attrs = coord_attrs(name, risk[name]) if name in ATTRS else risk[name].attrs
    risk.attrs["configuration"] = cfg_path.read_text()
    append_history(risk, f"roughstick risk {cfg_path.name}")
    files = [rs.io.netcdf.write(risk, out / "risk.nc", compute=True, overwrite=True)]

    if c["output"]["figures"]:
        save = figure_options(args)
        _, fig = figures.stiction_probability(risk, level=0.5 if 0.5 in levels else None)
        files.append(save_figure(fig, out / "stiction_probability.png", **save))
        _, fig = figures.stiction_vs_length(risk)
        files.append(save_figure(fig, out / "stiction_vs_length.png", **save))
        _, fig = figures.fig20_adhesive_energy_bands(risk, measured=measured)
        files.append(save_figure(fig, out / "adhesive_energy_bands.png", **save))
        _, fig = figures.crack_length(risk, measured=measured)
        files.append(save_figure(fig, out / "crack_length.png", **save))

    n = risk.sizes.get("realization", g.sizes.get("realization"))
    LOG.info(f"from n = {n} surfaces per layer; [..] = {r['confidence']:.0%} interval"
             + (f"; P(stuck) of {zone['zone']}" if zone else ""))
    _crossing_table(risk, levels)
    for f in files:
        LOG.info(f"wrote {f}")
    finish_folder(out)
    return 0


def _run_subset(c, beam, lengths, out, *, overwrite, zone):
    r = c["risk"]
    risk = _subset_risk(c, beam, lengths, out, overwrite=overwrite)
    risk.attrs.update(zone)
    risk.attrs["configuration"] = c["path"].read_text()
    append_history(risk, f"roughstick risk {c['path'].name} (method={r['method']})")
    f = rs.io.netcdf.write(risk, out / "risk.nc", compute=True, overwrite=True)
    LOG.info(f"{r['method']}: P(stuck) of {zone['zone']}; [..] = {r['confidence']:.0%} interval, cv, "
             "model evaluations")
    for layer in risk.adsorbed_layer.values:
        for bl in risk.beam_length.values:
            for rh in risk.rh.values:
                d = risk.sel(adsorbed_layer=layer, beam_length=bl, rh=rh)
                LOG.info(f"  [{layer}] l={bl * 1e6:.0f}um RH {rh * 100:.1f}%: P = {float(d.stiction_probability):.3g} "
                         f"[{float(d.stiction_probability_lower):.3g}, {float(d.stiction_probability_upper):.3g}] "
                         f"cv {float(d.coefficient_of_variation):.2f}, {int(d.n_evaluations)} evaluations"
                         + ("" if int(d.converged) else " (target cv not met)")
                         + (" (few final lineages: cv unreliable)" if int(d.few_lineages) else "") + _confirmed(d))
    _crossing_table(risk, r["levels"])
    LOG.info(f"wrote {f} (no figures with method = {r['method']!r}: it has no Γ sample)")
    finish_folder(out)
    return 0


def _run_strips(c, beam, lengths, out, *, zone):
    """P(stuck)(adsorbed_layer, beam_length, rh) on the beam's own strips, small values included
    (:func:`roughstick.stiction.strip_stuck_probability`), and the crossing humidities."""
    ens, s, r = c["ensemble"], c["surface"], c["risk"]
    psd = _zone_psd(s)
    rh = list(ens["relative_humidity"])
    kw = {"scheduler": c["run"]["scheduler"]} if "scheduler" in c["run"] else {}
    material = config_material(c["material"])
    if material != POLYSILICON:
        kw["material"] = material
    per_layer = []
    for layer in ens["adsorbed_layer"]:
        LOG.info(f"[{layer}] strips of the beam's zone: {r['n_subzones']} sub-zones through Eq. 16"
                 + (f", {r['n_accurate']} through fft_bem where the answer depends on it" if r["model"] == "auto"
                    else f" ({r['model']} alone)") + f", {len(rh)} humidities, {len(lengths)} lengths ...")
        ds = rs.stuck_probability(psd, method="strips", relative_humidity=rh, beam_length=lengths, beam=beam,
                                  spacing=s["spacing"], model=r["model"], n=r["n_subzones"], seed=ens["seed"],
                                  confidence=r["confidence"], adsorbed_layer=layer,
                                  **({"n_accurate": r["n_accurate"], "target_cv": r["target_cv"]}
                                     if r["model"] == "auto" else {}),
                                  **({"model_band": tuple(r["model_band"])} if r.get("model_band") is not None
                                     else {}),
                                  **({"refine_crossing": list(r["levels"])} if r["refine_crossing"] else {}), **kw)
        if ds.attrs.get("refined_humidities"):
            LOG.info(f"[{layer}] refined at RH "
                     + ", ".join(f"{h * 100:.1f}%" for h in sorted(ds.attrs["refined_humidities"])))
        per_layer.append(ds.transpose("beam_length", "rh", ...))
    layers = xr.DataArray(list(ens["adsorbed_layer"]), dims="adsorbed_layer", name="adsorbed_layer")
    # each layer's crossings on its own humidities (refined ones differ between layers: NaN in the others)
    cross = xr.concat([_strip_crossings(ds, r["levels"]) for ds in per_layer], dim=layers)
    risk = xr.concat(per_layer, dim=layers, join="outer", combine_attrs="drop_conflicts")
    for name in cross.data_vars:
        risk[name] = cross[name]
    risk["beam_length"].attrs = dict(ATTRS["beam_length"])
    risk["adsorbed_layer"].attrs = coord_attrs("adsorbed_layer", risk["adsorbed_layer"])
    risk.attrs.update(zone, method="strips", configuration=c["path"].read_text(),
                      probability_model="released sharp-front beams on independent strips of the beam's "
                                        "interaction zone (paper Eq. 36, §5.2)")
    append_history(risk, f"roughstick risk {c['path'].name} (method=strips)")
    f = rs.io.netcdf.write(risk, out / "risk.nc", compute=True, overwrite=True)
    LOG.info(f"strips: P(stuck) of {zone['zone']}; [..] = {r['confidence']:.0%} interval, cv")
    for layer in risk.adsorbed_layer.values:
        for bl in risk.beam_length.values:
            for h in risk.rh.values:
                d = risk.sel(adsorbed_layer=layer, beam_length=bl, rh=h)
                if np.isnan(float(d.stiction_probability)):  # a humidity refined for another layer
                    continue
                if bool(d.beyond_reach):
                    what = (f"0: no combination of the sample sticks it (its threshold is "
                            f"{float(d.reach_margin):.3g} x the largest strip Γ found)" + _model_text(d))
                else:
                    what = (f"{float(d.stiction_probability):.3g} [{float(d.stiction_probability_lower):.3g}, "
                            f"{float(d.stiction_probability_upper):.3g}] cv {float(d.coefficient_of_variation):.2f}"
                            + _model_text(d)
                            + (" (few sub-zones carry it: interval unreliable)" if bool(d.few_subzones) else ""))
                LOG.info(f"  [{layer}] l={bl * 1e6:.0f}um RH {h * 100:.1f}%: P = {what}")
        if "random_pairs" in risk:
            pairs = risk["random_pairs"].sel(adsorbed_layer=layer)
            LOG.info(f"  [{layer}] fft_bem random pairs per RH: " + ", ".join(
                f"{h * 100:.1f}% {int(v) if v else 'none'}" for h, v in zip(risk.rh.values, pairs.values)
                if not np.isnan(v)))
    _crossing_table(risk, r["levels"])
    LOG.info(f"wrote {f} (no figures with method = 'strips': it has no Γ sample)")
    finish_folder(out)
    return 0


def _strip_crossings(ds, levels) -> xr.Dataset:
    """The crossing humidities of one strips result at every level; a beyond-reach cell (no
    combination of the sample fails) below every level, said with its margin."""
    fill = ds.copy()
    for v in ("stiction_probability_upper", "stiction_probability_model_upper"):
        if v in fill:
            fill[v] = fill[v].fillna(0.0)
    cross = xr.concat([rs.stiction.crossing_humidity(fill, probability=lev) for lev in levels],
                      dim=xr.DataArray(list(levels), dims="probability_level", name="probability_level"))
    cross["probability_level"].attrs = dict(ATTRS["probability_level"])
    return cross


def _model_text(d) -> str:
    """The interval of P(stuck) with the model band, where the result carries one."""
    if "stiction_probability_model_lower" not in d:
        return ""
    hi = float(d.stiction_probability_model_upper)
    return (f"; with the model band [{float(d.stiction_probability_model_lower):.3g}, "
            + (f"{hi:.3g}]" if np.isfinite(hi) else "n/a: beyond reach there too]"))


def _confirmed(d) -> str:
    """The BEM re-check of an Eq. 16 point's failure states, when it has one: the confirmed
    fraction with its Wilson interval, the median ratio with its order-statistic interval."""
    if "failure_bem_ratio" not in d or not np.isfinite(float(d.failure_bem_ratio)):
        return ""
    f, r = float(d.failures_confirmed_by_bem), float(d.failure_bem_ratio)
    n = int(d["failures_checked_by_bem"]) if "failures_checked_by_bem" in d else 0
    if n > 0:
        k = int(round(f * n))
        lo, hi = (float(v) for v in rs.ensemble.binomial_interval(k, n, confidence=0.95))
        head = f", BEM: {k} of {n} failure states confirmed (95 % Wilson [{lo:.0%}, {hi:.0%}])"
    else:
        head = f", BEM: {f:.0%} of its failure states confirmed (number checked unknown: no interval)"
    lo, hi = (float(d[v]) if v in d else np.nan for v in ("failure_bem_ratio_low", "failure_bem_ratio_high"))
    band = (f"95 % [{lo:.2f}, {hi:.2f}]" if np.isfinite(lo) and np.isfinite(hi) else
            "no interval: too few states checked to bound the median" if "failure_bem_ratio_low" in d else
            "no interval: only the median is kept")
    return head + f", median BEM/Eq. 16 {r:.2f} ({band})" + (
        " (Eq. 16 artefacts: use [risk] model = 'fft_bem')" if r < ARTEFACT_RATIO else "")


def _crossing_table(risk, levels):
    """A short table on the terminal, each crossing with its interval."""
    layers = list(risk.adsorbed_layer.values) if "adsorbed_layer" in risk.dims else [None]
    for layer in layers:
        d = risk.sel(adsorbed_layer=layer) if layer is not None else risk
        if layer is not None:
            LOG.info(f"adsorbed layer: {layer}")
        for lev in levels:
            row = []
            for bl in np.atleast_1d(d.beam_length.values):
                cr = d.crossing_humidity.sel(probability_level=lev, beam_length=bl)
                lo = d.crossing_humidity_lower.sel(probability_level=lev, beam_length=bl)
                hi = d.crossing_humidity_upper.sel(probability_level=lev, beam_length=bl)
                cell = f"l={bl * 1e6:.0f}um: {_pct(cr)} [{_pct(lo)}, {_pct(hi)}]"
                if "crossing_humidity_model_lower" in d:
                    mlo, mhi = (d[f"crossing_humidity_model_{e}"].sel(probability_level=lev, beam_length=bl)
                                for e in ("lower", "upper"))
                    cell += f" (with the model band [{_pct(mlo)}, {_pct(mhi)}])"
                row.append(cell)
            LOG.info(f"  RH where P(stuck) reaches {lev:g}: " + "; ".join(row))


def _pct(v) -> str:

    v = float(v)
    if np.isnan(v):
        return "n/a"
    if v == -np.inf:
        return "<min RH"
    if v == np.inf:
        return ">max RH"
    return f"{v * 100:.1f}%"
