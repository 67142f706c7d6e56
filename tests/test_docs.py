"""The reference pages stay in step with the code: docs/api.md lists every public name under the
module that defines it, docs/cli.md every sub-command, docs/architecture.md every subpackage."""

import pathlib
import re

import roughstick as rs
from roughstick.cli import build_parser

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs"


def test_api_page_lists_every_public_name_under_its_module():
    text = (DOCS / "api.md").read_text()
    listed = {}
    module = None
    for line in text.splitlines():
        m = re.match(r"### `(roughstick\.[\w.]+)`", line)
        if m:
            module = m.group(1)
        elif line.startswith("   ") and line.strip().isidentifier() and module:
            listed[line.strip()] = module
    missing = [n for n in rs.__all__ if n not in listed and n not in rs.materials.__all__ + ["UnitsError"]]
    assert not missing, f"docs/api.md does not list {missing}"
    for name, module in listed.items():
        obj = getattr(rs, name, None)
        home = getattr(obj, "__module__", None)
        if callable(obj) and home and home.startswith("roughstick.") and not home.startswith("roughstick._core"):
            assert home == module, f"docs/api.md lists {name} under {module}, it lives in {home}"


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
