"""Molecular dynamics of the HMF model with on-the-fly <dJ^2> (paper, sec. "Comparison with
simulations", eqs. hmfmdbath, hmfmdfull, dj2, hmfmddif).

Dynamics (`run_md`):

* 'bath' (eq. hmfmdbath): N_b bath particles in the static field theta'' = -M0 sin(theta), M0 the
  state's theoretical magnetisation; N_tp test particles driven, without feedback, by the
  instantaneous bath magnetisation: theta'' = -Mx_b sin(theta) + My_b cos(theta).
* 'full' (eq. hmfmdfull): all N particles in the instantaneous magnetisation
  theta'' = -Mx sin(theta) + My cos(theta); optional test particles driven by it without
  feeding back.

Integrator: velocity Verlet (kick-drift-kick leapfrog, 2nd order, symplectic and time
reversible).  Consecutive half kicks are fused, so one pass over the particles per step updates
p and theta and accumulates sum cos, sum sin of the new angles; a last half kick re-synchronises
p with theta at each sampling time.  sin and cos of the new angle (wrapped to [-pi, pi)) come
from a branch-free half-angle polynomial (`_sincos_wrapped`, absolute error < 6e-16) so that the
loop vectorises; they are cached per particle, so each step costs one sincos per particle.
A general vectorisable sincos (`_sincos`: quadrant reduction with a three-part pi/2, error
~1 ulp for |x| up to ~1e5) serves the action evaluation.  Both are tested against numpy.

Reductions are deterministic: the particles are cut into a fixed number of chunks (independent
of the thread count), each chunk's partial sums are combined in chunk order, so the same seed
gives bit-identical output for any thread count on the same machine and build.

Actions: J of every tracked particle, with the static M0 and, for 'full', in the frame of the
instantaneous magnetisation (theta - arg(Mx + i My)); for 'bath' in the fixed frame.  K and E by
the arithmetic-geometric mean (`action_numba`, ~1e-15 relative, tested against orbits.action).

<dJ^2> (eq. dj2) is accumulated while the run goes: at every origin t0 (every `origin_every`)
J(t0) and the J-bar bin of each tracked particle are stored in a ring buffer; at every sampling
time the squared displacements of all active origins are added to sums per (bin, lag, block).
Only origins whose whole lag window fits in the run are used, so every lag averages the same
set of origins.  Origins are split into `n_blocks` contiguous blocks for error estimates.
"""

from __future__ import annotations

import math
import os
import sys
import time as _time

# The kernels synchronise all threads at every time step.  With OpenMP's default active
# waiting, a thread that loses its core to another process stalls the others, which then spin:
# on this 2-core machine with a competing process, 2 threads fell from 1.6e8 to 7e7
# particle-steps/s.  Passive waiting (set only if the user has not chosen) avoids the collapse;
# it must be set before the OpenMP runtime starts, i.e. before the first parallel kernel runs.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import numba  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from numba import njit, prange  # noqa: E402

from . import sampling  # noqa: E402

__all__ = [
    "sincos_array",
    "sincos_wrapped_array",
    "action_numba",
    "actions",
    "DisplacementAccumulator",
    "Particles",
    "leapfrog",
    "advance_system",
    "run_md",
    "INTEGRATOR",
]

INTEGRATOR = "velocity Verlet (kick-drift-kick leapfrog), 2nd order, symplectic"

# no 'nnan'/'ninf': NaN checks must keep working (numba's fastmath=True would assume no NaN)
_FM = {"reassoc", "contract", "arcp", "nsz"}

_TWO_PI = 2.0 * math.pi
_INV_TWO_PI = 1.0 / _TWO_PI
_TWO_OVER_PI = 2.0 / math.pi
# pi/2 split in three parts (33 + 33 + 53 bits): k * _P1 and k * _P2 are exact for |k| < 2^20
_P1 = 1.57079632673412561417e00
_P2 = 6.07710050630396597660e-11
_P3 = 2.02226624879595063154e-21

# Near-minimax polynomials on [-pi/4, pi/4] (weighted least squares at 400 Chebyshev nodes,
# 40-digit arithmetic, fitted for this module): sin r = r + r^3 S(r^2), cos r = 1 - r^2/2 +
# r^4 C(r^2).  Error against numpy below 2.3e-16 over [-4 pi, 4 pi] (tests/test_md.py).
_S1, _S2, _S3, _S4, _S5, _S6 = (
    -0.1666666666666663,
    0.008333333333321907,
    -0.00019841269829452244,
    2.755731358095979e-06,
    -2.505074222357712e-08,
    1.5895943103357368e-10,
)
_C1, _C2, _C3, _C4, _C5, _C6 = (
    0.04166666666666659,
    -0.0013888888888872505,
    2.480158728855358e-05,
    -2.755731410296429e-07,
    2.0875691483269687e-09,
    -1.1358093609276402e-11,
)

# Half-angle polynomials on [-pi/2, pi/2] (weighted least squares at 500 Chebyshev nodes in
# 40-digit arithmetic, fitted for this module; truncation error 2e-19 and 6e-18):
# sin u = u + u^3 SH(u^2), cos u = 1 - u^2/2 + u^4 CH(u^2).
_SH = (
    -0.16666666666666666,
    0.008333333333333106,
    -0.0001984126984118389,
    2.7557319207506058e-06,
    -2.5052106585314903e-08,
    1.6058926918823753e-10,
    -7.642691997901776e-13,
    2.71829976216082e-15,
)
_CH = (
    0.04166666666666578,
    -0.0013888888888827712,
    2.4801587285345367e-05,
    -2.755731702734344e-07,
    2.0876590527674145e-09,
    -1.1463582501750082e-11,
    4.615589456771727e-14,
)
_SH1, _SH2, _SH3, _SH4, _SH5, _SH6, _SH7, _SH8 = _SH
_CH1, _CH2, _CH3, _CH4, _CH5, _CH6, _CH7 = _CH

