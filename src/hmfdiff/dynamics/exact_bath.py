"""The bath of MD(bath) on its exact orbits: its magnetisation synthesised at every time step
from the orbits' Fourier series with a non-uniform FFT, instead of integrating N_b particles.

The bath of eq. hmfmdbath moves in the static field M0, so particle i follows its pendulum orbit
theta_i(t) = theta(w_i + Omega_i t, kappa_i) (appendix A; (kappa_i, w_i, sign_i) from its initial
phase point).  With the Fourier coefficients of eqs. hmfcm, hmfsm (c_-n = c_n, s_n = -i sigma_n)

    cos theta = c_0 + 2 sum_{n >= 1} c_n cos(n w),     sin theta = 2 sum_{n >= 1} sigma_n sin(n w),

so at the times t_k = k dt

    Mx(t_k) = (1/N_b) sum_i c_0(kappa_i) + (1/N_b) Re F_x(k),   My(t_k) = (1/N_b) Im F_y(k),
    F(k) = sum_{i, n} a_in exp(i k x_in),   x_in = n Omega_i dt (mod 2 pi),

with a_in = 2 c_n e^{i n w_i} for F_x and 2 sigma_n e^{i n w_i} for F_y: a type-1 non-uniform
FFT (`finufft.nufft1d1`) over the points x_in, one mode per time step.

Harmonics per particle.  With the nome q of the orbit, rho = q^(1/2) on librating orbits and q
on rotating ones, and A = (pi/K)^2 (times 2 kappa^2 on rotating orbits), eqs. hmfcm, hmfsm give
|c_n|, |sigma_n| = A n rho^n / (1 -+ rho^(2n)) <= A n rho^n / (1 - rho^2).  Particle i keeps the
first N_i harmonics, N_i the smallest integer with the tail bound

    2 A / (1 - rho^2) sum_{n > N_i} n rho^n = 2 A rho^(N_i + 1) (N_i + 1 - N_i rho)
                                               / ((1 - rho^2) (1 - rho)^2)  <=  tolerance,

so that truncation moves each cos theta_i, sin theta_i, hence Mx and My, by at most
`tolerance` at every time; the transform's own error is set to an rms error of about
`tolerance` on M as well.  Orbits that would need more than `max_harmonics` (the few within
~1e-7 of the separatrix, where q -> 1) are integrated directly by velocity Verlet in the static
field, with the run's time step, and their cos, sin added to the synthesised sums.

The bath's mean momentum obeys d<p>/dt = -M0 My, integrated here by the trapezoid rule on the
time steps; its mean energy in the static field is constant.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from ..meanfield import orbits
from .integrator import Field, Particles
from .jit import njit

__all__ = ["MAX_HARMONICS", "ExactBath", "harmonic_amplitudes", "harmonics_needed"]

#: most harmonics synthesised for one orbit; orbits needing more are integrated directly
MAX_HARMONICS = 256
#: points per call of the non-uniform FFT (buffers of ~40 bytes per point, reused)
_CHUNK_POINTS = 500_000


def _orbit_parts(kappa):
    """(rho, A, librating, K, E) of each orbit: coefficients |c_n|, |sigma_n| = A n rho^n /
    (1 -+ rho^(2n)) (eqs. hmfcm, hmfsm), and the complete elliptic integrals of its modulus
    (`orbits._K_E`), which the synthesis reuses for Omega and c_0 instead of evaluating them
    twice more."""
    m, m1, lib = orbits._modulus_parameter(kappa)
    K, E = orbits._K_E(m, m1)
    q = orbits.nome(m, m1)
    with np.errstate(invalid="ignore", divide="ignore"):
        rho = np.where(lib, np.sqrt(q), q)
        A = (np.pi / K) ** 2 * np.where(lib, 1.0, 2.0 * kappa**2)
    return rho, A, lib, K, E


def _orbit_parameters(kappa):
    """(rho, A, librating) of each orbit (`_orbit_parts`)."""
    return _orbit_parts(kappa)[:3]


def _frequency_c0(kappa, lib, K, E, M0):
    """(Omega, c_0) of orbits kappa from their K and E: the expressions of
    `orbits.frequency` and `fourier.cos_coefficient(0, kappa)` (the same numbers to the bit),
    without evaluating K, E and the nome again."""
    s = np.sqrt(M0)
    with np.errstate(divide="ignore", invalid="ignore"):
        omega = np.where(lib, np.pi * s / (2.0 * K), np.pi * s * kappa / K)
        c0_lib = 2.0 * E / K - 1.0
        c0_rot = 1.0 - 2.0 * kappa**2 * (1.0 - E / K)
    return omega, np.where(lib, c0_lib, c0_rot)


@njit
def _harmonics_needed(rho, A, tolerance, max_harmonics, out):
    for i in range(rho.size):
        r = rho[i]
        if not (r >= 0.0 and r < 1.0 and math.isfinite(A[i])):
            out[i] = max_harmonics + 1
            continue
        if r == 0.0:
            out[i] = 0
            continue
        pre = 2.0 * A[i] / ((1.0 - r * r) * (1.0 - r) ** 2)
        n = 0
        rn1 = r  # rho^(n + 1)
        while n <= max_harmonics and pre * rn1 * ((n + 1) - n * r) > tolerance:
            n += 1
            rn1 *= r
        out[i] = n


def harmonics_needed(kappa, tolerance, max_harmonics=MAX_HARMONICS, parameters=None):
    """N_i of each orbit (module docstring); max_harmonics + 1 where more than max_harmonics
    would be needed (the separatrix, kappa = 1, included).  parameters: `_orbit_parameters`
    of kappa if already computed."""
    kappa = np.ascontiguousarray(kappa, dtype=float)
    rho, A, _ = _orbit_parameters(kappa) if parameters is None else parameters
    out = np.empty(kappa.size, dtype=np.int64)
    _harmonics_needed(rho, A, float(tolerance), int(max_harmonics), out)
    return out


@njit(inline="always")
def _coefficients(n, r_n, A, lib, sign):
    """(c_n, sigma_n) from rho^n = r_n (eqs. hmfcm, hmfsm; sigma_n for the direction sign)."""
    base = A * n * r_n
    r2n = r_n * r_n
    c = base / (1.0 - r2n)
    s = base / (1.0 + r2n)
    if lib:
        if n % 2 == 0:
            s = 0.0
        else:
            c = 0.0
    else:
        s = sign * s
    return c, s


@njit(parallel=True)
def _sources(first, count, offsets, rho, A, lib, sign, w, omega_dt, shift, x, ax, ay):
    """Points x = n Omega dt (wrapped to [-pi, pi)) and strengths 2 c_n z^n, 2 sigma_n z^n with
    z = e^{i (w + shift Omega dt)} (= e^{i (n w + shift x)} for the integer shift, which places
    time step 0 on the first mode of the transform), for the orbits first ... first + count - 1.
    z^n by recurrence (rounding ~ n 1e-16, n <= MAX_HARMONICS)."""
    two_pi = 2.0 * math.pi
    for j in prange(count):
        i = first + j
        o = offsets[i] - offsets[first]
        phi = (w[i] + shift * omega_dt[i]) % two_pi
        z1 = complex(math.cos(phi), math.sin(phi))
        z = complex(1.0, 0.0)
        r_n = 1.0
        for n in range(1, offsets[i + 1] - offsets[i] + 1):
            r_n *= rho[i]
            z *= z1
            c, s = _coefficients(n, r_n, A[i], lib[i], sign[i])
            xx = n * omega_dt[i]
            x[o + n - 1] = xx - two_pi * math.floor(xx / two_pi + 0.5)
            ax[o + n - 1] = 2.0 * c * z
            ay[o + n - 1] = 2.0 * s * z


def harmonic_amplitudes(kappa, n_max, sign=1.0):
    """(c_n, sigma_n) for n = 1 ... n_max of each orbit as this module evaluates them, shape
    (orbit, n) (for the tests: compared with `hmfdiff.meanfield.fourier`)."""
    kappa = np.atleast_1d(np.asarray(kappa, dtype=float))
    sign = np.broadcast_to(np.asarray(sign, dtype=float), kappa.shape)
    rho, A, lib = _orbit_parameters(kappa)
    c = np.zeros((kappa.size, n_max))
    s = np.zeros((kappa.size, n_max))
    for i in range(kappa.size):
        for n in range(1, n_max + 1):
            c[i, n - 1], s[i, n - 1] = _coefficients.py_func(
                n, rho[i] ** n, A[i], bool(lib[i]), sign[i]
            )
    return c, s


class ExactBath:
    """The magnetisation of a bath of N_b particles in the static field M0, at t_k = k dt for
    k = 0 ... n_steps, from their exact orbits (module docstring).

    theta, p: initial phase points (the same a bath integrated from them would start from);
    tolerance: bound on the truncation error of each particle's cos theta and sin theta, hence
    of Mx and My; threads: threads of the non-uniform FFT; chunk_points: harmonics per call of
    the transform (default `_CHUNK_POINTS`; lowered by the tests to span many chunks).
    Attributes: `history` (n_steps + 1, 2) of (Mx, My); `momentum` (n_steps + 1) mean p;
    `energy` (mean p^2/2 - M0 cos theta, constant); `n_direct` orbits integrated directly;
    `n_points` harmonics synthesised in all; `max_harmonics_used`.
    """

    def __init__(
        self,
        theta,
        p,
        M0,
        *,
        dt,
        n_steps,
        tolerance=1e-9,
        threads=1,
        max_harmonics=None,
        chunk_points=_CHUNK_POINTS,
    ):
        import finufft

        theta = np.asarray(theta, dtype=float)
        p = np.asarray(p, dtype=float)
        n_b = theta.size
        if n_b < 1:
            raise ValueError("the bath needs at least one particle")
        if not 0.0 < tolerance < 1e-3:
            raise ValueError(f"tolerance = {tolerance!r} must lie in (0, 1e-3)")
        n_max = MAX_HARMONICS if max_harmonics is None else int(max_harmonics)
        n_steps = int(n_steps)
        self.M0, self.dt, self.n_steps, self.tolerance = float(M0), float(dt), n_steps, tolerance
        kappa, w, sign = orbits.angle_action(theta, p, M0)
        rho, A, lib, K, E = _orbit_parts(kappa)
        params = (rho, A, lib)
        n_harm = harmonics_needed(kappa, tolerance, n_max, params)
        direct = n_harm > n_max
        self.n_direct = int(direct.sum())
        syn = ~direct
        kappa_s, w_s, sign_s, nh = kappa[syn], w[syn], sign[syn], n_harm[syn]
        rho, A, lib, K, E = (v[syn] for v in (rho, A, lib, K, E))
        omega, c0 = _frequency_c0(kappa_s, lib, K, E, M0)
        omega_dt = omega * dt
        offsets = np.concatenate([[0], np.cumsum(nh)]).astype(np.int64)
        self.n_points = int(offsets[-1])
        self.max_harmonics_used = int(nh.max(initial=0))

        n_modes = n_steps + 1 + (n_steps + 1) % 2  # even number of modes >= n_steps + 1
        shift = n_modes // 2
        # the transform's relative l2 error eps gives an rms error ~ eps sqrt(n_points) / N_b
        # on M (strengths |a| <= 1): eps = tolerance N_b / sqrt(n_points), within [1e-14, 1e-6]
        eps = float(np.clip(tolerance * n_b / np.sqrt(max(self.n_points, 1)), 1e-14, 1e-6))
        self.fft_eps = eps
        F = np.zeros((2, n_modes), dtype=complex)
        chunk_points = int(chunk_points)
        if chunk_points < 1:
            raise ValueError(f"chunk_points = {chunk_points!r} must be positive")
        size = min(self.n_points, chunk_points)
        x_buf, a_buf = np.empty(size), np.empty((2, size), dtype=complex)
        first = 0
        while first < kappa_s.size:
            # orbits first ... last - 1, at most chunk_points harmonics (at least one orbit)
            last = int(np.searchsorted(offsets, offsets[first] + chunk_points, "right")) - 1
            last = min(max(last, first + 1), kappa_s.size)
            m = int(offsets[last] - offsets[first])
            if m > 0:
                if m > x_buf.size:
                    x_buf, a_buf = np.empty(m), np.empty((2, m), dtype=complex)
                x = x_buf[:m]
                a = a_buf if m == x_buf.size else a_buf[:, :m]
                _sources(
                    first,
                    last - first,
                    offsets,
                    rho,
                    A,
                    lib,
                    sign_s,
                    w_s,
                    omega_dt,
                    float(shift),
                    x,
                    a[0],
                    a[1],
                )
                a = np.ascontiguousarray(a)  # a copy only for a short last chunk
                F += finufft.nufft1d1(x, a, n_modes, eps=eps, isign=1, nthreads=int(threads))
            first = last
        hist = np.empty((n_steps + 1, 2))
        hist[:, 0] = (c0.sum() + F[0, : n_steps + 1].real) / n_b
        hist[:, 1] = F[1, : n_steps + 1].imag / n_b
        if self.n_direct:
            hist += self._integrate_directly(theta[direct], p[direct]) * (self.n_direct / n_b)
        self.history = hist
        P0 = float(np.mean(p))
        dP = -self.M0 * 0.5 * dt * (hist[1:, 1] + hist[:-1, 1])
        self.momentum = P0 + np.concatenate([[0.0], np.cumsum(dP)])
        self.energy = float(np.mean(0.5 * p * p - M0 * np.cos(theta)))

    def _integrate_directly(self, theta, p):
        """(mean cos, mean sin) of the given particles at every time step, integrated by
        velocity Verlet in the static field M0 (positions are exact at every step start)."""
        P = Particles(theta, p)
        out = np.empty((self.n_steps + 1, 2))
        m = P.moments()
        out[0] = m[:2]
        k = 0
        while k < self.n_steps:
            n = min(4096, self.n_steps - k)
            h = P.open_steps(n, dt=self.dt, field=Field.STATIC, fx=self.M0, fy=0.0)
            P.close_steps(dt=self.dt, fx=self.M0, fy=0.0)
            out[k + 1 : k + n + 1] = h[:, :2]
            k += n
        return out

    def attrs(self):
        """What the synthesis did, for the run's netCDF attributes."""
        return {
            "bath_method": "exact orbits, magnetisation synthesised by a type-1 non-uniform "
            "FFT of the orbits' Fourier series (finufft)",
            "bath_tolerance": self.tolerance,
            "bath_harmonics_total": self.n_points,
            "bath_fft_eps": self.fft_eps,
            "bath_harmonics_max": self.max_harmonics_used,
            "bath_max_harmonics": MAX_HARMONICS,
            "bath_n_direct": self.n_direct,
        }
