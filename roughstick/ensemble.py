"""Monte Carlo ensembles (paper §4.3, Figs. 14-17): PSD → surfaces → curves → summaries → bands.

:func:`run_ensemble` builds the lazy pipeline ``generate_surfaces`` → ``rough_contact_curves`` →
``adhesion_summary`` as one Dataset over ``(realization, rh, distance)`` and ``(realization, rh)``,
chunked over realization and humidity; nothing is computed until asked. Realization ``k`` is
always generated from the same ``SeedSequence`` child (:func:`roughstick._core.dask.realization_rng`),
so results do not depend on the chunking, the scheduler or the number of workers.

With ``output=folder`` the run streams one CF NetCDF file per block into ``folder`` as blocks
complete (see :mod:`roughstick.io.netcdf`) and resumes from what is there when restarted with
the same parameters. With ``n="auto"`` realizations are added in batches until the 95 % band of
Γ and of the pressure curve stops moving.

:func:`confidence_band` reduces over realizations to the mean and a quantile band, with the
band's own sampling uncertainty (order-statistic or bootstrap intervals);
:func:`ensemble_histogram` and :func:`ensemble_ecdf` give the distributions of Fig. 17.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import pathlib
import sys
import time
import warnings
from collections.abc import Callable, Sequence

import numpy as np
import xarray as xr

from ._core.conventions import ATTRS, append_history, dataset_attrs
from ._core.dask import as_seed_sequence
from ._core.references import PAPER, cite
from ._core.validate import distance_array, relative_humidity_array
from ._core.version import __version__

__all__ = [
    "run_ensemble",
    "ensemble_distance_grid",
    "surface_size_study",
    "confidence_band",
    "quantile_interval",
    "ensemble_histogram",
    "ensemble_ecdf",
    "progress_bar",
]

REFERENCES = cite((PAPER, "sections 4.2-4.3, Eqs. 13, 16-23, 33-34"))
_CURVE_DIMS = ("realization", "rh", "distance")


# ============================================================================ helpers
def _psd_m0(psd: xr.DataArray) -> float:
    """Height variance m0 [m2] of a 2-D ``(qy, qx)`` or isotropic ``(q)`` PSD (architecture.md)."""
    if "qx" in psd.dims and "qy" in psd.dims:
        qx = np.asarray(psd["qx"].values, float)
        qy = np.asarray(psd["qy"].values, float)
        # the PSD is a small input, read eagerly on purpose (the grid must be known up front)
        arr = np.asarray(psd.transpose(..., "qy", "qx").values, float).reshape(-1, qy.size, qx.size)
        return float(np.nansum(arr.mean(axis=0)) * abs(qx[1] - qx[0]) * abs(qy[1] - qy[0]))
    if "q" in psd.dims:
        q = np.asarray(psd["q"].values, float)
        arr = np.asarray(psd.transpose(..., "q").data, float).reshape(-1, q.size).mean(axis=0)
        return float(2 * np.pi * np.trapezoid(np.nan_to_num(arr) * q, q))
    raise ValueError(
        f"psd must have dims ('qy', 'qx') or ('q',); got {psd.dims}. Build one with "
        "roughstick.power_spectrum / average_psd or roughstick.fit_self_affine."
    )


def _water_heights(rh: np.ndarray, adsorbed_layer) -> np.ndarray:
    from .contact.meniscus import water_height

    return np.asarray(water_height(rh, adsorbed_layer=adsorbed_layer).values, float)


def _resolve_shape(shape, size, spacing) -> tuple[int, int]:
    if (shape is None) == (size is None):
        raise ValueError("give exactly one of shape=(ny, nx) (pixels) or size=(Ly, Lx) (m).")
    if shape is not None:
        shp = (int(shape), int(shape)) if np.ndim(shape) == 0 else tuple(int(s) for s in shape)
        if np.ndim(shape) == 0 and int(shape) != shape or any(
            s != o for s, o in zip(shp, np.atleast_1d(shape), strict=False)
        ):
            raise ValueError(f"shape must be integers, got {shape!r}.")
    else:
        sz = (float(size), float(size)) if np.ndim(size) == 0 else tuple(float(s) for s in size)
        shp = tuple(int(round(s / spacing)) for s in sz)
        for s, n in zip(sz, shp, strict=True):
            if n < 1 or not math.isclose(n * spacing, s, rel_tol=1e-6):
                raise ValueError(
                    f"size {s!r} m is not a whole number of pixels of spacing {spacing!r} m; "
                    f"use size={n * spacing!r} or give shape= instead."
                )
    if len(shp) != 2 or min(shp) < 4:
        raise ValueError(f"surface shape must be two integers >= 4, got {shp}.")
    return shp


def ensemble_distance_grid(
    psd=None,
    *,
    shape,
    n: int,
    relative_humidity,
    adsorbed_layer="paper",
    m0: float | None = None,
    num: int | None = None,
    lower: float = 1.5,
    exceedance: float = 1e-6,
    points_per_water_height: float = 10.0,
) -> xr.DataArray:
    r"""A distance grid common to every realization of an ensemble.

    The top of the grid is first water contact of the highest surface one can expect in the whole
    ensemble: a union (Bonferroni) bound over all ``n * ny * nx`` Gaussian heights gives a height
    :math:`z_\max = \sqrt{m_0}\,\Phi^{-1}(1 - \epsilon / (n\,n_y n_x))` that any pixel exceeds with
    probability below ``exceedance`` :math:`\epsilon`, and :math:`d_\max = z_\max + \max h_{water}`.
    The bottom, ``lower`` :math:`\sqrt{m_0}`, lies below the equilibrium distances the paper reports
    (2.6 to 6.2 :math:`\sqrt{m_0}`, §4.3.2). The grid is uniform; by default its step is the
    smallest water height divided by ``points_per_water_height`` (the attractive part of a curve at
    low RH is about one water height wide), with 100 to 2000 points. Γ (Eq. 13) converges as the
    step shrinks (tested against a 4x finer grid). :func:`run_ensemble` checks both ends for every
    realization and raises if a surface pokes above the top or a curve is still attractive at the
    bottom.

    Parameters
    ----------
    psd : xarray.DataArray, optional
        PSD (2-D or isotropic) giving :math:`m_0`; or pass ``m0``.
    shape : tuple of int
        Surface shape (ny, nx).
    n : int
        Number of realizations.
    relative_humidity : sequence of float
        Humidities (fractions) of the run.
    adsorbed_layer : {"paper", "none"} or callable
        Adsorbed-layer model (:func:`roughstick.water_height`).
    m0 : float, optional
        Height variance [m2], instead of ``psd``.
    num : int, optional
        Number of grid points (overrides ``points_per_water_height``).
    lower : float, default 1.5
        Bottom of the grid in units of :math:`\sqrt{m_0}`.
    exceedance : float, default 1e-6
        Probability that some pixel of the ensemble exceeds the grid's top.
    points_per_water_height : float, default 10
        Grid points per smallest water height :math:`h_{water}` of the run (when ``num`` is None).

    Returns
    -------
    xarray.DataArray
        ``distance`` coordinate [m], ascending.

    Examples
    --------
    >>> d = rs.ensemble_distance_grid(m0=16e-18, shape=(64, 64), n=10, relative_humidity=[0.5])
    >>> d.sizes["distance"], round(float(d[0]) * 1e9, 2), round(float(d[-1]) * 1e9, 2)
    (144, 6.0, 27.83)
    """
    from scipy.stats import norm

    if m0 is None:
        if psd is None:
            raise ValueError("give psd= or m0= to ensemble_distance_grid.")
        m0 = _psd_m0(psd)
    if not (m0 > 0 and np.isfinite(m0)):
        raise ValueError(f"height variance m0 must be positive and finite, got {m0!r}.")
    if num is not None and int(num) < 2:
        raise ValueError(f"num must be >= 2, got {num!r}.")
    rh = relative_humidity_array(relative_humidity)
    sigma = math.sqrt(m0)
    npix = int(np.prod(shape)) * max(int(n), 1)
    z_top = sigma * float(norm.isf(exceedance / npix))
    hw = _water_heights(rh, adsorbed_layer)
    d_max = z_top + float(np.max(hw))
    d_min = lower * sigma
    if d_min >= d_max:
        raise ValueError(f"lower={lower} sqrt(m0) is above the grid's top; use a smaller lower.")
    if num is None:
        step = float(np.min(hw)) / float(points_per_water_height)
        num = int(np.clip(math.ceil((d_max - d_min) / step) + 1, 100, 2000))
    d = np.linspace(d_min, d_max, int(num))
    return xr.DataArray(
        d, dims="distance", coords={"distance": d}, name="distance", attrs=dict(ATTRS["distance"])
    ).pipe(lambda a: a.assign_coords(distance=a.distance.assign_attrs(ATTRS["distance"])))


# ============================================================================ the spec
@dataclasses.dataclass(frozen=True, eq=False)
class _Spec:
    psd: xr.DataArray
    shape: tuple[int, int]
    spacing: float
    rh: np.ndarray
    distance: np.ndarray
    seed: np.random.SeedSequence
    chunk: int
    rh_chunk: int
    adsorbed_layer: object
    material: object
    generate: Callable
    curves: Callable
    summary: Callable
    generate_kwargs: dict
    curves_kwargs: dict
    water_max: float
    token: str

    def rh_blocks(self):
        r = self.rh.size
        return [(j, lo, min(lo + self.rh_chunk, r)) for j, lo in enumerate(range(0, r, self.rh_chunk))]

    def realization_blocks(self, start, stop):
        """Blocks [a, b) aligned on multiples of ``chunk`` (index i = a // chunk)."""
        out = []
        a = start
        while a < stop:
            b = min((a // self.chunk + 1) * self.chunk, stop)
            out.append((a // self.chunk, a, b))
            a = b
        return out


def _callable_id(f) -> str:
    return f"{getattr(f, '__module__', '?')}.{getattr(f, '__qualname__', repr(f))}"


def _hash_params(spec_fields: dict) -> str:
    h = hashlib.sha256()
    psd = spec_fields["psd"]
    h.update(np.ascontiguousarray(np.asarray(psd.data, dtype=float)).tobytes())
    for c in sorted(psd.coords):
        h.update(c.encode())
        h.update(np.ascontiguousarray(np.asarray(psd[c].values, dtype=float)).tobytes())
    h.update(np.ascontiguousarray(spec_fields["distance"]).tobytes())
    h.update(np.ascontiguousarray(spec_fields["rh"]).tobytes())
    rest = {
        k: spec_fields[k]
        for k in ("shape", "spacing", "chunk", "rh_chunk", "seed_entropy", "seed_spawn_key")
    }
    rest["version"] = __version__
    rest["adsorbed_layer"] = (
        spec_fields["adsorbed_layer"]
        if isinstance(spec_fields["adsorbed_layer"], str)
        else _callable_id(spec_fields["adsorbed_layer"])
    )
    rest["material"] = repr(spec_fields["material"])
    rest["functions"] = [_callable_id(spec_fields[k]) for k in ("generate", "curves", "summary")]
    rest["kwargs"] = repr(sorted(spec_fields["generate_kwargs"].items())) + repr(
        sorted(spec_fields["curves_kwargs"].items())
    )
    h.update(json.dumps(rest, sort_keys=True, default=str).encode())
    return h.hexdigest()[:24]


# ============================================================================ one block
def _surfaces(spec: _Spec, start: int, stop: int) -> xr.DataArray:
    import inspect

    gen = spec.generate
    try:
        params = inspect.signature(gen).parameters
    except (TypeError, ValueError):  # pragma: no cover
        params = {}
    kw = dict(spec.generate_kwargs)
    if "realizations" in params:
        h = gen(spec.psd, realizations=np.arange(start, stop), shape=spec.shape,
                spacing=spec.spacing, seed=spec.seed, **kw)
    else:
        # realizations [start, stop) form exactly the last chunk of an n=stop ensemble chunked by
        # (stop - start) when start is a multiple of it; else generate [0, stop) and slice.
        c = stop - start
        chunks = c if start % c == 0 else stop
        h = gen(spec.psd, n=stop, shape=spec.shape, spacing=spec.spacing, seed=spec.seed,
                chunks=chunks, **kw)
        h = h.isel(realization=slice(start, stop))
    if h.chunks is not None:
        h = h.compute(scheduler="sync")
    return h


def _block(spec: _Spec, start: int, stop: int, rh_lo: int, rh_hi: int) -> xr.Dataset:
    """Compute realizations [start, stop) at humidities rh[rh_lo:rh_hi] (numpy in, numpy out)."""
    from .contact.meniscus import as_relative_humidity

    h = _surfaces(spec, start, stop)
    top = h.max(("y", "x")) - h.mean(("y", "x"))  # d is measured from the mean plane (Eq. 16)
    hw = spec.water_max
    if float(top.max()) + hw > spec.distance[-1] * (1 + 1e-12):
        k = int(np.argmax(np.asarray(top.values)))
        raise ValueError(
            f"realization {int(h.realization[k])}: highest point {float(top[k]) * 1e9:.3f} nm plus the "
            f"water height {hw * 1e9:.3f} nm lies above the top of the common distance grid "
            f"({spec.distance[-1] * 1e9:.3f} nm). Pass distance= reaching higher, or a smaller "
            "exceedance to ensemble_distance_grid."
        )
    rh = as_relative_humidity(spec.rh[rh_lo:rh_hi])
    dist = xr.DataArray(spec.distance, dims="distance", coords={"distance": spec.distance},
                        attrs=dict(ATTRS["distance"]))
    parts = []
    for k in range(h.sizes["realization"]):
        # one realization at a time: its numbers cannot depend on which block it falls in
        hk = h.isel(realization=[k])
        curves = spec.curves(hk, relative_humidity=rh, distance=dist, material=spec.material,
                             adsorbed_layer=spec.adsorbed_layer, **spec.curves_kwargs)
        if isinstance(curves, xr.DataArray):
            curves = curves.to_dataset(name=curves.name or "pressure")
        summary = spec.summary(curves)
        parts.append(xr.merge([curves, summary], compat="override", combine_attrs="drop_conflicts"))
    ds = parts[0] if len(parts) == 1 else xr.concat(
        parts, "realization", data_vars="minimal", coords="minimal", compat="override",
        combine_attrs="drop_conflicts")
    ds["max_height"] = top.assign_attrs(ATTRS["max_height"])
    if "pressure" in ds:
        p_low = ds["pressure"].isel(distance=0)
        bad = p_low < 0
        if bool(bad.any()):
            idx = np.argwhere(np.asarray(bad.transpose("realization", "rh").values))[0]
            raise ValueError(
                f"realization {start + int(idx[0])} at RH {float(rh[idx[1]]):.3g}: the mean pressure is "
                f"still attractive ({float(p_low.transpose('realization', 'rh')[tuple(idx)]):.4g} Pa) at "
                f"the bottom of the distance grid ({spec.distance[0] * 1e9:.3f} nm), so Γ (Eq. 13) would "
                "be cut short. Pass distance= reaching lower, or a smaller lower= to "
                "ensemble_distance_grid."
            )
    out = {}
    for name, var in ds.data_vars.items():
        order = [d for d in _CURVE_DIMS if d in var.dims] + [d for d in var.dims if d not in _CURVE_DIMS]
        out[name] = var.transpose(*order)
    res = xr.Dataset(out).drop_vars([c for c in ds.coords if c not in ("realization", "rh", "distance")],
                                    errors="ignore")
    res = res.assign_coords(realization=np.arange(start, stop), rh=spec.rh[rh_lo:rh_hi],
                            distance=spec.distance)
    for c in ("realization", "rh", "distance"):
        res[c].attrs = dict(ATTRS[c])
    return res


def _pick(block: xr.Dataset, name: str) -> np.ndarray:
    return np.asarray(block[name].data)


def _discard(_):
    return None


# ============================================================================ lazy assembly
def _template(spec: _Spec) -> xr.Dataset:
    """Run the pipeline on a tiny synthetic egg-box surface to learn variable names/dims/dtypes."""
    from .testing import make_topography

    n = 16
    x = np.arange(n) * 2 * np.pi / 8
    sigma = math.sqrt(max(_psd_m0(spec.psd), 1e-30))
    z = 2 * sigma * np.sin(x)[None, :] * np.sin(x)[:, None]
    h = make_topography(z, spacing=spec.spacing, periodic=True).expand_dims(realization=[0])
    h.attrs["periodic"] = 1
    probe = dataclasses.replace(spec, generate=lambda *a, **k: h)
    try:
        return _block(probe, 0, 1, 0, 1)
    except ValueError:
        return _block(dataclasses.replace(probe, distance=spec.distance + 10 * sigma), 0, 1, 0, 1)


def _lazy(spec: _Spec, start: int, stop: int) -> xr.Dataset:
    import dask
    import dask.array as dsa

    tmpl = _template(spec)
    spec_d = dask.delayed(spec, pure=True, name=f"roughstick-ensemble-spec-{spec.token}")
    rblocks = spec.realization_blocks(start, stop)
    hblocks = spec.rh_blocks()
    blocks = {}
    for i, a, b in rblocks:
        for j, lo, hi in hblocks:
            blocks[i, j] = dask.delayed(_block, pure=True)(
                spec_d, a, b, lo, hi, dask_key_name=f"roughstick-ensemble-block-{spec.token}-{i}-{j}"
            )
    data_vars = {}
    for name, var in tmpl.data_vars.items():
        dims = var.dims
        rows = []
        for i, a, b in rblocks:
            cols = []
            for j, lo, hi in hblocks if "rh" in dims else hblocks[:1]:
                shape = tuple(
                    {"realization": b - a, "rh": hi - lo}.get(d, var.sizes[d]) for d in dims
                )
                arr = dsa.from_delayed(
                    dask.delayed(_pick, pure=True)(blocks[i, j], name),
                    shape=shape, dtype=var.dtype, meta=np.empty((0,) * len(dims), var.dtype),
                )
                cols.append(arr)
            rows.append(dsa.concatenate(cols, axis=dims.index("rh")) if "rh" in dims else cols[0])
        data = dsa.concatenate(rows, axis=dims.index("realization")) if "realization" in dims else rows[0]
        data_vars[name] = xr.Variable(dims, data, attrs=dict(var.attrs))
    ds = xr.Dataset(
        data_vars,
        coords={
            "realization": ("realization", np.arange(start, stop), dict(ATTRS["realization"])),
            "rh": ("rh", spec.rh, dict(ATTRS["rh"])),
            "distance": ("distance", spec.distance, dict(ATTRS["distance"])),
        },
    )
    return ds


def _attrs(spec: _Spec, n) -> dict:
    layer = spec.adsorbed_layer if isinstance(spec.adsorbed_layer, str) else _callable_id(spec.adsorbed_layer)
    return dataset_attrs(
        "Monte Carlo ensemble of rough-surface humid adhesive contact (paper section 4.3)",
        references=REFERENCES,
        seed=str(spec.seed.entropy),
        seed_spawn_key=json.dumps(list(spec.seed.spawn_key)),
        n_realizations=int(n),
        surface_shape=json.dumps(list(spec.shape)),
        surface_size_m=json.dumps([s * spec.spacing for s in spec.shape]),
        spacing_m=spec.spacing,
        psd_m0_m2=_psd_m0(spec.psd),
        adsorbed_layer=layer,
        material=repr(spec.material),
        contact_function=_callable_id(spec.curves),
        surface_function=_callable_id(spec.generate),
        summary_function=_callable_id(spec.summary),
        realization_chunk=spec.chunk,
        rh_chunk=spec.rh_chunk,
        params_hash=spec.token,
    )


# ============================================================================ execution
def _interactive() -> bool:
    if os.environ.get("CI", "").lower() not in ("", "0", "false", "no"):
        return False
    try:  # Jupyter kernels have no tty but do show widgets
        from IPython import get_ipython

        ip = get_ipython()
        if ip is not None and "IPKernelApp" in getattr(ip, "config", {}):
            return True
    except ImportError:  # pragma: no cover
        pass
    return bool(getattr(sys.stderr, "isatty", lambda: False)())


def _tqdm_class():
    """tqdm.auto (a Jupyter widget) when ipywidgets is there, else the text bar."""
    try:
        import ipywidgets  # noqa: F401
        from tqdm.auto import tqdm
    except ImportError:
        from tqdm import tqdm
    return tqdm


def progress_bar(progress: bool | None = None, **kwargs):
    """A dask callback showing a tqdm progress bar (terminal or Jupyter), or a no-op.

    ``progress=None`` shows it only when interactive: stderr is a terminal or the code runs in a
    Jupyter kernel, and the ``CI`` environment variable is not set.

    Examples
    --------
    >>> with rs.progress_bar(False):
    ...     pass
    """
    import contextlib

    if progress is None:
        progress = _interactive()
    if not progress:
        return contextlib.nullcontext()
    from tqdm.dask import TqdmCallback

    return TqdmCallback(tqdm_class=_tqdm_class(), **kwargs)


def _resolve_client(scheduler, connect_timeout: float):
    """None/"threads"/"sync"/"processes" → (None, name); "tcp://..." or a Client → (client, None)."""
    if scheduler is None:
        return None, "threads"
    if isinstance(scheduler, str) and scheduler in ("threads", "threading", "sync", "synchronous", "processes"):
        return None, scheduler
    try:
        from distributed import Client
    except ImportError as exc:  # pragma: no cover
        raise ValueError("scheduler addresses need the 'distributed' package: pip install distributed") from exc
    if isinstance(scheduler, Client):
        return scheduler, None
    if isinstance(scheduler, str) and "://" in scheduler:
        try:
            client = Client(scheduler, timeout=f"{connect_timeout}s", set_as_default=False)
        except (OSError, TimeoutError) as exc:
            raise ConnectionError(
                f"could not connect to the dask scheduler at {scheduler!r} within {connect_timeout:g} s "
                f"({type(exc).__name__}). Check the address and that the scheduler is running "
                "(`dask scheduler` prints it), or run locally by omitting the scheduler."
            ) from exc
        return client, None
    raise ValueError(
        f"scheduler must be None, 'threads', 'sync', 'processes', a 'tcp://host:port' address or a "
        f"distributed.Client; got {scheduler!r}."
    )


def _compute_blocks(spec, todo, client, local, on_block, progress):
    """Compute blocks ``todo`` = [(i, a, b, j, lo, hi)], calling ``on_block(i, j, ds)`` as each ends."""
    import dask

    if not todo:
        return
    bar = None
    if progress if progress is not None else _interactive():
        bar = _tqdm_class()(total=len(todo), desc="ensemble blocks", unit="block")
    spec_d = dask.delayed(spec, pure=True, name=f"roughstick-ensemble-spec-{spec.token}")
    delayed = {}
    for i, a, b, j, lo, hi in todo:
        key = f"roughstick-ensemble-block-{spec.token}-{i}-{j}"
        delayed[key] = ((i, j), dask.delayed(_block, pure=True)(spec_d, a, b, lo, hi, dask_key_name=key))
    try:
        if client is not None:
            from distributed import as_completed

            futures = client.compute([d for _, d in delayed.values()])
            ij_of = {f.key: ij for f, (ij, _) in zip(futures, delayed.values(), strict=True)}
            for fut in as_completed(futures):
                ds = fut.result()
                on_block(*ij_of[fut.key], ds)
                fut.release()
                if bar is not None:
                    bar.update(1)
        else:
            from dask.callbacks import Callback

            def posttask(key, result, dsk, state, worker_id):
                name = key if isinstance(key, str) else None
                if name in delayed:
                    on_block(*delayed[name][0], result)
                    if bar is not None:
                        bar.update(1)

            sinks = [dask.delayed(_discard, pure=True)(d) for _, d in delayed.values()]
            with Callback(posttask=posttask):
                dask.compute(*sinks, scheduler=local)
    finally:
        if bar is not None:
            bar.close()


# ============================================================================ streaming
def _manifest_for(spec: _Spec, n, attrs) -> dict:
    from .io.netcdf import MANIFEST_FORMAT

    rblocks = spec.realization_blocks(0, n)
    return {
        "format": MANIFEST_FORMAT,
        "params_hash": spec.token,
        "n": int(n),
        "realization_chunks": [[a, b] for _, a, b in rblocks],
        "rh_chunks": [[lo, hi] for _, lo, hi in spec.rh_blocks()],
        "relative_humidity": spec.rh.tolist(),
        "shape": list(spec.shape),
        "spacing": spec.spacing,
        "seed": str(spec.seed.entropy),
        "attrs": {k: v for k, v in attrs.items() if isinstance(v, (str, int, float))},
        "completed": [],
        "complete": False,
    }


def _prepare_folder(folder: pathlib.Path, spec: _Spec, n: int, attrs: dict, overwrite: bool) -> dict:
    import shutil

    from .io import netcdf as nc

    if folder.exists() and not folder.is_dir():
        raise FileExistsError(f"output {str(folder)!r} exists and is not a folder; choose another path.")
    m = nc.read_manifest(folder) if folder.exists() else None
    if m is not None and m["params_hash"] != spec.token:
        if not overwrite:
            raise FileExistsError(
                f"output folder {str(folder)!r} holds a run with different parameters "
                f"(hash {m['params_hash']} != {spec.token}); refusing to mix them. To resume that run, "
                "use its original parameters/config; to replace it, pass overwrite=True "
                "(`roughstick run CONFIG --overwrite`); or choose another output folder."
            )
        shutil.rmtree(folder)
        m = None
    if m is None and folder.exists() and any(folder.iterdir()):
        if not overwrite:
            raise FileExistsError(
                f"output folder {str(folder)!r} is not empty and holds no roughstick manifest; "
                "choose an empty or new folder, or pass overwrite=True (`--overwrite`) to clear it."
            )
        shutil.rmtree(folder)
    folder.mkdir(parents=True, exist_ok=True)
    nc.remove_partial_files(folder)
    new = _manifest_for(spec, n, attrs)
    if m is not None:
        new["completed"] = [c for c in m.get("completed", []) if (folder / c).exists()]
    nc.write_manifest(folder, new)
    return new


def _stream(spec, n, folder, *, overwrite, scheduler, connect_timeout, progress, attrs, start=0):
    from .io import netcdf as nc

    manifest = _prepare_folder(folder, spec, n, attrs, overwrite)
    todo = []
    done = set(manifest["completed"])
    for i, a, b in spec.realization_blocks(start, n):
        for j, lo, hi in spec.rh_blocks():
            name = nc.block_name(i, j)
            if name in done and nc.valid_block(folder / name, params_hash=spec.token, block=(i, j)):
                continue
            if (folder / name).exists() and nc.valid_block(folder / name, params_hash=spec.token, block=(i, j)):
                manifest["completed"].append(name)  # written but not yet recorded when killed
                continue
            todo.append((i, a, b, j, lo, hi))
    client, local = _resolve_client(scheduler, connect_timeout)

    def on_block(i, j, ds):
        ds = ds.copy()
        ds.attrs = {**attrs, "roughstick_params_hash": spec.token, "roughstick_block_realization": i,
                    "roughstick_block_rh": j, "roughstick_block_complete": 1}
        name = nc.block_name(i, j)
        nc.write(ds, folder / name, compute=True)
        manifest["completed"].append(name)
        nc.write_manifest(folder, manifest)

    try:
        _compute_blocks(spec, todo, client, local, on_block, progress)
    finally:
        if client is not None and not _is_client(scheduler):
            client.close()
    manifest["completed"] = sorted(set(manifest["completed"]))
    total = len(spec.realization_blocks(0, n)) * len(spec.rh_blocks())
    manifest["complete"] = len(manifest["completed"]) >= total
    nc.write_manifest(folder, manifest)
    return len(todo)


def _is_client(obj) -> bool:
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover
        return False
    return isinstance(obj, Client)


# ============================================================================ auto n
def _band_change(old: xr.Dataset, new: xr.Dataset, variables) -> dict:
    out = {}
    for v in variables:
        if v not in old:
            continue
        a, b = old[v], new[v]
        if "distance" in a.dims:
            scale = np.abs(b).max("distance")
            change = (np.abs(b - a).max("distance") / scale.where(scale > 0)).max()
        else:
            change = (np.abs(b - a) / np.abs(b).where(np.abs(b) > 0)).max()
        out[v] = float(change.fillna(0.0))
    return out


def _auto(spec, *, batch, tolerance, n_max, patience, level, folder, stream_kw, scheduler,
          connect_timeout, progress, attrs):
    variables = ("adhesive_energy", "pressure")
    parts = []
    n = 0
    prev = None
    history = []
    stable = 0
    results = {}

    def keep(i, j, block):
        results[i, j] = block

    client, local = _resolve_client(scheduler, connect_timeout) if folder is None else (None, None)
    try:
        while n < n_max:
            n_next = min(n + batch, n_max)
            if folder is not None:
                _stream(spec, n_next, folder, attrs=attrs, start=n, scheduler=scheduler,
                        connect_timeout=connect_timeout, progress=progress, **stream_kw)
                stream_kw = {**stream_kw, "overwrite": False}
                from .io.netcdf import open_ensemble

                ds = open_ensemble(folder).load()
            else:
                results.clear()
                todo = [(i, a, b, j, lo, hi) for i, a, b in spec.realization_blocks(n, n_next)
                        for j, lo, hi in spec.rh_blocks()]
                _compute_blocks(spec, todo, client, local, keep, progress)
                rows = [xr.concat([results[i, j] for j, _, _ in spec.rh_blocks()], "rh",
                                  data_vars="minimal", coords="minimal", compat="override")
                        for i, _, _ in spec.realization_blocks(n, n_next)]
                parts.extend(rows)
                ds = xr.concat(parts, "realization", data_vars="minimal", coords="minimal",
                               compat="override")
            n = n_next
            band = confidence_band(ds[[v for v in variables if v in ds]], level=level, uncertainty=None)
            if prev is not None:
                ch = _band_change(prev, band, [v for v in variables if v in band])
                worst = max(ch.values()) if ch else 0.0
                history.append((n, worst))
                stable = stable + 1 if worst < tolerance else 0
                if stable >= patience:
                    break
            prev = band
    finally:
        if client is not None and not _is_client(scheduler):
            client.close()
    converged = stable >= patience
    ds = ds.copy()
    ds.attrs = {**attrs, "n_realizations": int(n)}
    ds.attrs.update(
        n_mode="auto",
        n_final=int(n),
        auto_converged=int(converged),
        auto_stopping_rule=(
            f"add batches of {batch} realizations until the {level:.0%} band (quantiles "
            f"{(1 - level) / 2:g}, {(1 + level) / 2:g}) of {', '.join(variables)} moves by less than "
            f"{tolerance:g} (relative; pressure relative to its largest magnitude per rh) for "
            f"{patience} consecutive batch(es), at most {n_max} realizations"
        ),
        auto_band_changes=json.dumps([[int(k), float(c)] for k, c in history]),
    )
    return ds


# ============================================================================ public API
def run_ensemble(
    psd: xr.DataArray,
    *,
    n,
    relative_humidity,
    spacing: float,
    size=None,
    shape=None,
    seed=0,
    chunks=None,
    distance=None,
    adsorbed_layer="paper",
    material=None,
    output=None,
    overwrite: bool = False,
    scheduler=None,
    connect_timeout: float = 5.0,
    progress: bool | None = None,
    batch: int = 100,
    tolerance: float = 0.02,
    n_max: int = 3000,
    patience: int = 2,
    level: float = 0.95,
    generate: Callable | None = None,
    curves: Callable | None = None,
    summary: Callable | None = None,
    generate_kwargs: dict | None = None,
    curves_kwargs: dict | None = None,
) -> xr.Dataset:
    r"""Monte Carlo ensemble of rough-surface humid adhesion from a PSD (paper §4.3).

    For realization :math:`k = 0 … n-1`: a surface from ``psd`` (Eqs. 33-34,
    :func:`roughstick.generate_surfaces`), its pressure–distance curves at every humidity (modified
    DMT, Eqs. 16-23, :func:`roughstick.rough_contact_curves`) on a distance grid common to all
    realizations, and their summaries (Γ of Eq. 13, pull-off pressure, equilibrium distance,
    :func:`roughstick.adhesion_summary`).

    Parameters
    ----------
    psd : xarray.DataArray
        2-D ``(qy, qx)`` or isotropic ``(q)`` PSD [m4] (architecture.md normalisation).
    n : int or "auto"
        Number of realizations (>= 1), or ``"auto"``: add batches of ``batch`` realizations until the
        ``level`` band of Γ and of the pressure curve moves by less than ``tolerance`` for
        ``patience`` consecutive batches (at most ``n_max``). The stopping rule, the final n and the
        band changes are recorded in ``attrs``. ``"auto"`` computes (it must look at the results).
    relative_humidity : sequence of float
        Humidities as fractions in (0, 1); becomes the ``rh`` dimension.
    spacing : float
        Pixel size [m].
    size, shape : float or (float, float), int or (int, int)
        Surface side(s) in metres, or in pixels; give exactly one.
    seed : int or numpy.random.SeedSequence, default 0
        Root seed; realization ``k`` uses its child ``k`` whatever the chunking.
    chunks : int or dict, optional
        Realizations per block (default: about 4 MiB of heights, at least 1), or
        ``{"realization": c, "rh": r}`` to split humidities too (each humidity block regenerates
        its surfaces, which costs one inverse FFT per surface).
    distance : array-like or xarray.DataArray, optional
        Common distance grid [m]; default :func:`ensemble_distance_grid`.
    adsorbed_layer : {"paper", "none"} or callable, default "paper"
        Adsorbed-layer model (§2.1).
    material : roughstick.Material, optional
        Both bodies' material (default poly-silicon).
    output : str or pathlib.Path, optional
        Stream results into this folder (one CF NetCDF file per block plus ``manifest.json``) as
        blocks complete, resuming from any blocks already there, and return the Dataset opened from
        it (lazily). A folder holding a run with other parameters is refused unless ``overwrite``.
    overwrite : bool, default False
        Replace a different run in ``output``.
    scheduler : None, "threads", "sync", "processes", str or distributed.Client
        Where blocks run when streaming or with ``n="auto"``: local threads by default, or an
        existing dask.distributed cluster by its address (``"tcp://host:8786"``) or client. The lazy
        result (no ``output``) computes with whatever dask scheduler is active.
    connect_timeout : float, default 5
        Seconds to wait for a scheduler address to answer before raising ``ConnectionError``.
    progress : bool, optional
        Progress bar when streaming/auto; default: only when interactive (see :func:`progress_bar`).
    batch, tolerance, n_max, patience, level
        Parameters of ``n="auto"``.
    generate, curves, summary : callable, optional
        Replace :func:`roughstick.generate_surfaces`, :func:`roughstick.rough_contact_curves` and
        :func:`roughstick.adhesion_summary` (same signatures), e.g. to run another contact model.
    generate_kwargs, curves_kwargs : dict, optional
        Extra keyword arguments for ``generate`` and ``curves``.

    Returns
    -------
    xarray.Dataset
        Curves over ``(realization, rh, distance)`` (``pressure`` … as returned by ``curves``),
        summaries over ``(realization, rh)`` (``adhesive_energy`` …) and ``max_height`` over
        ``(realization)``; dask-backed and chunked over realization and rh unless ``n="auto"``.

    Raises
    ------
    ValueError
        n < 1, empty or invalid humidities, bad shapes, a grid that does not cover a realization.
    ConnectionError
        A scheduler address that does not answer within ``connect_timeout``.
    FileExistsError
        ``output`` holds a different run (pass ``overwrite=True``) or unrelated files.

    See Also
    --------
    confidence_band, ensemble_histogram, ensemble_ecdf, roughstick.open_ensemble

    Notes
    -----
    Each block is a pure function of (parameters, realization range, humidity range), so a block
    recomputed after an interruption is bit-identical, and the lazy Dataset, the streamed folder,
    a threaded run and a run on a distributed cluster give the same numbers.

    References
    ----------
    Hoang et al. (2015), doi:10.1016/j.cam.2015.02.022, §4.3.
    """
    from ._core import materials

    if isinstance(n, str):
        if n != "auto":
            raise ValueError(f"n must be a positive integer or 'auto', got {n!r}.")
        auto = True
        n_total = int(n_max)
    else:
        if isinstance(n, bool) or int(n) != n:
            raise ValueError(f"n must be a positive integer or 'auto', got {n!r}.")
        auto = False
        n_total = int(n)
    if n_total < 1:
        raise ValueError(f"n must be at least 1 realization, got {n_total}.")
    if not isinstance(psd, xr.DataArray):
        raise TypeError(f"psd must be an xarray.DataArray, got {type(psd).__name__}.")
    spacing = float(spacing)
    if not spacing > 0:
        raise ValueError(f"spacing must be a positive length in m, got {spacing!r}.")
    shp = _resolve_shape(shape, size, spacing)
    rh = relative_humidity_array(relative_humidity)
    if material is None:
        material = materials.POLYSILICON
    if generate is None:
        from .surface.generate import generate_surfaces as generate
    if curves is None:
        from .contact.curves import rough_contact_curves as curves
    if summary is None:
        from .contact.adhesion import adhesion_summary as summary
    root = as_seed_sequence(seed)
    if distance is None:
        dist = np.asarray(
            ensemble_distance_grid(psd, shape=shp, n=n_total, relative_humidity=rh,
                                   adsorbed_layer=adsorbed_layer).values
        )
    else:
        dist = distance_array(distance, min_size=2)
    if isinstance(chunks, dict):
        c_r = chunks.get("realization")
        c_h = chunks.get("rh", -1)
    else:
        c_r, c_h = chunks, -1
    if c_r is None:
        c_r = max(1, int(4 * 2**20 // (8 * shp[0] * shp[1])))
    c_r = int(c_r)
    c_h = rh.size if c_h in (-1, None) else int(c_h)
    if c_r < 1 or c_h < 1:
        raise ValueError(f"chunks must be positive, got realization={c_r}, rh={c_h}.")
    if auto:
        batch = max(c_r, int(math.ceil(batch / c_r)) * c_r)
    fields = dict(
        psd=psd.load() if psd.chunks is not None else psd, shape=shp, spacing=spacing, rh=rh,
        distance=dist, chunk=c_r, rh_chunk=min(c_h, rh.size), adsorbed_layer=adsorbed_layer,
        material=material, generate=generate, curves=curves, summary=summary,
        generate_kwargs=dict(generate_kwargs or {}), curves_kwargs=dict(curves_kwargs or {}),
        seed_entropy=str(root.entropy), seed_spawn_key=list(root.spawn_key),
    )
    token = _hash_params(fields)
    spec = _Spec(
        psd=fields["psd"], shape=shp, spacing=spacing, rh=rh, distance=dist, seed=root, chunk=c_r,
        rh_chunk=fields["rh_chunk"], adsorbed_layer=adsorbed_layer, material=material,
        generate=generate, curves=curves, summary=summary,
        generate_kwargs=fields["generate_kwargs"], curves_kwargs=fields["curves_kwargs"],
        water_max=float(np.max(_water_heights(rh, adsorbed_layer))), token=token,
    )
    attrs = _attrs(spec, n_total)
    folder = pathlib.Path(output) if output is not None else None
    if auto:
        ds = _auto(spec, batch=batch, tolerance=tolerance, n_max=n_total, patience=patience,
                   level=level, folder=folder, stream_kw={"overwrite": overwrite},
                   scheduler=scheduler, connect_timeout=connect_timeout, progress=progress,
                   attrs=attrs)
        return append_history(ds, f"run_ensemble(n='auto') stopped at n={ds.attrs['n_final']}")
    if folder is not None:
        t0 = time.perf_counter()
        _stream(spec, n_total, folder, overwrite=overwrite, scheduler=scheduler,
                connect_timeout=connect_timeout, progress=progress, attrs=attrs)
        from .io.netcdf import open_ensemble

        ds = open_ensemble(folder, chunks={})
        return append_history(ds, f"run_ensemble streamed to {str(folder)!r} "
                                  f"({time.perf_counter() - t0:.1f} s this session)")
    ds = _lazy(spec, 0, n_total)
    ds.attrs = attrs
    return append_history(ds, f"run_ensemble(n={n_total}, shape={shp}, rh={rh.tolist()})")


def surface_size_study(
    psd: xr.DataArray,
    *,
    sizes: Sequence[float] | None = None,
    shapes: Sequence | None = None,
    spacing: float,
    n: int,
    relative_humidity,
    seed=0,
    **kwargs,
) -> xr.Dataset:
    """The same PSD at several surface sizes on one distance grid (paper Figs. 16-17).

    Runs :func:`run_ensemble` once per size with a common distance grid (built for the largest
    surface) and independent seeds (child ``i`` of ``seed`` for size ``i``) and concatenates along a
    new ``surface_size`` dimension (side length along x, m).

    Parameters
    ----------
    psd : xarray.DataArray
        PSD [m4].
    sizes : sequence of float, optional
        Side lengths [m] of square surfaces (e.g. ``[5.12e-6, 10.24e-6]``); or give ``shapes``.
    shapes : sequence of (int, int), optional
        Surface shapes in pixels.
    spacing : float
        Pixel size [m].
    n : int
        Realizations per size.
    relative_humidity : sequence of float
        Humidities.
    seed : int or numpy.random.SeedSequence
        Root seed.
    **kwargs
        Passed to :func:`run_ensemble` (``output`` is not supported here).

    Returns
    -------
    xarray.Dataset
        As :func:`run_ensemble` plus a leading ``surface_size`` dimension; lazy.
    """
    if (sizes is None) == (shapes is None):
        raise ValueError("give exactly one of sizes= (m) or shapes= (pixels).")
    if "output" in kwargs:
        raise ValueError("surface_size_study does not stream; call run_ensemble(output=...) per size.")
    shp = [_resolve_shape(None, s, spacing) for s in sizes] if sizes is not None else [
        _resolve_shape(s, None, spacing) for s in shapes
    ]
    if not shp:
        raise ValueError("sizes/shapes is empty; give at least one surface size.")
    rh = relative_humidity_array(relative_humidity)
    dist = kwargs.pop("distance", None)
    if dist is None:
        big = max(shp, key=lambda s: s[0] * s[1])
        dist = ensemble_distance_grid(psd, shape=big, n=n, relative_humidity=rh,
                                      adsorbed_layer=kwargs.get("adsorbed_layer", "paper"))
    root = as_seed_sequence(seed)
    parts = []
    for i, s in enumerate(shp):
        child = np.random.SeedSequence(root.entropy, spawn_key=tuple(root.spawn_key) + (i,))
        parts.append(run_ensemble(psd, n=n, shape=s, spacing=spacing, relative_humidity=rh,
                                  seed=child, distance=dist, **kwargs))
    lengths = [s[1] * spacing for s in shp]
    ds = xr.concat(parts, dim=xr.DataArray(lengths, dims="surface_size", name="surface_size"),
                   combine_attrs="drop_conflicts", data_vars="all", coords="minimal", compat="override")
    ds["surface_size"].attrs = dict(ATTRS["surface_size"])
    ds.attrs = {**parts[0].attrs, "surface_sizes_m": json.dumps(lengths)}
    for k in ("surface_shape", "surface_size_m", "params_hash", "seed_spawn_key"):
        ds.attrs.pop(k, None)
    return ds


# ============================================================================ bands
def _order_statistic_kernel(a, probs, alpha):
    """Distribution-free interval [X_(r), X_(s)] for each quantile p (last axis = samples).

    P(X_(r) <= xi_p <= X_(s)) = B(s-1) - B(r-1) >= 1 - alpha with B the Binomial(n, p) CDF;
    r < 1 or s > n means the sample cannot bound the quantile: -inf / +inf.
    """
    from scipy.stats import binom

    a = np.sort(np.asarray(a, dtype=float), axis=-1)  # NaN last
    nvalid = np.sum(~np.isnan(a), axis=-1)
    lo = np.full(a.shape[:-1] + (len(probs),), np.nan)
    hi = np.full_like(lo, np.nan)
    for nv in np.unique(nvalid):
        if nv == 0:
            continue
        mask = nvalid == nv
        sub = a[mask][..., :nv]
        for k, p in enumerate(probs):
            r = int(binom.ppf(alpha / 2, nv, p))
            s = int(binom.ppf(1 - alpha / 2, nv, p)) + 1
            lo[mask, k] = sub[..., r - 1] if r >= 1 else -np.inf
            hi[mask, k] = sub[..., s - 1] if s <= nv else np.inf
    return lo, hi


def _bootstrap_kernel(a, probs, alpha, n_boot, entropy):
    a = np.asarray(a, dtype=float)
    n = a.shape[-1]
    rng = np.random.default_rng(np.random.SeedSequence(entropy))
    reps = np.empty((n_boot,) + a.shape[:-1] + (len(probs),))
    for b in range(n_boot):
        idx = rng.integers(0, n, size=n)
        reps[b] = np.moveaxis(np.nanquantile(a[..., idx], probs, axis=-1), 0, -1)
    lo = np.nanquantile(reps, alpha / 2, axis=0)
    hi = np.nanquantile(reps, 1 - alpha / 2, axis=0)
    return lo, hi


def quantile_interval(
    da: xr.DataArray,
    quantiles,
    *,
    dim: str = "realization",
    confidence: float = 0.95,
    method: str = "order_statistic",
    n_bootstrap: int = 500,
    rng=0,
) -> tuple[xr.DataArray, xr.DataArray]:
    r"""Confidence interval of sample quantiles: how well ``n`` realizations pin a band down.

    ``method="order_statistic"`` (default) gives the distribution-free interval
    :math:`[X_{(r)}, X_{(s)}]` whose coverage :math:`F_B(s-1) - F_B(r-1) \ge` ``confidence`` with
    :math:`F_B` the Binomial(n, p) CDF (Conover, *Practical Nonparametric Statistics*, §3.2);
    ``-inf``/``inf`` where n is too small to bound the quantile at all. ``"bootstrap"`` gives the
    percentile bootstrap interval from ``n_bootstrap`` resamples drawn with ``rng`` (the same
    resamples for every element, so chunking does not change it).

    Parameters
    ----------
    da : xarray.DataArray
        Samples along ``dim`` (NaN ignored).
    quantiles : sequence of float
        Probabilities in [0, 1].
    dim : str
        Sample dimension, rechunked to one chunk.
    confidence : float
        Coverage of the interval.
    method : {"order_statistic", "bootstrap"}
    n_bootstrap : int
    rng : int or numpy.random.SeedSequence
        Seed of the bootstrap resamples.

    Returns
    -------
    lower, upper : xarray.DataArray
        Dims ``(quantile, ...)``.

    Examples
    --------
    >>> x = xr.DataArray(np.arange(100.0), dims="realization")
    >>> lo, hi = rs.quantile_interval(x, [0.5])
    >>> float(lo[0]), float(hi[0])
    (39.0, 60.0)
    """
    probs = np.atleast_1d(np.asarray(quantiles, dtype=float))
    if np.any((probs < 0) | (probs > 1)):
        raise ValueError(f"quantiles must lie in [0, 1], got {probs.tolist()}.")
    if not 0 < confidence < 1:
        raise ValueError(f"confidence must lie in (0, 1), got {confidence!r}.")
    if dim not in da.dims:
        raise ValueError(f"{da.name!r} has no dimension {dim!r} (dims {da.dims}).")
    alpha = 1 - confidence
    if da.chunks is not None:
        da = da.chunk({dim: -1})
    if method == "order_statistic":
        func, kw = _order_statistic_kernel, {"probs": probs, "alpha": alpha}
    elif method == "bootstrap":
        func = _bootstrap_kernel
        kw = {"probs": probs, "alpha": alpha, "n_boot": int(n_bootstrap),
              "entropy": as_seed_sequence(rng).entropy}
    else:
        raise ValueError(f"method must be 'order_statistic' or 'bootstrap', got {method!r}.")
    lo, hi = xr.apply_ufunc(
        func, da, kwargs=kw,
        input_core_dims=[[dim]],
        output_core_dims=[["quantile"], ["quantile"]],
        dask="parallelized",
        output_dtypes=[float, float],
        dask_gufunc_kwargs={"output_sizes": {"quantile": probs.size}},
    )
    out = []
    for x, side in ((lo, "lower"), (hi, "upper")):
        x = x.assign_coords(quantile=probs).transpose("quantile", ...)
        x.attrs = {**{k: v for k, v in da.attrs.items() if k in ("units", "standard_name")},
                   "long_name": f"{side} {confidence:.0%} confidence limit of the quantile of "
                                f"{da.attrs.get('long_name', da.name)}",
                   "method": method}
        x["quantile"].attrs = dict(ATTRS["quantile"])
        out.append(x.rename(f"{da.name}_ci_{side}" if da.name else None))
    return out[0], out[1]


def confidence_band(
    ds,
    dim: str = "realization",
    level: float = 0.95,
    *,
    uncertainty: str | None = "order_statistic",
    confidence: float = 0.95,
    n_bootstrap: int = 500,
    rng=0,
):
    r"""Mean and ``level`` band over realizations, with the band's sampling uncertainty (Figs. 14-16).

    For every data variable with ``dim``: the quantiles :math:`(1-\ell)/2`, 0.5 and
    :math:`(1+\ell)/2` along ``dim`` (variable ``v``, new leading dim ``quantile``), the mean
    (``v_mean``) and its standard error (``v_mean_stderr``), and unless ``uncertainty=None`` a
    ``confidence`` interval of each quantile (``v_ci_lower``, ``v_ci_upper``, see
    :func:`quantile_interval`): if that interval is narrow compared with the band, n was enough.
    ``dim`` is rechunked to a single chunk first, so the result does not depend on the chunking;
    lazy inputs stay lazy.

    Parameters
    ----------
    ds : xarray.Dataset or xarray.DataArray
        Ensemble, e.g. from :func:`run_ensemble`.
    dim : str, default "realization"
    level : float, default 0.95
        Central probability of the band.
    uncertainty : {"order_statistic", "bootstrap", None}
        How to compute the quantiles' sampling intervals.
    confidence : float, default 0.95
        Coverage of those intervals.
    n_bootstrap, rng
        For ``uncertainty="bootstrap"``.

    Returns
    -------
    xarray.Dataset
        Attrs ``level``, ``confidence``, ``n_samples``.

    Examples
    --------
    >>> x = xr.DataArray(np.arange(1000.0), dims="realization", name="g",
    ...                  attrs={"units": "J m-2", "long_name": "energy"})
    >>> b = rs.confidence_band(x)
    >>> b["g"].values, float(b["g_mean"])
    (array([ 24.975, 499.5  , 974.025]), 499.5)
    """
    if not 0 < level < 1:
        raise ValueError(f"level must lie in (0, 1), got {level!r}.")
    if isinstance(ds, xr.DataArray):
        name = ds.name or "data"
        ds = ds.to_dataset(name=name)
    if dim not in ds.dims:
        raise ValueError(f"the input has no dimension {dim!r} (dims {tuple(ds.dims)}).")
    n = ds.sizes[dim]
    if n < 1:
        raise ValueError(f"dimension {dim!r} is empty: no realizations to reduce.")
    probs = np.round([(1 - level) / 2, 0.5, (1 + level) / 2], 12)  # exact labels for .sel
    out = {}
    for v, da in ds.data_vars.items():
        if dim not in da.dims or da.dtype.kind not in "fiub":
            continue
        da = da.astype(float) if da.dtype.kind != "f" else da
        if da.chunks is not None:
            da = da.chunk({dim: -1})
        keep = {k: a for k, a in da.attrs.items() if k in ("units", "standard_name")}
        long = da.attrs.get("long_name", v)
        with warnings.catch_warnings():  # all-NaN rows (e.g. fit_error before contact) give NaN
            warnings.filterwarnings("ignore", "All-NaN slice", RuntimeWarning)
            q = da.quantile(probs, dim=dim).transpose("quantile", ...)
        q.attrs = {**keep, "long_name": f"quantiles over {dim} of {long}"}
        out[v] = q
        mean = da.mean(dim)
        mean.attrs = {**keep, "long_name": f"mean over {dim} of {long}"}
        out[f"{v}_mean"] = mean
        se = da.std(dim, ddof=1) / np.sqrt(da.count(dim)) if n > 1 else da.isel({dim: 0}) * np.nan
        se.attrs = {**keep, "long_name": f"standard error of the mean of {long}"}
        out[f"{v}_mean_stderr"] = se.drop_vars(dim, errors="ignore")
        if uncertainty is not None:
            lo, hi = quantile_interval(da.rename(v), probs, dim=dim, confidence=confidence,
                                       method=uncertainty, n_bootstrap=n_bootstrap, rng=rng)
            out[f"{v}_ci_lower"], out[f"{v}_ci_upper"] = lo, hi
    res = xr.Dataset(out)
    res["quantile"] = ("quantile", probs, dict(ATTRS["quantile"]))
    for c in res.coords:
        if c in ATTRS:
            res[c].attrs = dict(ATTRS[c])
    res.attrs = {k: v for k, v in ds.attrs.items() if k in ("Conventions", "source", "references", "history", "title")}
    res.attrs.update(level=level, confidence=confidence, n_samples=int(n),
                     uncertainty_method=str(uncertainty))
    return append_history(res, f"confidence_band(level={level}, dim={dim!r}, n={n})")


# ============================================================================ distributions
def _inverse_units(units: str) -> str:
    if units in ("1", ""):
        return "1"
    out = []
    for tok in units.split():
        base = tok.rstrip("-0123456789")
        exp = tok[len(base):] or "1"
        e = -int(exp)
        out.append(base if e == 1 else f"{base}{e}")
    return " ".join(out)


def _hist_kernel(a, edges, density):
    a = np.asarray(a, float)
    flat = a.reshape(-1, a.shape[-1])
    res = np.empty((flat.shape[0], edges.size - 1))
    for k, row in enumerate(flat):
        res[k] = np.histogram(row[np.isfinite(row)], bins=edges, density=density)[0] if np.isfinite(row).any() else np.nan
    return res.reshape(a.shape[:-1] + (edges.size - 1,))


def ensemble_histogram(da: xr.DataArray, *, dim: str = "realization", bins=30, range=None,
                       density: bool = True) -> xr.DataArray:
    """Histogram along ``dim`` as a labelled DataArray (Fig. 17), one per remaining element.

    The bin edges are common to every element (``range``, or the data's min/max for in-memory
    data), so histograms at different humidities or sizes can be compared directly.

    Parameters
    ----------
    da : xarray.DataArray
        Samples, e.g. ``ds.adhesive_energy`` over ``(realization, rh)``.
    dim : str
    bins : int or sequence of float
        Number of bins or edges (in the units of ``da``).
    range : (float, float), optional
        Required for lazy inputs when ``bins`` is an int (the library does not compute on its own).
    density : bool, default True
        Probability density (units inverse of ``da``'s) instead of counts.

    Returns
    -------
    xarray.DataArray
        Dim ``bin`` with coords ``bin`` (centres), ``bin_lower`` and ``bin_upper``.

    Examples
    --------
    >>> x = xr.DataArray(np.array([0.1, 0.2, 0.2, 0.9]), dims="realization", name="g",
    ...                  attrs={"units": "J m-2", "long_name": "energy"})
    >>> h = rs.ensemble_histogram(x, bins=2, range=(0, 1), density=False)
    >>> h.values, h.attrs["units"]
    (array([3., 1.]), '1')
    """
    if dim not in da.dims:
        raise ValueError(f"{da.name!r} has no dimension {dim!r}.")
    if np.ndim(bins) == 0:
        if range is None:
            if da.chunks is not None:
                raise ValueError("pass range=(lo, hi) for a lazy input (or .compute() it first).")
            vals = np.asarray(da.values, float)
            vals = vals[np.isfinite(vals)]
            if vals.size == 0:
                raise ValueError(f"{da.name!r} holds no finite value to histogram.")
            range = (float(vals.min()), float(vals.max()))
            if range[0] == range[1]:
                range = (range[0] - 0.5 * abs(range[0] or 1), range[1] + 0.5 * abs(range[1] or 1))
        edges = np.linspace(float(range[0]), float(range[1]), int(bins) + 1)
    else:
        edges = np.asarray(bins, float)
    if da.chunks is not None:
        da = da.chunk({dim: -1})
    out = xr.apply_ufunc(
        _hist_kernel, da, kwargs={"edges": edges, "density": density},
        input_core_dims=[[dim]], output_core_dims=[["bin"]], dask="parallelized",
        output_dtypes=[float], dask_gufunc_kwargs={"output_sizes": {"bin": edges.size - 1}},
    )
    units = da.attrs.get("units", "1")
    cattrs = {"units": units}
    out = out.assign_coords(
        bin=("bin", 0.5 * (edges[1:] + edges[:-1]), {**cattrs, "long_name": f"bin centre of {da.attrs.get('long_name', da.name)}"}),
        bin_lower=("bin", edges[:-1], {**cattrs, "long_name": "lower bin edge"}),
        bin_upper=("bin", edges[1:], {**cattrs, "long_name": "upper bin edge"}),
    )
    out.name = f"{da.name}_{'density' if density else 'count'}"
    out.attrs = {
        "units": _inverse_units(units) if density else "1",
        "long_name": f"{'probability density' if density else 'count'} over {dim} of "
                     f"{da.attrs.get('long_name', da.name)}",
    }
    for c in out.coords:
        if c in ATTRS and c not in ("bin",):
            out[c].attrs = dict(ATTRS[c])
    return out


def ensemble_ecdf(da: xr.DataArray, *, dim: str = "realization") -> xr.DataArray:
    r"""Empirical CDF along ``dim`` (Fig. 17): sorted values over ``cumulative_probability``.

    Value ``k`` (0-based) of the result is the :math:`(k+1)`-th smallest sample, where the ECDF
    reaches :math:`(k+1)/n`; plot ``x=values, y=cumulative_probability``. NaN samples sort last.

    Examples
    --------
    >>> x = xr.DataArray([3.0, 1.0, 2.0], dims="realization", name="g",
    ...                  attrs={"units": "J m-2", "long_name": "energy"})
    >>> e = rs.ensemble_ecdf(x)
    >>> e.values, e.cumulative_probability.values
    (array([1., 2., 3.]), array([0.33333333, 0.66666667, 1.        ]))
    """
    if dim not in da.dims:
        raise ValueError(f"{da.name!r} has no dimension {dim!r}.")
    n = da.sizes[dim]
    if da.chunks is not None:
        da = da.chunk({dim: -1})
    out = xr.apply_ufunc(
        np.sort, da, kwargs={"axis": -1}, input_core_dims=[[dim]],
        output_core_dims=[["cumulative_probability"]], dask="parallelized", output_dtypes=[da.dtype],
        dask_gufunc_kwargs={"output_sizes": {"cumulative_probability": n}},
    )
    out = out.assign_coords(cumulative_probability=np.arange(1, n + 1) / n)
    out["cumulative_probability"].attrs = dict(ATTRS["cumulative_probability"])
    out.attrs = dict(da.attrs)
    out.name = da.name
    return out
