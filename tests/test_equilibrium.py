"""Equilibrium states against direct quadrature in (theta, p), independent of the orbit
representation (and so a check of the factor 2 for the two directions of rotation)."""

import numpy as np
import pytest
from scipy import special

from hmfdiff.meanfield import equilibrium as eq


def phase_space_moments(f_energy, M0, n_theta=1024, n_p=6001, p_max=None):
    """int f, int cos(theta) f, int p^2/2 f over (theta, p): periodic trapezoid x Simpson."""
    from scipy.integrate import simpson

    p_max = p_max or 8.0
    theta = np.linspace(-np.pi, np.pi, n_theta, endpoint=False)
    p = np.linspace(-p_max, p_max, n_p)
    TH, P = np.meshgrid(theta, p, indexing="ij")
    f = f_energy(0.5 * P**2 - M0 * np.cos(TH))
    dth = 2 * np.pi / n_theta

    def integ(g):
        return simpson(g, x=p, axis=1).sum() * dth

    return integ(f), integ(np.cos(TH) * f), integ(0.5 * P**2 * f)


@pytest.mark.parametrize("M0", [1e-3, 0.05, 0.3, 0.7285, 0.9, 0.95, 0.999])
def test_thermal_beta_solves_bessel_self_consistency(M0):
    beta = eq.thermal_beta(M0)
    x = beta * M0
    # independent: orbit average over theta with the Boltzmann weight, by periodic trapezoid
    th = np.linspace(-np.pi, np.pi, 4096, endpoint=False)
    w = np.exp(x * (np.cos(th) - 1))
    assert np.sum(np.cos(th) * w) / np.sum(w) == pytest.approx(M0, rel=1e-12)
    assert special.iv(1, x) / special.iv(0, x) == pytest.approx(M0, rel=1e-12)


def test_thermal_limits():
    # M0 -> 0: beta -> 2 (+ M0^2); M0 -> 1: beta ~ 1/(2 (1 - M0))
    assert eq.thermal_beta(1e-3) == pytest.approx(2 + 1e-6, rel=1e-8)
    assert eq.thermal_beta(0.999) * 2 * (1 - 0.999) == pytest.approx(1.0, rel=2e-3)


@pytest.mark.parametrize(
    "u,M0_paper,digits",
    [(-0.1, 0.7285, 4), (-0.1, 0.728, 3), (0.2475, 0.0632, 4), (-0.2, 0.816, 3), (0.0, 0.622, 3)],
)
def test_paper_state_pairs_are_reproduced(u, M0_paper, digits):
    """The (u, M0) pairs of figs. 5, 6, 9 with u = 1/(2 beta) - M0^2/2 (no +1/2 in H)."""
    M0 = eq.thermal_M0_from_energy(u)
    assert round(M0, digits) == pytest.approx(M0_paper, abs=0.5 * 10**-digits + 1e-12)
    assert eq.thermal_energy(M0) == pytest.approx(u, abs=1e-12)


@pytest.mark.parametrize("M0", [0.0632, 0.622, 0.9])
def test_thermal_f_normalisation_magnetisation_energy_direct(M0):
    s = eq.ThermalState(M0=M0)
    n, m, k = phase_space_moments(s.f_energy, M0)
    assert n == pytest.approx(1.0, rel=1e-9)
    assert m == pytest.approx(M0, rel=1e-9)
    assert k - 0.5 * M0**2 == pytest.approx(s.u, rel=1e-8)  # u = <p^2>/2 - M0^2/2
    # and the orbit quadrature (both directions of rotation counted) agrees
    q = s.quadrature()
    assert q.integrate(s.f(q.kappa)) == pytest.approx(1.0, rel=1e-12)


def test_thermal_dfdkappa_is_derivative():
    s = eq.ThermalState(u=-0.1)
    k = np.linspace(0.05, 2.5, 9)
    d = 1e-6
    np.testing.assert_allclose(s.dfdkappa(k), (s.f(k + d) - s.f(k - d)) / (2 * d), rtol=1e-7)


