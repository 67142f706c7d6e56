"""``roughstick psd MAP... --out FILE.nc``: PSD and roughness statistics of AFM maps."""

from __future__ import annotations

import argparse
import pathlib

import numpy as np
import xarray as xr
from scipy.special import stdtrit

import roughstick as rs

from .._core.remedy import flag
from ..io import netcdf
from ._common import LOG, check_output_file, positive_int
from ._types import (
    LEVEL_HELP,
    check_map_flags,
    flag_value,
    pixel_size_arg,
    read_map,
    wavevector_arg,
)


def register(sub):
    p = sub.add_parser(
        "psd",
        help="PSD (averaged over maps and sub-maps) and roughness statistics of AFM maps or line scans",
        description=(
            "Read AFM maps of one sample, level them, and write the averaged PSD (Eq. 31), its "
            "radial average, the spatial variances (cubic splines), the PSD moments at the cutoff "
            "and the Eq. 32 check to a CF NetCDF file. Maps of different sizes or pixel sizes are "
            "averaged on a common log-spaced q grid over their bands' overlap. Line scans (1-D "
            "profiles) give the profile PSD and the profile moments m0, m2, m4 instead. The FFT "
            "window is Hann by default (measured scans are not periodic; --window none for the "
            "paper's unwindowed Table 3)."
        ),
    )
    p.add_argument("maps", nargs="+", help="AFM files (.nc, .npy, text, or vendor formats): all "
                   "2-D maps, or all line scans; bundled:S1A ... bundled:S2C name the sample maps "
                   "shipped with roughstick")
    p.add_argument("--out", required=True, help="output NetCDF file (.nc)")
    p.add_argument("--spacing", default=None, type=pixel_size_arg,
                   help="pixel size for .npy/text, with its unit, e.g. '5 nm'")
    p.add_argument("--units", default=None, help="height units for .npy/text, e.g. 'nm'")
    p.add_argument("--channel", default=None, help="channel name or index (vendor files)")
    p.add_argument("--level", default="auto", choices=["auto", "plane", "mean", "line", "none"],
                   help=LEVEL_HELP)
    p.add_argument("--nan", default="raise", choices=["raise", "fill"], help="NaN pixels")
    p.add_argument("--submaps", type=positive_int, default=16,
                   help="sub-maps per map: 1, 4, 16 (default 16; maps only)")
    p.add_argument("--qmax", default=None,
                   help="cutoff with its unit, e.g. '289 rad/um'; default: chosen to match the "
                        "spatial variances")
    p.add_argument("--surrogates", type=_count0, default=50,
                   help="Gaussian surrogates of each map behind the height-distribution "
                        "diagnostics (is the film Gaussian within its sampling error?); 0 skips "
                        "them (default 50, about 0.5 s per 512 x 512 map)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out file")
    p.add_argument("--window", default="auto",
                   help="FFT window: auto (default: Hann unless the map is marked periodic; "
                   "without a window the edge step of a non-periodic scan inflates m2 and m4 by "
                   "up to 112 %% and 1368 %%, docs/topography_psd.md), none, or a scipy window "
                   "name, e.g. hann, blackman")
    p.set_defaults(func=_run, remedies=lambda args: {"levelling": flag("--level")})


def _count0(text: str) -> int:
    """argparse type: an integer >= 0."""
    try:
        v = int(text)
    except ValueError:
        v = -1
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected an integer >= 0, got {text!r}")
    return v


