"""Separatrix values of the action-angle map (`meanfield.orbits`) against the separatrix orbit
itself: p = 2 sqrt(M0) cos(theta/2) (h = M0), whose area is 16 sqrt(M0), so that
(1/2 pi) oint p dtheta is 8 sqrt(M0)/pi for the librating torus that encloses the whole
separatrix and 4 sqrt(M0)/pi for one rotating torus (half the area, one direction).

Bugs guarded against: the sides of `action_separatrix` swapped, J-bar at kappa = 1 taken as
J/2 (the librating rule) so that J-bar jumps there, and the range check of the rotating
`kappa_from_action` never firing (a J below the separatrix value then returns kappa = 1
silently instead of raising).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import action_by_quadrature
from scipy import integrate

from hmfdiff.meanfield import orbits

M0 = 0.55


def _separatrix_area():
    """int_{-pi}^{pi} 2 p_sep dtheta, both branches p = +-2 sqrt(M0) cos(theta/2)."""
    val = integrate.quad(lambda t: 2.0 * np.sqrt(M0) * np.cos(t / 2.0), -np.pi, np.pi)[0]
    return 2.0 * val


def test_action_on_either_side_of_the_separatrix():
    """action_separatrix(side=-1) = area/(2 pi) (librating), side=+1 = area/(4 pi) (rotating);
    and both are the limits of J(kappa) from below and above (J - J_sep ~ (1 - kappa^2)
    log(1 - kappa): 2e-8 relative at 1 -+ 1e-9)."""
    area = _separatrix_area()
    assert area == pytest.approx(16.0 * np.sqrt(M0), rel=1e-12)
    assert orbits.action_separatrix(M0, -1) == pytest.approx(area / (2 * np.pi), rel=1e-12)
    assert orbits.action_separatrix(M0, +1) == pytest.approx(area / (4 * np.pi), rel=1e-12)
    assert orbits.action(1.0 - 1e-9, M0) == pytest.approx(area / (2 * np.pi), rel=1e-6)
    assert orbits.action(1.0 + 1e-9, M0) == pytest.approx(area / (4 * np.pi), rel=1e-6)


def test_rescaled_action_is_continuous_through_kappa_one():
    """J-bar(1) = 4 sqrt(M0)/pi = area/(4 pi), equal to J-bar just below (J/2) and above (J);
    and computed without a floating-point warning (the librating branch is not evaluated at
    kappa = 1, where it would be inf - inf)."""
    with np.errstate(all="raise"):
        jb = orbits.rescaled_action(np.array([1.0 - 1e-9, 1.0, 1.0 + 1e-9]), M0)
    np.testing.assert_allclose(jb, _separatrix_area() / (4 * np.pi), rtol=1e-6)
    assert orbits.jbar_separatrix(M0) == pytest.approx(_separatrix_area() / (4 * np.pi))


def test_rotating_action_below_the_separatrix_value_is_refused():
    """No rotating torus has J < 4 sqrt(M0)/pi; 0.9 of it must raise, 1.001 of it is accepted."""
    Jsep = _separatrix_area() / (4 * np.pi)
    with pytest.raises(ValueError, match="rotating action"):
        orbits.kappa_from_action(0.9 * Jsep, M0, "rotation")
    k = orbits.kappa_from_action(1.001 * Jsep, M0, "rotation")
    assert k > 1.0 and orbits.action(k, M0) == pytest.approx(1.001 * Jsep, rel=1e-10)


def _jbar_quadrature(kappa):
    """J-bar from (1/2 pi) oint p dtheta: J/2 on librating orbits, J on rotating ones."""
    J = action_by_quadrature(kappa, M0)
    return J / 2.0 if kappa < 1.0 else J


def test_kappa_from_rescaled_action_inverts_the_orbit_quadrature():
    """kappa_from_rescaled_action(J-bar) returns the kappa whose orbit has that J-bar, with
    J-bar from quadrature of p(theta) (librating J = 2 J-bar); guards the inversion solving
    J = J-bar on librating orbits.  Agreement measured 1e-15; tolerance 1e-9."""
    kappa = np.array([0.1, 0.5, 0.9, 0.999, 1.001, 1.2, 2.5])
    jbar = np.array([_jbar_quadrature(k) for k in kappa])
    np.testing.assert_allclose(orbits.kappa_from_rescaled_action(jbar, M0), kappa, rtol=1e-9)


def test_kappa_grid_is_densest_at_the_separatrix_on_both_sides():
    """kappa_grid's documented contract: half the points on (0, 1 - gap], half on
    [1 + gap, kappa_max], spacing shrinking towards kappa = 1 on both sides (a uniform rotating
    half would put as many points at kappa = 3 as beside the separatrix)."""
    g = orbits.kappa_grid(40, 3.0, gap=1e-6)
    lib, rot = g[:20], g[20:]
    assert lib[-1] == pytest.approx(1 - 1e-6) and rot[0] == pytest.approx(1 + 1e-6)
    assert rot[-1] == pytest.approx(3.0)
    dl, dr = np.diff(lib), np.diff(rot)
    assert np.all(np.diff(dl) < 0) and np.all(np.diff(dr) > 0)
    assert dr[0] < 0.1 * dr[-1] and dl[-1] < 0.1 * dl[0]


def test_kappa_from_energy_agrees_with_the_phase_space_label():
    """kappa_from_energy(p^2/2 - M0 cos theta) is the kappa that `angle_action` assigns to the
    point (theta, p) from p^2/(4 M0) + sin^2(theta/2) (an independent expression); guards a lost
    factor 2 in (h + M0)/(2 M0).  Agreement measured 1e-16; tolerance 1e-12."""
    theta = np.array([0.3, -1.2, 2.0, 3.0, 0.0])
    p = np.array([0.1, 0.8, -1.5, 2.2, 0.4])
    h = p**2 / 2 - M0 * np.cos(theta)
    kappa, _, _ = orbits.angle_action(theta, p, M0)
    np.testing.assert_allclose(orbits.kappa_from_energy(h, M0), kappa, rtol=1e-12)
