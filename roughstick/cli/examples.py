"""``roughstick examples [NAME ...] [--out DIR]``: list, or copy, the example configurations
shipped with roughstick (``examples/*.toml`` of the repository, package data of the wheel).

Each file opens with a ``# description: ...`` line saying what question it answers; the listing
prints it under the command that runs the file.

Their maps are named ``bundled:S1A`` ... (the sample maps inside the package), so a copy runs
from any folder; the output folders they name are relative to the copy.
"""

from __future__ import annotations

import pathlib

import roughstick as rs

from ..io.netcdf import write_text_atomic
from ._config import SCHEMAS, read_toml


def register(sub):
    p = sub.add_parser(
        "examples",
        help="list the example configurations of run, risk and beam, or copy them to --out",
        description=(
            "Without --out, list the example TOML configurations shipped with roughstick, the "
            "command that runs each and what it answers. With --out DIR, copy them (or the NAMEs given) into DIR, e.g. "
            "`roughstick examples --out examples` then `roughstick run "
            "examples/ensemble_S1_samples.toml`. Their sample maps are named bundled:S1A ..., so "
            "the copies run from any folder."
        ),
    )
    p.add_argument("names", nargs="*", metavar="NAME",
                   help="examples to copy (default: all), e.g. risk or risk.toml")
    p.add_argument("--out", default=None, help="folder to copy them to (created); without it, list them")
    p.add_argument("--overwrite", action="store_true", help="replace files of the same name in --out")
    p.set_defaults(func=_run)


def _command(path: pathlib.Path) -> str:
    """The sub-command whose schema holds every table of the config ``path``."""
    tables = {k for k, v in read_toml(path).items() if isinstance(v, (dict, list))}
    return next((c for c in ("run", "risk", "beam") if tables <= set(SCHEMAS[c])), "run")


def description(path: pathlib.Path) -> str:
    """What the example ``path`` answers: its ``# description: ...`` comment line (empty if none)."""
    for line in path.read_text().splitlines():
        head, sep, text = line.partition("description:")
        if sep and head.strip() == "#":
            return text.strip()
        if line.strip() and not line.startswith("#"):
            break  # the description sits in the opening comments
    return ""


def _run(args):
    shipped = rs.datasets.example_configs()
    picked = list(shipped)
    if args.names:
        unknown = [n for n in args.names if n not in shipped and f"{n}.toml" not in shipped]
        if unknown:
            raise ValueError(f"NAME {' '.join(unknown)}: no such example; the shipped examples are "
                             f"{', '.join(n.removesuffix('.toml') for n in shipped)}.")
        picked = [n if n in shipped else f"{n}.toml" for n in args.names]
    if args.out is None:
        print("example configurations shipped with roughstick (copy them with "
              "`roughstick examples --out examples`):")
        for name in picked:
            print(f"  roughstick {_command(shipped[name])} examples/{name}")
            text = description(shipped[name])
            if text:
                print(f"      {text}")
        return 0
    out = pathlib.Path(args.out)
    if out.exists() and not out.is_dir():
        raise FileExistsError(f"--out {str(out)!r} is a file; give a folder, e.g. --out examples.")
    clash = [n for n in picked if (out / n).exists()]
    if clash and not args.overwrite:
        raise FileExistsError(f"--out {str(out)!r} already holds {', '.join(clash)}; pass --overwrite "
                              "to replace them or choose another --out.")
    out.mkdir(parents=True, exist_ok=True)
    for name in picked:
        write_text_atomic(out / name, shipped[name].read_text())
        print(f"wrote {out / name}  (run: roughstick {_command(shipped[name])} {out / name})")
    return 0
