"""Greenwood–Williamson statistical contact (paper §3.2 Eq. 14, §3.4.2, Fig. 9).

Independent references used here: closed forms of Nayak (1971) / McCool (1986) for summit
statistics, the classical GW load integral with Gaussian summit heights (parabolic-cylinder
closed form of F_{3/2}), a Monte Carlo count and force sum over the summits of generated
Gaussian surfaces, and quadrature refinement.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr
from scipy import integrate, special

import roughstick as rs
from roughstick.contact.sphere._kernels import sphere_force_kernel
from roughstick.testing import raise_if_dask_computes

NM = 1e-9


def moments(m0_nm2, m2, m4_nm2, dims=()):
    def v(x, u):
        return (dims, np.asarray(x, dtype=float), {"units": u})

    return xr.Dataset({"m0": v(m0_nm2, "nm2"), "m2": v(m2, "1"), "m4": v(m4_nm2, "nm-2")})


S1 = moments(15.7, 0.040, 5.08e-4)  # Table 3, PSD moments of sample S1
S2 = moments(4.32, 0.021, 3.99e-4)  # Table 3, sample S2
RH6 = [0.3, 0.5, 0.6, 0.7, 0.8, 0.9]


def gamma(pressure):
    """Apparent adhesive energy of Eq. 13 by the trapezoid rule (independent of adhesion.py)."""
    neg = np.minimum(pressure.values, 0.0)
    return -np.trapezoid(neg, pressure["distance"].values, axis=-1)


# --------------------------------------------------------------------------------------------
# summit statistics
# --------------------------------------------------------------------------------------------


def grid_density(alpha, measure, xi, t):
    ds = moments(1.0, 1.0, alpha)  # m0 = 1 nm2, m2 = 1, m4 = alpha nm-2 -> bandwidth alpha
    h = xr.DataArray(xi * NM, dims="xi", attrs={"units": "m"})
    k = xr.DataArray(t * np.sqrt(alpha) / NM, dims="t")
    rho = rs.contact.summit_joint_density(h, k, moments=ds, curvature_measure=measure)
    return rho.values * NM * np.sqrt(alpha) / NM  # dimensionless density in (xi, t)


@pytest.mark.parametrize("measure", ["geometric", "mean"])
@pytest.mark.parametrize("alpha", [1.55, 3.0, 10.0, 1e4])
def test_joint_density_normalised_and_nayak_moments(alpha, measure):
    xi = np.linspace(-9, 11, 2001)
    t = np.linspace(0, 8, 1601)
    rho = grid_density(alpha, measure, xi, t)
    assert np.all(rho >= 0) and np.all(np.isfinite(rho))
    marg_h = integrate.simpson(rho, x=t, axis=1)
    total = integrate.simpson(marg_h, x=xi)
    assert total == pytest.approx(1.0, abs=1e-7)
    # Nayak (1971) / McCool (1986): mean summit height 4/sqrt(pi alpha), variance 1 - 0.8968/alpha
    mean = integrate.simpson(xi * marg_h, x=xi)
    var = integrate.simpson((xi - mean) ** 2 * marg_h, x=xi)
    assert mean == pytest.approx(4 / np.sqrt(np.pi * alpha), rel=1e-6)
    assert var == pytest.approx(1 - 0.8968 / alpha, abs=2e-5)
    marg_t = integrate.simpson(rho, x=xi, axis=0)
    if measure == "mean":  # Nayak: mean summit curvature (8/3) sqrt(m4/pi)
        assert integrate.simpson(t * marg_t, x=t) == pytest.approx(8 / (3 * np.sqrt(np.pi)), rel=1e-6)
    else:  # geometric-mean curvature: (9/2) t^3 exp(-3t^2/4) erfcx(3t/2), any alpha
        ref = 4.5 * t**3 * np.exp(-0.75 * t**2) * special.erfcx(1.5 * t)
        np.testing.assert_allclose(marg_t, ref, atol=1e-7)


def test_summit_density_value():
    # N = m4 / (6 pi sqrt(3) m2) = 5.08e-4 / (6 pi sqrt 3 * 0.040) nm-2
    assert float(rs.surface.summit_density(S1)) == pytest.approx(5.08e-4 / (6 * np.pi * np.sqrt(3) * 0.04) * 1e18)
    assert rs.surface.summit_density(S1).attrs["units"] == "m-2"


def gaussian_field(rng, n, dx, q0, sigma):
    q = 2 * np.pi * np.fft.fftfreq(n, dx)
    QY, QX = np.meshgrid(q, q, indexing="ij")
    amp = np.exp(-(QX**2 + QY**2) / (4 * q0**2))
    z = np.fft.ifft2(amp * (rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n)))).real
    return z * sigma / z.std(), QX, QY


def summits(z, QX, QY):
    """Heights and geometric-mean radii of the summits, refined by one Newton step (spectral)."""
    Z = np.fft.fft2(z)

    def der(f):
        return np.fft.ifft2(f * Z).real

    zx, zy = der(1j * QX), der(1j * QY)
    zxx, zyy, zxy = der(-QX**2), der(-QY**2), der(-QX * QY)
    top = np.ones(z.shape, bool)
    for sy in (-1, 0, 1):
        for sx in (-1, 0, 1):
            if sy or sx:
                top &= z > np.roll(z, (sy, sx), axis=(0, 1))
    iy, ix = np.nonzero(top)
    a, b, c = zxx[iy, ix], zyy[iy, ix], zxy[iy, ix]
    gx, gy = zx[iy, ix], zy[iy, ix]
    det = a * b - c * c
    ok = (a < 0) & (det > 0)
    step_x = -(b * gx - c * gy) / det
    step_y = -(-c * gx + a * gy) / det
    h = z[iy, ix] + 0.5 * (gx * step_x + gy * step_y)
    return h[ok], 1 / np.sqrt(det[ok])


@pytest.fixture(scope="module")
def monte_carlo():
    rng = np.random.default_rng(20240607)
    n, dx = 1024, 5 * NM
    H, R, mom = [], [], []
    for _ in range(2):
        z, QX, QY = gaussian_field(rng, n, dx, q0=0.15 / dx, sigma=4 * NM)
        h, r = summits(z, QX, QY)
        H.append(h)
        R.append(r)
        h_map = rs.testing.make_topography(z, spacing=dx, periodic=True)
        mom.append(rs.surface.roughness_moments(h_map, method="spectral"))
    m = xr.concat(mom, "r").mean("r")
    for k in m:
        m[k].attrs = mom[0][k].attrs
    return np.concatenate(H), np.concatenate(R), m, 2 * (n * dx) ** 2


def test_monte_carlo_summits_match_nayak(monte_carlo):
    H, R, m, area = monte_carlo
    m0, m2, m4 = (float(m[k]) for k in ("m0", "m2", "m4"))
    alpha = m0 * m4 / m2**2
    assert alpha == pytest.approx(3.0, rel=0.02)  # Gaussian PSD: alpha = 3
    count = float(rs.surface.summit_density(m)) * area
    assert H.size == pytest.approx(count, rel=0.04)  # ~4300 summits
    assert H.mean() / np.sqrt(m0) == pytest.approx(4 / np.sqrt(np.pi * alpha), abs=0.04)
    assert H.var() / m0 == pytest.approx(1 - 0.8968 / alpha, abs=0.04)


def test_monte_carlo_force_sum_matches_quadrature(monte_carlo):
    """Eq. 14 against the literal sum of modified-DMT forces over the generated summits."""
    H, R, m, area = monte_carlo
    t = 1 / R / np.sqrt(float(m["m4"]))
    sel = (t > 0.1) & (t < 2.5)
    K = rs.materials.hertz_modulus()
    dP, hw = abs(float(rs.contact.laplace_pressure(0.9))), float(rs.contact.water_height(0.9))
    d = np.linspace(0, 25 * NM, 26)
    direct = np.array(
        [sphere_force_kernel("modified_dmt", H[sel] - di, R[sel], K, dP, hw).sum() / area for di in d]
    )
    p = rs.contact.gw_curves(m, relative_humidity=0.9, distance=d).pressure.values
    rep = direct > 1e8  # tens of summits or more in contact
    np.testing.assert_allclose(p[rep], direct[rep], rtol=0.06)
    assert p.min() == pytest.approx(direct.min(), rel=0.15)
    assert d[np.argmin(p)] == pytest.approx(d[np.argmin(direct)], abs=1.1 * NM)


# --------------------------------------------------------------------------------------------
# classical GW limit, quadrature convergence
# --------------------------------------------------------------------------------------------


def F32(x):
    """int_x^inf (s - x)^{3/2} phi(s) ds = Gamma(5/2)/sqrt(2 pi) exp(-x^2/4) D_{-5/2}(x)."""
    return special.gamma(2.5) / np.sqrt(2 * np.pi) * np.exp(-(x**2) / 4) * special.pbdv(-2.5, x)[0]


def test_hertz_equals_classical_gw_integral():
    # alpha -> infinity: summit heights are N(0, m0) independent of curvature (GW 1966)
    m0, m4 = 9.0, 4e-4
    alpha = 1e16
    m2 = np.sqrt(m0 * m4 / alpha)
    ds = moments(m0, m2, m4)
    sigma = 3.0 * NM
    d = np.array([-1.0, 0.0, 1.0, 2.0, 3.0, 4.0]) * sigma
    out = rs.contact.gw_curves(ds, relative_humidity=0.5, distance=d, sphere_model="hertz")
    N = float(rs.surface.summit_density(ds))
    K = rs.materials.hertz_modulus()

    def rho_t(t):
        return 4.5 * t**3 * np.exp(-0.75 * t**2) * special.erfcx(1.5 * t)

    mean_sqrt_r = integrate.quad(lambda t: rho_t(t) / np.sqrt(t), 0.1, 2.5, epsabs=0, epsrel=1e-12)[0]
    mean_sqrt_r /= (m4 * 1e18) ** 0.25
    ref = N * K * mean_sqrt_r * sigma**1.5 * F32(d / sigma)
    np.testing.assert_allclose(out.pressure.values, ref, rtol=2e-6)
    np.testing.assert_allclose(out.repulsive_pressure.values, ref, rtol=2e-6)
    # the expected number of contacts: N P(h > d) within the curvature limits
    p_t = integrate.quad(rho_t, 0.1, 2.5)[0]
    np.testing.assert_allclose(out.n_contacts.values, N * p_t * special.ndtr(-d / sigma), rtol=2e-6)
    # contact area: sum of pi R delta
    mean_r = integrate.quad(lambda t: rho_t(t) / t, 0.1, 2.5)[0] / np.sqrt(m4 * 1e18)
    F1 = np.exp(-(d / sigma) ** 2 / 2) / np.sqrt(2 * np.pi) - d / sigma * special.ndtr(-d / sigma)
    np.testing.assert_allclose(out.contact_fraction.values, N * np.pi * mean_r * sigma * F1, rtol=2e-6)
    assert np.all(out.wet_fraction.values == 0)


def test_quadrature_converges():
    d = np.linspace(-2, 30, 97) * NM
    res = {}
    for nh, nk in [(8, 6), (16, 12), (32, 24), (128, 96)]:
        c = rs.contact.gw_curves(S1, relative_humidity=[0.3, 0.9], distance=d, height_cutoff=2.5,
                                 n_height=nh, n_curvature=nk)
        res[nh] = (gamma(c.pressure), c.pressure.values)
    g_ref, p_ref = res[128]
    errs = [np.max(np.abs(res[n][0] / g_ref - 1)) for n in (8, 16)]
    assert errs[0] > errs[1] > 0
    assert np.max(np.abs(res[32][0] / g_ref - 1)) < 1e-7  # the defaults
    scale = np.abs(p_ref).max(axis=-1, keepdims=True)
    assert np.max(np.abs(res[32][1] - p_ref) / scale) < 1e-7
    default = rs.contact.gw_curves(S1, relative_humidity=[0.3, 0.9], distance=d, height_cutoff=2.5)
    np.testing.assert_array_equal(default.pressure.values, res[32][1])


def test_integration_top_is_beyond_the_density():
    d = np.linspace(0, 30, 61) * NM
    a = rs.contact.gw_curves(S1, relative_humidity=0.9, distance=d)
    b = rs.contact.gw_curves(S1, relative_humidity=0.9, distance=d, height_cutoff=9.0)
    np.testing.assert_allclose(a.pressure, b.pressure, rtol=1e-9, atol=1e-9 * float(abs(a.pressure).max()))


# --------------------------------------------------------------------------------------------
# the paper's findings (§3.4.2, Fig. 9)
# --------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def cutoff_study():
    d = np.linspace(-5, 40, 181) * NM
    return rs.contact.gw_cutoff_study(S1, relative_humidity=[0.3, 0.9], distance=d,
                              height_cutoffs=[2.5, 3, 4, 5, 6, 7, None])


def test_fig9_cutoff_study(cutoff_study):
    g = gamma(cutoff_study.pressure)  # (cutoff, rh)
    cuts = cutoff_study.height_cutoff.values
    assert np.isinf(cuts[-1])
    g30, g90 = g[:, 0], g[:, 1]
    # Gamma decreases as the cutoff is raised (fewer, stiffer tall summits stop the approach)
    assert np.all(np.diff(g30) < 0) and np.all(np.diff(g90) <= 0)
    # RH 30 %: converged (to 1e-4 of the 2.5 sqrt(m0) value) from 6 sqrt(m0) on, not before
    err = np.abs(g30 - g30[-1]) / g30[0]
    assert err[cuts == 6][0] < 1e-4 and err[cuts == 7][0] < 1e-4
    assert err[cuts == 5][0] > 1e-4 and err[cuts == 4][0] > 1e-3
    # ... and then predicts almost no stiction (Gamma(no cutoff) < 1e-3 Gamma(2.5 sqrt m0))
    assert g30[-1] < 1e-3 * g30[0]
    # RH 90 %: converged to 0.1 % at 6 sqrt(m0)
    assert abs(g90[cuts == 6][0] / g90[-1] - 1) < 1e-3


def test_no_saturation_in_gw():
    """§3.4.2: GW sums unmerged menisci, so its wetted fraction and tension are not capped.

    The paper reports GW's maximum adhesive pressure at RH 90 % as 20 MPa for S1 (> |ΔP| =
    14.6 MPa). With the S1 moments of Table 3 this implementation gives 2.1 MPa (6.5 MPa with
    the 2.5 sqrt(m0) cutoff; a Monte Carlo summit sum agrees, see above); with the S2 moments
    and the cutoff of ref. [1] it exceeds |ΔP|. See docs/greenwood_williamson.md.
    """
    d = np.linspace(-5, 40, 451) * NM
    dP = abs(float(rs.contact.laplace_pressure(0.9)))
    assert dP == pytest.approx(14.6e6, rel=2e-3)
    for ds in (S1, S2):
        c = rs.contact.gw_curves(ds, relative_humidity=0.9, distance=d)
        assert float(c.wet_fraction.max()) > 1.0  # a merged meniscus can cover at most 1
    c = rs.contact.gw_curves(S2, relative_humidity=0.9, distance=d, height_cutoff=2.5)
    assert -float(c.pressure.min()) > dP


def test_modified_dmt_decomposition():
    """pressure = Hertz part + ΔP × wetted fraction, exactly, for the modified DMT (Eq. 9)."""
    d = np.linspace(-3, 30, 67) * NM
    c = rs.contact.gw_curves(S2, relative_humidity=RH6, distance=d)
    dP = rs.contact.laplace_pressure(RH6)
    np.testing.assert_allclose(
        c.pressure, c.repulsive_pressure + dP * c.wet_fraction, rtol=1e-10,
        atol=1e-10 * float(abs(c.pressure).max()),
    )
    # humidity changes only the water term; the Hertz part and the contacts do not depend on it
    assert float(abs(c.repulsive_pressure.diff("rh")).max()) == 0
    assert float(abs(c.contact_fraction.diff("rh")).max()) == 0
    # monotone in humidity: more water, more tension at every distance in contact
    assert np.all(c.wet_fraction.diff("rh") >= -1e-12)


def test_sphere_models_agree_for_stiff_polysilicon():
    """Table 1: DMT and Maugis adhesive energies within ~10 % of the modified DMT (λ < 0.2)."""
    d = np.linspace(-2, 30, 129) * NM
    g = {}
    for model in ("modified_dmt", "dmt", "maugis"):
        c = rs.contact.gw_curves(S1, relative_humidity=[0.3, 0.7, 0.9], distance=d,
                                 sphere_model=model, height_cutoff=2.5)
        g[model] = gamma(c.pressure)
    np.testing.assert_allclose(g["dmt"], g["modified_dmt"], rtol=0.05)
    np.testing.assert_allclose(g["maugis"], g["modified_dmt"], rtol=0.12)


def test_force_table_matches_direct_kernel():
    d = np.linspace(-2, 30, 81) * NM
    kw = dict(relative_humidity=[0.3, 0.9], distance=d, height_cutoff=3.0)
    direct = rs.contact.gw_curves(S1, force_table=0, **kw)
    table = rs.contact.gw_curves(S1, force_table=256, **kw)
    scale = float(abs(direct.pressure).max())
    np.testing.assert_allclose(table.pressure, direct.pressure, atol=1e-6 * scale)
    np.testing.assert_allclose(gamma(table.pressure), gamma(direct.pressure), rtol=1e-5)


def test_extreme_humidity_and_no_layer():
    d = np.linspace(-5, 60, 131) * NM
    c = rs.contact.gw_curves(S1, relative_humidity=[0.01, 0.999], distance=d)
    assert np.all(np.isfinite(c.pressure))
    # RH 0.01: water height ~0.1 nm -> tension far below the RH 99.9 % one
    assert gamma(c.pressure)[0] < 1e-3 * gamma(c.pressure)[1]
    none = rs.contact.gw_curves(S1, relative_humidity=0.9, distance=d, adsorbed_layer="none")
    paper = rs.contact.gw_curves(S1, relative_humidity=0.9, distance=d)
    assert gamma(none.pressure) < gamma(paper.pressure)


# --------------------------------------------------------------------------------------------
# layout, metadata, backends
# --------------------------------------------------------------------------------------------


def test_layout_and_metadata():
    d = np.linspace(30, -2, 40) * NM  # descending on input, stored ascending
    ens = moments([15.7, 4.32], [0.040, 0.021], [5.08e-4, 3.99e-4], dims=("realization",))
    c = rs.contact.gw_curves(ens, relative_humidity=[0.3, 0.9], distance=d, apparent_area=(5.12e-6) ** 2)
    for v in ("pressure", "repulsive_pressure", "wet_fraction", "contact_fraction", "n_contacts",
              "fit_error", "max_interference"):
        assert c[v].dims == ("realization", "rh", "distance"), v
    assert np.all(np.diff(c.distance.values) > 0)
    assert c.pressure.attrs["units"] == "Pa"
    assert c.n_contacts.attrs["units"] == "1"
    assert c.distance.attrs["units"] == "m" and c.rh.attrs["units"] == "1"
    assert c.fit_error.isnull().all()
    assert c.attrs["contact_model"] == "gw"  # the registry name
    assert "10.1115/1.3451608" in c.attrs["references"]
    assert c.summit_density.dims == ("realization",)
    np.testing.assert_allclose(c.max_interference.isel(rh=0),
                               10 * np.sqrt(ens.m0 * 1e-18) - c.distance)
    per_area = rs.contact.gw_curves(ens, relative_humidity=[0.3, 0.9], distance=d)
    assert per_area.n_contacts.attrs["units"] == "m-2"
    np.testing.assert_allclose(c.n_contacts, per_area.n_contacts * (5.12e-6) ** 2)
    # each realization equals its own single-moment call
    one = rs.contact.gw_curves(S2, relative_humidity=[0.3, 0.9], distance=d)
    np.testing.assert_allclose(per_area.pressure.isel(realization=1), one.pressure, rtol=1e-12)


def test_dask_matches_numpy_and_stays_lazy():
    d = np.linspace(-2, 30, 33) * NM
    ens = moments([15.7, 4.32, 9.0], [0.040, 0.021, 0.03], [5.08e-4, 3.99e-4, 4e-4],
                  dims=("realization",))
    rh = xr.DataArray([0.3, 0.6, 0.9], dims="rh", coords={"rh": [0.3, 0.6, 0.9]}, attrs={"units": "1"})
    eager = rs.contact.gw_curves(ens, relative_humidity=rh, distance=d)
    with raise_if_dask_computes():
        lazy = rs.contact.gw_curves(ens.chunk({"realization": 1}), relative_humidity=rh.chunk({"rh": 2}),
                                    distance=d)
    assert isinstance(lazy.pressure.data, type(ens.chunk().m0.data))
    xr.testing.assert_allclose(lazy.compute(), eager, rtol=1e-12)


def test_height_map_input():
    rng = np.random.default_rng(0)
    z, _, _ = gaussian_field(rng, 128, 5 * NM, q0=0.2 / (5 * NM), sigma=3 * NM)
    h = rs.testing.make_topography(z, spacing=5 * NM, periodic=True)
    m = rs.surface.roughness_moments(h, method="spectral")
    assert float(m.m0) == pytest.approx(z.var(), rel=1e-12)  # Parseval
    d = np.linspace(0, 20, 21) * NM
    a = rs.contact.gw_curves(h, relative_humidity=0.7, distance=d, moment_method="spectral")
    b = rs.contact.gw_curves(m, relative_humidity=0.7, distance=d)
    xr.testing.assert_allclose(a.pressure, b.pressure)
    # the default estimator of a map's moments is the paper's (Table 2 cubic splines)
    c = rs.contact.gw_curves(h, relative_humidity=0.7, distance=d)
    e = rs.contact.gw_curves(rs.surface.roughness_moments(h, method="spline"), relative_humidity=0.7, distance=d)
    xr.testing.assert_allclose(c.pressure, e.pressure)
    bad = h.copy()
    bad[3, 4] = np.nan
    with pytest.raises(ValueError, match="(?i)nan"):
        rs.contact.gw_curves(bad, relative_humidity=0.7, distance=d)


# --------------------------------------------------------------------------------------------
# bad input
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "ds, match",
    [
        (moments(-1.0, 0.04, 5e-4), "m0 must be positive"),
        (moments(15.7, 0.0, 5e-4), "m2 must be positive"),
        (moments(15.7, 0.04, np.nan), "m4 must be positive"),
        (moments(1.0, 0.04, 2e-3), "bandwidth alpha"),  # alpha = 1.25
    ],
)
def test_bad_moments(ds, match):
    with pytest.raises(ValueError, match=match):
        rs.contact.gw_curves(ds, relative_humidity=0.5, distance=[0.0, 1e-9])


def test_bad_moments_lazy_raise_at_compute():
    ds = moments([15.7, -1.0], [0.04, 0.04], [5e-4, 5e-4], dims=("realization",)).chunk({"realization": 1})
    out = rs.contact.gw_curves(ds, relative_humidity=0.5, distance=[0.0, 1e-9])
    with pytest.raises(ValueError, match="m0 must be positive"):
        out.pressure.compute()


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(curvature_limits=(2.5, 0.1)), "curvature_limits"),
        (dict(curvature_limits=(-0.1, 2.5)), "curvature_limits"),
        (dict(curvature_limits=(0.1, np.inf)), "curvature_limits"),
        (dict(curvature_limits=0.1), "curvature_limits"),
        (dict(height_cutoff=0.0), "height_cutoff"),
        (dict(height_cutoff=-2.5), "height_cutoff"),
        (dict(sphere_model="jkr"), "sphere_model"),
        (dict(curvature_measure="gaussian"), "curvature_measure"),
        (dict(n_height=1), "n_height"),
        (dict(force_table=5), "force_table"),
        (dict(apparent_area=-1.0), "apparent_area"),
        (dict(distance=None, n_distance=1), "n_distance"),
        (dict(n_distance=50), "drop it"),
        (dict(distance=[0.0, np.nan]), "finite"),
        (dict(distance=[[0.0, 1e-9]]), "1-D"),
        (dict(distance=[1e-9, 1e-9]), "repeated"),
        (dict(relative_humidity=30), "between 0 and 1"),
    ],
)
def test_bad_arguments(kwargs, match):
    args = dict(relative_humidity=0.5, distance=[0.0, 1e-9])
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        rs.contact.gw_curves(S1, **args)


def test_bad_moment_containers():
    with pytest.raises(ValueError, match="'m4' is missing"):
        rs.contact.gw_curves(S1.drop_vars("m4"), relative_humidity=0.5, distance=[0.0])
    no_units = S1.copy()
    no_units["m0"].attrs = {}
    with pytest.raises(ValueError, match="no 'units'"):
        rs.contact.gw_curves(no_units, relative_humidity=0.5, distance=[0.0])
    wrong = S1.copy()
    wrong["m4"].attrs = {"units": "m"}
    with pytest.raises(ValueError, match="units 'm'"):
        rs.contact.gw_curves(wrong, relative_humidity=0.5, distance=[0.0])
    with pytest.raises(TypeError, match="moments must be"):
        rs.contact.gw_curves({"m0": 1.0}, relative_humidity=0.5, distance=[0.0])


def test_plot_gw_cutoff_study(cutoff_study):
    import matplotlib.pyplot as plt

    from roughstick.plotting import plot_gw_cutoff_study

    fig = plot_gw_cutoff_study(cutoff_study)
    assert len(fig.axes) == 3
    assert len(fig.axes[0].lines) == cutoff_study.sizes["height_cutoff"] + 1  # + zero line
    plt.close(fig)
    with pytest.raises(ValueError, match="height_cutoff"):
        plot_gw_cutoff_study(cutoff_study.isel(height_cutoff=0))


# --------------------------------------------------------------------------------------------
# automatic distance grid (distance=None)
# --------------------------------------------------------------------------------------------


def _map(family, rms=None, seed=1):
    h = rs.datasets.surface_family(family, shape=(64, 64), seed=seed)
    return h if rms is None else h * (rms / float(h.std()))


@pytest.mark.parametrize(
    "family, rms, rh",
    [("S1", None, [0.6]), ("S1", 10e-9, [0.9]), ("S1", None, [1e-6, 0.3, 0.9]),
     ("smooth", None, [0.3, 0.9]), ("rough", None, [0.5])],
)
def test_automatic_grid_spans_onset_to_repulsion(family, rms, rh):
    # GW's onset and equilibrium are set by the Gaussian tail of the summit heights, which
    # reaches above the map's highest pixel (S1 at RH 0.6: equilibrium ~7 sqrt(m0) against a
    # highest pixel at ~3 sqrt(m0)); the grid of the map's pixels ended in repulsion there
    h = _map(family, rms)
    area = h.size * 25e-18
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.contact.CurveGridWarning)
        c = rs.contact.gw_curves(h, relative_humidity=rh, apparent_area=area)
        s = rs.contact.summary(c)
    assert c.attrs["distance_grid"] == "automatic"
    d = c.distance.values
    assert np.all(np.diff(d) > 0)
    p = c.pressure.transpose("rh", "distance").values
    pull = s.pull_off_pressure.values
    assert np.all(pull > 0) and np.all(s.adhesive_energy.values > 0)
    assert np.all(np.isfinite(s.equilibrium_distance.values))
    # the top is where the pressure has vanished, the bottom is repulsive, below the equilibrium
    assert np.all(np.abs(p[:, -1]) <= 1e-4 * pull)
    assert np.all(p[:, 0] > 0) and np.all(s.equilibrium_distance.values > d[0])
    # the same as a dense grid spanning everything from all summits in contact to dry
    sigma = float(np.sqrt(rs.surface.roughness_moments(h).m0))
    top = 10.5 * sigma + float(rs.contact.water_height(max(rh)))
    ref = rs.contact.summary(rs.contact.gw_curves(
        h, relative_humidity=rh, apparent_area=area,
        distance=np.linspace(min(d[0], -2 * sigma), top, 4000)))
    np.testing.assert_allclose(s.adhesive_energy, ref.adhesive_energy, rtol=1e-2)
    np.testing.assert_allclose(s.pull_off_pressure, ref.pull_off_pressure, rtol=1e-2)
    np.testing.assert_allclose(s.equilibrium_distance, ref.equilibrium_distance, rtol=1e-3)


@pytest.mark.parametrize("kwargs", [dict(sphere_model="dmt"), dict(height_cutoff=2.5),
                                    dict(sphere_model="hertz")])
def test_automatic_grid_other_models_and_cutoff(kwargs):
    h = _map("S1")
    c = rs.contact.gw_curves(h, relative_humidity=[0.3, 0.9], n_distance=300, **kwargs)
    d, p = c.distance.values, c.pressure.transpose("rh", "distance").values
    assert d.size >= 300 and np.all(np.diff(d) > 0)
    assert np.all(p[:, -1] == pytest.approx(0.0, abs=1e-4 * np.abs(p).max()))
    assert np.all(p[:, 0] > 0)  # reaches contact
    if kwargs.get("height_cutoff"):  # nothing above the cutoff summits and their water
        sigma = float(np.sqrt(rs.surface.roughness_moments(h).m0))
        assert d[-1] <= 2.5 * sigma + float(rs.contact.water_height(0.9)) + 1e-12


def test_automatic_grid_needs_eager_moments():
    lazy = moments([15.7, 16.0], [0.04, 0.04], [5e-4, 5e-4], dims=("realization",)).chunk(
        {"realization": 1})
    with pytest.raises(ValueError, match="eager"):
        rs.contact.gw_curves(lazy, relative_humidity=0.5)
    both = rs.contact.gw_curves(lazy.compute(), relative_humidity=[0.5, 0.8])
    assert both.pressure.dims == ("realization", "rh", "distance")
    assert bool(np.isfinite(rs.contact.summary(both).equilibrium_distance).all())


def test_cutoff_study_on_one_automatic_grid():
    # every cutoff's curve on one shared grid (the union of their automatic grids)
    h = _map("S1")
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.contact.CurveGridWarning)
        st = rs.contact.gw_cutoff_study(h, relative_humidity=[0.3, 0.9], height_cutoffs=(2.5, None))
        s = rs.contact.summary(st)
    assert bool(np.isfinite(st.pressure).all()) and st.attrs["distance_grid"] == "automatic"
    assert bool((s.adhesive_energy > 0).all()) and bool(np.isfinite(s.equilibrium_distance).all())
    # a lower cutoff removes the highest summits: the equilibrium comes closer to the mean plane
    assert bool((s.equilibrium_distance.sel(height_cutoff=2.5)
                 < s.equilibrium_distance.sel(height_cutoff=np.inf)).all())


@pytest.mark.parametrize("rms, rh", [(None, [0.6]), (10e-9, [0.9])])
def test_rough_contact_curves_gw_uses_the_summit_grid(rms, rh):
    # through the dispatcher the GW curves used the modified DMT's pixel grid, which ended in
    # repulsion below GW's equilibrium: Γ = 0 and a NaN equilibrium, without a warning
    h = _map("S1", rms)
    with warnings.catch_warnings():
        warnings.simplefilter("error", rs.contact.CurveGridWarning)
        c = rs.contact.curves(h, relative_humidity=rh, model="gw")
        s = rs.contact.summary(c)
    assert c.attrs["distance_grid"] == "automatic"
    assert np.all(s.adhesive_energy.values > 0)
    assert np.all(np.isfinite(s.equilibrium_distance.values))
    direct = rs.contact.summary(rs.contact.gw_curves(h, relative_humidity=rh,
                                                      apparent_area=h.size * 25e-18))
    np.testing.assert_allclose(s.adhesive_energy, direct.adhesive_energy, rtol=1e-12)
