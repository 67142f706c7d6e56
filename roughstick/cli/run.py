"""``roughstick run CONFIG.toml``: a Monte Carlo ensemble from a TOML config (docs/configuration.md).

Writes, into the config's output folder: ``ensemble/`` (one CF NetCDF file per block plus
``manifest.json``; an interrupted run resumes from it), ``band.nc`` (median, 95 % band, each band
edge's own confidence interval, the run's parameters and, for ``n = "auto"``, whether it
converged), and unless ``figures = false`` ``curves.png``, ``energy_band.png``,
``energy_ecdf.png`` (or ``.pdf``/``.svg`` with ``--format``, at ``--dpi``). Every file appears
under its final name only once complete. The scheduler and the output folder are checked, and
the folder claimed for this run, before any work.
"""

from __future__ import annotations

import dataclasses
import pathlib
import time
import warnings

import numpy as np

import roughstick as rs

from .._core.materials import POLYSILICON, material_attrs
from .._core.validate import surface_shape
from ..plotting.ensemble import (
    plot_energy_band,
    plot_energy_distribution,
    plot_ensemble_curves,
)
from ..plotting.save import DEFAULT_DPI, DEFAULT_FORMAT, save_figure
from ._common import (
    LOG,
    add_figure_options,
    check_scheduler,
    claim_folder,
    config_spellings,
    figure_options,
    finish_folder,
)
from ._config import HEIGHTS_DEFAULT, load_config


def register(sub):
    p = sub.add_parser(
        "run",
        help="run a Monte Carlo ensemble from a TOML config; write NetCDF and figures (resumable)",
        description="Run the ensemble described by CONFIG.toml (PSD source, surface size, n, humidities, "
                    "adsorbed layer, output folder, scheduler; see docs/configuration.md). Re-running "
                    "the same command resumes an interrupted run.",
    )
    p.add_argument("config", help="TOML file (docs/configuration.md; `roughstick examples --out examples` writes the shipped ones, e.g. examples/ensemble_S1_samples.toml)")
    p.add_argument("--scheduler", default=None,
                   help="dask scheduler: 'threads' (default), 'sync', or a distributed address tcp://host:port")
    p.add_argument("--n", default=None, help="override [ensemble] n (an integer >= 1 or 'auto')")
    p.add_argument("--out", default=None, help="override [output] folder")
    p.add_argument("--overwrite", action="store_true",
                   help="replace a run with different parameters in the output folder")
    p.add_argument("--no-figures", action="store_true", help="write NetCDF only")
    add_figure_options(p)
    p.set_defaults(func=_run, remedies=lambda args: config_spellings(contact_model="ensemble"))


def _auto_keywords(auto: dict) -> dict:
    """The [ensemble] keys of n = 'auto' as keywords of :func:`roughstick.ensemble.run`."""
    return {{"tolerance": "target_precision"}.get(k, k): v for k, v in auto.items()}


#: RunConfig fields that do not change the results (where and how they are computed).
_NOT_PARAMS = ("path", "folder", "overwrite", "scheduler", "connect_timeout", "progress", "figures")


def run_params(cfg) -> dict:
    """The parameters of a run that decide its results, as the output folder's marker records them
    (the contact model and material only when not the defaults, and under the marker's names, so
    earlier folders resume)."""
    out = {f.name: getattr(cfg, f.name) for f in dataclasses.fields(cfg) if f.name not in _NOT_PARAMS}
    model = out.pop("model")
    if model != "modified_dmt":
        out["contact_model"] = model
    heights = out.pop("height_distribution")
    if heights != HEIGHTS_DEFAULT:  # a run that does not set them resumes its earlier folders
        out["height_distribution"] = heights
    if out["psd"].get("level", "auto") == "auto":  # the default: earlier folders resume
        out["psd"] = {k: v for k, v in out["psd"].items() if k != "level"}
    material = out.pop("material", POLYSILICON)
    if material != POLYSILICON:
        out["material"] = material_attrs(material)
    return out


