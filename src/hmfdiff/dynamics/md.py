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
import sys
import time as _time

import numba
import numpy as np
import xarray as xr

from . import sampling
from .accumulator import DisplacementAccumulator
from .elementary import actions
from .integrator import INTEGRATOR, Particles, advance_system

__all__ = ["run_md"]


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
