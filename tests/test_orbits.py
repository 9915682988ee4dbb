"""Action-angle variables against quadrature and numerically integrated pendulum orbits."""

import numpy as np
import pytest
from conftest import integrate_orbit
from scipy.integrate import quad

from hmfdiff.meanfield import orbits

M0 = 0.7
KAPPAS = [0.01, 0.2, 0.5, 0.8, 0.95, 0.999, 1.001, 1.05, 1.5, 3.0, 20.0]


def action_by_quadrature(kappa, M0):
    """J = (1/2pi) oint p dtheta, integrated directly over theta."""
    h = orbits.energy_from_kappa(kappa, M0)
    p = lambda th: np.sqrt(max(2.0 * (h + M0 * np.cos(th)), 0.0))  # noqa: E731
    if kappa < 1:
        thm = np.arccos(1.0 - 2.0 * kappa**2)
        return 2.0 * quad(p, -thm, thm, epsabs=1e-14, epsrel=1e-13, limit=200)[0] / (2 * np.pi)
    return quad(p, -np.pi, np.pi, epsabs=1e-14, epsrel=1e-13, limit=200)[0] / (2 * np.pi)


@pytest.mark.parametrize("kappa", KAPPAS)
def test_action_matches_quadrature(kappa):
    assert orbits.action(kappa, M0) == pytest.approx(action_by_quadrature(kappa, M0), rel=1e-9)


@pytest.mark.parametrize("kappa", [0.05, 0.5, 0.9, 0.99, 1.01, 1.2, 2.5])
def test_frequency_matches_integrated_period(kappa):
    period = integrate_orbit(kappa, M0)
    assert orbits.frequency(kappa, M0) == pytest.approx(2 * np.pi / period, rel=1e-9)


@pytest.mark.parametrize("kappa", [0.05, 0.5, 0.95, 1.05, 2.0, 10.0])
def test_derivatives_match_finite_differences_of_quadrature(kappa):
    d = 1e-5 * kappa
    dJ = (action_by_quadrature(kappa + d, M0) - action_by_quadrature(kappa - d, M0)) / (2 * d)
    assert orbits.dJ_dkappa(kappa, M0) == pytest.approx(dJ, rel=1e-6)
    # Omega = dh/dJ with dh/dkappa = 4 M0 kappa
    assert orbits.frequency(kappa, M0) == pytest.approx(4 * M0 * kappa / dJ, rel=1e-6)
    dOm = (orbits.frequency(kappa + d, M0) - orbits.frequency(kappa - d, M0)) / (2 * d)
    assert orbits.dOmega_dkappa(kappa, M0) == pytest.approx(dOm, rel=1e-6)


def test_small_kappa_limits():
    k = np.array([1e-6, 1e-4, 1e-3])
    # J ~ 2 sqrt(M0) kappa^2, Omega ~ sqrt(M0)(1 - kappa^2/4), dOmega/dkappa ~ -sqrt(M0) kappa/2
    np.testing.assert_allclose(orbits.action(k, M0), 2 * np.sqrt(M0) * k**2, rtol=1e-5)
    np.testing.assert_allclose(orbits.frequency(k, M0), np.sqrt(M0) * (1 - k**2 / 4), rtol=1e-12)
    np.testing.assert_allclose(orbits.dOmega_dkappa(k, M0), -np.sqrt(M0) * k / 2, rtol=1e-5)


def test_separatrix_is_finite_on_both_sides_and_J_jumps():
    eps = np.array([1e-12, 1e-9, 1e-6])
    for k in (1 - eps, 1 + eps):
        for fn in (orbits.action, orbits.frequency, orbits.dJ_dkappa, orbits.dOmega_dkappa):
            assert np.all(np.isfinite(fn(k, M0)))
    s = np.sqrt(M0)
    assert orbits.action(1 - 1e-12, M0) == pytest.approx(8 * s / np.pi, rel=1e-9)
    assert orbits.action(1 + 1e-12, M0) == pytest.approx(4 * s / np.pi, rel=1e-9)
    # Omega -> 0 logarithmically: K(k) ~ ln(4/k') as k' = sqrt(1 - k^2) -> 0
    kp = np.sqrt(1 - (1 - 1e-12) ** 2)
    assert orbits.frequency(1 - 1e-12, M0) == pytest.approx(
        np.pi * s / (2 * np.log(4 / kp)), rel=1e-6
    )
    assert orbits.frequency(1 + 1e-12, M0) < orbits.frequency(1 + 1e-6, M0) < s
    # J-bar is continuous across the separatrix
    assert orbits.rescaled_action(1 - 1e-12, M0) == pytest.approx(
        orbits.rescaled_action(1 + 1e-12, M0), rel=1e-9
    )


def test_large_kappa_free_rotation():
    # kappa >> 1: p ~ 2 sqrt(M0) kappa, J ~ p, Omega ~ p
    k = 1e3
    assert orbits.action(k, M0) == pytest.approx(2 * np.sqrt(M0) * k, rel=1e-6)
    assert orbits.frequency(k, M0) == pytest.approx(2 * np.sqrt(M0) * k, rel=1e-6)


