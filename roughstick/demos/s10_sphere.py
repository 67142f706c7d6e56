"""Demo step: meniscus physics and the sphere contact models (paper §2, Fig. 1b, Fig. 3, Table 1).

Writes into ``out``:

- ``fig1b_meniscus.png``: Laplace pressure and water height against RH (Eqs. 2 and 6);
- ``fig3_sphere_models.png`` and ``sphere_curves.nc``: force-interference curves of the Maugis,
  DMT and modified DMT models for R = 100 and 800 nm at RH 30, 50 and 70 %;
- ``table1.nc`` and ``table1.csv``: the adhesive energies of Table 1, computed and printed,
  with their relative differences.
"""

from __future__ import annotations

import pathlib

import numpy as np
import xarray as xr

import roughstick as rs

from .._core.conventions import append_history, dataset_attrs, set_coord_attrs
from .._core.references import cite
from ..io.netcdf import write, write_text_atomic
from ..plotting.save import save_figure
from ..plotting.sphere import plot_meniscus, plot_sphere_curves

MODELS = ["maugis", "dmt", "modified_dmt"]
RADII = [100e-9, 800e-9]
RHS = [0.3, 0.5, 0.7]
#: Table 1 of the paper [J], (model, radius, rh).
TABLE1_PRINTED = {
    "maugis": [[5.11e-17, 8.07e-17, 3.72e-16], [4.75e-16, 7.25e-16, 3.14e-15]],
    "dmt": [[5.11e-17, 8.05e-17, 3.68e-16], [4.95e-16, 7.32e-16, 3.16e-15]],
    "modified_dmt": [[5.18e-17, 8.08e-17, 3.68e-16], [5.22e-16, 7.49e-16, 3.18e-15]],
}


def _coord(name, values, units, long_name):
    return xr.DataArray(np.asarray(values), dims=(name,), attrs={"units": units, "long_name": long_name})


def table1() -> xr.Dataset:
    """Table 1 computed by :func:`roughstick.sphere_adhesive_energy` next to the printed values."""
    radius = xr.DataArray(RADII, dims="radius", coords={"radius": RADII}, attrs={"units": "m"})
    rh = xr.DataArray(RHS, dims="rh", coords={"rh": RHS}, attrs={"units": "1"})
    computed = xr.concat(
        [rs.sphere_adhesive_energy(model=m, radius=radius, relative_humidity=rh) for m in MODELS],
        dim=_coord("model", MODELS, "1", "sphere contact model"),
    )
    computed.attrs = {"units": "J", "long_name": "adhesive energy computed by roughstick"}
    printed = xr.DataArray(
        np.array([TABLE1_PRINTED[m] for m in MODELS]), dims=("model", "radius", "rh"),
        coords=computed.coords, attrs={"units": "J", "long_name": "adhesive energy printed in Table 1"},
    )
    rel = (computed - printed) / printed
    rel.attrs = {"units": "1", "long_name": "relative difference (computed - printed) / printed"}
    ds = xr.Dataset({"adhesive_energy": computed, "printed": printed, "relative_error": rel})
    ds["transition_parameter"] = rs.transition_parameter(radius=radius, relative_humidity=rh)
    ds["model"].attrs = {"units": "1", "long_name": "sphere contact model"}
    set_coord_attrs(ds)
    ds.attrs = dataset_attrs("Table 1: adhesive energy of a poly-Si sphere on a poly-Si flat",
                             references=cite("maugis1992"))
    return append_history(ds, "roughstick.demos.s10_sphere.table1()")


def curves(n: int = 1401) -> xr.Dataset:
    """Force-interference curves of Fig. 3 as a Dataset over (model, radius, rh, interference)."""
    h_max = float(rs.water_height(max(RHS)))
    d = np.linspace(-1.3 * h_max, 2.5e-9, n)
    force = xr.concat(
        [rs.sphere_force(d, model=m, radius=RADII, relative_humidity=RHS) for m in MODELS],
        dim=_coord("model", MODELS, "1", "sphere contact model"),
    )
    ds = force.to_dataset(name="force")
    ds = ds.reset_coords(["contact_radius", "adhesive_radius"])
    ds["contact_radius"].attrs = dict(rs.conventions.ATTRS["contact_radius"])
    ds["adhesive_radius"].attrs = dict(rs.conventions.ATTRS["adhesive_radius"])
    ds["force"].attrs = dict(rs.conventions.ATTRS["force"])
    ds["water_height"] = rs.water_height(ds["rh"].values).assign_coords(rh=ds["rh"])
    ds["laplace_pressure"] = rs.laplace_pressure(ds["rh"].values).assign_coords(rh=ds["rh"])
    ds["model"].attrs = {"units": "1", "long_name": "sphere contact model"}
    set_coord_attrs(ds)
    ds.attrs = dataset_attrs("Fig. 3: force-interference curves of a poly-Si sphere on a flat",
                             references="see docs/sphere_models.md", branch="retraction")
    return append_history(ds, "roughstick.demos.s10_sphere.curves()")


def run(out, *, quick: bool = False) -> list[pathlib.Path]:
    """Write Fig. 1b, Fig. 3, the curves and Table 1 into ``out``; return the file paths."""
    import matplotlib

    matplotlib.use("Agg")


    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    files = []

    rh = np.linspace(0.05, 0.95, 46 if quick else 181)
    ax, _ = plot_meniscus(rs.laplace_pressure(rh), rs.water_height(rh))
    p = out / "fig1b_meniscus.png"
    files.append(save_figure(ax.figure, p, dpi=120, bbox_inches="tight"))

    ds = curves(n=401 if quick else 1401)
    p = out / "sphere_curves.nc"
    write(ds, p, compute=True)
    files.append(p)
    axes = plot_sphere_curves(ds)
    p = out / "fig3_sphere_models.png"
    files.append(save_figure(axes[0, 0].figure, p, dpi=120, bbox_inches="tight"))

    t1 = table1()
    p = out / "table1.nc"
    write(t1, p, compute=True)
    files.append(p)
    p = out / "table1.csv"
    write_text_atomic(p, t1[["adhesive_energy", "printed", "relative_error"]].to_dataframe().to_csv())
    files.append(p)
    return files
