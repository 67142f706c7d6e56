"""Build notebooks/02_topography_psd.ipynb (no outputs): python notebooks/_build_02.py"""

import pathlib

import nbformat as nbf

cells = [
    nbf.v4.new_markdown_cell(
        "# 02 · Topography and power spectral densities\n\n"
        "From AFM maps to roughness statistics and the PSD that drives surface generation "
        "(paper §3.1, §4.1, §5.2: Eqs. 15, 24-32, 37; Tables 2-4; Figs. 12 and 19).\n\n"
        "The maps `S1A`…`S2C` shipped with roughstick (`rs.datasets`) are **synthetic** stand-ins "
        "for the paper's measurements (see `data_samples/README.md`); the last section reads one "
        "from its file the way you read your own AFM file. All values are SI; tables show nm."
    ),
    nbf.v4.new_code_cell(
        "import pathlib\n\n"
        "import matplotlib.pyplot as plt\n"
        "import numpy as np\n"
        "import pandas as pd\n"
        "import xarray as xr\n\n"
        "import roughstick as rs\n"
        "from roughstick.paper import topography as figures\n"
        "from roughstick.plotting import plot_height, plot_psd_schemes\n\n"
        "QMAX = 289e6  # rad/m: the paper's cutoff, 289 rad/µm"
    ),
    nbf.v4.new_markdown_cell(
        "## Read and level the maps\n\n`read_afm` returns `height` (y, x) in metres; `level` removes "
        "the mean plane (or a line per scan line) and records it in `history`."
    ),
    nbf.v4.new_code_cell(
        "def sample(name):\n"
        "    maps = [rs.surface.level(rs.datasets.load_sample(f'{name}{c}')) for c in 'ABC']\n"
        "    h = xr.concat(maps, dim='map', coords='minimal', compat='override', combine_attrs='drop')\n"
        "    h.attrs = maps[0].attrs\n"
        "    return h.assign_coords(map=[f'{name}{c}' for c in 'ABC'])\n\n"
        "S = {name: sample(name) for name in ('S1', 'S2')}\n"
        "print(S['S1'].attrs['history'].splitlines()[-1])\n"
        "fig, axes = plt.subplots(1, 2, figsize=(10, 4))\n"
        "plot_height(S['S1'].isel(map=0), ax=axes[0]); axes[0].set_title('S1A (synthetic)')\n"
        "plot_height(S['S2'].isel(map=0), ax=axes[1]); axes[1].set_title('S2A (synthetic)');"
    ),
    nbf.v4.new_markdown_cell(
        "## Table 2/3-style statistics\n\nSpatial variances from cubic-spline derivatives (the "
        "paper's method, averaged over x and y and over the three maps) against PSD moments "
        "(16 sub-maps per map, scheme 3) at ξmax = 289 rad/µm and at the cutoff chosen to match."
    ),
    nbf.v4.new_code_cell(
        "rows, psd3 = [], {}\n"
        "for name, h in S.items():\n"
        "    spatial = rs.surface.roughness_moments(h).mean('map')\n"
        "    psd3[name] = rs.surface.submap_psd(h, n=16)\n"
        "    fixed = rs.surface.psd_moments(psd3[name], qmax=QMAX)\n"
        "    chosen = rs.surface.choose_cutoff(psd3[name], spatial)\n"
        "    for label, m, q in (('spatial', spatial, np.nan), ('PSD, 289 rad/µm', fixed, QMAX),\n"
        "                        ('PSD, chosen ξmax', chosen, float(chosen.qmax))):\n"
        "        rows.append({'sample': name, 'estimate': label, 'm0 [nm²]': float(m.m0) * 1e18,\n"
        "                     'm2': float(m.m2), 'm4 [1e-4 nm⁻²]': float(m.m4) * 1e-14,\n"
        "                     'ξmax [rad/µm]': q * 1e-6})\n"
        "    st = rs.surface.asperity_statistics(spatial)\n"
        "    print(f\"{name}: summit density {float(st.summit_density) * 1e-12:.0f} µm⁻², \"\n"
        "          f\"mean summit radius {float(st.summit_radius) * 1e9:.0f} nm, bandwidth {float(st.bandwidth):.1f}\")\n"
        "pd.DataFrame(rows).round(4)"
    ),
    nbf.v4.new_markdown_cell(
        "## Fig. 12: three estimation schemes and the Eq. 32 check\n\n"
        "Scheme 1: the 3 whole maps; scheme 2: 4 sub-maps each; scheme 3: 16 sub-maps each "
        "(Eq. 31). Eq. 32 is the relative spread of the sub-map variances. The sub-maps are not "
        "periodic, so their spectra leak power into the tail above ξmax."
    ),
    nbf.v4.new_code_cell(
        "schemes = {n: rs.surface.submap_psd(S['S1'], n=n) for n in (1, 4, 16)}\n"
        "for n in (4, 16):\n"
        "    chk = rs.surface.submap_variance_check(S['S1'], n=n)\n"
        "    print(f'S1, {n} sub-maps per map: Eq. 32 = {float(chk.relative_std):.3f}')\n"
        "fig, ax = plt.subplots(figsize=(6, 4.5))\n"
        "plot_psd_schemes({f'{n} sub-map(s) per map': s for n, s in schemes.items()}, ax=ax, qmax=QMAX, title='S1');"
    ),
    nbf.v4.new_markdown_cell(
        "## Table 4 → Eq. 37 (Fig. 19)\n\n"
        "Roughness 2.6 and 2.4 nm, R = 220 nm and N = 80.1 µm⁻² give μ0, μ2, μ4 (with μ4 = "
        "(3√π/(8R))², the square missing in print). Solving Eq. 37 with ξmax = 289 rad/µm gives "
        "ξ0 ≈ 21.2 rad/µm; the paper's printed 19.4 rad/µm, 6.46e3 nm⁴, 6.29e-3 nm⁴ come out "
        "with N = 88.1 µm⁻² instead. Both are shown."
    ),
    nbf.v4.new_code_cell(
        "fits, rows = figures.table4_self_affine(), []  # the paper's figures, one copy\n"
        "for label, fit in fits.items():\n"
        "    m0, m2, m4 = fit.attrs['asperity_moments']\n"
        "    rows.append({'fit': label, 'μ0 [nm²]': m0 * 1e18, 'μ2': m2, 'μ4 [µm⁻²]': m4 * 1e-12,\n"
        "                 'ξ0 [rad/µm]': float(fit.q0) * 1e-6, 's0 [nm⁴]': float(fit.s0) * 1e36,\n"
        "                 's1 [nm⁴]': float(fit.s1) * 1e36})\n"
        "rows.append({'fit': 'printed', 'ξ0 [rad/µm]': 19.4, 's0 [nm⁴]': 6.46e3, 's1 [nm⁴]': 6.29e-3})\n"
        "display(pd.DataFrame(rows))\n"
        "figures.fig19_self_affine_psd(fits, measured={f'{k} (scheme 3)': v for k, v in psd3.items()});"
    ),
    nbf.v4.new_markdown_cell(
        "## From a map file: the steps for your own AFM data\n\n"
        "No measured map ships with roughstick, so this section reads a bundled map **from its "
        "file** with `rs.io.read_afm`, the same call that reads your own measurement (NanoScope "
        "`.spm`/`.di`, Park `.tiff`, Gwyddion `.gwy`, NetCDF, text; set `path` to your file). "
        "It levels the map two ways, tabulates its roughness statistics, compares its PSD "
        "moments at ξmax = 289 rad/µm with the Table 3 values the map was made to match, and draws the map with its PSD by the three schemes."
    ),
    nbf.v4.new_code_cell(
        "path = rs.datasets.sample_path('S2A')  # or pathlib.Path('my_scan.spm')\n"
        "raw = rs.io.read_afm(path)\n"
        "print(f\"{path.name}: {raw.sizes['y']} x {raw.sizes['x']} pixels of {float(raw.x[1] - raw.x[0]) * 1e9:g} nm\")\n"
        "for method in ('plane', 'line'):\n"
        "    print(f'{method:5s} levelling: Sq = {float(rs.surface.level(raw, method=method).std()) * 1e9:.3f} nm')\n"
        "lv = rs.surface.level(raw)\n"
        "st = rs.surface.roughness_statistics(lv)\n"
        "display(pd.Series({'rms height [nm]': float(st.rms_height) * 1e9, 'm2': float(st.m2),\n"
        "                   'm4 [1e-4 nm⁻²]': float(st.m4) * 1e-14,\n"
        "                   'summit density [µm⁻²]': float(st.summit_density) * 1e-12,\n"
        "                   'summit radius [nm]': float(st.summit_radius) * 1e9,\n"
        "                   'bandwidth α': float(st.bandwidth)}).round(4).to_frame(path.name))\n"
        "psd = rs.surface.submap_psd(lv, n=16)\n"
        "m = rs.surface.psd_moments(psd, qmax=QMAX)\n"
        "t3 = rs.datasets.paper_table(3).sel(sample='S2', estimate='psd')  # what S2A was made to match\n"
        "pd.DataFrame({'this map (scheme 3)': [float(m.m0) * 1e18, float(m.m2), float(m.m4) * 1e-14],\n"
        "              'Table 3, S2 (PSD)': [float(t3.m0) * 1e18, float(t3.m2), float(t3.m4) * 1e-14]},\n"
        "             index=['m0 [nm²]', 'm2', 'm4 [1e-4 nm⁻²]']).round(4)"
    ),
    nbf.v4.new_code_cell(
        "fig, axes = plt.subplots(1, 2, figsize=(12, 4.5), layout='constrained')\n"
        "plot_height(lv, ax=axes[0])\n"
        "axes[0].set_title(f'{path.name}, plane-levelled')\n"
        "plot_psd_schemes({f'{n} sub-map(s)': rs.surface.submap_psd(lv, n=n) for n in (1, 4, 16)}, ax=axes[1],\n"
        "                 qmax=QMAX, title=path.name);"
    ),
]
nb = nbf.v4.new_notebook(cells=cells, metadata={
    "kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
out = pathlib.Path(__file__).with_name("02_topography_psd.ipynb")
nbf.write(nb, out)
print(f"wrote {out}")
