"""Sphere-on-flat contact models: physics, limits, hard cases, backends, metadata, errors."""

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import trapezoid

import roughstick as rs
from roughstick.contact.sphere import _kernels as k
from roughstick.testing import assert_units, raise_if_dask_computes

KPS = rs.materials.hertz_modulus()  # 115.4 GPa
MODELS = ["hertz", "jkr", "dmt", "maugis", "modified_dmt"]
ADHESIVE = ["jkr", "dmt", "maugis", "modified_dmt"]


def _dimless_units(R, w, Kmod=KPS):
    """Maugis length scale of delta and force scale."""
    return np.cbrt(np.pi**2 * w**2 * R / Kmod**2), np.pi * w * R


# ------------------------------------------------------------------------------------------
# physics
# ------------------------------------------------------------------------------------------
def test_modulus_and_lambda_of_table1():
    assert KPS == pytest.approx(115.4e9, rel=1e-3)
    lam = rs.contact.transition_parameter(radius=[100e-9, 800e-9], relative_humidity=[0.3, 0.5, 0.7])
    assert float(lam.min()) == pytest.approx(0.0214, abs=5e-4)
    assert float(lam.max()) == pytest.approx(0.169, abs=1e-3)
    # lambda ~ R^(1/3) at fixed adhesion (Eq. 7)
    np.testing.assert_allclose(lam.isel(radius=1) / lam.isel(radius=0), 2.0, rtol=1e-12)


def test_hertz_three_halves_power_and_contact_radius():
    R = 250e-9
    d = np.geomspace(1e-12, 1e-8, 41)
    f = rs.contact.sphere_force(d, sphere_model="hertz", radius=R)
    np.testing.assert_allclose(f.values, KPS * np.sqrt(R) * d**1.5, rtol=1e-12)
    slope = np.diff(np.log(f.values)) / np.diff(np.log(d))
    np.testing.assert_allclose(slope, 1.5, rtol=1e-10)
    np.testing.assert_allclose(f.contact_radius.values, np.sqrt(R * d), rtol=1e-12)
    # a^3 = R F / K (Eq. 10)
    np.testing.assert_allclose(f.contact_radius.values ** 3, R * f.values / KPS, rtol=1e-10)
    assert float(rs.contact.sphere_force(-1e-9, sphere_model="hertz", radius=R)) == 0.0


def test_dmt_pull_off_is_2_pi_R_w():
    R, w, s0 = 1e-6, 0.05, 1e8  # lambda = 0.016
    d = np.linspace(-2 * w / s0, 3e-9, 40001)
    f = rs.contact.sphere_force(d, sphere_model="dmt", radius=R, work_of_adhesion=w, adhesive_stress=s0, dmt_outer="paraboloid")
    assert float(f.sel(interference=0.0, method="nearest")) == pytest.approx(-2 * np.pi * R * w, rel=1e-3)
    assert float(f.min()) == pytest.approx(-2 * np.pi * R * w, rel=1e-3)


def test_jkr_pull_off_is_1p5_pi_R_w_and_closed_form():
    R, w = 1e-6, 0.05
    ld, fs = _dimless_units(R, w)
    d = np.linspace(-1.5 * ld, 3 * ld, 30001)
    f = rs.contact.sphere_force(d, sphere_model="jkr", radius=R, work_of_adhesion=w)
    assert float(f.min()) == pytest.approx(-1.5 * np.pi * R * w, rel=1e-5)
    # parametric closed form: F = K a^3/R - sqrt(6 pi w K a^3), delta = a^2/R - 2/3 sqrt(6 pi w a/K)
    a = np.linspace(0.6, 2.0, 50) * np.cbrt(np.pi * w * R**2 / KPS)
    dd = a**2 / R - 2 / 3 * np.sqrt(6 * np.pi * w * a / KPS)
    ff = KPS * a**3 / R - np.sqrt(6 * np.pi * w * KPS * a**3)
    got = rs.contact.sphere_force(dd, sphere_model="jkr", radius=R, work_of_adhesion=w)
    np.testing.assert_allclose(got.values, ff, rtol=1e-9, atol=1e-12 * fs)
    np.testing.assert_allclose(got.contact_radius.values, a, rtol=1e-9)
    # jump-off below delta_min = -3 * 6^(-2/3) in Maugis units
    assert float(rs.contact.sphere_force(-0.9 * ld, sphere_model="jkr", radius=R, work_of_adhesion=w)) < 0
    assert float(rs.contact.sphere_force(-0.92 * ld, sphere_model="jkr", radius=R, work_of_adhesion=w)) == 0.0


