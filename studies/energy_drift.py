"""Where does the float32 MD's energy drift come from?  (issue 39 part 1)

The relaxation ensembles (full dynamics, `hmfdiff.dynamics.ensemble`) lose energy at a steady
rate, the same sign in every realisation.  This study runs the ensemble's step with each of its
pieces switched between float32 and float64 in turn, at test size, and measures the secular
slope of the energy per particle against time: per realisation a least-squares slope of
u_r(t) - u_r(0), then their mean over the (independent) realisations with its standard error.

Pieces (a variant names the ones taken in float64 or changed):

  kick     p stored and kicked in float64 (p += h (Fy C - Fx S))
  pstore   p stored in float64, its kick h (Fy C - Fx S) formed in float32 (then added in float64)
  force64  the kick h (Fy C - Fx S) formed in float64 (h, Fx, Fy unrounded), p in float32
  force64r the same with h, Fx, Fy rounded to float32 first
  folded   the kick as p + (a C - b S) with a = h Fy, b = h Fx rounded to float32 once a step
           (the present kernel's)
  plain    the kick as p + h (Fy C - Fx S), h, Fx, Fy rounded to float32 (the previous kernel's)
  m1       the rotation as S' = S + (S (cos d - 1) + C sin d), C' likewise, cos d - 1 kept to
           float32's relative precision (not the kernel's: it changed nothing measurable)
  rot      (sin theta, cos theta) stored and rotated in float64 (with sin d, cos d exact)
  sincos   sin d, cos d of the drift angle exact (float64 of the wrapped float64 angle, error
           < 6e-16, then rounded to float32)
           instead of the float32 Taylor polynomials
  msum     the chunk sums of cos, sin (the magnetisation) in float64
  renorm64 the periodic division of (S, C) by its norm computed in float64
  norenorm no periodic renormalisation (only the closing kick's)

The energy itself is measured in float64 from the state after a float64 closing half kick
(as the ensemble measures it); 'float64' takes every piece in float64; 'present' is the
library's kernel as it is (`ensemble._ensemble_steps`, to the bit).

    python studies/energy_drift.py [--n 1000] [--r 32] [--t 4000] [--dt 0.1] [--every 200]
        [--variants float32,kick,...] [--case corehalo_hothalo] [--threads 1]

Prints per variant: the slope of u against t with its standard error and z, the mean change
of u over the run, its spread between realisations, and the wall time.
"""

from __future__ import annotations

import argparse
import math
import textwrap
import time

import numba
import numpy as np
import yaml

from hmfdiff.dynamics import elementary, ensemble, integrator
from hmfdiff.dynamics.elementary import (
    _CHUNK,
    _FM,
    DRIFT_MAX,
    DRIFT_SHORT,
    _sincos_drift32,
    _sincos_drift32_short,
    _sincos_wrapped,
)
from hmfdiff.meanfield.equilibrium import ThermalState, make_state

F32, F64 = "np.float32", "np.float64"

#: variant -> (p storage type, (S, C) storage type, rotation arithmetic type, magnetisation sum
#: type, sincos ('previous' | 'present' | 'exact'), renormalisation ('f32' | 'f64' | 'none'),
#: arithmetic type of the kick's force h (Fy C - Fx S), type h, Fx, Fy are rounded to first,
#: form of the kick ('plain' | 'folded')).  'previous': the kernel before issue 39, its drift's
#: sincos by the float32 Taylor polynomials (below) and the plain kick; 'present': the library's
#: (elementary's polynomials, the folded kick); every other piece as the library's ensemble
#: kernel has it.
VARIANTS = {
    "previous": (F32, F32, F32, F32, "previous", "f32", F32, F32, "plain"),
    "kick": (F64, F32, F32, F32, "previous", "f32", F64, F64, "plain"),
    "rot": (F32, F64, F64, F32, "exact", "f32", F32, F32, "plain"),
    "sincos": (F32, F32, F32, F32, "exact", "f32", F32, F32, "plain"),
    "msum": (F32, F32, F32, F64, "previous", "f32", F32, F32, "plain"),
    "renorm64": (F32, F32, F32, F32, "previous", "f64", F32, F32, "plain"),
    "norenorm": (F32, F32, F32, F32, "previous", "none", F32, F32, "plain"),
    "float64": (F64, F64, F64, F64, "exact", "f64", F64, F64, "plain"),
    "present": (F32, F32, F32, F32, "present", "f32", F32, F32, "folded"),
}

# the drift's sincos before issue 39: Taylor coefficients rounded to float32, cos as
# (1 - z/2) + z^2 C(z)
_D1f, _D2f, _D3f = (np.float32((-1) ** k / math.factorial(2 * k + 1)) for k in range(1, 4))
_E2f, _E3f, _E4f = (np.float32((-1) ** k / math.factorial(2 * k)) for k in range(2, 5))
_HALF_F = np.float32(0.5)
_ONE_F = np.float32(1.0)


