"""Ensembles of independent HMF systems for relaxation studies at small N (eq. hmfmdfull).

R realisations of N interacting particles are advanced together, each in its own
self-consistent magnetisation.  One kernel call advances every realisation by many steps:
realisations are independent, so the parallel loop runs over them and each one is integrated
to the end of the interval while its N particles sit in cache (N = 500 ... 8000 particles are
6-96 kB in float32).  The arithmetic of one realisation is that of the single-system kernel
(`integrator`): the same fused velocity-Verlet step (`integrator._chunk_step`), the same
chunked reduction of the magnetisation in the same order and the same per-chunk choice of the
drift's sincos and the same closing half kick (`integrator._kick`), so a realisation follows
the single-system integration to the bit, and the result does not depend on the thread count.

Measurements, at times given by a schedule (`measurement_times`: dense early, sparse late):
|M|, the direction of M, the energy and the momentum per particle of each realisation, and the
histogram of the rescaled action J-bar of its particles.  Actions are measured in each
realisation's own magnetisation frame, with the magnetisation modulus of the mean field, the
ensemble mean <|M|>(t): the kinetic f(J, tau) is defined with the mean field M0(tau), of which
<|M|> is the estimate; a realisation's own |M| carries O(1/sqrt N) fluctuations that are part
of the noise driving the relaxation, not of the mean field that defines the orbits.  Two other
measures are kept beside it, to show that a result does not hang on that choice: J-bar with
each realisation's own |M| ('hist_own') and with the initial state's static M0
('hist_static').
"""

from __future__ import annotations

import sys
import time as _time

import numba
import numpy as np
from numba import prange

from . import sampling
from .elementary import _CHUNK, _FM, angles, frame_actions, sincos_wrapped_array
from .integrator import _BOUND_REFRESH, STATE_DTYPE, _chunk_advance, _kick
from .jit import njit

__all__ = ["ACTION_MEASURES", "Ensemble", "measurement_times", "run_ensemble"]

#: suffixes of the histograms of J-bar measured with the modulus <|M|>(t) of the ensemble
#: (the mean field, ''), each realisation's own |M| ('_own') and the state's static M0
#: ('_static'); every measure in the realisation's own direction of M
ACTION_MEASURES = ("", "_own", "_static")


@njit(fastmath={"contract"}, parallel=True)
def _ensemble_steps(p, S, C, M, n_steps, dt):
    """n_steps velocity-Verlet steps of every realisation (rows of p, S = sin theta,
    C = cos theta), in place; M[r] = (Mx, My) of realisation r on entry and on exit.  p is
    synchronised with the angles on exit (a last half kick, `integrator._kick` itself, which
    also divides (S, C) by its norm)."""
    R, N = p.shape
    h = 0.5 * dt
    n_chunks = (N + _CHUNK - 1) // _CHUNK
    for r in prange(R):
        fx = M[r, 0]
        fy = M[r, 1]
        kick = h
        bound = np.zeros(n_chunks)
        path = np.zeros(n_chunks, dtype=np.int64)
        for j in range(n_steps):
            tc = 0.0
            ts = 0.0
            periodic = j % _BOUND_REFRESH == 0
            for ch in range(n_chunks):
                lo = ch * _CHUNK
                hi = min(lo + _CHUNK, N)
                a, b, bound[ch], path[ch] = _chunk_advance(
                    p[r, lo:hi], S[r, lo:hi], C[r, lo:hi], kick, dt, fx, fy, bound[ch], path[ch],
                    periodic,
                )  # fmt: skip
                tc += a
                ts += b
            fx = tc / N
            fy = ts / N
            kick = dt
        _kick(p[r], S[r], C[r], h, fx, fy)  # the single-system kernel's closing half kick
        M[r, 0] = fx
        M[r, 1] = fy


