"""The subset-simulation engine: settings, level store, levels on dask, estimate.

Private to :mod:`roughstick.reliability`: the level bookkeeping (one :class:`_Level` per subset
level, written to one NetCDF file each so an interrupted run resumes), the chains of a level
evaluated block by block on dask, and the runs' estimate, coefficient of variation and interval
(:class:`Estimate`) assembled into the result Dataset.
"""

from __future__ import annotations

import dataclasses
import json
import math
import pathlib
from typing import NamedTuple

import numpy as np
import xarray as xr

from .._core.arguments import check_numbers
from .._core.conventions import append_history, dataset_attrs
from .._core.dask import owns_client, resolve_scheduler
from .._core.progress import StagedProgress, current_staged_progress
from .._core.references import cite
from ..io.netcdf import publish, write
from . import _kernels as _k
from . import _moves as _m

__all__: list[str] = []

REFERENCES = cite(("au2001", "subset simulation, cv with the chain correlation factor gamma"),
                  ("cotter2013", "pCN"),
                  ("papaioannou2015", "MCMC in subset simulation, adaptive spread"))

_METHODS = ("subset", "monte_carlo")
#: Rules (roughstick._core.arguments) of the sampler's settings, shared by its public callers.
SETTING_RULES = dict(n_per_level="count", level_probability="fraction", independent_runs="count",
                     proposal_scale="positive", target_acceptance="fraction", max_levels="count",
                     target_cv="positive?", max_evaluations="count?", confidence="fraction",
                     seed="seed", chunks="count")
#: ... and of failure_probability's surface limit state (``lower`` signed: below the mean plane).
SURFACE_RULES = dict(points_per_water_height="positive", lower="finite", connectivity=(4, 8),
                     patches="count", check_failures="count0")


def checked(*names, **more):
    """``check_numbers`` with the :data:`SETTING_RULES` of ``names`` and the ``more`` rules."""
    return check_numbers(**{n: SETTING_RULES[n] for n in names}, **more)


_PROPOSALS = ("adaptive", "pcn")
_FORMAT = "roughstick-rare-events/1"

#: CF attributes of the variables written here
ATTRS = {
    "run": {"units": "1", "long_name": "independent run index"},
    "level": {"units": "1", "long_name": "subset-simulation level (0: crude Monte Carlo)"},
    "sample": {"units": "1", "long_name": "sample index within a level (chain-major order)"},
    "noise": {"units": "1", "long_name": "white-noise coordinate (flattened standard-normal input of the limit state)"},
    "failure": {"units": "1", "long_name": "failure sample index"},
    "failure_probability": {"units": "1", "long_name": "estimated probability of the failure event"},
    "failure_probability_lower": {"units": "1", "long_name": "lower bound of the confidence interval on the failure probability"},
    "failure_probability_upper": {"units": "1", "long_name": "upper bound of the confidence interval on the failure probability"},
    "coefficient_of_variation": {"units": "1", "long_name": "estimated coefficient of variation of the failure probability estimate"},
    "n_evaluations": {"units": "1", "long_name": "number of model evaluations"},
    "au_beck_cv": {"units": "1", "long_name": "coefficient of variation from Au and Beck's level formula (chains inside a level only)"},
    "between_run_cv": {"units": "1", "long_name": "coefficient of variation from the spread of the independent runs (NaN with one run)"},
    "converged": {"units": "1", "long_name": "1 if the target coefficient of variation was met"},
    "response": {"long_name": "model response of each state"},
    "proposal_response": {"long_name": "model response of each proposed state (NaN: not evaluated)"},
    "accepted": {"units": "1", "long_name": "1 if the state is a newly accepted proposal (or a level-0 sample / chain seed), 0 if rejected, -1 no sample", "flag_values": "-1 0 1"},
    "chain": {"units": "1", "long_name": "Markov chain of the state (level 0: the sample itself), -1 no sample"},
    "level_threshold": {"long_name": "threshold the states of the level are conditioned on (NaN at level 0)"},
    "next_threshold": {"long_name": "intermediate threshold set from the level (the failure threshold at the last level)"},
    "conditional_probability": {"units": "1", "long_name": "fraction of the level's states above next_threshold"},
    "correlation_factor": {"units": "1", "long_name": "Au-Beck chain correlation factor gamma of the level"},
    "level_cv": {"units": "1", "long_name": "coefficient of variation of the level's conditional probability"},
    "proposal_scale": {"units": "1", "long_name": "proposal scale of each round of the level's chains (pCN sigma, or the adaptive lambda)"},
    "round": {"units": "1", "long_name": "step of the level's chains (step 0: the seeds)"},
    "acceptance_rate": {"units": "1", "long_name": "fraction of the level's proposals accepted"},
    "level_evaluations": {"units": "1", "long_name": "model evaluations of the level"},
    "run_probability": {"units": "1", "long_name": "failure probability estimated by the run"},
    "run_cv": {"units": "1", "long_name": "coefficient of variation of the run's estimate (genealogical)"},
    "run_evaluations": {"units": "1", "long_name": "model evaluations of the run"},
    "run_levels": {"units": "1", "long_name": "number of levels of the run"},
    "run_samples": {"units": "1", "long_name": "samples per level of the run"},
    "run_offset": {"units": "1", "long_name": "index of the run's first level-0 sample (its seed child)"},
    "failure_noise": {"units": "1", "long_name": "white noise of the failure samples of the last level (surface_from_noise regenerates them)"},
    "failure_response": {"long_name": "response of the failure samples"},
    "failure_run": {"units": "1", "long_name": "run of the failure sample"},
}


