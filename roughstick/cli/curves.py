"""``roughstick curves MAP.nc --rh 0.3 0.5 ... --out curves.nc``: force-distance curves of a map."""

from __future__ import annotations

import pathlib
import sys
import warnings

import numpy as np

import roughstick as rs

from .._core.materials import material_attrs
from .._core.remedy import flag
from .._core.units import parse_quantity
from ..io import netcdf
from ._common import check_output_file, length_with_unit, positive_int
from ._types import (
    LEVEL_HELP,
    flag_value,
    material_arg,
    pixel_size_arg,
    positive_float_arg,
    read_map,
    relative_humidity_arg,
)


def register(sub):
    p = sub.add_parser(
        "curves",
        help="force-distance curves (by the cheapest model measured within --accuracy of the "
        "boundary-element reference, or the model named) and adhesion summary of one height map",
        description=(
            "Read a height map, compute the pressure versus distance at the given humidities "
            "(by default --model auto: the cheapest contact model measured within --accuracy of the "
            "boundary-element reference for this surface; --model modified_dmt is the paper's "
            "model, Eqs. 16-23) and its adhesive energy (Eq. 13), and write both to a "
            "CF NetCDF file. --resolution also reports how the summaries change with the pixel "
            "size."
        ),
    )
    p.add_argument("map", help="height map (.nc, .npy, text, or vendor formats); bundled:S1A ... "
                   "bundled:S2C name the sample maps shipped with roughstick")
    p.add_argument("--rh", type=relative_humidity_arg, nargs="+", required=True,
                   help="relative humidities as fractions or percentages, e.g. --rh 0.3 0.5 0.7 "
                   "or --rh '30 %%' '50 %%'")
    p.add_argument("--out", required=True,
                   help="output NetCDF file (.nc; its folder is created; an existing file is kept "
                   "unless --overwrite)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out file")
    p.add_argument("--spacing", default=None, type=pixel_size_arg,
                   help="pixel size for .npy/text, with its unit, e.g. '5 nm'")
    p.add_argument("--units", default=None, help="height units for .npy/text, e.g. 'nm'")
    p.add_argument("--level", default="auto", choices=["auto", "plane", "mean", "line", "none"],
                   help=LEVEL_HELP)
    p.add_argument("--n-distance", type=positive_int, default=None,
                   help="points of the automatic grid, at least (default: 200 for modified_dmt and "
                   "gw, 40 for bem, about 50 adaptive points for fft_bem, the chosen model's "
                   "own for auto)")
    p.add_argument("--distance", nargs=3, metavar=("LOW", "HIGH", "N"), default=None,
                   help="explicit uniform grid: low and high distance with their unit and the number "
                        "of points, e.g. --distance '1 nm' '20 nm' 400")
    p.add_argument("--adsorbed-layer", default="paper", choices=["paper", "none"])
    p.add_argument("--connectivity", type=int, default=4, choices=[4, 8])
    p.add_argument("--periodic", default=None, choices=["yes", "no"],
                   help="override the map's 'periodic' attribute")
    p.add_argument("--model", default="auto", choices=rs.contact.model_names(auto=True),
                   help="contact model (default auto: the cheapest model whose measured error bound "
                   "for this surface meets --accuracy, docs/accuracy.md; modified_dmt: the paper's "
                   "model, Eq. 16)")
    p.add_argument("--accuracy", "--tolerance", dest="accuracy", type=positive_float_arg, default=0.1,
                   help="accepted relative error against the boundary-element reference "
                   "(default 0.1): --model auto meets it; modified_dmt warns where it may not "
                   "(--tolerance: its old name)")
    p.add_argument("--resolution", action="store_true",
                   help="also report how the adhesive energy, pull-off pressure and equilibrium "
                   "distance change with the pixel size (resampled map, same model)")
    p.add_argument("--resolution-factors", type=positive_float_arg, nargs="+", default=[0.5, 1, 2],
                   metavar="F",
                   help="pixel sizes relative to the map's (integers or their inverses; "
                   "default 0.5 1 2)")
    p.add_argument("--material", nargs="+", default=None, metavar="NAME|E NU",
                   help="material of both bodies (default polysilicon): a name roughstick knows, or "
                   "Young's modulus with its unit and the Poisson ratio, e.g. --material '250 GPa' 0.23 "
                   "(a label first: --material SiN '250 GPa' 0.23)")
    p.set_defaults(func=_run, remedies=remedies)


def remedies(args) -> dict:
    """How the warnings of ``roughstick curves`` spell their remedies: its flags
    (:mod:`roughstick._core.remedy`)."""
    measured = ("the --resolution table this command prints below" if args.resolution else
                "--resolution (add it to this command: Γ, pull-off and d_eq at half and twice the pixel)")
    return {"contact_model": flag("--model", extra={"accuracy": "--accuracy"}),
            "levelling": flag("--level"),
            "spacing": lambda v, **kw: f"a map generated at a pixel of {v * 1e9:.2g} nm",
            "resolution": lambda v=None, **kw: measured}


def _distance_grid(low: str, high: str, n: str) -> np.ndarray:
    """``--distance LOW HIGH N``: lengths with their unit, LOW < HIGH, N >= 2 points."""
    lo, hi = (parse_quantity(flag_value("--distance", length_with_unit, t), "length", name="--distance")
              for t in (low, high))
    try:
        count = int(n)
    except ValueError:
        count = 0
    if count < 2:
        raise ValueError(f"--distance {low!r} {high!r} {n!r}: N must be a whole number of points >= 2, "
                         "e.g. --distance '1 nm' '20 nm' 400.")
    if not lo < hi:
        raise ValueError(f"--distance {low!r} {high!r} {n!r}: LOW must be below HIGH, e.g. "
                         "--distance '1 nm' '20 nm' 400.")
    return np.linspace(lo, hi, count)


