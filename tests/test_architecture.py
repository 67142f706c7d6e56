"""The guard of the package layout (issue 11): run it before landing anything in roughstick/.

It reads every module of the package with ``ast`` (nothing is imported) and fails on

- an import that goes up the layers, or sideways between two stages of the same rank;
- a cycle between modules;
- a private name (``_x``, or a ``_module``) imported from another subpackage (``_core`` is the
  shared layer: its public names are for everyone, its private ones for itself);
- a function-local import of a roughstick module (function-local imports are for optional
  dependencies only: Tamaas, SurfaceTopography, distributed, tqdm, IPython, and matplotlib, which
  the plotting functions import when called so that ``import roughstick.plotting`` stays cheap);
- a module longer than 650 lines.

A new subpackage or top-level module must be given a rank in ``RANK`` below.
"""

from __future__ import annotations

import ast
import pathlib
from collections import defaultdict

import pytest

PACKAGE = pathlib.Path(__file__).resolve().parents[1] / "roughstick"
MAX_LINES = 650

#: Layers, bottom first (docs/architecture.md). A module may import from a lower rank, and from
#: its own layer; never from a higher rank nor from another layer of the same rank.
RANK = {
    "_core": 0,        # units, validate, references, conventions, constants, materials, dask
    "io": 1,
    "surface": 1,
    "testing": 1,      # public test helpers (make_topography, ...) over _core
    "datasets": 2,     # bundled data: uses io and surface
    "contact": 3,
    "ensemble": 4,
    "stiction": 5,
    "plotting": 6,
    "accessor": 6,     # forwarding methods over every stage
    "paper": 7,        # the figures of the paper, once: (Dataset, Figure) per figure group
    "demos": 8,        # call paper/
    "cli": 9,          # calls demos/ and paper/
    "__main__": 10,    # python -m roughstick: runs cli
    "roughstick": 10,  # the package's __init__: the facade that re-exports everything
}
#: Layers allowed to import the facade ``import roughstick as rs`` (applications of the package).
FACADE_USERS = {"demos", "paper", "cli"}


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


def test_no_private_name_across_subpackages():
    bad = []
    for module, edges in EDGES.items():
        src = _layer(module)
        for target, names, line, _ in edges:
            dst = _layer(target)
            if dst == src:
                continue
            private_module = [p for p in target.split(".")[1:] if p.startswith("_") and p != "_core"]
            private_names = [n for n in names if n.startswith("_") and not n.endswith("__")]
            if private_module or private_names:
                bad.append(f"{module}:{line} imports {private_names or target} from {target}")
    assert not bad, ("private names across subpackages (promote them to a documented public helper of "
                     "the lower layer, or to _core):\n" + "\n".join(bad))


def test_function_local_imports_are_for_optional_dependencies_only():
    bad = []
    for module, edges in EDGES.items():
        for target, _, line, is_local in edges:
            if is_local:
                bad.append(f"{module}:{line} imports {target} inside a function")
    assert not bad, "function-local imports of roughstick modules:\n" + "\n".join(bad)


@pytest.mark.parametrize("module", sorted(MODULES))
def test_module_length(module):
    n = len(MODULES[module].read_text().splitlines())
    assert n <= MAX_LINES, f"{module} has {n} lines (> {MAX_LINES}): split it by concern"


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
