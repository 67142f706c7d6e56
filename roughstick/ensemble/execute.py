"""How the blocks of an ensemble run: local threads or a dask.distributed cluster, a progress bar,
streaming into a folder (:mod:`.store`), and ``n="auto"`` (batches until the band stops moving).

Whatever runs them, blocks are the pure :func:`.pipeline.compute_block`, so the numbers do not
depend on the scheduler or the number of workers.
"""

from __future__ import annotations

import json
import logging
import time

import dask
import numpy as np
import xarray as xr
from dask.callbacks import Callback

from .._core.dask import owns_client, resolve_scheduler
from .._core.progress import interactive, tqdm_class
from .pipeline import compute_block
from .statistics import confidence_band
from .store import (
    finish_manifest,
    open_ensemble,
    pending_blocks,
    prepare_folder,
    record_attrs,
    write_block,
)

__all__: list[str] = []

_LOG = logging.getLogger("roughstick")


class LogProgress:
    """Progress as INFO lines of the ``roughstick`` logger (no terminal needed): one at the start,
    then at most one per ``every`` seconds (and at each tenth of the work), with an estimate of
    the time left; the ``roughstick`` command routes them to stdout line by line."""

    def __init__(self, total: int, *, what: str, every: float = 30.0):
        self.total, self.what, self.every = int(total), what, float(every)
        self.done = 0
        self.t0 = self.last = time.monotonic()
        self.step = max(1, self.total // 10)
        _LOG.info(f"{what}: {self.total} to compute")

    def update(self, k: int = 1) -> None:
        self.done += k
        now = time.monotonic()
        if self.done >= self.total or self.done % self.step == 0 or now - self.last >= self.every:
            self.last = now
            el = now - self.t0
            eta = el / self.done * (self.total - self.done) if self.done else float("nan")
            _LOG.info(f"{self.what}: {self.done}/{self.total} done ({100 * self.done / self.total:.0f} %), "
                      f"{el:.0f} s elapsed, about {eta:.0f} s left")

    def close(self) -> None:
        pass


def compute_blocks(spec, todo, client, local, on_block, progress):
    """Compute blocks ``todo`` = [(i, a, b, j, lo, hi)], calling ``on_block(i, j, ds)`` as each ends."""
    if not todo:
        return
    if progress if progress is not None else interactive():
        bar = tqdm_class()(total=len(todo), desc="ensemble blocks", unit="block")
    else:  # batch jobs (SLURM, CI, nohup): a log line now and then, not silence until the end
        bar = LogProgress(len(todo), what="ensemble blocks")
    spec_d = dask.delayed(spec, pure=True, name=f"roughstick-ensemble-spec-{spec.token}")
    delayed = {}
    for i, a, b, j, lo, hi in todo:
        key = f"roughstick-ensemble-block-{spec.token}-{i}-{j}"
        delayed[key] = ((i, j), dask.delayed(compute_block, pure=True)(spec_d, a, b, lo, hi, dask_key_name=key))
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


def _discard(_):
    return None


def stream(spec, n, folder, *, overwrite, scheduler, connect_timeout, progress, attrs, start=0):
    """Compute the missing blocks of realizations ``[start, n)`` into ``folder``; return how many."""
    manifest = prepare_folder(folder, spec, n, attrs, overwrite)
    todo = pending_blocks(folder, spec, manifest, start, n)
    client, local = resolve_scheduler(scheduler, connect_timeout)

    def on_block(i, j, ds):
        write_block(folder, spec, manifest, attrs, i, j, ds)

    try:
        compute_blocks(spec, todo, client, local, on_block, progress)
    finally:
        if client is not None and owns_client(scheduler):
            client.close()
    finish_manifest(folder, spec, manifest, n)
    return len(todo)


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


def auto_ensemble(spec, *, batch, target_precision, n_max, patience, confidence, folder, stream_kw,
                  scheduler, connect_timeout, progress, attrs):
    """``n="auto"``: add batches of ``batch`` realizations until the ``confidence`` band of Γ and of
    the pressure curve moves by less than ``target_precision`` for ``patience`` batches."""
    variables = ("adhesive_energy", "pressure")
    parts = []
    n = 0
    prev = None
    history = []
    stable = 0
    results = {}

    def keep(i, j, block):
        results[i, j] = block

    client, local = resolve_scheduler(scheduler, connect_timeout) if folder is None else (None, None)
    try:
        while n < n_max:
            n_next = min(n + batch, n_max)
            if folder is not None:
                stream(spec, n_next, folder, attrs=attrs, start=n, scheduler=scheduler,
                        connect_timeout=connect_timeout, progress=progress, **stream_kw)
                stream_kw = {**stream_kw, "overwrite": False}
                ds = open_ensemble(folder).load()
            else:
                results.clear()
                todo = [(i, a, b, j, lo, hi) for i, a, b in spec.realization_blocks(n, n_next)
                        for j, lo, hi in spec.rh_blocks()]
                compute_blocks(spec, todo, client, local, keep, progress)
                rows = [xr.concat([results[i, j] for j, _, _ in spec.rh_blocks()], "rh",
                                  data_vars="minimal", coords="minimal", compat="override")
                        for i, _, _ in spec.realization_blocks(n, n_next)]
                parts.extend(rows)
                ds = xr.concat(parts, "realization", data_vars="minimal", coords="minimal",
                               compat="override")
            n = n_next
            band = confidence_band(ds[[v for v in variables if v in ds]], confidence=confidence,
                                   uncertainty=None)
            if prev is not None:
                ch = _band_change(prev, band, [v for v in variables if v in band])
                worst = max(ch.values()) if ch else 0.0
                history.append((n, worst))
                stable = stable + 1 if worst < target_precision else 0
                if stable >= patience:
                    break
            prev = band
    finally:
        if client is not None and owns_client(scheduler):
            client.close()
    converged = stable >= patience
    ds = ds.copy()
    ds.attrs = {**attrs, "n_realizations": int(n)}
    ds.attrs.update(
        n_mode="auto",
        n_final=int(n),
        auto_converged=int(converged),
        auto_stopping_rule=(
            f"add batches of {batch} realizations until the {confidence:.0%} band (quantiles "
            f"{(1 - confidence) / 2:g}, {(1 + confidence) / 2:g}) of {', '.join(variables)} moves by "
            f"less than {target_precision:g} (relative; pressure relative to its largest magnitude per rh) for "
            f"{patience} consecutive batch(es), at most {n_max} realizations"
        ),
        auto_band_changes=json.dumps([[int(k), float(c)] for k, c in history]),
    )
    if folder is not None:  # the convergence state is part of the run folder, not only in memory
        record_attrs(folder, {k: v for k, v in ds.attrs.items()
                              if k.startswith("auto_") or k in ("n_mode", "n_final")})
    return ds
