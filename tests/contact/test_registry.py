"""Adding a contact model is one registry entry: a toy model gets curves, summaries, ``auto``'s
consideration (or its exclusion), the accessor and the command line from the registry alone."""

from __future__ import annotations

import pathlib
import re

import numpy as np
import pytest
import xarray as xr

import roughstick as rs
from roughstick.cli import build_parser, main
from roughstick.cli._schema import SCHEMAS


def _flat_punch(z, distance, context):
    """A rigid flat punch at the map's highest point: a wet neck of the Laplace pressure over the
    whole area while the gap is below the water height, a stiff spring in contact."""
    gap = distance[None, :] - np.nanmax(z)
    wet = (gap > 0) & (gap < context.water_height[:, None])
    spring = context.options["stiffness"] * np.maximum(-gap, 0.0)
    pressure = spring + np.where(wet, context.laplace_pressure[:, None], 0.0)
    return {"pressure": pressure, "wet_fraction": wet.astype(float)}


def _grid(z, context):
    """64 distances from below the top into the dry range, and both sides of each step."""
    top, hw = float(np.nanmax(z)), context.water_height
    steps = np.concatenate([[top, np.nextafter(top, np.inf)], top + hw, np.nextafter(top + hw, -np.inf)])
    return rs.contact.Grid(np.unique(np.concatenate([top + np.linspace(-1e-9, 1.2 * hw.max(), 64), steps])))


def toy(**changes):
    kw = dict(name="toy", title="a flat punch (toy)", kernel=_flat_punch,
              variables=("pressure", "wet_fraction"), default_grid=_grid,
              options={"stiffness": rs.contact.Option(1e18, rule="positive")}, cost_rank=0.5)
    return rs.contact.ContactModel(**{**kw, **changes})


@pytest.fixture
def registered():
    def register(model):
        rs.contact.register_model(model, replace=True)
        return model

    yield register
    if "toy" in rs.contact.MODELS:
        rs.contact.unregister_model("toy")


@pytest.fixture(scope="module")
def height():
    return rs.datasets.surface_family("smooth", shape=(32, 32), seed=1, n=1).isel(realization=0).compute()


def test_a_toy_model_gets_curves_and_summaries_from_the_registry(registered, height):
    registered(toy())
    rh = [0.5, 0.9]
    c = rs.contact.curves(height, relative_humidity=rh, model="toy")
    assert c.attrs["contact_model"] == "toy" and c.attrs["distance_grid"] == "automatic"
    assert set(rs.conventions.CURVE_VARIABLES) <= set(c.data_vars)  # the common layout
    assert c.pressure.dims == ("rh", "distance") and c.fit_error.isnull().all()
    assert c.rh.attrs == rs.conventions.ATTRS["rh"] and "water_height" in c.coords
    assert c.attrs["history"].splitlines()[-1].endswith("roughstick.contact.curves(model='toy')")
    s = rs.contact.summary(c)
    # the work of a neck of |ΔP| over the water height: Eq. 13 on the toy's curve
    expected = -rs.contact.laplace_pressure(rh) * rs.contact.water_height(rh)
    np.testing.assert_allclose(s.adhesive_energy, expected, rtol=1e-6)
    # given distances, a stack, the options: the same pipeline
    stack = xr.concat([height, height + 1e-9], "realization")
    given = rs.contact.curves(stack, relative_humidity=0.7, model="toy", distance=c.distance.values,
                              stiffness=1e17)
    assert given.pressure.dims == ("realization", "distance") and given.attrs["distance_grid"] == "given"
    with pytest.raises(TypeError, match=r"unexpected keyword argument\(s\) \['connectivity'\] for model='toy'"):
        rs.contact.curves(height, relative_humidity=0.7, model="toy", connectivity=8)
    with pytest.raises(ValueError, match="stiffness=-1.0: must be a finite number > 0"):
        rs.contact.curves(height, relative_humidity=0.7, model="toy", stiffness=-1.0)


