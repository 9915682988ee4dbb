"""The MD kernels as hmfdiff ran them until 2026-11-27, kept as the baselines that
benchmarks/bench_md.py and bench_ensemble.py measure the present kernels against in the same
run (issue 23 part 2): the angle stored and its half-angle sincos evaluated every step (about
36 floating-point operations and 32 bytes per particle and step), where the present kernels
rotate (sin theta, cos theta) by the drift angle (`hmfdiff.dynamics.integrator`); and the
<dJ^2> accumulator as it ran until 2026-11-27 (`PreviousDisplacementAccumulator`: every
(origin, particle) pair added into its bin's cell, in particle index order), where the present
one keeps each origin's particles sorted by bin and in the order of their J-bar.

Also the float32 step as it ran until issue 39 (`full_steps_float32_taylor`,
`ensemble_steps_float32_taylor`): the present kernels' arithmetic but for the drift's sincos
by float32 Taylor polynomials and the kick p + h (Fy C - Fx S) with h rounded to float32, the
two roundings with a sign that made its energy drift; they give the library's kernels of
before to the bit (checked against them when written: p, sin, cos and M after 100-300 steps
of `advance_system` and `Ensemble.advance`).

And what an MD job paid around the kernels until 2026-11-28 (benchmarks/bench_md_job.py): the
ensemble's set-up with the kappa marginal's table recomputed per realisation
(`initial_ensemble_per_realisation_table`), and the orbit functions and the exact bath's set-up
that evaluated both branches of K and J everywhere (`previous_orbits`).
"""

from __future__ import annotations

import contextlib

import numba
import numpy as np

from hmfdiff.dynamics import accumulator, elementary, integrator

_CHUNK = elementary._CHUNK


@numba.njit(fastmath=elementary._FM)
def _chunk_step(theta, p, S, C, h, dt, Fx, Fy):
    """One fused leapfrog step of a chunk: kick, drift of the stored angle, its sincos."""
    sc = 0.0
    ss = 0.0
    for i in range(theta.size):
        pi_ = p[i] + h * (Fy * C[i] - Fx * S[i])
        th = theta[i] + dt * pi_
        th = th - elementary._TWO_PI * np.floor(th * elementary._INV_TWO_PI + 0.5)
        s2, c2 = elementary._sincos_wrapped(th)
        sc += c2
        ss += s2
        p[i] = pi_
        theta[i] = th
        S[i] = s2
        C[i] = c2
    return sc, ss


@numba.njit(parallel=True)
def full_steps(theta, p, S, C, n_steps, dt, fx, fy):
    """n_steps fused MD(full) leapfrog steps of one system (chunked, deterministic reduction);
    returns the last (Mx, My)."""
    n = theta.size
    n_chunks = (n + _CHUNK - 1) // _CHUNK
    part_c = np.zeros(n_chunks)
    part_s = np.zeros(n_chunks)
    h = 0.5 * dt
    for _ in range(n_steps):
        for ch in numba.prange(n_chunks):
            lo = ch * _CHUNK
            hi = min(lo + _CHUNK, n)
            a, b = _chunk_step(theta[lo:hi], p[lo:hi], S[lo:hi], C[lo:hi], h, dt, fx, fy)
            part_c[ch] = a
            part_s[ch] = b
        tc = 0.0
        ts = 0.0
        for ch in range(n_chunks):
            tc += part_c[ch]
            ts += part_s[ch]
        fx = tc / n
        fy = ts / n
        h = dt
    return fx, fy


@numba.njit(fastmath={"contract"}, parallel=True)
def ensemble_steps(theta, p, S, C, M, n_steps, dt):
    """n_steps MD(full) leapfrog steps of every realisation (rows), in place, M[r] its
    magnetisation on entry and exit; the closing half kick at the end."""
    R, N = theta.shape
    h = 0.5 * dt
    for r in numba.prange(R):
        fx = M[r, 0]
        fy = M[r, 1]
        kick = h
        for _ in range(n_steps):
            tc = 0.0
            ts = 0.0
            for lo in range(0, N, _CHUNK):
                hi = min(lo + _CHUNK, N)
                a, b = _chunk_step(
                    theta[r, lo:hi], p[r, lo:hi], S[r, lo:hi], C[r, lo:hi], kick, dt, fx, fy
                )
                tc += a
                ts += b
            fx = tc / N
            fy = ts / N
            kick = dt
        for i in range(N):
            p[r, i] = p[r, i] + h * (fy * C[r, i] - fx * S[r, i])
        M[r, 0] = fx
        M[r, 1] = fy


