"""The boundary-element reference of humid rough contact, via Tamaas (registered as ``"bem"``).

:func:`bem_curves`: the model the others are measured against (``pip install roughstick[bem]``);
the Tamaas adapter (solver, retries, the states without hard contact) in :mod:`._tamaas`.
"""

from ._curves import MODEL, bem_curves

__all__ = ["bem_curves", "MODEL"]