_CHUNK = 4096  # particles per chunk of the deterministic reductions


# ---------------------------------------------------------------------------------------------
# elementary kernels
# ---------------------------------------------------------------------------------------------
@njit(fastmath={"contract"})
def _sincos(x):
    """(sin x, cos x) for |x| up to ~1e5, branch-free so that loops vectorise."""
    k = np.floor(x * _TWO_OVER_PI + 0.5)
    r = ((x - k * _P1) - k * _P2) - k * _P3
    z = r * r
    s = r + r * z * (_S1 + z * (_S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))))
    c = 1.0 - 0.5 * z + z * z * (_C1 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6)))))
    q = k - 4.0 * np.floor(0.25 * k)  # k mod 4 in {0, 1, 2, 3}
    odd = (q == 1.0) | (q == 3.0)
    sx = c if odd else s
    cx = s if odd else c
    sx = -sx if q >= 2.0 else sx
    cx = -cx if (q == 1.0) | (q == 2.0) else cx
    return sx, cx


@njit(fastmath={"contract"})
def _sincos_wrapped(x):
    """(sin x, cos x) for |x| <= pi (angles wrapped to [-pi, pi)), from the half angle:
    sin x = 2 sin(x/2) cos(x/2), cos x = (c - s)(c + s).  No range reduction and no quadrant
    selection: ~40% cheaper than `_sincos`; absolute error < 6e-16 (tests/test_md.py)."""
    u = 0.5 * x
    z = u * u
    s = u + u * z * (
        _SH1
        + z * (_SH2 + z * (_SH3 + z * (_SH4 + z * (_SH5 + z * (_SH6 + z * (_SH7 + z * _SH8))))))
    )
    c = (
        1.0
        - 0.5 * z
        + z * z * (_CH1 + z * (_CH2 + z * (_CH3 + z * (_CH4 + z * (_CH5 + z * (_CH6 + z * _CH7))))))
    )
    return 2.0 * s * c, (c - s) * (c + s)


@njit(fastmath=_FM)
def _sincos_wrapped_kernel(x, s_out, c_out):
    for i in range(x.size):
        s, c = _sincos_wrapped(x[i])
        s_out[i] = s
        c_out[i] = c


def _sincos_with(kernel, x):
    x = np.ascontiguousarray(x, dtype=np.float64).ravel()
    s = np.empty_like(x)
    c = np.empty_like(x)
    kernel(x, s, c)
    return s, c


def sincos_wrapped_array(x):
    """(sin x, cos x) by the half-angle polynomial of the MD step, for |x| <= pi."""
    return _sincos_with(_sincos_wrapped_kernel, x)


@njit(fastmath=_FM)
def _sincos_kernel(x, s_out, c_out):
    for i in range(x.size):
        s, c = _sincos(x[i])
        s_out[i] = s
        c_out[i] = c


def sincos_array(x):
    """Vectorised polynomial (sin x, cos x) used by the MD kernels (exposed for tests)."""
    return _sincos_with(_sincos_kernel, x)


@njit(fastmath=_FM)
def _chunk_step(theta, p, S, C, h, dt, Fx, Fy):
    """One fused leapfrog step of the particles (a chunk, passed as array views); returns sum
    cos, sum sin of the new angles.

    p += h (-Fx sin theta + Fy cos theta); theta += dt p; theta wrapped to [-pi, pi);
    S, C hold sin, cos of the current angles on entry and of the new angles on exit, so that
    each step evaluates one sincos per particle."""
    sc = 0.0
    ss = 0.0
    # range(size), not range(lo, hi): numba's negative-index handling blocks vectorisation
    for i in range(theta.size):
        pi_ = p[i] + h * (Fy * C[i] - Fx * S[i])
        th = theta[i] + dt * pi_
        th = th - _TWO_PI * np.floor(th * _INV_TWO_PI + 0.5)
        s2, c2 = _sincos_wrapped(th)
        sc += c2
        ss += s2
        p[i] = pi_
        theta[i] = th
        S[i] = s2
        C[i] = c2
    return sc, ss


@njit(parallel=True)
def _kick_drift(theta, p, S, C, first_kick, kick, dt, fx, fy, n_steps, field, out):
    """n_steps fused leapfrog steps of particles (theta, p, S = sin theta, C = cos theta), in place.

    Step j: p += h_j (-Fx sin theta + Fy cos theta); theta += dt p; theta wrapped to [-pi, pi);
    h_0 = first_kick, h_j = kick for j > 0.  (Fx, Fy) at step j:
      field == 0: (fx, fy) constant (static field);
      field == 1: self-consistent: the magnetisation of these particles at the current time
                  (fx, fy on entry are the magnetisation of the initial angles);
      field == 2: external history: out[j, 2], out[j, 3] hold (Fx, Fy) of step j.
    out[j, 0], out[j, 1] = mean cos, mean sin of the angles after step j.
    Reductions go through fixed chunks combined in order (deterministic for any thread count).
    """
    n = theta.size
    n_chunks = (n + _CHUNK - 1) // _CHUNK
    part_c = np.zeros(n_chunks)
    part_s = np.zeros(n_chunks)
    Fx = fx
    Fy = fy
    h = first_kick
    for j in range(n_steps):
        if field == 2:
            Fx = out[j, 2]
            Fy = out[j, 3]
        for ch in prange(n_chunks):
            lo = ch * _CHUNK
            hi = min(lo + _CHUNK, n)
            a, b = _chunk_step(theta[lo:hi], p[lo:hi], S[lo:hi], C[lo:hi], h, dt, Fx, Fy)
            part_c[ch] = a
            part_s[ch] = b
        tc = 0.0
        ts = 0.0
        for ch in range(n_chunks):
            tc += part_c[ch]
            ts += part_s[ch]
        out[j, 0] = tc / max(n, 1)
        out[j, 1] = ts / max(n, 1)
        if field == 1:
            Fx = out[j, 0]
            Fy = out[j, 1]
        h = kick


