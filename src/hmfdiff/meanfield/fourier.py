"""Fourier coefficients of cos(theta) and sin(theta) along pendulum orbits (eqs. hmfcm, hmfsm).

c_n(kappa) = (1/2pi) int cos(theta(w, kappa)) exp(-i n w) dw   (real, c_{-n} = c_n)
s_n(kappa) = (1/2pi) int sin(theta(w, kappa)) exp(-i n w) dw   (imaginary, s_{-n} = -s_n)

with the angle w of `orbits` (w = 0 at theta = 0).  Corrections to the paper, each checked
by FFT of numerically integrated orbits in tests/test_fourier.py:

* c_0 is not printed: 2E/K - 1 on librating orbits, 1 - 2 kappa^2 (1 - E(1/kappa)/K(1/kappa)) on
  rotating orbits (it is the orbit average of cos(theta)).
* The rotating s_n of eq. (hmfsm) is labelled "p > 1" / "p < 1": read p > 0 / p < 0.  On an orbit
  rotating with p < 0 the sign of s_n flips (`sign=-1`); c_n does not depend on the direction.
"""

from __future__ import annotations

import numpy as np

from . import separatrix
from .orbits import _K_E, _modulus_parameter, nome

__all__ = [
    "cos_coefficient",
    "cos_coefficient_eta",
    "sin_coefficient",
    "sin_coefficient_imag",
    "sin_coefficient_imag_eta",
]


def _parts(n, kappa):
    n = np.asarray(n)
    kappa = np.asarray(kappa, dtype=float)
    n, kappa = np.broadcast_arrays(n, kappa)
    m, m1, lib = _modulus_parameter(kappa)
    K, E = _K_E(m, m1)
    q = nome(m, m1)
    return n, kappa, m, m1, lib, K, E, q


def _parts_eta(n, eta):
    """The same parts from the signed distance to the separatrix eta = kappa - 1
    (`separatrix`), without the loss of 1 - m that kappa suffers next to it."""
    n = np.asarray(n)
    eta = np.asarray(eta, dtype=float)
    n, eta = np.broadcast_arrays(n, eta)
    kappa, m, m1, lib, K, E = separatrix.fourier_parts(eta)
    q = nome(m, m1)
    return n, kappa, m, m1, lib, K, E, q


def cos_coefficient(n, kappa):
    """c_n(kappa), eq. (hmfcm), broadcasting over n (integers) and kappa.

    kappa < 1:  (pi/K)^2 |n| q^{|n|/2} / (1 - q^{|n|}) for even n != 0, 0 for odd n;
    kappa > 1:  2 kappa^2 (pi/K)^2 |n| q^{|n|} / (1 - q^{2|n|}),
                with K = K(1/kappa), q = q(1/kappa).
    """
    return _cos_coefficient(*_parts(n, kappa))


def cos_coefficient_eta(n, eta):
    """c_n of the orbit eta = kappa - 1 (eq. hmfcm), accurate at any distance from the
    separatrix (`separatrix`)."""
    return _cos_coefficient(*_parts_eta(n, eta))


def sin_coefficient_imag_eta(n, eta, sign=1.0):
    """sigma_n (s_n = -i sigma_n, eq. hmfsm) of the orbit eta = kappa - 1 (`separatrix`)."""
    return _sin_coefficient_imag(*_parts_eta(n, eta), sign)


def _cos_coefficient(n, kappa, m, m1, lib, K, E, q):
    a = np.abs(n).astype(float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        lib_c = (np.pi / K) ** 2 * a * q ** (a / 2) / -np.expm1(a * np.log(q))
        lib_c = np.where(n % 2 == 0, lib_c, 0.0)
        rot_c = 2.0 * kappa**2 * (np.pi / K) ** 2 * a * q**a / -np.expm1(2 * a * np.log(q))
        c0_lib = 2.0 * E / K - 1.0
        c0_rot = 1.0 - 2.0 * kappa**2 * (1.0 - E / K)
    c = np.where(lib, lib_c, rot_c)
    c0 = np.where(lib, c0_lib, c0_rot)
    out = np.where(n == 0, c0, c)
    # kappa -> 0: q -> 0 and every n != 0 coefficient vanishes; avoid 0 * inf
    return np.where((kappa == 0) & (n != 0), 0.0, out)


def sin_coefficient_imag(n, kappa, sign=1.0):
    """sigma_n with s_n = -i sigma_n (real), eq. (hmfsm); `sign` is the direction of rotation.

    kappa < 1:  (pi/K)^2 n q^{|n|/2} / (1 + q^{|n|}) for odd n, 0 for even n;
    kappa > 1:  sign * 2 kappa^2 (pi/K)^2 n q^{|n|} / (1 + q^{2|n|}).
    """
    return _sin_coefficient_imag(*_parts(n, kappa), sign)


def _sin_coefficient_imag(n, kappa, m, m1, lib, K, E, q, sign):
    sign = np.broadcast_to(np.asarray(sign, dtype=float), n.shape)
    nf = n.astype(float)
    a = np.abs(nf)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        lib_s = (np.pi / K) ** 2 * nf * q ** (a / 2) / (1.0 + q**a)
        lib_s = np.where(n % 2 == 1, lib_s, 0.0)  # n % 2 == 1 holds for negative odd n too
        rot_s = sign * 2.0 * kappa**2 * (np.pi / K) ** 2 * nf * q**a / (1.0 + q ** (2 * a))
    out = np.where(lib, lib_s, rot_s)
    return np.where((kappa == 0) | (n == 0), 0.0, out)


def sin_coefficient(n, kappa, sign=1.0):
    """s_n(kappa) as a complex number, s_n = -i sigma_n (eq. hmfsm)."""
    return -1j * sin_coefficient_imag(n, kappa, sign)
