"""Build notebooks/01_sphere_models.ipynb (no outputs committed): ``python notebooks/_build_01.py``."""

import pathlib

import nbformat as nbf

cells = [
    nbf.v4.new_markdown_cell(
        "# 01 · Meniscus physics and sphere contact models\n\n"
        "Paper §2: Laplace pressure and water height (Eqs. 1-6, Fig. 1b), the Hertz, JKR, DMT, "
        "Maugis–Dugdale (+ Kim) and modified DMT models of a poly-Si sphere on a poly-Si flat "
        "(Eqs. 7-11, Fig. 3) and the adhesive energies of Table 1. "
        "Equations and choices: `docs/meniscus.md`, `docs/sphere_models.md`."
    ),
    nbf.v4.new_code_cell(
        "import numpy as np\n"
        "import matplotlib.pyplot as plt\n"
        "import roughstick as rs\n"
        "from roughstick.plotting import plot_meniscus, plot_sphere_curves\n"
        "from roughstick.paper import sphere as figures  # the paper's figures, one copy"
    ),
    nbf.v4.new_markdown_cell("## Fig. 1b: Laplace pressure and water height"),
    nbf.v4.new_code_cell(
        "figures.fig1b_meniscus(n=91);\n"
        "rs.contact.laplace_pressure([0.3, 0.5, 0.7, 0.9]).values / 1e6, rs.contact.water_height([0.3, 0.5, 0.7]).values * 1e9"
    ),
    nbf.v4.new_markdown_cell(
        "## Fig. 3: force–interference curves\n\n"
        "Maugis (retraction branch), DMT and modified DMT for R = 100 and 800 nm at RH 30/50/70 %. "
        "Positive force is repulsive."
    ),
    nbf.v4.new_code_cell(
        "curves, fig = figures.fig3_sphere_models(n=601)\n"
        "curves"
    ),
    nbf.v4.new_markdown_cell(
        "## Table 1: adhesive energies [J]\n\n"
        "Work to separate = integral of the attractive part of the curve, from the equilibrium out to "
        "separation. The transition parameter λ (Eq. 7) shows all cases are near the DMT limit."
    ),
    nbf.v4.new_code_cell(
        "t1 = figures.table1()\n"
        "table = t1[['adhesive_energy', 'printed', 'relative_error']].to_dataframe()\n"
        "table['relative_error'] = (100 * table['relative_error']).round(2)  # percent\n"
        "table"
    ),
    nbf.v4.new_code_cell("t1.transition_parameter.to_pandas().round(4)"),
    nbf.v4.new_markdown_cell(
        "## All five models, and the JKR–DMT transition\n\n"
        "Given adhesion (ω = 0.05 J/m², R = 1 µm): Maugis for increasing λ moves from the DMT "
        "pull-off −2πRω to the JKR pull-off −1.5πRω."
    ),
    nbf.v4.new_code_cell(
        "R, w = 1e-6, 0.05\n"
        "K = rs.materials.hertz_modulus()\n"
        "fig, ax = plt.subplots(figsize=(6, 4))\n"
        "for lam in [0.01, 0.3, 1.0, 3.0, 100.0]:\n"
        "    s0 = lam / 2 * np.cbrt(np.pi * w * K**2 / R)\n"
        "    ld = np.cbrt(np.pi**2 * w**2 * R / K**2)\n"
        "    d = np.linspace(-2 / (np.pi * lam) - 1, 3, 600) * ld\n"
        "    f = rs.contact.sphere_force(d, sphere_model='maugis', radius=R, work_of_adhesion=w, adhesive_stress=s0)\n"
        "    ax.plot(d / ld, f / (np.pi * R * w), label=f'Maugis λ={lam:g}')\n"
        "d = np.linspace(-1, 3, 400) * ld\n"
        "ax.plot(d / ld, rs.contact.sphere_force(d, sphere_model='jkr', radius=R, work_of_adhesion=w) / (np.pi * R * w), 'k--', label='JKR')\n"
        "ax.plot(d / ld, rs.contact.sphere_force(d, sphere_model='hertz', radius=R) / (np.pi * R * w), 'k:', label='Hertz')\n"
        "ax.set_xlim(-3, 3); ax.set_ylim(-2.2, 3)\n"
        "ax.set_xlabel(r'$\\Delta = \\delta\\,/\\,(\\pi^2\\omega^2 R/K^2)^{1/3}$'); ax.set_ylabel('F / (πωR)'); ax.legend(fontsize=8); ax.grid(alpha=0.3)"
    ),
]
nb = nbf.v4.new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
nbf.write(nb, pathlib.Path(__file__).with_name("01_sphere_models.ipynb"))