@njit(fastmath=_FM)
def _kick(p, S, C, h, fx, fy):
    """Kick p += h (-fx sin theta + fy cos theta) with the stored S, C (re-synchronises p).

    Serial: it runs once per sampling interval (memory bound, ~1 ms for 5e5 particles)."""
    for i in range(p.size):
        p[i] = p[i] + h * (fy * C[i] - fx * S[i])


@njit(fastmath=_FM)
def _chunk_moments(p, S, C):
    a = 0.0
    b = 0.0
    c = 0.0
    d = 0.0
    for i in range(p.size):
        a += C[i]
        b += S[i]
        c += p[i]
        d += p[i] * p[i]
    return a, b, c, d


@njit
def _moments(p, S, C):
    """(mean cos, mean sin, mean p, mean p^2), chunked reduction (same chunks as the steps)."""
    n = p.size
    n_chunks = (n + _CHUNK - 1) // _CHUNK
    part = np.zeros((n_chunks, 4))
    for ch in range(n_chunks):
        lo = ch * _CHUNK
        hi = min(lo + _CHUNK, n)
        a, b, c, d = _chunk_moments(p[lo:hi], S[lo:hi], C[lo:hi])
        part[ch, 0] = a
        part[ch, 1] = b
        part[ch, 2] = c
        part[ch, 3] = d
    tot = np.zeros(4)
    for ch in range(n_chunks):
        for k in range(4):
            tot[k] += part[ch, k]
    return tot / max(n, 1)


class Particles:
    """Angles (wrapped to [-pi, pi)), momenta and the cached sin, cos of the angles."""

    def __init__(self, theta, p):
        self.theta = np.ascontiguousarray(sampling.wrap_angle(theta), dtype=np.float64)
        self.p = np.ascontiguousarray(p, dtype=np.float64).copy()
        self.S, self.C = sincos_wrapped_array(self.theta)

    def __len__(self):
        return self.theta.size

    def moments(self):
        """(Mx, My, mean p, mean p^2)."""
        return _moments(self.p, self.S, self.C)

    def steps(self, n_steps, dt, first_kick, kick, field, fx=0.0, fy=0.0, history=None):
        """n_steps fused steps (see `_kick_drift`); returns the (n_steps, 4) history array."""
        out = np.zeros((n_steps, 4)) if history is None else history
        _kick_drift(
            self.theta,
            self.p,
            self.S,
            self.C,
            float(first_kick),
            float(kick),
            float(dt),
            float(fx),
            float(fy),
            int(n_steps),
            int(field),
            out,
        )
        return out

    def kick(self, h, fx, fy):
        _kick(self.p, self.S, self.C, float(h), float(fx), float(fy))


def leapfrog(particles, n_steps, dt, field, fx=0.0, fy=0.0):
    """n_steps velocity-Verlet steps (p synchronised with theta at the end).

    field 'self': the particles' own magnetisation (eq. hmfmdfull); 'static': the constant
    field (fx, fy).  Returns the magnetisation after each step, shape (n_steps, 2)."""
    if n_steps < 1:
        return np.zeros((0, 2))
    if field == "self":
        m = particles.moments()
        out = particles.steps(n_steps, dt, 0.5 * dt, dt, 1, m[0], m[1])
        particles.kick(0.5 * dt, out[-1, 0], out[-1, 1])
    elif field == "static":
        out = particles.steps(n_steps, dt, 0.5 * dt, dt, 0, fx, fy)
        particles.kick(0.5 * dt, fx, fy)
    else:
        raise ValueError(f"field = {field!r}: must be 'self' or 'static'")
    return out[:, :2].copy()


# ---------------------------------------------------------------------------------------------
# actions (eq. hmfaction) by the arithmetic-geometric mean
# ---------------------------------------------------------------------------------------------
_AGM_ITERATIONS = 10  # enough for k' >= 1e-8, i.e. every kappa != 1 in double precision


@njit(fastmath=_FM)
def _action_of_kappa2(k2, sqrtM0):
    """(J, J-bar) of the orbit with kappa^2 = k2, eq. (hmfaction), branch-free (vectorises).

    K(m) = pi / (2 AGM(1, k')) and E = K (1 - m/2 - S), S = sum_{n>=1} 2^(n-1) c_n^2 with
    c_{n+1} = c_n^2 / (4 a_{n+1}) (Gauss-Legendre AGM, DLMF 19.8), a fixed number of steps.
    Librating (m = kappa^2): J = (8 sqrt(M0)/pi) [E - (1-m) K] = (8 sqrt(M0)/pi) K (m/2 - S),
    free of cancellation at small kappa; rotating (m = 1/kappa^2):
    J = (4 sqrt(M0)/pi) kappa E(m).  J-bar = J/2 on librating orbits.
    """
    lib = k2 < 1.0
    m = k2 if lib else 1.0 / k2
    m1 = 1.0 - k2 if lib else (k2 - 1.0) / k2
    a = 1.0
    b = math.sqrt(m1)
    c2 = m
    S = 0.0
    w = 0.5
    for _ in range(_AGM_ITERATIONS):
        a1 = 0.5 * (a + b)
        b = math.sqrt(a * b)
        cn = c2 / (4.0 * a1)
        a = a1
        c2 = cn * cn
        w *= 2.0
        S += w * c2
    K = math.pi / (2.0 * a)
    J_lib = 8.0 * sqrtM0 / math.pi * K * (0.5 * m - S)
    J_rot = 4.0 * sqrtM0 / math.pi * math.sqrt(k2) * K * (1.0 - 0.5 * m - S)
    J = J_lib if lib else J_rot
    J = 4.0 * sqrtM0 / math.pi if k2 == 1.0 else J
    Jbar = 0.5 * J if lib else J
    return J, Jbar


@njit(fastmath=_FM)
def _chunk_kappa_actions(kappa, sqrtM0, J, Jbar):
    for i in range(kappa.size):
        a, b = _action_of_kappa2(kappa[i] * kappa[i], sqrtM0)
        J[i] = a
        Jbar[i] = b


