"""TOML configuration of an ensemble run (``roughstick run CONFIG.toml``).

A config has four tables; lengths may be numbers (SI) or strings with units (``"5 nm"``,
``"5.12 um"``, ``"15.7 nm2"``, ``"289 rad/um"``). Relative paths are relative to the config file.

.. code-block:: toml

    title = "S1, 5.12 um surfaces"

    [psd]
    source = "samples"        # "samples" (height maps), "moments" (Eq. 37 fit) or "file" (NetCDF PSD)
    files = ["../data_samples/S1A.nc", "../data_samples/S1B.nc", "../data_samples/S1C.nc"]
    submaps = 16              # sub-maps per map (paper scheme 3)
    qmax = "289 rad/um"       # optional cutoff (Table 3)
    # source = "moments": m0 = "15.7 nm2", m2 = 0.040, m4 = "5.08e-4 nm-2", qmax = "289 rad/um"
    # source = "file":    path = "psd.nc", variable = "psd"

    [surface]
    size = "5.12 um"          # or shape = [1024, 1024]
    spacing = "5 nm"

    [ensemble]
    n = 300                   # or "auto" (then batch, tolerance, n_max, patience)
    relative_humidity = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]
    seed = 0
    chunks = 4                # realizations per block (one NetCDF file each)
    adsorbed_layer = "paper"  # or "none"

    [output]
    folder = "ensemble-S1"
    figures = true

    [run]
    scheduler = "threads"     # or "tcp://host:8786"
    connect_timeout = 5
"""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np
import xarray as xr

import roughstick as rs

from .._core.units import parse_quantity

__all__ = ["RunConfig", "load_config", "parse_quantity"]

_KNOWN = {
    "title": None,
    "psd": {"source", "files", "submaps", "qmax", "m0", "m2", "m4", "path", "variable", "spacing", "num_q"},
    "surface": {"size", "shape", "spacing"},
    "ensemble": {"n", "relative_humidity", "seed", "chunks", "adsorbed_layer", "batch", "tolerance",
                 "n_max", "patience", "distance_points", "distance_lower"},
    "output": {"folder", "figures", "overwrite"},
    "run": {"scheduler", "connect_timeout", "progress"},
}


def _toml_load(path: pathlib.Path) -> dict:
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        try:
            import tomli as tomllib
        except ModuleNotFoundError as exc:
            raise ValueError(
                "reading TOML configs on Python 3.10 needs the 'tomli' package: pip install tomli "
                "(Python >= 3.11 has tomllib built in)."
            ) from exc
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{str(path)!r} is not valid TOML: {exc}") from exc


@dataclasses.dataclass
class RunConfig:
    """A parsed run configuration (SI values, absolute paths)."""

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

    def build_psd(self):
        """The PSD DataArray [m4] described by the ``[psd]`` table."""


        p = self.psd
        src = p["source"]
        if src == "samples":
            maps = [rs.level(rs.read_afm(f), method="plane") for f in p["files"]]
            shapes = {m.shape for m in maps}
            if len(shapes) != 1:
                raise ValueError(f"the sample maps differ in shape {sorted(shapes)}; give maps of one size.")
            h = xr.concat(maps, dim="map", coords="minimal", compat="override", join="override",
                          combine_attrs="drop_conflicts")
            psd = rs.submap_psd(h, n=int(p.get("submaps", 16)))
        elif src == "moments":
            fit = rs.fit_self_affine(m0=p["m0"], m2=p["m2"], m4=p["m4"], qmax=p["qmax"])
            qn = np.pi / self.spacing
            q = np.linspace(0, max(qn * np.sqrt(2), p["qmax"]) * 1.0001, int(p.get("num_q", 4096)))
            psd = rs.self_affine_psd(q, s0=float(fit["s0"]), s1=float(fit["s1"]), q0=float(fit["q0"]),
                                     qmax=float(fit["qmax"]))
        elif src == "file":
            with xr.open_dataset(p["path"], engine="netcdf4") as ds:
                var = p.get("variable", "psd")
                if var not in ds:
                    raise ValueError(f"{p['path']!r} has no variable {var!r}; set psd.variable.")
                psd = ds[var].load()
        else:  # checked in load_config
            raise ValueError(src)
        if "qmax" in p and src != "moments":
            qmax = p["qmax"]
            if "qx" in psd.dims:
                qq = np.hypot(psd["qx"], psd["qy"])
            else:
                qq = psd["q"]
            psd = psd.where(qq <= qmax, 0.0).assign_attrs(psd.attrs)
            psd.attrs["qmax_cutoff"] = qmax
        return psd


def _check_keys(raw: dict, path) -> None:
    for k, v in raw.items():
        if k not in _KNOWN:
            raise ValueError(f"{path}: unknown table or key {k!r}; known: {sorted(_KNOWN)}.")
        if isinstance(_KNOWN[k], set):
            if not isinstance(v, dict):
                raise ValueError(f"{path}: [{k}] must be a table.")
            bad = set(v) - _KNOWN[k]
            if bad:
                raise ValueError(f"{path}: unknown key(s) {sorted(bad)} in [{k}]; known: {sorted(_KNOWN[k])}.")


