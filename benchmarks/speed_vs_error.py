"""Speed against error: GW (Eq. 14) and modified DMT (Eq. 16) against the boundary-element reference.

Regenerates the tables of docs/accuracy.md (docs/accuracy_tables.md), the figure
docs/accuracy_speed_vs_error.png and, with ``--validity``, a modulus sweep in
benchmarks/validity_results/speed_vs_error_sweep.csv (the shipped validity map is written by
``benchmarks/bench_accuracy.py report``).

    python benchmarks/speed_vs_error.py                 # S1/S2-like 256² comparison + figure
    python benchmarks/speed_vs_error.py --validity      # + modulus sweep -> validity_results/
    python benchmarks/speed_vs_error.py --reuse-bem     # reuse cached BEM curves (timings too)

Surfaces: one periodic Gaussian surface per sample, drawn with ``roughstick.surface.generate_surfaces``
from the Eq. 37 PSD stored in data_samples/S1A.nc and S2A.nc (the Table 3 moments), 5 nm pixels,
so that GW, modified DMT and BEM see exactly the same periodic geometry. All three use the same
distance grid per humidity; summaries (Eq. 13 energy, pull-off, equilibrium distance) come from
``roughstick.adhesion_summary``. Errors are relative to the BEM. Times are wall-clock seconds per
curve (one surface, one humidity) measured in this run; the BEM runs on one core (Tamaas is
serial). The machine is shared, so times carry maybe +-30 % noise.
"""

from __future__ import annotations

import argparse
import csv
import datetime as dt
import os
import pathlib
import platform
import sys
import time

import numpy as np
import xarray as xr

import roughstick as rs

ROOT = pathlib.Path(__file__).resolve().parents[1]
SPACING = 5e-9
SEED = 2026


def sample_psd(name):
    p = rs.datasets.family_parameters(name)  # the Eq. 37 PSD the bundled samples were drawn from

    def psd(q):
        return rs.surface.self_affine_psd(q.ravel(), **p).values.reshape(q.shape)

    return psd


def make_surface(name, n, spacing=SPACING):
    h = rs.surface.generate_surfaces(sample_psd(name), n=1, shape=n, spacing=spacing, seed=SEED)
    return h.isel(realization=0).compute()


