"""Speed against error of confirming a neck break on the FFT-BEM automatic grid (docs/fft_bem.md,
automatic grid step 2: a retraction step that loses the last hard contact is retried with half
the step, up to ``BREAK_HALVINGS`` times, before the neck counts as broken).

    nice -n 5 python benchmarks/fft_bem_neck_break.py [SIZE] [SEED]

For one map of S1, S2, Table 4 and the smooth family (SIZE² pixels at 5 nm, default 64, seed 0)
and five humidities from 1e-4 to 0.9: the default call ``rough_contact_curves(h, model="fft_bem")``
with the confirmation (``new``) and without it (``old``: ``BREAK_HALVINGS = 0``, the grid before
session 12). Reference for Γ, per humidity: the same solver marched along a fine uniform grid,
1,600 points from the bottom of the new automatic grid to max z + max(6 h_water, 1.5 x its top
above max z) (small steps cannot jump off the attached branch). Prints Γ/Γ_ref - 1 of both
grids, the states solved and the wall time of the default call (min of 2), new/old and in units
of one 1024² iFFT; ``benchmarks/untuned_surfaces.py`` makes the same check on random maps at
RH 1e-3.
"""

import sys
import warnings

import numpy as np
from _yardstick import best_of, ifft_seconds

import roughstick as rs
from roughstick.contact.fft_bem import _kernels as _fft_bem_kernels

HUMIDITIES = [1e-4, 1e-3, 0.05, 0.5, 0.9]
FAMILIES = ["S1", "S2", "table4", "smooth"]


def default_call(h, halvings):
    """Curves, summary and best time of 2 of the default call with ``halvings`` confirmations."""
    _fft_bem_kernels.BREAK_HALVINGS = halvings
    curves, best = best_of(lambda: rs.contact.curves(h, relative_humidity=HUMIDITIES,
                                                           model="fft_bem"))
    return curves, rs.contact.summary(curves), best


def fine_gamma(h, curves, i, rh):
    """Γ of the retraction along a fine uniform grid spanning humidity i's automatic grid."""
    d = curves.distance.values[curves.solved.values[i] > 0]
    zmax, hw = float(h.max()), float(rs.contact.water_height(rh))
    fine = np.linspace(d[0], zmax + max(6 * hw, 1.5 * (d[-1] - zmax)), 1600)
    ref = rs.contact.fft_bem_curves(h, relative_humidity=rh, distance=fine)
    return float(rs.contact.summary(ref).adhesive_energy)


def main(size=64, seed=0):
    warnings.simplefilter("ignore", rs.ValidityWarning)
    default = _fft_bem_kernels.BREAK_HALVINGS
    unit = ifft_seconds()
    print(f"{size}² maps, seed {seed}, RH {HUMIDITIES}; Γ against a fine uniform retraction")
    worst = {"old": 0.0, "new": 0.0}
    for fam in FAMILIES:
        h = rs.datasets.surface_family(fam, shape=(size, size), seed=seed)
        c_old, s_old, t_old = default_call(h, 0)
        c_new, s_new, t_new = default_call(h, default)
        ref = np.array([fine_gamma(h, c_new, i, rh) for i, rh in enumerate(HUMIDITIES)])
        e_old = s_old.adhesive_energy.values / ref - 1
        e_new = s_new.adhesive_energy.values / ref - 1
        worst["old"] = max(worst["old"], float(np.max(np.abs(e_old))))
        worst["new"] = max(worst["new"], float(np.max(np.abs(e_new))))
        n_old, n_new = int(c_old.solved.sum()), int(c_new.solved.sum())
        print(f"{fam:7s} Γ/Γ_ref - 1 per RH: old {np.array2string(e_old, precision=4)} "
              f"new {np.array2string(e_new, precision=4)} | states {n_old} -> {n_new} | "
              f"time {t_old:.2f} -> {t_new:.2f} s ({t_new / t_old:.2f} x; {t_new / unit:.0f} iFFT)",
              flush=True)
    print(f"largest |Γ/Γ_ref - 1|: old {worst['old']:.4f}, new {worst['new']:.4f}")
    _fft_bem_kernels.BREAK_HALVINGS = default


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
