"""Old top-level names of roughstick and where they live now (``rs.<old>`` still works, with a
``DeprecationWarning`` naming the new name: see ``roughstick.__getattr__``).

Each value is a dotted path below ``roughstick`` (``"contact.curves"``). One section per area of
the package; add a line to your own section only.
"""

RENAMED: dict[str, str] = {}

# ---------------------------------------------------------------------------- _core, io, surface
RENAMED.update({
})


# --------------------------------------------------------------------------------------- contact
RENAMED.update({
})


# ------------------------------------------------------------------------ ensemble, paper, misc
RENAMED.update({
})


# ---------------------------------------------------------------- stiction, beam, reliability
RENAMED.update({
})
