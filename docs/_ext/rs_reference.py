"""``{namespace}``: a reference page that follows a namespace's ``__all__``.

A reference page is one directive (inside ``{eval-rst}`` on a MyST page)::

    ```{eval-rst}
    .. namespace:: roughstick.contact
    ```

which writes the namespace's docstring, a table of every name (with its docstring's first
paragraph) in its ``__all__`` (in that order) and then each name's full documentation (autodoc + numpydoc). Nothing is listed by hand, so
a name added to or removed from ``__all__`` appears on or leaves the page at the next build.

``.. namespace:: roughstick`` (the top level) lists each name of ``roughstick.__all__`` under the
namespace that also exports it (``contact.curves``) and documents in full only the names
that live at the top level alone (``Material``, ...).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

logger = logging.getLogger(__name__)


def public_namespaces(package: str = "roughstick") -> list[str]:
    """The importable sub-modules of ``package`` that declare a non-empty ``__all__``."""
    pkg = importlib.import_module(package)
    found = []
    for info in pkgutil.iter_modules(pkg.__path__):
        if info.name.startswith("_"):
            continue
        try:
            mod = importlib.import_module(f"{package}.{info.name}")
        except ImportError:
            continue
        if getattr(mod, "__all__", None):
            found.append(mod.__name__)
    return found


def _summary(obj) -> str:
    """The first paragraph of an object's own docstring, on one line (autosummary's first
    sentence would stop at the period of "Eqs. 1-6")."""
    doc = obj.__doc__ if isinstance(obj.__doc__, str) else None
    if not doc or (not inspect.isclass(obj) and not callable(obj) and doc == type(obj).__doc__):
        return ""
    first = inspect.cleandoc(doc).split("\n\n", 1)[0]
    return " ".join(line.strip() for line in first.splitlines())


def _directive_for(obj) -> str:
    if inspect.isclass(obj):
        return "autoexception" if issubclass(obj, BaseException) else "autoclass"
    if callable(obj):
        return "autofunction"
    return "autodata"


def _entry(name: str, obj) -> list[str]:
    kind = _directive_for(obj)
    lines = [f".. {kind}:: {name}"]
    if kind == "autoclass":
        lines += ["   :members:", "   :show-inheritance:"]
    elif kind == "autodata":
        lines += ["   :no-value:"]
    return lines + [""]


class NamespaceDirective(SphinxDirective):
    """Document a namespace from its ``__all__`` (see the module docstring)."""

    required_arguments = 1
    has_content = False

    def run(self) -> list[nodes.Node]:
        modname = self.arguments[0]
        try:
            mod = importlib.import_module(modname)
        except ImportError as exc:
            logger.warning(f"{modname} cannot be imported ({exc}): its reference page is empty",
                           location=self.get_location())
            return []
        names = list(getattr(mod, "__all__", []))
        if not names:
            logger.warning(f"{modname} has no __all__: nothing to document",
                           location=self.get_location())
        homes = self._homes(modname, mod, names)
        lines = [f".. automodule:: {modname}", "", f".. currentmodule:: {modname}", "",
                 ".. list-table::", "   :widths: 30 70", ""]
        for name in names:
            target = homes.get(name, name)
            lines += [f"   * - :py:obj:`{target}`", f"     - {_summary(getattr(mod, name))}"]
        lines += [""]
        for name in names:
            if name not in homes:
                lines += _entry(name, getattr(mod, name))
        node = nodes.section()
        node.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, source=self.get_source_info()[0]),
                                 node)
        return node.children

    @staticmethod
    def _homes(modname: str, mod, names: list[str]) -> dict[str, str]:
        """For the top-level package: the namespace that also exports each name."""
        if "." in modname:
            return {}
        homes = {name: f"{modname}.{name}" for name in names
                 if inspect.ismodule(getattr(mod, name))}  # a namespace: its own page
        for ns in public_namespaces(modname):
            sub = importlib.import_module(ns)
            for name in getattr(sub, "__all__", []):
                if name in names and name not in homes and getattr(sub, name) is getattr(mod, name):
                    homes[name] = f"{ns.partition('.')[2]}.{name}"
        return homes


def setup(app):
    app.add_directive("namespace", NamespaceDirective)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
