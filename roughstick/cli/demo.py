"""``roughstick demo``: the README's main job on the bundled samples."""

from __future__ import annotations

import pathlib
import time

from ..demos import steps


def register(sub):
    p = sub.add_parser(
        "demo",
        help="run the whole pipeline on the bundled samples; write NetCDF and PNG figures",
        description="Run every demo step on the bundled samples and write NetCDF + PNG to --out.",
    )
    p.add_argument("--out", default="roughstick-demo", help="output folder (default ./roughstick-demo)")
    p.add_argument("--only", nargs="*", default=None, help="run only the steps whose name contains one of these words")
    p.add_argument("--quick", action="store_true", help="smaller sizes (used by the tests)")
    p.set_defaults(func=_run)


def _run(args):
    import matplotlib

    matplotlib.use("Agg")

    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for mod in steps():
        name = mod.__name__.rsplit(".", 1)[-1]
        if args.only and not any(w in name for w in args.only):
            continue
        t0 = time.perf_counter()
        files = mod.run(out, quick=args.quick)
        written += files
        print(f"[{name}] {len(files)} files in {time.perf_counter() - t0:.1f} s")
        for f in files:
            print(f"    {f}")
    print(f"wrote {len(written)} files to {out.resolve()}")
    return 0
