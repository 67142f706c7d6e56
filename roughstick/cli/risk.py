"""``roughstick risk CONFIG.toml``: stiction probability of cantilevers versus RH and length.

Reads a TOML file (see ``examples/risk.toml``), predicts the interaction-zone adhesive energy Γ
with the paper's §5.2 model (or reads a Γ sample you computed), and writes ``risk.nc`` plus PNG
plots: P(stuck) versus RH for each beam length, P versus length, the Fig. 20a/b-style Γ bands
with your measured points, and the predicted crack length. Lengths in the file carry their unit
in the key (``_um``, ``_nm``); humidities are in percent (``rh_percent``).
"""

from __future__ import annotations

import pathlib

import numpy as np
import xarray as xr

import roughstick as rs

from .. import plotting
from .._core.conventions import append_history, set_attrs

_SCHEMA = {
    "output": {"directory"},
    "beam": {"width_um", "thickness_um", "gap_um", "youngs_modulus_GPa", "interaction_length_um",
             "lengths_um"},
    "surface": {"roughness_nm", "asperity_radius_nm", "asperity_density_per_um2", "qmax_rad_per_um",
                "spacing_nm", "shape", "psd"},
    "humidity": {"rh_percent", "adsorbed_layer"},
    "ensemble": {"realizations", "seed", "chunks", "stream", "scheduler", "adhesive_energy"},
    "risk": {"levels", "confidence", "interval", "quantiles"},
    "measured": {"rh_percent", "crack_length_um", "adhesive_energy_mJ_per_m2", "label", "file"},
}


def register(sub):
    p = sub.add_parser(
        "risk",
        help="stiction probability of cantilevers vs RH and beam length (paper §5); NetCDF + plots",
        description=__doc__,
    )
    p.add_argument("config", help="TOML configuration (see examples/risk.toml)")
    p.add_argument("--out", default=None, help="output folder (default: [output] directory, else ./risk-output)")
    p.set_defaults(func=_run)


def _load_toml(path: pathlib.Path) -> dict:
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        try:
            import tomli as tomllib
        except ModuleNotFoundError as exc:  # pragma: no cover
            raise ValueError("reading TOML on Python 3.10 needs the 'tomli' package: pip install tomli") from exc
    if not path.is_file():
        raise FileNotFoundError(f"configuration file {str(path)!r} not found.")
    with open(path, "rb") as f:
        try:
            cfg = tomllib.load(f)
        except tomllib.TOMLDecodeError as exc:
            raise ValueError(f"{path}: not valid TOML: {exc}") from exc
    unknown = sorted(set(cfg) - set(_SCHEMA))
    if unknown:
        raise ValueError(f"{path}: unknown section(s) {unknown}; known: {sorted(_SCHEMA)}.")
    for sec, body in cfg.items():
        items = body if isinstance(body, list) else [body]
        for it in items:
            if not isinstance(it, dict):
                raise ValueError(f"{path}: [{sec}] must be a table.")
            bad = sorted(set(it) - _SCHEMA[sec])
            if bad:
                raise ValueError(f"{path}: unknown key(s) {bad} in [{sec}]; known: {sorted(_SCHEMA[sec])}.")
    return cfg


def _resolve(base: pathlib.Path, p: str) -> pathlib.Path:
    q = pathlib.Path(p).expanduser()
    return q if q.is_absolute() else base / q


def _beam(cfg):

    b = cfg.get("beam", {})
    d = rs.PAPER_CANTILEVER
    beam = rs.Cantilever(
        length=d.length,
        width=b.get("width_um", d.width * 1e6) * 1e-6,
        thickness=b.get("thickness_um", d.thickness * 1e6) * 1e-6,
        gap=b.get("gap_um", d.gap * 1e6) * 1e-6,
        youngs_modulus=b.get("youngs_modulus_GPa", d.youngs_modulus / 1e9) * 1e9,
        interaction_length=(b["interaction_length_um"] * 1e-6 if "interaction_length_um" in b else None),
    )
    lengths = [float(v) * 1e-6 for v in b.get("lengths_um", [d.length * 1e6])]
    return beam, lengths


