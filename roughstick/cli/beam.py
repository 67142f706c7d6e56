"""``roughstick beam CONFIG.toml``: cantilevers on random patch laws (beam-scale stochastic model).

Builds (or reads back from its on-disk cache) a bank of patch laws for the PSD and RH of the file,
runs the crack-front model of :mod:`roughstick.stiction.beam_model` on ``realizations`` beams per
length, and writes ``beam.nc`` (crack length, stuck flag, apparent Γ by Eq. 36, P(stuck) with its
Wilson interval over (realization, rh, beam_length)). Lengths carry their unit in the key
(``_um``, ``_nm``); humidities are in percent. See ``examples/beam.toml``.
"""

from __future__ import annotations

import pathlib
import time

import numpy as np

import roughstick as rs

from ._config import _toml_load

_SCHEMA = {
    "output": {"directory"},
    "beam": {"lengths_um", "width_um", "thickness_um", "gap_um", "youngs_modulus_GPa",
             "patch_length_um"},
    "surface": {"psd", "spacing_nm", "shape"},
    "humidity": {"rh_percent", "protocol"},
    "bank": {"laws", "seed", "cache_directory", "model"},
    "ensemble": {"realizations", "seed"},
}


def register(sub):
    p = sub.add_parser("beam", help="beam-scale stochastic stiction: crack length and P(stuck) "
                       "from random patch laws (paper §5); NetCDF", description=__doc__)
    p.add_argument("config", help="TOML configuration (see examples/beam.toml)")
    p.add_argument("--out", default=None, help="output folder (default [output] directory, else ./beam-output)")
    p.set_defaults(func=_run)


def _load(path: pathlib.Path) -> dict:
    if not path.is_file():
        raise FileNotFoundError(f"configuration file {str(path)!r} not found.")
    cfg = _toml_load(path)
    unknown = sorted(set(cfg) - set(_SCHEMA))
    if unknown:
        raise ValueError(f"{path}: unknown section(s) {unknown}; known: {sorted(_SCHEMA)}.")
    for sec, body in cfg.items():
        bad = sorted(set(body) - _SCHEMA[sec])
        if bad:
            raise ValueError(f"{path}: unknown key(s) {bad} in [{sec}]; known: {sorted(_SCHEMA[sec])}.")
    return cfg


def _psd(name: str):
    if name != "table4":
        raise ValueError(f"[surface] psd = {name!r}: only 'table4' (the paper's cantilever PSD, "
                         "Eq. 37) is available from the CLI; use the Python API for others.")
    c = rs.cantilever_psd()
    q = np.geomspace(1e5, 4e9, 400)
    return rs.self_affine_psd(q, s0=float(c.s0), s1=float(c.s1), q0=float(c.q0), qmax=float(c.qmax))


def _run(args) -> int:
    path = pathlib.Path(args.config)
    cfg = _load(path)
    b, s, h, bank_cfg, ens = (cfg.get(k, {}) for k in ("beam", "surface", "humidity", "bank", "ensemble"))
    beam = rs.Cantilever(width=b.get("width_um", 30.0) * 1e-6,
                         thickness=b.get("thickness_um", 2.62) * 1e-6,
                         gap=b.get("gap_um", 1.9) * 1e-6,
                         youngs_modulus=b.get("youngs_modulus_GPa", 164.0) * 1e9)
    lengths = np.asarray(b.get("lengths_um", [1500.0]), dtype=float) * 1e-6
    patch = b.get("patch_length_um")
    rh = np.asarray(h.get("rh_percent", [60.0]), dtype=float) / 100.0
    cache = bank_cfg.get("cache_directory", "beam-bank-cache")
    cache = pathlib.Path(cache) if pathlib.Path(cache).is_absolute() else path.parent / cache
    t0 = time.perf_counter()
    bank = rs.build_patch_bank(_psd(s.get("psd", "table4")), relative_humidity=rh,
                               n_law=int(bank_cfg.get("laws", 1000)),
                               shape=tuple(s.get("shape", [64, 64])),
                               spacing=s.get("spacing_nm", 20.0) * 1e-9,
                               seed=int(bank_cfg.get("seed", 0)),
                               model=bank_cfg.get("model", "modified_dmt"), cache_dir=cache)
    t1 = time.perf_counter()
    ds = rs.simulate_beams(bank, beam_length=lengths, n_realization=int(ens.get("realizations", 1000)),
                           seed=int(ens.get("seed", 0)), protocol=h.get("protocol", "release"),
                           beam=beam, patch_length=None if patch is None else patch * 1e-6)
    t2 = time.perf_counter()
    out = pathlib.Path(args.out or cfg.get("output", {}).get("directory", "beam-output"))
    out.mkdir(parents=True, exist_ok=True)
    ds.to_netcdf(out / "beam.nc")
    src = "read from cache" if bank.attrs.get("from_cache") else "computed"
    print(f"bank: {bank.sizes['law']} laws x {bank.sizes['rh']} RH {src} in {t1 - t0:.1f} s "
          f"({bank.attrs.get('cache_file')})")
    print(f"beams: {ds.sizes['realization']} x {len(lengths)} lengths x {len(rh)} RH in {t2 - t1:.2f} s")
    p = ds.stuck_probability
    for r in ds.rh.values:
        for length in ds.beam_length.values:
            sel = dict(rh=r, beam_length=length)
            print(f"RH {100 * r:5.1f} %  l {length * 1e6:7.1f} um  P(stuck) {float(p.sel(sel)):.3f} "
                  f"[{float(ds.stuck_probability_lower.sel(sel)):.3f}, "
                  f"{float(ds.stuck_probability_upper.sel(sel)):.3f}] (95 % Wilson, "
                  f"n = {ds.sizes['realization']})")
    print(f"wrote {out / 'beam.nc'}")
    return 0
