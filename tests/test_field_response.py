"""The tools of the field-or-response split (studies/spectrum_scaling.py) on synthetic data with
known answers.

The answers rest on an identity independent of the code under test: for any orbit,
sum_{n >= 1} n^2 (c_n^2 + sigma_n^2) = <(d theta / dw)^2> / 2 = <p^2> / (2 Omega^2) = J / (2 Omega)
(Parseval, and <p^2> over an orbit = Omega J), so a flat (white) field spectrum N S gives
N D = N S J / (2 Omega) on every orbit.
"""

import numpy as np
import pytest

from hmfdiff.analysis.fluctuations import quasilinear_dj2
from hmfdiff.analysis.md_spectrum import resonance_bands
from hmfdiff.kinetic.spectrum import bin_diffusion_from_spectrum
from hmfdiff.meanfield import orbits

M0 = 0.7263
KAPPA = np.array([0.43, 0.9, 1.3])  # librating core edge, near the separatrix, rotating


def parseval(kappa):
    return orbits.action(kappa, M0) / (2.0 * orbits.frequency(kappa, M0))


class Flat:
    """A white spectrum N S = level in both components, to harmonic n_max."""

    def __init__(self, level, n_max):
        self.level, self.n_max = level, n_max

    def __call__(self, omega, component):
        return np.full(np.shape(omega), self.level)


def test_quasilinear_dj2_white_field_gives_parseval_diffusion():
    # white noise of variance v every dt: two-sided S = v dt in each component, so
    # <dJ^2>(t) = 2 S t sum n^2 (c_n^2 + sigma_n^2) = S t J / Omega exactly in expectation
    rng = np.random.default_rng(3)
    dt, v, T = 0.25, 1e-3, 2400
    R = 60
    dmx = rng.normal(0.0, np.sqrt(v), (R, T))
    dmy = rng.normal(0.0, np.sqrt(v), (R, T))
    lags = np.array([200, 400])
    origins = np.arange(0, T - 400 + 1, 400)  # disjoint windows at the longest lag
    dj2 = quasilinear_dj2(dmx, dmy, dt, KAPPA, M0, lags, origins, n_max=24).mean(axis=0)
    expected = v * dt * np.outer(2.0 * parseval(KAPPA), lags * dt)
    # R x 6 origins = 360 independent exponential |A|^2 per harmonic: ~5 % per entry
    np.testing.assert_allclose(dj2 / expected, 1.0, atol=0.2)
    assert abs(np.mean(dj2 / expected) - 1.0) < 0.05


def test_quasilinear_dj2_resonant_sinusoid_is_ballistic():
    # dMy = a cos(Omega s) on a librating orbit drives only n = 1 resonantly:
    # A_1 ~ -i sigma_1 a t / 2, <dJ^2> = 2 |A_1|^2 = sigma_1^2 a^2 t^2 / 2 (+ bounded terms)
    from hmfdiff.meanfield.fourier import sin_coefficient_imag

    k = np.array([0.43])
    Om = float(orbits.frequency(k, M0)[0])
    dt, a, T = 0.05, 1e-3, 40000
    t = np.arange(T) * dt
    dmy = a * np.cos(Om * t)
    lags = np.array([20000, 40000 - 1])
    dj2 = quasilinear_dj2(np.zeros(T), dmy, dt, k, M0, lags, np.array([0]), n_max=4)[0]
    expected = sin_coefficient_imag(1, k)[0] ** 2 * a**2 * (lags * dt) ** 2 / 2.0
    np.testing.assert_allclose(dj2, expected, rtol=0.01)


def test_bin_diffusion_from_flat_spectrum_is_the_weighted_parseval_sum():
    jb_sep = orbits.jbar_separatrix(M0)
    lo, hi = 0.3 * jb_sep, 0.6 * jb_sep

    def density(jb):
        return 1.0 + 5.0 * (jb - lo) / (hi - lo)  # a tilted density, as tracked particles

    got = bin_diffusion_from_spectrum(Flat(2.0, 24), lo, hi, M0, density, n_sub=41)
    jb = np.linspace(lo, hi, 43)[1:-1]
    w = density(jb)
    expected = 2.0 * np.sum(parseval(orbits.kappa_from_rescaled_action(jb, M0)) * w) / w.sum()
    assert got == pytest.approx(expected, rel=1e-6)
    terms = bin_diffusion_from_spectrum(Flat(2.0, 24), lo, hi, M0, density, per_harmonic=True)
    assert terms.shape == (24, 2) and terms.sum() == pytest.approx(got, rel=1e-12)


def test_resonance_bands_span_n_omega_of_the_bin():
    bands = resonance_bands(0.35, 0.49, M0, 3, pad=0.01)
    om = orbits.frequency(np.array([0.49, 0.35]), M0)
    for n in (1, 2, 3):
        assert bands[n] == pytest.approx((n * om[0] - 0.01, n * om[1] + 0.01))
