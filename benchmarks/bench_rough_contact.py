"""Speed and accuracy of the rough-surface modified DMT kernel (issue 12; not run by pytest).

Everything is a ratio to one 1024 x 1024 complex inverse FFT (numpy) timed interleaved in the
same run (min of several repeats; CPU time of this process, so other jobs on a shared machine
count less). Prints:

1. per surface (data_samples S1A and S2A, a Table-4 surface, the smooth and the rough self-affine
   families; 1024^2 at 5 nm, six RH): the public default call ``rs.contact.curves(h, relative_humidity=RH)``, the kernel's
   default call (automatic one-pass grid) and the same levels as an explicit grid, the number of levels and of sphere fits, and the contact fraction
   at the lowest level;
2. accuracy of the automatic grid: Gamma (Eq. 13), pull-off and d_eq against the same grid with
   every interval split in four (max over the six RH); 1b: the public default call's time and
   the error of its Gamma and pull-off against 8000 uniform distances;
3. the fast path against the literal reference (scipy relabel + least_squares per asperity) on
   256^2 crops, at 8 levels of the automatic grid: max relative pressure difference, and per
   asperity how many fast fits have a larger Eq. 23 residual than the reference's (and smaller);
4. time versus map size (256^2 .. 4096^2) and versus the contact fraction at the floor of an
   explicit grid (to show what the cost grows with);
5. one interaction zone of the paper's cantilever (524 x 6000 pixels, Table 4 PSD).

    nice -n 10 python benchmarks/bench_rough_contact.py [--quick] [--part 1]
"""

# ruff: noqa: B023  (lambdas are called at once, inside their loop iteration)
from __future__ import annotations

import argparse
import pathlib
import sys
import time
import warnings

import numpy as np
import xarray as xr

import roughstick as rs
from roughstick.contact.adhesion import summary_kernel as _summary_kernel
from roughstick.contact.modified_dmt import _controller as rk
from roughstick.contact.modified_dmt._fit import fit_footprint

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests" / "contact" / "modified_dmt"))
from eq21_reference import fit_asperity, footprints, reference_curves  # noqa: E402  (a test oracle)

DATA = pathlib.Path(__file__).resolve().parents[1] / "data_samples"


def family_surface(name, *, shape, seed):
    """The issue's families (5 nm pixels, periodic): PSDs of the S1/S2 samples, the paper's
    Table 4 (Eq. 37), a smooth (rms 2 nm, Hurst 0.8, roll-off 2e7 rad/m) and a rough (rms 8 nm,
    Hurst 0.5, roll-off 5e7 rad/m) self-affine one; cut at 2.89e8 rad/m."""
    if name in ("S1", "S2"):
        a = xr.open_dataset(DATA / f"{name}A.nc").attrs
        p = dict(s0=a["psd_s0"], s1=a["psd_s1"], q0=a["psd_q0"], qmax=a["psd_qmax"])
    elif name == "table4":
        c = rs.stiction.cantilever_psd()
        p = dict(s0=float(c.s0), s1=float(c.s1), q0=float(c.q0), qmax=float(c.qmax))
    else:
        rms, hurst, q0, qmax = (2e-9, 0.8, 2e7, 289e6) if name == "smooth" else (8e-9, 0.5, 5e7, 289e6)
        ratio = (qmax / q0) ** (-2.0 * (1.0 + hurst))
        s0 = rms**2 / float(rs.surface.self_affine_moments(s0=1.0, s1=ratio, q0=q0, qmax=qmax).m0)
        p = dict(s0=s0, s1=s0 * ratio, q0=q0, qmax=qmax)
    ens = rs.surface.generate_surfaces(lambda q: rs.surface.self_affine_psd(q, **p), n=1, shape=shape,
                               spacing=5e-9, seed=seed)
    return ens.isel(realization=0).compute()

RH = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]
HW = rs.contact.water_height(RH).values
DP = rs.contact.laplace_pressure(RH).values
K = rs.materials.hertz_modulus()
SPEC = np.fft.fft2(np.random.default_rng(0).standard_normal((1024, 1024)))


def cpu(fn):
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def ratio(fn, reps=5):
    """(min kernel time, min FFT time), interleaved."""
    tk, tf = [], []
    out = None
    for _ in range(reps):
        tf.append(cpu(lambda: np.fft.ifft2(SPEC))[0])
        t, out = cpu(fn)
        tk.append(t)
    return min(tk), min(tf), out


def surface(name, shape=(1024, 1024), seed=1):
    if name in ("S1A", "S2A"):
        h = rs.io.read_afm(DATA / f"{name}.nc")
        return h.isel(y=slice(0, shape[0]), x=slice(0, shape[1])).load()
    if name == "Table 4":
        name = "table4"
    return family_surface(name, shape=shape, seed=seed)


def kw(h):
    return dict(dx=float(h.x[1] - h.x[0]), dy=float(h.y[1] - h.y[0]), K=K,
                periodic=bool(h.attrs.get("periodic", 0)), connectivity=4)


