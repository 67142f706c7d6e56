"""``roughstick psd MAP... --out FILE.nc``: PSD and roughness statistics of AFM maps."""

from __future__ import annotations

import pathlib

import xarray as xr

import roughstick as rs

from ..io import netcdf
from . import _config
from ._common import LOG, positive_int


def register(sub):
    p = sub.add_parser(
        "psd",
        help="PSD (averaged over maps and sub-maps) and roughness statistics of AFM maps",
        description=(
            "Read AFM maps of one sample, level them, and write the averaged PSD (Eq. 31), its "
            "radial average, the spatial variances (cubic splines), the PSD moments at the cutoff "
            "and the Eq. 32 check to a CF NetCDF file."
        ),
    )
    p.add_argument("maps", nargs="+", help="AFM files (.nc, .npy, text, or vendor formats)")
    p.add_argument("--out", required=True, help="output NetCDF file")
    p.add_argument("--spacing", default=None, help="pixel size for .npy/text, e.g. '5 nm'")
    p.add_argument("--units", default=None, help="height units for .npy/text, e.g. 'nm'")
    p.add_argument("--channel", default=None, help="channel name or index (vendor files)")
    p.add_argument("--level", default="plane", choices=["plane", "mean", "line", "none"])
    p.add_argument("--nan", default="raise", choices=["raise", "fill"], help="NaN pixels")
    p.add_argument("--submaps", type=positive_int, default=16,
                   help="sub-maps per map: 1, 4, 16 (default 16)")
    p.add_argument("--qmax", default=None,
                   help="cutoff with its unit, e.g. '289 rad/um'; default: chosen to match the "
                        "spatial variances")
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out file")
    p.add_argument("--window", default=None, help="FFT window, e.g. hann")
    p.set_defaults(func=_run)


def _run(args):
    out = pathlib.Path(args.out)
    if out.exists() and not args.overwrite:
        raise FileExistsError(f"{str(out)!r} exists; pass --overwrite to replace it or choose another --out.")
    if out.is_dir():
        raise FileExistsError(f"--out {str(out)!r} is a folder; give a file name, e.g. {str(out / 'psd.nc')!r}.")
    qmax = None
    if args.qmax is not None:
        qmax = _config.parse({"x": {"qmax": args.qmax}}, "psd", base=".", source="--qmax",
                             schema={"x": {"qmax": _config.Field("wavevector", "cutoff")}})["x"]["qmax"]
    channel = args.channel
    if channel is not None and channel.isdigit():
        channel = int(channel)
    maps = []
    for path in args.maps:
        h = rs.read_afm(path, spacing=args.spacing, channel=channel, units=args.units)
        maps.append(rs.level(h, method=args.level, nan=args.nan))
        used = h.attrs.get("channel")
        LOG.info(f"{path}: {h.sizes['y']} x {h.sizes['x']} px of {float(h.x[1] - h.x[0]) * 1e9:.4g} nm"
                 + (f", channel {used}" + (f" (of {h.attrs['channels_in_file']})"
                                            if "channels_in_file" in h.attrs else "") if used else ""))
    shapes = {m.shape for m in maps}
    if len(shapes) > 1:
        raise ValueError(f"all maps must have the same size to be averaged; got {sorted(shapes)}.")
    spacings = {round(float(m.x[1] - m.x[0]), 15) for m in maps}
    if len(spacings) > 1:
        raise ValueError(f"all maps must have the same pixel size; got {sorted(spacings)} m.")
    stack = xr.concat(maps, dim="map", coords="minimal", compat="override", combine_attrs="drop")
    stack = stack.assign_coords(map=[pathlib.Path(p).name for p in args.maps])
    stack.attrs = dict(maps[0].attrs)
    ds = rs.psd_summary(stack, n=args.submaps, qmax=qmax, window=args.window)
    ds.attrs["input_files"] = " ".join(str(p) for p in args.maps)
    rs.conventions.append_history(ds, "roughstick psd " + " ".join(args.maps) + f" --out {args.out}")
    out.parent.mkdir(parents=True, exist_ok=True)
    netcdf.write(ds, out, compute=True)
    LOG.info(
        f"{len(maps)} maps, {args.submaps} sub-maps each: sqrt(m0) = {float(ds.spatial_m0) ** 0.5 * 1e9:.3g} nm, "
        f"m2 = {float(ds.spatial_m2):.3g}, m4 = {float(ds.spatial_m4) * 1e-18:.3g} nm^-2 (spatial); "
        f"qmax = {float(ds.qmax) * 1e-6:.4g} rad/um, Eq. 32 = {float(ds.relative_std):.3g}; wrote {out}"
    )
    return 0
