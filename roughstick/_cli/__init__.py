"""Sub-commands of the ``roughstick`` console script.

Each module here defines ``register(subparsers)`` that adds one sub-command whose handler calls
the public API only (no physics in the CLI). :mod:`roughstick.cli` discovers them.
"""