def _run(args):
    out = pathlib.Path(args.out)
    check_output_file(out, overwrite=args.overwrite)
    distance = None if args.distance is None else _distance_grid(*args.distance)  # before any work
    material = material_arg(args.material) if args.material else rs.POLYSILICON
    # levelled as every command levels a measured map (printed; --level); --periodic yes: not
    levelling = "none" if args.level == "auto" and args.periodic == "yes" else args.level
    h = read_map(args.map, spacing=args.spacing, units=args.units, levelling=levelling)
    n_distance = args.n_distance
    if n_distance is None and args.model in ("modified_dmt", "gw"):
        n_distance = 200  # auto: the chosen model's own default, as from Python
    periodic = None if args.periodic is None else args.periodic == "yes"
    # the asperity settings go to the models that take them (all of them for --model auto)
    takes = set().union(*(m.options for m in rs.contact.MODELS.values())) if args.model == "auto" \
        else set(rs.contact.MODELS[args.model].options)
    kw = {k: v for k, v in {"connectivity": args.connectivity, "periodic": periodic}.items() if k in takes}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", rs.contact.ValidityWarning)
        ds = rs.contact.curves(
            h,
            relative_humidity=list(args.rh),
            distance=distance,
            n_distance=n_distance,
            adsorbed_layer=args.adsorbed_layer,
            model=args.model,
            accuracy=args.accuracy,
            material=material,
            **kw,
        )
    for w in caught:
        if issubclass(w.category, rs.contact.ValidityWarning):
            # on the command line the remedy is a flag: say it as a message, not a traceback line
            print(f"roughstick curves: warning: {w.message}", file=sys.stderr)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    summary = rs.contact.summary(ds)
    for name in summary.data_vars:
        ds[name] = summary[name]
    res = None
    if args.resolution:
        res = rs.contact.resolution_study(h, relative_humidity=list(args.rh),
                                  factors=args.resolution_factors,
                                  model=ds.attrs.get("contact_model", args.model),
                                  adsorbed_layer=args.adsorbed_layer, material=material)
        print(f"pixel-size sensitivity ({res.attrs['resampling']}):")
        r = res.transpose("pixel_size", ...)
        for i, px in enumerate(r.pixel_size.values):
            for j, rh in enumerate(np.atleast_1d(r.rh.values) if "rh" in r.dims else [args.rh[0]]):
                sel = r.isel(pixel_size=i, **({"rh": j} if "rh" in r.dims else {}))
                print(f"  pixel {px * 1e9:6.3g} nm  RH {rh:.3g}: Γ {float(sel.adhesive_energy):.4g} "
                      f"J/m2 ({float(sel.relative_change_adhesive_energy):+.1%}), pull-off "
                      f"{float(sel.pull_off_pressure) / 1e6:.4g} MPa "
                      f"({float(sel.relative_change_pull_off_pressure):+.1%}), d_eq "
                      f"{float(sel.equilibrium_distance) * 1e9:.4g} nm "
                      f"({float(sel.relative_change_equilibrium_distance):+.1%})")
        for name in res.data_vars:
            ds[f"resolution_{name}"] = res[name].rename(pixel_size="resolution_pixel_size")
    ds.attrs["input_file"] = str(args.map)
    ds.attrs.update(material_attrs(material))
    rs.conventions.append_history(
        ds, f"roughstick curves {args.map} --rh {' '.join(map(str, args.rh))} --model "
            f"{args.model} --accuracy {args.accuracy}"
            + (f" --material {' '.join(args.material)}" if args.material else "") + f" --out {args.out}"
    )
    out.parent.mkdir(parents=True, exist_ok=True)
    netcdf.write(ds, out, compute=True, overwrite=True)  # checked: check_output_file
    budget = rs.contact.error_budget(summary, res)
    print(f"contact model {ds.attrs.get('contact_model', args.model)}; relative error budget "
          "[model bound, distance grid, pixel (--resolution with a factor below 1)]:")
    for j, (rh, g, deq) in enumerate(zip(np.atleast_1d(ds.rh.values),
                                         np.atleast_1d(summary.adhesive_energy.values),
                                         np.atleast_1d(summary.equilibrium_distance.values), strict=True)):
        print(f"RH {rh:.3g}: adhesive energy {g:.4g} J/m2 {_budget_text(budget, 'adhesive_energy', j)}, "
              f"equilibrium distance {deq * 1e9:.3g} nm {_budget_text(budget, 'equilibrium_distance', j)}")
    print(f"wrote {out}")


def _budget_text(budget, quantity: str, j: int) -> str:
    """``[model ≤ a %, grid b %, pixel c %]`` of one summary at humidity index ``j``."""
    row = budget.sel(quantity=quantity).isel(rh=j)

    def pct(v, bound=False):
        v = float(v)
        return "not measured" if np.isnan(v) else ("unbounded" if np.isinf(v) else
                                                   f"{'<= ' if bound else ''}{v:.1%}")
    return f"[model {pct(row.model, True)}, grid {pct(row.grid)}, pixel {pct(row.pixel)}]"
    return 0