def _maugis_P(Delta, lam):
    return k._maugis_dimless(Delta, lam)[0]


def test_maugis_tends_to_dmt_as_lambda_to_zero():
    Delta = np.linspace(0.0, 4.0, 201)
    dmt = Delta**1.5 - 2.0  # classical DMT in Maugis units
    err = [np.max(np.abs(_maugis_P(Delta, lam) - dmt)) for lam in (1e-2, 1e-3, 1e-4)]
    assert err[2] < 0.05
    assert err[1] / err[2] > 2.5 and err[0] / err[1] > 2.5  # converges ~ sqrt(lambda)
    # pull-off -> -2 pi R w
    for lam, tol in ((1e-3, 2e-4), (1e-2, 3e-3)):
        Cj, Cs, Dj, Dstar = k._kim_constants(lam)
        D = np.linspace(Dstar, 2, 20001)
        assert _maugis_P(D, lam).min() == pytest.approx(-2.0, abs=tol)


def test_maugis_tends_to_jkr_as_lambda_to_infinity():
    Delta = np.linspace(-0.89, 4.0, 301)  # JKR jump-off at -0.9086
    jkr = k._jkr_dimless(Delta, "retraction")[0]
    for lam, tol in ((1e2, 1e-4), (1e3, 1e-6)):
        np.testing.assert_allclose(_maugis_P(Delta, lam), jkr, atol=tol)
    # and in SI through the public API: pull-off -> -1.5 pi R w
    R, w = 1e-6, 0.05
    s0 = 1e3 / 2 * np.cbrt(np.pi * w * KPS**2 / R)  # lambda = 1000
    lam = rs.contact.transition_parameter(radius=R, work_of_adhesion=w, adhesive_stress=s0)
    assert float(lam) == pytest.approx(1e3)
    ld, fs = _dimless_units(R, w)
    f = rs.contact.sphere_force(np.linspace(-1, 1, 4001) * ld, sphere_model="maugis", radius=R, work_of_adhesion=w, adhesive_stress=s0)
    assert float(f.min()) / fs == pytest.approx(-1.5, abs=1e-4)


