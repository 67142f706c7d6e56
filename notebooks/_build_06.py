"""Build notebooks/06_cantilever_risk.ipynb (no outputs committed): ``python notebooks/_build_06.py``."""

import pathlib

import nbformat as nbf

md, code = nbf.v4.new_markdown_cell, nbf.v4.new_code_cell
cells = [
    md(
        "# 06 · Cantilever beams and the risk of stiction\n\n"
        "Paper §5: the S-shaped cantilever test (Eq. 36), the equivalent surface of Table 4 and its "
        "self-affine PSD (Eq. 37), the predicted apparent adhesive energy of the interaction zone "
        "with and without adsorbed water layers (Fig. 20a/b), and what the paper leaves undone: the "
        "**probability that a beam stays stuck** versus humidity and beam length, with its Monte-Carlo "
        "uncertainty. Written for MEMS designers: see `docs/cantilever_risk.md` for the meaning and "
        "the limits of these numbers. The ensembles here are small so that the notebook runs in "
        "seconds; use `roughstick risk examples/risk.toml` for real runs."
    ),
    code(
        "import numpy as np\n"
        "import xarray as xr\n"
        "import matplotlib.pyplot as plt\n"
        "import roughstick as rs\n"
        "from roughstick import plotting\n"
        "from roughstick.paper import cantilever as figures  # the paper's figures, one copy"
    ),
    md(
        "## Eq. 36: crack length ↔ adhesive energy\n\n"
        "An S-shaped beam of thickness t, gap h and modulus E that lands at distance s from its anchor "
        "has Γ = (3/2) E h² t³ / s⁴. A beam of length l stays stuck when Γ exceeds Γ_crit = Γ(s = l)."
    ),
    code(
        "beam = rs.PAPER_CANTILEVER  # w = 30 µm, t = 2.62 µm, l = 1500 µm, h = 1.9 µm, E = 164 GPa\n"
        "lengths = [250e-6, 300e-6, 400e-6, 500e-6, 1500e-6]\n"
        "gcrit = rs.stiction.critical_adhesive_energy(beam_length=lengths, beam=beam)\n"
        "print('Γ_crit [mJ/m²]:', dict(zip([f'{l*1e6:.0f} µm' for l in lengths], (gcrit.values * 1e3).round(4).tolist())))\n"
        "s = rs.stiction.crack_length_from_adhesive_energy(np.array([1e-5, 1e-4, 1e-3, 1e-2]), beam=beam)\n"
        "print('crack length [µm] for Γ = 0.01, 0.1, 1, 10 mJ/m²:', (s * 1e6).round(1))\n"
        "# a 15 % error on a measured s is a factor 1.15**4 = 1.75 on Γ (paper §5.3)\n"
        "rs.stiction.adhesive_energy_from_crack_length(400e-6) / rs.stiction.adhesive_energy_from_crack_length(460e-6)"
    ),
    md(
        "## Table 4 → Eq. 37\n\n"
        "The two rough surfaces are replaced by their sum against a flat, so the variances add "
        "(√(2.6² + 2.4²) = 3.54 nm). Nayak's relations give μ4 = (3√π/(8R))² and "
        "μ2 = μ4/(6√3 π N). Solving Eq. 37 with ξmax = 289 rad/µm and the table's N = 80.1 µm⁻² "
        "does **not** give the printed ξ0 = 19.4 rad/µm, s0 = 6.46e3 nm⁴, s1 = 6.29e-3 nm⁴; "
        "N = 88.1 µm⁻² does (within 1 %). Both are shown."
    ),
    code(
        "rows = {}\n"
        "for n in (80.1, 88.1):\n"
        "    p = rs.stiction.cantilever_psd(asperity_density=n * 1e12)\n"
        "    rows[f'N = {n} µm⁻²'] = dict(sqrt_m0_nm=float(p.m0)**0.5*1e9, m2=float(p.m2), m4_um2=float(p.m4)/1e12,\n"
        "                               q0_rad_um=float(p.q0)/1e6, s0_nm4=float(p.s0)*1e36, s1_nm4=float(p.s1)*1e36)\n"
        "rows['printed'] = dict(sqrt_m0_nm=3.54, m2=0.0035, m4_um2=9.1, q0_rad_um=19.4, s0_nm4=6.46e3, s1_nm4=6.29e-3)\n"
        "import pandas as pd\n"
        "pd.DataFrame(rows).T.round(5)"
    ),
    md(
        "## A generated interaction zone\n\n"
        "The interaction zone Δs × w = 2.62 µm × 30 µm is 524 × 6000 pixels at 5 nm. One surface of "
        "the full zone (the PSD evaluated exactly on its wave-vector grid) and its moments, measured "
        "with spectral derivatives, against Table 4:"
    ),
    code(
        "fit = rs.stiction.cantilever_psd()\n"
        "shape = rs.stiction.interaction_zone_shape(beam)\n"
        "h = rs.surface.generate_surfaces(rs.stiction.interaction_zone_psd(fit, shape=shape), n=1, shape=shape, spacing=5e-9, seed=1).isel(realization=0).compute()\n"
        "z = h.values - h.values.mean()\n"
        "qx = 2*np.pi*np.fft.fftfreq(shape[1], 5e-9); qy = 2*np.pi*np.fft.fftfreq(shape[0], 5e-9)\n"
        "P = np.abs(np.fft.fft2(z))**2 / z.size**2\n"
        "QX, QY = np.meshgrid(qx, qy)\n"
        "print(shape, 'rms', z.std()*1e9, 'nm (3.54);',\n"
        "      'm2x', (P*QX**2).sum(), 'm2y', (P*QY**2).sum(), '(0.0035);',\n"
        "      'm4x', (P*QX**4).sum()/1e12, 'm4y', (P*QY**4).sum()/1e12, 'µm⁻² (9.1)')\n"
        "fig, ax = plt.subplots(figsize=(10, 2.6), layout='constrained')\n"
        "plotting.plot_height(h.isel(x=slice(0, 1500)), ax=ax)\n"
        "ax.set_title('a generated interaction-zone surface (first 7.5 µm along the beam)');"
    ),
    md(
        "## Predicted Γ of the interaction zone (Fig. 20a/b)\n\n"
        "Small settings for speed: 10 surfaces of 64 × 512 pixels (0.32 × 2.56 µm). A zone that small "
        "holds fewer tall asperities than the real 2.62 × 30 µm one, so Γ is biased upwards at low RH "
        "(paper Fig. 16a): these are illustrations, not predictions. Both adsorbed-layer models use "
        "the same surfaces and distance grid, so they coincide up to 65 % RH."
    ),
    code(
        "rh = list(rs.stiction.PAPER_HUMIDITIES)\n"
        "layers = ['none', 'paper']\n"
        "# the paper's model (Eq. 16), by name: Fig. 20 as the paper computed it\n"
        "g = xr.concat([rs.stiction.predict_adhesive_energy(fit, n=10, shape=(64, 512), relative_humidity=rh,\n"
        "                                          adsorbed_layer=layer, seed=7, model='modified_dmt'\n"
        "                                          ).adhesive_energy.compute()\n"
        "               for layer in layers], dim=xr.DataArray(layers, dims='adsorbed_layer', name='adsorbed_layer'))\n"
        "risk = rs.stiction.risk_summary(g, beam_length=lengths, probabilities=[0.1, 0.5, 0.9])\n"
        "figures.fig20_adhesive_energy_bands(risk);"
    ),
    md(
        "Your measured beams go on the same plot with `rs.stiction.measured_adhesion(rh, crack_length=...)` "
        "(or `adhesive_energy=...`). The experimental points of the paper's Fig. 20 are not printed "
        "in its text, so none are bundled, e.g.:\n\n"
        "```python\n"
        "mine = rs.stiction.measured_adhesion([0.4, 0.6, 0.8], crack_length=[450e-6, 410e-6, 380e-6], label='chip A')\n"
        "figures.fig20_adhesive_energy_bands(risk, measured=mine)\n"
        "```"
    ),
    md(
        "## Stiction probability\n\n"
        "P(stuck) = P(Γ > Γ_crit(l)) is the fraction of the Monte-Carlo sample above the beam's "
        "critical energy; the band is its 95 % Wilson interval (it shrinks as 1/√n). The crosses mark "
        "where P first reaches 50 %."
    ),
    code(
        "_, fig = figures.stiction_probability(risk, level=0.5, lengths=[300e-6, 400e-6, 500e-6])\n"
        "c = risk.crossing_humidity.sel(probability_level=0.5)\n"
        "(c * 100).to_pandas().round(1)  # RH [%] where half of the beams stay stuck (±inf: outside 30-95 %)"
    ),
    md(
        "## Crossing length and the crack-length distribution\n\n"
        "Because P(stuck | l) = P(s < l), the beam length at which a fraction p of the beams stays stuck "
        "is the p-quantile of the predicted crack length, with a distribution-free interval from the "
        "order statistics:"
    ),
    code(
        "cl = risk.sel(adsorbed_layer='paper', probability_level=0.1)\n"
        "pd.DataFrame({'l_10% [µm]': cl.crossing_length.values * 1e6,\n"
        "              'lower': cl.crossing_length_lower.values * 1e6,\n"
        "              'upper': cl.crossing_length_upper.values * 1e6}, index=(cl.rh.values * 100).round()).T.round(0)"
    ),
    code(
        "_, fig = figures.crack_length(risk)"
    ),
    md(
        "## How many surfaces?\n\n"
        "The Monte-Carlo interval on P(stuck) is binomial: with n surfaces, its half-width near "
        "P = 0.5 is about 1/√n. To resolve a 1 % stiction risk the sample must hold well over 100 "
        "surfaces (with k = 0 stuck out of n, the 95 % upper bound is ≈ 3.8/n for Wilson):"
    ),
    code(
        "for n in (10, 30, 100, 300, 1000):\n"
        "    lo, hi = rs.ensemble.binomial_interval(0, n)\n"
        "    lo5, hi5 = rs.ensemble.binomial_interval(n // 2, n)\n"
        "    print(f'n={n:5d}: 0 stuck -> P < {float(hi):.3f};  half stuck -> [{float(lo5):.3f}, {float(hi5):.3f}]')"
    ),
]
nb = nbf.v4.new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
nbf.write(nb, pathlib.Path(__file__).with_name("06_cantilever_risk.ipynb"))
