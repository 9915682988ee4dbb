"""Velocity-Verlet (kick-drift-kick leapfrog) integration of HMF particles (eqs. hmfmdbath,
hmfmdfull): `Particles` (momenta and the sin, cos of the angles), the field that drives them
(`Field`), `leapfrog` for one population and `advance_system` for the MD's bath and tracers.

Consecutive half kicks are fused, so one pass over the particles per step updates p and the
angle and accumulates sum cos, sum sin of the new angles; a last half kick re-synchronises p
with the angle at each sampling time. A particle carries (S, C) = (sin theta, cos theta), not
theta: the drift theta += d, d = dt p, is the rotation of (S, C) by d, with sin d and cos d
from short polynomials with fitted float32 coefficients (shorter still for |d| <=
`elementary.DRIFT_SHORT`, which holds at dt = 0.05 for |p| < 4; up to |d| <=
`elementary.DRIFT_MAX` longer ones; a chunk whose momenta may exceed that, by a bound on |p|
kept per chunk, takes the general half-angle sincos of the wrapped d).  The kick is
p + (a C - b S) with a = h Fy, b = h Fx rounded to float32 once a step.

The state (p, S, C) and the steps' arithmetic are float32 (`STATE_DTYPE`): on the short path
about 18 floating-point operations (a fused multiply-add counted once) and 12 bytes per
particle and step, twice as many particles per vector instruction as float64
(`benchmarks/bench_md.py` on 2026-11-27: x2.0 on 2 threads and x2.5 per CPU second on one
against the float64 kernel it replaced, two runs an hour apart). What that costs: p and the
angle are held to 6e-8 relative and absolute, the drift angle of each step is rounded to
float32 (a relative frequency error below 1e-7), the rotation's rounding changes the norm of
(S, C) by up to ~6e-8 a step (divided out every `_BOUND_REFRESH` steps and by each closing half
kick), and the total momentum, conserved exactly in exact arithmetic, walks by the kicks'
rounding, ~1e-7 / sqrt(12 N) a step. All of it is far below the O(N^-1/2) fluctuations the MD
measures (the magnetisation's ~1e-3 at N = 5e5; an action's rms change over the fit window
~1e-3); the trust study is in the README ("MD in float32").  None of these roundings may have a
sign: velocity Verlet's energy error is bounded in exact arithmetic, and a biased rounding makes
it drift.  Two did (studies/energy_drift.py, each piece of the step switched to float64 in
turn): the float32 Taylor sincos of the drift angle, which shrank (S, C) in slow particles
(`elementary`), and the kick p + h (Fy C - Fx S) with h = float32(0.1), whose products' digits
below p's last clustered at tenths, one cluster at a half that rounded in the kick's direction:
together -1e-9 per unit time at dt = 0.1, every realisation the same way
(tests/test_energy_drift.py). The magnetisation, the energy, the
momentum and the actions are formed in float64 from the float32 state; the sums of cos and sin
over a chunk within a step are float32 (their rounding, ~1e-8 on the magnetisation of 5e5
particles). The closing half kick is computed in float64 and also divides (S, C) by its norm.
The angles, where needed (`Particles.theta`), are atan2(S, C). Reductions are deterministic:
particles are cut into a fixed number of chunks (independent of the thread count) whose partial
sums are combined in order.
"""

from __future__ import annotations

import enum
import math

import numpy as np
from numba import prange

from . import sampling
from .elementary import (
    _CHUNK,
    _FM,
    _INV_TWO_PI,
    _TWO_PI,
    DRIFT_MAX,
    DRIFT_SHORT,
    _sincos_drift32,
    _sincos_drift32_short,
    _sincos_wrapped,
    angles,
    sincos_wrapped_array,
)
from .jit import njit

__all__ = [
    "INTEGRATOR",
    "STATE_DTYPE",
    "Field",
    "Particles",
    "leapfrog",
    "advance_system",
    "advance_in_field",
]

INTEGRATOR = (
    "velocity Verlet (kick-drift-kick leapfrog), 2nd order, symplectic; state (p, sin theta, "
    "cos theta) and steps in float32, magnetisation, energy and actions formed in float64"
)

#: the floating-point type of the particles' state (p, sin theta, cos theta) and of the steps'
#: arithmetic; magnetisation, energy and actions are computed from it in float64
STATE_DTYPE = np.float32


class Field(enum.Enum):
    """The field (Fx, Fy) that drives particles: p' = -Fx sin theta + Fy cos theta."""

    STATIC = "static"  # a constant field (fx, fy): the bath of eq. hmfmdbath, (M0, 0)
    SELF = "self"  # the particles' own magnetisation (eq. hmfmdfull)
    EXTERNAL = "external"  # a prescribed history, one (Fx, Fy) per step (test particles)


# the kernel's integer code of each field kind
_FIELD_CODE = {Field.STATIC: 0, Field.SELF: 1, Field.EXTERNAL: 2}


