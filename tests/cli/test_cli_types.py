"""Command-line values are refused naming the flag and the fix, before any work (not Python
attribute names, not ``np.float64(...)``), and ``--rh "60 %"`` means 60 %."""

from __future__ import annotations

import argparse

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.cli import main
from roughstick.cli._common import check_output_file
from roughstick.cli._types import pixel_size_arg, relative_humidity_arg


def _err(capsys, argv, code):
    """Run the console script; return its stderr's last line (the error), checking the status."""
    try:
        rc = main(argv)
    except SystemExit as exc:  # argparse: bad usage
        rc = exc.code
    assert rc == code, argv
    lines = capsys.readouterr().err.strip().splitlines()
    if code == 1:  # a command's error: one line, nothing else
        assert len(lines) == 1, lines
    return lines[-1] if lines else ""


def _python_words(msg):
    return [w for w in ("np.float64", "attrs[", "spacing=", "units=", "x.qmax", "relative_humidity",
                        "tolerance must", "factors must") if w in msg]


@pytest.fixture
def nm_map(tmp_path):
    h = rs.datasets.surface_family("smooth", shape=(32, 32), seed=3)
    path = tmp_path / "map.npy"
    np.save(path, h.values * 1e9)  # heights in nm
    return path


@pytest.mark.parametrize("text, value", [("0.6", 0.6), ("60 %", 0.6), ("60%", 0.6), (" 35.5 % ", 0.355)])
def test_rh_fraction_or_percent(text, value):
    assert relative_humidity_arg(text) == pytest.approx(value, rel=1e-15)


@pytest.mark.parametrize("text, says", [
    ("60", "RH must lie strictly between 0 and 1 (a fraction): did you mean 0.6 or '60 %'?"),
    ("1", "1 is saturation (RH 100 %), outside the models' range; give at most e.g. 0.99 or '99 %'"),
    ("0", "e.g. 0.6 or '60 %'); 0 is dry air"),
    ("120 %", "strictly between 0 and 100 %"), ("abc", "this is not a number"),
    ("nan", "this is not a number"), ("100 %", "100 % is saturation"),
    ("120", "120 is not a relative humidity")])
def test_rh_refused_with_the_fix(text, says):
    with pytest.raises(argparse.ArgumentTypeError, match=None) as err:
        relative_humidity_arg(text)
    assert says in str(err.value)


def test_curves_rh_percent_and_the_likely_percent(capsys, nm_map, tmp_path):
    out = tmp_path / "c.nc"
    assert main(["curves", str(nm_map), "--spacing", "5 nm", "--units", "nm", "--rh", "60 %",
                 "--n-distance", "20", "--out", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        assert np.atleast_1d(ds.rh.values).tolist() == [0.6]
    msg = _err(capsys, ["curves", str(nm_map), "--spacing", "5 nm", "--units", "nm", "--rh", "60",
                        "--out", str(tmp_path / "d.nc")], 2)
    assert msg.endswith("argument --rh: '60': RH must lie strictly between 0 and 1 (a fraction): did you mean 0.6 or '60 %'?")
    assert not _python_words(msg)


@pytest.mark.parametrize("command", ["psd", "curves"])
def test_flags_are_named_not_python_attributes(command, capsys, nm_map, tmp_path):
    rh = ["--rh", "0.5"] if command == "curves" else []
    base = [command, str(nm_map), *rh, "--out", str(tmp_path / "o.nc")]
    msg = _err(capsys, [*base, "--spacing", "5 m", "--units", "nm"], 2)
    assert "argument --spacing" in msg and "did you mean '5 nm' or '5 um'?" in msg and not _python_words(msg)
    msg = _err(capsys, [*base, "--spacing", "5 nm", "--units", "m"], 1)  # nm heights labelled m
    assert "with --units m the heights span" in msg and "--units nm" in msg and not _python_words(msg)
    msg = _err(capsys, [*base, "--units", "nm"], 1)
    assert "give their pixel size and height unit, e.g. --spacing '5 nm'" in msg and not _python_words(msg)
    if command == "psd":
        msg = _err(capsys, [*base, "--spacing", "5 nm", "--units", "nm", "--qmax", "289"], 1)
        assert msg.endswith("error: --qmax '289' has no unit; write it with one, e.g. '289 rad/um'")
        assert "'289 rad/um'" in msg and "'289 rad/um'" in msg and not _python_words(msg)
    else:
        msg = _err(capsys, [*base, "--spacing", "5 nm", "--units", "nm", "--accuracy", "-1"], 2)
        assert "argument --accuracy" in msg and not _python_words(msg)
        msg = _err(capsys, [*base, "--spacing", "5 nm", "--units", "nm", "--resolution",
                            "--resolution-factors", "0"], 2)
        assert "argument --resolution-factors" in msg and not _python_words(msg)
    assert not (tmp_path / "o.nc").exists()


@pytest.mark.parametrize("command", ["psd", "curves"])
def test_output_extension_is_checked_before_computing(command, capsys, tmp_path):
    """--out foo.txt used to get NetCDF bytes (psd) after the work; now refused at once, naming
    --out and the fix (the map does not even exist: nothing is read)."""
    rh = ["--rh", "0.5"] if command == "curves" else []
    msg = _err(capsys, [command, str(tmp_path / "absent.npy"), *rh, "--out", str(tmp_path / "foo.txt")], 1)
    assert f"error: --out '{tmp_path / 'foo.txt'}': the output is a NetCDF file; give it the .nc " \
           f"extension, e.g. --out {tmp_path / 'foo.nc'}" in msg
    assert not (tmp_path / "foo.txt").exists()
    check_output_file(tmp_path / "b.NC")  # accepted
    check_output_file(tmp_path / "x.nc4")


def test_pixel_size_keeps_plausible_lengths():
    assert pixel_size_arg("5 nm") == "5 nm" and pixel_size_arg("0.2 um") == "0.2 um"
    with pytest.raises(argparse.ArgumentTypeError, match="has no unit"):
        pixel_size_arg("5")


@pytest.mark.parametrize("command", ["psd", "curves"])
def test_units_on_a_netcdf_map_already_in_metres_is_named(command, capsys, tmp_path):
    """--units nm on a NetCDF map in m rescaled it to a 1e-17 m surface without a word."""
    rs.datasets.surface_family("S1", shape=(32, 32), seed=1).to_netcdf(tmp_path / "m.nc")
    rh = ["--rh", "0.5"] if command == "curves" else []
    msg = _err(capsys, [command, str(tmp_path / "m.nc"), *rh, "--units", "nm", "--out", str(tmp_path / "o.nc")], 1)
    assert "with --units nm the heights span" in msg and "drop --units" in msg and not _python_words(msg)
