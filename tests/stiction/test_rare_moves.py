"""Tests of the shell-direction move of subset simulation (``proposal="shell"``, issue 15)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.fft
import xarray as xr
from scipy.stats import chi2, kstest, norm

import roughstick as rs
from roughstick.stiction import _rare_moves as _m
from roughstick.stiction import _rare_surface as _s
from roughstick.stiction import rare_events as re_

pytestmark = pytest.mark.filterwarnings("ignore::roughstick.ValidityWarning")

SHAPES = [(16, 16), (15, 12), (12, 9), (9, 14)]


def labels_of(shape, spacing=20e-9):
    return _s.NoiseToSurface(rs.datasets.family_psd("table4"), shape=shape, spacing=spacing).shell_labels


def project(z, labels, g):
    """Component of z in shell g, computed in pixel space (independent of the move's norms)."""
    spec = scipy.fft.rfft2(z, norm="ortho")
    return scipy.fft.irfft2(np.where(labels == g, spec, 0), s=z.shape, norm="ortho")


@pytest.mark.parametrize("shape", SHAPES)
def test_shells_hold_modes_of_one_amplitude_and_hermitian_partners(shape):
    f = _s.NoiseToSurface(rs.datasets.family_psd("table4"), shape=shape, spacing=20e-9)
    lab, amp = f.shell_labels, f.amplitude
    assert lab.max() >= 2 and np.all((lab >= 0) == (amp > 0))
    for g in range(lab.max() + 1):
        a = amp[lab == g]
        assert a.max() - a.min() <= 1e-9 * a.max()
    ny, nx = shape
    cols = [0] + ([nx // 2] if nx % 2 == 0 else [])
    for c in cols:  # (ky, c) and (-ky, c) are conjugate partners stored in the same column
        assert np.array_equal(lab[:, c], lab[(-np.arange(ny)) % ny, c])


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("sigma", [1.0, 0.3])
def test_shell_move_keeps_every_shell_norm_and_moves_the_direction(shape, sigma):
    lab = labels_of(shape)
    rng = np.random.default_rng(3)
    z = rng.standard_normal(shape)
    z1 = _m.ShellMove(lab, shape, sigma)(z, rng)
    assert z1.shape == shape and np.isrealobj(z1)
    for g in range(lab.max() + 1):
        a, b = project(z, lab, g), project(z1, lab, g)
        assert math.isclose(np.sum(a * a), np.sum(b * b), rel_tol=1e-10)
        if np.sum(_m._weights(*shape, shape[1] // 2 + 1)[lab == g]) > 1:  # 1-D shell: a sign flip or not
            assert np.linalg.norm(a - b) > 1e-3 * np.linalg.norm(a)
    rest = z - sum(project(z, lab, g) for g in range(lab.max() + 1))
    rest1 = z1 - sum(project(z1, lab, g) for g in range(lab.max() + 1))
    np.testing.assert_allclose(rest1, rest, atol=1e-12)  # modes of no shell are untouched


def test_radius_and_one_shell_variants():
    """mode="radius" keeps each shell's direction (new norm); one_of=K moves one shell only."""
    shape = (16, 16)
    lab = labels_of(shape)
    rng = np.random.default_rng(5)
    z = rng.standard_normal(shape)
    z1 = _m.ShellMove(lab, shape, 0.5, mode="radius")(z, rng)
    z2 = _m.ShellMove(lab, shape, 1.0, one_of=3)(z, rng)
    moved = 0
    for g in range(lab.max() + 1):
        a, b, c = project(z, lab, g), project(z1, lab, g), project(z2, lab, g)
        k = np.sum(a * b) / np.sum(a * a)
        assert k > 0 and np.allclose(b, k * a, atol=1e-12)
        moved += not np.allclose(c, a, atol=1e-12)
        assert math.isclose(np.sum(c * c), np.sum(a * a), rel_tol=1e-10)
    assert moved == 1


@pytest.mark.parametrize(("shape", "sigma", "mode", "one_of"), [
    ((16, 16), 1.0, "direction", None), ((16, 16), 0.3, "direction", None), ((15, 12), 1.0, "direction", None),
    ((15, 12), 0.3, "direction", None), ((16, 16), 0.5, "radius", None), ((15, 12), 1.0, "radius", None),
    ((16, 16), 1.0, "direction", 4)])
def test_shell_move_leaves_the_prior_invariant_and_is_reversible(shape, sigma, mode, one_of):
    """z ~ N(0, I) -> z' = move(z): z' is N(0, I) again (per-coordinate mean/variance, a KS test,
    the empirical covariance), and (z, z') is exchangeable: E[z z'^T] is symmetric (a reversible
    kernel; a fixed rotation inside a shell would keep the prior but fail this)."""
    lab = labels_of(shape)
    n = 4000
    rng = np.random.default_rng(11)
    move = _m.ShellMove(lab, shape, sigma, mode=mode, one_of=one_of)
    z = rng.standard_normal((n,) + shape)
    z1 = np.stack([move(zi, rng) for zi in z])
    a, b = z.reshape(n, -1), z1.reshape(n, -1)
    se = 1 / math.sqrt(n)
    assert np.max(np.abs(b.mean(axis=0))) < 5 * se
    assert np.max(np.abs(b.var(axis=0) - 1)) < 5 * math.sqrt(2) * se
    assert kstest(b[:, 5], norm.cdf).pvalue > 1e-3
    cov = b.T @ b / n
    assert np.max(np.abs(cov - np.eye(cov.shape[0]))) < 6 * math.sqrt(2) * se
    assert np.max(np.abs(asymmetry(a, b))) < 6 * math.sqrt(2) * se
    assert np.abs(np.trace(a.T @ b / n) / a.shape[1] - 1) > 0.005  # the move moved
    dims = np.bincount(lab[lab >= 0], weights=_m._weights(*shape, shape[1] // 2 + 1)[lab >= 0])
    energies = np.array([_m.shell_energies(zi, lab) for zi in z1])
    pvalues = [kstest(energies[:, g], chi2(dims[g]).cdf).pvalue for g in range(dims.size)]
    assert min(pvalues) > 1e-3 / dims.size  # each shell's squared norm stays chi2 (Bonferroni)
    # the same check catches a move that keeps the prior but is not reversible: a quarter turn of
    # the interior Fourier coefficients (orthogonal, so N(0, I) is kept)
    quarter = [scipy.fft.irfft2(_quarter_turn(scipy.fft.rfft2(zi, norm="ortho"), shape[1]), s=shape,
                                norm="ortho") for zi in z[:1000]]
    assert np.max(np.abs(asymmetry(a[:1000], np.reshape(quarter, (1000, -1))))) > 20 / math.sqrt(1000)


def asymmetry(a, b):
    cross = a.T @ b / a.shape[0]
    return cross - cross.T


def _quarter_turn(spec, nx):
    out = spec.copy()
    last = nx // 2 if nx % 2 == 0 else nx // 2 + 1
    out[:, 1:last] *= 1j
    return out


class LinearWithShells:
    """Exact limit state P(Y > beta) = Phi(-beta) on a 2-D noise with the shells of a PSD."""

    def __init__(self, shape):
        self.shell_labels = labels_of(shape)
        a = np.random.default_rng(0).standard_normal(shape)
        self.a = a / np.linalg.norm(a)

    def __call__(self, z):
        return float(np.sum(self.a * z))


def test_shell_proposal_against_exact_linear_limit_state():
    """Indicator acceptance with the alternating moves: mean of 20 runs at P = 1e-3 within 3
    standard errors of the exact value."""
    shape, beta = (16, 16), 3.09
    ps = np.array([float(re_.subset_simulation(LinearWithShells(shape), noise_shape=shape, threshold=beta,
                                               seed=s, samples_per_level=500, proposal="shell",
                                               scheduler="sync").failure_probability)
                   for s in range(20)])
    assert abs(ps.mean() - norm.sf(beta)) < 3 * ps.std(ddof=1) / math.sqrt(ps.size)


def test_shell_proposal_needs_shells_and_is_bit_identical_across_chunks():
    with pytest.raises(ValueError, match="shell_labels"):
        re_.subset_simulation(lambda z: float(z.sum()), noise_shape=(4, 4), threshold=1.0, proposal="shell")
    kw = dict(threshold=0.02, relative_humidity=0.5, shape=(48, 48), spacing=5e-9, seed=2,
              samples_per_level=50, proposal="shell")
    a = re_.failure_probability(rs.datasets.family_psd("table4"), chunks=1, scheduler="sync", **kw)
    b = re_.failure_probability(rs.datasets.family_psd("table4"), chunks=13, scheduler="threads", **kw)
    xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())
    assert a.sizes["level"] >= 2 and a.attrs["proposal"] == "shell"
