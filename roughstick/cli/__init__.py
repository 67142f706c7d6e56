"""The ``roughstick`` console script: a thin argparse front end over the public API.

One module per sub-command, each defining ``register(subparsers)`` that adds the sub-command and
a handler calling the public API only (no physics here), and optionally ``remedies(args)``, how
the warnings raised during the command spell their fixes (flags or configuration keys,
:mod:`roughstick._core.remedy`): ``curves``, ``demo`` (every step of
:mod:`roughstick.paper.demo` on the bundled samples), ``examples`` (the shipped example configs), ``psd``, ``reproduce``, ``risk`` and ``run``
(TOML configs read by :mod:`._config`). See docs/cli.md.
"""

from __future__ import annotations

import argparse
import sys
import warnings

from .._core.remedy import spelled
from .._core.version import __version__
from . import beam, curves, demo, examples, psd, reproduce, risk, run
from ._common import add_common_options, setup_logging, teardown_logging, user_message
from ._process import interrupted_message, release_folders, run_stoppable

__all__ = ["main", "build_parser", "COMMANDS"]

#: The sub-command modules, in the order ``roughstick --help`` lists them.
COMMANDS = (curves, demo, examples, psd, reproduce, risk, run, beam)


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
    for cmd in sub.choices.values():  # the same --quiet / --verbose on every command
        add_common_options(cmd, overwrite=False)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``roughstick`` console script.

    Exit status: 0 done, 1 an error the user can fix (one line naming the fix), 2 bad command-line
    usage, 130 interrupted (Ctrl-C; re-running the same command resumes). Other exceptions are
    bugs and keep their traceback.

    Called without ``argv`` (the console script, ``python -m roughstick``), the process is the
    command's: one Ctrl-C ends it within moments, whatever it is computing or writing
    (:func:`._process.run_stoppable`). Called with ``argv`` (from Python), a Ctrl-C raises
    ``KeyboardInterrupt`` in the command as usual, which is then reported the same way.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        remedies = getattr(args, "remedies", None)  # the command's spelling of the fixes it names
        with warnings.catch_warnings(), spelled(**(remedies(args) if remedies else {})):
            setup_logging(quiet=getattr(args, "quiet", False), verbose=getattr(args, "verbose", False))
            if argv is None:  # this process runs the command: Ctrl-C ends it at once
                return int(run_stoppable(args.func, args, command=args.command) or 0)
            return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print(interrupted_message(args.command), file=sys.stderr)
        return 130
    except Exception as exc:
        msg = user_message(exc)
        if msg is None:
            raise
        print(f"roughstick {args.command}: error: {msg}", file=sys.stderr)
        return 1
    finally:
        release_folders()  # however the command ended, its output folders are free for the next
        teardown_logging()
