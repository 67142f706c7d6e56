"""Build notebooks/07_beam_model.ipynb (no outputs committed): ``python notebooks/_build_07.py``."""

import pathlib

import nbformat as nbf

md, code = nbf.v4.new_markdown_cell, nbf.v4.new_code_cell
cells = [
    md(
        "# 07 · Beam-scale stochastic model: a crack front on random patches\n\n"
        "A cantilever stuck on its pad has a crack front at distance s from the clamp. The interface "
        "is a row of patches, each with the adhesive energy of one random surface patch (a law from a "
        "bank). The front stops at the first energy minimum (Eq. 36 locally). See `docs/beam.md` for "
        "the model and its scope. Small bank here so the notebook runs in seconds; use "
        "`roughstick beam examples/beam.toml` for real runs."
    ),
    code(
        "import tempfile, warnings\n"
        "import numpy as np\n"
        "import matplotlib.pyplot as plt\n"
        "import roughstick as rs\n"
        "warnings.simplefilter('ignore')"
    ),
    md("## Deterministic limit: a uniform law gives Eq. 36"),
    code(
        "beam = rs.PAPER_CANTILEVER\n"
        "for g0 in [1e-5, 1e-4, 1e-3]:\n"
        "    s = rs.beam.crack_length(np.full(600, g0), beam=beam)\n"
        "    print(f'Γ0 = {g0:g} J/m²: model s = {float(s)*1e6:.2f} µm, Eq. 36 s = '\n"
        "          f'{rs.stiction.crack_length_from_adhesive_energy(g0, beam=beam)*1e6:.2f} µm')"
    ),
    md("## A bank of patch laws (Table 4 PSD, modified DMT), cached on disk"),
    code(
        "c = rs.stiction.cantilever_psd()\n"
        "psd = rs.surface.self_affine_psd(np.geomspace(1e5, 4e9, 300), s0=float(c.s0), s1=float(c.s1),\n"
        "                         q0=float(c.q0), qmax=float(c.qmax))\n"
        "bank = rs.beam.build_patch_bank(psd, relative_humidity=[0.3, 0.6, 0.9], n=20, shape=(32, 32),\n"
        "                           spacing=20e-9, cache_dir=tempfile.mkdtemp())\n"
        "bank.to_pandas().describe()"
    ),
    md("The bank re-checks its 8 largest Eq. 16 energies per RH with the FFT boundary-element "
       "model (`check_tail=8`): the median BEM/Eq. 16 ratio. A beam's small P(stuck) is set by "
       "those laws; below 0.8 `build_patch_bank` warns and names `model='fft_bem'` "
       "(docs/beam.md, \"The bank's tail\": on 3,000 laws of this bank the largest are 3 × too "
       "high at 30 % RH, and P(stuck) of a 300 µm beam there is 0.57 on Eq. 16 against 0.19 on "
       "the BEM bank of the same patches)."),
    code("{f'RH {r:.1f}': round(float(v), 2) for r, v in zip(bank.rh.values, bank.attrs['tail_bem_ratio'])}"),
    md("## Crack lengths and P(stuck) with its 95 % Wilson interval; both protocols"),
    code(
        "lengths = np.array([100, 150, 200, 300]) * 1e-6\n"
        "rel = rs.beam.simulate(bank, beam_length=lengths, n=200, seed=1)\n"
        "up = rs.beam.simulate(bank, beam_length=lengths, n=200, seed=1, protocol='step_up')\n"
        "rel.stuck_probability.to_pandas()"
    ),
    code(
        "fig, ax = plt.subplots()\n"
        "for r in rel.rh.values:\n"
        "    p = rel.stuck_probability.sel(rh=r)\n"
        "    lo, hi = rel.stuck_probability_lower.sel(rh=r), rel.stuck_probability_upper.sel(rh=r)\n"
        "    ax.errorbar(lengths * 1e6, p, yerr=[p - lo, hi - p], marker='o', capsize=3, label=f'RH {r:.0%}')\n"
        "ax.set_xlabel('beam length [µm]'); ax.set_ylabel('P(stuck)'); ax.legend();"
    ),
    md("## Beside the pull-out proxy of Fig. 20\n\n"
       "The proxy treats one patch as the whole interaction zone: the beam sticks when that "
       "patch's Γ exceeds Eq. 36's critical energy for its length (`rs.stuck_probability`, the "
       "paper's Fig. 20). The beam model instead lets the crack front run over many random "
       "patches. Same bank, both with 95 % Wilson intervals; the proxy's n is the 20 laws, so its "
       "intervals are wide."),
    code(
        "proxy = rs.stuck_probability(bank.rename(law='realization'), beam_length=lengths)\n"
        "fig, axes = plt.subplots(1, rel.rh.size, figsize=(4 * rel.rh.size, 3.2), sharey=True)\n"
        "for ax, r in zip(axes, rel.rh.values):\n"
        "    for ds, v, lab in ((rel, 'stuck_probability', 'beam model'), (proxy, 'stiction_probability', 'pull-out proxy (Fig. 20)')):\n"
        "        p = ds[v].sel(rh=r); lo = ds[v + '_lower'].sel(rh=r); hi = ds[v + '_upper'].sel(rh=r)\n"
        "        ax.errorbar(lengths * 1e6, p, yerr=[p - lo, hi - p], marker='o', capsize=3, label=lab)\n"
        "    ax.set_title(f'RH {r:.0%}'); ax.set_xlabel('beam length [µm]')\n"
        "axes[0].set_ylabel('P(stuck)'); axes[0].legend(fontsize=8);"
    ),
    md("Hysteresis: with RH stepped up and the beam left in place, the front stays pinned further "
       "out than after a fresh release at the same RH."),
    code(
        "d = (up.crack_length - rel.crack_length).sel(beam_length=300e-6)\n"
        "print('mean crack length, release [µm]:', (rel.crack_length.sel(beam_length=300e-6).mean('realization').values * 1e6).round(1))\n"
        "print('mean crack length, step up [µm]:', (up.crack_length.sel(beam_length=300e-6).mean('realization').values * 1e6).round(1))\n"
        "print('largest difference [µm]:', float(d.max()) * 1e6)"
    ),
    md("## The cohesive beam on the same draws\n\n"
       "`beam_model='cohesive'` solves the Euler–Bernoulli cantilever loaded by each patch's law "
       "(pull-in, then release by front continuation) instead of the sharp-front energy balance. "
       "Same seed, same patches: the two can be compared beam by beam. It costs ~0.5 s per beam "
       "(docs/beam.md), so only 10 beams here."),
    code(
        "kw = dict(beam_length=[300e-6], n=10, seed=1)\n"
        "sharp = rs.beam.simulate(bank.sel(rh=[0.6]), **kw)\n"
        "coh = rs.beam.simulate(bank.sel(rh=[0.6]), beam_model='cohesive', **kw)\n"
        "print('stuck flags agree on', int((sharp.stuck == coh.stuck).sum()), 'of', sharp.stuck.size, 'beams')\n"
        "print('failed solves:', int(coh.solver_failed.sum()))\n"
        "ds = (coh.crack_length - sharp.crack_length).where(coh.stuck & sharp.stuck)\n"
        "print('crack length, cohesive minus sharp front [µm]: mean', float(ds.mean()) * 1e6, ', largest', float(abs(ds).max()) * 1e6)"
    ),
]
nb = nbf.v4.new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
nbf.write(nb, pathlib.Path(__file__).with_name("07_beam_model.ipynb"))
