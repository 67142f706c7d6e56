"""CF-1.10 compliance of every NetCDF file the demo (and `roughstick run`) writes (issue 16 item 6).

Two independent checks: roughstick's own list of the defects users found (always run), and the
IOOS compliance-checker's cf:1.10 suite at its HIGH and MEDIUM levels (when installed; it is in
the ``test`` extra)."""

from __future__ import annotations

import pathlib

import netCDF4
import numpy as np
import pytest

from roughstick.cli import main


@pytest.fixture(scope="module")
def written(tmp_path_factory) -> list[pathlib.Path]:
    out = tmp_path_factory.mktemp("demo")
    assert main(["demo", "--quick", "--quiet", "--out", str(out)]) == 0
    files = sorted(out.rglob("*.nc"))
    assert any(f.parent.name == "ensemble_S1" for f in files)  # the streamed blocks too
    return files


def _defects(path: pathlib.Path) -> list[str]:
    bad = []
    with netCDF4.Dataset(path) as nc:
        for attr in ("Conventions", "title", "history", "source"):
            if not str(getattr(nc, attr, "")).strip():
                bad.append(f"global attribute {attr} missing")
        for name, var in nc.variables.items():
            attrs = var.ncattrs()
            is_coord = name in nc.dimensions and var.dimensions == (name,)
            if is_coord and "_FillValue" in attrs:
                bad.append(f"coordinate {name} has _FillValue")
            if "long_name" not in attrs and "standard_name" not in attrs:
                bad.append(f"{name} has no long_name")
            if var.dtype is str or getattr(var.dtype, "kind", "") in "SU":
                if "units" in attrs:
                    bad.append(f"string variable {name} has units {var.units!r}")
            elif "units" not in attrs:
                bad.append(f"{name} has no units")
            if name == "realization" and getattr(var, "standard_name", None) != "realization":
                bad.append("realization without its CF standard_name")
            if getattr(var.dtype, "kind", "") == "f" and "_ci_" in name:  # band edges
                data = var[:]
                if np.isinf(np.ma.filled(data, 0.0)).any():
                    bad.append(f"{name} holds +-inf (n too small: write NaN and say why)")
        numbered = [v for v in nc.variables if v.rstrip("0123456789").endswith("_") and
                    v.rstrip("0123456789") != v]
        if len(numbered) > 1:
            bad.append(f"numbered variables {numbered}: use a dimension")
    return bad


def test_no_known_cf_defect_in_any_file(written):
    problems = {f.name: d for f in written if (d := _defects(f))}
    assert not problems, problems


def test_compliance_checker_cf_1_10(written):
    pytest.importorskip("compliance_checker")
    from compliance_checker.runner import CheckSuite

    suite = CheckSuite()
    suite.load_all_available_checkers()
    failures = {}
    seen = set()
    for f in written:
        if f.parent.name == "ensemble_S1":  # one block stands for all (same writer, same layout)
            if "block" in seen:
                continue
            seen.add("block")
        groups, _errors = suite.run_all(suite.load_dataset(str(f)), ["cf:1.10"], skip_checks=[])["cf:1.10"]
        for g in groups:
            ok = g.value[0] >= g.value[1] if isinstance(g.value, tuple) else bool(g.value)
            if g.weight >= 2 and not ok:
                failures.setdefault(f.name, []).append(f"{g.name}: {g.msgs}")
    assert not failures, failures


def test_the_checks_catch_the_defects(tmp_path):
    """The checks can fail: a file with the defects of issue 16 is flagged."""
    p = tmp_path / "bad.nc"
    with netCDF4.Dataset(p, "w") as nc:
        nc.createDimension("x", 2)
        x = nc.createVariable("x", "f8", ("x",), fill_value=np.nan)
        x.units, x.long_name = "m", "x"
        x[:] = [0.0, 1.0]
        for k in range(3):
            v = nc.createVariable(f"pressure_ci_{k}", "f8", ("x",))
            v.units, v.long_name = "Pa", "p"
            v[:] = [-np.inf, 1.0]
    text = " ".join(_defects(p))
    for needle in ("history missing", "coordinate x has _FillValue", "+-inf", "numbered variables"):
        assert needle in text