def _attrs(da, name, **extra):
    out = da.copy(deep=False)
    out.attrs = {**ATTRS[name], **extra}
    return out


# ============================================================================ settings and store
@dataclasses.dataclass(frozen=True)
class _Settings:
    """The sampler's settings of one estimate (their field names are part of the resume hash)."""

    method: str
    samples: int
    level_probability: float
    proposal: str
    scale: float
    target_acceptance: float
    max_levels: int

    @property
    def n_keep(self):
        return int(round(self.level_probability * self.samples))

    @classmethod
    def checked(cls, *, method, n_per_level, level_probability, proposal, proposal_scale,
                target_acceptance, max_levels) -> _Settings:
        """The settings, refused with the argument's name when out of range."""
        if method not in _METHODS:
            raise ValueError(f"method must be one of {_METHODS}, got {method!r}.")
        if not (isinstance(n_per_level, (int, np.integer)) and n_per_level >= 2):
            raise ValueError(f"n_per_level must be an integer >= 2, got {n_per_level!r}.")
        if not 0 < level_probability < 1:
            raise ValueError(f"level_probability must lie in (0, 1) (0.1 is customary), got {level_probability!r}.")
        if method == "subset":
            nk = level_probability * n_per_level
            if nk < 1 or n_per_level - nk < 1 or abs(nk - round(nk)) > 1e-9:
                raise ValueError(
                    f"level_probability * n_per_level = {nk:g} must be a whole number of chains "
                    f"between 1 and n_per_level - 1; e.g. n_per_level=1000 with "
                    f"level_probability=0.1.")
        if proposal not in _PROPOSALS:
            raise ValueError(f"proposal must be one of {_PROPOSALS}, got {proposal!r}.")
        if not 0 < proposal_scale <= 1:
            raise ValueError(f"proposal_scale (the pCN step sqrt(1 - rho^2)) must lie in (0, 1], got {proposal_scale!r}.")
        if not 0 < target_acceptance < 1:
            raise ValueError(f"target_acceptance must lie in (0, 1), got {target_acceptance!r}.")
        if not (isinstance(max_levels, (int, np.integer)) and max_levels >= 1):
            raise ValueError(f"max_levels must be an integer >= 1, got {max_levels!r}.")
        return cls(method, int(n_per_level), float(level_probability), proposal, float(proposal_scale),
                   float(target_acceptance), int(max_levels))

    def check_stopping(self, target_cv, max_evaluations, confidence) -> None:
        """Refuse a stopping rule the settings cannot meet."""
        if target_cv is not None and not target_cv > 0:
            raise ValueError(f"target_cv must be positive (e.g. 0.3) or None, got {target_cv!r}.")
        if max_evaluations is not None and not max_evaluations >= self.samples:
            raise ValueError(f"max_evaluations ({max_evaluations!r}) must be at least n_per_level ({self.samples}).")
        if not 0 < confidence < 1:
            raise ValueError(f"confidence must lie in (0, 1), got {confidence!r}.")


def store_token(limit_state, token):
    """The limit state's name in a stored run's parameter hash: ``token``, else its repr, refused
    when that holds a memory address (a rerun in a new process could not find the run)."""
    if token is not None:
        return token
    if " at 0x" in repr(limit_state):
        raise ValueError("output= needs token='...' for this limit state: its repr holds a memory address, so "
                         "a rerun in a new process could not find the stored run; name the limit state "
                         "and its parameters, e.g. token='linear beta=3.09'.")
    return repr(limit_state)