@pytest.mark.parametrize("lam", [1e-3, 0.05, 0.5, 0.9, 1.0, 2.0, 30.0, 1e3])
def test_kim_branch_joins_contact_branch_continuously(lam):
    Cj, Cs, Dj, Dstar = k._kim_constants(lam)
    # contact branch at a -> 0 (phi -> pi/2) lands on Kim's branch at C = Cj
    Dc, Pc, Ac, Cc = k._maugis_contact(np.pi / 2 - np.array([1e-6, 1e-8]), lam)
    assert Ac[-1] < 1e-7 * max(Cj, 1e-3)
    np.testing.assert_allclose(Cc[-1], Cj, rtol=1e-6)
    np.testing.assert_allclose(Dc[-1], k._kim_delta(Cj, lam), rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(Pc[-1], -0.5 * np.pi * lam * Cj**2, rtol=1e-6)
    # Kim's stress-free gap condition at r = c equals Maugis' Eq. (1) limit
    np.testing.assert_allclose(np.pi * lam * Cj**2 / 4 + 4 * lam**2 * Cj / 3 * (np.pi / 2 - 1), 1.0)
    if Cs < Cj:  # the retraction branch passes the junction: force and radii continuous there
        eps = 1e-9 * max(1.0, abs(Dj))
        P, A, C = k._maugis_dimless(np.array([Dj - eps, Dj + eps]), lam)
        np.testing.assert_allclose(P[0], P[1], rtol=1e-5, atol=1e-8)
        np.testing.assert_allclose(C[0], C[1], rtol=1e-4)
        assert A[0] == 0 and A[1] < 1e-3 * Cj


@pytest.mark.parametrize("lam", np.geomspace(1e-3, 1e3, 13))
def test_maugis_inversion_over_lambda_range(lam):
    """Evaluate the parametric curve, feed its Delta back to the solver, recover P (rtol 1e-9)."""
    Cj, Cs, Dj, Dstar = k._kim_constants(lam)
    if Cs < Cj:
        phi_min = np.pi / 2
        C = np.linspace(Cs, Cj, 50)[1:-1]
        D_k = k._kim_delta(C, lam)
        np.testing.assert_allclose(_maugis_P(D_k, lam), -0.5 * np.pi * lam * C**2, rtol=1e-9)
    else:
        phi_min = float(k._maugis_phi_min(np.array([lam]))[0])
    phi = np.geomspace(phi_min * 0.999, phi_min * 1e-4, 80)
    D, P, A, C = k._maugis_contact(phi, lam)
    assert np.all(np.diff(D) > 0)  # rising (stable) branch
    P2, A2, C2 = k._maugis_dimless(D, lam)
    np.testing.assert_allclose(P2, P, rtol=1e-8, atol=1e-10 * np.abs(P).max())
    np.testing.assert_allclose(A2, A, rtol=1e-8)
    # below the jump-off point the sphere is free
    Dlow = np.min(D) - 0.01 * (1 + abs(np.min(D)))
    if Cs < Cj:
        Dlow = Dstar - 1e-3 * (1 + abs(Dstar))
    assert _maugis_P(np.array([Dlow]), lam)[0] == 0.0


def test_branches_differ_only_below_first_interaction():
    R, w, s0 = 1e-6, 0.05, 5e8
    h0 = w / s0
    d = np.linspace(-1.2 * h0, 1e-9, 2001)
    kw = dict(sphere_model="maugis", radius=R, work_of_adhesion=w, adhesive_stress=s0)
    ret = rs.contact.sphere_force(d, **kw)
    app = rs.contact.sphere_force(d, branch="approach", **kw)
    above = d >= -h0
    np.testing.assert_array_equal(ret.values[above], app.values[above])
    assert np.all(app.values[~above] == 0) and np.any(ret.values[~above] < 0)


@pytest.mark.parametrize("model", ["jkr", "dmt", "maugis", "modified_dmt"])
@pytest.mark.parametrize(("rh", "radius"), [(0.3, 800e-9), (0.7, 100e-9), (0.5, 20e-9)])
def test_adhesive_energy_matches_dense_trapezoid(model, rh, radius):
    """Closed-form / Gauss-Legendre energy vs a literal integral of -F 1(F<0) on a dense grid."""
    W = float(rs.contact.sphere_adhesive_energy(sphere_model=model, radius=radius, relative_humidity=rh))
    h = float(rs.contact.water_height(rh))
    d = np.linspace(-1.5 * h - 1e-9, 2e-9, 200001)
    f = rs.contact.sphere_force(d, sphere_model=model, radius=radius, relative_humidity=rh).values
    ref = trapezoid(np.where(f < 0, -f, 0.0), d)
    assert W == pytest.approx(ref, rel=3e-4 if model == "jkr" else 2e-6)


def test_jkr_energy_independent_of_rh_below_layer_onset():
    """Capillary w = |dP| h_men = 2 * 0.53 nm * R T / V_m does not depend on RH (no layer)."""
    W = rs.contact.sphere_adhesive_energy(sphere_model="jkr", radius=1e-7, relative_humidity=[0.2, 0.4, 0.6])
    np.testing.assert_allclose(W.values, W.values[0], rtol=1e-12)


def test_modified_dmt_formula_literal():
    R, rh = 300e-9, 0.5
    dP = float(rs.contact.laplace_pressure(rh))
    h = float(rs.contact.water_height(rh))
    d = np.array([-2 * h, -h / 2, 0.0, 0.3e-9, 2e-9])
    f = rs.contact.sphere_force(d, sphere_model="modified_dmt", radius=R, relative_humidity=rh)
    a2 = np.where(d > 0, R * d, 0)
    Fr = KPS * np.sqrt(R) * np.clip(d, 0, None) ** 1.5
    wet = np.where(d > -h, R**2 - (R - d - h) ** 2 - a2, 0)
    np.testing.assert_allclose(f.values, Fr + dP * np.pi * wet, rtol=1e-12)


# ------------------------------------------------------------------------------------------
# hard cases
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("rh", [0.01, 0.999])
@pytest.mark.parametrize("radius", [1e-9, 100e-6])
def test_extreme_humidity_and_radius(model, rh, radius):
    h = float(rs.contact.water_height(rh))
    w = h * -float(rs.contact.laplace_pressure(rh))
    ld = np.cbrt(np.pi**2 * w**2 * radius / KPS**2)  # JKR's length scale
    scale = max(h, ld)
    d = np.concatenate([np.linspace(-2 * scale, 2 * scale, 401), np.geomspace(2 * scale, 0.1 * radius, 50)])
    f = rs.contact.sphere_force(d, sphere_model=model, radius=radius, relative_humidity=rh)
    assert np.all(np.isfinite(f.values))
    if model in ("dmt", "modified_dmt"):
        assert np.all(f.values[d < -1.01 * h] == 0)
    if model == "maugis":  # retraction may stay attached below -h (stretched neck); approach not
        fa = rs.contact.sphere_force(d, sphere_model=model, radius=radius, relative_humidity=rh, branch="approach")
        assert np.all(fa.values[d < -1.0001 * h] == 0)
    assert float(f.isel(interference=-1)) > 0  # deep contact is repulsive
    if model != "hertz":
        assert float(f.min()) < 0
        W = float(rs.contact.sphere_adhesive_energy(sphere_model=model, radius=radius, relative_humidity=rh))
        assert np.isfinite(W) and W > 0
        # the wetted cap can never exceed the sphere: |F| <= |dP| pi R^2 (+ JKR's own bound)
        if model in ("dmt", "modified_dmt"):
            assert float(f.min()) >= -abs(float(rs.contact.laplace_pressure(rh))) * np.pi * radius**2 * (1 + 1e-9)


def test_interference_empty_scalar_unsorted_nan():
    kw = dict(radius=200e-9, relative_humidity=0.5)
    for model in MODELS:
        empty = rs.contact.sphere_force([], sphere_model=model, **kw)
        assert empty.dims == ("interference",) and empty.size == 0
        scalar = rs.contact.sphere_force(0.5e-9, sphere_model=model, **kw)
        assert scalar.ndim == 0 and np.isfinite(float(scalar))
        d = np.array([1e-9, -1e-9, 0.0, np.nan, 0.5e-9, -3e-9])
        f = rs.contact.sphere_force(d, sphere_model=model, **kw)
        order = np.argsort(d[[0, 1, 2, 4, 5]])
        fs = rs.contact.sphere_force(np.sort(d[[0, 1, 2, 4, 5]]), sphere_model=model, **kw)
        np.testing.assert_array_equal(f.values[[0, 1, 2, 4, 5]][order], fs.values)
        assert np.isnan(f.values[3]) and np.isnan(f.contact_radius.values[3])
        assert np.all(np.isfinite(f.values[[0, 1, 2, 4, 5]]))


def test_kernel_broadcasts_delta_and_radius():
    d = np.linspace(-2e-9, 2e-9, 7)[:, None]
    R = np.array([50e-9, 300e-9, 1e-6])[None, :]
    for model in MODELS:
        f = k.sphere_force_kernel(model, d, R, KPS, 96e6, 1.53e-9)
        assert f.shape == (7, 3)
        for j in range(3):
            np.testing.assert_array_equal(f[:, j], k.sphere_force_kernel(model, d[:, 0], R[0, j], KPS, 96e6, 1.53e-9))


# ------------------------------------------------------------------------------------------
# backends, laziness, metadata
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("model", MODELS)
def test_numpy_and_dask_agree_and_stay_lazy(model, backend):
    radius = xr.DataArray([100e-9, 800e-9], dims="radius", attrs={"units": "m"})
    rh = xr.DataArray([30.0, 50.0, 70.0], dims="rh", attrs={"units": "%"})
    d = xr.DataArray(np.linspace(-5, 2, 15) * 1e-9, dims="interference", attrs={"units": "m"})
    ref = rs.contact.sphere_force(d, sphere_model=model, radius=radius, relative_humidity=rh)
    with raise_if_dask_computes():
        got = rs.contact.sphere_force(d, sphere_model=model, radius=backend(radius), relative_humidity=backend(rh, {"rh": 1}))
        energy = rs.contact.sphere_adhesive_energy(sphere_model=model, radius=backend(radius), relative_humidity=backend(rh))
    assert isinstance(got.data, type(backend(radius).data))
    xr.testing.assert_allclose(got.compute(), ref, rtol=1e-12)
    xr.testing.assert_allclose(
        energy.compute(), rs.contact.sphere_adhesive_energy(sphere_model=model, radius=radius, relative_humidity=rh), rtol=1e-12
    )


def test_metadata():
    f = rs.contact.sphere_force([0.0, 1e-9], sphere_model="maugis", radius=[100e-9], relative_humidity=[0.5])
    assert f.name == "force" and f.dims == ("interference", "radius", "rh")
    assert_units(f, "N")
    assert f.contact_radius.attrs["units"] == "m" and f.adhesive_radius.attrs["units"] == "m"
    assert f.attrs["contact_model"] == "maugis" and "10.1016/0021-9797(92)90285-T" in f.attrs["references"]
    assert f.attrs["branch"] == "retraction"
    ds = rs.contact.sphere_contact([0.0, 1e-9], sphere_model="modified_dmt", radius=100e-9, relative_humidity=0.5)
    assert ds.attrs["Conventions"].startswith("CF")
    assert set(ds.data_vars) >= {"force", "contact_radius", "adhesive_radius", "work_of_adhesion", "transition_parameter"}
    assert_units(ds.work_of_adhesion, "J m-2")
    W = rs.contact.sphere_adhesive_energy(sphere_model="dmt", radius=100e-9, relative_humidity=0.5)
    assert_units(W, "J")
    lam = rs.contact.transition_parameter(radius=100e-9, relative_humidity=0.5)
    assert_units(lam, "1")


def test_units_are_converted():
    a = rs.contact.sphere_force(1e-9, sphere_model="hertz", radius=100e-9)
    b = rs.contact.sphere_force(
        xr.DataArray(1.0, attrs={"units": "nm"}), sphere_model="hertz", radius=xr.DataArray(0.1, attrs={"units": "um"}),
        reduced_modulus=xr.DataArray(rs.materials.reduced_modulus() / 1e9, attrs={"units": "GPa"}),
    )
    assert float(b) == pytest.approx(float(a), rel=1e-12)


def test_given_adhesion_equals_capillary_with_same_parameters():
    rh = 0.5
    s0 = -float(rs.contact.laplace_pressure(rh))
    h0 = float(rs.contact.water_height(rh))
    d = np.linspace(-2e-9, 1e-9, 31)
    for model in ADHESIVE:
        a = rs.contact.sphere_force(d, sphere_model=model, radius=1e-7, relative_humidity=rh)
        b = rs.contact.sphere_force(d, sphere_model=model, radius=1e-7, work_of_adhesion=s0 * h0, adhesive_stress=s0)
        np.testing.assert_allclose(a.values, b.values, rtol=1e-10)


# ------------------------------------------------------------------------------------------
# errors
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(sphere_model="maugis", radius=1e-7, relative_humidity=1.2), "between 0 and 1"),
        (dict(sphere_model="maugis", radius=1e-7, relative_humidity=0.0), "between 0 and 1"),
        (dict(sphere_model="dmt", radius=-1e-7, relative_humidity=0.5), "radius must be positive.*in m"),
        (dict(sphere_model="dmt", radius=0.0, relative_humidity=0.5), "radius must be positive"),
        (dict(sphere_model="dmt", radius=1e-7, relative_humidity=0.5, reduced_modulus=0.0), "reduced_modulus must be positive"),
        (dict(sphere_model="dkt", radius=1e-7, relative_humidity=0.5), "valid names are 'hertz', 'jkr'"),
        (dict(sphere_model="dmt", radius=xr.DataArray(1e-7), relative_humidity=0.5), "no 'units' attribute.*attrs\\['units'\\]"),
        (dict(sphere_model="dmt", radius=1e-7, relative_humidity=xr.DataArray(0.5)), "no 'units' attribute"),
        (dict(sphere_model="dmt", radius=1e-7, work_of_adhesion=0.1), "adhesive_stress"),
        (dict(sphere_model="maugis", radius=1e-7), "needs adhesion"),
        (dict(sphere_model="jkr", radius=1e-7, work_of_adhesion=-0.1), "work_of_adhesion must be positive"),
        (dict(sphere_model="jkr", radius=1e-7, relative_humidity=0.5, work_of_adhesion=0.1), "not both"),
        (dict(sphere_model="maugis", radius=1e-7, relative_humidity=0.5, branch="up"), "branch"),
    ],
)
def test_bad_input_errors(kwargs, match):
    with pytest.raises(ValueError, match=match):
        rs.contact.sphere_force(1e-9, **kwargs)