def test_auto_considers_a_registered_model_by_its_cost_rank_or_excludes_it(registered, height):
    registered(toy(cost_rank=-1.0))  # cheaper than every model, but never measured
    assert rs.contact.model_names()[0] == "toy" and list(rs.contact.MODELS)[0] == "toy"
    model, reason = rs.contact.select_model(height, relative_humidity=0.7, accuracy=0.5)
    assert model != "toy" and "toy bound unbounded" in reason
    registered(toy(cost_rank=None))  # never chosen by model="auto"
    model, reason = rs.contact.select_model(height, relative_humidity=0.7, accuracy=0.5)
    assert "toy" not in reason
    assert rs.contact.model_names()[-1] == "toy"  # those without a rank come last
    # a reference (error 0 by definition) is chosen where nothing cheaper meets the accuracy
    registered(toy(cost_rank=-1.0, reference=True))
    assert rs.contact.select_model(height, relative_humidity=0.7, accuracy=0.5)[0] == "toy"
    assert rs.contact.model_error("toy", {}).upper == 0.0


def test_the_accessor_and_the_command_line_read_the_registry(registered, height, tmp_path):
    assert "toy_curves" not in dir(height.rough)
    registered(toy())
    assert "toy_curves" in dir(height.rough)
    rs.testing.assert_same_result(height.rough.toy_curves(relative_humidity=0.6),
                                  rs.contact.curves(height, relative_humidity=0.6, model="toy"))
    args = build_parser().parse_args(["curves", "m.npy", "--rh", "0.6", "--out", "x.nc", "--model", "toy"])
    assert args.model == "toy"
    for schema in (SCHEMAS["run"]["ensemble"], SCHEMAS["risk"]["risk"], SCHEMAS["beam"]["bank"]):
        assert "toy" in schema["model"].choices
    np.save(tmp_path / "m.npy", height.values * 1e9)
    out = tmp_path / "toy.nc"
    assert main(["curves", str(tmp_path / "m.npy"), "--spacing", "5 nm", "--units", "nm", "--rh", "0.6",
                 "--out", str(out), "--model", "toy"]) == 0
    written = xr.open_dataset(out)
    assert written.attrs["contact_model"] == "toy" and "adhesive_energy" in written
    written.close()
    rs.contact.unregister_model("toy")
    assert "toy_curves" not in dir(height.rough) and "toy" not in rs.contact.MODEL_CHOICES
    with pytest.raises(SystemExit):
        build_parser().parse_args(["curves", "m.npy", "--rh", "0.6", "--out", "x.nc", "--model", "toy"])


def test_registering_checks_the_entry():
    with pytest.raises(ValueError, match="other than 'auto'"):
        rs.contact.register_model(toy(name="auto"))
    with pytest.raises(ValueError, match="registered already"):
        rs.contact.register_model(toy(name="gw"))
    with pytest.raises(ValueError, match="unknown trust checks"):
        rs.contact.register_model(toy(checks=("validity", "speed")))
    with pytest.raises(ValueError, match="min_distances=0: must be an integer >= 1"):
        toy(min_distances=0)
    with pytest.raises(KeyError, match="no contact model named 'toy'"):
        rs.contact.unregister_model("toy")


def test_the_api_page_lists_the_registered_models():
    """The contact reference page's table of models is the registry's (name and description)."""
    page = (pathlib.Path(__file__).resolve().parents[2] / "docs" / "reference" / "contact.md").read_text()
    rows = dict(re.findall(r"^\| `(\w+)` \| (.+?) \|$", page, flags=re.M))
    assert {k: v for k, v in rows.items() if k in rs.contact.MODELS or k == "auto"} == {
        **{name: m.description for name, m in rs.contact.MODELS.items()},
        "auto": "the cheapest registered model whose measured error bound meets `accuracy`"}