class _Store:
    """A folder of one NetCDF file per completed level plus a manifest (resume)."""

    def __init__(self, folder, token, overwrite, info, rattrs):
        import shutil

        self.rattrs = rattrs
        self.folder = pathlib.Path(folder)
        self.token = token
        if self.folder.exists() and not self.folder.is_dir():
            raise FileExistsError(f"output {str(self.folder)!r} exists and is not a folder; choose another path.")
        manifest = self.folder / "manifest.json"
        if self.folder.exists() and any(self.folder.iterdir()):
            old = json.loads(manifest.read_text()) if manifest.exists() else None
            if old is None or old.get("params_hash") != token:
                if not overwrite:
                    what = ("holds a run with different parameters" if old is not None
                            else "is not empty and holds no rare-event manifest")
                    raise FileExistsError(
                        f"output folder {str(self.folder)!r} {what}; refusing to mix them. Resume with "
                        "the original parameters, pass overwrite=True to replace it, or choose another "
                        "folder.")
                shutil.rmtree(self.folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        for p in self.folder.glob("*.tmp*"):
            p.unlink()
        if not manifest.exists():
            tmp = manifest.with_suffix(".json.tmp")
            tmp.write_text(json.dumps({"format": _FORMAT, "params_hash": token, **info}, indent=1))
            publish(tmp, manifest)

    def path(self, run, level):
        return self.folder / f"run{run:03d}-level{level:02d}.nc"

    def load(self, run, level):
        p = self.path(run, level)
        if not p.exists():
            return None
        with xr.open_dataset(p) as ds:
            ds = ds.load()
        if ds.attrs.get("roughstick_params_hash") != self.token:
            return None
        return _Level.from_dataset(ds)

    def save(self, run, level, lev):

        ds = lev.to_dataset(self.rattrs)
        ds.attrs = {"roughstick_params_hash": self.token, "run": run, "level": level,
                    "Conventions": "CF-1.10", "title": "one completed subset-simulation level"}
        write(ds, self.path(run, level), compute=True, overwrite=True)


# ============================================================================ one level
_LEVEL_VARS = {
    "response": "response of each state", "proposal_response": "response of each proposal",
    "accepted": "1 if the state is an accepted proposal or a seed", "chain": "chain of the state",
    "keep_noise": "white noise of the states kept (next seeds or failures)",
    "keep_response": "response of the states kept", "scales": "proposal scale of each round",
    "spread": "spread of the seeds per white-noise coordinate",
    "threshold": "conditioning threshold", "next_threshold": "next intermediate threshold",
    "probability": "conditional probability", "gamma": "chain correlation factor",
    "cv2": "squared coefficient of variation", "final": "1 if last level",
    "evaluations": "model evaluations", "noise_shape": "shape of the white noise", "sample": "sample",
}
_RESPONSE_VARS = ("response", "proposal_response", "keep_response", "threshold", "next_threshold")
@dataclasses.dataclass
class _Level:
    response: np.ndarray
    proposal: np.ndarray
    accepted: np.ndarray
    chain: np.ndarray
    threshold: float          # conditioning threshold (-inf at level 0)
    next_threshold: float
    final: bool
    probability: float
    gamma: float
    cv2: float
    evaluations: int
    scales: np.ndarray        # proposal scale of each step (NaN at step 0 / level 0)
    spread: np.ndarray        # per-coordinate spread of the seeds (ones at level 0)
    keep_noise: np.ndarray = None   # seeds of the next level, or failure samples of the last
    keep_response: np.ndarray = None

    @property
    def acceptance(self):
        prop = ~np.isnan(self.proposal)
        return float(self.accepted[prop].mean()) if prop.any() else float("nan")

    def to_dataset(self, rattrs):
        n = self.response.size
        kn = self.keep_noise.reshape(self.keep_noise.shape[0], self.spread.size)  # 0 kept: (0, n)
        ds = xr.Dataset(
            {
                "response": ("sample", self.response),
                "proposal_response": ("sample", self.proposal),
                "accepted": ("sample", self.accepted.astype(np.int8)),
                "chain": ("sample", self.chain.astype(np.int32)),
                "keep_noise": (("keep", "noise"), kn),
                "keep_response": ("keep", self.keep_response),
                "scales": ("round", self.scales),
                "spread": ("noise", self.spread.ravel()),
            },
            coords={"sample": np.arange(n)},
        )
        for name in ("threshold", "next_threshold", "probability", "gamma", "cv2"):
            ds[name] = xr.DataArray(float(getattr(self, name)))
        ds["final"] = xr.DataArray(np.int8(self.final))
        ds["evaluations"] = xr.DataArray(np.int64(self.evaluations))
        ds["noise_shape"] = xr.DataArray(np.asarray(self.spread.shape, dtype=np.int64), dims="noise_axis")
        for name, long_name in _LEVEL_VARS.items():
            units = rattrs.get("units", "1") if name in _RESPONSE_VARS else "1"
            ds[name].attrs = {"units": units, "long_name": long_name}
        return ds

    @classmethod
    def from_dataset(cls, ds):
        shape = tuple(int(v) for v in ds["noise_shape"].values)
        kn = ds["keep_noise"].values.reshape((ds.sizes["keep"],) + shape)
        return cls(
            response=ds["response"].values, proposal=ds["proposal_response"].values,
            accepted=ds["accepted"].values.astype(np.int8), chain=ds["chain"].values.astype(np.int64),
            threshold=float(ds["threshold"]), next_threshold=float(ds["next_threshold"]),
            final=bool(int(ds["final"])), probability=float(ds["probability"]),
            gamma=float(ds["gamma"]), cv2=float(ds["cv2"]), evaluations=int(ds["evaluations"]),
            scales=ds["scales"].values, spread=ds["spread"].values.reshape(shape),
            keep_noise=kn, keep_response=ds["keep_response"].values,
        )


# ============================================================================ dask
def _compute(fn, model, blocks, scheduler, **kwargs):
    """Evaluate ``fn(model, block, **kwargs)`` for each block on dask; results in block order."""
    import dask

    client, local = resolve_scheduler(scheduler)
    model_d = dask.delayed(model, pure=True, traverse=False)
    tasks = [dask.delayed(fn, pure=False)(model_d, b, **kwargs) for b in blocks]
    try:
        if client is not None:
            return client.gather(client.compute(tasks))
        return list(dask.compute(*tasks, scheduler=local))
    finally:
        if client is not None and owns_client(scheduler):
            client.close()


def _level0_block(model, indices, *, entropy, spawn_key, noise_shape):
    return _k.evaluate_samples(model, indices, entropy=entropy, spawn_key=spawn_key, noise_shape=noise_shape)


def _round_block(model, block, *, entropy, spawn_key, run, level, step, threshold, move):
    out = []
    for c, z, y in block:
        rng = _k.step_rng(entropy, spawn_key, run, level, c, step)
        out.append(_k.chain_step(model, z, y, threshold=threshold, move=move, rng=rng))
    return out


def _blocks(items, size):
    return [items[i:i + size] for i in range(0, len(items), size)]


# ============================================================================ the engine
class _Engine:
    def __init__(self, model, noise_shape, threshold, settings, root, chunks, scheduler, store,
                 max_evaluations=None):
        self.model = model
        self.noise_shape = tuple(int(v) for v in noise_shape)
        self.y_star = float(threshold)
        self.s = settings
        self.entropy = root.entropy
        self.spawn_key = tuple(root.spawn_key)
        self.chunks = int(chunks)
        self.scheduler = scheduler
        self.store = store
        # one line per level with the time left (the caller's progress counts the points of a
        # whole command; alone, this estimate is one point)
        self.progress = current_staged_progress() or StagedProgress(
            1, what=settings.method.replace("_", " "), budget=max_evaluations)
        self.progress.start_point(f"RH {model.rh:g}" if isinstance(getattr(model, "rh", None), float) else "")
        if settings.method == "subset":  # a run started is completed: up to max_levels levels
            self.progress.set_cap(settings.samples + (settings.max_levels - 1) * (settings.samples - 1))
        self._computed = True

    # -- level 0: independent samples ------------------------------------------------------
    def level0(self, run, offset, n):
        idx = list(range(offset, offset + n))
        parts = _compute(_level0_block, self.model, _blocks(idx, self.chunks), self.scheduler,
                         entropy=self.entropy, spawn_key=self.spawn_key, noise_shape=self.noise_shape)
        y = np.concatenate(parts) if parts else np.empty(0)
        lev = self._finish(y, np.full(n, np.nan), np.ones(n, np.int8), np.arange(n),
                           threshold=-np.inf, evaluations=n, scales=np.full(1, np.nan),
                           spread=np.ones(self.noise_shape), last=self.s.max_levels == 1)

        def noise_of(sel):
            return np.stack([_k.sample_noise(offset + int(i), entropy=self.entropy,
                                             spawn_key=self.spawn_key, noise_shape=self.noise_shape)
                             for i in sel]) if len(sel) else np.empty((0,) + self.noise_shape)

        return self._keep(lev, noise_of)

    # -- level j >= 1: conditional chains, advanced in rounds ----------------------------------
    def level(self, run, j, prev, scale):
        """Grow the chains of level ``j`` from the seeds kept by ``prev``; returns (level, scale)."""
        n = self.s.samples
        seeds_z, seeds_y = prev.keep_noise, prev.keep_response
        m = seeds_y.size
        lengths = _k.chain_lengths(n, m)
        b = prev.next_threshold
        adaptive = self.s.proposal == "adaptive"
        spread = seeds_z.std(axis=0, ddof=1) if adaptive and m > 1 else np.ones(self.noise_shape)
        L = int(lengths.max())
        ys = np.full((m, L), np.nan)
        yps = np.full((m, L), np.nan)
        accs = np.zeros((m, L), np.int8)
        ys[:, 0] = seeds_y
        accs[:, 0] = 1
        zs = [np.array(z, dtype=float) for z in seeds_z]
        scales = np.full(L, np.nan)
        moves = [None] * L
        per_task = max(1, self.chunks)
        for k in range(1, L):
            moves[k] = _m.PCNMove(*_k.proposal_scales(spread, scale))
            scales[k] = scale
            active = [c for c in range(m) if lengths[c] > k]
            items = [(c, zs[c], ys[c, k - 1]) for c in active]
            parts = _compute(_round_block, self.model, _blocks(items, per_task), self.scheduler,
                             entropy=self.entropy, spawn_key=self.spawn_key, run=run, level=j, step=k,
                             threshold=b, move=moves[k])
            results = [r for part in parts for r in part]
            for c, (z_new, y_new, yp, a) in zip(active, results, strict=True):
                zs[c] = z_new
                ys[c, k], yps[c, k], accs[c, k] = y_new, yp, a
            if adaptive and np.isfinite(scales[k]):
                scale = _k.adapt_scale(scale, float(np.mean([r[3] for r in results])),
                                       self.s.target_acceptance, k)
        keep = np.arange(L)[None, :] < lengths[:, None]
        y, yp, acc = ys[keep], yps[keep], accs[keep]
        chain = np.repeat(np.arange(m), lengths)
        lev = self._finish(y, yp, acc, chain, threshold=b, evaluations=int(n - m), scales=scales,
                           spread=spread, last=j >= self.s.max_levels - 1)
        starts = np.concatenate([[0], np.cumsum(lengths)[:-1]])

        def noise_of(sel):
            out = []
            sel = np.asarray(sel, dtype=np.int64)
            for c in np.unique(chain[sel]):
                steps = sel[chain[sel] == c] - starts[c]
                a = acc[starts[c]:starts[c] + lengths[c]]
                out.extend(_k.replay_chain(
                    seeds_z[c], a, steps, moves=moves,
                    rng_of_step=lambda k, c=int(c): _k.step_rng(self.entropy, self.spawn_key, run, j, c, k)))
            return np.stack(out) if out else np.empty((0,) + self.noise_shape)

        return self._keep(lev, noise_of), scale

    def _finish(self, y, yp, acc, chain, *, threshold, evaluations, scales, spread, last=False):
        s = self.s
        n = y.size
        if s.method == "monte_carlo" or last:
            b, final = self.y_star, True
        else:
            b = _k.intermediate_threshold(y, s.n_keep)
            final = b >= self.y_star
            if final:
                b = self.y_star
        ind = np.where(np.isnan(y), False, y > b)
        if not final and not ind.any():  # an atom at the top of the response: cannot go on
            b, final = self.y_star, True
            ind = np.where(np.isnan(y), False, y > b)
        p = float(ind.mean())
        if np.isfinite(threshold):
            per_chain = [ind[chain == c] for c in np.unique(chain)]
            gamma = _k.correlation_factor(per_chain, p)
        else:
            gamma = 0.0
        return _Level(response=y, proposal=yp, accepted=acc, chain=chain, threshold=float(threshold),
                      next_threshold=float(b), final=bool(final), probability=p, gamma=float(gamma),
                      cv2=_k.level_cv2(p, n, gamma), evaluations=int(evaluations), scales=scales,
                      spread=spread)

    def _keep(self, lev, noise_of):
        sel = np.flatnonzero(np.where(np.isnan(lev.response), False, lev.response > lev.next_threshold))
        lev.keep_noise = noise_of(sel)
        lev.keep_response = lev.response[sel]
        return lev

    # -- one run ------------------------------------------------------------------------------
    def run(self, r, offset, n):
        levels = []
        lev = self._load_or(r, 0, lambda: (self.level0(r, offset, n), None))
        levels.append(lev)
        self._report(r, levels)
        scale = self.s.scale
        while not lev.final:
            j = len(levels)
            if j > 1 and self.s.proposal != "pcn":  # carry the scale the last level ended with
                scale = _last_scale(levels[-1], self.s)
            prev = lev
            lev = self._load_or(r, j, lambda j=j, prev=prev, scale=scale: self.level(r, j, prev, scale))
            levels.append(lev)
            self._report(r, levels)
        return levels

    def _report(self, r, levels):
        """The progress line of the level just completed (INFO, logger ``roughstick``)."""
        lev, j = levels[-1], len(levels) - 1
        where = f"batch {r + 1}" if self.s.method == "monte_carlo" else f"run {r + 1}, level {j}"
        goal = ("failure threshold" if lev.final else
                f"threshold {lev.next_threshold:.4g} of {self.y_star:.4g}")
        p = float(np.prod([lv.probability for lv in levels]))
        self.progress.stage(f"{where} done ({goal}; P {'=' if lev.final else 'so far'} {p:.3g})",
                            evaluations=lev.evaluations, computed=self._computed)

    def _load_or(self, r, j, compute):
        self._computed = True
        if self.store is not None:
            lev = self.store.load(r, j)
            if lev is not None:
                self._computed = False  # read back: not timed
                return lev
        lev, _ = compute()
        if self.store is not None:
            self.store.save(r, j, lev)
        return lev


def _last_scale(lev, s):
    """The scale after the last round of a level (replays the deterministic update)."""
    sc = lev.scales
    k = int(np.max(np.flatnonzero(np.isfinite(sc)))) if np.isfinite(sc).any() else 0
    if k == 0:
        return s.scale
    prop = ~np.isnan(lev.proposal)
    # acceptance of the last round: states at step k of every chain
    steps = np.concatenate([np.arange(c) for c in np.bincount(lev.chain)])
    sel = prop & (steps == k)
    return _k.adapt_scale(float(sc[k]), float(lev.accepted[sel].mean()), s.target_acceptance, k)


def _above(lv):
    return np.where(np.isnan(lv.response), False, lv.response > lv.next_threshold)


def _genealogical_cv2(levels):
    """Squared cv of one run from its genealogy (see ``_kernels.genealogical_cv2``)."""
    kept = [np.flatnonzero(_above(lv)) for lv in levels]
    roots = _k.root_ancestors([lv.chain for lv in levels], kept)
    return _k.genealogical_cv2(roots[-1], _above(levels[-1]), levels[0].response.size)


class RunSummary(NamedTuple):
    """One run's estimate: P, its genealogical cv, model evaluations and Au-Beck's cv."""

    probability: float
    cv: float
    evaluations: int
    au_beck_cv: float


def _run_summary(levels) -> RunSummary:
    """The :class:`RunSummary` of one run (a list of levels)."""
    p = float(np.prod([lv.probability for lv in levels]))
    au2 = float(sum(lv.cv2 for lv in levels))
    return RunSummary(p, math.sqrt(_genealogical_cv2(levels)), int(sum(lv.evaluations for lv in levels)),
                      math.sqrt(au2))


@dataclasses.dataclass
class Runs:
    """The independent runs of one estimate: their levels, sizes (samples per level) and the
    index of each run's first level-0 sample."""

    levels: list = dataclasses.field(default_factory=list)
    sizes: list = dataclasses.field(default_factory=list)
    offsets: list = dataclasses.field(default_factory=list)

    def add(self, levels, size, offset):
        self.levels.append(levels)
        self.sizes.append(size)
        self.offsets.append(offset)

    def __len__(self):
        return len(self.levels)

    def summaries(self) -> list[RunSummary]:
        return [_run_summary(lv) for lv in self.levels]

    def evaluations(self) -> int:
        return sum(s.evaluations for s in self.summaries())

    def largest_run(self) -> int:
        """Model evaluations of the costliest run so far."""
        return max(s.evaluations for s in self.summaries())


@dataclasses.dataclass(frozen=True)
class Estimate:
    """P, its cv (the one the interval uses), Au-Beck's and the between-run cv, the interval
    and how it was built."""

    probability: float
    cv: float
    au_beck_cv: float
    between_run_cv: float
    lower: float
    upper: float
    interval: str


def _estimate(runs: Runs, method, confidence) -> Estimate:
    """Estimate, cv and interval from the runs (see subset_simulation's Notes)."""
    from scipy.special import stdtrit

    # a subset run that stops at level 0 is crude Monte Carlo: the binomial cv and Wilson interval
    # (Au-Beck's and the genealogical cv are 0 when every sample fails, which no sample proves)
    if method == "monte_carlo" or all(len(levels) == 1 for levels in runs.levels):
        k = sum(int(round(lv[0].probability * n)) for lv, n in zip(runs.levels, runs.sizes, strict=True))
        tot = sum(runs.sizes)
        p = k / tot
        cv = math.sqrt((1 - p) / (tot * p)) if p > 0 else math.inf
        return Estimate(p, cv, cv, math.nan, *_k.wilson_interval(k, tot, confidence), "wilson")
    summ = runs.summaries()
    ps = np.array([a.probability for a in summ])
    cvs = np.array([a.cv for a in summ])
    R = ps.size
    p = float(ps.mean())
    aus = np.array([a.au_beck_cv for a in summ])
    gen = float(math.sqrt(np.mean(cvs**2) / R)) if np.all(np.isfinite(cvs)) else math.inf
    au = float(math.sqrt(np.mean(aus**2) / R)) if np.all(np.isfinite(aus)) else math.inf
    between = float(ps.std(ddof=1) / math.sqrt(R) / p) if R >= 2 and p > 0 else math.nan
    if R >= 3 and np.isfinite(between) and between > gen:
        cv, q, how = between, float(stdtrit(R - 1, 0.5 + confidence / 2)), f"log-normal, between-run cv, Student t with {R - 1} dof"
    else:
        cv, q, how = gen, None, "log-normal, genealogical cv"
    if p > 0:
        lo, hi = _k.lognormal_interval(p, cv, confidence, quantile=q)
    else:  # no failure seen: the levels reached times a Wilson bound on 0 out of N
        bounds = [float(np.prod([lv.probability for lv in levels[:-1]]))
                  * _k.wilson_interval(0, levels[-1].response.size, confidence)[1] for levels in runs.levels]
        lo, hi, cv = 0.0, min(bounds), math.inf
    return Estimate(p, cv, au, between, lo, hi, how)


def _level_arrays(runs: Runs):
    """The per-state ``(run, level, sample)``, per-level ``(run, level)`` and per-round arrays
    of the runs, and the failure samples of their last levels."""
    R, L, N = len(runs), max(len(lv) for lv in runs.levels), max(runs.sizes)
    resp = np.full((R, L, N), np.nan)
    prop = np.full((R, L, N), np.nan)
    acc = np.full((R, L, N), -1, np.int8)
    chain = np.full((R, L, N), -1, np.int32)
    per = {k: np.full((R, L), np.nan) for k in ("level_threshold", "next_threshold", "conditional_probability",
                                               "correlation_factor", "level_cv",
                                               "acceptance_rate", "level_evaluations")}
    fails, frun, fresp = [], [], []
    n_round = max(lv.scales.size for levels in runs.levels for lv in levels)
    scale = np.full((R, L, n_round), np.nan)
    for r, levels in enumerate(runs.levels):
        for j, lv in enumerate(levels):
            n = lv.response.size
            resp[r, j, :n] = lv.response
            prop[r, j, :n] = lv.proposal
            acc[r, j, :n] = lv.accepted
            chain[r, j, :n] = lv.chain
            per["level_threshold"][r, j] = lv.threshold if np.isfinite(lv.threshold) else np.nan
            per["next_threshold"][r, j] = lv.next_threshold
            per["conditional_probability"][r, j] = lv.probability
            per["correlation_factor"][r, j] = lv.gamma
            per["level_cv"][r, j] = math.sqrt(lv.cv2)
            scale[r, j, :lv.scales.size] = lv.scales
            per["acceptance_rate"][r, j] = lv.acceptance
            per["level_evaluations"][r, j] = lv.evaluations
        last = levels[-1]
        if last.final and last.keep_noise is not None and last.keep_noise.shape[0]:
            fails.append(last.keep_noise.reshape(last.keep_noise.shape[0], -1))
            frun.extend([r] * last.keep_noise.shape[0])
            fresp.extend(last.keep_response.tolist())
    states = {"response": resp, "proposal_response": prop, "accepted": acc, "chain": chain}
    return states, per, scale, (fails, frun, fresp)


def _to_dataset(runs: Runs, s: _Settings, *, threshold, target_cv, converged, confidence, root, rattrs):
    """The result Dataset of :func:`roughstick.reliability.subset_simulation`."""
    method = s.method
    states, per, scale, (fails, frun, fresp) = _level_arrays(runs)
    summ = runs.summaries()
    est = _estimate(runs, method, confidence)
    R, L, N = states["response"].shape
    rdims = ("run", "level", "sample")
    ds = xr.Dataset(coords={"run": np.arange(R), "level": np.arange(L), "sample": np.arange(N)})
    for k, v in states.items():
        extra = rattrs if k in ("response", "proposal_response") else {}
        ds[k] = _attrs(xr.DataArray(v, dims=rdims), k, **extra)
    for k, v in per.items():
        extra = rattrs if k in ("level_threshold", "next_threshold") else {}
        ds[k] = _attrs(xr.DataArray(v, dims=("run", "level")), k, **extra)
    ds["proposal_scale"] = _attrs(xr.DataArray(scale, dims=("run", "level", "round")), "proposal_scale")
    ds["run_probability"] = _attrs(xr.DataArray([a.probability for a in summ], dims="run"), "run_probability")
    ds["run_cv"] = _attrs(xr.DataArray([a.cv for a in summ], dims="run"), "run_cv")
    ds["run_evaluations"] = _attrs(xr.DataArray(np.array([a.evaluations for a in summ], np.int64), dims="run"),
                                   "run_evaluations")
    ds["run_levels"] = _attrs(xr.DataArray(np.array([len(lv) for lv in runs.levels], np.int64), dims="run"),
                              "run_levels")
    ds["run_samples"] = _attrs(xr.DataArray(np.array(runs.sizes, np.int64), dims="run"), "run_samples")
    ds["run_offset"] = _attrs(xr.DataArray(np.array(runs.offsets, np.int64), dims="run"), "run_offset")
    if fails:
        ds["failure_noise"] = _attrs(xr.DataArray(np.concatenate(fails), dims=("failure", "noise")), "failure_noise")
        ds["failure_run"] = _attrs(xr.DataArray(np.array(frun, np.int64), dims="failure"), "failure_run")
        ds["failure_response"] = _attrs(xr.DataArray(np.array(fresp), dims="failure"), "failure_response", **rattrs)
    ds["failure_probability"] = _attrs(xr.DataArray(est.probability), "failure_probability")
    ds["failure_probability_lower"] = _attrs(xr.DataArray(float(est.lower)), "failure_probability_lower")
    ds["failure_probability_upper"] = _attrs(xr.DataArray(float(est.upper)), "failure_probability_upper")
    ds["coefficient_of_variation"] = _attrs(xr.DataArray(float(est.cv)), "coefficient_of_variation")
    ds["au_beck_cv"] = _attrs(xr.DataArray(float(est.au_beck_cv)), "au_beck_cv")
    ds["between_run_cv"] = _attrs(xr.DataArray(float(est.between_run_cv)), "between_run_cv")
    ds["n_evaluations"] = _attrs(xr.DataArray(np.int64(sum(a.evaluations for a in summ))), "n_evaluations")
    ds["converged"] = _attrs(xr.DataArray(np.int8(bool(converged) and est.probability > 0)), "converged")
    ds = ds.assign_coords(round=np.arange(scale.shape[2]))
    for c in ("run", "level", "sample", "round"):
        ds[c].attrs = dict(ATTRS[c])
    recorded = int(root.entropy) if int(root.entropy) < 2**63 else str(root.entropy)
    first = runs.levels[0][0]
    ds.attrs = dataset_attrs(
        "failure probability by " + ("subset simulation" if method == "subset" else "crude Monte Carlo"),
        references=REFERENCES, method=method, threshold=float(threshold),
        samples_per_level=int(s.samples), level_probability=float(s.level_probability),
        proposal=s.proposal, proposal_scale=float(s.scale),
        target_acceptance=float(s.target_acceptance), confidence_level=float(confidence),
        interval_method=est.interval, target_cv=float(target_cv) if target_cv is not None else "none",
        seed=recorded, noise_shape=list(first.keep_noise.shape[1:]) if first.keep_noise is not None else [],
    )
    append_history(ds, f"subset_simulation(method={method!r}, threshold={threshold:.6g}, runs={R}, "
                       f"evaluations={int(ds.n_evaluations)})")
    return ds