def action_numba(kappa, M0):
    """(J, J-bar) of orbits kappa with magnetisation M0 (numba, AGM); see orbits.action."""
    k = np.ascontiguousarray(kappa, dtype=np.float64).ravel()
    J = np.empty_like(k)
    Jb = np.empty_like(k)
    _chunk_kappa_actions(k, math.sqrt(M0), J, Jb)
    return J.reshape(np.shape(kappa)), Jb.reshape(np.shape(kappa))


@njit(fastmath=_FM)
def _chunk_phase_actions(theta, p, phase, M0, J, Jbar):
    """(J, J-bar) of a chunk of phase points; the AGM runs with the loops interchanged (each
    AGM step over the whole chunk) so that every loop vectorises."""
    n = theta.size
    sqrtM0 = math.sqrt(M0)
    inv4M0 = 1.0 / (4.0 * M0)
    k2 = np.empty(n)
    a = np.empty(n)
    b = np.empty(n)
    c2 = np.empty(n)
    S = np.zeros(n)
    for i in range(n):
        th = theta[i] - phase
        th = th - _TWO_PI * np.floor(th * _INV_TWO_PI + 0.5)
        s, _ = _sincos(0.5 * th)
        # kappa^2 = p^2/(4 M0) + sin^2(theta/2), free of the cancellation in h + M0
        q = p[i] * p[i] * inv4M0 + s * s
        k2[i] = q
        lib = q < 1.0
        c2[i] = q if lib else 1.0 / q  # c_0^2 = m
        b[i] = math.sqrt(1.0 - q if lib else (q - 1.0) / q)  # k'
        a[i] = 1.0
    w = 0.5
    for _ in range(_AGM_ITERATIONS):
        w *= 2.0
        tot = 0.0
        for i in range(n):
            # c_{n+1} = c_n^2 / (4 a_{n+1}) keeps relative precision ((a_n - b_n)/2 would
            # leave rounding noise ~1e-16 in c, amplified by 2^n in S at small kappa)
            a1 = 0.5 * (a[i] + b[i])
            b[i] = math.sqrt(a[i] * b[i])
            cn = c2[i] / (4.0 * a1)
            a[i] = a1
            c2[i] = cn * cn
            S[i] += w * c2[i]
            tot += c2[i]
        if tot < 1e-36:  # every c_n < 1e-18 < 1e-16 a_n (a_n > 0.07 for k' >= 1e-8): converged
            break
    for i in range(n):
        q = k2[i]
        lib = q < 1.0
        m = q if lib else 1.0 / q
        K = math.pi / (2.0 * a[i])
        J_lib = 8.0 * sqrtM0 / math.pi * K * (0.5 * m - S[i])
        J_rot = 4.0 * sqrtM0 / math.pi * math.sqrt(q) * K * (1.0 - 0.5 * m - S[i])
        Jv = J_lib if lib else J_rot
        Jv = 4.0 * sqrtM0 / math.pi if q == 1.0 else Jv
        J[i] = Jv
        Jbar[i] = 0.5 * Jv if lib else Jv


@njit(parallel=True)
def _phase_actions_kernel(theta, p, phase, M0, J, Jbar):
    n = theta.size
    n_chunks = (n + _CHUNK - 1) // _CHUNK
    for ch in prange(n_chunks):
        lo = ch * _CHUNK
        hi = min(lo + _CHUNK, n)
        _chunk_phase_actions(theta[lo:hi], p[lo:hi], phase, M0, J[lo:hi], Jbar[lo:hi])


def actions(theta, p, M0, phase=0.0, out=None):
    """(J, J-bar) of phase-space points, in the frame rotated by `phase` (numba, parallel)."""
    theta = np.ascontiguousarray(theta, dtype=np.float64)
    p = np.ascontiguousarray(p, dtype=np.float64)
    if out is None:
        out = (np.empty_like(theta), np.empty_like(theta))
    _phase_actions_kernel(theta, p, float(phase), float(M0), out[0], out[1])
    return out


# ---------------------------------------------------------------------------------------------
# <dJ^2> accumulator
# ---------------------------------------------------------------------------------------------
@njit(parallel=True)
def _accumulate_kernel(J, Jbar, slots, lags, blocks, J0, lib0, bin0, acc):
    """For each active origin a (slot slots[a], lag lags[a], block blocks[a]) add, per particle
    with bin0 >= 0: (J - J0)^2, (Jbar - Jbar0)^2, J - J0 and 1 into acc[:, bin, lag, block].

    Active origins have distinct lags, so the prange over origins never writes one cell twice;
    each cell sums its particles in index order (deterministic)."""
    n = J.size
    for a in prange(slots.size):
        sl = slots[a]
        L = lags[a]
        B = blocks[a]
        for i in range(n):
            b = bin0[sl, i]
            if b >= 0:
                j0 = J0[sl, i]
                jb0 = 0.5 * j0 if lib0[sl, i] else j0
                d = J[i] - j0
                db = Jbar[i] - jb0
                acc[0, b, L, B] += d * d
                acc[1, b, L, B] += db * db
                acc[2, b, L, B] += d
                acc[3, b, L, B] += 1.0


@njit
def _mark_seen(bins, seen):
    for i in range(bins.size):
        if bins[i] >= 0:
            seen[i, bins[i]] = 1


