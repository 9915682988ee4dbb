"""c_n and s_n closed forms (eqs. hmfcm, hmfsm) against FFT of integrated pendulum orbits."""

import numpy as np
import pytest
from conftest import integrate_orbit

from hmfdiff.meanfield.fourier import cos_coefficient, sin_coefficient

M0 = 0.6
N = np.arange(-6, 7)


@pytest.mark.parametrize(
    "kappa,sign",
    [
        (0.1, 1),
        (0.5, 1),
        (0.9, 1),
        (0.99, 1),
        (1.01, 1),
        (1.01, -1),
        (1.5, 1),
        (1.5, -1),
        (3.0, -1),
    ],
)
def test_coefficients_match_fft_of_integrated_orbit(kappa, sign):
    """Integrate the orbit from theta = 0 (w = 0), sample uniformly in time over one period
    (w = Omega t), and Fourier transform cos(theta), sin(theta)."""
    n_samples = 512
    _, _, theta, _ = integrate_orbit(kappa, M0, sign=sign, n_samples=n_samples)
    C = np.fft.fft(np.cos(theta)) / n_samples
    S = np.fft.fft(np.sin(theta)) / n_samples
    np.testing.assert_allclose(cos_coefficient(N, kappa), C[N].real, atol=1e-9)
    np.testing.assert_allclose(C[N].imag, 0.0, atol=1e-9)
    np.testing.assert_allclose(sin_coefficient(N, kappa, sign), S[N], atol=1e-9)


def test_parity_and_symmetry():
    k = np.linspace(0.05, 0.95, 7)
    assert np.all(cos_coefficient(3, k) == 0) and np.all(sin_coefficient(2, k) == 0)
    kr = np.linspace(1.05, 3, 7)
    np.testing.assert_allclose(cos_coefficient(-4, kr), cos_coefficient(4, kr))
    np.testing.assert_allclose(sin_coefficient(-3, kr), -sin_coefficient(3, kr))
    # p < 0 flips s_n, not c_n
    np.testing.assert_allclose(sin_coefficient(3, kr, -1), -sin_coefficient(3, kr, 1))


def test_c0_is_orbit_average_and_limits():
    # c_0 -> 1 at the bottom of the well, -> 0 for fast rotation; c_2 ~ kappa^2/2, s_1 ~ -i kappa
    assert cos_coefficient(0, 1e-6) == pytest.approx(1.0, abs=1e-11)
    assert abs(cos_coefficient(0, 100.0)) < 1e-4
    k = 1e-3
    assert cos_coefficient(2, k) == pytest.approx(k**2 / 2, rel=1e-5)
    assert sin_coefficient(1, k) == pytest.approx(-1j * k, rel=1e-5)
    assert np.all(np.isfinite(cos_coefficient(N[:, None], np.array([0.0, 1 - 1e-12, 1 + 1e-12]))))
