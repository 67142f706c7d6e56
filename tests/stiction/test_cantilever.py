"""Tests of roughstick.stiction.cantilever: Eq. 36 both ways, its edge cases, units and laziness."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from scipy import integrate, optimize

import roughstick as rs
from conftest import lognormal_gamma
from roughstick._core.units import UnitsError
from roughstick.testing import raise_if_dask_computes

BEAM = rs.PAPER_CANTILEVER


K = 1.5 * 164e9 * (1.9e-6) ** 2 * (2.62e-6) ** 3  # 3/2 E h^2 t^3 of the paper's beams [N m^2]


def test_eq36_stiffness_term_and_value():
    assert BEAM.stiffness_term == pytest.approx(K, rel=1e-14)
    # Gamma_crit of the 1500 um beams: 3/2 E h^2 t^3 / l^4, by hand: 1.5971e-17 / 5.0625e-12
    assert rs.stiction.critical_adhesive_energy() == pytest.approx(3.1549e-6, rel=1e-4)
    assert rs.stiction.adhesive_energy_from_crack_length(1500e-6) == pytest.approx(rs.stiction.critical_adhesive_energy())


def test_eq36_round_trip_numpy_and_units():
    s = np.array([50e-6, 200e-6, 1500e-6, 4e-3])
    g = rs.stiction.adhesive_energy_from_crack_length(s)
    np.testing.assert_allclose(rs.stiction.crack_length_from_adhesive_energy(g), s, rtol=1e-14)
    gamma = np.geomspace(1e-7, 1e-1, 13)
    np.testing.assert_allclose(rs.stiction.adhesive_energy_from_crack_length(rs.stiction.crack_length_from_adhesive_energy(gamma)),
                               gamma, rtol=1e-13)
    # s^-4 scaling: a 15 % change of s changes Gamma by a factor 1.15^4 = 1.75 (paper §5.3)
    assert rs.stiction.adhesive_energy_from_crack_length(400e-6) / rs.stiction.adhesive_energy_from_crack_length(460e-6) == pytest.approx(1.15**4)
    # DataArray in micrometres
    da = xr.DataArray([300.0, 600.0], dims="point", attrs={"units": "um"})
    out = rs.stiction.adhesive_energy_from_crack_length(da)
    assert out.attrs["units"] == "J m-2" and out.name == "adhesive_energy"
    np.testing.assert_allclose(out.values, K / (np.array([300e-6, 600e-6]) ** 4))
    back = rs.stiction.crack_length_from_adhesive_energy(out)
    rs.testing.assert_units(back, "m")
    np.testing.assert_allclose(back.values, [300e-6, 600e-6], rtol=1e-14)


def test_eq36_from_energy_minimisation():
    """Independent derivation: the S-shaped beam (cubic w(x) = h(3 xi^2 - 2 xi^3)) of length s
    has bending energy (EI/2) int w''^2 dx; minimising U(s) = U_bend - Gamma w (l - s) gives s."""
    E, t, h, w, beam_len = 164e9, 2.62e-6, 1.9e-6, 30e-6, 1500e-6
    inertia = w * t**3 / 12

    def bending(s):
        curv = lambda x: h * (6 / s**2 - 12 * x / s**3)  # noqa: E731
        val, _ = integrate.quad(lambda x: curv(x) ** 2, 0, s)
        return 0.5 * E * inertia * val

    for gamma in (2e-5, 1e-3, 3e-2):
        def total(s, gamma=gamma):
            return bending(s) - gamma * w * (beam_len - s)

        res = optimize.minimize_scalar(total, bounds=(10e-6, beam_len), method="bounded",
                                       options={"xatol": 1e-12})
        assert rs.stiction.crack_length_from_adhesive_energy(gamma) == pytest.approx(res.x, rel=1e-5)


def test_eq36_edge_cases():
    assert rs.stiction.crack_length_from_adhesive_energy(0.0) == np.inf
    assert rs.stiction.adhesive_energy_from_crack_length(0.0) == np.inf
    assert np.isnan(rs.stiction.crack_length_from_adhesive_energy(np.nan))
    with pytest.raises(ValueError, match="must be >= 0"):
        rs.stiction.crack_length_from_adhesive_energy(-1e-3)
    with pytest.raises(ValueError, match="must be >= 0"):
        rs.stiction.adhesive_energy_from_crack_length([1e-4, -1e-4])
    with pytest.raises(UnitsError, match="units"):
        rs.stiction.crack_length_from_adhesive_energy(xr.DataArray([1e-3]))
    with pytest.raises(UnitsError, match="not a energy_per_area unit"):
        rs.stiction.crack_length_from_adhesive_energy(xr.DataArray([1e-3], attrs={"units": "m"}))
    with pytest.raises(ValueError, match="has no 'adhesive_energy'"):
        rs.stiction.crack_length_from_adhesive_energy(xr.Dataset({"x": 1.0}))


def test_eq36_lazy(backend):
    g, _ = lognormal_gamma(n=8)
    gi = backend(g, chunks={"realization": 4})
    with raise_if_dask_computes():
        s = rs.stiction.crack_length_from_adhesive_energy(gi)
    assert isinstance(s.data, type(gi.data))
    xr.testing.assert_allclose(s, rs.stiction.crack_length_from_adhesive_energy(g))
    if backend.kind == "dask":
        bad = backend(-g, chunks={"realization": 4})
        out = rs.stiction.crack_length_from_adhesive_energy(bad)  # lazy: the error comes at compute time
        with pytest.raises(ValueError, match="must be >= 0"):
            out.compute()


def test_cantilever_validation():
    assert rs.Cantilever().interaction_area == pytest.approx(2.62e-6 * 30e-6)
    assert rs.Cantilever(interaction_length=5e-6).interaction_zone_length == 5e-6
    for kw in ({"length": 0.0}, {"thickness": -1e-6}, {"youngs_modulus": np.nan}, {"gap": "2um"}):
        with pytest.raises(ValueError, match="must be a positive finite number"):
            rs.Cantilever(**kw)
    with pytest.raises(ValueError, match="beam lengths must be positive"):
        rs.stiction.critical_adhesive_energy(beam_length=[100e-6, -1.0])
