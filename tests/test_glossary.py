"""One meaning per keyword, over every public signature (docs/architecture.md, the glossary).

Each keyword of the public API means one thing everywhere: ``model`` is the contact model only,
the accepted error, a solver's tolerance and a convergence rule have three names, ``confidence``
is an interval's level, ``n`` counts what is drawn, a beam's length is ``beam_length``,
``material`` defaults to poly-silicon. The front door is small: at most 40 top-level names.
"""

from __future__ import annotations

import importlib
import inspect

import pytest

import roughstick as rs
from roughstick._core.materials import POLYSILICON

#: Keywords that are not part of the glossary, and what to write instead.
FORBIDDEN = {
    "tolerance": "accuracy (accepted error), solver_tolerance (a solver's) or target_precision "
                 "(a convergence rule)",
    "level": "confidence (an interval's level) or probability (a probability level)",
    "length": "beam_length",
    "n_realization": "n",
    "n_law": "n",
    "samples_per_level": "n_per_level",
    "n_distances": "n_distance",
    "num": "n_distance",
    "contact_model": "model",
    "rh": "relative_humidity",
}
#: What ``model=`` may name: the contact models (their registry) and "auto".
CONTACT_MODEL_DEFAULTS = {None, "auto", "modified_dmt", "gw", "fft_bem", "bem"}
NAMESPACES = ("io", "surface", "contact", "ensemble", "stiction", "beam", "reliability",
              "datasets", "testing")

#: Signatures not yet in the glossary: (function, keyword). Shrinks to empty as the API moves to
#: its namespaces; an entry that no longer applies fails the test, so the list stays true.
NOT_YET: set = set()


def _public_callables():
    seen = {}
    sources = [("roughstick", rs)]
    for ns in NAMESPACES:
        try:
            sources.append((f"roughstick.{ns}", importlib.import_module(f"roughstick.{ns}")))
        except ImportError:
            continue
    for prefix, mod in sources:
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name, None)
            if callable(obj) and not isinstance(obj, (type, type(rs))):  # classes: fields
                seen.setdefault(id(obj), (f"{prefix}.{name}", obj))
    return sorted(seen.values(), key=lambda t: t[0])


def _violations():
    out = {}
    for qual, obj in _public_callables():
        try:
            params = inspect.signature(obj).parameters
        except (TypeError, ValueError):
            continue
        name = getattr(obj, "__name__", qual.rsplit(".", 1)[-1])
        for p in params.values():
            why = None
            if p.name in FORBIDDEN:
                why = f"write {FORBIDDEN[p.name]}"
            elif p.name == "model" and ("sphere" in name or "sphere" in getattr(obj, "__module__", "")
                                        or (isinstance(p.default, str)
                                            and p.default not in CONTACT_MODEL_DEFAULTS)):
                why = "model= is the contact model: write sphere_model, beam_model or layer_model"
            elif p.name in ("material", "material1") and p.default is not p.empty \
                    and p.default is not None and p.default != POLYSILICON:
                why = "material defaults to poly-silicon"
            if why:
                out[(name, p.name)] = f"{qual}({p.name}=...): {why}"
    return out


def test_one_meaning_per_keyword():
    found = _violations()
    new = {k: v for k, v in found.items() if k not in NOT_YET}
    assert not new, "keywords outside the glossary:\n" + "\n".join(sorted(new.values()))
    stale = NOT_YET - set(found)
    assert not stale, f"remove from NOT_YET (now in the glossary): {sorted(stale)}"


def test_the_front_door_is_small():
    assert len(rs.__all__) <= 40, f"{len(rs.__all__)} top-level names"


def test_renamed_names_point_somewhere():
    """Every old top-level name in the rename table resolves, with a warning naming the new one."""
    from roughstick._renamed import RENAMED

    for old, new in RENAMED.items():
        assert rs._resolve(new) is not None, (old, new)
        if old not in vars(rs):
            with pytest.warns(DeprecationWarning, match=new.replace(".", r"\.")):
                getattr(rs, old)