# steps between exact refreshes of the per-chunk bound on |p| (in between, each step adds its
# largest possible kick |h| (|Fx| + |Fy|) to it, and the bound is refreshed early whenever that
# growth alone would move the chunk to a costlier sincos: `_refreshed_bound`)
_BOUND_REFRESH = 32


@njit(fastmath=_FM)
def _chunk_p_bound(p):
    """(sum p^8)^(1/8) over a chunk, in float64: >= max |p| (within 2^(1/8) of it over 4096
    particles of a Maxwellian), vectorisable where a max is not; inf or NaN if some p is huge
    or NaN."""
    q8 = 0.0
    for i in range(p.size):
        q = np.float64(p[i])
        q2 = q * q
        q4 = q2 * q2
        q8 += q4 * q4
    return q8**0.125


@njit
def _drift_path(drift_bound):
    """The sincos path of `_chunk_step` for a bound on |d|: 0 short polynomial, 1 long polynomial,
    2 general (also for a NaN bound)."""
    if drift_bound <= DRIFT_SHORT:
        return 0
    if drift_bound <= DRIFT_MAX:
        return 1
    return 2


@njit
def _refreshed_bound(p, bound, path, periodic, grow, dt):
    """(bound on |p|, its path) of a chunk before a step whose kick is at most `grow`: the
    exact bound `_chunk_p_bound` when `periodic`, or when the bound grown by kicks since the
    last refresh would pick a costlier path than `path` (the one of that refresh); else the
    bound and path unchanged.  In a hot state (|p| up to 4, dt = 0.1) the grown bound would
    otherwise leave the polynomial paths within a few steps of each refresh."""
    if periodic or _drift_path(abs(dt) * (bound + grow)) > path:
        bound = _chunk_p_bound(p)
        path = _drift_path(abs(dt) * (bound + grow))
    return bound, path


@njit
def _chunk_advance(p, S, C, h, dt, Fx, Fy, bound, path, periodic):
    """One step of a chunk with its bound on |p| kept: refreshed if due (`_refreshed_bound`),
    used to pick the sincos path, then grown by the step's largest kick.  On the periodic
    steps (S, C) is first divided by its norm: a float32 rotation by a nearly constant angle
    changes the norm coherently, by up to ~6e-8 a step, so this holds it within ~2e-6 of 1
    however long a call runs.  Returns (sum cos, sum sin of the new angles, bound, path).  The
    one place both kernels (`_kick_drift`, the ensemble's) keep the bound and the norm."""
    grow = abs(h) * (abs(Fx) + abs(Fy))
    if periodic:
        _chunk_normalise(S, C)
    bound, path = _refreshed_bound(p, bound, path, periodic, grow, dt)
    a, b = _chunk_step(p, S, C, h, dt, Fx, Fy, bound)
    return a, b, bound + grow, path


@njit(fastmath={"contract"})
def _chunk_normalise(S, C):
    """(S, C) divided by its norm, computed in float64 and rounded once to the state's float32,
    so that the norm is 1 to the float32 rounding, without a bias.  In float32 with fast-math
    reciprocals an AVX-512 build took 1/sqrt from an estimate that left the norm short on
    average (norm^2 - 1 = -1.2e-7 over 1e6 angles): a coherent scale of every particle's
    coupling to the field, and an energy error of every kick that the normalisation preceded."""
    for i in range(S.size):
        s = np.float64(S[i])
        c = np.float64(C[i])
        r = 1.0 / math.sqrt(s * s + c * c)
        S[i] = s * r
        C[i] = c * r


