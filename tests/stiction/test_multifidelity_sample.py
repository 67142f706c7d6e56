"""A count of P(stuck) never counts the cheap model of a multi-fidelity ensemble: the sample of
predict_adhesive_energy runs one model on every surface, and an ensemble whose adhesive_energy
is the cheap model's is refused with the fix."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr

import roughstick as rs


def _psd():
    q = np.geomspace(1e5, 4e9, 300)
    p = xr.DataArray(rs.datasets.family_psd("table4")(q), dims="q", coords={"q": q},
                     attrs={"units": "m4"})
    p["q"].attrs["units"] = "rad m-1"
    return p


def test_a_multifidelity_ensemble_is_not_counted():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ens = rs.ensemble.run(_psd(), n=6, shape=(32, 32), spacing=5e-9, relative_humidity=[0.5],
                              model="modified_dmt", accurate_model="fft_bem", n_accurate=2, seed=1)
    assert "cheap model" in ens.adhesive_energy.attrs["multifidelity"]
    for data in (ens, ens.adhesive_energy):
        with pytest.raises(ValueError, match="multi-fidelity.*cheap model's P\\(stuck\\).*"
                                             "accurate_model=False.*confidence_band"):
            rs.stuck_probability(data, method="count", beam_length=[200e-6])
        with pytest.raises(ValueError, match="multi-fidelity"):
            rs.stiction.risk_summary(data, beam_length=[200e-6])


def test_the_sample_runs_one_model_on_every_surface():
    """Where the default ensemble goes multi-fidelity (n = 200, an accuracy Eq. 16 misses: the
    pilot asks for 40 of 200 here), the sample does not: the chosen model on all surfaces."""
    kw = dict(n=200, shape=(32, 32), relative_humidity=[0.5], seed=1, accuracy=0.3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        default = rs.ensemble.run(_psd(), spacing=5e-9, **kw)
        ds = rs.stiction.predict_adhesive_energy(_psd(), **kw)
        plain = rs.ensemble.run(_psd(), spacing=5e-9, accurate_model=False, **kw)
    assert default.attrs["accurate_model"] == "fft_bem"
    for d in (ds, plain):
        assert "accurate_model" not in d.attrs and "adhesive_energy_accurate" not in d
        assert d.attrs["contact_model"] == "fft_bem"
    with pytest.raises(ValueError, match="one model runs on every surface.*drop accurate_model"):
        rs.stiction.predict_adhesive_energy(_psd(), n=4, shape=(32, 32), relative_humidity=[0.5],
                                            accurate_model="fft_bem")
