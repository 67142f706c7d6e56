"""``roughstick beam CONFIG.toml``: cantilevers on random patch laws (beam-scale stochastic model).

Builds (or reads back from its on-disk cache) a bank of patch laws for the PSD and RH of the file,
runs the crack-front model of :mod:`roughstick.stiction.beam_model` on ``n`` beams per length and
RH, and writes ``beam.nc`` (crack length, stuck flag, apparent Γ by Eq. 36, P(stuck) with its
Wilson interval over (realization, rh, beam_length)). The file follows the one configuration
schema of every command (docs/configuration.md); see ``examples/beam.toml``.
"""

from __future__ import annotations

import pathlib
import time

import numpy as np

import roughstick as rs

from ..io.netcdf import write as write_netcdf
from ._common import LOG, claim_folder, finish_folder
from ._config import check_memory, parse, read_toml

__all__ = ["register"]


def register(sub):
    p = sub.add_parser("beam", help="beam-scale stochastic stiction: crack length and P(stuck) "
                       "from random patch laws (paper §5); NetCDF", description=__doc__)
    p.add_argument("config", help="TOML configuration (see examples/beam.toml)")
    p.add_argument("--out", default=None,
                   help="output folder (default: [output] folder, else ./beam-output)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace results of another run in the output folder")
    p.set_defaults(func=_run)


def _psd(surface: dict):
    if surface.get("psd") is not None:
        return rs.open_dataset(surface["psd"])["psd"]
    c = rs.cantilever_psd()
    q = np.geomspace(1e5, 4e9, 400)
    return rs.self_affine_psd(q, s0=float(c.s0), s1=float(c.s1), q0=float(c.q0), qmax=float(c.qmax))


def _beside(config: pathlib.Path, folder) -> pathlib.Path:
    """A relative folder of the config (defaults included) is taken beside the config file."""
    folder = pathlib.Path(folder)
    return folder if folder.is_absolute() else config.parent / folder


def _run(args) -> int:
    path = pathlib.Path(args.config)
    c = parse(read_toml(path), "beam", base=path.parent, source=path.name)
    b, s, ens, bank_cfg, o = (c[k] for k in ("beam", "surface", "ensemble", "bank", "output"))
    shape = s["shape"]
    shape = (shape, shape) if np.ndim(shape) == 0 else tuple(shape)
    check_memory(shape, where=f"{path.name} [surface] shape")
    beam = rs.Cantilever(width=b["width"], thickness=b["thickness"], gap=b["gap"],
                         youngs_modulus=b["youngs_modulus"])
    rh = np.asarray(ens["relative_humidity"], dtype=float)
    out = pathlib.Path(args.out) if args.out else _beside(path, o.get("folder") or "beam-output")
    claim_folder(out, command="beam", params={"config": path.read_text()},
                 overwrite=args.overwrite or o["overwrite"])
    t0 = time.perf_counter()
    bank = rs.build_patch_bank(_psd(s), relative_humidity=rh, n_law=bank_cfg["laws"], shape=shape,
                               spacing=s["spacing"], seed=bank_cfg["seed"], model=bank_cfg["model"],
                               cache_dir=_beside(path, bank_cfg["cache"]))
    t1 = time.perf_counter()
    ds = rs.simulate_beams(bank, beam_length=np.asarray(b["lengths"], dtype=float), n_realization=ens["n"],
                           seed=ens["seed"], protocol=ens["protocol"], beam=beam,
                           patch_length=b.get("patch_length"), model=ens["beam_model"])
    t2 = time.perf_counter()
    write_netcdf(ds, out / "beam.nc", compute=True)
    finish_folder(out)
    src = "read from cache" if bank.attrs.get("from_cache") else "computed"
    LOG.info(f"bank: {bank.sizes['law']} laws x {bank.sizes['rh']} RH {src} in {t1 - t0:.1f} s "
             f"({bank.attrs.get('cache_file')})")
    LOG.info(f"beams: {ds.sizes['realization']} x {ds.sizes['beam_length']} lengths x {len(rh)} RH "
             f"in {t2 - t1:.2f} s")
    for r in ds.rh.values:
        for length in ds.beam_length.values:
            sel = dict(rh=r, beam_length=length)
            LOG.info(f"RH {r:.2f}  l {length * 1e6:7.1f} um  P(stuck) "
                     f"{float(ds.stuck_probability.sel(sel)):.3f} "
                     f"[{float(ds.stuck_probability_lower.sel(sel)):.3f}, "
                     f"{float(ds.stuck_probability_upper.sel(sel)):.3f}] "
                     f"(95 % Wilson interval, n = {ds.sizes['realization']})")
    LOG.info(f"wrote {out / 'beam.nc'}")
    return 0
