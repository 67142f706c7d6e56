"""Demo step: cantilever comparison and stiction risk (paper §5, Eq. 36, Table 4, Eq. 37, Fig. 20).

Table 4 -> Nayak moments -> Eq. 37 PSD (both the N = 80.1 µm⁻² of the table and the 88.1 µm⁻²
that reproduces the printed solution), an ensemble of interaction-zone surfaces with and without
the adsorbed layer, and the stiction probability of beams of several lengths. Writes:

- ``table4_eq37.csv``: moments and Eq. 37 parameters for N = 80.1 and 88.1 µm⁻², next to the
  values printed in the paper;
- ``cantilever_risk.nc``: Γ sample, bands, P(stuck) with its interval, crossing RH and length;
- ``fig20_adhesive_energy_bands.png``, ``stiction_probability.png``, ``crack_length.png``.

The interaction zone is smaller than the paper's 2.62 x 30 µm (524 x 6000 px) to keep the demo
short (``quick``: 64 x 512 px, 8 surfaces; otherwise 128 x 1500 px, 20 surfaces): a smaller zone
holds fewer tall asperities, so its Γ is biased upwards at low RH (paper Fig. 16a). Run
``roughstick risk examples/risk.toml`` without ``shape`` for the full zone.
"""

from __future__ import annotations

import csv
import io
import logging
import pathlib
import warnings

import numpy as np
import xarray as xr

import roughstick as rs

from ...io.netcdf import write_text_atomic
from ...plotting.save import DEFAULT_DPI, save_figure
from .. import cantilever as figures

LENGTHS = [250e-6, 300e-6, 350e-6, 400e-6, 500e-6, 1500e-6]
PRINTED = {"q0": 19.4e6, "s0": 6.46e3 * 1e-36, "s1": 6.29e-3 * 1e-36}


def _table4(out: pathlib.Path) -> pathlib.Path:
    path = out / "table4_eq37.csv"
    f = io.StringIO(newline="")
    if True:  # the table is written whole (atomically) below
        w = csv.writer(f)
        w.writerow(["case", "N_per_um2", "sqrt_m0_nm", "m2", "m4_per_um2", "q0_rad_per_um",
                    "s0_nm4", "s1_nm4"])
        for n in (80.1, 88.1):
            p = rs.stiction.cantilever_psd(asperity_density=n * 1e12)
            w.writerow([f"solved, N = {n}", n, f"{float(p.m0) ** 0.5 * 1e9:.3f}", f"{float(p.m2):.5f}",
                        f"{float(p.m4) / 1e12:.3f}", f"{float(p.q0) / 1e6:.2f}",
                        f"{float(p.s0) * 1e36:.4g}", f"{float(p.s1) * 1e36:.4g}"])
        w.writerow(["printed in the paper", 80.1, 3.54, 0.0035, 9.1, PRINTED["q0"] / 1e6,
                    PRINTED["s0"] * 1e36, PRINTED["s1"] * 1e36])
    write_text_atomic(path, f.getvalue())
    return path


def run(out: pathlib.Path, *, quick: bool, figure_format: str = "png",
        dpi: int = DEFAULT_DPI) -> list[pathlib.Path]:
    out = pathlib.Path(out)
    files = [_table4(out)]
    shape, n = ((64, 512), 8) if quick else ((128, 1500), 20)
    rh = list(rs.stiction.PAPER_HUMIDITIES)
    layers = ["none", "paper"]
    with warnings.catch_warnings():  # Fig. 20 by the paper's model, named; its bound said once below
        warnings.simplefilter("ignore", rs.ValidityWarning)
        gammas = [rs.stiction.predict_adhesive_energy(n=n, shape=shape, relative_humidity=rh,
                                                      adsorbed_layer=layer, seed=2015,
                                                      model="modified_dmt").adhesive_energy.compute()
                  for layer in layers]
    LOG.info("    Fig. 20 uses the paper's model (Eq. 16, model='modified_dmt'), as the paper did; "
             "rs.stiction.predict_adhesive_energy without model= uses the cheapest model measured "
             "within 10 % of the boundary-element reference")
    g = xr.concat(gammas, dim=xr.DataArray(layers, dims="adsorbed_layer", name="adsorbed_layer"))
    g["adsorbed_layer"].attrs = rs.conventions.coord_attrs("adsorbed_layer", g["adsorbed_layer"])
    risk = rs.stiction.risk_summary(g, beam_length=LENGTHS, probabilities=[0.05, 0.5, 0.95])
    risk["adhesive_energy"] = rs.conventions.set_attrs(g, "surface_adhesive_energy")
    rs.conventions.set_coord_attrs(risk)
    risk.attrs.update(interaction_zone_shape=list(shape), interaction_zone_spacing=5e-9,
                      note="demo: interaction zone smaller than the paper's 524 x 6000 px")
    files.append(rs.io.netcdf.write(risk, out / "cantilever_risk.nc", compute=True, overwrite=True))

    _, fig = figures.fig20_adhesive_energy_bands(risk)
    fig.suptitle(f"predicted Γ, {n} surfaces of {shape[0]} x {shape[1]} px (demo size)")
    files.append(save_figure(fig, out / "fig20_adhesive_energy_bands.png", format=figure_format, dpi=dpi))
    _, fig = figures.stiction_probability(risk, level=0.5, lengths=[300e-6, 400e-6, 500e-6, 1500e-6])
    files.append(save_figure(fig, out / "stiction_probability.png", format=figure_format, dpi=dpi))
    _, fig = figures.crack_length(risk)
    files.append(save_figure(fig, out / "crack_length.png", format=figure_format, dpi=dpi))
    sel = {"probability_level": 0.5, "adsorbed_layer": "paper"}
    crossing = risk.crossing_humidity.sel(sel)
    lower, upper = risk.crossing_humidity_lower.sel(sel), risk.crossing_humidity_upper.sel(sel)
    LOG.info(f"    RH at which half of the beams stay stuck (with layer; n = {n} surfaces, "
             "[95 % interval]): "
             + ", ".join(f"{bl * 1e6:.0f} µm: {_pct(v)} [{_pct(a)}, {_pct(b)}]" for bl, v, a, b in
                         zip(crossing.beam_length.values, crossing.values, lower.values, upper.values,
                             strict=True)))
    return files


LOG = logging.getLogger("roughstick")


def _pct(v):
    v = float(v)
    return "n/a" if np.isnan(v) else "<min RH" if v == -np.inf else ">max RH" if v == np.inf else f"{v * 100:.0f} %"
