"""Build notebooks/08_small_probabilities.ipynb (no outputs committed): ``python notebooks/_build_08.py``."""

import pathlib

import nbformat as nbf

md, code = nbf.v4.new_markdown_cell, nbf.v4.new_code_cell
cells = [
    md(
        "# 08 · Small stiction probabilities: 1e-3 and 1e-4 without a million surfaces\n\n"
        "A designer asks whether one beam in a thousand sticks, not one in two. Counting stuck "
        "realizations needs ~10/p surfaces; **subset simulation** (Au & Beck 2001) walks into the "
        "tail instead, with Markov chains in the standard-normal white noise that the generator "
        "filters by the PSD (Eqs. 33-34): preconditioned Crank–Nicolson moves "
        "z' = ρ z + √(1-ρ²) ξ keep the PSD exactly. See `docs/rare_events.md`. The runs here are "
        "small so that the notebook finishes in under a minute; the figures quoted in the docs come "
        "from `examples/small_stiction_probability.py`."
    ),
    code(
        "import warnings\n"
        "import numpy as np\n"
        "from scipy.stats import norm\n"
        "import roughstick as rs\n"
        "warnings.simplefilter('ignore', rs.ValidityWarning)  # Table-4 zones: see docs/accuracy.md"
    ),
    md(
        "## The estimator on a case with a known answer\n\n"
        "Any callable `noise -> float` is a limit state (the beam model can plug in the same way). "
        "A linear one, `a·z` with |a| = 1, exceeds β with probability Φ(-β) exactly: 1e-4 here."
    ),
    code(
        "shape = (64, 64)\n"
        "a = np.random.default_rng(1).standard_normal(shape); a /= np.linalg.norm(a)\n"
        "beta = norm.isf(1e-4)\n"
        "r = rs.reliability.subset_simulation(lambda z: float(np.sum(a * z)), noise_shape=shape,\n"
        "                                     threshold=beta, n_per_level=500, seed=0)\n"
        "print(f\"P = {float(r.failure_probability):.2e} (exact 1.00e-04), 95% [{float(r.failure_probability_lower):.2e}, \"\n"
        "      f\"{float(r.failure_probability_upper):.2e}], cv {float(r.coefficient_of_variation):.2f}, \"\n"
        "      f\"{int(r.n_evaluations)} evaluations; crude MC would need {(1 - 1e-4) / (1e-4 * float(r.coefficient_of_variation)**2):.0f}\")\n"
        "r.next_threshold.isel(run=0).values  # the intermediate thresholds of the levels"
    ),
    md(
        "## The designer's question, on a small square: at which RH does P(stuck) reach 1e-3?\n\n"
        "**Read this section for the estimator, not for a beam.** The zones below are 128 × 128 px "
        "at 5 nm: a 0.64 µm square pulled off alone, 1/192 of a real beam's interaction zone "
        "(Δs × w = 2.62 × 30 µm). Γ is not an area average: a larger zone rests on taller summits, "
        "so the square carries far more Γ than the beam's zone at low and middle RH "
        "(`rs.stiction.zone_size_bias`, next cell), and its P(stuck) overstates the beam's. The "
        "beam's own answer comes from its strips: notebook 07 (`method='front'` on the strips' Γ) "
        "and `docs/zone_size.md`.\n\n"
        "Measured with `examples/small_stiction_probability.py` on such squares (Eq. 16, "
        "pull-out proxy P(Γ > Γ_crit(l)), 300 samples per level; docs/rare_events.md has the output):\n\n"
        "| beam | Γ_crit | P(stuck) of the 0.64 µm square | RH where it reaches 1e-3 |\n|---|---|---|---|\n"
        "| 150 µm | 31.5 mJ/m² | 1-2.5e-4 at 50-65 % RH, 0.17 at 70 % | 66 % [59 %, 67 %] |\n"
        "| 200 µm | 10.0 mJ/m² | 8e-4 to 8e-3 at 5-50 % RH | already at 5 % RH |\n"
        "| 1500 µm | 3e-3 mJ/m² | 1 [0.987, 1] at 5-50 % RH | always stuck |\n\n"
        "Below, a much smaller live run for the 150 µm beam at 60 % and 70 % RH (few samples per level, "
        "so the intervals are wide)."
    ),
    code(
        "bias = rs.stiction.zone_size_bias((128, 128), spacing=5e-9)\n"
        "print('median Γ of a 128² square / that of the 2.62 x 30 um zone of the beam:')\n"
        "print(', '.join(f'{b:.3g} x at RH {r:.1f}' for r, b in zip(bias.rh.values, bias.values)))"
    ),
    code(
        "psd = rs.datasets.family_psd('table4')\n"
        "warnings.filterwarnings('ignore', message='zones of 128 x 128 px')  # the square's zone: said above\n"
        "ds = rs.stuck_probability(psd, method='subset', relative_humidity=[0.6, 0.7], shape=(128, 128),\n"
        "                          spacing=5e-9, beam_length=150e-6, n_per_level=60, target_cv=None,\n"
        "                          max_levels=4, seed=8)\n"
        "for i, rh in enumerate(ds.rh.values):\n"
        "    d = ds.isel(rh=i)\n"
        "    print(f\"RH {rh:.2f}: P(stuck) = {float(d.stiction_probability):.2e} 95% [{float(d.stiction_probability_lower):.2e}, \"\n"
        "          f\"{float(d.stiction_probability_upper):.2e}] ({int(d.n_evaluations)} evaluations)\")\n"
        "ch = rs.stiction.crossing_humidity(ds[['stiction_probability', 'stiction_probability_lower', 'stiction_probability_upper']], probability=1e-3)\n"
        "edge = lambda v: f'{v:.3f}' if np.isfinite(v) else ('below the lowest RH computed' if v < 0 else 'above the highest RH computed')\n"
        "print(f\"P(stuck) = 1e-3 at RH {edge(float(ch.crossing_humidity))} [{edge(float(ch.crossing_humidity_lower))}, \"\n"
        "      f\"{edge(float(ch.crossing_humidity_upper))}]\")"
    ),
    code(
        "import matplotlib.pyplot as plt\n"
        "fig, ax = plt.subplots(figsize=(6, 3.8), layout='constrained')\n"
        "p, lo, hi = (ds[v].values for v in ('stiction_probability', 'stiction_probability_lower', 'stiction_probability_upper'))\n"
        "rh_pct = ds.rh.values * 100\n"
        "ax.errorbar(rh_pct, p, yerr=[p - lo, hi - p], fmt='o', capsize=4, label='subset simulation, 95 % interval')\n"
        "ax.axhline(1e-3, ls='--', color='0.4', label='design target P = 1e-3')\n"
        "if np.isfinite(float(ch.crossing_humidity)):\n"
        "    span = np.clip([float(ch.crossing_humidity_lower), float(ch.crossing_humidity_upper)], 0.55, 0.75)  # ±inf: off the RH range\n"
        "    ax.axvspan(*(100 * span), color='C1', alpha=0.2,\n"
        "               label='RH where P = 1e-3 (95 % interval)')\n"
        "ax.set(xlim=(55, 75), yscale='log', xlabel='relative humidity [%]', ylabel='P(beam stays stuck)',\n"
        "       title='150 µm beam, 0.64 µm Table-4 squares (live run, few samples)')\n"
        "ax.legend(fontsize='small');"
    ),
    md(
        "## Two fidelities in the tail: Eq. 16 corrected by the boundary-element model\n\n"
        "Eq. 16's rarest zones are often artefacts (docs/rare_events.md), and `fft_bem` on every "
        "state of a run costs ~20 × more. `accurate_model='fft_bem'` runs subset simulation on Eq. 16 "
        "to a threshold relaxed by a measured BEM/Eq. 16 ratio bound, then the BEM on a few hundred "
        "final states (and on a band just below, to check that no BEM failure lies outside). The "
        "estimate is the boundary-element probability. Small 32² zones here, where crude `fft_bem` "
        "Monte Carlo measured P(Γ > 70 mJ/m²) = 8.3e-3 [7.0e-3, 9.6e-3] at RH 0.5 "
        "(docs/evidence/small_probabilities.md; Eq. 16 alone says 8.5e-2)."
    ),
    code(
        "tf = rs.reliability.failure_probability(psd, threshold=0.07, relative_humidity=0.5, shape=(32, 32),\n"
        "                                        spacing=5e-9, model='modified_dmt', accurate_model='fft_bem',\n"
        "                                        n_accurate=150, n_per_level=500, seed=1)\n"
        "print(f\"Eq. 16 above the relaxed level: {float(tf.cheap_probability):.2e}; BEM fraction there: \"\n"
        "      f\"{float(tf.conditional_fraction):.2f}\")\n"
        "print(f\"P(Γ_BEM > 70 mJ/m²) = {float(tf.failure_probability):.2e} 95% [{float(tf.failure_probability_lower):.2e}, \"\n"
        "      f\"{float(tf.failure_probability_upper):.2e}] with {int(tf.n_evaluations)} Eq. 16 and \"\n"
        "      f\"{int(tf.n_accurate_evaluations)} fft_bem evaluations; containment violations: \"\n"
        "      f\"{int(tf.containment_violations)} of {int(tf.containment_checked)}\")"
    ),
    md(
        "## The beam's own zone: strips recombined from sub-zones\n\n"
        "Everything above runs on small squares. The beam's interaction zone Δs × w (2.62 × 30 µm) "
        'is 12 independent sub-zones of 524 × 500 px under one rigid flat (docs/zone_size.md), so a '
        "strip is a function of 12 draws from one distribution of sub-zone laws. `method='strips'` "
        'computes `n` sub-zone laws with Eq. 16 (the first `n_accurate` also with `fft_bem`), '
        'recombines them into strips by importance sampling over their combinations, and carries the '
        "boundary-element answer by scaling each sub-zone's law by a boundary-element/Eq. 16 ratio "
        '(its own where `fft_bem` ran, else one drawn from the pairs nearest it in Eq. 16 Γ), plus a '
        "residual from the pairs' recombined strips of similar Γ; P(stuck) of every length follows "
        "from the sharp front on independent strips (Eq. 36). Where a beam's cv of P(stuck) stays "
        "above 0.6 × `target_cv` (0.3) because of the pairs' ratios, the pairs at that humidity are "
        'doubled, and doubled again up to `max_accurate` (default 4 × `n_accurate`; `random_pairs` '
        "says how many each humidity got). The interval of P(stuck) is the sampling's; "
        "`stiction_probability_model_lower`/`_upper` widen it by the models' own error in each "
        "strip's Γ (`model_band`, default −0.5 % to +4.5 %: the composed law leaves out the "
        "sub-zones' elastic interaction, which whole strips solved by `fft_bem` show, and the "
        'two-fidelity correction runs about 1 % low on strong strips; measured on Table 4 at 77 % '
        'RH, docs/rare_events.md). A tiny live run, its pairs capped at 16 (the designer table, '
        '12,000 sub-zones and 288 through fft_bem per humidity, up to 1,008 where the cv asks for '
        'it, is `python benchmarks/bench_designer.py table`; docs/rare_events.md):'
    ),
    code(
        "r = rs.stuck_probability(psd, method='strips', relative_humidity=[0.75],\n"
        '                         beam_length=[200e-6, 250e-6, 300e-6], n=144, n_accurate=8, n_tail=0, max_accurate=16,\n'
        '                         n_combinations=10_000, n_boot=10, seed=0)\n'
        'print(f"fft_bem/Eq. 16 Γ of the random pairs\' sub-zones (median): "\n'
        '      f"{float(r.accurate_ratio.sel(quantile=0.5)[0]):.2f}; random pairs used: {int(r.random_pairs[0])}")\n'
        "r[['stiction_probability', 'stiction_probability_lower', 'stiction_probability_upper',\n"
        "   'stiction_probability_model_lower', 'stiction_probability_model_upper',\n"
        "   'coefficient_of_variation', 'few_subzones']].to_dataframe()"
    ),
    md(
        "## Weakest link: from a patch to a structure\n\n"
        "A structure of m independent patches fails if any does: 1 − (1 − p)^m, its interval mapped "
        "through the same increasing function. Valid for events that are a union over patches (a "
        "pull-off at the weakest spot), with patches longer than the PSD's correlation length; "
        "not for Γ of a whole zone, which is an average (docs/rare_events.md)."
    ),
    code(
        "w = rs.reliability.weakest_link(ds.isel(rh=1).rename(stiction_probability='failure_probability',\n"
        "                                                      stiction_probability_lower='failure_probability_lower',\n"
        "                                                      stiction_probability_upper='failure_probability_upper'),\n"
        "                                patches=[1, 4, 16, 64])\n"
        "w[['failure_probability', 'failure_probability_lower', 'failure_probability_upper']].to_dataframe()"
    ),
]
nb = nbf.v4.new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3"}})
nbf.write(nb, pathlib.Path(__file__).with_name("08_small_probabilities.ipynb"))
