"""Speed against error of the FFT-BEM automatic grid's extra bisection rounds around the pull-off
(docs/fft_bem.md, automatic grid step 4).

    nice -n 5 python benchmarks/fft_bem_pull_off_grid.py [SIZE] [SEED]

For one map of S1, S2, Table 4 and the smooth family (SIZE² pixels at 5 nm, default 64, seed 2)
and five humidities from 1e-4 to 0.5: the default call ``rough_contact_curves(h, model="fft_bem")``
with the extra rounds (``new``) and without them (``old``: ``EXTRA_PULL_OFF_ROUNDS = 0``, the
grid before session 10). Reference for the pull-off, per humidity: the same retraction on the
old automatic grid plus 200 uniform points across the four intervals around its most tensile
point (an independent, locally dense grid). Prints the largest |error| of the pull-off of each
grid against it (and the signed error per humidity), the largest change of Γ new/old, and the wall time of the default call (min of
2), new/old and in units of one 1024² iFFT.
"""

import sys
import warnings

import numpy as np
from _yardstick import best_of, ifft_seconds

import roughstick as rs
from roughstick.contact.fft_bem import _kernels as _fft_bem_kernels

HUMIDITIES = [1e-4, 1e-3, 1e-2, 0.1, 0.5]
FAMILIES = ["S1", "S2", "table4", "smooth"]


def default_call(h, extra):
    _fft_bem_kernels.EXTRA_PULL_OFF_ROUNDS = extra
    curves, best = best_of(lambda: rs.contact.curves(h, relative_humidity=HUMIDITIES,
                                                           model="fft_bem"))
    return curves, rs.contact.summary(curves), best


def dense_pull_off(h, curves, i, rh):
    """Pull-off of the retraction on humidity i's own grid plus 200 points around its peak."""
    solved = curves.solved.values[i] > 0
    d, p = curves.distance.values[solved], curves.pressure.values[i][solved]
    j = int(np.argmin(p))
    local = np.linspace(d[max(j - 2, 0)], d[min(j + 2, d.size - 1)], 200)
    ref = rs.contact.fft_bem_curves(h, relative_humidity=rh, distance=np.union1d(d, local))
    return float(rs.contact.summary(ref).pull_off_pressure)


def main(size=64, seed=2):
    warnings.simplefilter("ignore", rs.ValidityWarning)
    default = _fft_bem_kernels.EXTRA_PULL_OFF_ROUNDS
    unit = ifft_seconds()
    print(f"{size}² maps, seed {seed}, RH {HUMIDITIES}; pull-off error against a locally dense retraction")
    for fam in FAMILIES:
        h = rs.datasets.surface_family(fam, shape=(size, size), seed=seed)
        c_old, s_old, t_old = default_call(h, 0)
        _, s_new, t_new = default_call(h, default)
        ref = np.array([dense_pull_off(h, c_old, i, rh) for i, rh in enumerate(HUMIDITIES)])
        err_old = s_old.pull_off_pressure.values / ref - 1
        err_new = s_new.pull_off_pressure.values / ref - 1
        e_old, e_new = np.max(np.abs(err_old)), np.max(np.abs(err_new))
        dg = np.max(np.abs(s_new.adhesive_energy.values / s_old.adhesive_energy.values - 1))
        print(f"{fam:7s} pull-off error old {e_old:6.2%} new {e_new:6.2%} | Γ new/old within {dg:.2%} | "
              f"default call old {t_old:.2f} s, new {t_new:.2f} s ({t_new / t_old:.2f} x; "
              f"{t_new / unit:.0f} x one 1024^2 iFFT)", flush=True)
        print("        per RH, old: " + " ".join(f"{e:+.2%}" for e in err_old)
              + "; new: " + " ".join(f"{e:+.2%}" for e in err_new), flush=True)
    _fft_bem_kernels.EXTRA_PULL_OFF_ROUNDS = default


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
