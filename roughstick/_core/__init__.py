"""What every stage of roughstick shares: units, validation, references, conventions, dask helpers.

Modules here import nothing else from roughstick (tests/test_architecture.py checks it). Their
public names are the helpers the stages build on; the user-facing ones are re-exported by the
stage that owns them (e.g. :func:`roughstick.contact.as_relative_humidity` from :mod:`roughstick.contact`).
"""
