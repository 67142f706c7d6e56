"""The guard of the package layout (issue 11): run it before landing anything in roughstick/.

It reads every module of the package with ``ast`` (nothing is imported) and fails on

- an import that goes up the layers, or sideways between two stages of the same rank;
- a cycle between modules;
- a private name (``_x``, or a ``_module``) imported from another subpackage (``_core`` is the
  shared layer: its public names are for everyone, its private ones for itself);
- a function-local import of a roughstick module (function-local imports are for optional
  dependencies only: Tamaas, SurfaceTopography, distributed, tqdm, IPython, and matplotlib, which
  the plotting functions import when called so that ``import roughstick.plotting`` stays cheap);
- a function longer than 120 lines (its docstring not counted; numba kernels excepted: they are
  one loop nest each, and splitting them costs calls in the innermost loop);
- three or more ``_prefix_*.py`` modules side by side: a family that shares private state is a
  sub-package (``contact/modified_dmt/``), not a naming convention.

A new subpackage or top-level module must be given a rank in ``RANK`` below.
"""

from __future__ import annotations

import ast
import pathlib
from collections import defaultdict

import pytest

PACKAGE = pathlib.Path(__file__).resolve().parents[1] / "roughstick"
MAX_FUNCTION_LINES = 120

#: Layers, bottom first (docs/architecture.md). A module may import from a lower rank, and from
#: its own layer; never from a higher rank nor from another layer of the same rank.
RANK = {
    "_core": 0,        # units, validate, references, conventions, constants, materials, dask, api
    "_renamed": 0,     # the table of old top-level names (data only)
    "io": 1,
    "surface": 1,
    "testing": 1,      # public test helpers (make_topography, ...) over _core
    "datasets": 2,     # bundled data: uses io and surface
    "contact": 3,
    "ensemble": 4,
    "stiction": 5,     # Eq. 36 and the paper's section 5 proxy
    "beam": 6,         # the beam-scale model: sharp front, cohesive beam, patch banks
    "reliability": 7,  # small probabilities: subset simulation, limit states, weakest link
    "plotting": 8,
    "accessor": 8,     # forwarding methods over every stage
    "paper": 9,        # the figures of the paper, once, and the steps of `roughstick demo`
    "cli": 10,         # calls paper/
    "__main__": 11,    # python -m roughstick: runs cli
    "roughstick": 11,  # the package's __init__: the front door
}
#: Layers allowed to import the facade ``import roughstick as rs`` (applications of the package).
FACADE_USERS = {"paper", "cli"}