@numba.njit(fastmath={"contract"})
def previous_sincos_drift32(d):
    z = d * d
    s = d + d * z * (_D1f + z * (_D2f + z * _D3f))
    c = _ONE_F - _HALF_F * z + z * z * (_E2f + z * (_E3f + z * _E4f))
    return s, c


@numba.njit(fastmath={"contract"})
def previous_sincos_drift32_short(d):
    z = d * d
    s = d + d * z * (_D1f + z * _D2f)
    c = _ONE_F - _HALF_F * z + z * z * (_E2f + z * _E3f)
    return s, c


@numba.njit(fastmath={"contract"})
def sincosm1_drift32(d):
    """(sin d, cos d - 1) by elementary's polynomials, cos d - 1 = z (-1/2 + z C(z)) kept to
    float32's relative precision, not rounded on the grid near 1 (variant 'm1' rotates by
    S' = S + (S (cos d - 1) + C sin d): its norm error then has no sign where cos d rounds
    to 1)."""
    z = d * d
    s = d + d * z * (elementary._DS1 + z * (elementary._DS2 + z * elementary._DS3))
    cm1 = z * (
        elementary._MINUS_HALF_F
        + z * (elementary._DC2 + z * (elementary._DC3 + z * elementary._DC4))
    )
    return s, cm1


@numba.njit(fastmath={"contract"})
def sincosm1_drift32_short(d):
    """The same on |d| <= DRIFT_SHORT."""
    z = d * d
    s = d + d * z * (elementary._DS1s + z * elementary._DS2s)
    cm1 = z * (elementary._MINUS_HALF_F + z * (elementary._DC2s + z * elementary._DC3s))
    return s, cm1


