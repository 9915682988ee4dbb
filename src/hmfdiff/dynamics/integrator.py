"""Velocity-Verlet (kick-drift-kick leapfrog) integration of HMF particles (eqs. hmfmdbath,
hmfmdfull): `Particles` (angles, momenta, cached sin and cos), the field that drives them
(`Field`), `leapfrog` for one population and `advance_system` for the MD's bath and tracers.

Consecutive half kicks are fused, so one pass over the particles per step updates p and theta
and accumulates sum cos, sum sin of the new angles; a last half kick re-synchronises p with
theta at each sampling time.  sin and cos of the new angle are cached per particle, so each step
costs one sincos per particle.  Reductions are deterministic: particles are cut into a fixed
number of chunks (independent of the thread count) whose partial sums are combined in order.
"""

from __future__ import annotations

import enum

import numpy as np
from numba import prange

from . import sampling
from .elementary import _CHUNK, _FM, _INV_TWO_PI, _TWO_PI, _sincos_wrapped, sincos_wrapped_array
from .jit import njit

__all__ = ["INTEGRATOR", "Field", "Particles", "leapfrog", "advance_system", "advance_in_field"]

INTEGRATOR = "velocity Verlet (kick-drift-kick leapfrog), 2nd order, symplectic"


class Field(enum.Enum):
    """The field (Fx, Fy) that drives particles: p' = -Fx sin theta + Fy cos theta."""

    STATIC = "static"  # a constant field (fx, fy): the bath of eq. hmfmdbath, (M0, 0)
    SELF = "self"  # the particles' own magnetisation (eq. hmfmdfull)
    EXTERNAL = "external"  # a prescribed history, one (Fx, Fy) per step (test particles)


# the kernel's integer code of each field kind
_FIELD_CODE = {Field.STATIC: 0, Field.SELF: 1, Field.EXTERNAL: 2}


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
    h_0 = first_kick, h_j = kick for j > 0.  (Fx, Fy) at step j, by the code of the `Field`:
      0 (STATIC): (fx, fy) constant;
      1 (SELF): the magnetisation of these particles at the current time (fx, fy on entry are
                the magnetisation of the initial angles);
      2 (EXTERNAL): out[j, 2], out[j, 3] hold (Fx, Fy) of step j.
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

    def open_steps(self, n_steps, *, dt, field, fx=0.0, fy=0.0, history=None):
        """n_steps fused velocity-Verlet steps of time step dt, opened by a half kick: on return
        p lags theta by half a kick, which `close_steps` applies.

        field: a `Field`.  STATIC: the constant (fx, fy); SELF: the particles' magnetisation,
        (fx, fy) being that of the current angles; EXTERNAL: history[j, 2:4] is (Fx, Fy) at
        step j.  Returns the (n_steps, 4) history: columns 0, 1 hold mean cos, mean sin of the
        angles after each step (written into `history` if given)."""
        out = np.zeros((n_steps, 4)) if history is None else history
        _kick_drift(
            self.theta,
            self.p,
            self.S,
            self.C,
            float(0.5 * dt),
            float(dt),
            float(dt),
            float(fx),
            float(fy),
            int(n_steps),
            _FIELD_CODE[Field(field)],
            out,
        )
        return out

    def close_steps(self, *, dt, fx, fy):
        """The closing half kick p += (dt/2) (-fx sin theta + fy cos theta): p and theta are
        synchronised again."""
        _kick(self.p, self.S, self.C, float(0.5 * dt), float(fx), float(fy))


def leapfrog(particles, n_steps, dt, field=Field.SELF, *, fx=0.0, fy=0.0):
    """n_steps velocity-Verlet steps of time step dt (p synchronised with theta at the end).

    field: Field.SELF (or 'self'), the particles' own magnetisation (eq. hmfmdfull);
    Field.STATIC (or 'static'), the constant field (fx, fy).  Returns the magnetisation after
    each step, shape (n_steps, 2)."""
    field = Field(field)
    if n_steps < 1:
        return np.zeros((0, 2))
    if field is Field.SELF:
        m = particles.moments()
        out = particles.open_steps(n_steps, dt=dt, field=field, fx=m[0], fy=m[1])
        particles.close_steps(dt=dt, fx=out[-1, 0], fy=out[-1, 1])
    elif field is Field.STATIC:
        out = particles.open_steps(n_steps, dt=dt, field=field, fx=fx, fy=fy)
        particles.close_steps(dt=dt, fx=fx, fy=fy)
    else:
        raise ValueError(f"field = {field!r}: leapfrog takes Field.SELF or Field.STATIC")
    return out[:, :2].copy()


def advance_system(bath, test, *, dynamics, M, n_steps, dt, M0, work=None, m_out=None):
    """Advance bath / interacting particles and test particles by n_steps velocity-Verlet steps.

    dynamics 'full': `bath` holds the N interacting particles (eq. hmfmdfull); 'bath': `bath`
    feels the static field M0 on x (eq. hmfmdbath).  Test particles (`test`, may be empty) feel
    the instantaneous magnetisation of `bath` without feeding back.  M is the magnetisation of
    `bath` on entry; returns it after the steps.  p is synchronised with theta on return.
    work: two (>= n_steps, 4) scratch arrays, reused between calls.  m_out: an (n_steps, 2)
    array that receives the magnetisation of `bath` after each step, or None.
    """
    if n_steps < 1:
        return M
    if work is None or work[0].shape[0] < n_steps:
        work = (np.zeros((n_steps, 4)), np.zeros((n_steps, 4)))
    out = work[0][:n_steps]
    if dynamics == "full":  # eq. hmfmdfull
        bath.open_steps(n_steps, dt=dt, field=Field.SELF, fx=M[0], fy=M[1], history=out)
    else:  # eq. hmfmdbath: the static field M0 on x
        bath.open_steps(n_steps, dt=dt, field=Field.STATIC, fx=M0, fy=0.0, history=out)
    if m_out is not None:
        m_out[:] = out[:, :2]
    if len(test):
        # test particles at step j feel the magnetisation before step j (eq. hmfmdbath)
        e = work[1][:n_steps]
        e[0, 2:] = M
        e[1:, 2:] = out[:-1, :2]
        test.open_steps(n_steps, dt=dt, field=Field.EXTERNAL, history=e)
    M = out[n_steps - 1, :2].copy()
    if dynamics == "full":
        bath.close_steps(dt=dt, fx=M[0], fy=M[1])
    else:
        bath.close_steps(dt=dt, fx=M0, fy=0.0)
    if len(test):
        test.close_steps(dt=dt, fx=M[0], fy=M[1])
    return M


def advance_in_field(test, field, *, dt, work=None):
    """Advance test particles by len(field) - 1 velocity-Verlet steps in a prescribed field:
    field[j] = (Fx, Fy) at the start of step j, field[-1] at the end (p synchronised with
    theta on return).  The tracers of MD(bath) with an exact bath (eq. hmfmdbath).
    work: a (>= len(field) - 1, 4) scratch array, or None."""
    n_steps = len(field) - 1
    if n_steps < 1 or not len(test):
        return
    e = np.zeros((n_steps, 4)) if work is None or work.shape[0] < n_steps else work[:n_steps]
    e[:, 2:] = field[:-1]
    test.open_steps(n_steps, dt=dt, field=Field.EXTERNAL, history=e)
    test.close_steps(dt=dt, fx=field[-1][0], fy=field[-1][1])
