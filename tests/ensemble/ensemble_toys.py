"""Stand-ins for the ensemble tests: a toy surface generator, a toy contact model and summary (so that the ensemble machinery is tested on its own), and helpers to compare runs."""

from __future__ import annotations

import numpy as np
import xarray as xr

import roughstick as rs
from roughstick._core.conventions import ATTRS
from roughstick._core.dask import realization_rng

SIGMA = 4e-9  # rms height of the toy surfaces [m]


def toy_psd(sigma=SIGMA, n=16, spacing=5e-9):
    """A flat (white) 2-D PSD with variance sigma**2 on an n x n grid (architecture.md normalisation)."""
    q = np.fft.fftshift(np.fft.fftfreq(n, spacing)) * 2 * np.pi
    dq = q[1] - q[0]
    s = np.full((n, n), sigma**2 / (n * n * dq * dq))
    return xr.DataArray(s, dims=("qy", "qx"), coords={"qy": q, "qx": q}, name="psd",
                        attrs=dict(ATTRS["psd"]))


def toy_generate(psd, *, n, shape, spacing, seed, chunks=None, **kw):
    """Smoothed Gaussian noise, realization k from realization_rng(seed, k); heights sum to zero."""
    m0 = float(psd.sum()) * float(psd.qx[1] - psd.qx[0]) ** 2
    out = np.empty((n,) + tuple(shape))
    for k in range(n):
        z = realization_rng(seed, k).standard_normal(shape)
        z = (z + np.roll(z, 1, 0) + np.roll(z, 1, 1) + np.roll(z, (1, 1), (0, 1))) / 2
        z -= z.mean()
        out[k] = z * np.sqrt(m0)
    h = rs.testing.make_topography(out, spacing=spacing, periodic=True).rename({"dim_0": "realization"})
    return h.assign_coords(realization=np.arange(n)).chunk({"realization": chunks or n})


def toy_curves(height, *, relative_humidity, distance, material=None, adsorbed_layer="paper", **kw):
    """A monotone toy of Eq. 16: linear 'Hertz' on the interference plus Laplace pressure on the wet area."""
    rh = rs.contact.as_relative_humidity(relative_humidity)
    hw = rs.contact.water_height(rh, adsorbed_layer=adsorbed_layer)
    dp = rs.contact.laplace_pressure(rh)
    z = height.stack(p=("y", "x"))
    contact = (z >= distance).mean("p")
    wet = (z >= distance - hw).mean("p") - contact
    rep = 2e11 * np.maximum(z - distance, 0).mean("p") / 1e-8
    ds = xr.Dataset({
        "pressure": rep + dp * wet,
        "repulsive_pressure": rep + 0 * rh,
        "wet_fraction": wet,
        "contact_fraction": contact + 0 * rh,
        "n_contacts": ((z >= distance).sum("p") + 0 * rh).astype(np.int64),
    })
    for v in ds.data_vars:
        ds[v].attrs = dict(ATTRS[v])
    return ds.transpose("realization", "rh", "distance")


def toy_summary(curves):
    p = curves["pressure"]
    d = curves["distance"]
    neg = np.minimum(p, 0)
    gamma = -neg.integrate("distance")
    eq = d.where((p.shift(distance=1) > 0) & (p <= 0)).max("distance")  # approx: sign change
    out = xr.Dataset({
        "adhesive_energy": gamma.assign_attrs(ATTRS["surface_adhesive_energy"]),
        "pull_off_pressure": (-neg.min("distance")).assign_attrs(ATTRS["pull_off_pressure"]),
        "equilibrium_distance": eq.assign_attrs(ATTRS["equilibrium_distance"]),
    })
    return out


TOY = dict(generate=toy_generate, curves=toy_curves, summary=toy_summary)


RH = [0.3, 0.5, 0.7, 0.9]


def toy_run(n=6, shape=(16, 16), chunks=2, **kw):
    kw = {**TOY, **kw}
    return rs.ensemble.run(toy_psd(), n=n, shape=shape, spacing=5e-9, relative_humidity=kw.pop("rh", RH),
                           seed=kw.pop("seed", 3), chunks=chunks, **kw)


def values(ds):
    return {v: ds[v].values for v in ds.data_vars}


def assert_same_values(a, b):
    assert sorted(a.data_vars) == sorted(b.data_vars)
    for v in a.data_vars:
        np.testing.assert_array_equal(a[v].values, b[v].transpose(*a[v].dims).values, err_msg=v)
    for c in ("realization", "rh", "distance"):
        np.testing.assert_array_equal(a[c].values, b[c].values)
