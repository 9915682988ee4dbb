"""Vectorisable elementary kernels of the MD: sin/cos polynomials and actions by the AGM.

sin and cos of the drift angle dt p of one step come from short polynomials in float32, the
MD state's precision (`_sincos_drift32`, |dt p| <= DRIFT_MAX, within about one ulp and without
a systematic error: see below), those of a wrapped angle from a branch-free
half-angle polynomial (`_sincos_wrapped`, absolute error < 6e-16), so that the particle loops
vectorise; a general
vectorisable sincos (`_sincos`: quadrant reduction with a three-part pi/2, error ~1 ulp for |x|
up to ~1e5) serves the action evaluation.  Both are tested against numpy.

Actions (eq. hmfaction): J and J-bar of particles at (theta, p), with the static M0, in a frame
rotated by `phase` (`actions`), the same from (sin theta, cos theta, p) as the MD's particles
carry them (`frame_actions`), or of orbit labels kappa (`actions_from_kappa`).  Both go
through one arithmetic-geometric-mean routine (`_agm_actions`, the J formulas written once).
The library's definition of J stays `hmfdiff.meanfield.orbits.action` (scipy's elliptic
integrals, used by the sampler and the theory); the compiled AGM matches it to ~1e-15 relative
(tests/test_md.py) and exists because the MD evaluates it for every particle at every sample.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from .jit import njit

__all__ = [
    "DRIFT_MAX",
    "sincos_array",
    "sincos_wrapped_array",
    "sincos_drift_array",
    "actions_from_kappa",
    "actions",
    "frame_actions",
    "angles",
]

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

# sin and cos of the drift angle d = dt p of one step, in the float32 of the MD's state
# (`integrator.STATE_DTYPE`): sin d = d + d z S(z), cos d = 1 + z (-1/2 + z C(z)), z = d^2, on
# |d| <= DRIFT_MAX with S of degree 2 and C of degree 2 (the degrees of the Taylor series through
# d^7 and d^8), on |d| <= DRIFT_SHORT (the drift angles of the MD at dt = 0.05, |p| < 4) one
# degree less in each.  Their float32 coefficients are fitted, not Taylor's: least squares of the
# relative error of sin d and the absolute error of cos d at 400 Chebyshev nodes of z in 40-digit
# arithmetic, each coefficient rounded to float32 before the next ones are refitted
# (studies/drift_polynomials.py).  In exact arithmetic they err by < 3.7e-11 (sin) and 3.4e-12
# (cos) on |d| <= DRIFT_MAX, < 9e-11 and 1.5e-12 on |d| <= DRIFT_SHORT, far below float32's half
# ulp (3e-8 near 1), so that what is left is the rounding of the float32 evaluation, which has no
# sign.  Why it matters: the rotation's error changes the norm of (sin theta, cos theta), the
# particle's coupling to the field, and a norm error of one sign, correlated with the particle's
# place in the well, makes the energy drift.  The Taylor polynomials used before erred so: sin
# through d^7 reads sin d low by d^9/9! (-2.9e-9 on average over 0.4 < |d| < 0.5), and cos d
# evaluated as (1 - z/2) + z^2 C(z), its first sum rounded before the quartic term is added, lost
# that term for |d| < 0.03 (cos d read low by 4.9e-9 on average there): the relaxation ensembles
# lost energy at 1e-9 per unit time (studies/energy_drift.py).  The Horner form rounds
# 1 + z (-1/2 + ...) once, after its small terms are summed.
DRIFT_MAX = 0.5
DRIFT_SHORT = 0.2
_DS1, _DS2, _DS3 = (
    np.float32(-0.1666666567325592),
    np.float32(0.008333118632435799),
    np.float32(-0.0001970301236724481),
)
_DC2, _DC3, _DC4 = (
    np.float32(0.0416666641831398),
    np.float32(-0.0013888520188629627),
    np.float32(2.462497286614962e-05),
)
_DS1s, _DS2s = np.float32(-0.16666652262210846), np.float32(0.008322078734636307)
_DC2s, _DC3s = np.float32(0.04166664183139801), np.float32(-0.0013872907729819417)
_MINUS_HALF_F = np.float32(-0.5)
_ONE_F = np.float32(1.0)

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


@njit(fastmath={"contract"})
def _sincos_drift32(d):
    """(sin d, cos d) of a float32 d, |d| <= DRIFT_MAX, in float32 (the MD's step): fitted
    polynomials, no range reduction; within about one ulp, with no systematic error beyond
    4e-11 (tests/test_drift_rotation.py).  cos in Horner form: 1 + z (-1/2 + z C(z)) is rounded
    once, after its small terms are summed."""
    z = d * d
    s = d + d * z * (_DS1 + z * (_DS2 + z * _DS3))
    c = _ONE_F + z * (_MINUS_HALF_F + z * (_DC2 + z * (_DC3 + z * _DC4)))
    return s, c


@njit(fastmath={"contract"})
def _sincos_drift32_short(d):
    """(sin d, cos d) of a float32 d, |d| <= DRIFT_SHORT, in float32: one degree less than
    `_sincos_drift32` in each."""
    z = d * d
    s = d + d * z * (_DS1s + z * _DS2s)
    c = _ONE_F + z * (_MINUS_HALF_F + z * (_DC2s + z * _DC3s))
    return s, c


@njit(fastmath=_FM)
def _sincos_drift32_kernel(x, s_out, c_out, short):
    for i in range(x.size):
        s, c = _sincos_drift32_short(x[i]) if short else _sincos_drift32(x[i])
        s_out[i] = s
        c_out[i] = c


def sincos_drift_array(x, short=False):
    """(sin x, cos x) in float32 by the polynomials of the MD's drift rotation, for x
    rounded to float32, |x| <= DRIFT_MAX (short: the shorter ones, for |x| <= DRIFT_SHORT)
    (exposed for tests)."""
    x = np.ascontiguousarray(x, dtype=np.float32).ravel()
    s, c = np.empty_like(x), np.empty_like(x)
    _sincos_drift32_kernel(x, s, c, bool(short))
    return s, c


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


# ---------------------------------------------------------------------------------------------
# actions (eq. hmfaction) by the arithmetic-geometric mean
# ---------------------------------------------------------------------------------------------
_AGM_ITERATIONS = 10  # enough for k' >= 1e-8, i.e. every kappa != 1 in double precision


@njit(fastmath=_FM)
def _agm_actions(k2, sqrtM0, J, Jbar):
    """(J, J-bar) of the orbits with kappa^2 = k2 (a chunk), eq. (hmfaction): the one AGM
    evaluation of the library's compiled code.

    K(m) = pi / (2 AGM(1, k')) and E = K (1 - m/2 - S), S = sum_{n>=1} 2^(n-1) c_n^2 with
    c_{n+1} = c_n^2 / (4 a_{n+1}) (Gauss-Legendre AGM, DLMF 19.8).  Librating (m = kappa^2):
    J = (8 sqrt(M0)/pi) [E - (1-m) K] = (8 sqrt(M0)/pi) K (m/2 - S), free of cancellation at
    small kappa; rotating (m = 1/kappa^2): J = (4 sqrt(M0)/pi) kappa E(m); J-bar = J/2 on
    librating orbits.  The AGM runs with the loops interchanged (each step over the whole
    chunk), so that every loop vectorises, and stops when every c_n has converged.
    """
    n = k2.size
    a = np.empty(n)
    b = np.empty(n)
    c2 = np.empty(n)
    S = np.zeros(n)
    for i in range(n):
        q = k2[i]
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
        # every c_n < 1e-10: a_n is the AGM to c_{n+1} ~ c_n^2/(4 a) < 1e-18 relative (a_n > 0.07
        # for k' >= 1e-8) and the omitted terms 2^n c_{n+1}^2 of S are < 1e-35: converged
        if tot < 1e-20:
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


@njit(fastmath=_FM)
def _chunk_phase_actions(theta, p, phase, M0, J, Jbar):
    """(J, J-bar) of a chunk of phase points (theta, p) in the frame rotated by `phase`."""
    n = theta.size
    inv4M0 = 1.0 / (4.0 * M0)
    k2 = np.empty(n)
    for i in range(n):
        th = theta[i] - phase
        th = th - _TWO_PI * np.floor(th * _INV_TWO_PI + 0.5)
        s, _ = _sincos(0.5 * th)
        # kappa^2 = p^2/(4 M0) + sin^2(theta/2), free of the cancellation in h + M0
        k2[i] = p[i] * p[i] * inv4M0 + s * s
    _agm_actions(k2, math.sqrt(M0), J, Jbar)


@njit(fastmath=_FM)
def _chunk_frame_actions(S, C, p, index, cphi, sphi, M0, J, Jbar):
    """(J, J-bar) of the phase points index[k] (a chunk) given by sin theta, cos theta and p
    (float32 or float64, read in place: arithmetic in float64), in the frame rotated by the
    angle phi (cos phi, sin phi): x = theta - phi, cos x = C cos phi + S sin phi,
    sin x = S cos phi - C sin phi, both divided by the norm of (S, C)."""
    n = index.size
    inv4M0 = 1.0 / (4.0 * M0)
    k2 = np.empty(n)
    for k in range(n):
        i = index[k]
        c = C[i] * cphi + S[i] * sphi
        s = S[i] * cphi - C[i] * sphi
        r2 = c * c + s * s
        cr = c * math.sqrt(r2)
        # sin^2(x/2) = (1 - cos x)/2, or sin^2 x / (2 (1 + cos x)) where cos x > 0: no
        # cancellation on either side (deeply trapped orbits have x ~ 0)
        half = (r2 - cr) / (2.0 * r2) if c <= 0.0 else s * s / (2.0 * (r2 + cr))
        pi = np.float64(p[i])
        k2[k] = pi * pi * inv4M0 + half
    _agm_actions(k2, math.sqrt(M0), J, Jbar)


@njit(parallel=True)
def _frame_actions_kernel(S, C, p, index, cphi, sphi, M0, J, Jbar):
    n = index.size
    n_chunks = (n + _CHUNK - 1) // _CHUNK
    for ch in prange(n_chunks):
        lo = ch * _CHUNK
        hi = min(lo + _CHUNK, n)
        _chunk_frame_actions(S, C, p, index[lo:hi], cphi, sphi, M0, J[lo:hi], Jbar[lo:hi])


def frame_actions(S, C, p, M0, phase=0.0, out=None, index=None):
    """(J, J-bar) of phase-space points given by (sin theta, cos theta, p), in the frame rotated
    by `phase` (numba, parallel): what the MD measures, whose particles carry sin and cos of
    their angles rather than the angles.  Agrees with `actions` to rounding.

    index: the points to evaluate, in this order (default: all); S, C, p are read in place
    (float32, the MD's state, or float64; no copy): the MD's tracked subset costs no gather."""
    dtype = np.float32 if all(np.asarray(a).dtype == np.float32 for a in (S, C, p)) else np.float64
    S, C, p = (np.ascontiguousarray(a, dtype=dtype).ravel() for a in (S, C, p))
    if index is None:
        index = np.arange(p.size, dtype=np.int64)
    else:
        index = np.ascontiguousarray(index, dtype=np.int64)
        if index.size and not (0 <= index.min() and index.max() < p.size):
            raise IndexError(f"index must lie in [0, {p.size})")
    if out is None:
        out = (np.empty(index.size), np.empty(index.size))
    phase = float(phase)
    _frame_actions_kernel(
        S, C, p, index, math.cos(phase), math.sin(phase), float(M0), out[0], out[1]
    )
    return out


@njit(parallel=True)
def _angles_kernel(S, C, out):
    n = S.size
    for i in prange(n):
        out[i] = math.atan2(S[i], C[i])


def angles(S, C):
    """The angles theta in [-pi, pi) of points given by (sin theta, cos theta)."""
    S = np.ascontiguousarray(S, dtype=np.float64)
    C = np.ascontiguousarray(C, dtype=np.float64)
    out = np.empty(S.shape)
    _angles_kernel(S.ravel(), C.ravel(), out.ravel())
    out[out >= math.pi] -= _TWO_PI
    return out


@njit(parallel=True)
def _kappa_actions_kernel(kappa, sqrtM0, J, Jbar):
    n = kappa.size
    n_chunks = (n + _CHUNK - 1) // _CHUNK
    for ch in prange(n_chunks):
        lo = ch * _CHUNK
        hi = min(lo + _CHUNK, n)
        _agm_actions(kappa[lo:hi] * kappa[lo:hi], sqrtM0, J[lo:hi], Jbar[lo:hi])


def actions_from_kappa(kappa, M0):
    """(J, J-bar) of the orbits kappa with magnetisation M0 (compiled AGM; the reference is
    `hmfdiff.meanfield.orbits.action`, which it matches to ~1e-15 relative)."""
    k = np.ascontiguousarray(kappa, dtype=np.float64).ravel()
    J = np.empty_like(k)
    Jb = np.empty_like(k)
    _kappa_actions_kernel(k, math.sqrt(M0), J, Jb)
    return J.reshape(np.shape(kappa)), Jb.reshape(np.shape(kappa))


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