def _module_name(path: pathlib.Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _layer(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "roughstick"


def _is_package(module: str) -> bool:
    return MODULES.get(module, pathlib.Path()).name == "__init__.py"


def _resolve(importer: str, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = importer.split(".")
    if not _is_package(importer):
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(module: str):
    """(target module, imported names, line, inside a function) for every roughstick import."""
    tree = ast.parse(MODULES[module].read_text())
    parents = {}
    for parent in ast.walk(tree):
        for child in ast.iter_child_nodes(parent):
            parents[child] = parent

    def local(node):
        while node in parents:
            node = parents[node]
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                return True
        return False

    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "roughstick":
                    yield alias.name, [], node.lineno, local(node)
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(module, node)
            if target.split(".")[0] != "roughstick":
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if sub in MODULES:  # `from pkg import submodule`
                    yield sub, [], node.lineno, local(node)
                else:
                    yield target, [alias.name], node.lineno, local(node)


EDGES = {m: list(_imports(m)) for m in MODULES}


def test_every_layer_has_a_rank():
    missing = sorted({_layer(m) for m in MODULES} - set(RANK))
    assert not missing, f"give these new layers a rank in tests/test_architecture.py RANK: {missing}"


def test_imports_only_go_down():
    bad = []
    for module, edges in EDGES.items():
        src = _layer(module)
        for target, _, line, _ in edges:
            dst = _layer(target)
            if dst == src:
                continue
            if target == "roughstick":
                if src not in FACADE_USERS:
                    bad.append(f"{module}:{line} imports the roughstick facade (only {sorted(FACADE_USERS)} may)")
            elif RANK[dst] >= RANK[src]:
                bad.append(f"{module}:{line} imports {target} ({dst}, rank {RANK[dst]}) from rank {RANK[src]}")
    assert not bad, "upward or sideways imports:\n" + "\n".join(bad)


def test_no_import_cycle():
    graph = defaultdict(set)
    for module, edges in EDGES.items():
        for target, _, _, _ in edges:
            if target in MODULES and target != module:
                graph[module].add(target)
    index, low, stack, on_stack, cycles = {}, {}, [], set(), []
    counter = [0]

    def visit(v):  # Tarjan's strongly connected components
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in list(MODULES):
        if v not in index:
            visit(v)
    assert not cycles, f"import cycles: {cycles}"


def _owner(target: str, names) -> str | None:
    """The package that owns the private part of an import (None: nothing private).

    ``roughstick.contact.modified_dmt._kernels`` is owned by ``roughstick.contact.modified_dmt``; a
    private name ``_x`` of ``roughstick.contact.meniscus`` by ``roughstick.contact``. ``_core`` is the
    shared layer: its public names are for everyone."""
    parts = target.split(".")
    for i, part in enumerate(parts[1:], start=1):
        if part.startswith("_") and part != "_core" and not part.endswith("__"):
            return ".".join(parts[:i])
    if any(n.startswith("_") and not n.endswith("__") for n in names):
        return target if _is_package(target) else ".".join(parts[:-1])
    return None


def test_no_private_name_across_subpackages():
    """A private module or name is used only inside the package that owns it (and the packages
    nested in it): a family's private state stays in its sub-package."""
    bad = []
    for module, edges in EDGES.items():
        for target, names, line, _ in edges:
            owner = _owner(target, names)
            if owner is None or owner == "roughstick":
                if owner is None or _layer(module) == _layer(target):
                    continue
            if module == owner or module.startswith(owner + "."):
                continue
            private = [n for n in names if n.startswith("_") and not n.endswith("__")]
            bad.append(f"{module}:{line} imports {private or target} from {target} (private to {owner})")
    assert not bad, ("private names across (sub-)packages (move the shared part to the owner's "
                     "_shared.py or to _core, or make it public where users need it):\n" + "\n".join(bad))


def test_function_local_imports_are_for_optional_dependencies_only():
    bad = []
    for module, edges in EDGES.items():
        for target, _, line, is_local in edges:
            if is_local:
                bad.append(f"{module}:{line} imports {target} inside a function")
    assert not bad, "function-local imports of roughstick modules:\n" + "\n".join(bad)


def _is_numba(node) -> bool:
    return any(any(k in ast.unparse(d) for k in ("njit", "numba", "jit")) for d in node.decorator_list)


def _long_functions():
    """(module, qualified name, lines) of every function over the cap (docstring not counted)."""
    out = []
    for module, path in MODULES.items():
        tree = ast.parse(path.read_text())
        stack = [(tree, "")]
        while stack:
            node, prefix = stack.pop()
            for child in ast.iter_child_nodes(node):
                if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                    name = f"{prefix}{child.name}"
                    stack.append((child, name + "."))
                    if isinstance(child, ast.ClassDef) or _is_numba(child):
                        continue
                    body = child.body
                    if (isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant)
                            and isinstance(body[0].value.value, str)):
                        body = body[1:]
                    if body:
                        n = body[-1].end_lineno - body[0].lineno + 1
                        if n > MAX_FUNCTION_LINES:
                            out.append((module, name, n))
    return out


#: Functions over the cap that the restructuring has still to split (shrinks to empty; an entry
#: that no longer applies fails the test, so the list stays true).
LONG_FUNCTIONS_TO_SPLIT: set[tuple[str, str]] = set()


def test_function_length():
    long = _long_functions()
    new = [f"{m}.{f}: {n} lines" for m, f, n in long if (m, f) not in LONG_FUNCTIONS_TO_SPLIT]
    assert not new, (f"functions over {MAX_FUNCTION_LINES} lines (docstring not counted): split them "
                     "by what they do:\n" + "\n".join(new))
    stale = LONG_FUNCTIONS_TO_SPLIT - {(m, f) for m, f, _ in long}
    assert not stale, f"remove from LONG_FUNCTIONS_TO_SPLIT (now short or gone): {sorted(stale)}"


def _prefix_families():
    """{(folder, prefix): [files]} for every ``_prefix_*.py`` group of three or more modules."""
    groups = defaultdict(list)
    for path in MODULES.values():
        parts = path.stem.split("_")
        if path.stem.startswith("_") and len(parts) >= 3 and parts[1]:
            groups[(str(path.parent.relative_to(PACKAGE.parent)), parts[1])].append(path.name)
    return {k: sorted(v) for k, v in groups.items() if len(v) >= 3}


#: ``_prefix_`` families still to become sub-packages (shrinks to empty, as above).
PREFIX_FAMILIES_TO_MOVE: set = set()


def test_families_of_private_modules_are_sub_packages():
    fam = _prefix_families()
    new = {k: v for k, v in fam.items() if k not in PREFIX_FAMILIES_TO_MOVE}
    assert not new, f"three or more _prefix_ modules side by side: make each family a sub-package: {new}"
    stale = PREFIX_FAMILIES_TO_MOVE - set(fam)
    assert not stale, f"remove from PREFIX_FAMILIES_TO_MOVE (now a sub-package): {sorted(stale)}"


def test_the_guard_catches_what_it_should(tmp_path, monkeypatch):
    """The checks fire on a planted upward import, private import, local import and cycle."""
    fake = {
        "roughstick._core.bad": "from ..contact import meniscus\n",
        "roughstick.surface.bad": "def f():\n    from ..contact.rough import _spacing\n",
        "roughstick.io.x": "from . import y\n",
        "roughstick.io.y": "from . import x\n",
    }
    files = {}
    for name, text in fake.items():
        path = tmp_path / (name.replace(".", "/") + ".py")
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
        files[name] = path
    monkeypatch.setitem(globals(), "MODULES", {**MODULES, **files})
    edges = {m: list(_imports(m)) for m in fake}
    monkeypatch.setitem(globals(), "EDGES", {**EDGES, **edges})
    for check, expected in ((test_imports_only_go_down, "roughstick._core.bad"),
                            (test_no_private_name_across_subpackages, "_spacing"),
                            (test_function_local_imports_are_for_optional_dependencies_only, "roughstick.surface.bad"),
                            (test_no_import_cycle, "roughstick.io.x")):
        with pytest.raises(AssertionError, match=expected.replace(".", r"\.")):
            check()