@njit(fastmath=_FM, parallel=True)
def _ensemble_moments(p, S, C, out):
    """out[r] = (mean cos, mean sin, mean p, mean p^2) of realisation r."""
    R, N = p.shape
    for r in prange(R):
        a = 0.0
        b = 0.0
        c = 0.0
        d = 0.0
        for i in range(N):
            q = np.float64(p[r, i])
            a += C[r, i]
            b += S[r, i]
            c += q
            d += q * q
        out[r, 0] = a / N
        out[r, 1] = b / N
        out[r, 2] = c / N
        out[r, 3] = d / N


class Ensemble:
    """R realisations of N particles: p and the sin S and cos C of the angles, of shape (R, N)
    and type `integrator.STATE_DTYPE` (the angles themselves: `theta`), and the magnetisation
    (Mx, My) of each realisation."""

    def __init__(self, theta, p):
        theta = np.atleast_2d(np.asarray(theta, dtype=np.float64))
        p = np.atleast_2d(np.asarray(p, dtype=np.float64))
        if theta.shape != p.shape or theta.shape[1] < 1:
            raise ValueError(f"theta {theta.shape} and p {p.shape} must both be (R, N), N >= 1")
        theta = np.ascontiguousarray(sampling.wrap_angle(theta))
        self.p = np.array(p, dtype=STATE_DTYPE)
        s, c = sincos_wrapped_array(theta)
        self.S = s.reshape(theta.shape).astype(STATE_DTYPE)
        self.C = c.reshape(theta.shape).astype(STATE_DTYPE)
        self.M = np.ascontiguousarray(self.moments()[:, :2])

    @property
    def theta(self):
        """The angles in [-pi, pi), shape (R, N): atan2(S, C) (computed on each access)."""
        return angles(self.S, self.C)

    @property
    def shape(self):
        return self.p.shape

    def moments(self):
        """(R, 4): Mx, My, mean p, mean p^2 of each realisation."""
        out = np.empty((self.shape[0], 4))
        _ensemble_moments(self.p, self.S, self.C, out)
        return out

    def advance(self, n_steps, dt):
        """n_steps velocity-Verlet steps of every realisation (eq. hmfmdfull)."""
        if n_steps > 0:
            _ensemble_steps(self.p, self.S, self.C, self.M, int(n_steps), float(dt))

    def energy(self, mom=None):
        """H/N = <p^2>/2 - |M|^2/2 per realisation (eq. hmfhamiltonian)."""
        mom = self.moments() if mom is None else mom
        return 0.5 * mom[:, 3] - 0.5 * (mom[:, 0] ** 2 + mom[:, 1] ** 2)


def measurement_times(t_max, n_times, dt, t_first=None):
    """A schedule dense early and sparse late: 0 and n_times - 1 times spaced geometrically
    from t_first (default: 10 dt) to t_max, rounded to whole steps, without repeats."""
    if not (t_max > 0 and dt > 0 and n_times >= 2):
        raise ValueError(f"need t_max > 0, dt > 0, n_times >= 2 (got {t_max}, {dt}, {n_times})")
    t_first = 10.0 * dt if t_first is None else t_first
    steps = np.rint(np.geomspace(max(t_first, dt), t_max, n_times - 1) / dt).astype(np.int64)
    steps = np.unique(np.concatenate([[0], np.maximum(steps, 1)]))
    return steps * dt


def _initial_ensemble(state, n_particles, n_realisations, seed):
    """Each realisation from its own generator default_rng(SeedSequence([seed, r])): angles
    rotated so that its magnetisation lies on x, its mean momentum subtracted.  The kappa
    marginal's table is computed once for all realisations (it depends on the state only; at
    R = 512 recomputing it took half of the ensemble's set-up)."""
    th = np.empty((n_realisations, n_particles))
    p = np.empty_like(th)
    table = None if getattr(state, "kind", "") == "thermal" else sampling.jbar_cdf_table(state)
    for r in range(n_realisations):
        rng = sampling.make_rng(seed, r)
        t, q = sampling.sample_state(state, n_particles, rng, table=table)
        th[r], _ = sampling.rotate_to_x_axis(t)
        p[r] = q - q.mean()
    return Ensemble(th, p)