@pytest.mark.parametrize(
    "kappa,sign", [(0.3, 1), (0.9, 1), (0.999, 1), (1.02, 1), (1.02, -1), (2.0, 1), (2.0, -1)]
)
def test_phase_point_follows_integrated_orbit(kappa, sign):
    """theta(w), p(w) at w = Omega t reproduce the orbit integrated from w = 0."""
    period, t, theta, p = integrate_orbit(kappa, M0, sign=sign, n_samples=64)
    w = 2 * np.pi * t / period
    th2, p2 = orbits.phase_point(w, kappa, M0, sign)
    np.testing.assert_allclose(np.angle(np.exp(1j * (th2 - theta))), 0.0, atol=2e-8)
    np.testing.assert_allclose(p2, p, atol=2e-8)
    kap, w3, s3 = orbits.angle_action(theta, p, M0)
    np.testing.assert_allclose(kap, kappa, rtol=1e-9)
    np.testing.assert_allclose(np.angle(np.exp(1j * (w3 - w))), 0.0, atol=2e-8)
    assert np.all(s3 == (1.0 if kappa < 1 else sign))


def test_angle_action_round_trip_random_points():
    rng = np.random.default_rng(3)
    theta = rng.uniform(-np.pi, np.pi, 20000)
    p = rng.normal(0, 1.5, 20000)
    kappa, w, sign = orbits.angle_action(theta, p, M0)
    th2, p2 = orbits.phase_point(w, kappa, M0, sign)
    np.testing.assert_allclose(np.angle(np.exp(1j * (th2 - theta))), 0.0, atol=1e-9)
    np.testing.assert_allclose(p2, p, atol=1e-9)


@pytest.mark.parametrize(
    "family,kappa",
    [
        ("libration", np.array([1e-3, 0.3, 0.9, 0.999999])),
        ("rotation", np.array([1.000001, 1.1, 4.0, 50.0])),
    ],
)
def test_kappa_from_action_inverts_action(family, kappa):
    J = orbits.action(kappa, M0)
    np.testing.assert_allclose(orbits.kappa_from_action(J, M0, family), kappa, rtol=1e-10)


def test_kappa_from_frequency_inverts_frequency():
    s = np.sqrt(M0)
    # (below ~0.4 Omega_0 the rotating root lies within 1e-8 of kappa = 1, where one ulp of kappa
    # moves Omega by ~1e-9 relative: a representation limit, not an error of the solver)
    om = np.array([0.5, 0.8, 0.99]) * s
    k1 = orbits.kappa_from_frequency(om, M0, "libration")
    k2 = orbits.kappa_from_frequency(om, M0, "rotation")
    assert np.all(k1 < 1) and np.all(k2 > 1)
    np.testing.assert_allclose(orbits.frequency(k1, M0), om, rtol=1e-10)
    np.testing.assert_allclose(orbits.frequency(k2, M0), om, rtol=1e-10)
    assert np.isnan(orbits.kappa_from_frequency(1.5 * s, M0, "libration"))


@pytest.mark.parametrize("librating", [True, False])
def test_inverse_frequency_slope_is_the_derivative_of_its_value(librating):
    """The Newton iteration of kappa_from_frequency steps with d ln F/dt of
    `_log_inverse_frequency`: against a central difference of its ln F, over the whole range
    of t = ln(m1/m) (a wrong slope would leave the iteration to its bisection fallback)."""
    t = np.linspace(-60.0, 30.0, 181)
    h = 1e-5
    _, slope = orbits._log_inverse_frequency(t, librating)
    up, _ = orbits._log_inverse_frequency(t + h, librating)
    down, _ = orbits._log_inverse_frequency(t - h, librating)
    np.testing.assert_allclose(slope, (up - down) / (2.0 * h), rtol=1e-6, atol=1e-10)


@pytest.mark.parametrize("family", ["libration", "rotation"])
def test_kappa_from_frequency_roots_over_the_whole_family(family, monkeypatch):
    """Omega(kappa(omega)) = omega to what the representation of kappa allows, from next to the
    separatrix (|kappa - 1| ~ 1e-13 to 1e-15) to the bottom of the well or far out
    on rotation, agreeing with bisection of the same equation to the inverse's conditioning;
    the Newton iteration solves all of them (none left to its fallback)."""
    s = np.sqrt(M0)
    if family == "libration":
        om = s * np.concatenate([np.geomspace(0.1, 0.99, 400), 1.0 - np.geomspace(1e-3, 1e-9, 5)])
        lo, hi = 0.0, 1.0
        fun = lambda k: -orbits.frequency(k, M0)  # noqa: E731
        target = -om
    else:
        om = s * np.geomspace(0.2, 1e3, 400)  # below ~0.16 Omega_0 kappa - 1 < 1e-16
        lo, hi = 1.0, om / s + 2.0
        fun = lambda k: orbits.frequency(k, M0)  # noqa: E731
        target = om
    ref = orbits._bisect(fun, target, lo, hi)
    fallback = []
    monkeypatch.setattr(orbits, "_bisect", lambda *a, **kw: fallback.append(a) or a[2])
    k = orbits.kappa_from_frequency(om, M0, family)
    assert not fallback  # every root found by the Newton iteration
    # one ulp of kappa moves Omega by |dOmega/dkappa| ulp(kappa): beside the separatrix far
    # more than one ulp of Omega
    slack = np.abs(orbits.dOmega_dkappa(k, M0)) * np.spacing(k)
    assert np.all(np.abs(orbits.frequency(k, M0) - om) <= 8 * np.spacing(om) + 2 * slack)
    # relative conditioning of kappa(omega): |d ln kappa / d ln omega|
    cond = np.abs(om / (k * orbits.dOmega_dkappa(k, M0)))
    assert np.all(np.abs(k / ref - 1.0) <= 2e-15 * np.maximum(cond, 1.0))


def test_bad_inputs_raise():
    with pytest.raises(ValueError, match="librating action"):
        orbits.kappa_from_action(10.0, M0, "libration")
    with pytest.raises(ValueError, match="family"):
        orbits.kappa_from_action(1.0, M0, "both")
