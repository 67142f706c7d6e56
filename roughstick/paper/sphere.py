"""Meniscus physics and the sphere contact models, paper §2: Fig. 1b, Fig. 3 and Table 1.

The figure functions return ``(Dataset, Figure)``; :func:`table1` and :func:`curves` the data.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

import roughstick as rs

from .._core.conventions import append_history, dataset_attrs, set_coord_attrs
from .._core.references import cite
from ..plotting.sphere import plot_meniscus, plot_sphere_curves

__all__ = ["MODELS", "RADII", "RHS", "TABLE1_PRINTED", "table1", "curves", "fig1b_meniscus",
           "fig3_sphere_models"]

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
    """Table 1 computed by :func:`roughstick.contact.sphere_adhesive_energy` next to the printed values."""
    radius = xr.DataArray(RADII, dims="radius", coords={"radius": RADII}, attrs={"units": "m"})
    rh = xr.DataArray(RHS, dims="rh", coords={"rh": RHS}, attrs={"units": "1"})
    computed = xr.concat(
        [rs.contact.sphere_adhesive_energy(sphere_model=m, radius=radius, relative_humidity=rh) for m in MODELS],
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
    ds["transition_parameter"] = rs.contact.transition_parameter(radius=radius, relative_humidity=rh)
    ds["model"].attrs = {"units": "1", "long_name": "sphere contact model"}
    set_coord_attrs(ds)
    ds.attrs = dataset_attrs("Table 1: adhesive energy of a poly-Si sphere on a poly-Si flat",
                             references=cite("maugis1992"))
    return append_history(ds, "roughstick.paper.sphere.table1()")


def curves(n: int = 1401) -> xr.Dataset:
    """Force-interference curves of Fig. 3 as a Dataset over (model, radius, rh, interference)."""
    h_max = float(rs.contact.water_height(max(RHS)))
    d = np.linspace(-1.3 * h_max, 2.5e-9, n)
    force = xr.concat(
        [rs.contact.sphere_force(d, sphere_model=m, radius=RADII, relative_humidity=RHS) for m in MODELS],
        dim=_coord("model", MODELS, "1", "sphere contact model"),
    )
    ds = force.to_dataset(name="force")
    ds = ds.reset_coords(["contact_radius", "adhesive_radius"])
    ds["contact_radius"].attrs = dict(rs.conventions.ATTRS["contact_radius"])
    ds["adhesive_radius"].attrs = dict(rs.conventions.ATTRS["adhesive_radius"])
    ds["force"].attrs = dict(rs.conventions.ATTRS["force"])
    ds["water_height"] = rs.contact.water_height(ds["rh"].values).assign_coords(rh=ds["rh"])
    ds["laplace_pressure"] = rs.contact.laplace_pressure(ds["rh"].values).assign_coords(rh=ds["rh"])
    ds["model"].attrs = {"units": "1", "long_name": "sphere contact model"}
    set_coord_attrs(ds)
    ds.attrs = dataset_attrs("Fig. 3: force-interference curves of a poly-Si sphere on a flat",
                             references="see docs/sphere_models.md", branch="retraction")
    return append_history(ds, "roughstick.paper.sphere.curves()")


def fig1b_meniscus(*, n: int = 181):
    """Fig. 1b: Laplace pressure (Eq. 2) and water height (Eq. 6) against RH.

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
    """
    rh = np.linspace(0.05, 0.95, n)
    p, h = rs.contact.laplace_pressure(rh), rs.contact.water_height(rh)
    ax, _ = plot_meniscus(p, h)
    ds = xr.Dataset({"laplace_pressure": p, "water_height": h})
    return ds, ax.figure


def fig3_sphere_models(*, n: int = 1401):
    """Fig. 3: force-interference curves of the Maugis, DMT and modified DMT models.

    Returns
    -------
    (xarray.Dataset, matplotlib.figure.Figure)
        :func:`curves` and the figure.
    """
    ds = curves(n=n)
    axes = plot_sphere_curves(ds)
    return ds, np.asarray(axes).flat[0].figure
