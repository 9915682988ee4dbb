"""Tests of the bath fluctuation spectrum and the finite-time diffusion (hmfdiff.kinetic.spectrum).

Independent routes: the spectrum's sum rule against the closed-form thermal averages of
cos^2 and sin^2 (Bessel functions) and a phase-space quadrature of c_0^2; D through the
tabulated spectrum against D through the resonance roots (diffusion.resonance_table), bare and
dressed; the finite-time fit against its long-time limit."""

import numpy as np
import pytest
from scipy import special

from hmfdiff.kinetic import diffusion, spectrum
from hmfdiff.kinetic.dielectric import DielectricTensor
from hmfdiff.meanfield.equilibrium import ThermalState
from hmfdiff.meanfield.fourier import cos_coefficient

KAPPA = np.array([0.2, 0.5, 0.8, 0.95, 1.05, 1.3, 2.0])


@pytest.fixture(scope="module")
def thermal():
    return ThermalState(u=-0.1)


def test_sum_rule_of_the_bath_spectrum(thermal):
    """int domega/(2 pi) N S_x = <cos^2 theta> - <c_0^2> and int N S_y = <sin^2 theta>: for a
    thermal state <cos^2> = (1 + I_2/I_0)/2 and <sin^2> = (1 - I_2/I_0)/2 at beta M0."""
    st = thermal
    bm = st.beta * st.M0
    q = st.quadrature()
    c0sq = q.integrate(st.f(q.kappa) * cos_coefficient(0, q.kappa) ** 2)
    ratio = special.iv(2, bm) / special.iv(0, bm)
    tab = spectrum.SpectrumTable(st, n_max=12, d_omega=1e-3)
    ix = 2.0 * np.trapezoid(tab.S["cc"], tab.omega) / (2.0 * np.pi)
    iy = 2.0 * np.trapezoid(tab.S["ss"], tab.omega) / (2.0 * np.pi)
    assert ix == pytest.approx(0.5 * (1 + ratio) - c0sq, rel=1e-4)
    assert iy == pytest.approx(0.5 * (1 - ratio), rel=1e-4)


def test_table_interpolates_the_direct_spectrum(thermal):
    tab = spectrum.SpectrumTable(thermal, n_max=6)
    w = np.array([0.05, 0.3, 0.7, 1.2, 1.69, 1.9, 3.0, 6.0])
    for comp in ("cc", "ss"):
        direct = spectrum.bath_spectrum(thermal, w, 6, comp)
        np.testing.assert_allclose(tab(w, comp), direct, rtol=1e-5, atol=1e-12)
    assert np.all(spectrum.bath_spectrum(thermal, w, 6, "cc") >= 0)
    np.testing.assert_allclose(
        spectrum.bath_spectrum(thermal, -w, 6, "ss"), spectrum.bath_spectrum(thermal, w, 6, "ss")
    )


def test_dressed_table_interpolates_the_direct_dressed_spectrum(thermal):
    """The table divides by |eps|^2 on its grid and interpolates; dressed_spectrum divides the
    root-found bare spectrum at each omega: the two agree away from the band edges."""
    eps = DielectricTensor(thermal, l_max=6)
    tab = spectrum.SpectrumTable(thermal, n_max=6, eps=eps)
    w = np.array([0.05, 0.3, 0.7, 1.2, 1.9, 3.0])
    for comp in ("cc", "ss"):
        direct = spectrum.dressed_spectrum(thermal, w, eps, 6, comp)
        np.testing.assert_allclose(tab(w, comp), direct, rtol=1e-4, atol=1e-12)
        bare = spectrum.bath_spectrum(thermal, w, 6, comp)
        ok = bare > 0
        assert np.any(np.abs(direct[ok] / bare[ok] - 1) > 0.05)  # the dressing matters here


@pytest.mark.parametrize("collective", [False, True])
def test_diffusion_through_the_spectrum_equals_the_resonance_sum(thermal, collective):
    eps = DielectricTensor(thermal, l_max=6) if collective else None
    tab = spectrum.SpectrumTable(thermal, n_max=6, eps=eps)
    d_spec = spectrum.diffusion_from_spectrum(tab, KAPPA, thermal.M0)
    d_res = diffusion.diffusion_coefficients(
        thermal, KAPPA, n_max=6, l_max=6, collective=collective, eps=eps
    )["D"]
    np.testing.assert_allclose(d_spec, d_res, rtol=5e-4)


def test_finite_time_fit_tends_to_the_asymptotic_D(thermal):
    """The windowed fit is biased at early windows where S varies on the scale 1/t (deep in
    the libration band, next to the band edge 2 Omega_0) and converges as the window moves
    late."""
    tab = spectrum.SpectrumTable(thermal, n_max=6)
    d_inf = spectrum.diffusion_from_spectrum(tab, KAPPA, thermal.M0)
    errs = []
    for lags in (np.arange(100.0, 501.0, 2.0), np.arange(1000.0, 5001.0, 10.0)):
        d_win = spectrum.windowed_diffusion(tab, KAPPA, thermal.M0, lags)
        errs.append(np.max(np.abs(d_win / d_inf - 1.0)))
    assert errs[1] < 2e-3
    assert errs[1] < errs[0] / 10