def run_config(cfg, *, figures=True, log=LOG.info, scheduler_from="[run] scheduler",
               figure_format=DEFAULT_FORMAT, dpi=DEFAULT_DPI):
    """Run a parsed :class:`roughstick.cli._config.RunConfig`; return the written paths.

    Figures are saved as ``figure_format`` (png, pdf or svg) at ``dpi``
    (:func:`roughstick.plotting.save_figure`).

    The output folder is claimed (:func:`roughstick.cli._common.claim_folder`) before any work,
    and marked complete once every file is written."""
    t0 = time.perf_counter()
    # before any work: a bad scheduler, or an output folder that is a file, read-only or holds
    # another run's complete results, is said now, not after minutes of computing
    check_scheduler(cfg.scheduler, where=scheduler_from)
    claim_folder(cfg.folder, command="run", params=run_params(cfg), overwrite=cfg.overwrite, keep=[cfg.path])
    maps = cfg.sample_maps()
    psd = cfg.psd_da if hasattr(cfg, "psd_da") else cfg.build_psd(maps=maps)
    shape = surface_shape(shape=cfg.shape, size=cfg.size, spacing=cfg.spacing)
    said = _warn_if_extrapolated(psd, shape, cfg.spacing, source=cfg.psd["source"])
    heights = _heights(cfg, maps, log)
    n_grid = cfg.auto.get("n_max", 3000) if cfg.n == "auto" else cfg.n
    dist = rs.ensemble.distance_grid(psd, shape=shape, n=n_grid, relative_humidity=cfg.relative_humidity,
                                     adsorbed_layer=cfg.adsorbed_layer,
                                     n_distance=cfg.distance_points, lower=cfg.distance_lower,
                                     height_distribution=heights)
    ens_dir = cfg.folder / "ensemble"
    log(f"{cfg.title}: n={cfg.n}, shape={shape}, spacing={cfg.spacing * 1e9:g} nm, "
        f"RH={cfg.relative_humidity}, contact model {cfg.model}, material {cfg.material.name} "
        f"(E = {cfg.material.youngs_modulus / 1e9:.4g} GPa, ν = {cfg.material.poisson_ratio:g}), output {ens_dir}")
    with warnings.catch_warnings():
        if said:  # already said above in the config's words, not once more from the generator
            warnings.simplefilter("ignore", rs.surface.ExtrapolatedPSDWarning)
        ds = rs.ensemble.run(
            psd, n=cfg.n, shape=shape, spacing=cfg.spacing, relative_humidity=cfg.relative_humidity,
            seed=cfg.seed, chunks=cfg.chunks, distance=dist, adsorbed_layer=cfg.adsorbed_layer,
            output=ens_dir, overwrite=cfg.overwrite, scheduler=cfg.scheduler,
            connect_timeout=cfg.connect_timeout, progress=cfg.progress, material=cfg.material,
            model=cfg.model,
            maps=maps or None, height_distribution="gaussian" if heights is None else heights,
            distribution_method=cfg.height_distribution["distribution_method"],
            **_auto_keywords(cfg.auto),
        )
    ds = ds.load()
    written = [ens_dir]
    band = rs.ensemble.confidence_band(ds)
    band.attrs["title"] = f"{cfg.title}: ensemble band"
    band.attrs["configuration"] = cfg.path.read_text()
    band.attrs.update(material_attrs(cfg.material), contact_model=ds.attrs.get("contact_model", cfg.model))
    for v in [v for v in ds.data_vars if str(v).startswith("map_")]:  # the maps' own summaries
        band[v] = ds[v]
    path = cfg.folder / "band.nc"
    rs.io.netcdf.write(band, path, compute=True, overwrite=True)
    written.append(path)
    if figures and cfg.figures:
        import matplotlib

        matplotlib.use("Agg")

        fig = plot_ensemble_curves(ds)
        fig.suptitle(cfg.title)
        save = {"format": figure_format, "dpi": dpi}
        written.append(save_figure(fig, cfg.folder / "curves.png", **save))
        ax = plot_energy_band(ds)
        ax.set_title(cfg.title)
        written.append(save_figure(ax.figure, cfg.folder / "energy_band.png", **save))
        ax = plot_energy_distribution(ds)
        ax.set_title(cfg.title)
        written.append(save_figure(ax.figure, cfg.folder / "energy_ecdf.png", **save))
    log("apparent adhesive energy Γ:")
    for line in rs.ensemble.band_summary(band, median_interval=True):
        log("  " + line)
    for line in _map_lines(ds):
        log(line)
    if cfg.n == "auto":
        state = "converged" if band.attrs.get("auto_converged") else (
            "NOT converged: stopped at n_max; raise [ensemble] n_max or tolerance")
        log(f"n = 'auto': {state} (n = {ds.sizes['realization']})")
    finish_folder(cfg.folder)
    log(f"done in {time.perf_counter() - t0:.1f} s; n = {ds.sizes['realization']}")
    return written


