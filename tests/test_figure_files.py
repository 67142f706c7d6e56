"""Figure files for reports: ``roughstick.plotting.save_figure`` writes PNG, PDF or SVG at the
resolution asked for (200 dpi unless told), and refuses a bad format or resolution before writing."""

from __future__ import annotations

import struct

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from roughstick.plotting import save_figure  # noqa: E402

#: First bytes of each format.
MAGIC = {"png": b"\x89PNG\r\n\x1a\n", "pdf": b"%PDF-", "svg": b"<?xml"}


def png_dpi(path) -> float:
    """The resolution a PNG records (its pHYs chunk, pixels per metre)."""
    data = path.read_bytes()
    i = data.index(b"pHYs")
    ppm_x, _, unit = struct.unpack(">IIB", data[i + 4:i + 13])
    assert unit == 1  # metres
    return ppm_x * 0.0254


def _figure():
    fig, ax = plt.subplots(figsize=(4, 3), layout="constrained")
    ax.plot([0, 1, 2], [1, 3, 2])
    return fig


@pytest.mark.parametrize("fmt", ["png", "pdf", "svg"])
def test_save_figure_writes_the_format_asked_for(tmp_path, fmt):
    path = save_figure(_figure(), tmp_path / "fig.png", format=fmt, dpi=150)
    assert path == tmp_path / f"fig.{fmt}" and sorted(p.name for p in tmp_path.iterdir()) == [path.name]
    assert path.read_bytes().startswith(MAGIC[fmt])
    if fmt == "svg":
        assert b"<svg" in path.read_bytes()[:600]
    if fmt == "png":
        assert png_dpi(path) == pytest.approx(150, abs=0.1)


def test_save_figure_default_is_a_print_resolution_png(tmp_path):
    path = save_figure(_figure(), tmp_path / "fig.png")
    assert path.read_bytes().startswith(MAGIC["png"]) and png_dpi(path) == pytest.approx(200, abs=0.1)
    # a vector file carries no creation date: the same figure gives the same bytes
    a = save_figure(_figure(), tmp_path / "a.pdf").read_bytes()
    b = save_figure(_figure(), tmp_path / "b.pdf").read_bytes()
    assert a == b


@pytest.mark.parametrize("kw, match", [({"format": "jpg"}, "format='jpg': not a figure format; use 'png', 'pdf', 'svg'"),
                                       ({"dpi": 5}, "dpi=5: give a whole number of dots per inch from 50 to 1200"),
                                       ({"dpi": 1e5}, "dots per inch from 50 to 1200")])
def test_save_figure_refuses_bad_options_before_writing(tmp_path, kw, match):
    fig = _figure()
    with pytest.raises(ValueError, match=match):
        save_figure(fig, tmp_path / "fig.png", **kw)
    with pytest.raises(ValueError, match="extension of 'fig.jpg'"):
        save_figure(fig, tmp_path / "fig.jpg")
    assert list(tmp_path.iterdir()) == []
    plt.close(fig)