def _run(args):
    out = pathlib.Path(args.out)
    check_output_file(out, overwrite=args.overwrite)
    qmax = None if args.qmax is None else flag_value("--qmax", wavevector_arg, args.qmax)  # rad/m
    for path in args.maps:  # every map's flags before any is read
        check_map_flags(path, spacing=args.spacing, units=args.units)
    channel = args.channel
    if channel is not None and channel.isdigit():
        channel = int(channel)
    maps = []
    for path in args.maps:
        maps.append(read_map(path, spacing=args.spacing, channel=channel, units=args.units, line_scan=True,
                             levelling=args.level))  # says its size, channel and levelling
    names = [pathlib.Path(p).name for p in args.maps]
    scans = ["y" not in m.dims for m in maps]
    if any(scans) and not all(scans):
        raise ValueError("the files mix line scans (" + ", ".join(n for n, s in zip(names, scans) if s)
                         + ") and 2-D maps; run roughstick psd on each kind separately.")
    if all(scans):
        method = "line" if args.level in ("auto", "plane") else args.level  # a profile's plane is a line
        ds = _line_scans([rs.surface.level_profile(m, method=method, nan=args.nan) for m in maps], names, args, qmax)
    else:
        # levelled as read (read_afm, --level); here only the NaN pixels (--nan)
        maps = [rs.surface.level(m, method="none", nan=args.nan) for m in maps]
        rs.surface.warn_if_incompatible(maps, names)  # said before they are averaged
        same = len({m.shape for m in maps}) == 1 and len({round(float(m.x[1] - m.x[0]), 15) for m in maps}) == 1 \
            and len({round(float(m.y[1] - m.y[0]), 15) for m in maps}) == 1
        if same:
            stack = xr.concat(maps, dim="map", coords="minimal", compat="override", combine_attrs="drop")
            stack = stack.assign_coords(map=names)
            stack.attrs = dict(maps[0].attrs)
            ds = rs.surface.psd_summary(stack, n=args.submaps, qmax=qmax, window=args.window)
            _keep_per_map(ds, rs.surface.roughness_moments(stack), "map")
        else:
            ds = _different_grids(maps, names, args, qmax)
    height_lines = [] if all(scans) or args.surrogates < 1 else _height_lines(ds, maps, args.surrogates)
    ds.attrs["input_files"] = " ".join(str(p) for p in args.maps)
    rs.conventions.append_history(ds, "roughstick psd " + " ".join(args.maps) + f" --out {args.out}")
    plural = "s" if len(maps) > 1 else ""
    what = (f"{len(maps)} line scan{plural}" if all(scans)
            else f"{len(maps)} map{plural}, {args.submaps} sub-maps each")
    same_grid = "map" not in ds["spatial_m0"].dims
    lines = _moment_lines(ds, what, scans=all(scans)) if same_grid else []  # also sets their attrs
    out.parent.mkdir(parents=True, exist_ok=True)
    netcdf.write(ds, out, compute=True, overwrite=True)  # checked: check_output_file
    if not same_grid:  # maps of different pixel sizes: m2, m4 depend on it, no mean
        lo, hi = ({k: float(getattr(ds[f"spatial_{k}"], f)()) for k in ("m0", "m2", "m4")} for f in ("min", "max"))
        LOG.info(f"{what}: sqrt(m0) = {lo['m0'] ** 0.5 * 1e9:.3g}-{hi['m0'] ** 0.5 * 1e9:.3g} nm, m2 = "
                 f"{lo['m2']:.3g}-{hi['m2']:.3g}, m4 = {lo['m4'] * 1e-18:.3g}-{hi['m4'] * 1e-18:.3g} nm^-2 "
                 "(spatial, per map: slopes and curvatures depend on the pixel size)")
    qm = ds["qmax"] * 1e-6 if "qmax" in ds else None
    tail = ("no cutoff" if qm is None else f"qmax = {float(qm):.4g} rad/um" if qm.size == 1
            else f"qmax = {float(qm.min()):.4g}-{float(qm.max()):.4g} rad/um") + (
        f", Eq. 32 = {float(ds.relative_std.mean()):.3g}" if "relative_std" in ds else "")
    for line in lines + height_lines:
        LOG.info(line)
    LOG.info(f"{tail}; wrote {out}")
    return 0


