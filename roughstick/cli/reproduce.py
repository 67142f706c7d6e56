"""``roughstick reproduce [--quick]``: the paper's Figs. 13-17 from the bundled S1/S2 samples.

Paper scale (default): 3000 surfaces per sample and size, 5.12 µm (1024²) and 10.24 µm (2048²)
at 5 nm, six humidities: many CPU-hours; run it on a cluster with ``--scheduler tcp://...``, and
re-run the same command after an interruption: every ensemble streams into its own folder under
``--out`` and resumes. ``--quick``: 24 surfaces of 0.64 µm (128²) and 1.28 µm (256²), a few minutes
on a laptop; the figures say which scale they show.
"""

from __future__ import annotations

import pathlib
import time
import warnings

import numpy as np
import xarray as xr

import roughstick as rs

from ..paper import ensemble as figures
from ..plotting.save import DEFAULT_DPI, DEFAULT_FORMAT, save_figure
from ._common import (
    LOG,
    add_figure_options,
    check_scheduler,
    claim_folder,
    figure_options,
    finish_folder,
    fixed_spellings,
    positive_int,
    run_status,
)

RH = {"S1": [0.3, 0.5, 0.6, 0.7, 0.8, 0.9], "S2": [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]}
SCALES = {
    # n, (small, large) shapes at 5 nm
    "paper": (3000, (1024, 2048)),
    "quick": (24, (128, 256)),
}


def register(sub):
    p = sub.add_parser(
        "reproduce",
        help="regenerate the paper's Figs. 13-17 (Monte Carlo ensembles) at paper scale or --quick",
        description="Figs. 13-17 of the paper from the bundled S1/S2 samples. Resumable: re-run the "
                    "same command after an interruption.",
    )
    p.add_argument("--quick", action="store_true", help="24 surfaces of 128² and 256² instead of 3000 of 1024² and 2048²")
    p.add_argument("--out", default="roughstick-reproduce", help="output folder")
    p.add_argument("--n", type=positive_int, default=None, help="override the number of realizations (>= 1)")
    p.add_argument("--scheduler", default=None, help="'threads' (default) or tcp://host:port")
    p.add_argument("--overwrite", action="store_true", help="replace runs with other parameters in --out")
    add_figure_options(p)
    p.set_defaults(func=_run, remedies=lambda args: fixed_spellings("reproduce"))


def reproduce(out, *, quick: bool, n: int | None = None, scheduler=None, overwrite=False, log=LOG.info,
              figure_format: str = DEFAULT_FORMAT, dpi: int = DEFAULT_DPI):
    """Compute and plot Figs. 13-17 (figures as ``figure_format`` at ``dpi``); return the written paths."""
    # the paper (§4.2.1) generates surfaces up to 10.24 µm from the PSD of 1.28 µm sub-maps,
    # interpolated below its lowest wave number: said once in the log, not warned per size
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rs.surface.ExtrapolatedPSDWarning)
        return _reproduce(out, quick=quick, n=n, scheduler=scheduler, overwrite=overwrite, log=log,
                          save={"format": figure_format, "dpi": dpi})


def _reproduce(out, *, quick, n, scheduler, overwrite, log, save):
    import matplotlib

    matplotlib.use("Agg")


    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    scale = "quick" if quick else "paper"
    n_default, shapes = SCALES[scale]
    n = n or n_default
    files = []
    results = {}
    for k, sample in enumerate(("S1", "S2")):
        psd = rs.datasets.sample_psd(sample)
        scan = 2 * np.pi / float(psd.qx[1] - psd.qx[0])
        if max(shapes) * 5e-9 > scan * (1 + 1e-6):
            log(f"[{sample}] as in the paper (§4.2.1), surfaces larger than {scan * 1e6:.2f} µm use "
                "the PSD of the sub-maps interpolated below its lowest wave number")
        # Fig. 13: three generated surfaces
        _, fig = figures.fig13_surfaces(psd, shape=shapes[0], seed=13 + k, title=sample)
        files.append(save_figure(fig, out / f"fig13_surfaces_{sample}.png", **save))
        dist = rs.ensemble.distance_grid(psd, shape=(shapes[1], shapes[1]), n=n,
                                         relative_humidity=RH[sample])
        per_size = []
        for j, s in enumerate(shapes):
            t0 = time.perf_counter()
            folder = out / f"ensemble_{sample}_{s}"
            ds = rs.ensemble.run(psd, n=n, shape=s, spacing=5e-9, relative_humidity=RH[sample],
                                 seed=np.random.SeedSequence(2015, spawn_key=(k, j)), chunks=2 if s <= 512 else 1, distance=dist,
                                 output=folder, overwrite=overwrite, scheduler=scheduler, model="modified_dmt")
            files.append(folder)
            log(f"[{sample} {s}²] {n} realizations in {time.perf_counter() - t0:.1f} s -> {folder}")
            per_size.append(ds.load())
        both = xr.concat(per_size, dim="surface_size", data_vars="all", coords="minimal",
                         compat="override", combine_attrs="drop_conflicts")
        both = both.assign_coords(surface_size=("surface_size", [s * 5e-9 for s in shapes],
                                                dict(rs.conventions.ATTRS["surface_size"])))
        results[sample] = both
        # Figs. 14 (S1) and 15 (S2): curve sets at the smaller size
        _, fig = figures.fig14_ensemble_curves(
            per_size[0], title=f"Fig. {14 + k}: {sample}, surfaces of {shapes[0] * 5e-3:.2f} µm ({scale} scale)")
        files.append(save_figure(fig, out / f"fig{14 + k}_curves_{sample}.png", **save))
        band = rs.ensemble.confidence_band(both)
        files.append(rs.io.netcdf.write(band, out / f"band_{sample}.nc", compute=True, overwrite=True))
        for size in band.surface_size.values:
            log(f"[{sample}, {size * 1e6:.2f} µm] apparent adhesive energy Γ:")
            for line in rs.ensemble.band_summary(band.sel(surface_size=size)):
                log("  " + line)
    # Fig. 16: Γ bands vs RH for both sizes, S1 (a) and S2 (b)
    _, fig = figures.fig16_energy_bands(results, title=f"Fig. 16 ({scale} scale)")
    files.append(save_figure(fig, out / "fig16_energy_bands.png", **save))
    # Fig. 17: distributions of Γ for S1, both sizes
    _, fig = figures.fig17_energy_distributions(
        results["S1"], rh_panels=[(0.3, 0.5, 0.6), (0.7, 0.8, 0.9)],
        title=f"Fig. 17: distribution of Γ, S1, two surface sizes ({scale} scale)")
    files.append(save_figure(fig, out / "fig17_energy_distributions_S1.png", **save))
    return files




def _run(args):
    t0 = time.perf_counter()
    check_scheduler(args.scheduler, where="--scheduler")  # before any work
    unfinished = run_status(args.out) == "running"  # a failed earlier run never blocks this one
    claim_folder(args.out, command="reproduce", params={"quick": args.quick, "n": args.n},
                 overwrite=args.overwrite)
    opts = figure_options(args)
    files = reproduce(args.out, quick=args.quick, n=args.n, scheduler=args.scheduler,
                      overwrite=args.overwrite or unfinished, figure_format=opts["format"], dpi=opts["dpi"])
    finish_folder(args.out)
    for f in files:
        LOG.info(f"    {f}")
    LOG.info(f"wrote {len(files)} outputs to {pathlib.Path(args.out).resolve()} in {time.perf_counter() - t0:.0f} s")
    return 0
