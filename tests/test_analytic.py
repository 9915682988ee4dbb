"""Tests of the paper's closed forms (kinetic.analytic) against independent computations.

Independent ingredients used here (none of them goes through the closed forms under test):
* c_n, sigma_n by FFT of cos(theta(w)), sin(theta(w)) along the orbit (orbits.phase_point,
  Jacobi elliptic functions), not through the nome formulas of hmfdiff.meanfield.fourier;
* dJ/dkappa and dOmega/dkappa by central finite differences of orbits.action / .frequency;
* the general dielectric formula eps = 1 + 2 pi sum_l int W X_l^2 f'/(Omega - omega/l) evaluated
  by adaptive quadrature with QUADPACK's Cauchy (principal value) weight around each pole,
  written here from the definition;
* the appendix-C definitions integrated in kappa with the Cauchy weight (the closed forms use
  x = kappa^2 and exponential integrals).
Measured agreements are quoted in each test's docstring.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate

from hmfdiff.kinetic import analytic as A
from hmfdiff.meanfield import orbits
from hmfdiff.meanfield.equilibrium import CoreHaloState, ThermalState
from hmfdiff.meanfield.fourier import cos_coefficient, sin_coefficient_imag

CH = (0.298, 0.051, -0.517, 0.19)  # eta1, eta2, mu1, mu2 of the paper's ch* states


# ----------------------------------------------------------------------------- helpers
def fft_coefficients(kappa, M0, n_max, npts=1024):
    """(c_n, sigma_n) for n = 0..n_max by FFT of the orbit theta(w) (s_n = -i sigma_n)."""
    w = 2.0 * np.pi * np.arange(npts) / npts
    theta, _ = orbits.phase_point(w, kappa, M0)
    c = np.fft.fft(np.cos(theta)) / npts
    s = np.fft.fft(np.sin(theta)) / npts
    return c.real[: n_max + 1], (1j * s)[: n_max + 1].real


def fd(fun, x, h=1e-5):
    return (fun(x + h) - fun(x - h)) / (2.0 * h)


def general_resonant_term(kappa, state, n, which="D"):
    """N D (or N D_pol) of the n = n' and -n = -n' terms at kappa* = kappa, eps = 1, built
    from FFT coefficients and finite-difference derivatives."""
    M0 = state.M0
    c, s = fft_coefficients(kappa, M0, n)
    dJ = fd(lambda k: orbits.action(k, M0), kappa)
    dO = abs(fd(lambda k: orbits.frequency(k, M0), kappa))
    coupling = c[n] ** 4 + s[n] ** 4
    if which == "D":
        return 2 * 2.0 * np.pi**2 * n**2 * dJ * float(state.f(kappa)) / (n * dO) * coupling
    return 2 * 2.0 * np.pi**2 * n * n * float(state.dfdkappa(kappa)) / (n * dO) * coupling


def general_eps_quadrature(state, omega, l_max, points=(), panels=200, order=16):
    """eps_cc, eps_ss from the general definition (eq. hmfepscc/hmfepsss with W, omega + i0).

    Composite Gauss-Legendre in kappa on [0, 1] and [1, kappa_max] (panels graded towards the
    separatrix, with edges at `points` and at the pole).  Where omega/l is a frequency of the
    branch, the pole is subtracted: PV int g/(Omega - x0) = int [g/(Omega - x0)
    - G0/(kappa - kappa_p)] + G0 log|(b - kappa_p)/(a - kappa_p)|, G0 = g(kappa_p)/Omega'(kappa_p),
    and the imaginary part + i pi sign(l) g(kappa_p)/|Omega'(kappa_p)| is added.
    """
    M0 = state.M0
    x, wx = np.polynomial.legendre.leggauss(order)
    grade = [1.0 - 10.0**-j for j in range(1, 11)] + [1.0 + 10.0**-j for j in range(1, 11)]
    out = []
    for comp in ("cc", "ss"):
        total = 1.0 + 0j
        for l in [*range(1, l_max + 1), *range(-l_max, 0)]:

            def g(k, l=l, comp=comp):
                X = cos_coefficient(l, k) if comp == "cc" else sin_coefficient_imag(l, k)
                return orbits.phase_space_weight(k) * X**2 * state.dfdkappa(k)

            x0 = omega / l
            for fam, (a, b) in (("libration", (0.0, 1.0)), ("rotation", (1.0, state.kappa_max))):
                kp = float(orbits.kappa_from_frequency(x0, M0, fam)) if x0 > 0 else np.nan
                # a pole within 1e-9 of the separatrix carries g/|Omega'| ~ 0, and one at the
                # bottom of the well (omega/l within rounding of Omega_0, kappa_p < 1e-6)
                # g ~ kappa^(2|l|) ~ 0: no subtraction
                pole = np.isfinite(kp) and a < kp < b and abs(kp - 1.0) > 1e-9 and kp > 1e-6
                edges = [*np.linspace(a, b, panels + 1), *points, *grade] + ([kp] if pole else [])
                edges = np.unique([e for e in edges if a <= e <= b])
                lo, hi = edges[:-1, None], edges[1:, None]
                k = (0.5 * (hi - lo) * x + 0.5 * (hi + lo)).ravel()
                wk = (0.5 * (hi - lo) * wx).ravel()
                gap = orbits.frequency(k, M0) - x0
                # nodes whose Omega rounds onto x0 (the flat bottom of the well, g ~ 0 there)
                integrand = g(k) / np.where(gap == 0.0, np.inf, gap)
                if pole:
                    dO = float(orbits.dOmega_dkappa(kp, M0))
                    G0 = float(g(kp)) / dO
                    integrand = integrand - G0 / (k - kp)
                    val = wk @ integrand + G0 * np.log(abs((b - kp) / (a - kp)))
                    val = val + 1j * np.pi * np.sign(l) * float(g(kp)) / abs(dO)
                else:
                    val = wk @ integrand
                total += 2.0 * np.pi * val
        out.append(total)
    return out[0], out[1]


def fermi_points(state):
    """kappa of the Fermi edges +- a few widths (where the quadrature must look)."""
    pts = []
    for mu, b in zip(state.mu, state.betas, strict=True):
        for d in np.arange(-30, 31, 2) / b:
            if mu + d > -state.M0:
                pts.append(float(np.sqrt((mu + d + state.M0) / (2 * state.M0))))
    return sorted(pts)


# ----------------------------------------------------------------------------- 1. Landau
@pytest.fixture(scope="module")
def thermal():
    return ThermalState(M0=0.72846)  # (u, M0) = (-0.1, 0.72846), fig. 5/6


KAPPAS = np.array([0.05, 0.3, 0.6, 0.85, 0.95])


def test_sech4_is_the_n1_term(thermal):
    """eq. (coeff-analytic-ncoll) D_dif = the n = n' = +-1, kappa* = kappa term of eq. (hmfCEdif)
    (FFT sigma_1, finite-difference J', Omega').  Measured max relative error 7e-9 (kappa = 0.05
    to 0.95; set by the finite differences)."""
    ref = np.array([general_resonant_term(k, thermal, 1) for k in KAPPAS])
    got = A.landau_D_sech4(KAPPAS, thermal)
    np.testing.assert_allclose(got, ref, rtol=1e-7)


def test_sech4_Dpol_sign_corrected(thermal):
    """D_pol of eq. (coeff-analytic-ncoll) with (1 - kappa^2): equals the general n = n' = +-1 term
    (relative error 8e-9); the printed (kappa^2 - 1) would give exactly minus it."""
    ref = np.array([general_resonant_term(k, thermal, 1, "Dpol") for k in KAPPAS])
    got = A.landau_Dpol_sech4(KAPPAS, thermal)
    np.testing.assert_allclose(got, ref, rtol=1e-7)
    assert np.all(ref < 0) and np.all(got < 0)  # f' < 0 for a thermal state: friction


def test_librating_sum_n2(thermal):
    """|n|,|n'| <= 2 librating sum = n=+-1 (sine) + n=+-2 (cosine) terms at kappa* = kappa
    (relative error 7e-9).  The sech^4 form is low by the factor 1/(1 + 2 c_2^4/sigma_1^4), the same
    for every f: measured D_sum/D_sech4 = 1.0011 (kappa = 0.3), 1.011 (0.5), 1.067 (0.7),
    1.168 (0.8), 1.281 (0.85), 1.516 (0.9), 2.18 (0.95), 5.70 (0.99)."""
    ref = np.array(
        [
            general_resonant_term(k, thermal, 1) + general_resonant_term(k, thermal, 2)
            for k in KAPPAS
        ]
    )
    got = A.landau_D_librating_sum(KAPPAS, thermal, n_max=2)
    np.testing.assert_allclose(got, ref, rtol=1e-7)
    ratio = got / A.landau_D_sech4(KAPPAS, thermal)
    c, s = zip(*(fft_coefficients(k, thermal.M0, 2) for k in KAPPAS), strict=True)
    np.testing.assert_allclose(
        ratio, 1 + 2 * np.array(c)[:, 2] ** 4 / np.array(s)[:, 1] ** 4, rtol=1e-9
    )
    assert abs(ratio[1] - 1) < 2e-3 and ratio[3] - 1 > 0.2 and ratio[4] - 1 > 0.5


def test_small_kappa_expansion(thermal):
    """eq. (coeff-analytic-ncoll-exp): D_sech4/(32 pi^2 kappa^4 f) = 1 - 13/8 kappa^2 + O(kappa^4)
    and D_pol,sech4/(8 pi^2 kappa^3 f'/sqrt(M0)) = 1 - 15/8 kappa^2 + O(kappa^4) (coefficients
    from the series K, E, q of the closed form).  Measured (ratio - 1)/kappa^2 at kappa = 0.01:
    -1.62495 and -1.87491."""
    for k in (0.01, 0.02):
        rd = A.landau_D_sech4(k, thermal) / A.landau_D_small_kappa(k, thermal)
        rp = A.landau_Dpol_sech4(k, thermal) / A.landau_Dpol_small_kappa(k, thermal)
        assert abs((rd - 1) / k**2 + 13 / 8) < 5 * k**2
        assert abs((rp - 1) / k**2 + 15 / 8) < 5 * k**2


@pytest.mark.parametrize("M0", [0.72846, 0.95])
def test_thermal_identity_Dpol(M0):
    """Thermal f: D_pol = -beta Omega(kappa) D_dif (zero Landau flux), on the sign-corrected
    closed forms, on the librating sum and with rotating roots included, n_max = 3 (measured
    relative error 9e-16)."""
    st = ThermalState(M0=M0)
    k = np.linspace(0.02, 0.98, 25)
    mbO = -st.beta * orbits.frequency(k, M0)
    np.testing.assert_allclose(
        A.landau_Dpol_sech4(k, st), mbO * A.landau_D_sech4(k, st), rtol=1e-12
    )
    for rot in (False, True):
        D, P = A.landau_coefficients_resonant(k, st, n_max=3, include_rotating=rot)
        np.testing.assert_allclose(P, mbO * D, rtol=1e-12)


def test_rotating_root_is_extra(thermal):
    """For n = n' = 1 the resonance Omega(kappa*) = Omega(kappa) also has a rotating root; it is
    not in the sech^4 form.  Checked: the extra term equals the general formula at that root
    (W = 2, FFT sigma_1 of the rotating orbit; relative 1e-6).  At M0 = 0.728 (|n| <= 2) it adds
    0.2-0.3 % for 0.3 <= kappa <= 0.6, 1.7 % at 0.8, 8 % at 0.9, 23 % at 0.95, and dominates as
    kappa -> 0 (it is ~ kappa^2, the librating term ~ kappa^4): +6 % at 0.05, +155 % at 0.01."""
    M0 = thermal.M0
    k = 0.6
    ks = float(orbits.kappa_from_frequency(orbits.frequency(k, M0), M0, "rotation"))
    w = 2.0 * np.pi * np.arange(2048) / 2048
    th, _ = orbits.phase_point(w, ks, M0, 1.0)
    sig1_star = (1j * np.fft.fft(np.sin(th)) / 2048)[1].real
    _, s = fft_coefficients(k, M0, 1)
    dJ = fd(lambda x: orbits.action(x, M0), ks)
    dO = abs(fd(lambda x: orbits.frequency(x, M0), ks))
    extra = 2 * 2 * np.pi**2 * 2.0 * dJ * float(thermal.f(ks)) / dO * (s[1] * sig1_star) ** 2
    with_rot = A.landau_D_librating_sum(k, thermal, n_max=1, include_rotating=True)
    lib = A.landau_D_librating_sum(k, thermal, n_max=1)
    np.testing.assert_allclose(with_rot - lib, extra, rtol=1e-6)


# ----------------------------------------------------------------------------- 2. two-step
@pytest.fixture(scope="module")
def two_step():
    return CoreHaloState(*CH, shape="step")


OMEGAS_CH = [0.3, 1.1, 1.58, 3.2, -1.1]  # away from the poles l Omega(kappa_i) (0.72, 0.86, ...)


def test_two_step_kappa_i(two_step):
    """Steps at kappa_i = sqrt((mu_i/M0 + 1)/2): f jumps there (the printed sqrt(mu_i/M0 + 1)
    would put them at 0.60 and 1.11, the second outside the separatrix)."""
    for k, w in zip(two_step.step_kappas, two_step.step_weights, strict=True):
        jump = two_step.f(k - 1e-9) - two_step.f(k + 1e-9)
        np.testing.assert_allclose(jump, w, rtol=1e-12)
        h = orbits.energy_from_kappa(k, two_step.M0)
        assert np.isclose(h, two_step.mu[0]) or np.isclose(h, two_step.mu[1])


def test_two_step_eps_vs_steep_fermi(two_step):
    """Two-step eps (eq. hmfepscc/ss-ch, corrected: sum over l >= 1 plus omega -> -omega) against
    the general eps by PV quadrature for the Fermi core-halo with beta1 = beta2 = 1000 (and 250):
    measured max |eps_step - eps_fermi| = 2.8e-5 at beta = 1000, 4.5e-4 at beta = 250 (~ 1/beta^2;
    Richardson-extrapolated to beta = infinity: see assert), |Im eps_fermi| < 1e-28 away from
    the poles.  The quadrature itself is converged to 4e-15 (doubling panels)."""
    eps_step = np.array(A.two_step_dielectric(np.array(OMEGAS_CH), two_step, l_max=6))
    errs, vals = [], []
    for beta in (250.0, 1000.0):
        smooth = CoreHaloState(*CH, beta, beta)
        pts = fermi_points(smooth)
        e = np.array([general_eps_quadrature(smooth, om, 6, pts) for om in OMEGAS_CH]).T
        assert np.max(np.abs(e.imag)) < 1e-12
        vals.append(e.real)
        errs.append(np.max(np.abs(e.real - eps_step)))
    assert errs[1] < 5e-5
    assert errs[1] < errs[0] / 8  # converges like 1/beta^2
    # Richardson extrapolation in 1/beta^2 to beta = infinity
    extrap = vals[1] + (vals[1] - vals[0]) / 15.0
    assert np.max(np.abs(extrap - eps_step)) < 3e-6
    # the printed eq. (hmfepscc/ss-ch), typed literally (every l != 0 and the omega -> -omega
    # term, g_l(kappa_i) = -w_i X_l(kappa_i)^2): off from the quadrature by 0.26 (cc), 1.3 (ss)
    om = np.array(OMEGAS_CH)
    Oi = orbits.frequency(two_step.step_kappas, two_step.M0)
    printed = []
    for coef in (cos_coefficient, sin_coefficient_imag):
        e = np.ones_like(om)
        for l in [*range(-6, 0), *range(1, 7)]:
            for k, w, O in zip(two_step.step_kappas, two_step.step_weights, Oi, strict=True):
                g = -w * coef(l, k) ** 2
                e = e + 2 * np.pi * (g / (O - om / l) + g / (O + om / l))
        printed.append(e)
    assert np.all(np.max(np.abs(np.array(printed) - extrap), axis=1) > 0.1)


def test_two_step_eps_structure(two_step):
    """eps_step is real and even in omega and diverges at omega = l Omega(kappa_i)."""
    om = np.array([0.2, 0.9, 2.0, 30.0])
    ecc, ess = A.two_step_dielectric(om, two_step)
    ecc2, ess2 = A.two_step_dielectric(-om, two_step)
    np.testing.assert_array_equal(ecc, ecc2)
    np.testing.assert_array_equal(ess, ess2)
    Oi = orbits.frequency(two_step.step_kappas, two_step.M0)
    near = A.two_step_dielectric(np.array([Oi[0] * (1 + 1e-9), 2 * Oi[1] * (1 + 1e-9)]), two_step)
    assert abs(near[1][0]) > 1e6 and abs(near[0][1]) > 1e6


def step_moments(state):
    """(mass, M0, (C2_cc, C2_ss), (C4_cc, C4_ss)) of the two-step f by 1-d quadratures in theta.

    f_raw = sum_i eta_i Theta(mu_i - h): int dp Theta(mu - h) = 2 p_mu(theta), p_mu =
    sqrt(2 (mu + M0 cos theta)), so C2 = <sin^2 theta>, <cos^2 theta>; df/dh = -sum_i eta_i
    delta(h - mu_i) / mass turns C4 = -int dtheta dp (df/dh) (d^2 X/dt^2)^2 into integrals over
    the level curves h = mu_i, sum_i (eta_i/mass) int dtheta 2 (d^2 X/dt^2)^2 / p_mu_i (the
    1/sqrt singularity at the turning point by QUADPACK's algebraic weight).  No orbits, no
    Fourier coefficients, no kappa_i.
    """
    M0 = state.M0
    tot = np.zeros(6)
    for eta, mu in zip(state.eta, state.mu, strict=True):
        tm = np.arccos(np.clip(-mu / M0, -1.0, 1.0))  # turning point

        def p(t, mu=mu):
            return np.sqrt(np.maximum(2.0 * (mu + M0 * np.cos(t)), 0.0))

        def sqrt_gap_over_p(t, tm=tm):  # sqrt(tm - t) / p, finite at t = tm
            return 1.0 / np.sqrt(2 * M0 * np.sin(0.5 * (tm + t)) * np.sinc(0.5 * (tm - t) / np.pi))

        def area(g, p=p, tm=tm):
            return 2 * integrate.quad(lambda t: 2 * p(t) * g(t), 0, tm, epsabs=1e-14, limit=200)[0]

        def level(g, p=p, tm=tm, s=sqrt_gap_over_p):
            return (
                2
                * integrate.quad(
                    lambda t: 2 * g(t, p(t)) ** 2 * s(t), 0, tm, weight="alg", wvar=(0, -0.5)
                )[0]
            )

        tot += eta * np.array(
            [
                area(lambda t: 1.0),
                area(np.cos),
                area(lambda t: np.sin(t) ** 2),
                area(lambda t: np.cos(t) ** 2),
                level(lambda t, p: M0 * np.sin(t) ** 2 - p**2 * np.cos(t)),
                level(lambda t, p: M0 * np.sin(t) * np.cos(t) + p**2 * np.sin(t)),
            ]
        )
    mass = tot[0]
    return mass, tot[1] / mass, tuple(tot[2:4] / mass), tuple(tot[4:6] / mass)


def test_two_step_eps_large_frequency(two_step):
    """eps_step - 1 = C2/omega^2 + C4/omega^4 + ... (as for any f(h), see test_dielectric) with
    C2, C4 from `step_moments` (which also reproduces the state's mass and self-consistent M0
    to 1e-15); at omega = 16, 24 (l_max = 30) R = (eps - 1 - C2/omega^2) omega^4 exceeds C4
    by 0.5-1.3 % (the C6 term) and its Richardson extrapolation equals C4 within 1.1e-4.  The
    printed double sum (twice eps - 1) or a weight w_i without the mass would fail at once."""
    mass, M0, C2, C4 = step_moments(two_step)
    assert abs(mass / two_step.mass - 1) < 1e-12 and abs(M0 - two_step.M0) < 1e-12
    om = np.array([16.0, 24.0])
    for e, c2, c4 in zip(A.two_step_dielectric(om, two_step, l_max=30), C2, C4, strict=True):
        R = (e - 1 - c2 / om**2) * om**4
        assert np.all((R / c4 - 1 > 0) & (R / c4 - 1 < 0.03)), R / c4 - 1
        extrapolated = (R[1] * om[1] ** 2 - R[0] * om[0] ** 2) / (om[1] ** 2 - om[0] ** 2)
        assert abs(extrapolated / c4 - 1) < 1e-3


def test_two_step_neutral_mode(two_step):
    """Neutral rotational mode: eps_ss(omega -> 0) = 0 for any self-consistent f(h).  The two-step
    closed form satisfies it through the self-consistent M0 and w_i = eta_i/mass: measured
    eps_ss(0) = 7.6e-7 (l_max = 6), 1.2e-13 (l_max = 12), 7e-16 (l_max = 30); a wrong sign or
    factor 2 (the printed double sum) would give eps_ss(0) = 2 or -1.  Also for the paper's
    eta2 = 0.05 variant (ch1)."""
    assert abs(A.two_step_dielectric(0.0, two_step, l_max=6)[1]) < 2e-6
    assert abs(A.two_step_dielectric(0.0, two_step, l_max=30)[1]) < 1e-13
    other = CoreHaloState(*CH[:1], 0.05, *CH[2:], shape="step")
    assert abs(A.two_step_dielectric(0.0, other, l_max=30)[1]) < 1e-13


def test_two_step_D(two_step):
    """two_step_D: collective=False equals the librating Landau sum of the step state, and with
    collective effects it equals the n = n' terms (FFT coefficients, FD derivatives) dressed by
    the general eps of the beta = 1000 Fermi state (PV quadrature).  Measured relative
    difference -4e-5 (kappa = 0.2), 1.5e-4 (0.6) (the two f's differ at O(1/beta^2)).  The
    dressing divides D by 99 (kappa = 0.2) and 11 (0.6)."""
    k = np.array([0.2, 0.6])
    np.testing.assert_allclose(
        A.two_step_D(k, two_step, collective=False),
        A.landau_D_librating_sum(k, two_step, n_max=2),
        rtol=1e-13,
    )
    smooth = CoreHaloState(*CH, 1000.0, 1000.0)
    pts = fermi_points(smooth)
    got = A.two_step_D(k, two_step)
    for kk, g in zip(k, got, strict=True):
        Om = float(orbits.frequency(kk, two_step.M0))
        ref = 0.0
        for n in (1, 2):
            ecc, ess = general_eps_quadrature(smooth, n * Om, 6, pts)
            c, s = fft_coefficients(kk, two_step.M0, n)
            dJ = fd(lambda x: orbits.action(x, two_step.M0), kk)
            dO = abs(fd(lambda x: orbits.frequency(x, two_step.M0), kk))
            ref += (
                4
                * np.pi**2
                * n
                * dJ
                * float(two_step.f(kk))
                / dO
                * (c[n] ** 4 / abs(ecc) ** 2 + s[n] ** 4 / abs(ess) ** 2)
            )
        np.testing.assert_allclose(g, ref, rtol=5e-4)


# ----------------------------------------------------------------------------- 3. app. C
def mb_definition_quadrature(omega, M0):
    """eqs. (eps_cc_ap_def, eps_ss_ap_def) by direct quadrature in kappa (Cauchy weight at the
    pole, + i pi g/|Omega_a'| there for omega > 0, conj for the l < 0 half)."""
    st = ThermalState(M0=M0)
    s = np.sqrt(M0)
    res = []
    for p, pref, div in ((4, np.pi / 2, 2.0), (2, 2 * np.pi, 1.0)):
        tot = 1.0 + 0j
        for sgn in (1.0, -1.0):
            x0 = sgn * omega / div  # pole where s (1 - k^2/4) = x0

            def g(k, p=p):
                return k**p * float(st.dfdkappa(k))

            kp2 = 4.0 * (1.0 - x0 / s)
            if 0 < kp2 < 1:
                kp = np.sqrt(kp2)
                # s(1 - k^2/4) - x0 = (s/4)(kp - k)(kp + k)
                val = integrate.quad(
                    lambda k, kp=kp: -4 * g(k) / (s * (kp + k)),
                    0,
                    1,
                    weight="cauchy",
                    wvar=kp,
                    limit=200,
                )[0]
                im = sgn * np.pi * g(kp) / (s * kp / 2)
            else:
                val = integrate.quad(
                    lambda k, x0=x0: g(k) / (s * (1 - k * k / 4) - x0),
                    0,
                    1,
                    limit=200,
                    epsabs=1e-14,
                    epsrel=1e-12,
                )[0]
                im = 0.0
            tot += pref * (val + 1j * im)
        res.append(tot)
    return res


@pytest.mark.parametrize("M0", [0.9, 0.95])
def test_mb_closed_form_vs_definition(M0):
    """app. C closed forms (Ei, corrected) vs PV quadrature of the definitions, real and imaginary
    parts, both signs of omega, including omega inside the pole ranges (1.5 s, 2 s) for cc and
    (0.75 s, s) for ss.  Measured max |difference| 4e-14 (M0 = 0.9, 0.95)."""
    s = np.sqrt(M0)
    oms = s * np.array([0.3, 0.8, 0.9, 1.2, 1.7, 1.9, 2.6])
    oms = np.concatenate([oms, -oms])
    ecc, ess = A.mb_dielectric_appendix_c(oms, M0)
    for om, a, b in zip(oms, ecc, ess, strict=True):
        rcc, rss = mb_definition_quadrature(om, M0)
        assert abs(a - rcc) < 1e-10 and abs(b - rss) < 1e-10, (om, a, rcc, b, rss)
    # Im eps < 0 for omega > 0 inside the pole range (the printed +i ... has the other sign)
    assert ecc[4].imag < 0 and ess[1].imag < 0 and ecc[4 + 7].imag > 0
    # no imaginary part for 0 < omega < 3 s/2 (cc): the pole lies at kappa > 1, outside the
    # definition's range (the printed Theta(s - omega/2) Theta(omega) would put one there)
    assert ecc[3].imag == 0.0 and ess[0].imag == 0.0


def test_mb_printed_forms_against_the_definitions():
    """Appendix C typed literally, as printed and as corrected (module docstring of
    kinetic.analytic), against the principal-value quadrature of the defining integrals (eqs.
    eps_cc_ap_def, eps_ss_ap_def: `mb_definition_quadrature`), M0 = 0.95, omega > 0 inside and
    outside the pole ranges (1.5 s, 2 s) for cc and (0.75 s, s) for ss (s = sqrt(M0)).
    Measured: the printed real part of eq. (eps_cc_ap) (b = beta) is right (max |difference|
    3e-12); the printed eq. (eps_ss_ap) (constant 64 pi sinh(b M0)/sqrt(M0) and no C in the Ei
    term) is off by 4e6; the printed imaginary parts have the wrong sign inside the pole ranges
    and are not zero below them; the corrected eq. (eps_ss_ap) and imaginary parts are right
    (max |difference| 3e-12)."""
    from scipy.special import expi

    M0 = 0.95
    st = ThermalState(M0=M0)
    b, s, C = st.beta, np.sqrt(M0), float(st.f(np.sqrt(0.5)))

    def alpha1(w):
        return np.exp(4 * b * s * w - 7 * b * M0)

    def alpha3(w):
        return np.exp(8 * b * s * w - 7 * b * M0)

    def half_cc(w):  # eq. (eps_cc_ap), real part, as printed
        a2 = -4 * b * s * w + 9 * b * M0 + 1
        x1, x2 = 6 * b * M0 - 4 * b * s * w, 8 * b * M0 - 4 * b * s * w
        return 16 * np.pi * b * C * (w - 2 * s) ** 2 * alpha1(w) * (
            expi(x1) - expi(x2)
        ) / s + 2 * np.pi * C * (a2 * np.sinh(b * M0) - b * M0 * np.cosh(b * M0)) / (b * M0**1.5)

    def half_ss(w, printed=False):  # eq. (eps_ss_ap), real part, corrected or as printed
        x3, x4 = 8 * b * (M0 - s * w), 6 * b * M0 - 8 * b * s * w
        const, c = (64 * np.pi, 1.0) if printed else (16 * np.pi * C, C)
        return const * np.sinh(b * M0) / s - 64 * np.pi * b * c * (s - w) * alpha3(w) * (
            expi(x3) - expi(x4)
        )

    def im_cc(w, printed=False):
        if printed:  # + sign, Theta(sqrt(M0) - w/2) Theta(w)
            return 16 * np.pi**2 * b * C * (w - 2 * s) ** 2 * alpha1(w) / s * (s - w / 2 > 0)
        return -16 * np.pi**2 * b * C * (w - 2 * s) ** 2 * alpha1(w) / s * (1.5 * s < w < 2 * s)

    def im_ss(w, printed=False):
        if printed:  # 16 pi^3 b C (sqrt(M0) - w) alpha3 Theta(sqrt(M0) - w) Theta(w)
            return 16 * np.pi**3 * b * C * (s - w) * alpha3(w) * (s - w > 0)
        return -64 * np.pi**2 * b * C * (s - w) * alpha3(w) * (0.75 * s < w < s)

    def close(a, ref):
        return abs(a - ref) < 1e-9 * max(1.0, abs(ref))

    def close_im(a, ref):  # exactly zero where the definition has no pole
        return a == 0 if ref == 0 else abs(a / ref - 1) < 1e-9

    for w in (0.3, 0.5, 0.8, 0.9, 1.2, 1.7, 1.9, 2.5):
        ref_cc, ref_ss = mb_definition_quadrature(w, M0)
        assert close(1 + half_cc(w) + half_cc(-w), ref_cc.real), w
        assert close(1 + half_ss(w) + half_ss(-w), ref_ss.real), w
        assert close_im(im_cc(w), ref_cc.imag) and close_im(im_ss(w), ref_ss.imag), w
        printed_ss = 1 + half_ss(w, True) + half_ss(-w, True)
        assert abs(printed_ss - ref_ss.real) > 1e3 * max(1.0, abs(ref_ss.real)), w
        for printed, ref in ((im_cc(w, True), ref_cc.imag), (im_ss(w, True), ref_ss.imag)):
            if ref != 0:  # inside the pole range: the opposite sign
                assert np.sign(printed) == -np.sign(ref), w
    # below the pole ranges the definitions have no imaginary part; the printed forms do
    for w in (0.3, 0.5):
        assert mb_definition_quadrature(w, M0)[1].imag == 0 and im_ss(w, True) != 0
    assert mb_definition_quadrature(1.2, M0)[0].imag == 0 and im_cc(1.2, True) != 0


def test_mb_definitions_vs_general_eps():
    """The definitions' prefactors (pi/2 for cc with l = +-2, 2 pi for ss with l = +-1) against
    the general eps (all l <= 6, both orbit families, exact c_l, sigma_l, Omega; PV quadrature):
    the relative error of eps - 1 shrinks as M0 -> 1.  Measured max over omega/s in
    {0.5, 1.25, 1.8, 3}: cc 0.16, 0.073, 0.0062, 0.0011 and ss 0.16, 0.070, 0.026, 0.013 at
    M0 = 0.9, 0.95, 0.98, 0.99 (ss ~ 1/(beta M0)); a factor-2 error in a prefactor would
    leave O(1) errors."""
    errs = {}
    for M0 in (0.9, 0.98):
        s = np.sqrt(M0)
        st = ThermalState(M0=M0)
        e_cc, e_ss = [], []
        for x in (0.5, 1.25, 1.8, 3.0):
            ref = general_eps_quadrature(st, x * s, 6)
            app = A.mb_dielectric_appendix_c(x * s, M0)
            e_cc.append(abs(app[0] - ref[0]) / abs(ref[0] - 1))
            e_ss.append(abs(app[1] - ref[1]) / abs(ref[1] - 1))
        errs[M0] = (max(e_cc), max(e_ss))
    assert errs[0.98][0] < errs[0.9][0] / 2.5 and errs[0.98][1] < errs[0.9][1] / 2.5
    assert errs[0.98][0] < 0.01 and errs[0.98][1] < 0.04


def test_mb_neutral_mode_limit():
    """eps_ss(0) -> 0 as M0 -> 1 for the appendix-C form (leading order 1 - 1/M0): measured
    eps_ss(0) = -0.0655, -0.0255, -0.0126, -0.0063 at M0 = 0.95, 0.98, 0.99, 0.995, i.e.
    ~ -1.26 (1 - M0)."""
    for M0 in (0.95, 0.98, 0.99, 0.995):
        e_ss0 = A.mb_dielectric_appendix_c(0.0, M0)[1]
        assert e_ss0.imag == 0.0
        assert -1.4 * (1 - M0) < e_ss0.real < -1.0 * (1 - M0)


def test_mb_D_identity_and_limits():
    """mb_D_appendix_c: D_pol = -beta Omega D (exact orbital quantities, relative 1e-14); with
    eps = 1 it reduces to the |n| <= 2 librating Landau sum (relative 1e-14); the 'expanded'
    orbit variant approaches the exact one as kappa -> 0 (measured ratio 1.0007 at kappa = 0.02,
    1.07 at 0.18, 1.44 at 0.66)."""
    M0 = 0.95
    st = ThermalState(M0=M0)
    k = np.linspace(0.02, 0.9, 12)
    D = A.mb_D_appendix_c(k, M0)
    P = A.mb_Dpol_appendix_c(k, M0)
    np.testing.assert_allclose(P, -st.beta * orbits.frequency(k, M0) * D, rtol=1e-12)
    np.testing.assert_allclose(
        A.mb_D_appendix_c(k, M0, collective=False),
        A.landau_D_librating_sum(k, st, n_max=2),
        rtol=1e-12,
    )
    De = A.mb_D_appendix_c(k, M0, orbit="expanded")
    assert abs(De[0] / D[0] - 1) < 1e-3


# ----------------------------------------------------------------------------- cross-checks
def test_against_numerical_modules():
    """If kinetic.dielectric / kinetic.diffusion import: (a) their eps of the beta = 1000 Fermi
    core-halo matches the two-step closed form (|diff| < 1e-4); (b) their Landau D with
    n_max = 3 equals landau_coefficients_resonant(include_rotating=True), D and D_pol, for
    kappa = 0.1 ... 2 (measured relative 5e-14);
    (c) their thermal eps at M0 = 0.98 is within the appendix-C accuracy of
    mb_dielectric_appendix_c (cc 0.0062, ss 0.026 relative on eps - 1) and mb_D_appendix_c is
    within 4.1 % of their D; (d) their eps and this
    file's quadrature agree (measured 1.5e-8 thermal M0 = 0.728, 1.6e-11 Fermi beta = 1000).
    Measured (a): 2.8e-5."""
    try:
        from hmfdiff.kinetic.dielectric import dielectric_tensor
        from hmfdiff.kinetic.diffusion import diffusion_coefficients
    except ImportError as exc:  # pragma: no cover - depends on the other modules' state
        pytest.skip(f"numerical modules not importable: {exc}")
    step = CoreHaloState(*CH, shape="step")
    smooth = CoreHaloState(*CH, 1000.0, 1000.0)
    om = np.array(OMEGAS_CH)
    ecc, ess = dielectric_tensor(smooth, om, l_max=6)
    scc, sss = A.two_step_dielectric(om, step)
    assert np.max(np.abs(ecc - scc)) < 1e-4 and np.max(np.abs(ess - sss)) < 1e-4
    th = ThermalState(M0=0.72846)
    k = np.array([0.1, 0.5, 0.8, 1.3, 2.0])
    res = diffusion_coefficients(th, k, n_max=3, collective=False)
    D, P = A.landau_coefficients_resonant(k, th, n_max=3, include_rotating=True)
    np.testing.assert_allclose(res["D"], D, rtol=1e-6)
    np.testing.assert_allclose(res["Dpol"], P, rtol=1e-6)
    M0 = 0.98
    x = np.sqrt(M0) * np.array([0.5, 1.25, 3.0])
    ncc, nss = dielectric_tensor(ThermalState(M0=M0), x, l_max=6)
    acc, ass = A.mb_dielectric_appendix_c(x, M0)
    assert np.max(np.abs(acc - ncc) / np.abs(ncc - 1)) < 0.01
    assert np.max(np.abs(ass - nss) / np.abs(nss - 1)) < 0.04
    # (e) fig. 7(f): mb_D_appendix_c vs their Lenard-Balescu D (n_max = 2) at M0 = 0.98:
    # measured ratio 0.959, 1.023, 0.972, 0.959 at kappa = 0.1, 0.3, 0.5, 0.7
    kk = np.array([0.1, 0.3, 0.5, 0.7])
    lb = diffusion_coefficients(ThermalState(M0=M0), kk, n_max=2, collective=True)["D"]
    assert np.max(np.abs(A.mb_D_appendix_c(kk, M0) / lb - 1)) < 0.06
    x = np.array([0.3, 0.7, 1.2, 1.9, 3.0])
    ncc, nss = dielectric_tensor(th, x, l_max=6)
    mine = np.array([general_eps_quadrature(th, o, 6) for o in x]).T
    assert np.max(np.abs(ncc - mine[0])) < 1e-6 and np.max(np.abs(nss - mine[1])) < 1e-6


def test_appendix_c_is_flagged_where_it_does_not_apply_and_warns_nowhere():
    """Appendix C expands in 1/(beta M0): the file says where that holds (M0 = 0.9, 0.95: 0.19,
    0.10) and where not (M0 = 0.05: 10.0), and computing it on the default grids raises no
    floating-point warning; at the logarithmic end-point divergence omega = 3 sqrt(M0)/2 the
    real part of eps_cc is infinite and the imaginary part finite (not NaN)."""
    import warnings

    from hmfdiff.kinetic.closed_forms import closed_forms
    from hmfdiff.meanfield.equilibrium import ThermalState, thermal_beta
    from hmfdiff.pipeline.layouts.theory import closed_forms_dataset

    for M0, applies in ((0.05, 0), (0.9, 1), (0.95, 1)):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            ds = closed_forms_dataset(closed_forms(ThermalState(M0=M0), n_kappa=50))
        assert ds.attrs["dielectric_applies"] == applies
        beta = thermal_beta(M0)
        assert ds.attrs["dielectric_expansion_parameter"] == pytest.approx(1 / (beta * M0))
    s = np.sqrt(0.95)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ecc, ess = A.mb_dielectric_appendix_c(np.array([1.5 * s, 0.75 * s]), 0.95)
    assert np.isinf(ecc[0].real) and np.isfinite(ecc[0].imag)
    assert np.isinf(ess[1].real) and np.isfinite(ess[1].imag)