def _measured(cfg, base, beam):


    sets = cfg.get("measured", [])
    sets = sets if isinstance(sets, list) else [sets]
    out = []
    for m in sets:
        m = dict(m)
        if "file" in m:
            path = _resolve(base, m.pop("file"))
            if not path.is_file():
                raise FileNotFoundError(f"measured points file {str(path)!r} not found.")
            table = np.genfromtxt(path, delimiter=",", names=True, dtype=float, encoding="utf-8")
            cols = set(table.dtype.names or ())
            for c in cols & {"rh_percent", "crack_length_um", "adhesive_energy_mJ_per_m2"}:
                m[c] = np.atleast_1d(table[c]).tolist()
            if "rh_percent" not in m:
                raise ValueError(f"{path}: needs a header row with column 'rh_percent' and "
                                 "'crack_length_um' or 'adhesive_energy_mJ_per_m2'.")
        if "rh_percent" not in m:
            raise ValueError("[measured] needs rh_percent = [...] (or file = 'points.csv').")
        rh = np.asarray(m["rh_percent"], dtype=float) / 100.0
        kw = {}
        if "crack_length_um" in m:
            kw["crack_length"] = np.asarray(m["crack_length_um"], dtype=float) * 1e-6
        if "adhesive_energy_mJ_per_m2" in m:
            kw["adhesive_energy"] = np.asarray(m["adhesive_energy_mJ_per_m2"], dtype=float) * 1e-3
        out.append(rs.measured_adhesion(rh, beam=beam, label=m.get("label", "measured"), **kw))
    return out


def _gamma_samples(cfg, base, beam, out):
    """Γ(adsorbed_layer, realization, rh): read from a file, or simulated with the §5.2 model."""


    ens = cfg.get("ensemble", {})
    hum = cfg.get("humidity", {})
    layers = hum.get("adsorbed_layer", ["none", "paper"])
    layers = [layers] if isinstance(layers, str) else list(layers)
    if "adhesive_energy" in ens:
        path = _resolve(base, ens["adhesive_energy"])
        ds = rs.open_ensemble(path) if pathlib.Path(path).is_dir() else rs.open_dataset(path)
        if "adhesive_energy" not in ds:
            raise ValueError(f"{path}: no 'adhesive_energy' variable (has {sorted(ds.data_vars)}).")
        g = ds["adhesive_energy"]
        if "adsorbed_layer" not in g.dims:
            g = g.expand_dims(adsorbed_layer=[str(ds.attrs.get("adsorbed_layer_model", "given"))])
        print(f"read the Γ sample {dict(g.sizes)} from {path}")
        return g.load()
    s = cfg.get("surface", {})
    spacing = float(s.get("spacing_nm", 5.0)) * 1e-9
    if "psd" in s:
        psd_path = _resolve(base, s["psd"])
        psd = rs.open_dataset(psd_path)["psd"]
    else:
        psd = rs.cantilever_psd(
            roughness=[float(v) * 1e-9 for v in s.get("roughness_nm", [2.6, 2.4])],
            asperity_radius=float(s.get("asperity_radius_nm", 220.0)) * 1e-9,
            asperity_density=float(s.get("asperity_density_per_um2", 80.1)) * 1e12,
            qmax=float(s.get("qmax_rad_per_um", 289.0)) * 1e6,
        )
    shape = tuple(int(v) for v in s["shape"]) if "shape" in s else None
    rh = [float(v) / 100.0 for v in hum.get("rh_percent", list(range(30, 96, 5)))]
    n = ens.get("realizations", 20)
    chunks = ens.get("chunks")
    parts = []
    for layer in layers:
        kw = {}
        if ens.get("stream", True):
            kw["output"] = out / f"ensemble-{layer}"
        if "scheduler" in ens:
            kw["scheduler"] = ens["scheduler"]
        shp = shape or rs.interaction_zone_shape(beam, spacing=spacing)
        print(f"[{layer}] {n} surfaces of {shp[0]} x {shp[1]} px at {spacing * 1e9:g} nm, "
              f"{len(rh)} humidities ...", flush=True)
        ds = rs.predict_adhesive_energy(psd, beam=beam, relative_humidity=rh, n=n, spacing=spacing,
                                        shape=shape, adsorbed_layer=layer, seed=ens.get("seed", 0),
                                        chunks=chunks, **kw)
        parts.append(ds["adhesive_energy"].load())
    g = xr.concat(parts, dim=xr.DataArray(layers, dims="adsorbed_layer", name="adsorbed_layer"))
    g["adsorbed_layer"].attrs = {"long_name": "adsorbed water layer model", "units": "1"}
    return g


