"""One bibliography: every citation string and every DOI in the repository comes from it."""

from __future__ import annotations

import ast
import pathlib
import re

import pytest

import roughstick as rs
from roughstick._core.references import BIBLIOGRAPHY, PAPER, cite, reference

ROOT = pathlib.Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "roughstick"
_DOI = re.compile(r"10\.\d{4,9}/[-._;()/:A-Za-z0-9]+")


def _clean(doi: str) -> str:
    while doi and (doi[-1] in ".,;:" or (doi[-1] == ")" and doi.count(")") > doi.count("("))):
        doi = doi[:-1]
    return doi


def test_paper_entry_is_the_journal_record():
    paper = reference(PAPER)
    # author list of the J. Comput. Appl. Math. record (the paper's text carries no header)
    assert paper.authors == (
        "T.-V. Hoang, L. Wu, S. Paquay, A.C. Obreja, R.C. Voicu, R. Müller, J.-C. Golinval, L. Noels"
    )
    assert paper.doi == "10.1016/j.cam.2015.02.022"
    assert "289 (2015) 173-195" in paper.source
    assert rs.conventions.PAPER_REFERENCE == cite(PAPER)


def test_cite_formats_and_refuses_unknown_keys():
    s = cite(("hoang2015", "Eq. 37"), "nayak1971")
    assert s.count("; ") == 1 and "(Eq. 37)" in s and s.endswith("doi:10.1115/1.3451608")
    with pytest.raises(KeyError, match="known keys"):
        cite("nobody2099")


def test_every_entry_has_a_doi_or_says_why_not():
    for key, ref in BIBLIOGRAPHY.items():
        assert ref.authors and ref.title and ref.source and 1800 < ref.year < 2100, key
        if ref.doi is None:
            assert (any(p in ref.source for p in ("Wiley", "Press", "Springer"))
                    or ref.note.startswith("cited without DOI")), (
                f"{key}: only books go without DOI, or an article whose note says why")
        else:
            assert _DOI.fullmatch(ref.doi), key
        if not ref.checked:
            assert ref.note, f"{key}: an unchecked entry must say what was not checked"


def _strings_outside_docstrings(tree):
    docs = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                docs.add(id(body[0].value))
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs:
            yield node


def test_no_module_holds_its_own_citation_string():
    bad = []
    for path in PACKAGE.rglob("*.py"):
        if path.name == "references.py" and path.parent.name == "_core":
            continue
        for node in _strings_outside_docstrings(ast.parse(path.read_text())):
            if "doi" in node.value.lower() or "J. Comput. Appl. Math" in node.value:
                bad.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert not bad, "citation strings outside roughstick/_core/references.py: " + ", ".join(bad)


def test_every_doi_in_the_repository_is_in_the_bibliography():
    known = {r.doi for r in BIBLIOGRAPHY.values() if r.doi}
    unknown = []
    for path in ROOT.rglob("*"):
        if path.suffix not in (".py", ".md", ".toml", ".txt", ".ipynb") or not path.is_file():
            continue
        if any(part.startswith(".") for part in path.relative_to(ROOT).parts):
            continue
        for doi in _DOI.findall(path.read_text(errors="ignore")):
            if _clean(doi) not in known:
                unknown.append(f"{path.relative_to(ROOT)}: {_clean(doi)}")
    assert not unknown, "DOIs not in roughstick._core.references: " + "; ".join(unknown)