@numba.njit(parallel=True)
def _accumulate_kernel(J, Jbar, slots, lags, blocks, J0, lib0, bin0, acc):
    """Per active origin and particle with bin0 >= 0: (J - J0)^2, (Jbar - Jbar0)^2, J - J0 and
    1 added into acc[:, bin, lag, block]."""
    n = J.size
    for a in numba.prange(slots.size):
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


class PreviousDisplacementAccumulator(accumulator.DisplacementAccumulator):
    """The accumulator until 2026-11-27: J(t0), an int16 bin and a librating flag per particle
    and slot, in the particles' own order."""

    def __init__(self, *args):
        super().__init__(*args)
        shape = (self.n_slots, self.n_track)
        self.J0_all = np.zeros(shape)
        self.lib0_all = np.zeros(shape, dtype=np.bool_)
        self.bin0 = np.full(shape, -1, dtype=np.int16)

    def add(self, s, J, Jbar):
        sl = self.origin_at(s)
        if sl is not None:
            b = np.searchsorted(self.edges, Jbar, side="right") - 1
            b[(b >= self.n_bins) | (Jbar < self.edges[0])] = -1
            b[Jbar == self.edges[-1]] = self.n_bins - 1
            self.J0_all[sl] = J
            self.lib0_all[sl] = Jbar != J
            self.bin0[sl] = b
            inside = b >= 0
            self.seen[np.flatnonzero(inside), b[inside]] = 1
        slots, lags, blocks = self.active_origins(s)
        if slots.size:
            _accumulate_kernel(J, Jbar, slots, lags, blocks, self.J0_all, self.lib0_all,
                               self.bin0, self.acc)  # fmt: skip


# ---------------------------------------------------------------------------------------------
# the float32 step until issue 39
# ---------------------------------------------------------------------------------------------
_D1f, _D2f, _D3f = (np.float32((-1) ** k / np.prod(np.arange(1.0, 2 * k + 2))) for k in range(1, 4))
_E2f, _E3f, _E4f = (np.float32((-1) ** k / np.prod(np.arange(1.0, 2 * k + 1))) for k in range(2, 5))
_HALF_F = np.float32(0.5)
_ONE_F = np.float32(1.0)


@numba.njit(fastmath={"contract"})
def taylor_sincos32(d):
    """(sin d, cos d) of a float32 d, |d| <= DRIFT_MAX, by the Taylor series through d^7, d^8."""
    z = d * d
    s = d + d * z * (_D1f + z * (_D2f + z * _D3f))
    c = _ONE_F - _HALF_F * z + z * z * (_E2f + z * (_E3f + z * _E4f))
    return s, c


@numba.njit(fastmath={"contract"})
def taylor_sincos32_short(d):
    """The same through d^5, d^6 (|d| <= DRIFT_SHORT)."""
    z = d * d
    s = d + d * z * (_D1f + z * _D2f)
    c = _ONE_F - _HALF_F * z + z * z * (_E2f + z * _E3f)
    return s, c


@numba.njit(fastmath=elementary._FM)
def _chunk_step32(p, S, C, h, dt, Fx, Fy, p_bound):
    drift_bound = abs(dt) * (p_bound + abs(h) * (abs(Fx) + abs(Fy)))
    h32 = np.float32(h)
    dt32 = np.float32(dt)
    fx = np.float32(Fx)
    fy = np.float32(Fy)
    sc = np.float32(0.0)
    ss = np.float32(0.0)
    if drift_bound <= elementary.DRIFT_SHORT:
        for i in range(p.size):
            pi_ = p[i] + h32 * (fy * C[i] - fx * S[i])
            sd, cd = taylor_sincos32_short(dt32 * pi_)
            s2 = S[i] * cd + C[i] * sd
            c2 = C[i] * cd - S[i] * sd
            sc += c2
            ss += s2
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    elif drift_bound <= elementary.DRIFT_MAX:
        for i in range(p.size):
            pi_ = p[i] + h32 * (fy * C[i] - fx * S[i])
            sd, cd = taylor_sincos32(dt32 * pi_)
            s2 = S[i] * cd + C[i] * sd
            c2 = C[i] * cd - S[i] * sd
            sc += c2
            ss += s2
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    else:
        for i in range(p.size):
            pi_ = p[i] + h32 * (fy * C[i] - fx * S[i])
            d = dt * np.float64(pi_)
            d = d - elementary._TWO_PI * np.floor(d * elementary._INV_TWO_PI + 0.5)
            sd64, cd64 = elementary._sincos_wrapped(d)
            sd = np.float32(sd64)
            cd = np.float32(cd64)
            s2 = S[i] * cd + C[i] * sd
            c2 = C[i] * cd - S[i] * sd
            sc += c2
            ss += s2
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    return np.float64(sc), np.float64(ss)


