"""Make the bundled synthetic AFM maps S1A-S1C and S2A-S2C (reproducibly).

Run from the repository root::

    python data_samples/make_samples.py            # writes roughstick/data/S*.nc, prints moments
    python data_samples/make_samples.py --check    # regenerate in memory, compare with the files

Each set stands in for the three AFM measurements of samples S1 and S2 of the paper (§3.1,
Table 3): 1024 x 1024 maps with 5 nm pixels (5.12 um x 5.12 um). They are SYNTHETIC:

1. the self-affine PSD of Eq. 37 is solved for (q0, s0, s1) so that its moments equal the
   paper's Table 3 PSD moments (S1: m0 = 15.7 nm2, m2 = 0.040, m4 = 5.08e-4 nm-2;
   S2: 4.32 nm2, 0.021, 3.99e-4 nm-2) with the cutoff qmax = 289 rad/um
   (``roughstick.fit_self_affine``);
2. three periodic Gaussian surfaces of 1280 x 1280 pixels are generated from it
   (``roughstick.generate_surfaces``, realizations 0, 1, 2 of the root seed below) and the
   top-left 1024 x 1024 window of each is kept, so the stored maps are not periodic, like
   measurements (attrs ``periodic = 0``);
3. heights are stored as CF NetCDF, quantised to int16 with ``scale_factor`` = 10 pm
   (like the integer counts of an AFM), zlib level 9 with byte shuffle.
"""

from __future__ import annotations

import argparse
import pathlib

import numpy as np
import xarray as xr

import roughstick as rs
from roughstick._core.conventions import ATTRS, append_history, dataset_attrs

HERE = pathlib.Path(__file__).resolve().parent
#: the maps are package data (roughstick.datasets); data_samples/S*.nc link to them
PACKAGE_DATA = HERE.parent / "roughstick" / "data"

#: Table 3 PSD moments (SI) and the cutoff of the paper
TARGETS = {
    "S1": {"m0": 15.7e-18, "m2": 0.040, "m4": 5.08e-4 * 1e18},
    "S2": {"m0": 4.32e-18, "m2": 0.021, "m4": 3.99e-4 * 1e18},
}
QMAX = 289e6  # rad m-1
SEEDS = {"S1": 20260101, "S2": 20260102}
SPACING = 5e-9  # m
SHAPE = 1024  # stored pixels per side
PARENT = 1280  # pixels per side of the periodic parent surface (cropped to SHAPE)
SCALE = 1e-11  # m per int16 count (10 pm)
ENCODING = {
    "dtype": "int16",
    "scale_factor": SCALE,
    "add_offset": 0.0,
    "_FillValue": np.int16(-32768),
    "zlib": True,
    "complevel": 9,
    "shuffle": True,
}


def sample_psd(name: str):
    """Eq. 37 parameters fitted to the Table 3 moments of sample ``name``; returns (fit, callable)."""
    fit = rs.fit_self_affine(**TARGETS[name], qmax=QMAX)
    params = {k: float(fit[k]) for k in ("s0", "s1", "q0", "qmax")}

    def psd(q):
        q = np.asarray(q, dtype=float)
        return rs.self_affine_psd(q.ravel(), **params).values.reshape(q.shape)

    return fit, params, psd


