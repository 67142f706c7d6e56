"""The one configuration schema of every command (issue 16 items 3 and 11, issue 11's cli/).

Every example parses; each mistake a user made is refused, before any work, with the fix."""

from __future__ import annotations

import pathlib

import pytest
from _configs import MOMENTS_PSD

import roughstick as rs
from roughstick.cli import main
from roughstick.cli._config import SCHEMAS, ConfigError, load_config, parse, read_toml
from roughstick.cli.risk import load_risk_config

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))

RUN = MOMENTS_PSD + """[surface]
shape = [64, 64]
spacing = "5 nm"
[ensemble]
n = 4
relative_humidity = [0.3, 0.9]
[output]
folder = "out"
"""


def _run_cfg(tmp_path, old: str = "", new: str = "", extra: str = "") -> pathlib.Path:
    text = RUN.replace(old, new) if old else RUN
    assert old in RUN
    p = tmp_path / "c.toml"
    p.write_text(text + extra)
    return p


def test_every_example_parses_with_the_one_schema():
    assert len(EXAMPLES) >= 4
    for f in EXAMPLES:
        if f.name.startswith("risk"):
            c = load_risk_config(f)
            assert c["beam"]["width"] == pytest.approx(30e-6)
            assert c["beam"]["youngs_modulus"] == pytest.approx(164e9)
            assert c["surface"]["asperity_density"] == pytest.approx(80.1e12)
            raw = read_toml(f)  # the examples write fractions and lengths in um
            assert c["ensemble"]["relative_humidity"] == pytest.approx(raw["ensemble"]["relative_humidity"])
            assert c["beam"]["lengths"] == pytest.approx([float(v.removesuffix(" um")) * 1e-6
                                                          for v in raw["beam"]["lengths"]])
        elif f.name.startswith("beam"):
            c = parse(read_toml(f), "beam", base=f.parent, source=f.name)
            assert c["beam"]["youngs_modulus"] == pytest.approx(164e9)
            assert c["surface"]["spacing"] in (pytest.approx(5e-9), pytest.approx(20e-9))
            assert all(0 < r < 1 for r in c["ensemble"]["relative_humidity"])
        else:
            cfg = load_config(f)
            assert cfg.spacing == pytest.approx(5e-9) and all(0 < r < 1 for r in cfg.relative_humidity)


def test_run_and_risk_share_tables():
    """The same key means the same thing (and takes the same form) in every command."""
    run, risk = SCHEMAS["run"], SCHEMAS["risk"]
    for table in ("surface", "ensemble", "output"):
        for key in set(run[table]) & set(risk[table]):
            assert run[table][key].kind == risk[table][key].kind, (table, key)
    assert risk["ensemble"]["relative_humidity"].kind == "relative_humidity"


@pytest.mark.parametrize(
    "old, new, match",
    [
        ('spacing = "5 nm"', "spacing = 5", r'has no unit .*spacing = "5 nm"'),
        ('spacing = "5 nm"', 'spacing = "5"', r'has no unit; write e.g. "5 nm"'),
        ('spacing = "5 nm"', "spacing_nm = 5", r'Units go in the value.*spacing = "<number> nm"'),
        ('qmax = "289 rad/um"', "qmax = 289e6", r'has no unit.*rad/um'),
        ("relative_humidity = [0.3, 0.9]", "relative_humidity = [30, 90]",
         r"did you mean 0.3 or .30 %.\?"),
        ("relative_humidity = [0.3, 0.9]", "rh_percent = [0.3, 0.5]",
         r"unknown key 'rh_percent'.*relative_humidity = \[0.3, 0.5\]"),
        ("relative_humidity = [0.3, 0.9]", "relative_humidity = [0.3, 0.3]", "repeated"),
        ("relative_humidity = [0.3, 0.9]", 'relative_humidity = ["30 %", "90 %"]', None),
        ("n = 4", "n = 0", r"integer >= 1 or 'auto'"),
        ("n = 4", "n = 2.5", r"expected an integer or 'auto' \(write 2 or 3"),
        ("n = 4", "n = 4\nseed = 1.9", r"seed = 1.9: expected an integer \(write 1 or 2"),
        ("shape = [64, 64]", "shape = [64.7, 64]", r"integers >= 8"),
        ("shape = [64, 64]", "shape = [64, 64]\nsize = \"1 um\"", "exactly one of shape"),
        ('folder = "out"', 'folder = "out"\nfigures = "no"', "true or false"),
        ('source = "moments"', 'source = "moment"', r"must be one of \['samples', 'moments', 'file'\]"),
        ("n = 4", "n = 4\ntolerance = 0.01", "only apply with n = 'auto'"),
    ],
)
def test_run_config_mistakes_refused_with_the_fix(tmp_path, old, new, match):
    p = _run_cfg(tmp_path, old, new)
    if match is None:
        assert load_config(p).relative_humidity == [0.3, 0.9]
        return
    with pytest.raises(ConfigError, match=match):
        load_config(p)


