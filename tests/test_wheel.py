"""A built wheel carries the bundled data: from an installed wheel, outside the checkout, the samples,
their PSDs and the demo give the same numbers as from the checkout (issue 11).

The wheel is built from a copy of the files git tracks (so the checkout gets no build/ folder) and
installed without dependencies into a fresh virtual environment whose ``.pth`` file lists the
running interpreter's site-packages (``venv --system-site-packages`` would expose the *base*
interpreter's packages, not those of a venv that runs the tests).
The first test takes about 30 s with the wheel build; the full ``roughstick demo --quick`` /
``reproduce --quick --n 6`` comparison is ``slow`` (both together 261 s on the 2-core development
machine: ``pytest -m slow tests/test_wheel.py``), and so is running a shipped example config
(``roughstick examples`` then ``roughstick run``) from the wheel.
"""

from __future__ import annotations

import json
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

ROOT = pathlib.Path(__file__).resolve().parents[1]

PROBE = """
import json, pathlib, sys
import numpy as np
import roughstick as rs
out = {"file": rs.__file__}
out["S1A_sum"] = float(rs.datasets.load_sample("S1A").sum())
out["bundled_S1A_sum"] = float(rs.read_afm("bundled:S1A", levelling="none").sum())  # the one name of a shipped map
out["examples"] = sorted(rs.datasets.example_configs())
m = rs.psd_moments(rs.datasets.sample_psd("S2"))
out["S2_moments"] = [float(m[k]) for k in ("m0", "m2", "m4")]
out["table4_q0"] = rs.datasets.family_parameters("table4")["q0"]
out["validity_rows"] = int(rs.contact.validity_map()["rh"].size)
print(json.dumps(out))
"""


@pytest.fixture(scope="module")
def wheel_env(tmp_path_factory):
    pytest.importorskip("setuptools")
    tmp = tmp_path_factory.mktemp("wheel")
    src = tmp / "src"
    files = subprocess.run(["git", "-C", str(ROOT), "ls-files", "roughstick", "pyproject.toml", "README.md"],
                           capture_output=True, text=True)
    if files.returncode != 0:
        pytest.skip("needs a git checkout to know the tracked files")
    for rel in files.stdout.split():
        dst = src / rel
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / rel, dst)
    run = dict(capture_output=True, text=True, timeout=600)
    try:  # build with this environment's setuptools when it can make wheels (no download)
        import wheel  # noqa: F401

        isolation = ["--no-build-isolation"]
    except ImportError:
        isolation = []
    res = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", *isolation, "-q",
                          str(src), "-w", str(tmp / "dist")], **run)
    assert res.returncode == 0, res.stderr
    wheel = next((tmp / "dist").glob("roughstick-*.whl"))
    venv = tmp / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, **run)
    py = venv / "bin" / "python"
    # The new venv sees the dependencies of the environment running the tests, whatever that is
    # (a venv, a conda env, the system): a .pth file lists its site-packages. Plain path lines add
    # those folders after the venv's own, without running their .pth files, so an editable install
    # of the checkout there is not seen and the wheel's roughstick is the one imported.
    res = subprocess.run([str(py), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"], **run)
    own = pathlib.Path(res.stdout.strip())
    (own / "_roughstick_test_parent_env.pth").write_text("\n".join(_site_packages()) + "\n")
    res = subprocess.run([str(py), "-m", "pip", "install", "-q", "--no-deps", "--force-reinstall", str(wheel)], **run)
    assert res.returncode == 0, res.stderr
    work = tmp / "elsewhere"  # not the checkout: nothing of it on the path
    work.mkdir()
    return {"python": py, "script": venv / "bin" / "roughstick", "cwd": work, "wheel": wheel}


def _site_packages() -> list[str]:
    """The running interpreter's site-packages folders (venv, system, user), as on its sys.path."""
    import site

    paths = [*site.getsitepackages(), site.getusersitepackages()]
    return [p for p in dict.fromkeys(paths) if os.path.isdir(p) and p in sys.path]


def _probe(python, cwd, *, isolated=False):
    env = {k: v for k, v in os.environ.items() if not (isolated and k == "PYTHONPATH")}
    res = subprocess.run([str(python), "-c", PROBE], cwd=cwd, capture_output=True, text=True, timeout=600,
                         env=env)
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout.strip().splitlines()[-1])


def test_wheel_ships_the_data_and_gives_the_checkout_numbers(wheel_env):
    installed = _probe(wheel_env["python"], wheel_env["cwd"], isolated=True)  # not a PYTHONPATH checkout
    assert pathlib.Path(installed["file"]).is_relative_to(wheel_env["python"].parents[1])  # the wheel, not ROOT
    checkout = _probe(sys.executable, ROOT)
    assert pathlib.Path(checkout["file"]).is_relative_to(ROOT)
    for key in ("S1A_sum", "S2_moments", "table4_q0", "validity_rows", "examples"):
        assert installed[key] == checkout[key], key
    assert installed["bundled_S1A_sum"] == installed["S1A_sum"]
    assert installed["examples"] == sorted(p.name for p in (ROOT / "examples").glob("*.toml"))


def _run(cmd, cwd):
    res = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=1800,
                         env={**os.environ, "CI": "true", "MPLBACKEND": "Agg"})
    assert res.returncode == 0, res.stderr[-2000:]


def _same_numbers(a: pathlib.Path, b: pathlib.Path):
    ncs = sorted(a.rglob("*.nc"))
    assert ncs
    for fa in ncs:
        with xr.open_dataset(fa) as x, xr.open_dataset(b / fa.relative_to(a)) as y:
            for v in x.data_vars:
                np.testing.assert_array_equal(x[v].values, y[v].values, err_msg=f"{fa.name}:{v}")
    for fa in sorted(a.rglob("*.csv")):
        assert fa.read_text() == (b / fa.relative_to(a)).read_text(), fa.name


@pytest.mark.slow
@pytest.mark.parametrize("command", [["demo", "--quick"], ["reproduce", "--quick", "--n", "6"]])
def test_installed_commands_match_the_checkout(wheel_env, tmp_path, command):
    _run([str(wheel_env["script"]), *command, "--out", str(tmp_path / "wheel")], wheel_env["cwd"])
    _run([sys.executable, "-m", "roughstick.cli", *command, "--out", str(tmp_path / "checkout")], ROOT)
    _same_numbers(tmp_path / "wheel", tmp_path / "checkout")


@pytest.mark.slow
def test_installed_wheel_runs_a_shipped_example_config(wheel_env, tmp_path):
    """A wheel user (no examples/ nor data_samples/ folder) copies an example with `roughstick
    examples` and runs it: its maps are bundled:S1A ..., and the numbers are the checkout's."""
    script, cwd = str(wheel_env["script"]), wheel_env["cwd"]
    _run([script, "examples", "ensemble_S1_samples", "--out", "configs", "--overwrite"], cwd)
    _run([script, "run", "configs/ensemble_S1_samples.toml", "--n", "2", "--no-figures",
          "--out", str(tmp_path / "wheel")], cwd)
    _run([sys.executable, "-m", "roughstick.cli", "run", "examples/ensemble_S1_samples.toml", "--n", "2",
          "--no-figures", "--out", str(tmp_path / "checkout")], ROOT)
    assert (tmp_path / "wheel" / "band.nc").is_file()
    _same_numbers(tmp_path / "wheel", tmp_path / "checkout")
