"""The docs stay in step with the code and speak to a reader.

Reference pages are written at build time from each namespace's ``__all__``
(``docs/_ext/rs_reference.py``): here every public namespace must have its page, every CLI
sub-command and configuration key its entry, every subpackage its place in the architecture page.
The index's five sections (tutorials, how-to, reference, explanation, evidence) must reach every
page and every notebook, and no page may point at files outside the repository or at issue and
planning records.
"""

import importlib
import pathlib
import pkgutil
import re

import pytest

import roughstick as rs
from roughstick.cli import build_parser

ROOT = pathlib.Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
GENERATED = {"_build", "jupyter_execute", "_ext"}


def _pages():
    return sorted(p for p in DOCS.rglob("*.md") if not GENERATED & set(p.relative_to(DOCS).parts))


def _public_namespaces():
    """roughstick's sub-modules with a non-empty ``__all__``, less the command line (docs/cli.md
    documents it) and the accessor (its page documents the two accessor classes; its
    ``__all__`` holds the forwarding tables)."""
    found = []
    for info in pkgutil.iter_modules(rs.__path__):
        if info.name.startswith("_") or info.name in ("cli", "accessor"):
            continue
        if getattr(importlib.import_module(f"roughstick.{info.name}"), "__all__", None):
            found.append(info.name)
    return found


def _toctree_entries(text):
    entries = []
    for block in re.findall(r"```\{toctree\}\n(.*?)```", text, flags=re.S):
        entries += [line.strip() for line in block.splitlines()
                    if line.strip() and not line.startswith(":")]
    return entries


@pytest.mark.parametrize("name", ["roughstick", *_public_namespaces()])
def test_every_public_namespace_has_a_reference_page(name):
    page = DOCS / "reference" / f"{name}.md"
    module = name if name == "roughstick" else f"roughstick.{name}"
    assert page.exists(), f"{module} has no reference page: write {page.relative_to(ROOT)}"
    assert f".. namespace:: {module}\n" in page.read_text(), \
        f"{page.relative_to(ROOT)} must hold the directive '.. namespace:: {module}'"


def test_every_page_and_notebook_is_in_the_index():
    entries = _toctree_entries((DOCS / "index.md").read_text())
    globs = [e for e in entries if "*" in e]
    for page in _pages():
        doc = page.relative_to(DOCS).with_suffix("").as_posix()
        if doc == "index":
            continue
        assert doc in entries or any(pathlib.PurePosixPath(doc).match(g) for g in globs), \
            f"docs/{doc}.md is in no section of docs/index.md"
    for nb in sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb")):
        link = DOCS / "tutorials" / nb.name
        assert link.exists() and link.resolve() == nb.resolve(), \
            f"docs/tutorials/{nb.name} must link ../../notebooks/{nb.name}"
        assert f"tutorials/{nb.stem}" in entries, f"{nb.name} is not in the Tutorials section"


def test_notebooks_are_shown_not_executed_by_the_build():
    assert re.search(r'^nb_execution_mode = "off"$', (DOCS / "conf.py").read_text(), flags=re.M)


#: A reader cannot open these: planning records, issue numbers, working files outside the tree.
OUTSIDE = [
    (r"\bissues?[ -]#?\d+", "an issue number"),
    (r"\brounds?[ -]\d+\b|\bthis round\b", "a planning round"),
    (r"\bsessions?[ -]\d+|\bsession[ -]scripts?\b", "a work session"),
    (r"\b(DESIGN|STYLE)\.md\b", "a design file outside the repository"),
    (r"\.\./shared|/work/", "a path outside the repository"),
]
#: The bibliography names journal issues ("volume 28, issue 3"): not planning records.
JOURNAL_ISSUES = {"roughstick/_core/references.py"}


@pytest.mark.parametrize("pattern,what", OUTSIDE, ids=[w for _, w in OUTSIDE])
def test_pages_name_nothing_outside_the_repository(pattern, what):
    """Docs, README, the package and the notebooks' sources name nothing a reader cannot open."""
    places = [*_pages(), ROOT / "README.md", DOCS / "conf.py"]
    places += [p for p in sorted((ROOT / "roughstick").rglob("*.py"))
               if p.relative_to(ROOT).as_posix() not in JOURNAL_ISSUES]
    places += sorted((ROOT / "notebooks").glob("_build_*.py"))
    found = [f"{p.relative_to(ROOT)}:{i}: {m.group(0)!r}"
             for p in places for i, line in enumerate(p.read_text().splitlines(), 1)
             for m in [re.search(pattern, line, flags=re.I)] if m]
    assert not found, f"{what} (say what it means for a reader instead): {found}"


def test_cli_page_lists_every_subcommand():
    text = (DOCS / "cli.md").read_text()
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    for name in sub.choices:
        assert f"## `roughstick {name}`" in text, name


def test_architecture_page_shows_every_subpackage():
    text = (DOCS / "architecture.md").read_text()
    pkg = pathlib.Path(rs.__file__).parent
    for p in sorted(pkg.iterdir()):
        if p.is_dir() and (p / "__init__.py").exists():
            assert f"{p.name}/" in text, f"docs/architecture.md does not show {p.name}/"
        elif p.suffix == ".py" and p.name != "__init__.py":
            assert p.name in text, f"docs/architecture.md does not show {p.name}"


def test_configuration_page_lists_every_key_of_the_schema():
    from roughstick.cli._config import SCHEMAS

    text = (DOCS / "configuration.md").read_text()
    for command, tables in SCHEMAS.items():
        assert f"### `roughstick {command}`" in text, command
        for table, fields in tables.items():
            for key in fields:
                assert f"| `{key}` |" in text, (command, table, key)


def test_the_readme_python_block_runs_on_the_current_api(capsys):
    """The README's "From Python" example runs as printed, with no name that only forwards."""
    import warnings

    text = (ROOT / "README.md").read_text()
    code = re.search(r"## From Python\n\n```python\n(.*?)```", text, flags=re.S).group(1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        warnings.simplefilter("error", DeprecationWarning)
        exec(compile(code, "README.md", "exec"), {})
    assert "95% band" in capsys.readouterr().out
