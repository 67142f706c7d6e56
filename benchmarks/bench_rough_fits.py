"""Eq. 21 fits of the fast path against the literal reference on steep measured maps (issue 12).

Where asperities are steep and a few pixels wide, many cut by the edge of a measured map, the cost
of Eq. 21 has several local minima and two optimisers from the same starts can end in different
ones. Per asperity (the reference's footprints, every one of 3 pixels or more) this compares the
Eq. 23 residual E of the fast fit (:func:`roughstick.contact.modified_dmt._fit.fit_footprint`) with the
reference's (``fit_asperity`` of tests/contact/modified_dmt/eq21_reference.py, scipy least_squares):
'worse' counts the asperities where the fast E exceeds the reference's by more than
1e-9 E + 1e-9 a_f (the tolerance of tests/contact/test_rough_reference.py), 'better' the converse.

The maps: Gaussian-filtered white noise (rms 4 nm, 5 nm pixels) with a correlation length of
1.2-4 pixels, periodic or measured (cut by the edges), 10-14 levels from the top down 8-9 nm.
The five surface families are in bench_rough_contact.py (part 3) and in the slow test
``pytest -m slow -k families_sweep``. Takes a few minutes (the reference is slow):

    nice -n 10 python benchmarks/bench_rough_fits.py
"""

from __future__ import annotations

import math
import pathlib
import sys
import warnings

import numpy as np
from scipy import ndimage

from roughstick.contact.modified_dmt._controller import prepare_heights
from roughstick.contact.modified_dmt._fit import fit_footprint

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests" / "contact" / "modified_dmt"))
from eq21_reference import fit_asperity, footprints  # noqa: E402  (a test oracle)

DX = 5e-9
FIT_RTOL, FIT_ATOL = 1e-9, 1e-9


def field(shape, sigma_px, seed, wrap):
    rng = np.random.default_rng(seed)
    z = ndimage.gaussian_filter(rng.standard_normal(shape), sigma_px, mode="wrap" if wrap else "reflect")
    return z / z.std() * 4e-9


def below_top(z, first, last, n):
    """n levels from ``first`` to ``last`` [m] below the highest point of the centred map."""
    top = float((z - z.mean()).max())
    return np.linspace(top - first, top - last, n)


def maps(name):
    """(z, levels, periodic, connectivity) of each map of a set."""
    if name == "2 px":
        for wrap in (False, True):
            for seed in range(6):
                z = field((48, 56), 2, seed, wrap)
                yield z, below_top(z, 0.2e-9, 8e-9, 10), wrap, 4
        for conn in (4, 8):
            z = field((37, 52), 4, 2, False)
            yield z, below_top(z, -2e-9, 8e-9, 14), False, conn
    elif name == "1.5-3 px":
        for sigma in (1.5, 2.0, 3.0):
            for seed in range(6, 18):
                z = field((48, 56), sigma, seed, seed % 2 == 0)
                yield z, below_top(z, 0.2e-9, 8e-9, 10), seed % 2 == 0, 4
    elif name == "1.2-4 px":
        for sigma in (1.2, 2.5, 4.0):
            for seed in range(20, 30):
                z = field((40, 47), sigma, seed, seed % 3 == 0)
                yield z, below_top(z, 0.1e-9, 8e-9, 12), seed % 3 == 0, 4
    elif name == "1.5-3 px, 4/8-conn.":
        for sigma in (1.5, 2.0, 3.0):
            for seed in range(40, 52):
                z = field((44, 51), sigma, seed, seed % 4 == 0)
                yield z, below_top(z, 0.15e-9, 9e-9, 11), seed % 4 == 0, 8 if seed % 3 == 0 else 4
    elif name == "1.3-2.5 px, 4/8-conn.":
        for sigma in (1.3, 1.8, 2.5):
            for seed in range(60, 72):
                z = field((50, 43), sigma, seed, seed % 4 == 1)
                yield z, below_top(z, 0.12e-9, 8.5e-9, 11), seed % 4 == 1, 8 if seed % 3 == 1 else 4


def compare(name):
    worse = better = total = 0
    excess = []
    for z, levels, periodic, conn in maps(name):
        zc, _ = prepare_heights(z)
        for d in levels:
            for x, y, h in footprints(zc, d, dx=DX, dy=DX, periodic=periodic, connectivity=conn):
                if x.size < 3:
                    continue
                area = x.size * DX * DX
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # scipy's LinAlgWarning on singular paraboloids
                    _, e_ref = fit_asperity(x, y, h, d, area, DX, DX)
                _, e_fast = fit_footprint(x, y, h, d, DX, DX)
                tol = FIT_RTOL * e_ref + FIT_ATOL * math.sqrt(area / math.pi)
                total += 1
                if e_fast > e_ref + tol:
                    worse += 1
                    excess.append((x.size, e_fast / e_ref - 1))
                better += e_ref > e_fast + tol
    detail = ", ".join(f"{n} px +{100 * e:.1f} %" for n, e in excess)
    print(f"{name:22s} asperities {total:5d}  fast worse {worse:2d}{' (' + detail + ')' if detail else ''}  "
          f"fast better {better:3d}", flush=True)


if __name__ == "__main__":
    print("Eq. 21 fits, fast path vs the literal reference, per asperity of 3 pixels or more")
    for name in ("2 px", "1.5-3 px", "1.2-4 px", "1.5-3 px, 4/8-conn.", "1.3-2.5 px, 4/8-conn."):
        compare(name)
