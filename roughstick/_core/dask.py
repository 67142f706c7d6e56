"""Small dask helpers: laziness check and per-realization random generators (seeds)."""

from __future__ import annotations

import dask
import numpy as np
import xarray as xr

__all__ = ["is_lazy", "realization_rng", "as_seed_sequence", "resolve_scheduler", "owns_client"]


def is_lazy(obj) -> bool:
    """True when ``obj`` (DataArray, Dataset or array) holds dask data."""
    if isinstance(obj, xr.Dataset):
        return any(is_lazy(v) for v in obj.data_vars.values())
    data = getattr(obj, "data", obj)
    return type(data).__module__.startswith("dask")


def as_seed_sequence(seed) -> np.random.SeedSequence:
    """Normalise ``seed`` (int, SeedSequence, Generator or None) to a root ``SeedSequence``."""
    if isinstance(seed, np.random.SeedSequence):
        return seed
    if isinstance(seed, np.random.Generator):
        return np.random.SeedSequence(int(seed.integers(0, 2**63 - 1)))
    if seed is None:
        return np.random.SeedSequence()
    if isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
        if seed < 0:
            raise ValueError(f"seed must be a non-negative integer, got {seed}.")
        return np.random.SeedSequence(int(seed))
    raise TypeError(
        f"seed must be an int, numpy.random.SeedSequence, numpy.random.Generator or None, "
        f"got {type(seed).__name__}."
    )


def realization_rng(root: np.random.SeedSequence, index: int) -> np.random.Generator:
    """Generator of realization ``index``: ``SeedSequence(root.entropy, spawn_key=(index,))``.

    Independent of chunking and of evaluation order, so realization k can be regenerated alone.
    """
    ss = np.random.SeedSequence(root.entropy, spawn_key=tuple(root.spawn_key) + (int(index),))
    return np.random.default_rng(ss)


def resolve_scheduler(scheduler, connect_timeout: float = 5.0):
    """Where roughstick's own computations run: ``(client, None)`` or ``(None, local scheduler)``.

    ``None`` follows dask's convention: the active scheduler, i.e. an active
    ``distributed.Client`` (creating one makes it the default), else one set with
    ``dask.config.set(scheduler=...)``, else local threads. ``"threads"``/``"sync"``/
    ``"processes"`` name a local scheduler; ``"tcp://..."`` connects a new client (the caller
    closes it: :func:`owns_client`); a ``Client`` is used as it is.
    """
    if scheduler is None:
        active = dask.config.get("scheduler", None)
        if active in ("dask.distributed", "distributed"):
            try:
                from distributed import default_client

                return default_client(), None
            except (ImportError, ValueError):  # the client has gone: its setting lingers
                return None, "threads"
        return None, "threads" if active is None else active
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


def owns_client(scheduler) -> bool:
    """True when :func:`resolve_scheduler` opened the client for ``scheduler`` (an address), so
    the caller closes it; a client passed in or active in the session is left open."""
    return isinstance(scheduler, str) and "://" in scheduler