def _height_lines(ds, maps, n: int) -> list[str]:
    """The height-distribution diagnostics of the maps pooled (stored in ``ds``) as printed lines:
    skewness, kurtosis and the 99th/99.9th percentiles, each with the sampling interval of a
    Gaussian surface like the maps, and the verdict with what to do about it."""
    diag = rs.surface.height_diagnostics(list(maps), pooled=True, n=n)
    for k, v in diag.data_vars.items():
        ds[k] = v.astype("int8").assign_attrs(v.attrs, units="1") if v.dtype == bool else v
    ds.attrs["height_diagnostics"] = diag.attrs["interval_method"]

    def band(name, fmt=".3g", sel=None):
        v = diag[name] if sel is None else diag[name].sel(probability=sel)
        lo, hi = (diag[f"{name}_gaussian_{e}"] for e in ("lower", "upper"))
        if sel is not None:
            lo, hi = lo.sel(probability=sel), hi.sel(probability=sel)
        return f"{float(v):{fmt}} [{float(lo):{fmt}}, {float(hi):{fmt}}]"

    plural, them = ("s pooled", "them") if len(maps) > 1 else ("", "it")
    lines = [f"height distribution of the map{plural} (in brackets: the {diag.attrs['confidence']:.0%} "
             f"sampling interval of a Gaussian surface like {them}, {n} surrogates):",
             f"  skewness {band('skewness')}, kurtosis {band('kurtosis')} (Gaussian 0 and 3)",
             f"  99th height percentile {band('tail_quantile', sel=0.99)} rms (Gaussian 2.33), "
             f"99.9th {band('tail_quantile', sel=0.999)} rms (Gaussian 3.09)"]
    if bool(diag.gaussian):
        lines.append("  Gaussian within the sampling error: Gaussian surfaces (the default) describe "
                     "their heights")
    else:
        lines.append('  NOT Gaussian within the sampling error: generate surfaces with their height '
                     'distribution (roughstick run: [surface] height_distribution = "maps" with '
                     '[psd] source = "samples"; Python: generate_surfaces(..., '
                     "height_distribution=rs.surface.height_distribution(maps)))")
    return lines


#: Confidence of the printed interval of the mean spatial moments over maps.
CONFIDENCE = 0.95


def _keep_per_map(ds, per, label: str) -> None:
    """Store each map's (or scan's) spatial moments as ``map_spatial_m0/m2/m4`` over ``map``."""
    for k in ("m0", "m2", "m4"):
        ds[f"map_spatial_{k}"] = per[k].assign_attrs(
            units=per[k].attrs["units"], long_name=f"spatial {k} of each {label} (cubic splines)")
    ds["map"].attrs = {"long_name": "input file"}


def _moment_lines(ds, what: str, *, scans: bool) -> list[str]:
    """The printed spatial moments: the mean over the maps with the range across them and the
    95 % Student-t interval of the mean (maps as independent samples of the surface), or for one
    map that n = 1 is too small to bound their map-to-map spread."""
    label = "line scan" if scans else "map"
    per = {k: np.asarray(ds[f"map_spatial_{k}"].values, dtype=float) for k in ("m0", "m2", "m4")}
    n = per["m0"].size

    def show(k, v):
        return f"{v ** 0.5 * 1e9:.3g} nm" if k == "m0" else (
            f"{v:.3g}" if k == "m2" else f"{v * 1e-18:.3g} nm^-2")

    def name(k):
        return "sqrt(m0)" if k == "m0" else k

    if n < 2:
        values = ", ".join(f"{name(k)} = {show(k, float(per[k][0]))}" for k in per)
        return [f"{what}: spatial moments (cubic splines) {values}; n = 1 {label} is too small to "
                f"bound their {label}-to-{label} spread (give 2 or more {label}s)"]
    t = float(stdtrit(n - 1, 0.5 + CONFIDENCE / 2))
    lines = [f"{what}: spatial moments (cubic splines), mean over the {n} {label}s [range across "
             f"them; {CONFIDENCE:.0%} interval of the mean, Student t with {n - 1} dof]:"]
    for k, v in per.items():
        mean, half = float(v.mean()), t * float(v.std(ddof=1)) / np.sqrt(n)
        lo, hi = max(mean - half, 0.0), mean + half
        ds[f"spatial_{k}"].attrs.update({f"interval_{CONFIDENCE:.0%}".replace("%", "_percent"): [lo, hi],
                                         "interval_method": f"Student t over {n} {label}s"})
        lines.append(f"  {name(k)} = {show(k, mean)} [{show(k, float(v.min())).split()[0]}-"
                     f"{show(k, float(v.max()))}; {show(k, lo).split()[0]}-{show(k, hi)}]")
    return lines


