"""The map-to-answer path on the real AFM maps: what levelling changes, and what `roughstick curves
--model auto` costs on each map as every command now reads it (levelled by its plane).

    python benchmarks/bench_map_paths.py            # the four shared AFM maps (about a minute)

The maps are read from $ROUGHSTICK_AFM_DIR, else from ../shared/afm beside the project; absent
files are skipped with a message. Each command runs in its own process, as a user runs it, and
its wall time (reading, model choice, curves, writing) is measured.
"""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys
import tempfile
import time

import xarray as xr

ROOT = pathlib.Path(__file__).resolve().parents[1]
AFM_DIR = pathlib.Path(os.environ.get("ROUGHSTICK_AFM_DIR", "") or ROOT.parent / "shared" / "afm")
AFM_FILES = ("ST_di-1.di", "ST_di-3.di", "ST_di-6.di", "ST_example_ps.tiff")
RH = ("0.5", "0.7", "0.9")
#: A run longer than this is stopped (the criterion is one minute).
LIMIT_S = 120


def curves(path: pathlib.Path, out: pathlib.Path, *extra: str) -> tuple[float, str, xr.Dataset | None]:
    """Run `roughstick curves` on ``path``; (wall seconds, the lines it printed, its result)."""
    cmd = [sys.executable, "-m", "roughstick.cli", "curves", str(path), "--rh", *RH, "--out", str(out),
           "--overwrite", *extra]
    t0 = time.perf_counter()
    try:
        run = subprocess.run(cmd, capture_output=True, text=True, timeout=LIMIT_S)
    except subprocess.TimeoutExpired:
        return time.perf_counter() - t0, f"stopped after {LIMIT_S} s", None
    wall = time.perf_counter() - t0
    said = [line for line in (run.stdout + run.stderr).splitlines()
            if line.startswith(("read_afm", "contact model auto"))]
    return wall, "\n    ".join(said), xr.load_dataset(out) if run.returncode == 0 else None


def compatibility(found: list) -> None:
    """Which maps warn_if_incompatible takes for one surface: every pair of AFM maps (different
    films), and each map against its own crop (one surface at two scan sizes)."""
    import itertools
    import warnings

    import roughstick as rs

    maps = {name: rs.io.read_afm(AFM_DIR / name, levelling="auto") for name in found}

    def verdict(hs, names):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            stats = rs.surface.warn_if_incompatible(hs, names)
        what = ", ".join(f"{n}: Sq {s['rms_height'] * 1e9:.3g} nm, Sal {s['autocorrelation_length'] * 1e9:.3g} nm"
                         + (f", band rms {s['band_psd'] ** 0.5 * 1e9:.3g} nm" if "band_psd" in s else "")
                         for n, s in stats.items())
        return ("WARNS" if caught else "alike") + f" ({what})"

    print("\n== maps of one surface? rs.surface.warn_if_incompatible ==")
    for a, b in itertools.combinations(found, 2):
        print(f"  {a} + {b}: {verdict([maps[a], maps[b]], [a, b])}")
    for name in found:
        h = maps[name]
        crop = h.isel(y=slice(0, h.sizes["y"] // 4), x=slice(0, h.sizes["x"] // 4))
        print(f"  {name} + its top-left quarter-side crop: {verdict([h, crop], ['whole', 'crop'])}")


def main():
    found = [f for f in AFM_FILES if (AFM_DIR / f).is_file()]
    print(f"{time.strftime('%H:%M:%S')} load average {os.getloadavg()[0]:.2f}; real AFM maps: "
          f"{len(found)} of {len(AFM_FILES)} found")
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "c.nc"
        print(f"\n== roughstick curves MAP --rh {' '.join(RH)} --model auto (levelled by default) ==")
        for name in found:
            wall, said, ds = curves(AFM_DIR / name, out, "--model", "auto")
            gamma = ("" if ds is None else ", Γ " + ", ".join(f"{float(v) * 1e3:.3g}" for v in ds.adhesive_energy.values)
                     + f" mJ/m² by {ds.attrs['contact_model']}")
            print(f"  {name}: {wall:.1f} s{gamma}\n    {said}")
        print("\n== what a plane left in changes: --model modified_dmt, --level auto against --level none ==")
        for name in found:
            rows = {}
            for level in ("auto", "none"):
                wall, _, ds = curves(AFM_DIR / name, out, "--model", "modified_dmt", "--level", level)
                rows[level] = ds
            a, n = rows["auto"], rows["none"]
            ratio = ", ".join(f"RH {r}: Γ {float(g1) / float(g0) - 1:+.0%}, d_eq {float(d0) * 1e9:.3g} -> {float(d1) * 1e9:.3g} nm"
                              for r, g0, g1, d0, d1 in zip(RH, a.adhesive_energy.values, n.adhesive_energy.values,
                                                           a.equilibrium_distance.values, n.equilibrium_distance.values))
            print(f"  {name} unlevelled against levelled: {ratio}")
    compatibility(found)
    print(f"{time.strftime('%H:%M:%S')} load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
