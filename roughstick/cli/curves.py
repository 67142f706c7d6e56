"""``roughstick curves MAP.nc --rh 0.3 0.5 ... --out curves.nc``: force-distance curves of a map."""

from __future__ import annotations

import pathlib

import numpy as np

import roughstick as rs

from ..io import netcdf


def register(sub):
    p = sub.add_parser(
        "curves",
        help="modified-DMT force-distance curves (Eq. 16) and adhesion summary of one height map",
        description=(
            "Read a height map, compute the rough-surface modified-DMT pressure versus distance at "
            "the given humidities (Eqs. 16-23) and its adhesive energy (Eq. 13), and write both "
            "to a CF NetCDF file."
        ),
    )
    p.add_argument("map", help="height map (.nc, .npy, text, or vendor formats)")
    p.add_argument("--rh", type=float, nargs="+", required=True,
                   help="relative humidities as fractions, e.g. --rh 0.3 0.5 0.7")
    p.add_argument("--out", required=True, help="output NetCDF file")
    p.add_argument("--spacing", default=None, help="pixel size for .npy/text, e.g. '5 nm'")
    p.add_argument("--units", default=None, help="height units for .npy/text, e.g. 'nm'")
    p.add_argument("--n-distance", type=int, default=200, help="points of the automatic grid")
    p.add_argument("--distance", type=float, nargs=3, metavar=("LOW", "HIGH", "N"), default=None,
                   help="explicit uniform grid: low and high distance [m] and the number of points")
    p.add_argument("--adsorbed-layer", default="paper", choices=["paper", "none"])
    p.add_argument("--connectivity", type=int, default=4, choices=[4, 8])
    p.add_argument("--periodic", default=None, choices=["yes", "no"],
                   help="override the map's 'periodic' attribute")
    p.add_argument("--model", default="modified_dmt", choices=["modified_dmt", "gw"])
    p.set_defaults(func=_run)


def _run(args):


    h = rs.read_afm(args.map, spacing=args.spacing, units=args.units)
    distance = None
    if args.distance is not None:
        lo, hi, n = args.distance
        distance = np.linspace(lo, hi, int(n))
    periodic = None if args.periodic is None else args.periodic == "yes"
    ds = rs.rough_contact_curves(
        h,
        relative_humidity=list(args.rh),
        distance=distance,
        n_distance=args.n_distance,
        adsorbed_layer=args.adsorbed_layer,
        connectivity=args.connectivity,
        periodic=periodic,
        model=args.model,
    )
    summary = rs.adhesion_summary(ds)
    for name in summary.data_vars:
        ds[name] = summary[name]
    ds.attrs["input_file"] = str(args.map)
    rs.conventions.append_history(
        ds, f"roughstick curves {args.map} --rh {' '.join(map(str, args.rh))} --out {args.out}"
    )
    out = pathlib.Path(args.out)
    netcdf.write(ds, out, compute=True)
    for rh, g, deq in zip(np.atleast_1d(ds.rh.values), np.atleast_1d(summary.adhesive_energy.values),
                          np.atleast_1d(summary.equilibrium_distance.values), strict=True):
        print(f"RH {rh:.3g}: adhesive energy {g:.4g} J/m2, equilibrium distance {deq * 1e9:.3g} nm")
    print(f"wrote {out}")
    return 0
