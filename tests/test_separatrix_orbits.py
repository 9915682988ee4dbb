"""Orbit functions of the signed distance to the separatrix (`meanfield.separatrix`) against
arbitrary-precision quadrature (mpmath) at |eta| = 1e-3, 1e-8, 1e-16, 1e-30, 1e-100 on both
sides: the offset J-bar - J-bar_s (the action integral (1/2 pi) oint p dtheta, subtracted in
high precision), the frequency pi sqrt(M0)/(2 K) or pi sqrt(M0) kappa/K with K by quadrature
(`_K_quad`, checked against the AGM), dOmega/dkappa by differentiating mpmath's K (AGM) at the
working precision, <cos theta> + 1 (the orbit average of cos(theta) over time), the Fourier
coefficients c_n and sigma_n (integrals over the angle of cos(theta(w)) and sin(theta(w)) with
the Jacobi functions), and the primitive of <cos theta> (the phase-space integral of cos(theta)
over the region the orbit encloses), hence the cell integrals of <cos theta>.

Bugs guarded against: J-bar - J-bar_s taken as a difference of J-bars (zero or noise below
|eta| ~ 1e-16), the complementary parameter formed as 1 - kappa^2, E - 1 from `ellipe` (0 next
to the separatrix), a series coefficient off, the sides of a formula swapped.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from hmfdiff.meanfield import separatrix
from hmfdiff.meanfield.fourier import cos_coefficient_eta, sin_coefficient_imag_eta

M0 = 0.7
DISTANCES = [1e-3, 1e-8, 1e-16, 1e-30, 1e-100]
ETAS = [-d for d in DISTANCES] + DISTANCES


def _prec(eta):
    """Decimal digits enough to hold 1 - m next to 1 for this eta, and 20 more."""
    return int(-np.log10(abs(eta))) + 40


def _orbit(eta):
    """(kappa, m, p, librating) in mpmath at the working precision."""
    eta = mp.mpf(eta)
    kappa = 1 + eta
    lib = eta < 0
    m = kappa**2 if lib else 1 / kappa**2
    return kappa, m, 1 - m, lib


def _K_quad(m):
    """K(m) = int_0^{pi/2} dphi / sqrt(cos^2 phi + (1 - m) sin^2 phi), the peak at pi/2 (width
    sqrt(1 - m)) resolved by points approaching it geometrically."""
    p = 1 - m
    pts = [mp.mpf(0)] + [
        mp.pi / 2 - mp.mpf(10) ** (-k) for k in range(0, int(-mp.log10(p) / 2) + 8)
    ]
    pts.append(mp.pi / 2)
    return mp.quad(lambda t: 1 / mp.sqrt(mp.cos(t) ** 2 + p * mp.sin(t) ** 2), pts)


def _offset_quad(eta):
    """J-bar - J-bar_s: librating J-bar = (4 sqrt(M0)/pi) m int cos^2 phi / Delta dphi
    (sin(theta/2) = kappa sin phi), rotating J-bar = (4 sqrt(M0)/pi) kappa int Delta dphi."""
    kappa, m, p, lib = _orbit(eta)
    c = 4 * mp.sqrt(M0) / mp.pi
    if lib:
        pts = [0] + [mp.pi / 2 - mp.mpf(10) ** (-k) for k in range(0, int(-mp.log10(p) / 2) + 8)]
        pts.append(mp.pi / 2)
        integral = mp.quad(lambda t: mp.cos(t) ** 2 / mp.sqrt(1 - m * mp.sin(t) ** 2), pts)
        return c * m * integral - c
    integral = mp.quad(lambda t: mp.sqrt(1 - m * mp.sin(t) ** 2), [0, mp.pi / 2])
    return c * (kappa * integral - 1)


def _cos_theta(eta):
    """cos(theta) and sin(theta) along the orbit as functions of u (the Jacobi argument), with
    the half period U of u and the angle w = pi u / U (librating: u = 2 K w / pi over w in
    [0, pi] spans [0, 2K]; rotating: u = K w / pi spans [0, K])."""
    kappa, m, p, lib = _orbit(eta)
    K = _K_quad(m)
    if lib:

        def cs(u):
            sn, dn = mp.ellipfun("sn", u, m=m), mp.ellipfun("dn", u, m=m)
            return 1 - 2 * m * sn**2, 2 * kappa * sn * dn

        return cs, 2 * K, K

    def cs(u):
        sn, cn = mp.ellipfun("sn", u, m=m), mp.ellipfun("cn", u, m=m)
        return 1 - 2 * sn**2, 2 * sn * cn

    return cs, K, K


def _transitions(U):
    """Subdivision of [0, U]: the orbit turns near u = 0 and u = U within O(1) in u."""
    inner = [mp.mpf(x) for x in (1, 3, 8, 20) if x < U / 2]
    return [mp.mpf(0)] + inner + [U / 2] + [U - x for x in reversed(inner)] + [U]


@pytest.mark.parametrize("eta", ETAS)
def test_offset_frequency_and_its_derivative(eta):
    with mp.workdps(_prec(eta)):
        kappa, m, p, lib = _orbit(eta)
        x = _offset_quad(eta)
        s = mp.sqrt(M0)

        def omega(e):
            k, mm, _, lb = _orbit(e)
            K = mp.ellipk(mm)  # arbitrary precision by the AGM (scipy's ellipkm1: a series)
            return mp.pi * s / (2 * K) if lb else mp.pi * s * k / K

        om = omega(mp.mpf(eta))
        K = _K_quad(m)
        assert abs(K / mp.ellipk(m) - 1) < mp.mpf(10) ** -30  # the two K agree
        h = mp.mpf(abs(eta)) * mp.mpf(10) ** -12
        dom = (omega(mp.mpf(eta) + h) - omega(mp.mpf(eta) - h)) / (2 * h)
    assert separatrix.jbar_offset(eta, M0) == pytest.approx(float(x), rel=1e-14)
    assert separatrix.frequency(eta, M0) == pytest.approx(float(om), rel=1e-14)
    assert separatrix.dOmega_deta(eta, M0) == pytest.approx(float(dom), rel=1e-9)
    assert separatrix.eta_from_jbar_offset(float(x), M0) == pytest.approx(eta, rel=1e-13)


@pytest.mark.parametrize("eta", ETAS)
def test_orbit_average_of_cos_theta_and_fourier_coefficients(eta):
    """<cos theta> + 1 = (1/U) int (1 + cos theta) du over a half period, and c_n, sigma_n as
    (1/U) int cos theta cos(n pi u / U) du, (1/U) int sin theta sin(n pi u / U) du."""
    with mp.workdps(_prec(eta)):
        cs_raw, U, K = _cos_theta(eta)
        memo = {}

        def cs(u):  # the seven integrals share tanh-sinh's nodes: each Jacobi pair once
            if u not in memo:
                memo[u] = cs_raw(u)
            return memo[u]

        pts = _transitions(U)
        avg1 = mp.quad(lambda u: 1 + cs(u)[0], pts) / U
        ns = (1, 2, 3)
        c = [mp.quad(lambda u, n=n: cs(u)[0] * mp.cos(n * mp.pi * u / U), pts) / U for n in ns]
        sg = [mp.quad(lambda u, n=n: cs(u)[1] * mp.sin(n * mp.pi * u / U), pts) / U for n in ns]
    assert separatrix.cos_average_plus_one(eta) == pytest.approx(float(avg1), rel=1e-13)
    c_code = cos_coefficient_eta(np.array(ns), eta)
    s_code = sin_coefficient_imag_eta(np.array(ns), eta)
    scale = float(max(abs(v) for v in c + sg))
    np.testing.assert_allclose(c_code, [float(v) for v in c], rtol=1e-12, atol=1e-14 * scale)
    np.testing.assert_allclose(s_code, [float(v) for v in sg], rtol=1e-12, atol=1e-14 * scale)


def _area_cos(eta):
    """int int cos(theta) dtheta dp over the region the orbit encloses (librating: inside it;
    rotating: between its two branches), minus the same for the separatrix (16 sqrt(M0)/3)."""
    kappa, m, p, lib = _orbit(eta)
    h = M0 * (2 * kappa**2 - 1)

    def integrand(t):
        return 2 * mp.sqrt(2 * (h + M0 * mp.cos(t))) * mp.cos(t)

    if lib:
        tm = 2 * mp.asin(kappa)
        val = mp.quad(integrand, [-tm, 0, tm])
    else:
        val = mp.quad(integrand, [-mp.pi, 0, mp.pi])
    return val - 16 * mp.sqrt(M0) / 3


@pytest.mark.parametrize("eta", ETAS)
def test_primitive_of_cos_theta_is_its_phase_space_integral(eta):
    """4 pi P(eta) = int int cos(theta) over the orbit's region minus the separatrix's: the
    phase-space volume per J-bar is 4 pi on both sides."""
    with mp.workdps(_prec(eta)):
        ref = _area_cos(eta) / (4 * mp.pi)
    assert separatrix.cos_primitive(eta, M0) == pytest.approx(float(ref), rel=1e-12)


@pytest.mark.parametrize(
    "a, b", [(-2e-3, -1e-3), (-1e-8, -1e-9), (-1e-29, -1e-31), (1e-100, 1e-90), (2e-3, 0.02)]
)
def test_cell_integral_of_cos_theta_against_quadrature(a, b):
    """int <cos theta> dJ-bar over a cell [a, b] in eta: the difference of the primitive
    against mpmath's quadrature of <cos theta>(eta) dJ-bar/deta in ln|eta| (closed forms with
    mpmath's own elliptic integrals), and the cell average lies between its ends' values."""
    with mp.workdps(_prec(min(abs(a), abs(b)))):
        s = mp.sqrt(M0)

        def integrand(u):
            e = mp.sign(a) * mp.exp(u)
            kappa, m, p, lib = _orbit(e)
            K, E = mp.ellipk(m), mp.ellipe(m)
            cos_avg = 2 * E / K - 1 if lib else 1 - 2 * kappa**2 * (1 - E / K)
            djde = 4 * s / mp.pi * (kappa * K if lib else K)
            return cos_avg * djde * abs(e)

        ua, ub = mp.log(abs(mp.mpf(a))), mp.log(abs(mp.mpf(b)))
        ref = mp.quad(integrand, mp.linspace(min(ua, ub), max(ua, ub), 8))
    code = separatrix.cos_primitive(b, M0) - separatrix.cos_primitive(a, M0)
    assert code == pytest.approx(float(ref), rel=1e-11)
    width = separatrix.jbar_offset(b, M0) - separatrix.jbar_offset(a, M0)
    ends = np.sort(separatrix.cos_average_plus_one(np.array([a, b])) - 1.0)
    assert ends[0] <= code / width <= ends[1]


def test_offsets_are_not_differences_of_jbar():
    """Below |eta| ~ 1e-17 J-bar itself rounds to J-bar_s; the offset keeps its digits and its
    leading asymptotic (4 sqrt(M0)/pi) |eta| (ln(4/sqrt(2|eta|)) + 1/2)."""
    eta = np.array([-1e-40, 1e-40])
    x = separatrix.jbar_offset(eta, M0)
    lead = 4 * np.sqrt(M0) / np.pi * 1e-40 * (np.log(4 / np.sqrt(2e-40)) + 0.5)
    np.testing.assert_allclose(np.abs(x), lead, rtol=1e-12)
    assert x[0] < 0 < x[1]
