"""Cantilevers and the risk of staying stuck, paper §5: Fig. 20 and the stiction-probability plots.

One copy for ``roughstick demo`` and ``roughstick risk``. Every function takes a
:func:`roughstick.stiction.risk_summary` Dataset (optionally over ``adsorbed_layer``) and returns
``(Dataset, Figure)`` with one panel per adsorbed-layer model.
"""

from __future__ import annotations

from .. import plotting

__all__ = ["fig20_adhesive_energy_bands", "stiction_probability", "stiction_vs_length", "crack_length"]


def _layers(risk):
    return list(risk.adsorbed_layer.values) if "adsorbed_layer" in risk.dims else [None]


def _panels(n, **kw):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, n, figsize=(6.8 * n, 4), layout="constrained", squeeze=False, **kw)
    return fig, axes[0]


def fig20_adhesive_energy_bands(risk, *, measured=None):
    """Fig. 20a/b: the Γ band per adsorbed-layer model, with measured points if given."""
    fig = plotting.plot_cantilever_comparison(risk, measured=measured)
    keep = [v for v in ("adhesive_energy_quantile", "adhesive_energy") if v in risk]
    return risk[keep], fig


def stiction_probability(risk, *, level=0.5, lengths=None):
    """P(stuck) versus RH for each beam length, with its binomial interval, per layer model."""
    layers = _layers(risk)
    fig, axes = _panels(len(layers))
    for ax, layer in zip(axes, layers, strict=True):
        kw = {} if lengths is None else {"lengths": lengths}
        plotting.plot_stiction_probability(risk, ax=ax, layer=layer, level=level, **kw)
        if layer is not None:
            ax.set_title(f"P(stuck), adsorbed layer: {layer}", fontsize="medium")
    keep = [v for v in risk.data_vars if v.startswith("stiction_probability")]
    return risk[keep], fig


def stiction_vs_length(risk, *, every: int = 3):
    """P(stuck) versus beam length at every ``every``-th humidity, per layer model."""
    layers = _layers(risk)
    fig, axes = _panels(len(layers))
    for ax, layer in zip(axes, layers, strict=True):
        plotting.plot_stiction_vs_length(risk, ax=ax, layer=layer, rh=risk.rh.values[::every])
        if layer is not None:
            ax.set_title(f"adsorbed layer: {layer}", fontsize="medium")
    keep = [v for v in risk.data_vars if v.startswith("stiction_probability")]
    return risk[keep], fig


def crack_length(risk, *, measured=None):
    """The band of the predicted crack length s (Eq. 36) versus RH, beam lengths labelled."""
    layers = _layers(risk)
    fig, axes = _panels(len(layers), sharey=True)
    for ax, layer in zip(axes, layers, strict=True):
        plotting.plot_crack_length_band(risk, ax=ax, layer=layer, measured=measured)
        if layer is not None:
            ax.set_title(f"beams longer than s stay stuck (adsorbed layer: {layer})", fontsize="medium")
    keep = [v for v in risk.data_vars if v.startswith("crack_length")]
    return risk[keep], fig
