"""Demo step: AFM maps → roughness statistics and PSDs (paper §4.1, Tables 2-4, Figs. 12, 19).

Runs on the bundled maps S1A-S2C (:mod:`roughstick.datasets`, synthetic stand-ins for the paper's
measurements). Writes:

- ``topography_statistics.csv`` / ``.nc``: Table 2/3-style spatial variances and PSD moments
  (cutoff 289 rad/µm and the cutoff chosen to match the spatial variances), Eq. 32 for the
  three sub-map schemes;
- ``fig12_psd_schemes.png``: PSDs of S1 by the three schemes and of S2 by scheme 3;
- ``fig19_self_affine_psd.png`` and ``table4_self_affine.csv``: the Eq. 37 PSD solved from
  Table 4 (N = 80.1 and 88.1 µm⁻²) against S1 and S2.
"""

from __future__ import annotations

import csv
import io
import pathlib

import numpy as np
import xarray as xr

import roughstick as rs

from ...io import netcdf
from ...io.netcdf import write_text_atomic
from ...plotting.save import DEFAULT_DPI, save_figure
from .. import topography as figures
from ..topography import QMAX_PAPER


def _maps(sample: str, quick: bool) -> xr.DataArray:
    labels = [n for n in rs.datasets.SAMPLES if n.startswith(sample)]
    maps = [rs.datasets.load_sample(n) for n in labels]
    if quick:
        maps = [m.isel(x=slice(0, 256), y=slice(0, 256)) for m in maps]
    maps = [rs.surface.level(m, method="plane") for m in maps]
    out = xr.concat([m.drop_attrs() if hasattr(m, "drop_attrs") else m for m in maps], dim="map",
                    coords="minimal", compat="override")
    out.attrs = dict(maps[0].attrs)
    return out.assign_coords(map=labels)


def _write(ds: xr.Dataset, path: pathlib.Path) -> None:
    netcdf.write(ds, path, compute=True, overwrite=True)


def _write_csv(path, rows):
    """Write a list of dicts as CSV, floats to 4 significant digits."""

    f = io.StringIO(newline="")
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    for r in rows:
        w.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in r.items()})
    write_text_atomic(path, f.getvalue())

def run(out: pathlib.Path, *, quick: bool, figure_format: str = "png",
        dpi: int = DEFAULT_DPI) -> list[pathlib.Path]:
    """Compute the statistics and PSD figures; return the files written."""
    out = pathlib.Path(out)
    written = []
    rows, schemes, summaries = [], {}, {}
    for sample in ("S1", "S2"):
        h = _maps(sample, quick)
        spatial = rs.surface.roughness_moments(h).mean("map")
        # the paper's Table 3 / Fig. 12: periodograms without a window (window=None)
        schemes[sample] = {n: rs.surface.submap_psd(h, n=n, window=None) for n in (1, 4, 16)}
        eq32 = {n: float(rs.surface.submap_variance_check(h, n=n).relative_std) for n in (4, 16)}
        s3 = schemes[sample][16]
        fixed = rs.surface.psd_moments(s3, qmax=QMAX_PAPER)
        chosen = rs.surface.choose_cutoff(s3, spatial)
        summaries[sample] = rs.surface.psd_summary(h, n=16, window=None)
        for label, m, q in (("spatial variances (cubic splines)", spatial, np.nan),
                            ("PSD moments, scheme 3, xi_max = 289 rad/um", fixed, QMAX_PAPER),
                            ("PSD moments, scheme 3, chosen xi_max", chosen, float(chosen.qmax))):
            rows.append({
                "sample": sample, "estimate": label, "n_maps": h.sizes["map"],
                "map_pixels": f"{h.sizes['y']}x{h.sizes['x']}",
                "m0_nm2": float(m.m0) * 1e18, "m2": float(m.m2), "m4_nm-2": float(m.m4) * 1e-18,
                "xi_max_rad_per_um": q * 1e-6,
                "eq32_scheme2": eq32[4], "eq32_scheme3": eq32[16],
            })
    table = out / "topography_statistics.csv"
    _write_csv(table, rows)
    written.append(table)
    ds = xr.concat([summaries[s].drop_vars(["psd"]) for s in ("S1", "S2")], dim="sample",
                   coords="minimal", compat="override", join="outer")
    ds = ds.assign_coords(sample=("sample", ["S1", "S2"], {"units": "1", "long_name": "sample"}))
    ds.attrs = summaries["S1"].attrs
    nc = out / "topography_statistics.nc"
    _write(ds, nc)
    written.append(nc)

    # Fig. 12: the three schemes for S1, scheme 3 for S2
    _, fig = figures.fig12_psd_schemes(schemes)
    written.append(save_figure(fig, out / "fig12_psd_schemes.png", format=figure_format, dpi=dpi))

    # Table 4 -> Eq. 37 (both densities), Fig. 19
    fits = figures.table4_self_affine()
    trows = []
    for label, fit in fits.items():
        m0, m2, m4 = fit.attrs["asperity_moments"]
        trows.append({"N_um-2": float(label.split("N = ")[1].split(" ")[0]), "mu0_nm2": m0 * 1e18,
                      "mu2": m2, "mu4_um-2": m4 * 1e-12, "xi0_rad_per_um": float(fit.q0) * 1e-6,
                      "s0_nm4": float(fit.s0) * 1e36, "s1_nm4": float(fit.s1) * 1e36})
    trows.append({"N_um-2": "paper (printed)", "mu0_nm2": 12.53, "mu2": 0.0035, "mu4_um-2": 9.1,
                  "xi0_rad_per_um": 19.4, "s0_nm4": 6.46e3, "s1_nm4": 6.29e-3})
    t4 = out / "table4_self_affine.csv"
    _write_csv(t4, trows)
    written.append(t4)
    _, fig = figures.fig19_self_affine_psd(
        fits, measured={f"{s} (scheme 3)": schemes[s][16] for s in ("S1", "S2")})
    written.append(save_figure(fig, out / "fig19_self_affine_psd.png", format=figure_format, dpi=dpi))
    return written
