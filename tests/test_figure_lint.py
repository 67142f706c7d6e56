"""Each check of tests/_figure_lint.py fires on a figure with that defect and stays quiet on a
clean one, so that 'no problems' on the notebooks' and the paper's figures means something."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from _figure_lint import figure_problems  # noqa: E402

X = np.linspace(0.0, 1.0, 50)


def _clean(ax):
    ax.plot(X * 100, np.sin(3 * X), label="data")
    ax.set(xlabel="relative humidity [%]", ylabel="Γ [mJ m⁻²]", title="clean")
    ax.legend()


def test_clean_figure_has_no_problem():
    fig, axes = plt.subplots(1, 2, figsize=(8, 3), layout="constrained")
    for ax in axes:
        _clean(ax)
    axes[0].axhline(0.5, ls="--", label="threshold")
    axes[0].legend()
    axes[1].axhline(0.0, color="k")  # the axis itself needs no label
    assert figure_problems(fig) == []
    plt.close(fig)


DEFECTS = {
    "axis offset": lambda ax: (ax.cla(), ax.plot(X, 1e-23 * (1 + X)), ax.set(xlabel="x [m]", ylabel="area [m²]")),
    "literal TeX": lambda ax: ax.set_xlabel("Δ = δ/(π²ω²R/K²)^{1/3}"),
    "raw variable name": lambda ax: ax.set_ylabel("adhesive_energy [J m-2]"),
    "fill only": lambda ax: ax.set_xlim(-50, 1000),
    "has no label": lambda ax: ax.axhline(0.3, ls="--"),
    "overprinted": lambda ax: ax.text(0.5, 1.01, "a note written over the title", transform=ax.transAxes,
                                      ha="center", va="bottom"),
    "legend covers data": lambda ax: ax.legend(loc="upper center"),  # over the curve's crest
}


@pytest.mark.parametrize("defect", DEFECTS)
def test_each_defect_is_found(defect):
    fig, ax = plt.subplots(figsize=(5, 3), layout="constrained")
    _clean(ax)
    ax.text(5, 0.95, "note")
    DEFECTS[defect](ax)
    problems = figure_problems(fig)
    assert any(defect in p for p in problems), problems
    plt.close(fig)


def test_empty_panel_and_colour_bar_over_a_neighbour():
    fig, axes = plt.subplots(1, 3, figsize=(10, 4))  # no layout engine: labels collide
    axes[0].imshow(np.arange(16.0).reshape(4, 4))
    fig.colorbar(axes[0].images[0], ax=axes[0], label="height [nm]")
    _clean(axes[1])
    axes[1].set_ylabel("a long label on the neighbouring panel [nm⁴]")
    problems = figure_problems(fig)
    assert any("empty panel" in p for p in problems), problems
    assert any("overprinted" in p for p in problems), problems
    plt.close(fig)


def test_legend_over_a_band_or_points_is_found_and_outside_the_axes_is_not():
    """The legend check looks at what is drawn: shaded bands and scatter points count as data,
    a legend placed outside the axes covers nothing, and nor does one beside the data."""
    fig, axes = plt.subplots(1, 3, figsize=(12, 3), layout="constrained")
    axes[0].fill_between(X, 0.2, 0.8, alpha=0.3, label="band")
    axes[0].plot(X, 0.5 + 0.1 * np.sin(9 * X), label="median")
    axes[1].scatter(np.tile(X, 5), np.repeat(np.linspace(0, 1, 5), len(X)), s=4, label="points")
    for ax in axes[:2]:
        ax.set(xlabel="x [nm]", ylabel="y [nm]", title=f"panel {ax.get_subplotspec().colspan.start}")
        ax.legend(loc="center")
    axes[2].plot(X, X, label="rising")
    axes[2].set(xlabel="x [nm]", ylabel="y [nm]", title="outside")
    axes[2].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    problems = figure_problems(fig)
    assert any("panel 0: the legend covers data (band, median)" in p for p in problems), problems
    assert any("panel 1: the legend covers data (points)" in p for p in problems), problems
    assert not any(p.startswith("outside:") for p in problems), problems
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(5, 3), layout="constrained")
    ax.plot(X, X, label="rising")
    ax.set(xlabel="x [nm]", ylabel="y [nm]", title="beside")
    ax.legend(loc="upper left")  # the data run from lower left to upper right
    assert figure_problems(fig) == []
    plt.close(fig)