def make_set(name: str) -> dict[str, xr.Dataset]:
    """The three maps of sample ``name`` ('S1' or 'S2') as Datasets (float heights, before quantising)."""
    fit, params, psd = sample_psd(name)
    parent = rs.generate_surfaces(psd, n=3, shape=PARENT, spacing=SPACING, seed=SEEDS[name], chunks=1)
    out = {}
    for k, letter in enumerate("ABC"):
        h = parent.isel(realization=k, y=slice(0, SHAPE), x=slice(0, SHAPE)).drop_vars("realization")
        h = h.compute()
        h.attrs = {**ATTRS["height"], "periodic": 0}
        tag = f"{name}{letter}"
        ds = h.to_dataset(name="height")
        ds.attrs = dataset_attrs(
            f"Synthetic AFM map {tag} (stand-in for sample {name} of the paper)",
            references="paper Table 3, Eq. 37 and Eqs. 33-34; roughstick data_samples/README.md",
            comment=(
                "SYNTHETIC, not a measurement: a Gaussian random surface generated from the "
                f"self-affine PSD of Eq. 37 fitted to the Table 3 moments of sample {name}, "
                f"cropped from a {PARENT}x{PARENT} periodic surface, so periodic = 0."
            ),
            sample=name,
            seed=SEEDS[name],
            realization=k,
            psd_q0=params["q0"],
            psd_s0=params["s0"],
            psd_s1=params["s1"],
            psd_qmax=params["qmax"],
            target_m0=TARGETS[name]["m0"],
            target_m2=TARGETS[name]["m2"],
            target_m4=TARGETS[name]["m4"],
        )
        append_history(
            ds,
            f"data_samples/make_samples.py: generate_surfaces(seed={SEEDS[name]}) realization {k}, "
            f"{PARENT}x{PARENT} at {SPACING:g} m, cropped to {SHAPE}x{SHAPE}; int16 x {SCALE:g} m",
        )
        out[tag] = ds
    return out


def quantise(z: np.ndarray) -> np.ndarray:
    """Heights as stored: rounded to the int16 step (what a reader gets back)."""
    counts = np.round(z / SCALE)
    if np.abs(counts).max() >= 32767:
        raise ValueError("heights exceed the int16 range at this scale_factor; raise SCALE.")
    return counts * SCALE


def spline_moments(z: np.ndarray, spacing: float) -> tuple[float, float, float]:
    """m0, m2, m4 of a map: variance, and variances of cubic-spline first and second
    derivatives along x and y (averaged), as the paper's Table 2."""
    from scipy.interpolate import CubicSpline

    z = z - z.mean()
    t = np.arange(z.shape[1]) * spacing
    d1, d2 = [], []
    for arr in (z, z.T):
        cs = CubicSpline(t[: arr.shape[1]], arr, axis=1)
        d1.append(np.var(cs(t[: arr.shape[1]], 1)))
        d2.append(np.var(cs(t[: arr.shape[1]], 2)))
    return float(np.var(z)), float(np.mean(d1)), float(np.mean(d2))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare with the stored files")
    parser.add_argument("--out", type=pathlib.Path, default=PACKAGE_DATA)
    args = parser.parse_args(argv)
    print("map   m0 [nm2]  m2 [-]   m4 [nm-2]   (cubic-spline, stored int16 heights)  size")
    for name in ("S1", "S2"):
        fit, params, _ = sample_psd(name)
        print(f"{name}: Eq. 37 fit q0 = {params['q0'] / 1e6:.2f} rad/um, s0 = {params['s0'] * 1e36:.4g} nm4,"
              f" s1 = {params['s1'] * 1e36:.4g} nm4, exponent {float(fit.exponent):.3f}")
        for tag, ds in make_set(name).items():
            path = args.out / f"{tag}.nc"
            z = quantise(ds.height.values)
            if args.check:
                stored = xr.open_dataset(path).height.values
                err = np.abs(stored - z).max()
                print(f"{tag}: max |stored - regenerated| = {err:.3g} m")
                continue
            ds.to_netcdf(path, encoding={"height": ENCODING, "x": {"dtype": "float64"},
                                         "y": {"dtype": "float64"}}, engine="netcdf4")
            m0, m2, m4 = spline_moments(z, SPACING)
            print(f"{tag}  {m0 * 1e18:8.3f}  {m2:7.4f}  {m4 * 1e-18:10.4e}  "
                  f"{path.stat().st_size / 1e6:.2f} MB")


if __name__ == "__main__":
    main()
