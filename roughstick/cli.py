"""The ``roughstick`` console script: thin argparse front end over the public API.

Sub-commands live in :mod:`roughstick._cli` (one module each, discovered at start-up):
``demo`` runs every step of :mod:`roughstick.demos` on the bundled samples.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

from . import _cli
from ._core.version import __version__

__all__ = ["main", "build_parser"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="roughstick",
        description="Uncertainty of humid stiction between rough hard surfaces.",
    )
    parser.add_argument("--version", action="version", version=f"roughstick {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for info in sorted(pkgutil.iter_modules(_cli.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        mod = importlib.import_module(f"{_cli.__name__}.{info.name}")
        mod.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``roughstick`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except (ValueError, FileNotFoundError, FileExistsError, TypeError) as exc:
        print(f"roughstick {args.command}: error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
