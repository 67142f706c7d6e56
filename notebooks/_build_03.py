"""Build notebooks/03_generation.ipynb (no outputs committed): python notebooks/_build_03.py"""

from __future__ import annotations

import pathlib

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

cells = [
    new_markdown_cell(
        "# 03 · Random surfaces from a PSD (paper §4.2, Eqs. 33-35, Fig. 13)\n\n"
        "`roughstick.surface.generate_surfaces` draws periodic Gaussian surfaces whose power spectral "
        "density is a given PSD: Hermitian-symmetric complex Gaussian amplitudes "
        "$\\sqrt{s(\\mathbf q)\\,\\Delta q_x\\Delta q_y}\\,\\xi$ (the Rayleigh modulus $\\zeta$ and "
        "uniform phase of Eq. 33) and one inverse real FFT per surface (Eq. 34). With the project "
        "normalisation $\\iint s\\,dq_x dq_y = m_0$ the expected variance is the PSD summed over the "
        "target grid. The result is lazy (dask, chunked over `realization`) and every realization "
        "has its own seed, so it is reproducible whatever the chunking.\n\n"
        "Here the PSDs are the self-affine Eq. 37 fitted to the Table 3 moments of samples S1 and "
        "S2 (the same PSDs that made the bundled `data_samples/`). Surfaces are 256 × 256 pixels "
        "of 5 nm (1.28 µm) to keep the notebook fast; the paper's Fig. 13 shows 5.12 µm."
    ),
    new_code_cell(
        "import numpy as np\n"
        "import matplotlib.pyplot as plt\n"
        "import xarray as xr\n"
        "import roughstick as rs\n"
        "from roughstick.plotting import plot_surfaces, plot_generated_psd\n\n"
        "TABLE3 = {  # PSD moments of Table 3 (SI), cutoff 289 rad/um\n"
        "    'S1': dict(m0=15.7e-18, m2=0.040, m4=5.08e-4 * 1e18),\n"
        "    'S2': dict(m0=4.32e-18, m2=0.021, m4=3.99e-4 * 1e18),\n"
        "}\n"
        "psds, fits = {}, {}\n"
        "for name, m in TABLE3.items():\n"
        "    fit = rs.surface.fit_self_affine(**m, qmax=289e6)\n"
        "    p = {k: float(fit[k]) for k in ('s0', 's1', 'q0', 'qmax')}\n"
        "    fits[name] = p\n"
        "    psds[name] = lambda q, p=p: rs.surface.self_affine_psd(np.ravel(q), **p).values.reshape(np.shape(q))\n"
        "    print(f\"{name}: q0 = {p['q0']/1e6:.2f} rad/um, s0 = {p['s0']*1e36:.1f} nm4, s1 = {p['s1']*1e36:.3f} nm4\")"
    ),
    new_markdown_cell("## Three surfaces from each sample (Fig. 13)\n\nBuilding the ensemble computes nothing; plotting computes only the three surfaces shown."),
    new_code_cell(
        "ens = {name: rs.surface.generate_surfaces(psd, n=64, shape=256, spacing=5e-9, seed=2026, chunks=16)\n"
        "       for name, psd in psds.items()}\n"
        "ens['S1']"
    ),
    new_code_cell(
        "fig, axes = plt.subplots(2, 3, figsize=(11, 6.4), layout='constrained')\n"
        "plot_surfaces(ens['S1'], realizations=[0, 1, 2], axes=axes[0], title='S1')\n"
        "plot_surfaces(ens['S2'], realizations=[0, 1, 2], axes=axes[1], title='S2');"
    ),
    new_markdown_cell(
        "## Ensemble PSD against the target\n\n"
        "The radially averaged periodogram of the 64 surfaces against the target PSD on the same "
        "grid, with the ±2 standard-error Monte Carlo band of the mean."
    ),
    new_code_cell(
        "fig, axes = plt.subplots(1, 2, figsize=(11, 4), layout='constrained', sharey=True)\n"
        "for ax, name in zip(axes, ens):\n"
        "    plot_generated_psd(ens[name], psds[name], ax=ax, label=name)\n"
        "    ax.set_title(name)"
    ),
    new_markdown_cell(
        "## Moment check\n\n"
        "Target: the moments of the PSD summed over the 256² grid (what the generator imposes) and "
        "the Table 3 values. Measured: `rs.surface.psd_moments` of the ensemble-mean `rs.surface.power_spectrum` "
        "(direction x, Nayak). The sampling standard error of an ensemble mean is "
        "$\\sqrt{2\\sum_k w_k^2P_k^2/n}$ with $P_k$ the mode powers and $w_k = 1, q_x^2, q_x^4$."
    ),
    new_code_cell(
        "rows = []\n"
        "for name, h in ens.items():\n"
        "    f = rs.surface.surface_filter(psds[name], shape=256, spacing=5e-9)\n"
        "    dq2 = (2 * np.pi / (256 * 5e-9)) ** 2\n"
        "    P = f.values * dq2\n"
        "    qx = f.qx.values[None, :]\n"
        "    n = h.sizes['realization']\n"
        "    measured = rs.surface.psd_moments(rs.surface.power_spectrum(h).mean('realization'), direction='x')\n"
        "    for key, w, unit in (('m0', 1.0, 1e18), ('m2', qx**2, 1.0), ('m4', qx**4, 1e-18)):\n"
        "        grid = (w * P).sum()\n"
        "        se = np.sqrt(2 * ((w * P) ** 2).sum() / n)\n"
        "        got = float(measured[key])\n"
        "        rows.append(dict(sample=name, moment=key, table3=TABLE3[name][key] * unit,\n"
        "                         grid_target=grid * unit, ensemble=got * unit,\n"
        "                         z_score=(got - grid) / se))\n"
        "import pandas as pd\n"
        "table = pd.DataFrame(rows).set_index(['sample', 'moment'])\n"
        "print('units: nm2, 1, nm-2')\n"
        "table.round(6)"
    ),
    new_code_cell(
        "assert (table.z_score.abs() < 4).all()\n"
        "assert np.allclose(table.grid_target, table.table3, rtol=0.03)  # 256^2 grid vs Table 3"
    ),
    new_markdown_cell(
        "The moment from `power_spectrum` excludes the $q=0$ mode (it removes each map's mean); "
        "that mode carries $s_0\\Delta q^2 \\approx 2\\times10^{-2}$ nm² for S1 at this size, well "
        "inside the standard error.\n\n"
        "## Reproducibility\n\n"
        "Realization 5 regenerated alone, with another chunking, is bit-identical."
    ),
    new_code_cell(
        "alone = rs.surface.generate_surfaces(psds['S1'], realizations=[5], shape=256, spacing=5e-9, seed=2026)\n"
        "other = rs.surface.generate_surfaces(psds['S1'], n=64, shape=256, spacing=5e-9, seed=2026, chunks=5)\n"
        "print(bool((alone.isel(realization=0) == ens['S1'].sel(realization=5)).all()),\n"
        "      bool((other.sel(realization=5) == ens['S1'].sel(realization=5)).all()))\n"
        "print(ens['S1'].attrs['seed'], ens['S1'].attrs['periodic'])"
    ),
]

nb = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3",
                                                         "language": "python"}})
out = pathlib.Path(__file__).with_name("03_generation.ipynb")
nbformat.write(nb, out)
print(f"wrote {out}")