_TEMPLATE = """
@numba.njit(fastmath=_FM)
def _normalise(S, C):
    for i in range(S.size):
        if RENORM == "f32":
            r = np.float32(1.0) / np.sqrt(S[i] * S[i] + C[i] * C[i])
            S[i] = S[i] * r
            C[i] = C[i] * r
        elif RENORM == "f64":
            s = np.float64(S[i])
            c = np.float64(C[i])
            r = 1.0 / math.sqrt(s * s + c * c)
            S[i] = s * r
            C[i] = c * r


@numba.njit(fastmath=_FM, inline="always")
def _kick_of(p, S, C, hk, fx, fy, a, b):
    if KICK == "folded":
        return PT(p) + PT(a * FT(C) - b * FT(S))
    return PT(p) + PT(hk * (fy * FT(C) - fx * FT(S)))


@numba.njit(fastmath=_FM)
def _step(p, S, C, h, dt, Fx, Fy, p_bound):
    drift_bound = abs(dt) * (p_bound + abs(h) * (abs(Fx) + abs(Fy)))
    hk = FT(CT(h))
    fx = FT(CT(Fx))
    fy = FT(CT(Fy))
    a = FT(CT(h * Fy))  # the folded kick's h Fy, h Fx
    b = FT(CT(h * Fx))
    dt32 = np.float32(dt)
    sc = MT(0.0)
    ss = MT(0.0)
    if SINCOS == "exact":
        for i in range(p.size):
            pi_ = _kick_of(p[i], S[i], C[i], hk, fx, fy, a, b)
            d = dt * np.float64(pi_)
            d = d - _TWO_PI * np.floor(d * _INV_TWO_PI + 0.5)
            sd64, cd64 = _sincos_wrapped(d)
            sd = RT(sd64)
            cd = RT(cd64)
            s2 = RT(S[i]) * cd + RT(C[i]) * sd
            c2 = RT(C[i]) * cd - RT(S[i]) * sd
            sc += MT(c2)
            ss += MT(s2)
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    elif ROTFORM == "m1" and drift_bound <= DRIFT_SHORT:
        for i in range(p.size):
            pi_ = _kick_of(p[i], S[i], C[i], hk, fx, fy, a, b)
            sd, cm = _sincosm1_drift32_short(dt32 * np.float32(pi_))
            s2 = S[i] + (S[i] * cm + C[i] * sd)
            c2 = C[i] + (C[i] * cm - S[i] * sd)
            sc += MT(c2)
            ss += MT(s2)
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    elif ROTFORM == "m1" and drift_bound <= DRIFT_MAX:
        for i in range(p.size):
            pi_ = _kick_of(p[i], S[i], C[i], hk, fx, fy, a, b)
            sd, cm = _sincosm1_drift32(dt32 * np.float32(pi_))
            s2 = S[i] + (S[i] * cm + C[i] * sd)
            c2 = C[i] + (C[i] * cm - S[i] * sd)
            sc += MT(c2)
            ss += MT(s2)
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    elif drift_bound <= DRIFT_SHORT:
        for i in range(p.size):
            pi_ = _kick_of(p[i], S[i], C[i], hk, fx, fy, a, b)
            sd, cd = _SC_SHORT(dt32 * np.float32(pi_))
            s2 = RT(S[i]) * RT(cd) + RT(C[i]) * RT(sd)
            c2 = RT(C[i]) * RT(cd) - RT(S[i]) * RT(sd)
            sc += MT(c2)
            ss += MT(s2)
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    elif drift_bound <= DRIFT_MAX:
        for i in range(p.size):
            pi_ = _kick_of(p[i], S[i], C[i], hk, fx, fy, a, b)
            sd, cd = _SC_LONG(dt32 * np.float32(pi_))
            s2 = RT(S[i]) * RT(cd) + RT(C[i]) * RT(sd)
            c2 = RT(C[i]) * RT(cd) - RT(S[i]) * RT(sd)
            sc += MT(c2)
            ss += MT(s2)
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    else:
        for i in range(p.size):
            pi_ = _kick_of(p[i], S[i], C[i], hk, fx, fy, a, b)
            d = dt * np.float64(pi_)
            d = d - _TWO_PI * np.floor(d * _INV_TWO_PI + 0.5)
            sd64, cd64 = _sincos_wrapped(d)
            sd = RT(sd64)
            cd = RT(cd64)
            s2 = RT(S[i]) * cd + RT(C[i]) * sd
            c2 = RT(C[i]) * cd - RT(S[i]) * sd
            sc += MT(c2)
            ss += MT(s2)
            p[i] = pi_
            S[i] = s2
            C[i] = c2
    return np.float64(sc), np.float64(ss)


@numba.njit
def _advance(p, S, C, h, dt, Fx, Fy, bound, path, periodic):
    grow = abs(h) * (abs(Fx) + abs(Fy))
    if periodic:
        _normalise(S, C)
    bound, path = _refreshed_bound(p, bound, path, periodic, grow, dt)
    a, b = _step(p, S, C, h, dt, Fx, Fy, bound)
    return a, b, bound + grow, path


@numba.njit(parallel=True)
def steps(p, S, C, M, n_steps, dt):
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
            periodic = j % _BOUND_REFRESH == 0
            for ch in range(n_chunks):
                lo = ch * _CHUNK
                hi = min(lo + _CHUNK, N)
                a, b, bound[ch], path[ch] = _advance(
                    p[r, lo:hi], S[r, lo:hi], C[r, lo:hi], kick, dt, fx, fy, bound[ch],
                    path[ch], periodic,
                )
                tc += a
                ts += b
            fx = tc / N
            fy = ts / N
            kick = dt
        _kick(p[r], S[r], C[r], h, fx, fy)
        M[r, 0] = fx
        M[r, 1] = fy
"""


#: what each modifier of a variant 'BASE+MOD+...' changes (see `spec`)
MODIFIERS = {
    "kick": {0: F64, 6: F64},
    "pstore": {0: F64},
    "force64": {6: F64, 7: F64},
    "force64r": {6: F64, 7: F32},
    "folded": {8: "folded"},
    "m1": {9: "m1"},
    "plain": {8: "plain"},
    "rot": {1: F64, 2: F64},
    "exact": {4: "exact"},
    "msum": {3: F64},
    "renorm64": {5: "f64"},
    "norenorm": {5: "none"},
}


def spec(variant):
    """The pieces of `variant`: a name of VARIANTS, or 'BASE+MOD+...' with BASE in VARIANTS and
    each MOD in MODIFIERS (e.g. 'present+kick': the present kernel with p in float64)."""
    base, *mods = variant.split("+")
    out = list(VARIANTS[base]) + ["plain"]
    for m in mods:
        for k, v in MODIFIERS[m].items():
            out[k] = v
    return tuple(out)


