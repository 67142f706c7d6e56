"""Geometry of a periodic map shared by the two boundary-element solvers (``bem``, ``fft_bem``).

- :func:`periodic_offset_coefficient`: the lattice constant of the periodic Boussinesq kernel,
  which converts the zero-mean-displacement distance of an FFT solver into the isolated-contact
  convention of Eq. 16;
- :func:`count_periodic_clusters`: contact clusters of a mask on the torus.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage
from scipy.special import erfc

__all__ = ["periodic_offset_coefficient", "count_periodic_clusters", "merge_humidity_grids", "SOLVED_ATTRS"]

# the ``solved`` variable of both boundary-element models (see merge_humidity_grids)
SOLVED_ATTRS = {"long_name": "state solved at this humidity (1) or interpolated (0)", "units": "1"}


def periodic_offset_coefficient(length_x: float, length_y: float) -> float:
    r"""Lattice constant :math:`Z` of the periodic Boussinesq kernel [m-1].

    A periodic half-space loaded by one point force :math:`F` per cell, with the displacement's
    mean fixed to zero (the FFT convention), displaces near the load as the isolated Boussinesq
    solution plus the constant :math:`F Z / (\pi E^*)`. ``Z`` is the zero-background lattice sum
    :math:`\sum'_n 1/|\mathbf{R}_n|`, evaluated by Ewald summation; for a square cell of side
    :math:`L`, :math:`Z = -3.900265/L` (:math:`4\zeta(1/2)\beta(1/2)`).

    Parameters
    ----------
    length_x, length_y : float
        Cell sides [m], > 0.

    Returns
    -------
    float
        :math:`Z` [m-1] (negative).

    Examples
    --------
    >>> round(rs.contact.fft_bem.periodic_offset_coefficient(1.0, 1.0), 6)
    -3.900265
    """
    if not (length_x > 0 and length_y > 0):
        raise ValueError(f"cell sides must be positive, got {length_x!r}, {length_y!r}.")
    area = length_x * length_y
    alpha = np.sqrt(np.pi / area)
    n = 8
    i = np.arange(-n, n + 1)
    ii, jj = np.meshgrid(i, i, indexing="ij")
    keep = (ii != 0) | (jj != 0)
    r = np.hypot(ii * length_x, jj * length_y)[keep]
    g = np.hypot(2 * np.pi * ii / length_x, 2 * np.pi * jj / length_y)[keep]
    return float(
        (erfc(alpha * r) / r).sum()
        + (2 * np.pi / area) * (erfc(g / (2 * alpha)) / g).sum()
        - 2 * alpha / np.sqrt(np.pi)
        - 2 * np.sqrt(np.pi) / (area * alpha)
    )


def count_periodic_clusters(mask: np.ndarray) -> int:
    """Number of 4-connected clusters of ``mask`` on a torus (edges wrap)."""
    labels, n = ndimage.label(mask)
    if n == 0:
        return 0
    parent = np.arange(n + 1)

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    pairs = np.concatenate(
        [
            np.stack([labels[0, :], labels[-1, :]], axis=1),
            np.stack([labels[:, 0], labels[:, -1]], axis=1),
        ]
    )
    pairs = pairs[(pairs[:, 0] > 0) & (pairs[:, 1] > 0)]
    for a, b in np.unique(pairs, axis=0):
        ra, rb = find(int(a)), find(int(b))
        if ra != rb:
            parent[ra] = rb
    return len({find(k) for k in range(1, n + 1)})


def merge_humidity_grids(per_rh, zmax, names, unit, onto=None):
    """Curves of several humidities, each on its own grid, on the union of the grids.

    ``per_rh``: (distances, {name: values}) per humidity, in units of ``unit`` [m]. Between a
    humidity's own points its values are linearly interpolated (Eq. 13 on the piecewise-linear
    curve, the pull-off and d_eq are unchanged by that); below its first point they are NaN,
    above its last (beyond max z + h_water, or where the neck let go) the state is dry (zero,
    and ``max_interference`` = max z - d); ``solved`` marks the computed points. Returns the
    union [m] and arrays (n_rh, n_union); ``onto`` (same unit): report on that grid instead of
    the union. Used by both boundary-element models."""
    union = np.unique(np.concatenate([dd for dd, _ in per_rh])) if onto is None else np.asarray(onto)
    out = {k: np.full((len(per_rh), union.size), np.nan) for k in names}
    for i, (dd, v) in enumerate(per_rh):
        if dd.size == 0:  # nothing solved at this humidity (every BEM state stalled): NaN
            if "solved" in out:
                out["solved"][i] = 0.0
            continue
        inside = (union >= dd[0]) & (union <= dd[-1])
        above = union > dd[-1]
        for k in names:
            if k == "solved":
                out[k][i] = np.isin(union, dd).astype(float)
                continue
            out[k][i, inside] = np.interp(union[inside], dd, v[k])
            out[k][i, above] = (zmax - union[above]) * unit if k == "max_interference" else 0.0
    return union * unit, out