def run_ensemble(
    state,
    *,
    n_particles,
    n_realisations,
    dt,
    times,
    jbar_edges,
    seed,
    threads=1,
    progress=None,
    progress_every=10.0,
    M0_static=None,
):
    """Evolve R realisations of N particles drawn from `state` and measure them at `times`.

    times: increasing measurement times, whole multiples of dt starting at 0.  jbar_edges:
    increasing edges of the J-bar histogram.  Returns a dict of arrays: 'time' (T,);
    'M_abs', 'M_phase', 'energy', 'momentum' (T, R); 'M0_actions' (T,) the magnetisation
    modulus defining the actions (ensemble mean of |M|); 'hist' (T, R, B) counts of J-bar per
    bin (particles beyond the last edge are counted in 'overflow' (T, R)); 'hist_own',
    'overflow_own' the same with each realisation's own |M|, 'hist_static', 'overflow_static'
    with the state's M0 (M0_static, default state.M0).
    """
    n_particles, n_realisations = int(n_particles), int(n_realisations)
    if n_particles < 2 or n_realisations < 1:
        raise ValueError(
            f"n_particles = {n_particles} must be >= 2 and n_realisations = {n_realisations} >= 1"
        )
    times = np.asarray(times, dtype=float)
    steps = np.rint(times / dt).astype(np.int64)
    if times[0] != 0 or np.any(np.diff(steps) <= 0) or np.any(np.abs(steps * dt - times) > 1e-9):
        raise ValueError("times must start at 0, increase, and be whole multiples of dt")
    edges = np.asarray(jbar_edges, dtype=float)
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0) or edges[0] < 0:
        raise ValueError("jbar_edges must be an increasing 1-d array of >= 2 values >= 0")
    say = progress or (lambda msg: print(msg, file=sys.stderr, flush=True))
    numba.set_num_threads(int(threads))

    ens = _initial_ensemble(state, n_particles, n_realisations, seed)
    T, R, B = times.size, n_realisations, edges.size - 1
    out = {
        "time": times,
        "M_abs": np.empty((T, R)),
        "M_phase": np.empty((T, R)),
        "energy": np.empty((T, R)),
        "momentum": np.empty((T, R)),
        "M0_actions": np.empty(T),
    }
    for measure in ACTION_MEASURES:
        out["hist" + measure] = np.zeros((T, R, B), dtype=np.int64)
        out["overflow" + measure] = np.zeros((T, R), dtype=np.int64)
    m_static = float(state.M0 if M0_static is None else M0_static)
    J = np.empty(n_particles)
    Jb = np.empty(n_particles)
    wall0 = last = _time.perf_counter()
    done = 0
    for k, s in enumerate(steps):
        ens.advance(s - done, dt)
        done = s
        mom = ens.moments()
        m_abs = np.hypot(mom[:, 0], mom[:, 1])
        phase = np.arctan2(mom[:, 1], mom[:, 0])
        out["M_abs"][k], out["M_phase"][k] = m_abs, phase
        out["energy"][k] = ens.energy(mom)
        out["momentum"][k] = mom[:, 2]
        m0 = float(np.mean(m_abs))
        out["M0_actions"][k] = m0
        for r in range(R):
            for measure, m in zip(ACTION_MEASURES, (m0, m_abs[r], m_static), strict=True):
                frame_actions(ens.S[r], ens.C[r], ens.p[r], float(m), float(phase[r]), (J, Jb))
                idx = np.searchsorted(edges, Jb, side="right") - 1
                inside = (idx >= 0) & (idx < B)
                out["hist" + measure][k, r] = np.bincount(idx[inside], minlength=B)
                out["overflow" + measure][k, r] = n_particles - int(inside.sum())
        now = _time.perf_counter()
        if now - last >= progress_every or k == T - 1:
            rate = s * n_particles * R / max(now - wall0, 1e-9)
            say(
                f"ensemble N = {n_particles}, R = {R}: t = {times[k]:.6g} / {times[-1]:.6g}, "
                f"<|M|> = {m0:.4f}, {rate:.3g} particle-steps/s"
            )
            last = now
    out["wall_time_s"] = _time.perf_counter() - wall0
    return out