def test_core_halo_dfdkappa_is_derivative():
    """df/dkappa = 4 M0 kappa df/dh of the core-halo state (h = M0 (2 kappa^2 - 1)) against
    central differences of f(kappa), across both Fermi edges of ch2*: the derivative feeds the
    dielectric tensor and the diffusion currents (a 2 for the 4 halves it)."""
    s = eq.CoreHaloState(0.298, 0.051, -0.517, 0.19, 30.0, 10.0)
    k = np.linspace(0.05, 2.0, 40)
    d = 1e-6
    fd = (s.f(k + d) - s.f(k - d)) / (2 * d)
    np.testing.assert_allclose(s.dfdkappa(k), fd, rtol=1e-6, atol=1e-9 * np.abs(fd).max())


@pytest.mark.parametrize("params,M0_expected", [((0.298, 0.051, -0.517, 0.19, 30.0, 10.0), 0.8)])
def test_core_halo_self_consistent_direct(params, M0_expected):
    """ch2*: the paper says M0 = 0.8; check self-consistency and normalisation directly."""
    s = eq.CoreHaloState(*params)
    assert s.M0 == pytest.approx(M0_expected, abs=1e-3)
    n, m, k = phase_space_moments(s.f_energy, s.M0, n_theta=2048, n_p=12001, p_max=4.0)
    assert n == pytest.approx(1.0, rel=1e-6)
    assert m == pytest.approx(s.M0, rel=1e-6)
    assert k - 0.5 * s.M0**2 == pytest.approx(s.u, rel=1e-6)
    # the paper's parameters give a raw mass close to (but not exactly) one
    assert s.mass == pytest.approx(1.0, abs=2e-3)


def test_two_step_state():
    s = eq.CoreHaloState(0.298, 0.05, -0.517, 0.19, shape="step")
    n, m, _ = phase_space_moments(s.f_energy, s.M0, n_theta=2048, n_p=40001, p_max=2.0)
    assert n == pytest.approx(1.0, rel=1e-4)  # steps resolved by the grid only to ~1e-4
    assert m == pytest.approx(s.M0, rel=1e-4)
    # steps at kappa_i = sqrt((mu_i/M0 + 1)/2), where h = mu_i
    h = s.M0 * (2 * s.step_kappas**2 - 1)
    np.testing.assert_allclose(h, [-0.517, 0.19], rtol=1e-12)


@pytest.mark.parametrize(
    "kwargs,match",
    [
        ({"M0": 1.2}, "M0 = 1.2 is outside the allowed range 0 < M0 < 1"),
        ({"M0": 0.0}, "outside the allowed range"),
        ({"M0": 1.0}, "outside the allowed range"),  # |M| = 1: every particle at theta = 0
        ({"u": 0.3}, "u = 0.3 has no magnetised thermal state"),
        ({"u": -0.6}, "allowed range"),
        ({"M0": 0.5, "u": 0.0}, "exactly one of M0 or u"),
    ],
)
def test_thermal_bad_input(kwargs, match):
    with pytest.raises(eq.EquilibriumError, match=match):
        eq.ThermalState(**kwargs)


@pytest.mark.parametrize(
    "args,match",
    [
        ((0.298, 0.051, -0.517, 0.19, -30.0, 10.0), "beta1 = -30.0 must be > 0"),
        ((-0.1, 0.051, -0.517, 0.19, 30.0, 10.0), "eta1 = -0.1 must be >= 0"),
        ((0.298, 0.051, -1.5, 0.19, 30.0, 10.0), "mu1 = -1.5 must be > -1"),
    ],
)
def test_core_halo_bad_input(args, match):
    with pytest.raises(eq.EquilibriumError, match=match):
        eq.CoreHaloState(*args)
