"""THE configuration schema of every ``roughstick`` command that reads a TOML file.

One dialect for ``roughstick run``, ``roughstick risk`` and ``roughstick beam`` (docs/configuration.md):

* a dimensional quantity is a string with its unit, ``spacing = "5 nm"``, ``qmax = "289 rad/um"``,
  ``youngs_modulus = "164 GPa"``; a bare number is refused with the fix (``spacing = 5`` would
  otherwise be 5 m), and so is a unit in the key name (``spacing_nm``);
* relative humidity is a fraction, ``relative_humidity = [0.3, 0.5]`` (or ``"30 %"``); a value
  outside (0, 1) is refused with the advice of :func:`roughstick._core.validate.fraction_advice`
  (30: "did you mean 0.3"; 1: saturation; "120 %": not a humidity; a ratio such as ``target_cv``
  is never taken for a percentage);
* integers are integers (``seed = 1.9``, ``shape = [64.7, 64]`` and ``n = 0`` are refused),
  booleans are TOML booleans (``figures = "no"`` is refused);
* unknown tables and keys are refused, with the closest known key;
* every value is checked when the file is read, before any work starts; all problems of a file
  are reported together.

The tables a command accepts are in :data:`SCHEMAS`; :func:`parse` turns a raw TOML dict into SI
values (absolute paths) or raises :class:`ConfigError`.
"""

from __future__ import annotations

import dataclasses
import difflib
import pathlib
import re

import numpy as np
import xarray as xr

import roughstick as rs

from .._core.materials import POLYSILICON, Material, material_from
from .._core.memory import physical_memory
from .._core.units import KINDS, UnitsError, parse_quantity
from .._core.validate import as_fraction
from ..io.afm import bundled_map_names, resolve_map_path
from ._schema import SCHEMAS, Field
from ._types import read_map

__all__ = ["ConfigError", "Field", "SCHEMAS", "parse", "read_toml", "RunConfig", "load_config",
           "parse_quantity", "config_material"]


class ConfigError(ValueError):
    """A configuration file (or a command-line override) holds a value roughstick refuses."""


#: A typical unit to suggest for each kind of quantity, in the message that refuses a bare number.
_EXAMPLE_UNIT = {"length": "nm", "area": "nm2", "length4": "nm4", "inverse_area": "um-2",
                 "pressure": "GPa", "energy_per_area": "mJ m-2", "wavevector": "rad/um",
                 "force": "uN", "temperature": "K", "angle": "deg"}


#: Keys of the old dialects (units in key names, RH in percent) and what replaces them.
_RENAMED = {
    "rh_percent": "relative_humidity = [0.3, 0.5] (fractions; or \"30 %\")",
    "directory": "folder",
    "realizations": "n",
    "lengths_um": 'lengths = ["250 um", "300 um"]',
    "adhesive_energy_mJ_per_m2": 'adhesive_energy = ["0.5 mJ m-2"]',
    "asperity_density_per_um2": 'asperity_density = "80.1 um-2"',
    "qmax_rad_per_um": 'qmax = "289 rad/um"',
    "youngs_modulus_GPa": 'youngs_modulus = "164 GPa"',
    "samples_per_level": "n_per_level = 1000 (samples per level of subset simulation)",
}
_UNIT_SUFFIX = re.compile(r"^(?P<key>.+?)_(?P<unit>nm|um|mm|m|GPa|MPa|Pa|percent|pct|nm2|nm4)$")