def test_bad_material_modulus():
    with pytest.raises(ValueError, match="youngs_modulus must be positive"):
        rs.Material(youngs_modulus=-1.0)


def test_lazy_bad_radius_raises_at_compute():
    radius = xr.DataArray([1e-7, -1e-7], dims="radius", attrs={"units": "m"}).chunk({"radius": 1})
    f = rs.contact.sphere_force(1e-9, sphere_model="hertz", radius=radius)
    with pytest.raises(ValueError, match="radius must be positive"):
        f.compute()


def test_demo_step_writes_figures_curves_and_table1(tmp_path):
    from roughstick.paper.demo import s10_sphere

    files = s10_sphere.run(tmp_path, quick=True)
    names = {p.name for p in files}
    assert names == {"fig1b_meniscus.png", "fig3_sphere_models.png", "sphere_curves.nc", "table1.nc", "table1.csv"}
    assert all(p.exists() and p.stat().st_size > 0 for p in files)
    t1 = xr.open_dataset(tmp_path / "table1.nc")
    assert t1.adhesive_energy.attrs["units"] == "J"
    assert float(abs(t1.relative_error.sel(model="modified_dmt")).max()) < 0.01
    assert float(abs(t1.relative_error).max()) < 0.04
    curves = xr.open_dataset(tmp_path / "sphere_curves.nc")
    assert curves.force.dims == ("model", "interference", "radius", "rh")
    t1.close()
    curves.close()


