"""The modified DMT of a rough surface against a flat (paper §3.3, Eqs. 16-23).

:func:`modified_dmt_curves` (registered as the contact model ``"modified_dmt"``) and its
automatic grid :func:`contact_distance_grid`; :func:`kernel`, the same numbers on numpy arrays
for callers that evaluate thousands of maps. Inside: the compiled one-pass controller
(:mod:`._controller`) over the sorted top tail of the heights (:mod:`._tail`) and a union-find
that moves both ways (:mod:`._unionfind`), the sphere fit of Eq. 21 (:mod:`._fit`, its local
solver :mod:`._lm` and the search between local minima :mod:`._search`), and the grid policy
(:mod:`._policy`: the controller's named parameters; :mod:`._grid`: Γ's refinement).
"""

from ._curves import MODEL, REFERENCES, contact_distance_grid, kernel, modified_dmt_curves

__all__ = ["modified_dmt_curves", "contact_distance_grid", "kernel", "MODEL", "REFERENCES"]