@njit(fastmath=_FM)
def _chunk_step(p, S, C, h, dt, Fx, Fy, p_bound):
    """One fused leapfrog step of the particles (a chunk, passed as float32 array views);
    returns sum cos, sum sin of the new angles (as float64).

    p += h (-Fx sin theta + Fy cos theta); theta += dt p, i.e. (S, C) rotated by d = dt p, all
    in float32 (h Fx, h Fy and dt rounded to it), the chunk's two sums included (their rounding,
    ~1e-3 on a sum of 4096, is ~1e-8 on the magnetisation of 5e5 particles, whose own
    fluctuations are 1e-3).  p_bound >= max |p| on entry (inf when unknown): with the kick's
    bound |h| (|Fx| + |Fy|) it bounds |d|, and picks the short polynomial sincos of d
    (|d| <= DRIFT_SHORT), the long one (|d| <= DRIFT_MAX) or else the general one of d wrapped
    to [-pi, pi), in float64 (a NaN bound picks the general one)."""
    drift_bound = abs(dt) * (p_bound + abs(h) * (abs(Fx) + abs(Fy)))
    # the kick p + (a C - b S) with the step's a = h Fy, b = h Fx rounded to float32 once (not
    # p + h (Fy C - Fx S) with h rounded: float32(0.1) is so near 1/10 that h times a float32
    # has its digits below p's last in ten clusters, one at a half, which rounds away from p in
    # the kick's direction: every kick grew by ~0.03 ulp and the energy by 2e-10 per unit time)
    a = np.float32(h * Fy)
    b = np.float32(h * Fx)
    dt32 = np.float32(dt)
    sc = np.float32(0.0)
    ss = np.float32(0.0)
    # range(size), not range(lo, hi): numba's negative-index handling blocks vectorisation;
    # three loops that differ in the sincos line only, so that each vectorises without a branch
    if drift_bound <= DRIFT_SHORT:
        for i in range(p.size):
            pi_ = p[i] + (a * C[i] - b * S[i])
            sd, cd = _sincos_drift32_short(dt32 * pi_)
            s2 = S[i] * cd + C[i] * sd
            c2 = C[i] * cd - S[i] * sd
            sc += c2
            ss += s2
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    elif drift_bound <= DRIFT_MAX:
        for i in range(p.size):
            pi_ = p[i] + (a * C[i] - b * S[i])
            sd, cd = _sincos_drift32(dt32 * pi_)
            s2 = S[i] * cd + C[i] * sd
            c2 = C[i] * cd - S[i] * sd
            sc += c2
            ss += s2
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    else:
        for i in range(p.size):
            pi_ = p[i] + (a * C[i] - b * S[i])
            d = dt * np.float64(pi_)
            d = d - _TWO_PI * np.floor(d * _INV_TWO_PI + 0.5)
            sd64, cd64 = _sincos_wrapped(d)
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


@njit(parallel=True)
def _kick_drift(p, S, C, first_kick, kick, dt, fx, fy, n_steps, field, out):
    """n_steps fused leapfrog steps of particles (p, S = sin theta, C = cos theta), in place.

    Step j: p += h_j (-Fx sin theta + Fy cos theta); theta += dt p; h_0 = first_kick,
    h_j = kick for j > 0.  (Fx, Fy) at step j, by the code of the `Field`:
      0 (STATIC): (fx, fy) constant;
      1 (SELF): the magnetisation of these particles at the current time (fx, fy on entry are
                the magnetisation of the initial angles);
      2 (EXTERNAL): out[j, 2], out[j, 3] hold (Fx, Fy) of step j.
    out[j, 0], out[j, 1] = mean cos, mean sin of the angles after step j.
    Reductions go through fixed chunks combined in order (deterministic for any thread count).
    """
    n = p.size
    n_chunks = (n + _CHUNK - 1) // _CHUNK
    part_c = np.zeros(n_chunks)
    part_s = np.zeros(n_chunks)
    bound = np.zeros(n_chunks)
    path = np.zeros(n_chunks, dtype=np.int64)
    Fx = fx
    Fy = fy
    h = first_kick
    for j in range(n_steps):
        if field == 2:
            Fx = out[j, 2]
            Fy = out[j, 3]
        periodic = j % _BOUND_REFRESH == 0
        for ch in prange(n_chunks):
            lo = ch * _CHUNK
            hi = min(lo + _CHUNK, n)
            part_c[ch], part_s[ch], bound[ch], path[ch] = _chunk_advance(
                p[lo:hi], S[lo:hi], C[lo:hi], h, dt, Fx, Fy, bound[ch], path[ch], periodic
            )
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
    """Kick p += h (-fx sin theta + fy cos theta) with the stored S, C (re-synchronises p),
    and (S, C) divided by its norm (the rotations of the steps keep it 1 to rounding only);
    computed in float64, stored in the state's float32.

    Serial: it runs once per sampling interval (memory bound, ~1 ms for 5e5 particles)."""
    for i in range(p.size):
        s = np.float64(S[i])
        c = np.float64(C[i])
        p[i] = np.float64(p[i]) + h * (fy * c - fx * s)
        r = 1.0 / math.sqrt(s * s + c * c)
        S[i] = s * r
        C[i] = c * r


@njit(fastmath=_FM)
def _chunk_moments(p, S, C):
    a = 0.0
    b = 0.0
    c = 0.0
    d = 0.0
    for i in range(p.size):
        q = np.float64(p[i])
        a += C[i]
        b += S[i]
        c += q
        d += q * q
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
    """Momenta p and the sin S and cos C of the angles (the angles themselves: `theta`), in
    `STATE_DTYPE`."""

    def __init__(self, theta, p):
        theta = np.ascontiguousarray(sampling.wrap_angle(theta), dtype=np.float64)
        self.p = np.array(p, dtype=STATE_DTYPE)
        if self.p.shape != theta.shape:
            raise ValueError(f"theta {theta.shape} and p {self.p.shape} differ in shape")
        self.S, self.C = (a.astype(STATE_DTYPE) for a in sincos_wrapped_array(theta))

    @property
    def theta(self):
        """The angles in [-pi, pi), atan2(S, C) (computed on each access)."""
        return angles(self.S, self.C)

    def __len__(self):
        return self.p.size

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