def refine4(d):
    parts = [d[:1]]
    for a, b in zip(d[:-1], d[1:]):
        parts.append(a + (b - a) * np.array([0.25, 0.5, 0.75, 1.0]))
    return np.concatenate(parts)


FIT_RTOL, FIT_ATOL = 1e-9, 1e-9  # as tests/contact/test_rough_reference.py (why: there)


def per_asperity(z, levels, k):
    """Fast and reference fits of every asperity (reference footprints) at the levels: counts of
    fast worse / fast better beyond the tolerance, the total, and the largest relative excess."""
    zc, _ = rk.prepare_heights(z)
    worse = better = total = 0
    excess = 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for level in levels:
            for x, y, hz in footprints(zc, level, dx=k["dx"], dy=k["dy"], periodic=k["periodic"],
                                       connectivity=k["connectivity"]):
                area = x.size * k["dx"] * k["dy"]
                _, e_ref = fit_asperity(x, y, hz, level, area, k["dx"], k["dy"])
                _, e_fast = fit_footprint(x, y, hz, level, k["dx"], k["dy"])
                tol = FIT_RTOL * e_ref + FIT_ATOL * np.sqrt(area / np.pi)
                total += 1
                worse += e_fast > e_ref + tol
                better += e_ref > e_fast + tol
                if e_fast > e_ref + tol:
                    excess = max(excess, e_fast / e_ref - 1)
    return worse, better, total, excess


def fast_vs_reference():
    """Part 3 (alone: python -c "import bench_rough_contact as b; b.fast_vs_reference()" in benchmarks/)."""
    print("\n3. fast path vs the literal reference (256^2 crops, 8 levels of the automatic grid, six RH); per "
          "asperity (same footprint) the Eq. 23 residual E of both fits: 'worse' counts the asperities where the "
          f"fast one exceeds the reference's by more than {FIT_RTOL:g} E + {FIT_ATOL:g} a_f, 'better' the converse")
    for name in ("S1A", "S2A", "Table 4", "smooth", "rough"):
        h = surface(name, (256, 256))
        z = h.values
        d, o = rk.curves(z, HW, DP, **kw(h))
        cross = np.flatnonzero(o[4][0] > 0)
        pick = d[cross[np.linspace(0, cross.size - 1, 8).astype(int)]] if cross.size else d[:8]
        fast = rk.curves_kernel(z, pick, HW, DP, **kw(h))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t_ref, ref = cpu(lambda: reference_curves(z, pick, HW, DP, **kw(h)))
        t_fast, _ = cpu(lambda: rk.curves_kernel(z, pick, HW, DP, **kw(h)))
        big = np.abs(ref[0]) > 1e-3 * np.abs(ref[0]).max()
        rel = np.max(np.abs(fast[0] - ref[0])[big] / np.abs(ref[0])[big], initial=0.0)
        worse, better, total, excess = per_asperity(z, pick, kw(h))
        print(f"{name:9s} max rel. pressure diff {rel:.1e}; asperities {total:4d}, fast worse {worse} (largest "
              f"excess {excess:.1e} relative), fast better {better}; reference {t_ref:.1f} s, fast "
              f"{t_fast * 1e3:.1f} ms ({t_ref / max(t_fast, 1e-9):.0f}x)")


def public_grid_error(public, n_fine=8000):
    """Part 1b: the public default call (its grid refined per humidity): time, levels, and the
    grid error of its Gamma (Eq. 13) and pull-off against ``n_fine`` uniform distances over its
    range and its own (max over the six RH, relative)."""
    print(f"\n1b. public default call rs.contact.curves(h, relative_humidity=RH, model='modified_dmt'), "
          f"1024^2, six RH: time (x one FFT in the same run) and its grid error against {n_fine} uniform "
          "distances over the same range plus its own (max over RH; Gamma, pull-off)")
    print(f"{'surface':9s} {'time':>10s} {'x FFT':>7s} {'levels':>6s} {'Gamma err':>10s} {'pull-off err':>12s}")
    for name, h, tp, fp, c in public:
        d = c.distance.values
        g, pull, _, _, _ = _summary_kernel(c.pressure.values, c.wet_fraction.values, d)
        # the grid's own levels too: the reference has every point the grid has (a uniform grid
        # alone misses the wetting events the grid snaps its pull-off to)
        fine = np.union1d(np.linspace(d.min(), d.max(), n_fine), d)
        pf, _, wf, *_ = rk.curves_kernel(h.values, fine, HW, DP, **kw(h))
        gf, pullf, _, _, _ = _summary_kernel(pf, wf, fine)
        with np.errstate(invalid="ignore", divide="ignore"):
            eg = np.nanmax(np.abs(g / gf - 1))
            ep = np.nanmax(np.abs(pull / pullf - 1))
        print(f"{name:9s} {tp * 1e3:7.1f} ms {tp / fp:6.1f}x {d.size:6d} {eg:10.2%} {ep:12.2%}", flush=True)


