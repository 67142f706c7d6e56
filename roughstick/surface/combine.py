r"""PSDs of maps of different sizes or spacings averaged on a common q grid (Eq. 31).

:func:`roughstick.surface.average_psd` averages spectra on one grid; maps of different scan sizes or
pixel sizes (e.g. a 1 µm and a 10 µm scan of one sample) have different q grids and bands
:math:`[2\pi/L, \pi/\Delta]`. :func:`average_psd_common` interpolates each onto one
log-spaced grid over the bands' overlap (or union) and records which maps each q averages.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .._core.conventions import append_history, dataset_attrs, set_attrs
from .._core.references import PAPER, cite
from .._core.validate import check_core_not_chunked
from .spectrum import _units_psd, psd_isotropic

__all__ = ["average_psd_common"]


def _band(s, dim):
    q = np.asarray(s[dim].values, dtype=float)
    if np.any(np.diff(q) <= 0):
        raise ValueError(f"coordinate {dim!r} must be ascending; use psd.sortby({dim!r}).")
    pos = q > 0
    if pos.sum() < 2:
        raise ValueError(f"a PSD needs at least 2 samples at {dim} > 0 to be interpolated.")
    return q[pos], s.isel({dim: np.flatnonzero(pos)})


def _loglog_interp(row, q, grid):
    """Linear in (log q, log s); zero samples stay zero; NaN outside [q[0], q[-1]]."""
    tiny = np.finfo(float).tiny
    v = np.exp(np.interp(np.log(grid), np.log(q), np.log(np.maximum(row, tiny))))
    v = np.where(v <= tiny * 1.0001, 0.0, v)
    rel = 1e-9  # the band's own end points, to round-off
    return np.where((grid >= q[0] * (1 - rel)) & (grid <= q[-1] * (1 + rel)), v, np.nan)


def average_psd_common(psds, *, band: str = "overlap", n_q: int | None = None, names=None) -> xr.Dataset:
    r"""Average PSDs of maps of different sizes or spacings on a common log-spaced q grid (Eq. 31).

    Each PSD is interpolated linearly in :math:`(\log q, \log s)` (exact for a power law between
    samples) onto the common grid, within its own band :math:`[2\pi/L, q_{Nyquist}]` (its first
    positive and its last ``q``), NaN outside it; the average at each ``q`` is over the maps
    whose band covers it.

    Parameters
    ----------
    psds : sequence of xarray.DataArray
        Isotropic PSDs ``psd`` [m4] over ``(..., q)`` (:func:`psd_isotropic`; a 2D PSD over
        ``(qy, qx)`` is radially averaged first), or profile PSDs [m3] over ``(..., qx)``
        (:func:`roughstick.surface.profile_psd`: the positive ``qx``, so the result is one-sided). Leading
        dims must agree.
    band : {"overlap", "union"}
        The common grid spans the wave numbers every map covers (default), or any map covers
        (then ``n_maps`` varies with ``q``).
    n_q : int, optional
        Number of grid points; default: the most samples any map has inside the common band.
    names : sequence of str, optional
        Labels of the maps (the ``map`` coordinate); default ``0, 1, ...``.

    Returns
    -------
    xarray.Dataset
        ``psd`` over ``(..., q)`` (or ``qx``) with the input's units, ``n_maps`` (maps averaged
        at each q), ``contributed`` ``(map, q)`` (1 where that map's band covers q), ``q_min``
        and ``q_max`` ``(map,)`` (each map's band).

    Raises
    ------
    ValueError
        Fewer than one PSD, mixed kinds, or (``band="overlap"``) bands that do not overlap.

    Examples
    --------
    >>> q1, q2 = np.linspace(0, 1e9, 65), np.linspace(0, 4e8, 129)
    >>> s = [xr.DataArray(1e-40 * np.maximum(q, 1e6) ** -3.0, dims="q", coords={"q": q},
    ...                   attrs={"units": "m4"}, name="psd") for q in (q1, q2)]
    >>> ds = rs.surface.average_psd_common(s)
    >>> float(ds.q[0]), float(ds.q[-1]), int(ds.n_maps.min())
    (15625000.0, 400000000.0, 2)
    """
    if band not in ("overlap", "union"):
        raise ValueError(f"band must be 'overlap' or 'union', got {band!r}.")
    psds = list(psds) if isinstance(psds, (list, tuple)) else [psds]
    if not psds or not all(isinstance(s, xr.DataArray) for s in psds):
        raise TypeError("psds must be a non-empty sequence of PSD DataArrays.")
    names = [str(i) for i in range(len(psds))] if names is None else [str(n) for n in names]
    if len(names) != len(psds):
        raise ValueError(f"{len(names)} names for {len(psds)} PSDs.")
    prepared = []
    for s in psds:
        if {"qx", "qy"} <= set(s.dims):
            s = psd_isotropic(s)
        if "q" in s.dims:
            prepared.append(("q", _units_psd(s)))
        elif "qx" in s.dims:
            if s.attrs.get("units") != "m3":
                raise ValueError(f"a profile PSD has units 'm3', got {s.attrs.get('units')!r}.")
            prepared.append(("qx", s))
        else:
            raise ValueError(f"a PSD has dims {s.dims}; expected (..., 'q'), (..., 'qy', 'qx') or (..., 'qx').")
    kinds = {d for d, _ in prepared}
    if len(kinds) > 1:
        raise ValueError("cannot average isotropic (surface) PSDs with profile (line-scan) PSDs: "
                         "their units differ (m4 vs m3); project the surfaces' PSDs first with "
                         "roughstick.surface.project_psd.")
    dim = kinds.pop()
    bands = [_band(s, dim) for _, s in prepared]
    lo = [q[0] for q, _ in bands]
    hi = [q[-1] for q, _ in bands]
    q0, q1 = (max(lo), min(hi)) if band == "overlap" else (min(lo), max(hi))
    if q0 >= q1:
        spans = "; ".join(f"{n}: {a:.4g}-{b:.4g} rad m-1" for n, a, b in zip(names, lo, hi))
        raise ValueError(f"the PSDs' wave-number bands do not overlap ({spans}), so no q is covered "
                         "by every map; pass band='union' to average each q over the maps that "
                         "cover it, or drop the maps outside the others' band.")
    if n_q is None:
        n_q = max(int(((q >= q0) & (q <= q1)).sum()) for q, _ in bands)
    if int(n_q) < 2:
        raise ValueError(f"n_q must be at least 2, got {n_q}.")
    grid = np.geomspace(q0, q1, int(n_q))
    grid[0], grid[-1] = q0, q1
    rows = []
    for q, s in bands:
        check_core_not_chunked(s, [dim])
        out = xr.apply_ufunc(
            lambda a, q=q: np.apply_along_axis(_loglog_interp, -1, np.asarray(a, float), q, grid),
            s, input_core_dims=[[dim]], output_core_dims=[["__q"]], dask="forbidden",
        )
        rows.append(out.rename(__q=dim).assign_coords({dim: grid}))
    stack = xr.concat(rows, dim="map", join="exact", coords="minimal", compat="override",
                      combine_attrs="drop").assign_coords(map=names)
    covered = xr.DataArray(
        np.array([(grid >= a * (1 - 1e-9)) & (grid <= b * (1 + 1e-9)) for a, b in zip(lo, hi)], dtype="int8"),
        dims=("map", dim), coords={"map": names, dim: grid})
    gap = covered.sum("map").values == 0
    if gap.any():  # band="union" over disjoint bands: a hole no map covers
        raise ValueError(f"no map covers {dim} = {grid[gap][0]:.4g}-{grid[gap][-1]:.4g} rad m-1 (a gap "
                         "between the maps' bands); average the maps on each side separately, or add a "
                         "scan whose size and pixel size cover the gap.")
    key = "psd_1d" if dim == "qx" else "psd_isotropic"
    mean = set_attrs(stack.mean("map", skipna=True).rename("psd"), key,
                     **({"kind": "profile"} if dim == "qx" else {}))
    ds = xr.Dataset({
        "psd": mean,
        "n_maps": covered.sum("map").astype("int32").assign_attrs(
            units="1", long_name="number of maps averaged at this wave number"),
        "contributed": covered.assign_attrs(
            units="1", long_name="the map's band covers this wave number", flag_values=np.array([0, 1], "int8"),
            flag_meanings="outside_band averaged"),
        "q_min": xr.DataArray(lo, dims="map", attrs={"units": "rad m-1", "long_name": "smallest positive wave number of the map (2 pi / L)"}),
        "q_max": xr.DataArray(hi, dims="map", attrs={"units": "rad m-1", "long_name": "largest wave number of the map"}),
    })
    ds["map"].attrs = {"long_name": "map (label of the averaged PSD)"}
    ds.attrs = dataset_attrs(title="PSD averaged over maps on a common q grid", band=band,
                             references=cite((PAPER, "Eq. 31")))
    return append_history(ds, f"average_psd_common: {len(psds)} PSDs on {n_q} log-spaced {dim} in "
                              f"[{q0:.4g}, {q1:.4g}] rad m-1 ({band})")