@numba.njit
def _chunk_advance32(p, S, C, h, dt, Fx, Fy, bound, path, periodic):
    grow = abs(h) * (abs(Fx) + abs(Fy))
    if periodic:
        integrator._chunk_normalise(S, C)
    bound, path = integrator._refreshed_bound(p, bound, path, periodic, grow, dt)
    a, b = _chunk_step32(p, S, C, h, dt, Fx, Fy, bound)
    return a, b, bound + grow, path


@numba.njit(parallel=True)
def full_steps_float32_taylor(p, S, C, n_steps, dt, fx, fy):
    """n_steps fused MD(full) steps of one system (float32 p, S, C) by the step until issue 39
    (as `integrator.advance_system` 'full' with no test particles: the opening and the closing
    half kicks included); returns the last (Mx, My)."""
    n = p.size
    n_chunks = (n + _CHUNK - 1) // _CHUNK
    part_c = np.zeros(n_chunks)
    part_s = np.zeros(n_chunks)
    bound = np.zeros(n_chunks)
    path = np.zeros(n_chunks, dtype=np.int64)
    h = 0.5 * dt
    for j in range(n_steps):
        periodic = j % integrator._BOUND_REFRESH == 0
        for ch in numba.prange(n_chunks):
            lo = ch * _CHUNK
            hi = min(lo + _CHUNK, n)
            part_c[ch], part_s[ch], bound[ch], path[ch] = _chunk_advance32(
                p[lo:hi], S[lo:hi], C[lo:hi], h, dt, fx, fy, bound[ch], path[ch], periodic
            )
        tc = 0.0
        ts = 0.0
        for ch in range(n_chunks):
            tc += part_c[ch]
            ts += part_s[ch]
        fx = tc / max(n, 1)
        fy = ts / max(n, 1)
        h = dt
    integrator._kick(p, S, C, 0.5 * dt, fx, fy)
    return fx, fy


@numba.njit(fastmath={"contract"}, parallel=True)
def ensemble_steps_float32_taylor(p, S, C, M, n_steps, dt):
    """`ensemble._ensemble_steps` with the step until issue 39 (closing half kick included)."""
    R, N = p.shape
    h = 0.5 * dt
    n_chunks = (N + _CHUNK - 1) // _CHUNK
    for r in numba.prange(R):
        fx = M[r, 0]
        fy = M[r, 1]
        kick = h
        bound = np.zeros(n_chunks)
        path = np.zeros(n_chunks, dtype=np.int64)
        for j in range(n_steps):
            tc = 0.0
            ts = 0.0
            periodic = j % integrator._BOUND_REFRESH == 0
            for ch in range(n_chunks):
                lo = ch * _CHUNK
                hi = min(lo + _CHUNK, N)
                a, b, bound[ch], path[ch] = _chunk_advance32(
                    p[r, lo:hi], S[r, lo:hi], C[r, lo:hi], kick, dt, fx, fy, bound[ch], path[ch],
                    periodic,
                )  # fmt: skip
                tc += a
                ts += b
            fx = tc / N
            fy = ts / N
            kick = dt
        integrator._kick(p[r], S[r], C[r], h, fx, fy)
        M[r, 0] = fx
        M[r, 1] = fy