def build(variant):
    """The ensemble step of `variant` (a compiled `steps(p, S, C, M, n_steps, dt)`) and the
    storage types of p and of (S, C)."""
    pt, at, rt, mt, sincos, renorm, ft, ct, kick, rotform = spec(variant)
    ns = {
        "numba": numba,
        "np": np,
        "math": math,
        "_FM": _FM,
        "_CHUNK": _CHUNK,
        "_TWO_PI": 2.0 * math.pi,
        "_INV_TWO_PI": 1.0 / (2.0 * math.pi),
        "DRIFT_MAX": DRIFT_MAX,
        "DRIFT_SHORT": DRIFT_SHORT,
        "_SC_LONG": previous_sincos_drift32 if sincos == "previous" else _sincos_drift32,
        "_SC_SHORT": (
            previous_sincos_drift32_short if sincos == "previous" else _sincos_drift32_short
        ),
        "_sincos_wrapped": _sincos_wrapped,
        "_sincosm1_drift32": sincosm1_drift32,
        "_sincosm1_drift32_short": sincosm1_drift32_short,
        "ROTFORM": rotform,
        "_refreshed_bound": integrator._refreshed_bound,
        "_BOUND_REFRESH": integrator._BOUND_REFRESH,
        "_kick": integrator._kick,
        "PT": eval(pt, {"np": np}),
        "FT": eval(ft, {"np": np}),
        "CT": eval(ct, {"np": np}),
        "KICK": kick,
        "RT": eval(rt, {"np": np}),
        "MT": eval(mt, {"np": np}),
        "SINCOS": sincos,
        "RENORM": renorm,
    }
    exec(textwrap.dedent(_TEMPLATE), ns)
    return ns["steps"], eval(pt, {"np": np}), eval(at, {"np": np})


def energy(p, S, C):
    """u = <p^2>/2 - |M|^2/2 per realisation, in float64."""
    p, S, C = (np.asarray(a, dtype=np.float64) for a in (p, S, C))
    return 0.5 * np.mean(p * p, axis=1) - 0.5 * (np.mean(C, axis=1) ** 2 + np.mean(S, axis=1) ** 2)


def slope_stats(t, u):
    """(mean slope of u_r(t) against t, its standard error, mean final change, its spread):
    least squares per realisation (columns of u), statistics over the realisations."""
    du = u - u[0]
    tc = t - t.mean()
    slopes = (tc @ (du - du.mean(axis=0))) / (tc @ tc)
    R = u.shape[1]
    return (
        slopes.mean(),
        slopes.std(ddof=1) / math.sqrt(R),
        du[-1].mean(),
        du[-1].std(ddof=1),
    )


def run(variant, state, *, n, r, t_max, dt, every, seed=1):
    """(times, u of shape (T, R), wall seconds) of `variant` on R realisations of N."""
    steps, pt, at = build(variant)
    ens = ensemble._initial_ensemble(state, n, r, seed)
    p = ens.p.astype(pt)
    S = ens.S.astype(at)
    C = ens.C.astype(at)
    M = ens.M.copy()
    steps(p[:, :8].copy(), S[:, :8].copy(), C[:, :8].copy(), M.copy(), 2, dt)  # compile
    n_every = int(round(every / dt))
    n_meas = int(round(t_max / every))
    u = np.empty((n_meas + 1, r))
    u[0] = energy(p, S, C)
    t0 = time.perf_counter()
    for k in range(n_meas):
        steps(p, S, C, M, n_every, dt)
        u[k + 1] = energy(p, S, C)
    wall = time.perf_counter() - t0
    return np.arange(n_meas + 1) * n_every * dt, u, wall


def load_case(name, config="config/config.yaml"):
    with open(config) as f:
        return make_state(yaml.safe_load(f)["cases"][name])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--r", type=int, default=32)
    ap.add_argument("--t", type=float, default=4000.0)
    ap.add_argument("--dt", type=float, default=0.1)
    ap.add_argument("--every", type=float, default=20.0)
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--case", default="corehalo_hothalo")
    ap.add_argument("--thermal", action="store_true", help="the thermal state of the case's u")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    numba.set_num_threads(args.threads)
    state = load_case(args.case)
    if args.thermal:
        state = ThermalState(u=state.u)
    print(
        f"case {args.case}{' thermal' if args.thermal else ''} (M0 = {state.M0:.4f}), "
        f"N = {args.n}, R = {args.r}, dt = {args.dt}, "
        f"t = {args.t:g}; slope of u(t) per unit time, mean over realisations +- standard error"
    )
    print(f"{'variant':10s} {'slope':>11s} {'+-':>9s} {'z':>7s} {'du(t_max)':>11s} "
          f"{'spread':>9s} {'wall s':>7s}")  # fmt: skip
    out = {}
    for v in args.variants.split(","):
        t, u, wall = run(
            v, state, n=args.n, r=args.r, t_max=args.t, dt=args.dt, every=args.every,
            seed=args.seed,
        )  # fmt: skip
        s, e, du, sp = slope_stats(t, u)
        out[v] = (s, e, du, sp, wall)
        print(f"{v:10s} {s:+11.3e} {e:9.2e} {s / e:+7.1f} {du:+11.3e} {sp:9.2e} {wall:7.1f}",
              flush=True)  # fmt: skip
    return out


if __name__ == "__main__":
    main()