def _run(args):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    cfg_path = pathlib.Path(args.config)
    cfg = _load_toml(cfg_path)
    base = cfg_path.resolve().parent
    out = pathlib.Path(args.out) if args.out else _resolve(base, cfg.get("output", {}).get("directory", "risk-output"))
    out.mkdir(parents=True, exist_ok=True)
    beam, lengths = _beam(cfg)
    measured = _measured(cfg, base, beam)
    risk_cfg = cfg.get("risk", {})
    levels = [float(v) for v in risk_cfg.get("levels", [0.05, 0.5, 0.95])]

    g = _gamma_samples(cfg, base, beam, out)
    g = set_attrs(g, "surface_adhesive_energy")
    if "adsorbed_layer" in g.coords:
        g["adsorbed_layer"].attrs = {"long_name": "adsorbed water layer model", "units": "1"}
    risk = rs.stiction_risk(
        g, length=lengths, beam=beam, levels=levels,
        confidence=float(risk_cfg.get("confidence", 0.95)),
        interval=risk_cfg.get("interval", "wilson"),
        quantiles=risk_cfg.get("quantiles", [0.025, 0.5, 0.975]),
    )
    risk["adhesive_energy"] = g
    if "realization" in risk.coords:
        risk["realization"].attrs = {"units": "1", "long_name": "realization index"}
    risk.attrs["configuration"] = cfg_path.read_text()
    append_history(risk, f"roughstick risk {cfg_path.name}")
    nc = rs.io.netcdf.write(risk, out / "risk.nc", compute=True)
    files = [nc]

    layers = list(risk.adsorbed_layer.values) if "adsorbed_layer" in risk.dims else [None]
    fig, axes = plt.subplots(1, len(layers), figsize=(5.5 * len(layers), 4), layout="constrained",
                             squeeze=False)
    for ax, layer in zip(axes[0], layers, strict=True):
        plotting.plot_stiction_probability(risk, ax=ax, layer=layer, level=0.5 if 0.5 in levels else None)
        if layer is not None:
            ax.set_title(f"P(stuck), adsorbed layer: {layer}")
    files.append(_save(fig, out / "stiction_probability.png"))
    fig, axes = plt.subplots(1, len(layers), figsize=(5.5 * len(layers), 4), layout="constrained",
                             squeeze=False)
    for ax, layer in zip(axes[0], layers, strict=True):
        plotting.plot_stiction_vs_length(risk, ax=ax, layer=layer, rh=risk.rh.values[::3])
        if layer is not None:
            ax.set_title(f"adsorbed layer: {layer}")
    files.append(_save(fig, out / "stiction_vs_length.png"))
    files.append(_save(plotting.plot_cantilever_comparison(risk, measured=measured),
                       out / "adhesive_energy_bands.png"))
    fig, axes = plt.subplots(1, len(layers), figsize=(5.5 * len(layers), 4), layout="constrained",
                             squeeze=False, sharey=True)
    for ax, layer in zip(axes[0], layers, strict=True):
        plotting.plot_crack_length_band(risk, ax=ax, layer=layer, measured=measured)
        if layer is not None:
            ax.set_title(f"beams longer than s stay stuck (adsorbed layer: {layer})", fontsize="medium")
    files.append(_save(fig, out / "crack_length.png"))

    # a short table on the terminal
    for layer in layers:
        d = risk.sel(adsorbed_layer=layer) if layer is not None else risk
        print(f"adsorbed layer: {layer}" if layer is not None else "")
        for lev in levels:
            row = []
            for bl in np.atleast_1d(d.beam_length.values):
                c = d.crossing_humidity.sel(probability_level=lev, beam_length=bl)
                lo = d.crossing_humidity_lower.sel(probability_level=lev, beam_length=bl)
                hi = d.crossing_humidity_upper.sel(probability_level=lev, beam_length=bl)
                row.append(f"l={bl * 1e6:.0f}um: {_pct(c)} [{_pct(lo)}, {_pct(hi)}]")
            print(f"  RH where P(stuck) reaches {lev:g}: " + "; ".join(row))
    for f in files:
        print(f"wrote {f}")
    return 0


def _pct(v) -> str:

    v = float(v)
    if np.isnan(v):
        return "n/a"
    if v == -np.inf:
        return "<min RH"
    if v == np.inf:
        return ">max RH"
    return f"{v * 100:.1f}%"


def _save(fig, path):
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