def test_slope_kernel_fits_a_straight_line_exactly():
    """The kernel at x -> 0 is t^2, whose least-squares slope over [t1, t2] is t1 + t2."""
    lags = np.arange(100.0, 501.0, 2.0)
    assert spectrum.slope_kernel(lags, np.array([0.0]))[0] == pytest.approx(600.0, rel=1e-12)
    x = np.array([1e-7, 3e-3])
    direct = [np.polyfit(lags, 2 * (1 - np.cos(xi * lags)) / xi**2, 1)[0] for xi in x]
    np.testing.assert_allclose(spectrum.slope_kernel(lags, x), direct, rtol=1e-8)


def test_welch_spectrum_of_a_signal_of_known_spectrum():
    """An AR(1) series x_j = a x_{j-1} + e_j (var e = s^2) has the two-sided spectrum
    S(omega) = dt s^2 / |1 - a exp(-i omega dt)|^2; the estimate must agree within its own
    error bars (and would not with a factor 2 or 2 pi off in the normalisation), and the errors
    must be the right size: the z-scores have unit spread."""
    from hmfdiff.analysis.fluctuations import welch_spectrum

    rng = np.random.default_rng(4)
    a, s, dt = 0.9, 0.3, 0.5
    e = rng.normal(0.0, s, size=(64, 6000))
    x = np.zeros_like(e)
    for j in range(1, e.shape[1]):
        x[:, j] = a * x[:, j - 1] + e[:, j]
    omega, S, err, m = welch_spectrum(x, dt, 512)
    exact = dt * s**2 / np.abs(1.0 - a * np.exp(-1j * omega * dt)) ** 2
    sel = omega > 4 * np.pi / (512 * dt)  # the Hann window leaks at the lowest two bins
    z = (S[sel] - exact[sel]) / err[sel]
    assert m == 64 * 22
    assert 0.92 < np.mean(np.abs(z) < 2) < 0.98
    assert 0.9 < np.std(z) < 1.1
    assert abs(np.mean(S[sel] / exact[sel]) - 1.0) < 0.01


def test_welch_error_is_honest_for_a_line_spectrum():
    """A bath of finitely many orbits is a line spectrum: each realisation is a fixed set of
    sinusoids (random frequencies and phases), whose lines recur in every segment, so the
    segments of one realisation are not independent.  The error of the Welch mean must then
    come from the spread between realisations: over 300 repeated experiments of 10
    realisations each, the scatter of the mean agrees with the quoted error.  (The spread
    between segments of all realisations claims an error 1.4x too small here.)"""
    from hmfdiff.analysis.fluctuations import welch_spectrum

    rng = np.random.default_rng(11)
    dt, seg, n_lines, n_real, n_exp = 1.0, 64, 40, 10, 300
    t = np.arange(8 * seg) * dt
    k = 12  # a frequency bin well inside the band of the lines
    means, errs = [], []
    for _ in range(n_exp):
        nu = rng.uniform(0.5, 1.5, size=(n_real, n_lines, 1))
        phase = rng.uniform(0.0, 2.0 * np.pi, size=(n_real, n_lines, 1))
        x = np.cos(nu * t + phase).sum(axis=1)
        omega, S, err, _ = welch_spectrum(x, dt, seg)
        means.append(S[k])
        errs.append(err[k])
    assert 0.5 < omega[k] < 1.5
    ratio = np.std(means, ddof=1) / np.mean(errs)
    assert 0.85 < ratio < 1.2, ratio


@pytest.mark.parametrize("u", [-0.1, 0.2475])
@pytest.mark.parametrize("component", ["cc", "ss"])
def test_thermal_dressed_spectrum_is_the_fluctuation_dissipation_theorem(u, component):
    """For a thermal state f ~ exp(-beta h), df/dkappa = -beta Omega dJ/dkappa f (dh/dJ =
    Omega), so the pole of eps (2 pi^2 sum_l W c_l^2 f' / |Omega'|, dielectric module) is
    -(beta omega / 2) times the bare N S (4 pi^2 sum_n W J' f c_n^2 / |n Omega'|, spectrum
    module): Im eps = -(beta omega / 2) N S_bare, and the dressed spectrum is the
    fluctuation-dissipation theorem's N S = (2 / (beta omega)) |Im 1/eps|.  The two modules
    compute their sums by different routes (resonance roots against a quadrature in Omega with
    its pole subtracted); the identity ties the spectrum's normalisation to the tensor's, and
    fails if the dressing is dropped (u = 0.2475: |eps|^-2 up to ~300)."""
    st = ThermalState(u=u)
    eps = DielectricTensor(st)
    w = np.array([0.1, 0.13, 0.196, 0.3, 0.45, 0.5, 0.52, 0.8, 1.2, 1.7, 2.5, 3.5])
    e = eps(w)[0 if component == "cc" else 1]
    bare = spectrum.bath_spectrum(st, w, component=component)
    dressed = spectrum.dressed_spectrum(st, w, eps, component=component)
    ok = bare > 1e-8 * bare.max()  # the bare spectrum vanishes like exp(-pi sqrt(M0) / Omega)
    assert ok.sum() >= 9
    np.testing.assert_allclose(e.imag[ok], -0.5 * st.beta * w[ok] * bare[ok], rtol=1e-5)
    fdt = 2.0 / (st.beta * w) * np.abs((1.0 / e).imag)
    np.testing.assert_allclose(dressed[ok], fdt[ok], rtol=1e-5)
