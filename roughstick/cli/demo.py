"""``roughstick demo``: the README's main job on the bundled samples."""

from __future__ import annotations

import time

from ..paper.demo import steps
from ._common import (
    LOG,
    add_figure_options,
    claim_folder,
    figure_options,
    finish_folder,
    fixed_spellings,
)


def _names() -> list[str]:
    return [m.__name__.rsplit(".", 1)[-1] for m in steps()]


def register(sub):
    p = sub.add_parser(
        "demo",
        help="run the whole pipeline on the bundled samples; write NetCDF and figures",
        description="Run every demo step on the bundled samples and write NetCDF files and figures "
                    "(PNG, or PDF/SVG with --format) to --out. Re-running the same command rewrites "
                    "the same files (the ensemble resumes).",
    )
    p.add_argument("--out", default="roughstick-demo", help="output folder (default ./roughstick-demo)")
    p.add_argument("--only", nargs="+", default=None, metavar="STEP",
                   help="run only the steps whose name contains one of these words "
                        "(steps: sphere, topography, rough_contact, ensemble, cantilever)")
    p.add_argument("--quick", action="store_true", help="smaller sizes (used by the tests)")
    add_figure_options(p)
    p.add_argument("--overwrite", action="store_true",
                   help="replace the results of another command or other options in --out")
    p.set_defaults(func=_run, remedies=lambda args: fixed_spellings("demo"))


def _run(args):
    import matplotlib

    matplotlib.use("Agg")

    mods = steps()
    if args.only:
        names = _names()
        unknown = [w for w in args.only if not any(w in n for n in names)]
        if unknown:
            raise ValueError(f"--only {' '.join(unknown)}: no such step; the steps are "
                             f"{', '.join(n.split('_', 1)[1] for n in names)}.")
        mods = [m for m, n in zip(mods, names, strict=True) if any(w in n for w in args.only)]
    out = claim_folder(args.out, command="demo",
                       params={"quick": args.quick, "only": sorted(args.only or [])},
                       overwrite=args.overwrite)
    written = []
    t_all = time.perf_counter()
    for mod in mods:
        name = mod.__name__.rsplit(".", 1)[-1]
        LOG.info(f"[{name}] ...")
        t0 = time.perf_counter()
        opts = figure_options(args)
        files = mod.run(out, quick=args.quick, figure_format=opts["format"], dpi=opts["dpi"])
        written += files
        LOG.info(f"[{name}] {len(files)} files in {time.perf_counter() - t0:.1f} s")
        for f in files:
            LOG.debug(f"    {f}")
    finish_folder(out)
    LOG.info(f"wrote {len(written)} files to {out.resolve()} in {time.perf_counter() - t_all:.1f} s")
    return 0
