"""The paper's Table 1: adhesive energies [J] of a poly-Si sphere on a poly-Si flat, 18 cells."""

import pytest

import roughstick as rs

# rows: model; columns: (RH, R) in the paper's order (roughstick.datasets.paper_table(1))
COLUMNS = [(0.3, 100e-9), (0.3, 800e-9), (0.5, 100e-9), (0.5, 800e-9), (0.7, 100e-9), (0.7, 800e-9)]
_T1 = rs.datasets.paper_table(1).adhesive_energy
TABLE1 = {m: [float(_T1.sel(model=m, rh=rh, radius=r)) for rh, r in COLUMNS] for m in _T1.model.values}
# modified DMT is fully specified by Eqs. 8-11: 1 %; the paper's DMT/Maugis implementations are
# not (docs/sphere_models.md, "Table 1"): 4 %.
TOLERANCE = {"modified_dmt": 0.01, "dmt": 0.04, "maugis": 0.04}

CELLS = [
    pytest.param(model, rh, radius, TABLE1[model][i], id=f"{model}-RH{int(rh * 100)}-R{int(radius * 1e9)}nm")
    for model in TABLE1
    for i, (rh, radius) in enumerate(COLUMNS)
]


@pytest.mark.parametrize(("model", "rh", "radius", "printed"), CELLS)
def test_table1_cell(model, rh, radius, printed):
    W = rs.contact.sphere_adhesive_energy(sphere_model=model, radius=radius, relative_humidity=rh)
    assert W.attrs["units"] == "J"
    assert float(W) == pytest.approx(printed, rel=TOLERANCE[model])


def test_table1_whole_table_broadcasts():
    """One call per model over (radius, rh) gives the same cells as the scalar calls."""
    for model, row in TABLE1.items():
        W = rs.contact.sphere_adhesive_energy(sphere_model=model, radius=[100e-9, 800e-9], relative_humidity=[0.3, 0.5, 0.7])
        assert W.dims == ("radius", "rh")
        for i, (rh, radius) in enumerate(COLUMNS):
            assert float(W.sel(rh=rh, radius=radius)) == pytest.approx(row[i], rel=TOLERANCE[model])