def _heights(cfg, maps: list, log):
    """The height distribution of the run's surfaces ([surface] height_distribution), said
    before the work: None for Gaussian surfaces, else a distribution Dataset."""
    choice = cfg.heights()
    if not isinstance(choice, str):
        log(f"heights: Johnson {choice.attrs['family'][-2:].upper()} with skewness "
            f"{choice.attrs['skewness']:.3g}, kurtosis {choice.attrs['kurtosis']:.3g}")
        return choice
    if choice == "gaussian" or not maps:
        log("heights: Gaussian" + (" ([surface] height_distribution = \"gaussian\")" if maps else ""))
        return None
    gaussian = rs.surface.is_gaussian(maps)
    if choice == "auto" and gaussian:
        log("heights: Gaussian (the maps are Gaussian within their sampling error)")
        return None
    d = rs.surface.height_distribution(maps)
    log(f"heights: the maps' own distribution (skewness {d.attrs['skewness']:.3g}, kurtosis "
        f"{d.attrs['kurtosis']:.3g}" + (", not Gaussian within their sampling error" if not gaussian else "")
        + f"), imposed by {cfg.height_distribution['distribution_method']}")
    return d


def _map_lines(ds) -> list[str]:
    """The measured maps' own Γ and their percentiles in the ensemble, one line per map."""
    if "map_adhesive_energy" not in ds:
        return []
    lines = [f"the maps' own Γ ({ds.attrs.get('maps_compared', 'the whole maps')}) and their "
             "percentile in the ensemble:"]
    for name in ds["map"].values:
        cells = [f"RH {float(r):.2g}: {float(g) * 1e3:.3g} mJ/m² ({float(p):.0f} %)"
                 for r, g, p in zip(ds.rh.values, ds.map_adhesive_energy.sel(map=name).values,
                                    ds.map_percentile.sel(map=name).values, strict=True)]
        lines.append(f"  {name}: " + ", ".join(cells))
    return lines


def _warn_if_extrapolated(psd, shape, spacing: float, *, source: str) -> bool:
    """A measured PSD is known down to q = 2π/L of the scan it came from: generated surfaces larger
    than that scan rest on an extrapolated low-q PSD. Say so."""
    if source == "moments" or "qx" not in psd.dims:
        return False
    measured = [2 * np.pi / float(abs(psd[d][1] - psd[d][0])) for d in ("qy", "qx")]
    generated = [n * spacing for n in shape]
    if any(g > m * (1 + 1e-6) for g, m in zip(generated, measured, strict=True)):
        LOG.warning(
            f"warning: the generated surfaces ({generated[0] * 1e6:.3g} x {generated[1] * 1e6:.3g} µm) "
            f"are larger than the scans the PSD was measured on ({measured[0] * 1e6:.3g} x "
            f"{measured[1] * 1e6:.3g} µm): their low-q PSD is extrapolated. Use a smaller [surface] "
            "size, or fewer sub-maps ([psd] submaps) so the PSD reaches lower q.")
        return True
    return False


def _run(args):
    overrides = {"scheduler": args.scheduler, "overwrite": args.overwrite, "n": args.n}
    if args.out is not None:
        overrides["folder"] = str(pathlib.Path(args.out).resolve())
    cfg = load_config(args.config, overrides=overrides)
    opts = figure_options(args)
    files = run_config(cfg, figures=not args.no_figures,
                       scheduler_from="--scheduler" if args.scheduler is not None else "[run] scheduler",
                       figure_format=opts["format"], dpi=opts["dpi"])
    for f in files:
        LOG.info(f"    {f}")
    return 0