def read_toml(path) -> dict:
    """Read a TOML file, refusing what is not one (a folder, a missing file, broken TOML)."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        try:
            import tomli as tomllib
        except ModuleNotFoundError as exc:
            raise ConfigError("reading TOML configs on Python 3.10 needs the 'tomli' package: "
                              "pip install tomli (Python >= 3.11 has tomllib built in).") from exc

    path = pathlib.Path(path)
    if path.is_dir():
        raise ConfigError(f"{str(path)!r} is a folder; give the configuration file (e.g. examples/risk.toml; "
                          "`roughstick examples --out examples` writes the shipped examples).")
    if not path.is_file():
        raise FileNotFoundError(f"configuration file {str(path)!r} not found (`roughstick examples --out "
                                "examples` writes the example configurations shipped with roughstick).")
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path.name} is not valid TOML: {exc}") from exc
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{path.name} is not a text (TOML) file: {exc}") from exc


def _unknown(key: str, known, where: str) -> str:
    hint = ""
    new = [k for k, f in known.items() if key in getattr(f, "replaces", ())]
    if new:
        hint = (f" It is now {new[0]!r}: write {new[0]} = ... instead (the same value; the key "
                "has one name in every command).")
    elif key in _RENAMED:
        hint = f" Write {_RENAMED[key]} instead."
    elif m := _UNIT_SUFFIX.match(key):
        stem = m["key"] if m["key"] in known else (difflib.get_close_matches(m["key"], list(known), n=1)
                                                   or [m["key"]])[0]
        hint = f" Units go in the value, not the key: {stem} = \"<number> {m['unit']}\"."
    else:
        close = difflib.get_close_matches(key, list(known), n=1)
        if close:
            hint = f" Did you mean {close[0]!r}?"
    return f"{where}: unknown key {key!r}.{hint} Known: {sorted(known)}."


def _one(value, f: Field, name: str, base: pathlib.Path):
    """Validate one scalar value of field ``f``; return it in SI (or raise ConfigError)."""
    k = f.kind
    if k in KINDS:
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            raise ConfigError(f"{name} = {value!r}: expected a string with a unit, e.g. "
                              f"{name.rsplit('.', 1)[-1]} = \"5 {_EXAMPLE_UNIT.get(k, KINDS[k])}\".")
        if isinstance(value, (int, float)):
            u = _EXAMPLE_UNIT.get(k, KINDS[k])
            raise ConfigError(
                f"{name} = {value!r} has no unit (a bare number would be read as {KINDS[k]}); "
                f"write it with its unit, e.g. {name.rsplit('.', 1)[-1]} = \"{value:g} {u}\".")
        m = re.match(r"^\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s*$", value)
        if m:
            u = _EXAMPLE_UNIT.get(k, KINDS[k])
            raise ConfigError(f"{name} = {value!r} has no unit; write e.g. \"{value.strip()} {u}\".")
        try:
            if k in ("area", "length4", "inverse_area"):
                power = {"area": 2, "length4": 4, "inverse_area": -2}[k]
                v = parse_quantity(value, "length", name=name, power=power)
            else:
                v = parse_quantity(value, k, name=name)
        except (UnitsError, ValueError) as exc:
            raise ConfigError(str(exc)) from None
        if not np.isfinite(v) or v <= 0:
            raise ConfigError(f"{name} = {value!r}: must be positive and finite.")
        return v
    if k in ("int", "n"):
        if k == "n" and value == "auto":
            return "auto"
        if isinstance(value, bool) or not isinstance(value, int):
            also = " or 'auto'" if k == "n" else ""
            raise ConfigError(f"{name} = {value!r}: expected an integer{also}"
                              + (f" (write {int(value)} or {int(value) + 1} if you meant a whole number)"
                                 if isinstance(value, float) and np.isfinite(value) else "") + ".")
        lo = 1 if k == "n" else f.minimum
        if lo is not None and value < lo:
            also = " or 'auto'" if k == "n" else ""
            raise ConfigError(f"{name} = {value!r}: must be an integer >= {lo:g}{also}.")
        return int(value)
    if k == "shape":
        v = value if isinstance(value, list) else [value, value]
        if len(v) != 2 or any(isinstance(e, bool) or not isinstance(e, int) or e < 8 for e in v):
            raise ConfigError(f"{name} = {value!r}: expected an integer >= 8 or [ny, nx] of integers >= 8, "
                              "e.g. shape = [256, 256].")
        return (int(v[0]), int(v[1]))
    if k == "number":
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
            raise ConfigError(f"{name} = {value!r}: expected a finite number.")
        if f.minimum is not None and value < f.minimum:
            raise ConfigError(f"{name} = {value!r}: must be >= {f.minimum:g}.")
        return float(value)
    if k in ("fraction", "relative_humidity"):
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise ConfigError(f"{name} = {value!r}: expected a fraction like 0.3 (or the string '30 %').")
        quantity = k if k == "relative_humidity" else ("fraction" if f.percent else "ratio")
        label = "RH" if k == "relative_humidity" else name.rsplit(".", 1)[-1].split("[")[0]
        try:
            return as_fraction(value, name=name, quantity=quantity, label=label)
        except ValueError as exc:
            raise ConfigError(str(exc)) from None
    if k == "bool":
        if not isinstance(value, bool):
            raise ConfigError(f"{name} = {value!r}: expected true or false (TOML booleans, no quotes).")
        return value
    if k == "str":
        if not isinstance(value, str) or not value:
            raise ConfigError(f"{name} = {value!r}: expected a non-empty string.")
        return value
    if k == "choice":
        if value not in f.choices:
            raise ConfigError(f"{name} = {value!r}: must be one of {list(f.choices)}.")
        return value
    if k == "map":
        if not isinstance(value, str) or not value:
            raise ConfigError(f"{name} = {value!r}: expected a path or a bundled map name (a string), "
                              "e.g. \"bundled:S1A\".")
        try:
            return resolve_map_path(value, base=base)  # a real file of that name wins
        except ValueError:
            raise ConfigError(f"{name} = {value!r}: no such bundled map; the bundled maps are "
                              f"{bundled_map_names()} (or give a file path).") from None
    if k == "path":
        if not isinstance(value, str) or not value:
            raise ConfigError(f"{name} = {value!r}: expected a path (a string).")
        p = pathlib.Path(value).expanduser()
        return p if p.is_absolute() else (base / p).resolve()
    raise AssertionError(f"unknown field kind {k!r}")  # a bug in SCHEMAS, not a user error


def _value(value, f: Field, name: str, base: pathlib.Path):
    if f.many:
        items = value if isinstance(value, list) else [value]
        if not items:
            raise ConfigError(f"{name} is empty; give at least one value, e.g. {_example(f)}.")
        out = []
        for i, v in enumerate(items):
            out.append(_one(v, f, f"{name}[{i}]" if isinstance(value, list) else name, base))
        if f.kind == "relative_humidity" and len(set(out)) != len(out):
            raise ConfigError(f"{name} = {value!r}: repeated humidities; give each once.")
        return out
    if isinstance(value, list) and f.kind != "shape":
        raise ConfigError(f"{name} = {value!r}: expected one value, not a list.")
    return _one(value, f, name, base)


def _example(f: Field) -> str:
    if f.kind == "relative_humidity":
        return "[0.3, 0.5, 0.7, 0.9]"
    if f.kind in _EXAMPLE_UNIT:
        return f'["5 {_EXAMPLE_UNIT[f.kind]}"]'
    return "[...]"


def parse(raw: dict, command: str, *, base, source: str = "config", schema=None) -> dict:
    """Validate a raw TOML dict against ``SCHEMAS[command]``; return ``{table: {key: SI value}}``.

    Defaults are filled in; tables listed as arrays (``[[measured]]``) become lists of dicts.
    Every problem of the file is collected and raised together as one :class:`ConfigError`.
    """
    schema = SCHEMAS[command] if schema is None else schema
    base = pathlib.Path(base)
    errors: list[str] = []
    out: dict = {}
    top = schema.get("", {})
    for key in raw:
        if key in schema and key != "":
            continue
        if key in top:
            continue
        tables = sorted(t for t in schema if t)
        close = difflib.get_close_matches(key, tables + list(top), n=1)
        hint = f" Did you mean [{close[0]}]?" if close else ""
        if key in ("humidity",):
            hint = " Humidities go in [ensemble] relative_humidity = [0.3, 0.5] (fractions)."
        errors.append(f"{source}: unknown table or key {key!r}.{hint} Known tables: {tables}.")
    for table, fields in schema.items():
        if table == "":
            body = {k: v for k, v in raw.items() if k in fields}
            bodies = [body]
        else:
            body = raw.get(table, {})
            array = table == "measured"
            if array:
                bodies = body if isinstance(body, list) else [body]
            else:
                bodies = [body]
        parsed = []
        for b in bodies:
            if not isinstance(b, dict):
                errors.append(f"{source}: [{table}] must be a table.")
                continue
            where = f"{source} [{table}]" if table else source
            res = {}
            for key, value in b.items():
                if key not in fields:
                    errors.append(_unknown(key, fields, where))
                    continue
                try:
                    res[key] = _value(value, fields[key], f"{table}.{key}" if table else key, base)
                except ConfigError as exc:
                    errors.append(f"{source}: {exc}")
            for key, f in fields.items():
                if key in res or key in b:  # present (possibly refused above)
                    continue
                if f.required and not (table == "measured"):
                    errors.append(f"{source}: [{table}] {key} is required ({f.doc}).")
                elif f.default is not None:
                    res[key] = list(f.default) if isinstance(f.default, list) else f.default
            parsed.append(res)
        if table == "":
            out.update(parsed[0] if parsed else {})
        elif table == "measured":
            out[table] = parsed if raw.get(table) else []
        else:
            out[table] = parsed[0] if parsed else {}
    if errors:
        raise ConfigError("\n  ".join([f"{len(errors)} problem(s) in the configuration:"] + errors)
                          if len(errors) > 1 else errors[0])
    return out


#: Bytes held per pixel of one surface while it is generated and its curves computed (float64
#: heights, complex spectra, labels, work arrays): a deliberately generous bound.
BYTES_PER_PIXEL = 32 * 8


def check_memory(shape, *, chunks: int = 1, where: str = "config") -> None:
    """Refuse, before allocating anything, surfaces whose blocks cannot fit in this machine's
    memory, naming the size and the fix."""
    ny, nx = shape
    need = ny * nx * BYTES_PER_PIXEL * max(1, int(chunks))
    have = physical_memory()
    if have is not None and need > have:
        raise ConfigError(
            f"{where}: surfaces of {ny} x {nx} px in blocks of {chunks} need about {need / 2**30:.0f} GiB, "
            f"more than this machine's {have / 2**30:.0f} GiB of memory; use a smaller size or shape "
            "(or fewer realizations per block: chunks), or run on a larger machine with --scheduler.")


def config_material(table: dict, source: str = "config") -> Material:
    """The parsed [material] table as a :class:`~roughstick.Material` (poly-silicon when empty),
    or a :class:`ConfigError` naming the table and the keys to give."""
    try:
        return material_from(table.get("name"), youngs_modulus=table.get("youngs_modulus"),
                             poisson_ratio=table.get("poisson_ratio"))
    except ValueError as exc:
        raise ConfigError(f"{source}: [material] {exc}") from None


# ----------------------------------------------------------------------------- roughstick run


@dataclasses.dataclass
class RunConfig:
    """A parsed ``roughstick run`` configuration (SI values, absolute paths)."""

    path: pathlib.Path
    title: str
    psd: dict
    shape: tuple[int, int] | None
    size: tuple[float, float] | None
    spacing: float
    n: int | str
    relative_humidity: list[float]
    seed: int
    chunks: int | None
    adsorbed_layer: str
    auto: dict
    distance_points: int
    distance_lower: float
    folder: pathlib.Path
    figures: bool
    overwrite: bool
    scheduler: str | None
    connect_timeout: float
    progress: bool | None
    model: str = "auto"
    material: Material = POLYSILICON
    height_distribution: dict = dataclasses.field(default_factory=lambda: dict(HEIGHTS_DEFAULT))

    def sample_maps(self) -> list:
        """The ``[psd] files`` maps as :func:`roughstick.io.read_afm` levels them (``[psd] level``,
        default its least-squares plane unless periodic; ``source = "samples"``; else [])."""
        if self.psd["source"] != "samples":
            return []
        return [read_map(f, levelling=self.psd.get("level", "auto")) for f in self.psd["files"]]

    def heights(self):
        """The ``height_distribution=`` of :func:`roughstick.ensemble.run` that ``[surface]``
        asks for: "auto", "maps", "gaussian" or a Johnson distribution."""
        h = self.height_distribution
        if h["height_distribution"] == "johnson":
            return rs.surface.height_distribution(skewness=h["skewness"], kurtosis=h["kurtosis"])
        return h["height_distribution"]

    def build_psd(self, maps=None):
        """The PSD DataArray [m4] described by the ``[psd]`` table (``maps``: the levelled
        sample maps, if read already)."""
        p = self.psd
        src = p["source"]
        if src == "samples":
            maps = self.sample_maps() if maps is None else maps
            shapes = {m.shape for m in maps}
            if len(shapes) != 1:
                raise ValueError(f"the sample maps differ in shape {sorted(shapes)}; give maps of one size.")
            h = xr.concat(maps, dim="map", coords="minimal", compat="override", join="override",
                          combine_attrs="drop_conflicts")
            psd = rs.surface.submap_psd(h, n=int(p.get("submaps", 16)), window=p.get("window", "auto"))
        elif src == "moments":
            fit = rs.surface.fit_self_affine(m0=p["m0"], m2=p["m2"], m4=p["m4"], qmax=p["qmax"])
            qn = np.pi / self.spacing
            q = np.linspace(0, max(qn * np.sqrt(2), p["qmax"]) * 1.0001, int(p.get("num_q", 4096)))
            psd = rs.surface.self_affine_psd(q, s0=float(fit["s0"]), s1=float(fit["s1"]), q0=float(fit["q0"]),
                                     qmax=float(fit["qmax"]))
        else:
            with rs.io.open_dataset(p["path"]) as ds:
                var = p.get("variable", "psd")
                if var not in ds:
                    raise ValueError(f"{p['path']!r} has no variable {var!r} (it has "
                                     f"{sorted(ds.data_vars)}); set [psd] variable.")
                psd = ds[var].load()
        if "qmax" in p and src != "moments":
            qmax = p["qmax"]
            qq = np.hypot(psd["qx"], psd["qy"]) if "qx" in psd.dims else psd["q"]
            psd = psd.where(qq <= qmax, 0.0).assign_attrs(psd.attrs)
            psd.attrs["qmax_cutoff"] = qmax
        return psd


def _override(cfg: dict, table: str, key: str, value, command: str, flag: str, base) -> None:
    f = SCHEMAS[command][table][key]
    try:
        cfg[table][key] = _value(value, f, flag, base)
    except ConfigError as exc:
        raise ConfigError(f"{exc} (command-line option {flag})") from None


def load_config(path, *, overrides: dict | None = None) -> RunConfig:
    """Read and validate a ``roughstick run`` TOML configuration (see the module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.toml`` file.
    overrides : dict, optional
        ``{"n": ..., "scheduler": ..., "folder": ..., "overwrite": ...}`` from the command line,
        validated like the file's values (``--n 0`` is refused, not ignored).

    Raises
    ------
    FileNotFoundError
        Missing config or input files.
    ConfigError
        Unknown keys, bad values, naming the key and the fix.
    """
    path = pathlib.Path(path).resolve()
    raw = read_toml(path)
    base = path.parent
    c = parse(raw, "run", base=base, source=path.name)
    o = {k: v for k, v in (overrides or {}).items() if v is not None}
    cwd = pathlib.Path.cwd()
    if "n" in o:
        n = o["n"]
        if isinstance(n, str) and n != "auto":
            try:
                n = int(n)
            except ValueError:
                raise ConfigError(f"--n {o['n']!r}: expected an integer >= 1 or 'auto'.") from None
        _override(c, "ensemble", "n", n, "run", "--n", cwd)
    if "folder" in o:
        _override(c, "output", "folder", str(o["folder"]), "run", "--out", cwd)
    if o.get("overwrite"):
        c["output"]["overwrite"] = True
    if "scheduler" in o:
        c["run"]["scheduler"] = o["scheduler"]

    psd, surf, ens = c["psd"], c["surface"], c["ensemble"]
    problems = []
    need = {"samples": ("files",), "moments": ("m0", "m2", "m4", "qmax"), "file": ("path",)}
    for k in need[psd["source"]]:
        if k not in psd:
            problems.append(f"[psd] {k} is required for source = {psd['source']!r}")
    for f in list(psd.get("files", [])) + ([psd["path"]] if "path" in psd else []):
        if not pathlib.Path(f).is_file():
            problems.append(f"[psd] input file {str(f)!r} not found (the sample maps shipped with "
                            f"roughstick are named {bundled_map_names()})")
    if ("shape" in surf) == ("size" in surf):
        problems.append("[surface] needs exactly one of shape = [ny, nx] or size = \"5.12 um\"")
    if "folder" not in c["output"]:
        problems.append("[output] folder is required (or pass --out)")
    if ens["n"] == "auto":
        if "tolerance" not in ens:
            ens["tolerance"] = 0.02
    else:
        stray = [k for k in ("batch", "tolerance", "n_max", "patience") if k in ens]
        if stray:
            problems.append(f"[ensemble] {stray} only apply with n = 'auto' (n = {ens['n']}); remove them")
    if ens["n"] == "auto" and "n_max" in ens and "batch" in ens and ens["batch"] > ens["n_max"]:
        problems.append(f"[ensemble] batch = {ens['batch']} exceeds n_max = {ens['n_max']}")
    problems += _height_problems(surf, psd["source"])
    if problems:
        raise ConfigError(f"{path.name}: " + "; ".join(problems) + ".")
    size = surf.get("size")
    if size is not None:
        if len(size) == 1:
            size = size * 2
        if len(size) != 2:
            raise ConfigError(f"{path.name}: [surface] size takes one length or [y, x].")
    shape = surf.get("shape")
    if shape is None:
        shape = tuple(int(round(sz / surf["spacing"])) for sz in size)
    check_memory(shape, chunks=ens.get("chunks") or 1, where=f"{path.name}: [surface]")
    psd_table = {k: (str(v) if isinstance(v, pathlib.Path) else v) for k, v in psd.items()}
    if "files" in psd_table:
        psd_table["files"] = [str(f) for f in psd["files"]]
    return RunConfig(
        path=path,
        title=str(c.get("title", path.stem)),
        psd=psd_table,
        shape=surf.get("shape"),  # None when given by size
        size=tuple(size) if size is not None else None,
        spacing=surf["spacing"],
        n=ens["n"],
        relative_humidity=ens["relative_humidity"],
        seed=ens["seed"],
        chunks=ens.get("chunks"),
        adsorbed_layer=ens["adsorbed_layer"],
        auto={k: ens[k] for k in ("batch", "tolerance", "n_max", "patience") if k in ens},
        distance_points=ens["distance_points"],
        distance_lower=ens["distance_lower"],
        folder=pathlib.Path(c["output"]["folder"]),
        figures=c["output"]["figures"],
        overwrite=c["output"]["overwrite"],
        scheduler=c["run"].get("scheduler"),
        connect_timeout=c["run"]["connect_timeout"],
        progress=c["run"].get("progress"),
        model=ens["model"],
        material=config_material(c["material"], path.name),
        height_distribution={k: surf.get(k) for k in HEIGHTS_DEFAULT},
    )


#: The [surface] keys of the height distribution, as a run that does not set them has them.
HEIGHTS_DEFAULT = {"height_distribution": "auto", "skewness": None, "kurtosis": None,
                   "distribution_method": "translation"}


def _height_problems(surf: dict, source: str) -> list[str]:
    """What is wrong with the height-distribution keys of [surface] (empty: nothing)."""
    problems = johnson_problems(surf)
    if not problems and surf["height_distribution"] == "maps" and source != "samples":
        return ['[surface] height_distribution = "maps" needs the maps: [psd] source = "samples"']
    return problems


def johnson_problems(surf: dict) -> list[str]:
    """What is wrong with [surface] skewness and kurtosis of ``height_distribution = "johnson"``
    (``run`` and ``risk``; empty: nothing)."""
    kind = surf["height_distribution"]
    moments = [k for k in ("skewness", "kurtosis") if k in surf]
    if kind == "johnson" and len(moments) < 2:
        return ['[surface] height_distribution = "johnson" needs skewness and kurtosis (e.g. '
                "skewness = 0.4, kurtosis = 3.8)"]
    if kind != "johnson" and moments:
        return [f'[surface] {moments} only apply with height_distribution = "johnson"']
    if kind == "johnson" and not surf["kurtosis"] > 1 + surf["skewness"] ** 2:
        return [f"[surface] no distribution has skewness {surf['skewness']:g} and kurtosis "
                f"{surf['kurtosis']:g} (kurtosis must exceed 1 + skewness**2; 3 for a Gaussian)"]
    return []