@pytest.mark.parametrize("model", ["jkr", "dmt", "maugis", "modified_dmt"])
def test_soft_material_warns_small_strain_is_violated(model, recwarn):
    """Issue 16 item 11: on E* = 1 MPa the capillary adhesion alone gives a zero-load JKR contact
    radius a0 = (6 pi w R^2 / K)^(1/3) of 2.7 R (w = 2 gamma at RH 50 %), far outside the
    small-strain theory; on silicon a0 = 0.06 R and nothing is said."""
    delta = np.array([-2e-9, 0.0, 1e-9])
    kw = dict(sphere_model=model, radius=100e-9, relative_humidity=0.5)
    with pytest.warns(rs.contact.ValidityWarning, match=r"contact radius of 2\.7 sphere radii on E\* = 1e\+06 Pa"):
        rs.contact.sphere_force(delta, reduced_modulus=1e6, **kw)
    with pytest.warns(rs.contact.ValidityWarning, match="modulus is in Pa") as record:
        rs.contact.sphere_adhesive_energy(reduced_modulus=1e6, **kw)
    assert record[0].filename == __file__  # the user's line, not roughstick's
    w = 2 * 0.0728 * 1.0  # the paper's water on a wetting surface, upper bound of the capillary w
    a0 = np.cbrt(6 * np.pi * w * (100e-9) ** 2 / (4 / 3 * 86.6e9))
    assert a0 < 0.1 * 100e-9
    recwarn.clear()
    rs.contact.sphere_force(delta, reduced_modulus=86.6e9, **kw)
    rs.contact.sphere_adhesive_energy(reduced_modulus=86.6e9, **kw)
    assert not [r for r in recwarn if issubclass(r.category, rs.contact.ValidityWarning)]


def test_deep_interference_warns_even_without_adhesion():
    """Hertz on silicon at delta = R/2: a = sqrt(R delta) = 0.71 R, beyond small strain."""
    with pytest.warns(rs.contact.ValidityWarning, match=r"given interferences give a contact radius of 0\.71"):
        rs.contact.sphere_force([1e-9, 50e-9], sphere_model="hertz", radius=100e-9)
