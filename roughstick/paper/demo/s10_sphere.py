"""Demo step: meniscus physics and the sphere contact models (paper §2, Fig. 1b, Fig. 3, Table 1).

Writes into ``out``:

- ``fig1b_meniscus.png``: Laplace pressure and water height against RH (Eqs. 2 and 6);
- ``fig3_sphere_models.png`` and ``sphere_curves.nc``: force-interference curves of the Maugis,
  DMT and modified DMT models for R = 100 and 800 nm at RH 30, 50 and 70 %;
- ``table1.nc`` and ``table1.csv``: the adhesive energies of Table 1, computed and printed,
  with their relative differences.
"""

from __future__ import annotations

import pathlib

from ...io.netcdf import write, write_text_atomic
from ...plotting.save import DEFAULT_DPI, save_figure
from .. import sphere as figures


def run(out, *, quick: bool = False, figure_format: str = "png",
        dpi: int = DEFAULT_DPI) -> list[pathlib.Path]:
    """Write Fig. 1b, Fig. 3 (as ``figure_format`` at ``dpi``), the curves and Table 1 into
    ``out``; return the file paths."""
    import matplotlib

    matplotlib.use("Agg")

    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    files = []
    _, fig = figures.fig1b_meniscus(n=46 if quick else 181)
    files.append(save_figure(fig, out / "fig1b_meniscus.png", format=figure_format, dpi=dpi,
                             bbox_inches="tight"))
    ds, fig = figures.fig3_sphere_models(n=401 if quick else 1401)
    files.append(write(ds, out / "sphere_curves.nc", compute=True, overwrite=True))
    files.append(save_figure(fig, out / "fig3_sphere_models.png", format=figure_format, dpi=dpi,
                             bbox_inches="tight"))
    t1 = figures.table1()
    files.append(write(t1, out / "table1.nc", compute=True, overwrite=True))
    p = out / "table1.csv"
    write_text_atomic(p, t1[["adhesive_energy", "printed", "relative_error"]].to_dataframe().to_csv())
    files.append(p)
    return files
