"""Demo step: a small Monte Carlo ensemble on the bundled S1 samples (paper §4.3, Figs. 14, 16, 17).

PSD of the three S1 maps by the paper's scheme 3 (16 sub-maps each, cutoff 289 rad/µm), then
``run_ensemble`` streamed into ``ensemble_S1/`` (resumable), its 95 % band with the band's own
uncertainty in ``ensemble_S1_band.nc``, and the figures ``fig14_ensemble_curves.png``,
``fig16_energy_band.png`` and ``fig17_energy_ecdf.png``. ``quick``: 16 surfaces of 256²;
otherwise 48 surfaces of 512² (5 nm pixels).
"""

from __future__ import annotations

import logging
import pathlib

import roughstick as rs

from ..plotting.save import save_figure

from ..plotting.ensemble import (
    plot_energy_band,
    plot_energy_distribution,
    plot_ensemble_curves,
)

RH = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]
LOG = logging.getLogger("roughstick")


def run(out: pathlib.Path, *, quick: bool) -> list[pathlib.Path]:
    import matplotlib.pyplot as plt


    out = pathlib.Path(out)
    n, shape = (16, 256) if quick else (48, 512)
    psd = rs.datasets.sample_psd("S1")
    ds = rs.run_ensemble(psd, n=n, shape=shape, spacing=5e-9, relative_humidity=RH, seed=0,
                         chunks=2, output=out / "ensemble_S1", progress=False).load()
    band = rs.confidence_band(ds)
    band.attrs["title"] = f"S1 PSD, {n} surfaces of {shape}²: 95 % band of the ensemble"
    files = [out / "ensemble_S1", rs.io.netcdf.write(band, out / "ensemble_S1_band.nc", compute=True)]
    LOG.info("    apparent adhesive energy Γ of the S1 ensemble:")
    for line in rs.band_summary(band):
        LOG.info("      " + line)
    fig = plot_ensemble_curves(ds)
    fig.suptitle(f"S1 PSD, {n} surfaces of {shape * 5e-3:.2f} µm (Fig. 14 at demo scale)")
    files.append(_save(fig, out / "fig14_ensemble_curves.png"))
    ax = plot_energy_band(ds, label=f"{shape * 5e-3:.2f} µm")
    ax.set_title(f"Γ vs RH, n = {n} (Fig. 16)")
    files.append(_save(ax.figure, out / "fig16_energy_band.png"))
    ax = plot_energy_distribution(ds, rh=[0.3, 0.7, 0.9])
    ax.set_title("distribution of Γ (Fig. 17)")
    files.append(_save(ax.figure, out / "fig17_energy_ecdf.png"))
    plt.close("all")
    return files


def _save(fig, path):
    return save_figure(fig, path)
