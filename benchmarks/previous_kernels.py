"""The MD kernels as hmfdiff ran them until 2026-11-27, kept as the baselines that
benchmarks/bench_md.py and bench_ensemble.py measure the present kernels against in the same
run (issue 23 part 2): the angle stored and its half-angle sincos evaluated every step (about
36 floating-point operations and 32 bytes per particle and step), where the present kernels
rotate (sin theta, cos theta) by the drift angle (`hmfdiff.dynamics.integrator`).
"""

from __future__ import annotations

import numba
import numpy as np

from hmfdiff.dynamics import elementary

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
