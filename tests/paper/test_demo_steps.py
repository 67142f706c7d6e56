"""Tests of roughstick.paper.demo: the steps of `roughstick demo` (each writes its files)."""

from __future__ import annotations

import pytest

from roughstick.paper.demo import steps


def test_the_steps_run_in_the_order_of_their_names():
    names = [m.__name__.rsplit(".", 1)[-1] for m in steps()]
    assert names == sorted(names) and names[0] == "s10_sphere" and len(names) == 5


@pytest.mark.slow
def test_topography_step_writes_the_tables_and_figures(tmp_path):
    from roughstick.paper.demo import s20_topography

    files = s20_topography.run(tmp_path, quick=True)
    names = {f.name for f in files}
    assert {"topography_statistics.csv", "topography_statistics.nc", "fig12_psd_schemes.png",
            "fig19_self_affine_psd.png", "table4_self_affine.csv"} <= names
    text = (tmp_path / "table4_self_affine.csv").read_text()
    assert "21.19" in text and "19.49" in text and "19.4" in text