def _different_grids(maps, names, args, qmax):
    """Maps of different sizes/spacings: each map's own §4.1 chain (stacked over ``map``) and
    their radial PSDs averaged on a common log-spaced q grid over the bands' overlap."""
    per_map = [rs.surface.psd_summary(m, n=args.submaps, qmax=qmax, window=args.window) for m in maps]
    common = rs.surface.average_psd_common([s.psd_isotropic.drop_vars("n_ring") for s in per_map], names=names)
    keys = [k for k in per_map[0].data_vars if not set(per_map[0][k].dims) & {"q", "qx", "qy"}]
    ds = xr.concat([s[keys] for s in per_map], dim="map", combine_attrs="override").assign_coords(map=names)
    ds["psd_isotropic"] = common.psd
    ds["map"].attrs = {"long_name": "input file"}
    for k in ("n_maps", "contributed", "q_min", "q_max"):
        ds[k] = common[k]
    band = f"{float(common.q[0]) * 1e-6:.4g}-{float(common.q[-1]) * 1e-6:.4g} rad/um"
    ds.attrs = dict(per_map[0].attrs, title="PSD and roughness statistics of AFM maps of different "
                    "sizes or pixel sizes (paper §4.1, Eq. 31 on a common q grid)",
                    n_maps=len(maps), common_q_band=band)
    LOG.info(f"maps of different sizes/pixel sizes: radial PSDs averaged on {common.sizes['q']} "
             f"log-spaced q over their common band {band}; each map's statistics are kept over 'map'")
    return ds


def _line_scans(scans, names, args, qmax):
    """Line scans: the profile PSD (1-D Eqs. 26-31) averaged over scans, profile moments."""
    psds = [rs.surface.profile_psd(s, window=args.window) for s in scans]
    spatial = xr.concat([rs.surface.profile_moments(s) for s in scans], dim="map").assign_coords(map=names)
    dq = [float(c.qx[1] - c.qx[0]) for c in psds]
    same = len({c.sizes["qx"] for c in psds}) == 1 and all(abs(d / dq[0] - 1) < 1e-9 for d in dq)
    if same:
        avg = rs.surface.average_psd([c.assign_coords(qx=psds[0].qx) for c in psds], "map")
        ds = xr.Dataset({"psd_1d": avg})
    else:
        common = rs.surface.average_psd_common(psds, names=names)
        ds = common.rename({"psd": "psd_1d"})
        LOG.info(f"line scans of different lengths/spacings: averaged on {common.sizes['qx']} log-spaced "
                 f"qx (one-sided) over {float(common.qx[0]) * 1e-6:.4g}-{float(common.qx[-1]) * 1e-6:.4g} rad/um")
    _keep_per_map(ds, spatial, "line scan")
    spectral = rs.surface.profile_moments(ds.psd_1d, qmax=qmax)
    for k in ("m0", "m2", "m4"):
        ds[f"spatial_{k}"] = spatial[k].mean("map").assign_attrs(
            units=spatial[k].attrs["units"],
            long_name=f"profile {k} (cubic-spline variances, mean over line scans)")
        ds[k] = spectral[k].assign_attrs(long_name=f"profile PSD moment {k}" + (" up to qmax" if qmax else ""))
    if qmax is not None:
        ds["qmax"] = xr.DataArray(qmax, attrs={"units": "rad m-1", "long_name": "cutoff wave number"})
    ds.attrs = rs.conventions.dataset_attrs(
        "Profile PSD and moments of AFM line scans (1-D counterpart of paper §4.1, Eqs. 26-31)",
        references="roughstick.surface.profile_psd, profile_moments", n_maps=len(scans), kind="line scans",
        window=str(psds[0].attrs.get("window", args.window)))
    if args.window == "none":
        LOG.info("line scans are rarely periodic: without a window their edge step leaks "
                 "power to high q and inflates m2 and m4 (--window auto: Hann)")
    return ds