def initial_ensemble_per_realisation_table(state, n_particles, n_realisations, seed):
    """`hmfdiff.dynamics.ensemble._initial_ensemble` until 2026-11-28: the kappa marginal's CDF
    table recomputed for every realisation (inside `sampling.sample_state`)."""
    from hmfdiff.dynamics import ensemble, sampling

    th = np.empty((n_realisations, n_particles))
    p = np.empty_like(th)
    for r in range(n_realisations):
        rng = sampling.make_rng(seed, r)
        t, q = sampling.sample_state(state, n_particles, rng)
        th[r], _ = sampling.rotate_to_x_axis(t)
        p[r] = q - q.mean()
    return ensemble.Ensemble(th, p)


# ---------------------------------------------------------------------------------------------
# orbits and the exact bath's set-up until 2026-11-28: both branches of K and J evaluated at
# every point (np.where keeping one), E evaluated where only K was used, Omega and c_0 of the
# bath by orbits.frequency and fourier.cos_coefficient (the present ones give the same numbers
# to the bit, with less work)
# ---------------------------------------------------------------------------------------------
def _old_K_E(m, m1):
    from scipy import special

    K = np.where(m1 < 0.5, special.ellipkm1(m1), special.ellipk(m))
    E = special.ellipe(m)
    return K, E


def _old_K(m, m1):  # the callers of `_K` evaluated `K, _ = _K_E(m, m1)`
    return _old_K_E(m, m1)[0]


def _old_E_minus_m1K(m, m1):
    from scipy import special

    K = np.where(m1 < 0.5, special.ellipkm1(m1), special.ellipk(m))
    return m * (K - special.elliprd(0.0, m1, 1.0) / 3.0)


def _old_action(kappa, M0):
    from scipy import special

    from hmfdiff.meanfield import orbits

    kappa = orbits._as_array(kappa)
    m, m1, lib = orbits._modulus_parameter(kappa)
    s = np.sqrt(M0)
    lib_part = 8.0 * s / np.pi * _old_E_minus_m1K(np.where(lib, m, 0.0), np.where(lib, m1, 1.0))
    rot_part = 4.0 * s / np.pi * kappa * special.ellipe(m)
    return np.where(lib, lib_part, rot_part)


def _old_angle_action(theta, p, M0):
    from hmfdiff.meanfield import orbits

    theta = np.angle(np.exp(1j * orbits._as_array(theta)))
    p = orbits._as_array(p)
    kappa = np.sqrt(p**2 / (4.0 * M0) + np.sin(0.5 * theta) ** 2)
    m, m1, lib = orbits._modulus_parameter(kappa)
    K, _ = _old_K_E(m, m1)
    with np.errstate(divide="ignore", invalid="ignore"):
        phi = np.arctan2(np.sin(0.5 * theta), p / (2.0 * np.sqrt(M0)))
        j = np.round(phi / np.pi)
        F_lib = 2.0 * j * K + orbits._ellipf(phi - j * np.pi, m)
        w_lib = np.pi * F_lib / (2.0 * K)
        F_rot = orbits._ellipf(0.5 * theta, m)
        w_rot = np.where(p >= 0, 1.0, -1.0) * np.pi * F_rot / K
    w = np.mod(np.where(lib, w_lib, w_rot), 2.0 * np.pi)
    sign = np.where(lib, 1.0, np.where(p >= 0, 1.0, -1.0))
    return kappa, w, sign


def _old_frequency_c0(kappa, lib, K, E, M0):
    from hmfdiff.meanfield import orbits
    from hmfdiff.meanfield.fourier import cos_coefficient

    return orbits.frequency(kappa, M0), cos_coefficient(0, kappa)


@contextlib.contextmanager
def previous_orbits():
    """Within: hmfdiff.meanfield.orbits and the exact bath's set-up as they ran until
    2026-11-28 (module attributes swapped, restored on exit)."""
    from hmfdiff.dynamics import exact_bath
    from hmfdiff.meanfield import fourier, orbits

    swaps = [
        (orbits, "_K_E", _old_K_E),
        (orbits, "_K", _old_K),
        (orbits, "_E_minus_m1K", _old_E_minus_m1K),
        (orbits, "action", _old_action),
        (orbits, "angle_action", _old_angle_action),
        (fourier, "_K_E", _old_K_E),
        (exact_bath, "_frequency_c0", _old_frequency_c0),
    ]
    saved = [(mod, name, getattr(mod, name)) for mod, name, _ in swaps]
    try:
        for mod, name, fn in swaps:
            setattr(mod, name, fn)
        yield
    finally:
        for mod, name, fn in saved:
            setattr(mod, name, fn)