def test_all_problems_reported_at_once(tmp_path):
    p = _run_cfg(tmp_path, "n = 4", "n = 0\nseed = 1.9\nchunkz = 2")
    with pytest.raises(ConfigError) as err:
        load_config(p)
    text = str(err.value)
    assert "3 problem(s)" in text and "seed = 1.9" in text and "Did you mean 'chunks'" in text


def test_command_line_overrides_validated(tmp_path, capsys):
    p = _run_cfg(tmp_path)
    with pytest.raises(ConfigError, match=r"--n.*integer >= 1"):
        load_config(p, overrides={"n": "0"})  # --n 0 was silently the config's n
    assert main(["run", str(p), "--n", "0"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--n" in err
    assert not (tmp_path / "out").exists()  # refused before any work


@pytest.mark.parametrize(
    "text, match",
    [
        ("[beam]\nlength_um = 300\n", r"unknown key 'length_um'.*Units go in the value.*length"),
        ("[beam]\nlengths_um = [300]\n", r'lengths = \["250 um", "300 um"\]'),
        ("[beam]\nwidth = 30\n", r'width = 30 has no unit.*width = "30 nm"'),
        ("[beam]\nyoungs_modulus = \"164 nm\"\n", "pressure unit"),
        ("[humidity]\nrh_percent = [30, 50]\n", r"\[ensemble\] relative_humidity = \[0.3, 0.5\]"),
        ("[ensemble]\nrelative_humidity = [30, 50]\n", "did you mean 0.3"),
        ("[ensemble]\nrealizations = 20\n", "Write n instead"),
        ("[risk]\ninterval = \"wilsen\"\n", r"must be one of \['wilson'"),
        ("[risk]\nlevels = [5, 50, 95]\n", r"did you mean 0.05 or .5 %.\?"),
        ("[output]\ndirectory = \"x\"\n", "Write folder instead"),
        ("[ensemble]\nn = 0\n", "integer >= 1"),
        ("[surface]\nshape = [64.7, 64]\n", "integers >= 8"),
        ("[output]\nfigures = \"no\"\n", "true or false"),
        ("[ensemble]\nadhesive_energy = \"missing.nc\"\n", "not found"),
        ("[[measured]]\nrelative_humidity = [0.4, 0.5]\ncrack_length = [\"400 um\"]\n",
         "crack_length has 1 values"),
        ("[[measured]]\nfile = \"pts.csv\"\n", "not found"),
    ],
)
def test_risk_config_mistakes_refused_before_any_work(tmp_path, text, match):
    p = tmp_path / "risk.toml"
    p.write_text(text)
    with pytest.raises((ConfigError, FileNotFoundError), match=match):
        load_risk_config(p)


def test_risk_csv_needs_units_in_its_header(tmp_path):
    (tmp_path / "pts.csv").write_text("relative_humidity,crack_length\n0.4,420\n")
    p = tmp_path / "risk.toml"
    p.write_text('[[measured]]\nfile = "pts.csv"\n')
    with pytest.raises(ConfigError, match=r"needs its unit in brackets, e.g. 'crack_length \[um\]'"):
        load_risk_config(p)
    (tmp_path / "pts.csv").write_text("relative_humidity,crack_length [um]\n0.4,420\n")
    m = load_risk_config(p)["measured"][0]
    assert m["crack_length"] == [pytest.approx(420e-6)] and m["relative_humidity"] == [0.4]


def test_cli_risk_refuses_bad_config_without_leaving_a_folder(tmp_path, capsys):
    p = tmp_path / "risk.toml"
    p.write_text('[output]\nfolder = "out"\n[risk]\nlevels = [5, 50]\n')
    assert main(["risk", str(p)]) == 1
    assert "did you mean 0.05" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_config_that_is_not_a_file(tmp_path, capsys):
    assert main(["run", str(tmp_path)]) == 1
    assert "is a folder" in capsys.readouterr().err
    (tmp_path / "bin.toml").write_bytes(b"\xff\xfe\x00binary")
    assert main(["risk", str(tmp_path / "bin.toml")]) == 1
    assert "not" in capsys.readouterr().err


def test_sizes_that_cannot_fit_in_memory_refused_before_allocating(tmp_path):
    p = _run_cfg(tmp_path, "shape = [64, 64]", "shape = [400000, 400000]")
    with pytest.raises(ConfigError, match=r"400000 x 400000 px .* need about \d+ GiB, more than"):
        load_config(p)
    p = _run_cfg(tmp_path, "shape = [64, 64]", 'size = "2 mm"')
    with pytest.raises(ConfigError, match="400000 x 400000 px"):
        load_config(p)
    r = tmp_path / "risk.toml"
    r.write_text("[surface]\nshape = [1000000, 100000]\n")
    with pytest.raises(ConfigError, match="more than this machine"):
        load_risk_config(r)


SAMPLES_RUN = RUN.replace('''source = "moments"
m0 = "15.7 nm2"
m2 = 0.040
m4 = "5.08e-4 nm-2"
''', '''source = "samples"
files = FILES
''')


def test_psd_files_name_the_bundled_maps(tmp_path):
    """[psd] files = ["bundled:S1A", ...] are the maps inside the package, wherever the config is."""
    p = tmp_path / "c.toml"
    p.write_text(SAMPLES_RUN.replace("FILES", '["bundled:S1A", "bundled:S2B"]'))
    cfg = load_config(p)
    assert cfg.psd["files"] == [str(rs.datasets.sample_path("S1A")), str(rs.datasets.sample_path("S2B"))]
    (tmp_path / "bundled:S1A").write_text("x")  # a real file of that name wins over the bundled map
    cfg = load_config(p)
    assert cfg.psd["files"][0] == str(tmp_path / "bundled:S1A")


def test_unknown_bundled_map_in_psd_files_lists_the_bundled_names(tmp_path):
    p = tmp_path / "c.toml"
    p.write_text(SAMPLES_RUN.replace("FILES", '["bundled:S1A", "bundled:S9Z"]'))
    with pytest.raises(ConfigError, match=r"psd.files\[1\] = 'bundled:S9Z': no such bundled map") as err:
        load_config(p)
    assert all(f"bundled:{n}" in str(err.value) for n in rs.datasets.SAMPLES)
    assert "\n" not in str(err.value)
    p.write_text(SAMPLES_RUN.replace("FILES", '["data/S1A.nc"]'))  # a missing file: the bundled names
    with pytest.raises(ConfigError, match="not found .the sample maps shipped with roughstick are named bundled:S1A"):
        load_config(p)


@pytest.mark.parametrize(
    "text, says, never",
    [
        ("[ensemble]\nrelative_humidity = [0.5, 1.0]\n",
         r"relative_humidity\[1\] = 1.0: RH must lie strictly between 0 and 1: 1 is saturation "
         r"\(RH 100 %\), outside the models' range; give at most e.g. 0.99", "0.01"),
        ('[ensemble]\nrelative_humidity = ["120 %"]\n',
         r"'120 %': 120 % is not a relative humidity: RH must lie strictly between 0 and 100 %", "0.012"),
        ("[risk]\ntarget_cv = 1.5\n",
         r"target_cv = 1.5: target_cv must lie strictly between 0 and 1 \(a ratio such as 0.3, not a "
         r"percentage\)", "0.015"),
        ("[risk]\nconfidence = 1.0\n", r"confidence = 1.0: .*1 itself is excluded.*0.99", "0.01"),
    ],
)
def test_fractions_out_of_range_get_the_right_advice(tmp_path, text, says, never):
    """Saturation, a percentage above 100 % and a ratio are not percentages typed for a fraction."""
    p = tmp_path / "risk.toml"
    p.write_text(text)
    with pytest.raises(ConfigError, match=says) as err:
        load_risk_config(p)
    assert never not in str(err.value)