def main(quick=False, part=None):
    # the validity check still runs inside the public call (its cost is timed); its warning is
    # not printed
    warnings.simplefilter("ignore", rs.ValidityWarning)
    reps = 3 if quick else 5
    rk.curves(np.random.default_rng(0).normal(size=(16, 16)) * 1e-9, HW, DP, dx=5e-9, dy=5e-9, K=K,
              periodic=True, connectivity=4)  # compile
    tf0 = min(cpu(lambda: np.fft.ifft2(SPEC))[0] for _ in range(5))
    print(f"one 1024^2 complex inverse FFT (numpy): {tf0 * 1e3:.1f} ms CPU")
    print("\n1-2. 1024^2 at 5 nm, six RH (30-90 %): default call (automatic grid) and the same levels as an "
          "explicit grid; x = multiples of one FFT in the same run")
    print(f"{'surface':9s} {'public default':>16s} {'kernel default':>16s} {'explicit':>16s} {'levels':>6s} {'fits':>7s} {'c.f.':>6s} | "
          f"4x-finer grid: {'Gamma':>7s} {'pull-off':>8s} {'d_eq':>7s} (RH of the worst pull-off)")
    public = []
    for name in ("S1A", "S2A", "Table 4", "smooth", "rough"):
        h = surface(name)
        z = h.values
        t, f, (d, o) = ratio(lambda: rk.curves(z, HW, DP, **kw(h)), reps)
        te, fe, _ = ratio(lambda: rk.curves(z, HW, DP, distance=d, **kw(h)), reps)
        tp, fp, c = ratio(lambda: rs.contact.curves(h, relative_humidity=RH, model="modified_dmt"), reps)
        public.append((name, h, tp, fp, c))
        g, pull, deq, _, _ = _summary_kernel(o[0], o[2], d)
        d4 = refine4(d)
        _, o4 = rk.curves(z, HW, DP, distance=d4, **kw(h))
        g4, pull4, deq4, _, _ = _summary_kernel(o4[0], o4[2], d4)
        sig = float(np.nanstd(z))
        with np.errstate(invalid="ignore", divide="ignore"):
            eg = np.nanmax(np.abs(g / g4 - 1))
            ep = np.nanmax(np.abs(pull / pull4 - 1))
        ed = np.nanmax(np.abs(deq - deq4) / np.maximum(np.abs(deq4), sig))
        print(f"{name:9s} {tp * 1e3:7.1f} ms {tp / fp:5.1f}x {t * 1e3:7.1f} ms {t / f:5.1f}x "
              f"{te * 1e3:7.1f} ms {te / fe:5.1f}x {d.size:6d} "
              f"{int(o[4][0].sum()):7d} {o[3][0, 0]:6.3f} | {'':14s} {eg:7.1e} {ep:8.1e} {ed:7.1e} "
              f"({RH[int(np.nanargmax(np.abs(pull / pull4 - 1)))]:.1f})")

    public_grid_error(public)
    if part == "1":
        return

    fast_vs_reference()

    print("\n4a. time of the default call versus map size (x one 1024^2 FFT)")
    sizes = (256, 512, 1024, 2048) if quick else (256, 512, 1024, 2048, 4096)
    print(f"{'family':8s} {'size':>6s} {'time':>10s} {'x FFT':>7s} {'tail px':>9s} {'levels':>6s} {'fits':>8s}")
    for name in ("S2", "smooth"):
        for n in sizes:
            h = surface(name, (n, n))
            z = h.values
            t, f, (d, o) = ratio(lambda: rk.curves(z, HW, DP, **kw(h)), 1 if n >= 2048 else reps)
            zc = z - np.nanmean(z)
            print(f"{name:8s} {n:6d} {t * 1e3:8.1f}ms {t / f:7.1f} {int((zc >= d.min()).sum()):9d} {d.size:6d} "
                  f"{int(o[4][0].sum()):8d}")

    print("\n4b. explicit uniform grid of 100 levels on the smooth family (1024^2), floor at a given contact "
          "fraction: time versus contacting pixels")
    h = surface("smooth")
    z = h.values
    zc = z - z.mean()
    top = zc.max() + HW.max()
    for q in (0.995, 0.99, 0.98, 0.95, 0.90):
        floor = np.quantile(zc, q)
        d = np.linspace(floor, top, 100)
        t, f, o = ratio(lambda: rk.curves_kernel(z, d, HW, DP, **kw(h)), 3)
        print(f"footprint fraction at the floor {1 - q:5.3f}: {t * 1e3:8.1f} ms = {t / f:6.1f}x FFT; "
              f"sum of footprint pixels over the levels {int(sum((zc >= x).sum() for x in d)):9d}")

    print("\n5. one interaction zone of the paper's cantilever: 524 x 6000 pixels at 5 nm, Table 4 PSD")
    h = family_surface("table4", shape=(524, 6000), seed=1)
    z = h.values
    t, f, (d, o) = ratio(lambda: rk.curves(z, HW, DP, **kw(h)), 3)
    print(f"default call: {t:.3f} s CPU = {t / f:.1f}x FFT, {d.size} levels, {int(o[4][0].sum())} fits")


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--part", choices=["1"], help="1: parts 1 and 1b only (the 1024^2 maps)")
    args = ap.parse_args()
    main(args.quick, args.part)
