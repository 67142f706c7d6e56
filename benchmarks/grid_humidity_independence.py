"""Γ of one humidity alone and within other humidity sets, on the modified DMT's automatic grid.

    python benchmarks/grid_humidity_independence.py S1,S2,table4,smooth,rough 128

prints, per family, map and RH, the spread max/min - 1 of Γ(RH) over the call alone and in 5 sets
(docs/rough_contact.md, item 5 of the automatic grid).

    python benchmarks/grid_humidity_independence.py cost

times the default call (6 RH) on the 1024² samples S1A and S2A with and without the per-humidity
Γ refinement, interleaved, min of 5, against one 1024² complex inverse FFT in the same process.
"""

import sys
import time
import warnings

import numpy as np

import roughstick as rs

SETS = [[0.1, 0.5, 0.9], [0.3, 0.5, 0.7], [0.2, 0.4, 0.6, 0.8], [0.05, 0.5, 0.95], [0.5, 0.65, 0.66]]
HUMIDITIES = [0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.65, 0.66, 0.7, 0.8, 0.9, 0.95]


def gamma(curves):
    return rs.contact.summary(curves).adhesive_energy.values


def main(families, n):
    warnings.simplefilter("ignore")
    for fam in families:
        for seed in (1, 2):
            h = rs.datasets.surface_family(fam, shape=(n, n), seed=seed)
            worst = 0.0
            for r in HUMIDITIES:
                alone = gamma(rs.contact.curves(h, relative_humidity=[r], check_validity=False))[0]
                vals = [alone]
                for s in SETS:
                    ss = sorted(set(s) | {r})
                    c = rs.contact.curves(h, relative_humidity=ss, check_validity=False)
                    vals.append(gamma(c)[ss.index(r)])
                spread = max(vals) / min(vals) - 1
                worst = max(worst, spread)
                print(f"{fam} seed{seed} rh={r}: alone {alone:.5g} spread {spread:.3%}", flush=True)
            print(f"== {fam} seed{seed} worst spread {worst:.3%}", flush=True)


def cost():
    from roughstick.contact.modified_dmt import _grid as rough

    warnings.simplefilter("ignore")
    rh = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]
    rng = np.random.default_rng(0)
    spec = rng.normal(size=(1024, 1024)) + 1j * rng.normal(size=(1024, 1024))
    for name in ("S1A", "S2A"):
        h = rs.io.read_afm(f"data_samples/{name}.nc").load()
        rs.contact.curves(h.isel(x=slice(0, 64), y=slice(0, 64)), relative_humidity=rh,
                                check_validity=False)  # compile
        times, points, ffts = {0: [], rough._MAX_ROUNDS: []}, {}, []
        for _ in range(5):
            for rounds in list(times):
                saved, rough._MAX_ROUNDS = rough._MAX_ROUNDS, rounds
                t = time.perf_counter()
                c = rs.contact.curves(h, relative_humidity=rh, check_validity=False)
                times[rounds].append(time.perf_counter() - t)
                rough._MAX_ROUNDS = saved
                points[rounds] = c.sizes["distance"]
                t = time.perf_counter()
                np.fft.ifft2(spec)
                ffts.append(time.perf_counter() - t)
        f = min(ffts)
        print(f"{name}: one FFT {f * 1e3:.1f} ms; " + "; ".join(
            f"{'controller only' if r == 0 else 'with Γ refinement'}: {points[r]} levels, "
            f"{min(v):.3f} s = {min(v) / f:.1f} x FFT" for r, v in times.items()))


if __name__ == "__main__" and sys.argv[1:2] == ["cost"]:
    cost()
elif __name__ == "__main__":
    main(sys.argv[1].split(",") if len(sys.argv) > 1 else ["S1", "S2", "table4", "smooth", "rough"],
         int(sys.argv[2]) if len(sys.argv) > 2 else 128)
