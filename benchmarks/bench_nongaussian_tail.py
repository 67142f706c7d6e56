"""Small probabilities on a skewed film: subset simulation on the translation-process zones
(``failure_probability(height_distribution=...)``) against crude Monte Carlo on surfaces of
``generate_surfaces`` with the same height distribution, and the Gaussian film beside it.

    python benchmarks/bench_nongaussian_tail.py [--n 12000] [--threshold 0.14]

Table 4 PSD, 32 x 32 zones at 5 nm, RH 0.5, Eq. 16 (the estimator is the subject, not the
contact model), Johnson S_U with skewness 1 and kurtosis 5.
"""

from __future__ import annotations

import argparse
import time
import warnings

from scipy import stats

import roughstick as rs
from roughstick.reliability import _surface as _s


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=12000, help="crude Monte Carlo surfaces per film")
    ap.add_argument("--threshold", type=float, default=0.14, help="Γ threshold [J/m²]")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    psd, shape, spacing, rh = rs.datasets.family_psd("table4"), (32, 32), 5e-9, 0.5
    hw = float(rs.contact.water_height(rh).values)
    skewed = rs.surface.height_distribution(skewness=1.0, kurtosis=5.0)
    print(f"Table 4 PSD, {shape[0]} x {shape[1]} zones at 5 nm, RH {rh}, Eq. 16, threshold "
          f"{args.threshold} J/m²; crude n = {args.n}; subset n_per_level = 500")
    print(f"{'film':10s} {'crude P':>9s} {'95 % interval':>22s} {'subset P':>9s} {'95 % interval':>22s} "
          f"{'evals':>6s} {'crude s':>8s} {'subset s':>8s}")
    for name, dist in (("gaussian", None), ("S=1, K=5", skewed)):
        f = _s.NoiseToSurface(psd, shape=shape, spacing=spacing, height_distribution=dist)
        response = _s.SurfaceResponse(f, relative_humidity=rh, water_height=hw)
        t = time.perf_counter()
        maps = rs.generate_surfaces(psd, n=args.n, shape=shape, spacing=spacing, seed=5,
                                    height_distribution=dist).values
        k = int(sum(response.map_response(z, periodic=True) > args.threshold for z in maps))
        crude_s = time.perf_counter() - t
        ci = stats.binomtest(k, args.n).proportion_ci(0.95)
        t = time.perf_counter()
        ds = rs.reliability.failure_probability(
            psd, threshold=args.threshold, relative_humidity=rh, shape=shape, spacing=spacing,
            model="modified_dmt", height_distribution=dist, n_per_level=500, seed=1, check_failures=0)
        sub_s = time.perf_counter() - t
        print(f"{name:10s} {k / args.n:9.2e} [{ci.low:9.2e}, {ci.high:9.2e}] "
              f"{float(ds.failure_probability):9.2e} [{float(ds.failure_probability_lower):9.2e}, "
              f"{float(ds.failure_probability_upper):9.2e}] {int(ds.n_evaluations):6d} "
              f"{crude_s:8.1f} {sub_s:8.1f}")


if __name__ == "__main__":
    main()
