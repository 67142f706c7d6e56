"""``roughstick run CONFIG.toml``: a Monte Carlo ensemble from a TOML config (see roughstick._config).

Writes, into the config's output folder: ``ensemble/`` (one CF NetCDF file per block plus
``manifest.json``; an interrupted run resumes from it), ``band.nc`` (mean, 95 % band and its
uncertainty), and unless ``figures = false`` ``curves.png``, ``energy_band.png``,
``energy_ecdf.png``.
"""

from __future__ import annotations

import pathlib
import time

import roughstick as rs

from ..plotting.ensemble import (
    plot_energy_band,
    plot_energy_distribution,
    plot_ensemble_curves,
)
from ._config import load_config


def register(sub):
    p = sub.add_parser(
        "run",
        help="run a Monte Carlo ensemble from a TOML config; write NetCDF and figures (resumable)",
        description="Run the ensemble described by CONFIG.toml (PSD source, surface size, n, humidities, "
                    "adsorbed layer, output folder, scheduler). Re-running the same command resumes an "
                    "interrupted run.",
    )
    p.add_argument("config", help="TOML file (see docs/ensembles.md and examples/*.toml)")
    p.add_argument("--scheduler", default=None,
                   help="dask scheduler: 'threads' (default), 'sync', or a distributed address tcp://host:port")
    p.add_argument("--n", default=None, help="override [ensemble] n (an integer or 'auto')")
    p.add_argument("--out", default=None, help="override [output] folder")
    p.add_argument("--overwrite", action="store_true",
                   help="replace a run with different parameters in the output folder")
    p.add_argument("--no-figures", action="store_true", help="write NetCDF only")
    p.set_defaults(func=_run)


def run_config(cfg, *, figures=True, log=print):
    """Run a parsed :class:`roughstick._config.RunConfig`; return the written paths."""

    t0 = time.perf_counter()
    psd = cfg.psd_da if hasattr(cfg, "psd_da") else cfg.build_psd()
    shape = rs.surface_shape(shape=cfg.shape, size=cfg.size, spacing=cfg.spacing)
    n_grid = cfg.auto.get("n_max", 3000) if cfg.n == "auto" else cfg.n
    dist = rs.ensemble_distance_grid(psd, shape=shape, n=n_grid, relative_humidity=cfg.relative_humidity,
                                     adsorbed_layer=cfg.adsorbed_layer, num=cfg.distance_points,
                                     lower=cfg.distance_lower)
    cfg.folder.mkdir(parents=True, exist_ok=True)
    ens_dir = cfg.folder / "ensemble"
    log(f"{cfg.title}: n={cfg.n}, shape={shape}, spacing={cfg.spacing * 1e9:g} nm, "
        f"RH={cfg.relative_humidity}, output {ens_dir}")
    ds = rs.run_ensemble(
        psd, n=cfg.n, shape=shape, spacing=cfg.spacing, relative_humidity=cfg.relative_humidity,
        seed=cfg.seed, chunks=cfg.chunks, distance=dist, adsorbed_layer=cfg.adsorbed_layer,
        output=ens_dir, overwrite=cfg.overwrite, scheduler=cfg.scheduler,
        connect_timeout=cfg.connect_timeout, progress=cfg.progress, **cfg.auto,
    )
    ds = ds.load()
    written = [ens_dir]
    band = rs.confidence_band(ds)
    band.attrs["title"] = f"{cfg.title}: ensemble band"
    path = cfg.folder / "band.nc"
    rs.io.netcdf.write(band, path, compute=True)
    written.append(path)
    if figures and cfg.figures:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt


        fig = plot_ensemble_curves(ds)
        fig.suptitle(cfg.title)
        written.append(_save(fig, cfg.folder / "curves.png"))
        ax = plot_energy_band(ds)
        ax.set_title(cfg.title)
        written.append(_save(ax.figure, cfg.folder / "energy_band.png"))
        ax = plot_energy_distribution(ds)
        ax.set_title(cfg.title)
        written.append(_save(ax.figure, cfg.folder / "energy_ecdf.png"))
        plt.close("all")
    g = band["adhesive_energy"]
    for k, r in enumerate(band.rh.values):
        lo, med, hi = (g.values[:, k] * 1e3)
        log(f"  RH {r:.0%}: Γ median {med:.4g} mJ/m², {band.attrs['level']:.0%} band [{lo:.4g}, {hi:.4g}]")
    log(f"done in {time.perf_counter() - t0:.1f} s; n = {ds.sizes['realization']}")
    return written


def _save(fig, path: pathlib.Path) -> pathlib.Path:
    fig.savefig(path, dpi=110)
    return path


def _run(args):

    overrides = {"scheduler": args.scheduler, "overwrite": args.overwrite}
    if args.n is not None:
        overrides["n"] = args.n if args.n == "auto" else int(args.n)
    if args.out is not None:
        overrides["folder"] = str(pathlib.Path(args.out).resolve())
    cfg = load_config(args.config, overrides=overrides)
    try:
        files = run_config(cfg, figures=not args.no_figures)
    except ConnectionError as exc:
        raise ValueError(str(exc)) from exc
    for f in files:
        print(f"    {f}")
    return 0