class DisplacementAccumulator:
    """Sums of squared action displacements per (J-bar_0 bin, lag, block of origins), eq. (dj2).

    Feed it the actions of all tracked particles at every sampling time index s = 0, 1, 2, ...
    with `add(s, J, Jbar)`.  An origin starts at every s that is a multiple of `origin_every`
    (in samples) while s + max_lag <= n_samples - 1, so every lag sees the same origins.  J(t0)
    is kept in a ring buffer of max_lag // origin_every + 1 slots (float64 J, an int16 bin and a
    librating flag per particle and slot).  Lags are 0 ... max_lag samples.
    """

    def __init__(self, n_track, jbar_edges, n_samples, max_lag, origin_every, n_blocks):
        self.edges = np.asarray(jbar_edges, dtype=float)
        self.n_bins = self.edges.size - 1
        if self.n_bins < 1 or np.any(np.diff(self.edges) <= 0):
            raise ValueError("jbar_edges must be increasing with at least 2 entries")
        if self.n_bins > 32767:
            raise ValueError("at most 32767 bins")
        self.n_track = int(n_track)
        self.n_samples = int(n_samples)
        self.max_lag = int(max_lag)
        self.origin_every = int(origin_every)
        self.n_origins = (self.n_samples - 1 - self.max_lag) // self.origin_every + 1
        if self.n_origins < 1:
            raise ValueError("the run is too short for one origin with the full lag window")
        self.n_blocks = int(n_blocks)
        if not 1 <= self.n_blocks <= self.n_origins:
            raise ValueError(
                f"n_blocks = {n_blocks} must lie in [1, number of origins = {self.n_origins}]"
            )
        self.n_slots = min(self.max_lag // self.origin_every + 1, self.n_origins)
        self.J0 = np.zeros((self.n_slots, self.n_track))
        self.lib0 = np.zeros((self.n_slots, self.n_track), dtype=np.bool_)
        self.bin0 = np.full((self.n_slots, self.n_track), -1, dtype=np.int16)
        self.acc = np.zeros((4, self.n_bins, self.max_lag + 1, self.n_blocks))
        self.seen = np.zeros((self.n_track, self.n_bins), dtype=np.uint8)
        self.origin_sample = np.arange(self.n_origins) * self.origin_every

    def block_of(self, origin):
        return origin * self.n_blocks // self.n_origins

    def bins_of(self, Jbar):
        b = np.searchsorted(self.edges, Jbar, side="right") - 1
        b[(b >= self.n_bins) | (Jbar < self.edges[0])] = -1
        b[Jbar == self.edges[-1]] = self.n_bins - 1
        return b.astype(np.int16)

    def add(self, s, J, Jbar):
        """Record the actions at sample index s (called for s = 0, 1, ... in order)."""
        if s % self.origin_every == 0 and s // self.origin_every < self.n_origins:
            o = s // self.origin_every
            sl = o % self.n_slots
            self.J0[sl] = J
            self.lib0[sl] = Jbar != J  # J-bar = J/2 on librating orbits
            self.bin0[sl] = self.bins_of(Jbar)
            _mark_seen(self.bin0[sl], self.seen)
        o_last = min(s // self.origin_every, self.n_origins - 1)
        o_first = max(0, -(-(s - self.max_lag) // self.origin_every))
        if o_last < o_first:
            return
        orig = np.arange(o_first, o_last + 1)
        lags = s - orig * self.origin_every
        keep = (lags >= 0) & (lags <= self.max_lag)
        orig, lags = orig[keep], lags[keep]
        if orig.size == 0:
            return
        slots = (orig % self.n_slots).astype(np.int64)
        blocks = np.array([self.block_of(o) for o in orig], dtype=np.int64)
        _accumulate_kernel(
            np.ascontiguousarray(J),
            np.ascontiguousarray(Jbar),
            slots,
            lags.astype(np.int64),
            blocks,
            self.J0,
            self.lib0,
            self.bin0,
            self.acc,
        )

    @property
    def n_particles_in_bin(self):
        return self.seen.sum(axis=0, dtype=np.int64)


# ---------------------------------------------------------------------------------------------
# driver
# ---------------------------------------------------------------------------------------------
def advance_system(dynamics, bath, test, M, n_steps, dt, M0, work=None):
    """Advance bath / interacting particles and test particles by n_steps velocity-Verlet steps.

    dynamics 'full': `bath` holds the N interacting particles (eq. hmfmdfull); 'bath': `bath`
    feels the static field M0 on x (eq. hmfmdbath).  Test particles (`test`, may be empty) feel
    the instantaneous magnetisation of `bath` without feeding back.  M is the magnetisation of
    `bath` on entry; returns it after the steps.  p is synchronised with theta on return.
    """
    if n_steps < 1:
        return M
    if work is None or work[0].shape[0] < n_steps:
        work = (np.zeros((n_steps, 4)), np.zeros((n_steps, 4)))
    out = work[0][:n_steps]
    h = 0.5 * dt
    if dynamics == "full":
        bath.steps(n_steps, dt, h, dt, 1, M[0], M[1], out)  # eq. hmfmdfull
    else:
        bath.steps(n_steps, dt, h, dt, 0, M0, 0.0, out)  # static field M0 on x
    if len(test):
        # test particles at step j feel the magnetisation before step j (eq. hmfmdbath)
        e = work[1][:n_steps]
        e[0, 2:] = M
        e[1:, 2:] = out[:-1, :2]
        test.steps(n_steps, dt, h, dt, 2, 0.0, 0.0, e)
    M = out[n_steps - 1, :2].copy()
    if dynamics == "full":
        bath.kick(h, M[0], M[1])
    else:
        bath.kick(h, M0, 0.0)
    if len(test):
        test.kick(h, M[0], M[1])
    return M


def _default_progress(msg):
    print(msg, file=sys.stderr, flush=True)


def _multiple(name, value, unit_name, unit):
    k = int(round(value / unit))
    if k < 1 or abs(k * unit - value) > 1e-9 * max(abs(value), unit):
        raise ValueError(
            f"{name} = {value!r} must be a positive integer multiple of {unit_name} = {unit!r}"
        )
    return k


def _validate(
    state,
    dynamics,
    n_particles,
    n_test,
    test_sampling,
    jbar_range,
    dt,
    t_max,
    t_equilibrate,
    sample_every,
    max_lag,
    origin_every,
    jbar_edges,
    threads,
    n_blocks,
):
    if dynamics not in ("bath", "full"):
        raise ValueError(f"dynamics = {dynamics!r}: must be 'bath' or 'full'")
    if not hasattr(state, "M0") or not 0.0 < state.M0 < 1.0:
        raise ValueError("state must be an equilibrium state with 0 < M0 < 1")
    for name, v, lo in (("n_particles", n_particles, 1), ("n_test", n_test, 0)):
        if isinstance(v, bool) or int(v) != v or v < lo:
            raise ValueError(f"{name} = {v!r} must be an integer >= {lo}")
    if dynamics == "bath" and n_test < 1:
        raise ValueError("dynamics 'bath' tracks test particles only: n_test must be >= 1")
    if test_sampling not in ("f", "uniform"):
        raise ValueError(f"test_sampling = {test_sampling!r}: must be 'f' or 'uniform'")
    if test_sampling == "uniform" and n_test > 0:
        if jbar_range is None or len(jbar_range) != 2 or not 0 <= jbar_range[0] < jbar_range[1]:
            raise ValueError(
                f"jbar_range = {jbar_range!r}: test_sampling 'uniform' needs "
                "(Jbar_min, Jbar_max) with 0 <= Jbar_min < Jbar_max"
            )
    for name, v in (
        ("dt", dt),
        ("t_max", t_max),
        ("sample_every", sample_every),
        ("max_lag", max_lag),
        ("origin_every", origin_every),
    ):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v!r} must be finite and > 0")
    if not (np.isfinite(t_equilibrate) and t_equilibrate >= 0):
        raise ValueError(f"t_equilibrate = {t_equilibrate!r} must be finite and >= 0")
    if max_lag > t_max:
        raise ValueError(f"max_lag = {max_lag!r} must be <= t_max = {t_max!r}")
    n_sub = _multiple("sample_every", sample_every, "dt", dt)
    n_lag = _multiple("max_lag", max_lag, "sample_every", sample_every)
    n_orig = _multiple("origin_every", origin_every, "sample_every", sample_every)
    n_samp = _multiple("t_max", t_max, "sample_every", sample_every)
    n_eq = 0 if t_equilibrate == 0 else _multiple("t_equilibrate", t_equilibrate, "dt", dt)
    edges = np.asarray(jbar_edges, dtype=float)
    if (
        edges.ndim != 1
        or edges.size < 2
        or np.any(~np.isfinite(edges))
        or np.any(np.diff(edges) <= 0)
        or edges[0] < 0
    ):
        raise ValueError("jbar_edges must be a finite increasing 1-d array (>= 2 values, >= 0)")
    if (
        isinstance(threads, bool)
        or int(threads) != threads
        or not (1 <= threads <= numba.config.NUMBA_NUM_THREADS)
    ):
        raise ValueError(
            f"threads = {threads!r} must be an integer in [1, {numba.config.NUMBA_NUM_THREADS}]"
        )
    n_origins = (n_samp - n_lag) // n_orig + 1
    if isinstance(n_blocks, bool) or int(n_blocks) != n_blocks or not 1 <= n_blocks <= n_origins:
        raise ValueError(
            f"n_blocks = {n_blocks!r} must be an integer in [1, number of origins = {n_origins}]"
        )
    return n_sub, n_lag, n_orig, n_samp, n_eq, edges


def run_md(
    state,
    *,
    dynamics,
    n_particles,
    n_test=0,
    test_sampling="f",
    jbar_range=None,
    dt,
    t_max,
    t_equilibrate=0.0,
    sample_every,
    max_lag,
    origin_every,
    jbar_edges,
    seed,
    member=0,
    threads=1,
    n_blocks=10,
    n_store=16,
    zero_momentum=True,
    progress=_default_progress,
    progress_every=5.0,
):
    """Run MD(bath) or MD(full) and accumulate <dJ^2> per J-bar_0 bin and lag (eq. dj2).

    Times: the run integrates t_equilibrate (no measurement), then t_max of production with
    samples every `sample_every` (t = 0 is the start of production).  Origins every
    `origin_every`, lags 0 ... max_lag.  Tracked particles: the n_test test particles for
    'bath'; the n_particles particles and the n_test test particles for 'full'.

    Initial conditions: `sampling.sample_state` (exact thermal sampler for thermal states, the
    kappa marginal otherwise) for the bath / interacting particles; test particles from f
    ('f') or uniform in J-bar over `jbar_range` ('uniform').  All angles are then rotated so
    that the magnetisation of the interacting particles lies on x; for 'full' with
    zero_momentum, their mean momentum is subtracted (test particles are left as drawn).

    Parameters
    ----------
    state : equilibrium state (ThermalState, CoreHaloState) with .M0 and .f; M0 is the static
        field of the bath and the magnetisation used for every action.
    dynamics : 'bath' (eq. hmfmdbath) or 'full' (eq. hmfmdfull).
    n_particles : N_b bath particles ('bath') or N interacting particles ('full'), >= 1.
    n_test : test particles (>= 1 for 'bath'); test_sampling 'f' or 'uniform' (needs
        jbar_range = (Jbar_min, Jbar_max)).
    dt : time step (> 0); sample_every, t_max, t_equilibrate: integer multiples of dt;
        max_lag, origin_every, t_max: integer multiples of sample_every, max_lag <= t_max.
    jbar_edges : increasing edges of the bins of the initial rescaled action J-bar(t0).
    seed, member : the generator is default_rng(SeedSequence([seed, member])).
    threads : numba threads (numba.set_num_threads); results do not depend on it.
    n_blocks : contiguous blocks of origins for error estimates (1 <= n_blocks <= origins).
    n_store : number of tracked particles whose (theta, p, J) are stored for illustration.
    zero_momentum : 'full' only: subtract the mean momentum of the N particles at t = 0.
    progress : callable(message) called about every `progress_every` seconds of wall time
        (default: print to stderr), or None.

    Returns an xarray.Dataset: sums per (bin, lag) and per (bin, lag, block) of
    (J(t0+lag) - J(t0))^2, (Jbar(t0+lag) - Jbar(t0))^2, J(t0+lag) - J(t0) and counts over
    (origin, particle) pairs; <dJ^2> = sum_dJ2 / count (use ds["count"]: ds.count is a
    method); time series Mx, My, energy, momentum; a few stored trajectories; attributes with
    every parameter.
    """
    n_sub, n_lag, n_orig, n_samp, n_eq, edges = _validate(
        state,
        dynamics,
        n_particles,
        n_test,
        test_sampling,
        jbar_range,
        dt,
        t_max,
        t_equilibrate,
        sample_every,
        max_lag,
        origin_every,
        jbar_edges,
        threads,
        n_blocks,
    )
    if progress is None:
        progress = lambda msg: None  # noqa: E731
    n_particles, n_test = int(n_particles), int(n_test)
    M0 = float(state.M0)
    wall0 = _time.perf_counter()
    numba.set_num_threads(int(threads))

    # ---- initial conditions ----
    rng = sampling.make_rng(seed, member)
    th_b, p_b = sampling.sample_state(state, n_particles, rng)
    if n_test > 0:
        if test_sampling == "f":
            th_t, p_t = sampling.sample_state(state, n_test, rng)
        else:
            th_t, p_t = sampling.sample_uniform_jbar(M0, n_test, jbar_range, rng)
    else:
        th_t, p_t = np.zeros(0), np.zeros(0)
    th_b, th_t, phase0 = sampling.rotate_to_x_axis(th_b, th_t)
    if dynamics == "full" and zero_momentum:
        p_b = p_b - p_b.mean()
    bath = Particles(th_b, p_b)  # bath (MD bath) or interacting particles (MD full)
    test = Particles(th_t, p_t)

    n_track = n_particles + n_test if dynamics == "full" else n_test
    acc = DisplacementAccumulator(n_track, edges, n_samp + 1, n_lag, n_orig, n_blocks)
    n_store = min(int(n_store), n_track)
    store_idx = np.unique(np.linspace(0, n_track - 1, n_store).astype(np.int64))

    # ---- integration: velocity Verlet, p synchronised with theta after each call ----
    M = bath.moments()[:2].copy()  # magnetisation of the bath / interacting particles
    work = (np.zeros((max(n_sub, 1), 4)), np.zeros((max(n_sub, 1), 4)))

    def advance(n_steps):
        nonlocal M
        M = advance_system(dynamics, bath, test, M, n_steps, dt, M0, work)

    J = np.empty(n_track)
    Jb = np.empty(n_track)
    n_times = n_samp + 1
    ts = {k: np.zeros(n_times) for k in ("Mx", "My", "energy", "momentum")}
    store_th = np.zeros((n_times, store_idx.size))
    store_p = np.zeros_like(store_th)
    store_J = np.zeros_like(store_th)
    st_b = store_idx[store_idx < len(bath)] if dynamics == "full" else store_idx[:0]
    st_t = store_idx[store_idx >= len(bath)] - len(bath) if dynamics == "full" else store_idx

    def measure(s):
        mom = bath.moments()
        ts["Mx"][s], ts["My"][s] = mom[0], mom[1]
        ts["momentum"][s] = mom[2]
        if dynamics == "full":
            ts["energy"][s] = 0.5 * mom[3] - 0.5 * (mom[0] ** 2 + mom[1] ** 2)
            phase = math.atan2(mom[1], mom[0])
            actions(bath.theta, bath.p, M0, phase, (J[:n_particles], Jb[:n_particles]))
            if n_test:
                actions(test.theta, test.p, M0, phase, (J[n_particles:], Jb[n_particles:]))
        else:
            ts["energy"][s] = 0.5 * mom[3] - M0 * mom[0]
            phase = 0.0
            actions(test.theta, test.p, M0, 0.0, (J, Jb))
        th_st = np.concatenate([bath.theta[st_b], test.theta[st_t]])
        store_th[s] = sampling.wrap_angle(th_st - phase)
        store_p[s] = np.concatenate([bath.p[st_b], test.p[st_t]])
        store_J[s] = J[store_idx]
        acc.add(s, J, Jb)

    # ---- run ----
    n_total_steps = n_eq + n_samp * n_sub
    n_all = n_particles + n_test
    t_start = _time.perf_counter()
    last = [t_start, 0]  # wall time and steps at the last report
    steps_done = 0

    def report(tsim):
        now = _time.perf_counter()
        if now - last[0] >= progress_every:
            rate = (steps_done - last[1]) * n_all / max(now - last[0], 1e-9)
            progress(
                f"run_md[{dynamics}] t = {tsim:.6g} / {t_equilibrate + t_max:.6g} "
                f"({100.0 * steps_done / n_total_steps:.1f}%), {rate:.3g} particle-steps/s "
                "(including measurements)"
            )
            last[0], last[1] = now, steps_done

    remaining = n_eq
    while remaining > 0:
        k = min(remaining, work[0].shape[0])
        advance(k)
        remaining -= k
        steps_done += k
        report(steps_done * dt)
    measure(0)
    for s in range(1, n_samp + 1):
        advance(n_sub)
        steps_done += n_sub
        measure(s)
        report(t_equilibrate + s * sample_every)
    wall = _time.perf_counter() - wall0
    progress(
        f"run_md[{dynamics}] done in {wall:.1f} s wall, "
        f"{steps_done * n_all / max(_time.perf_counter() - t_start, 1e-9):.3g} "
        "particle-steps/s"
    )

    return _to_dataset(
        state,
        acc,
        ts,
        store_idx,
        store_th,
        store_p,
        store_J,
        locals_=dict(
            dynamics=dynamics,
            n_particles=n_particles,
            n_test=n_test,
            test_sampling=test_sampling,
            jbar_range=jbar_range,
            dt=dt,
            t_max=t_max,
            t_equilibrate=t_equilibrate,
            sample_every=sample_every,
            max_lag=max_lag,
            origin_every=origin_every,
            seed=seed,
            member=member,
            threads=threads,
            n_blocks=n_blocks,
            zero_momentum=zero_momentum,
            wall=wall,
            phase0=phase0,
            M0=M0,
            n_track=n_track,
        ),
    )


def _to_dataset(state, acc, ts, store_idx, store_th, store_p, store_J, locals_):
    g = locals_
    edges = acc.edges
    lag = np.arange(acc.max_lag + 1) * g["sample_every"]
    time = np.arange(store_th.shape[0]) * g["sample_every"]
    a = acc.acc
    dims3 = ("bin", "lag", "block")
    a1 = "action (dimensionless HMF units)"

    def v(dims, data, units, long_name):
        return xr.Variable(dims, data, {"units": units, "long_name": long_name})

    if g["dynamics"] == "full":
        e_def = "H/N = sum p^2/(2N) - (Mx^2 + My^2)/2 of the N interacting particles"
    else:
        e_def = (
            "mean one-particle energy of the bath in the static field, "
            "sum (p^2/2 - M0 cos theta)/N_b (conserved by the bath dynamics)"
        )
    ds = xr.Dataset(
        {
            "sum_dJ2": v(
                ("bin", "lag"),
                a[0].sum(-1),
                f"{a1}^2",
                "sum over origins and particles of (J(t0+lag) - J(t0))^2",
            ),
            "sum_dJbar2": v(
                ("bin", "lag"),
                a[1].sum(-1),
                f"{a1}^2",
                "sum over origins and particles of (Jbar(t0+lag) - Jbar(t0))^2",
            ),
            "sum_dJ": v(
                ("bin", "lag"),
                a[2].sum(-1),
                a1,
                "sum over origins and particles of J(t0+lag) - J(t0)",
            ),
            "count": v(
                ("bin", "lag"),
                a[3].sum(-1).astype(np.int64),
                "1",
                "number of (origin, particle) pairs in the sums",
            ),
            "sum_dJ2_block": v(dims3, a[0], f"{a1}^2", "sum_dJ2 restricted to a block of origins"),
            "sum_dJbar2_block": v(
                dims3, a[1], f"{a1}^2", "sum_dJbar2 restricted to a block of origins"
            ),
            "sum_dJ_block": v(dims3, a[2], a1, "sum_dJ restricted to a block of origins"),
            "count_block": v(
                dims3, a[3].astype(np.int64), "1", "count restricted to a block of origins"
            ),
            "n_particles_in_bin": v(
                ("bin",),
                acc.n_particles_in_bin,
                "1",
                "number of distinct particles in the bin at any origin",
            ),
            "n_origins_in_block": v(
                ("block",),
                np.bincount(
                    [acc.block_of(o) for o in range(acc.n_origins)], minlength=acc.n_blocks
                ),
                "1",
                "number of time origins in the block",
            ),
            "Mx": v(
                ("time",),
                ts["Mx"],
                "1",
                "magnetisation x component of the bath / interacting particles",
            ),
            "My": v(
                ("time",),
                ts["My"],
                "1",
                "magnetisation y component of the bath / interacting particles",
            ),
            "energy": v(("time",), ts["energy"], "energy per particle", e_def),
            "momentum": v(
                ("time",),
                ts["momentum"],
                "momentum per particle",
                "total momentum per particle sum p_i / N of the bath / interacting particles",
            ),
            "sample_theta": v(
                ("time", "tracer"),
                store_th,
                "rad",
                "angle of sample tracked particles in the action frame",
            ),
            "sample_p": v(("time", "tracer"), store_p, "1", "momentum of sample tracked particles"),
            "sample_J": v(("time", "tracer"), store_J, a1, "action J of sample tracked particles"),
        },
        coords={
            "jbar_edges": v(("edge",), edges, a1, "edges of the bins of initial rescaled action"),
            "jbar0": v(
                ("bin",),
                0.5 * (edges[1:] + edges[:-1]),
                a1,
                "bin centre of the initial rescaled action Jbar(t0)",
            ),
            "lag": v(("lag",), lag, "time (1/sqrt(M=1) units)", "time lag Delta t"),
            "time": v(("time",), time, "time", "time since the start of production"),
            "block": v(
                ("block",), np.arange(acc.n_blocks), "1", "block of consecutive time origins"
            ),
            "tracer": v(("tracer",), store_idx, "1", "index of the stored tracked particle"),
        },
    )
    ds.attrs.update(
        {
            "dynamics": g["dynamics"],
            "N": g["n_particles"],
            "n_test": g["n_test"],
            "n_tracked": g["n_track"],
            "test_sampling": g["test_sampling"] if g["n_test"] else "none",
            "jbar_range": "none"
            if g["jbar_range"] is None
            else np.asarray(g["jbar_range"], dtype=float),
            "dt": float(g["dt"]),
            "t_max": float(g["t_max"]),
            "t_equilibrate": float(g["t_equilibrate"]),
            "sample_every": float(g["sample_every"]),
            "origin_every": float(g["origin_every"]),
            "max_lag": float(g["max_lag"]),
            "n_origins": acc.n_origins,
            "n_blocks": acc.n_blocks,
            "integrator": INTEGRATOR,
            "seed": int(g["seed"]),
            "member": int(g["member"]),
            "threads": int(g["threads"]),
            "M0_actions": g["M0"],
            "action_frame": (
                "frame of the instantaneous magnetisation of the N particles"
                if g["dynamics"] == "full"
                else "fixed frame (static field on x)"
            ),
            "energy_definition": e_def,
            "zero_momentum": int(bool(g["zero_momentum"]) and g["dynamics"] == "full"),
            "initial_rotation": g["phase0"],
            "wall_time_s": g["wall"],
            "state_kind": getattr(state, "kind", type(state).__name__),
            "mean_dJ2": "sum_dJ2 / count; D_dif = slope / 2 (eq. hmfmddif)",
        }
    )
    return ds