def load_config(path, *, overrides: dict | None = None) -> RunConfig:
    """Read and validate a TOML run configuration (see the module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.toml`` file.
    overrides : dict, optional
        ``{"n": ..., "scheduler": ..., "folder": ..., "overwrite": ...}`` from the command line.

    Raises
    ------
    FileNotFoundError
        Missing config or sample files.
    ValueError
        Unknown keys, bad values (empty humidity list, n = 0 ...), naming the key and the fix.
    """
    path = pathlib.Path(path).resolve()
    if not path.exists():
        raise FileNotFoundError(f"config file {str(path)!r} not found.")
    raw = _toml_load(path)
    _check_keys(raw, path.name)
    base = path.parent
    o = overrides or {}

    psd = dict(raw.get("psd", {}))
    src = psd.get("source")
    if src not in ("samples", "moments", "file"):
        raise ValueError(f"{path.name}: [psd] source must be 'samples', 'moments' or 'file', got {src!r}.")
    if src == "samples":
        files = psd.get("files")
        if not files:
            raise ValueError(f"{path.name}: [psd] files = [...] (height maps) is required for source='samples'.")
        psd["files"] = [str((base / f).resolve()) for f in files]
        for f in psd["files"]:
            if not pathlib.Path(f).exists():
                raise FileNotFoundError(f"{path.name}: sample map {f!r} not found.")
    elif src == "moments":
        for k in ("m0", "m2", "m4", "qmax"):
            if k not in psd:
                raise ValueError(f"{path.name}: [psd] needs {k} for source='moments'.")
        psd["m0"] = parse_quantity(psd["m0"], "length", name="m0", power=2)
        psd["m2"] = float(psd["m2"])
        psd["m4"] = parse_quantity(psd["m4"], "length", name="m4", power=-2)
    else:
        if "path" not in psd:
            raise ValueError(f"{path.name}: [psd] path = 'file.nc' is required for source='file'.")
        psd["path"] = str((base / psd["path"]).resolve())
        if not pathlib.Path(psd["path"]).exists():
            raise FileNotFoundError(f"{path.name}: PSD file {psd['path']!r} not found.")
    if "qmax" in psd:
        psd["qmax"] = parse_quantity(psd["qmax"], "wavevector", name="qmax")

    surf = raw.get("surface", {})
    if "spacing" not in surf:
        raise ValueError(f"{path.name}: [surface] spacing is required (e.g. spacing = '5 nm').")
    spacing = parse_quantity(surf["spacing"], "length", name="spacing")
    shape = size = None
    if ("shape" in surf) == ("size" in surf):
        raise ValueError(f"{path.name}: [surface] needs exactly one of shape = [ny, nx] or size = '5.12 um'.")
    if "shape" in surf:
        s = surf["shape"]
        shape = (int(s), int(s)) if isinstance(s, int) else tuple(int(v) for v in s)
    else:
        s = surf["size"]
        size = tuple(parse_quantity(v, "length", name="size") for v in (s if isinstance(s, list) else [s, s]))

    ens = raw.get("ensemble", {})
    n = o.get("n") or ens.get("n")
    if n is None:
        raise ValueError(f"{path.name}: [ensemble] n is required (an integer >= 1 or 'auto').")
    if n != "auto":
        if isinstance(n, str) and n.isdigit():
            n = int(n)
        if not isinstance(n, int) or isinstance(n, bool) or n < 1:
            raise ValueError(f"{path.name}: [ensemble] n must be an integer >= 1 or 'auto', got {n!r}.")
    rh = ens.get("relative_humidity")
    if not rh:
        raise ValueError(
            f"{path.name}: [ensemble] relative_humidity is empty or missing; give fractions, "
            "e.g. relative_humidity = [0.3, 0.5, 0.7, 0.9]."
        )
    rh = [float(v) for v in rh]
    if any(not 0 < v < 1 for v in rh):
        raise ValueError(f"{path.name}: relative_humidity values must be fractions in (0, 1), got {rh}.")
    out = raw.get("output", {})
    folder = o.get("folder") or out.get("folder")
    if not folder:
        raise ValueError(f"{path.name}: [output] folder is required.")
    run = raw.get("run", {})
    return RunConfig(
        path=path,
        title=str(raw.get("title", path.stem)),
        psd=psd,
        shape=shape,
        size=size,
        spacing=spacing,
        n=n,
        relative_humidity=rh,
        seed=int(ens.get("seed", 0)),
        chunks=int(ens["chunks"]) if "chunks" in ens else None,
        adsorbed_layer=str(ens.get("adsorbed_layer", "paper")),
        auto={k: ens[k] for k in ("batch", "tolerance", "n_max", "patience") if k in ens},
        distance_points=int(ens.get("distance_points", 200)),
        distance_lower=float(ens.get("distance_lower", 1.5)),
        folder=(base / folder).resolve() if not pathlib.Path(folder).is_absolute() else pathlib.Path(folder),
        figures=bool(out.get("figures", True)),
        overwrite=bool(o.get("overwrite") or out.get("overwrite", False)),
        scheduler=o.get("scheduler") or run.get("scheduler"),
        connect_timeout=float(run.get("connect_timeout", 5.0)),
        progress=run.get("progress"),
    )
