"""The ``roughstick`` console script: a thin argparse front end over the public API.

One module per sub-command, each defining ``register(subparsers)`` that adds the sub-command and
a handler calling the public API only (no physics here): ``curves``, ``demo`` (every step of
:mod:`roughstick.demos` on the bundled samples), ``psd``, ``reproduce``, ``risk`` and ``run``
(TOML configs read by :mod:`._config`). See docs/cli.md.
"""

from __future__ import annotations

import argparse
import sys

from .._core.version import __version__
from . import beam, curves, demo, psd, reproduce, risk, run

__all__ = ["main", "build_parser", "COMMANDS"]

#: The sub-command modules, in the order ``roughstick --help`` lists them.
COMMANDS = (curves, demo, psd, reproduce, risk, run, beam)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``roughstick`` console script, every sub-command registered."""
    parser = argparse.ArgumentParser(
        prog="roughstick",
        description="Uncertainty of humid stiction between rough hard surfaces.",
    )
    parser.add_argument("--version", action="version", version=f"roughstick {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for mod in COMMANDS:
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