def downsample(h, factor):
    """Block-average a periodic map by ``factor`` (coarser pixels, same size)."""
    z = h.values
    ny, nx = z.shape
    zc = z.reshape(ny // factor, factor, nx // factor, factor).mean(axis=(1, 3))
    return rs.testing.make_topography(zc, spacing=SPACING * factor, periodic=True)


def distance_grid(h, rh, n, reduced_modulus):
    """Uniform grid from first water contact down past the equilibrium distance."""
    z = h.values
    hw = float(rs.contact.water_height(rh))
    depth = (1e-9 + 0.5 * hw) * (86.6e9 / reduced_modulus) ** (2 / 3)
    bottom = max(z.max() - depth, z.mean() + 0.25 * z.std())
    return np.linspace(bottom, z.max() + hw, n)


def summary(curves):
    """Eq. 13 energy, pull-off pressure, equilibrium distance (roughstick.adhesion_summary)."""
    if "adhesion_summary" in rs.__all__:
        s = rs.contact.summary(curves[["pressure", "wet_fraction"]])
        return {
            "adhesive_energy": s["adhesive_energy"].values,
            "pull_off_pressure": s["pull_off_pressure"].values,
            "equilibrium_distance": s["equilibrium_distance"].values,
        }
    # fallback (adhesion.py not there yet): the same definitions, docs/architecture.md
    p = curves.pressure.values
    d = curves.distance.values
    gamma = -np.trapezoid(np.minimum(p, 0), d, axis=-1)
    pull = np.maximum(-p.min(axis=-1), 0)
    deq = np.full(p.shape[:-1], np.nan)
    for idx in np.ndindex(p.shape[:-1]):
        pp = p[idx]
        for k in range(len(d) - 1, 0, -1):
            if pp[k] < 0 <= pp[k - 1]:
                deq[idx] = d[k - 1] + (d[k] - d[k - 1]) * pp[k - 1] / (pp[k - 1] - pp[k])
                break
    return {"adhesive_energy": gamma, "pull_off_pressure": pull, "equilibrium_distance": deq}


def timed(fn, *args, **kwargs):
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    if hasattr(out, "compute"):
        out = out.compute()
    return out, time.perf_counter() - t0


def bem_curves(h, rh, d, material, cache, key, reuse):
    import hashlib

    grid = hashlib.sha1(np.round(np.asarray(d) * 1e15).astype(np.int64).tobytes()).hexdigest()
    path = cache / f"bem_{key}_{grid[:8]}.nc"
    if reuse and path.exists():
        ds = xr.open_dataset(path).load()
        return ds, float(ds.attrs["wall_seconds"])
    ds, sec = timed(rs.contact.bem_curves, h, relative_humidity=rh, distance=d, material=material)
    ds.attrs["wall_seconds"] = sec
    cache.mkdir(parents=True, exist_ok=True)
    ds.to_netcdf(path)
    return ds, sec


def material_for(reduced_modulus):
    if np.isclose(reduced_modulus, rs.materials.reduced_modulus(), rtol=1e-9):
        return rs.POLYSILICON
    nu = rs.POLYSILICON.poisson_ratio
    return rs.Material(
        youngs_modulus=2 * (1 - nu**2) * reduced_modulus,
        poisson_ratio=nu,
        name=f"E*={reduced_modulus / 1e9:g} GPa",
    )


def rel(a, b):
    return float(abs(a - b) / abs(b)) if np.isfinite(a) and np.isfinite(b) and b != 0 else np.nan


def compare(name, h, rh, n_dist, material, cache, reuse, *, settings=True, tag=""):
    """All methods on one (surface, RH): list of result rows."""
    E = rs.materials.reduced_modulus(material)
    d = distance_grid(h, rh, n_dist, E)
    key = f"{name}_{h.sizes['x']}_{rh:.2f}_{E / 1e9:.4g}{tag}"
    bem, t_bem = bem_curves(h, rh, d, material, cache, key, reuse)
    ref = {k: float(v.ravel()[0]) for k, v in summary(bem).items()}
    rows = [
        dict(
            method="bem",
            setting=f"{n_dist} distances",
            seconds=t_bem,
            **ref,
            bem_solves=bem.attrs.get("bem_solves"),
            bem_unconverged=bem.attrs.get("bem_unconverged"),
        )
    ]
    if settings:
        # the BEM itself at 10 nm pixels: its own discretisation error
        b10, t10 = bem_curves(downsample(h, 2), rh, d, material, cache, key + "_10nm", reuse)
        rows.append(
            dict(
                method="bem",
                setting="10 nm pixels",
                seconds=t10,
                **{k: float(v.ravel()[0]) for k, v in summary(b10).items()},
            )
        )
    runs = [("modified_dmt", f"{n_dist} distances", h, d)]
    if settings:
        for n in (10, 20, 80):
            runs.append(("modified_dmt", f"{n} distances", h, np.linspace(d[0], d[-1], n)))
        runs.append(("modified_dmt", "10 nm pixels", downsample(h, 2), d))
    for method, setting, hh, dd in runs:
        cur, sec = timed(
            rs.contact.curves, hh, relative_humidity=rh, distance=dd, material=material
        )
        rows.append(
            dict(
                method=method,
                setting=setting,
                seconds=sec,
                **{k: float(v.ravel()[0]) for k, v in summary(cur).items()},
            )
        )
    gw_cut = (None, 3.0, 4.0) if settings else (None,)
    for cut in gw_cut:
        cur, sec = timed(
            rs.contact.gw_curves,
            hh_moments(h),
            relative_humidity=rh,
            distance=d,
            height_cutoff=cut,
            material=material,
        )
        rows.append(
            dict(
                method="gw",
                setting=f"height cutoff {cut}",
                seconds=sec,
                **{k: float(v.ravel()[0]) for k, v in summary(cur).items()},
            )
        )
    for r in rows:
        r.update(sample=name, pixels=h.sizes["x"], rh=rh, reduced_modulus=E)
        # an error is only a number when both curves cross zero on the grid (else Γ is cut off
        # at the grid bottom, which sits at max z - depth or mean plane + std/2)
        r["converged"] = int(
            np.isfinite(r["equilibrium_distance"]) and np.isfinite(ref["equilibrium_distance"])
        )
        for q in ("adhesive_energy", "pull_off_pressure", "equilibrium_distance"):
            r[f"error_{q}"] = rel(r[q], ref[q])
    return rows, bem


_MOMENTS = {}


def hh_moments(h):
    k = id(h)
    if k not in _MOMENTS:
        _MOMENTS[k] = rs.surface.psd_moments(rs.surface.power_spectrum(h))
    return _MOMENTS[k]


def fmt_table(rows, cols):
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        cells = []
        for c in cols:
            v = r.get(c, "")
            if isinstance(v, float):
                if c.startswith("error"):
                    v = f"{v:.1%}" if np.isfinite(v) else "n/a"
                elif c == "seconds":
                    v = f"{v:.3g}"
                elif c == "adhesive_energy":
                    v = f"{v * 1e3:.4g} mJ/m²"
                elif c == "pull_off_pressure":
                    v = f"{v / 1e6:.4g} MPa"
                elif c == "equilibrium_distance":
                    v = f"{v * 1e9:.3f} nm"
                elif c == "reduced_modulus":
                    v = f"{v / 1e9:.3g} GPa"
                else:
                    v = f"{v:.3g}"
            cells.append(str(v))
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def regime_table(rows):
    """Worst modified-DMT Γ error over samples and sizes, per (E*, RH); † = not converged."""
    sel = [r for r in rows if r["method"] == "modified_dmt"]
    Es = sorted({r["reduced_modulus"] for r in sel}, reverse=True)
    RHs = sorted({r["rh"] for r in sel})
    out = [
        "| E* \\ RH | " + " | ".join(f"{x:.0%}" for x in RHs) + " |",
        "|" + "---|" * (len(RHs) + 1),
    ]
    for E in Es:
        cells = []
        for x in RHs:
            c = [r for r in sel if r["reduced_modulus"] == E and r["rh"] == x]
            if not c:
                cells.append("")
                continue
            worst = max(c, key=lambda r: r["error_adhesive_energy"])
            flag = "" if all(r["converged"] for r in c) else " †"
            cells.append(f"{worst['error_adhesive_energy']:.1%}{flag}")
        out.append(f"| {E / 1e9:.3g} GPa | " + " | ".join(cells) + " |")
    return "\n".join(out)


def method_table(rows):
    """Median / max Γ error and median time per method and setting (the figure's points)."""
    keys = []
    for r in rows:
        k = (r["method"], r["setting"])
        if k not in keys:
            keys.append(k)
    out = [
        "| method | setting | median error Γ | max error Γ | median error pull-off | "
        "median error d_eq | median time per curve [s] |",
        "|---|---|---|---|---|---|---|",
    ]
    for m, st in keys:
        c = [r for r in rows if (r["method"], r["setting"]) == (m, st)]
        e = [r["error_adhesive_energy"] for r in c]
        out.append(
            f"| {m} | {st} | {np.nanmedian(e):.1%} | {np.nanmax(e):.1%} | "
            f"{np.nanmedian([r['error_pull_off_pressure'] for r in c]):.1%} | "
            f"{np.nanmedian([r['error_equilibrium_distance'] for r in c]):.1%} | "
            f"{np.median([r['seconds'] for r in c]):.3g} |"
        )
    return "\n".join(out)


def figure(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    marks = {"bem": "s", "modified_dmt": "o", "gw": "^"}
    agg = {}
    for r in rows:
        if r["method"] == "bem" and r["error_adhesive_energy"] == 0:
            continue
        k = (r["method"], r["setting"])
        agg.setdefault(k, {"t": [], "e": []})
        agg[k]["t"].append(r["seconds"])
        agg[k]["e"].append(r["error_adhesive_energy"])
    for (m, s), v in agg.items():
        e = np.nanmedian(v["e"])
        t = np.median(v["t"])
        ax.loglog(max(e, 1e-4), t, marks[m], label=f"{m}: {s}")
        ax.annotate(s, (max(e, 1e-4), t), fontsize=6, xytext=(3, 3), textcoords="offset points")
    tb = np.median(
        [r["seconds"] for r in rows if r["method"] == "bem" and r["error_adhesive_energy"] == 0]
    )
    ax.axhline(tb, color="k", ls="--", lw=0.8, label=f"BEM reference ({tb:.3g} s)")
    ax.set_xlabel("median relative error of Γ vs BEM (S1/S2-like, RH 30-90 %)")
    ax.set_ylabel("time per curve [s]")
    ax.legend(fontsize=6, loc="best")
    ax.set_title("Speed against error, 256² maps at 5 nm pixels")
    fig.tight_layout()
    fig.savefig(path, dpi=130)


def main(argv=None):
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--pixels", type=int, nargs="+", default=[256])
    ap.add_argument("--rh", type=float, nargs="+", default=[0.3, 0.5, 0.7, 0.9])
    ap.add_argument("--n-distances", type=int, default=40)
    ap.add_argument("--validity", action="store_true", help="also run the modulus sweep")
    ap.add_argument("--validity-pixels", type=int, default=128)
    ap.add_argument(
        "--moduli",
        type=float,
        nargs="+",
        default=[rs.materials.reduced_modulus(), 20e9, 5e9, 1e9],
        help="contact moduli E* [Pa] of the sweep (default: poly-Si 86.58 GPa, 20, 5, 1 GPa)",
    )
    ap.add_argument("--validity-rh", type=float, nargs="+", default=[0.3, 0.7, 0.9])
    ap.add_argument("--cache", default=str(ROOT / "benchmarks" / ".cache"))
    ap.add_argument("--reuse-bem", action="store_true")
    ap.add_argument("--docs", default=str(ROOT / "docs"))
    ap.add_argument(
        "--bem-only",
        action="store_true",
        help="only compute and cache the BEM curves (then rerun with --reuse-bem)",
    )
    args = ap.parse_args(argv)
    cache = pathlib.Path(args.cache)
    if args.bem_only:
        jobs = [(name, n, rs.POLYSILICON) for n in args.pixels for name in ("S1", "S2")]
        jobs = [(nm, n, m, rh) for nm, n, m in jobs for rh in args.rh]
        if args.validity:
            jobs += [
                (nm, args.validity_pixels, material_for(E), rh)
                for nm in ("S1", "S2")
                for E in args.moduli
                for rh in args.validity_rh
            ]
        for name, n, mat, rh in jobs:
            h = make_surface(name, n)
            E = rs.materials.reduced_modulus(mat)
            key = f"{name}_{n}_{rh:.2f}_{E / 1e9:.4g}"
            ds, sec = bem_curves(
                h, rh, distance_grid(h, rh, args.n_distances, E), mat, cache, key, True
            )
            print(
                f"BEM {key}: {sec:.1f} s, {ds.attrs.get('bem_solves')} solves, "
                f"{ds.attrs.get('bem_unconverged')} unconverged",
                flush=True,
            )
        return
    cache = pathlib.Path(args.cache)
    docs = pathlib.Path(args.docs)
    started = dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    machine = (
        f"{platform.node()} {platform.processor() or platform.machine()}, {os.cpu_count()} cores"
    )

    # warm-up: numba compilation of the modified-DMT kernels is not part of a curve's cost
    warm = make_surface("S2", 32)
    rs.contact.curves(
        warm, relative_humidity=0.5, distance=distance_grid(warm, 0.5, 4, 86.6e9)
    )
    rs.contact.gw_curves(hh_moments(warm), relative_humidity=0.5, distance=[1e-9, 2e-9])
    rows = []
    for n in args.pixels:
        for name in ("S1", "S2"):
            h = make_surface(name, n)
            for rh in args.rh:
                r, _ = compare(name, h, rh, args.n_distances, rs.POLYSILICON, cache, args.reuse_bem)
                rows.extend(r)
                for x in r:
                    print(
                        f"{name} {n} RH {rh:.2f} {x['method']:13s} {x['setting']:22s} "
                        f"{x['seconds']:8.3f} s  Γ {x['adhesive_energy']:.4g}  "
                        f"err {x['error_adhesive_energy']:.3g}",
                        flush=True,
                    )

    vrows = []
    if args.validity:
        for name in ("S1", "S2"):
            h = make_surface(name, args.validity_pixels)
            for E in args.moduli:
                for rh in args.validity_rh:
                    r, _ = compare(
                        name,
                        h,
                        rh,
                        args.n_distances,
                        material_for(E),
                        cache,
                        args.reuse_bem,
                        settings=False,
                    )
                    vrows.extend(r)
                    for x in r:
                        print(
                            f"validity {name} E* {E / 1e9:g} GPa RH {rh:.2f} {x['method']:13s}"
                            f" err Γ {x['error_adhesive_energy']:.3g}",
                            flush=True,
                        )
        cols = [
            "sample",
            "pixels",
            "method",
            "reduced_modulus",
            "rh",
            "error_adhesive_energy",
            "error_pull_off_pressure",
            "error_equilibrium_distance",
            "converged",
            "adhesive_energy",
            "pull_off_pressure",
            "equilibrium_distance",
            "seconds",
        ]
        out = ROOT / "benchmarks" / "validity_results" / "speed_vs_error_sweep.csv"
        out.parent.mkdir(exist_ok=True)
        base = [
            r
            for r in rows
            if r["setting"] in (f"{args.n_distances} distances", "height cutoff None")
        ]
        with out.open("w", newline="") as fh:
            fh.write(
                f"# written by: python benchmarks/{pathlib.Path(__file__).name} "
                f"{' '.join(sys.argv[1:])}\n# on {started}, {machine}\n"
                "# errors are |model - BEM| / |BEM| on the same periodic surface and grid\n"
            )
            w = csv.DictWriter(fh, fieldnames=cols, extrasaction="ignore")
            w.writeheader()
            for r in base + vrows:
                if r["method"] in ("modified_dmt", "gw"):
                    w.writerow(r)

    cols = [
        "sample",
        "pixels",
        "rh",
        "method",
        "setting",
        "converged",
        "seconds",
        "adhesive_energy",
        "error_adhesive_energy",
        "pull_off_pressure",
        "error_pull_off_pressure",
        "equilibrium_distance",
        "error_equilibrium_distance",
    ]
    text = [
        "# Accuracy tables (generated)",
        "",
        f"Written by `python benchmarks/speed_vs_error.py {' '.join(sys.argv[1:])}` on {started}, "
        f"{machine}. Do not edit by hand.",
        "",
        "## Summary per method and setting (poly-Si, S1/S2-like "
        + " and ".join(f"{n}²" for n in sorted({int(r["pixels"]) for r in rows}))
        + " pooled, RH 30/50/70/90 %)",
        "",
        method_table(rows),
        "",
        "## GW, modified DMT and BEM on S1/S2-like surfaces (poly-Si, E* = 86.6 GPa)",
        "",
        fmt_table(rows, cols),
    ]
    if vrows:
        vcols = [
            "sample",
            "pixels",
            "reduced_modulus",
            "rh",
            "method",
            "seconds",
            "adhesive_energy",
            "error_adhesive_energy",
            "error_pull_off_pressure",
            "error_equilibrium_distance",
            "converged",
        ]
        allrows = [r for r in rows if r["setting"] == f"{args.n_distances} distances"] + vrows
        text += [
            "",
            "## Validity map: worst modified-DMT error on Γ (S1/S2-like)",
            "",
            regime_table(allrows),
            "",
            "## Validity sweep: contact modulus and humidity",
            "",
            fmt_table(vrows, vcols),
        ]
    docs.mkdir(exist_ok=True)
    (docs / "accuracy_tables.md").write_text("\n".join(text) + "\n")
    if rows:
        figure(rows, docs / "accuracy_speed_vs_error.png")
    print("wrote", docs / "accuracy_tables.md")


if __name__ == "__main__":
    main()
