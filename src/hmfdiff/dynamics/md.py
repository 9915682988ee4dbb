"""The MD driver: one realisation of MD(bath) or MD(full) with <dJ^2> accumulated on the fly
(paper, sec. "Comparison with simulations", eqs. hmfmdbath, hmfmdfull, dj2, hmfmddif).

`run_md(state, run, seed, threads)` draws the initial conditions (`sampling`), advances them
(`integrator`), measures the actions of the tracked particles at every sample (`elementary`)
and feeds them to the <dJ^2> accumulator (`accumulator`); every setting comes from the
`MDRun` record (`settings`).  It returns an `MDResult` of arrays, which
`hmfdiff.pipeline.layouts.md.md_dataset` lays out as a netCDF file.

* 'bath' (eq. hmfmdbath): N_b bath particles in the static field theta'' = -M0 sin(theta), M0 the
  state's theoretical magnetisation; N_tp test particles driven, without feedback, by the
  instantaneous bath magnetisation: theta'' = -Mx_b sin(theta) + My_b cos(theta).  By default
  (run.bath 'exact') the bath is not integrated: it moves on its exact orbits and its
  magnetisation at every time step is synthesised from their Fourier series (`exact_bath`).
* 'full' (eq. hmfmdfull): all N particles in the instantaneous magnetisation
  theta'' = -Mx sin(theta) + My cos(theta); the actions of a random subset of n_track of them
  (all by default) are measured; optional test particles driven by it without feeding back.

Actions: J of every tracked particle, with the static M0 and, for 'full', in the frame of the
instantaneous magnetisation (theta - arg(Mx + i My)); for 'bath' in the fixed frame.

Reductions are deterministic (fixed chunks combined in order), so the same seed gives
bit-identical output for any thread count on the same machine and build.  The wall time of
each part (bath synthesis, integration, actions, accumulation) is recorded in the attributes.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time as _time

import numba
import numpy as np

from . import sampling
from .accumulator import DisplacementAccumulator
from .elementary import angles, frame_actions
from .exact_bath import ExactBath
from .integrator import INTEGRATOR, Particles, advance_in_field, advance_system
from .settings import MDRun

__all__ = ["MDResult", "run_md"]


def _default_progress(msg):
    print(msg, file=sys.stderr, flush=True)


@dataclasses.dataclass
class MDResult:
    """What one realisation measured, as arrays (laid out by `pipeline.layouts.md.md_dataset`).

    sums: (4, bin, lag, block) sums over (origin, particle) pairs of (J(t0+lag) - J(t0))^2,
    (Jbar(t0+lag) - Jbar(t0))^2, J(t0+lag) - J(t0) and 1 (eq. dj2); series: Mx, My, energy
    and momentum per particle at each sample; m_fine: (time_fine, 2) Mx, My every m_every of
    production; sample_*: (sample, tracer) angle in the action
    frame, momentum and J of `tracer` tracked particles; attrs: the run's settings
    (`MDRun.attrs`) and what the run found (seed, threads, frames, wall time ...).
    """

    run: MDRun
    attrs: dict
    jbar_edges: np.ndarray
    sums: np.ndarray
    n_particles_in_bin: np.ndarray
    n_origins_in_block: np.ndarray
    series: dict
    m_fine: np.ndarray
    tracer: np.ndarray
    sample_theta: np.ndarray
    sample_p: np.ndarray
    sample_J: np.ndarray


def _initial_conditions(state, run, rng):
    """(bath or interacting particles, test particles, rotation angle), eq. hmfmdbath/full.

    `sampling.sample_state` (exact thermal sampler for thermal states, the kappa marginal
    otherwise) for the bath / interacting particles; test particles from f ('f') or uniform in
    J-bar ('uniform').  All angles are rotated so that the magnetisation of the interacting
    particles lies on x; for 'full' with zero_momentum their mean momentum is removed (test
    particles are left as drawn)."""
    th_b, p_b = sampling.sample_state(state, run.n_particles, rng)
    if run.n_test > 0:
        if run.test_sampling == "f":
            th_t, p_t = sampling.sample_state(state, run.n_test, rng)
        else:
            jr = run.test_jbar_range(state.M0)
            th_t, p_t = sampling.sample_uniform_jbar(state.M0, run.n_test, jr, rng)
    else:
        th_t, p_t = np.zeros(0), np.zeros(0)
    th_b, th_t, phase0 = sampling.rotate_to_x_axis(th_b, th_t)
    if run.dynamics == "full" and run.zero_momentum:
        p_b = p_b - p_b.mean()
    return Particles(th_b, p_b), Particles(th_t, p_t), phase0


def _tracked_subset(run, rng):
    """Indices of the n_track tracked particles among the N of MD(full), drawn at random
    (sorted); all N when n_track is None; none for MD(bath)."""
    if run.dynamics != "full":
        return np.zeros(0, dtype=np.int64)
    if run.n_track is None or run.n_track == run.n_particles:
        return np.arange(run.n_particles, dtype=np.int64)
    return np.sort(rng.choice(run.n_particles, size=run.n_track, replace=False))


def run_md(
    state, run, seed, threads=1, *, member=0, progress=_default_progress, progress_every=5.0
):
    """Run one realisation of `run` (an `MDRun`) and accumulate <dJ^2> per J-bar_0 bin and lag.

    The run integrates t_equilibrate (no measurement), then t_max of production with samples
    every sample_every (t = 0 is the start of production); origins every origin_every, lags
    0 ... max_lag.  Tracked particles: the n_test test particles for 'bath'; n_track of the
    n_particles particles (all by default) and the n_test test particles for 'full'.  With
    run.bath 'exact', the bath of 'bath' is not integrated: its magnetisation at every step is
    synthesised from its exact orbits (`exact_bath.ExactBath`) and only the test particles are
    integrated, in that field.

    state: equilibrium state (ThermalState, CoreHaloState) with .M0 and .f; M0 is the static
    field of the bath and the magnetisation used for every action.  seed, member: the
    generator is default_rng(SeedSequence([seed, member])).  threads: numba threads, in
    [1, numba.config.NUMBA_NUM_THREADS]; results do not depend on it.  progress: callable
    (message) called about every `progress_every` seconds of wall time, or None.
    """
    if not isinstance(run, MDRun):
        raise TypeError(f"run must be an MDRun, got {type(run).__name__}")
    if not hasattr(state, "M0") or not 0.0 < state.M0 < 1.0:
        raise ValueError("state must be an equilibrium state with 0 < M0 < 1")
    n_cores = numba.config.NUMBA_NUM_THREADS
    if isinstance(threads, bool) or int(threads) != threads or not 1 <= threads <= n_cores:
        raise ValueError(f"threads = {threads!r} must be an integer in [1, {n_cores}]")
    if progress is None:
        progress = lambda msg: None  # noqa: E731
    M0 = float(state.M0)
    wall0 = _time.perf_counter()
    numba.set_num_threads(int(threads))
    clock = dict.fromkeys(("bath_synthesis", "integration", "actions", "accumulation"), 0.0)

    rng = sampling.make_rng(seed, member)
    bath, test, phase0 = _initial_conditions(state, run, rng)
    track = _tracked_subset(run, rng)
    edges = run.jbar_edges(M0)
    n_sub, n_samp = run.steps_per_sample, run.n_samples
    n_track = run.n_tracked
    n_f = track.size  # tracked particles of the N (MD(full))
    acc = DisplacementAccumulator(
        n_track, edges, n_samp + 1, run.lag_samples, run.origin_samples, run.n_blocks
    )
    n_store = min(int(run.n_store), n_track)
    store_idx = np.unique(np.linspace(0, n_track - 1, n_store).astype(np.int64))

    # ---- the magnetisation of the bath / interacting particles at every time step ----
    n_total_steps = run.n_steps
    exact = None
    if run.exact_bath:
        t0 = _time.perf_counter()
        exact = ExactBath(
            bath.theta,
            bath.p,
            M0,
            dt=run.dt,
            n_steps=n_total_steps,
            tolerance=run.bath_tolerance,
            threads=1,  # one thread: the FFT's sums in a fixed order, whatever `threads`
        )
        clock["bath_synthesis"] = _time.perf_counter() - t0
        m_all = exact.history
    else:
        m_all = np.empty((n_total_steps + 1, 2))
        m_all[0] = bath.moments()[:2]

    # ---- integration: velocity Verlet, p synchronised with theta after each call ----
    work = (np.zeros((max(n_sub, 1), 4)), np.zeros((max(n_sub, 1), 4)))
    step = 0  # time steps done

    def advance(n_steps):
        nonlocal step
        t0 = _time.perf_counter()
        if exact is not None:
            advance_in_field(test, m_all[step : step + n_steps + 1], dt=run.dt, work=work[1])
        else:
            advance_system(
                bath,
                test,
                dynamics=run.dynamics,
                M=m_all[step],
                n_steps=n_steps,
                dt=run.dt,
                M0=M0,
                work=work,
                m_out=m_all[step + 1 : step + n_steps + 1],
            )
        step += n_steps
        clock["integration"] += _time.perf_counter() - t0

    full = run.dynamics == "full"
    J = np.empty(n_track)
    Jb = np.empty(n_track)
    n_times = n_samp + 1
    ts = {k: np.zeros(n_times) for k in ("Mx", "My", "energy", "momentum")}
    store_th = np.zeros((n_times, store_idx.size))
    store_p = np.zeros_like(store_th)
    store_J = np.zeros_like(store_th)
    st_b = track[store_idx[store_idx < n_f]]  # stored particles of the N, as bath indices
    st_t = store_idx[store_idx >= n_f] - n_f

    def measure(s):
        t0 = _time.perf_counter()
        if exact is not None:
            ts["Mx"][s], ts["My"][s] = m_all[step]
            ts["momentum"][s] = exact.momentum[step]
            ts["energy"][s] = exact.energy
        else:
            mom = bath.moments()
            ts["Mx"][s], ts["My"][s] = mom[0], mom[1]
            ts["momentum"][s] = mom[2]
            if full:
                ts["energy"][s] = 0.5 * mom[3] - 0.5 * (mom[0] ** 2 + mom[1] ** 2)
            else:
                ts["energy"][s] = 0.5 * mom[3] - M0 * mom[0]
        phase = math.atan2(ts["My"][s], ts["Mx"][s]) if full else 0.0
        if full:
            frame_actions(bath.S, bath.C, bath.p, M0, phase, (J[:n_f], Jb[:n_f]), track)
        if run.n_test:
            frame_actions(test.S, test.C, test.p, M0, phase, (J[n_f:], Jb[n_f:]))
        th_st = angles(
            np.concatenate([bath.S[st_b], test.S[st_t]]),
            np.concatenate([bath.C[st_b], test.C[st_t]]),
        )
        store_th[s] = sampling.wrap_angle(th_st - phase)
        store_p[s] = np.concatenate([bath.p[st_b], test.p[st_t]])
        store_J[s] = J[store_idx]
        t1 = _time.perf_counter()
        acc.add(s, J, Jb)
        clock["actions"] += t1 - t0
        clock["accumulation"] += _time.perf_counter() - t1

    # ---- run ----
    n_all = run.n_test + (0 if exact is not None else run.n_particles)
    t_start = _time.perf_counter()
    last = [t_start, 0]  # wall time and steps at the last report

    def report(tsim):
        now = _time.perf_counter()
        if now - last[0] >= progress_every:
            rate = (step - last[1]) * n_all / max(now - last[0], 1e-9)
            progress(
                f"run_md[{run.dynamics}] t = {tsim:.6g} / {run.t_equilibrate + run.t_max:.6g} "
                f"({100.0 * step / n_total_steps:.1f}%), {rate:.3g} integrated "
                "particle-steps/s (including measurements)"
            )
            last[0], last[1] = now, step

    while step < run.equilibration_steps:
        advance(min(run.equilibration_steps - step, work[0].shape[0]))
        report(step * run.dt)
    measure(0)
    for s in range(1, n_samp + 1):
        advance(n_sub)
        measure(s)
        report(run.t_equilibrate + s * run.sample_every)
    wall = _time.perf_counter() - wall0
    progress(
        f"run_md[{run.dynamics}] done in {wall:.1f} s wall, "
        f"{step * n_all / max(_time.perf_counter() - t_start, 1e-9):.3g} "
        "integrated particle-steps/s; " + ", ".join(f"{k} {v:.1f} s" for k, v in clock.items())
    )
    m_fine = m_all[run.equilibration_steps :: run.m_steps]

    if full:
        e_def = "H/N = sum p^2/(2N) - (Mx^2 + My^2)/2 of the N interacting particles"
        frame = "frame of the instantaneous magnetisation of the N particles"
    else:
        e_def = (
            "mean one-particle energy of the bath in the static field, "
            "sum (p^2/2 - M0 cos theta)/N_b (conserved by the bath dynamics)"
        )
        frame = "fixed frame (static field on x)"
    attrs = run.attrs(M0)
    attrs.update({f"wall_{k}_s": v for k, v in clock.items()})
    if exact is not None:
        attrs.update(exact.attrs())
        e_def = (
            "mean one-particle energy of the bath in the static field, "
            "sum (p^2/2 - M0 cos theta)/N_b (constant: the bath moves on exact orbits)"
        )
    attrs.update(
        energy_definition=e_def,
        integrator=INTEGRATOR,
        seed=int(seed),
        member=int(member),
        threads=int(threads),
        M0_actions=M0,
        action_frame=frame,
        initial_rotation=phase0,
        wall_time_s=wall,
        state_kind=getattr(state, "kind", type(state).__name__),
        mean_dJ2="sum_dJ2 / count; D_dif = slope / 2 (eq. hmfmddif)",
    )
    return MDResult(
        run=run,
        attrs=attrs,
        jbar_edges=edges,
        sums=acc.acc,
        n_particles_in_bin=acc.n_particles_in_bin,
        n_origins_in_block=np.bincount(
            [acc.block_of(o) for o in range(acc.n_origins)], minlength=acc.n_blocks
        ),
        series=ts,
        m_fine=m_fine,
        tracer=store_idx,
        sample_theta=store_th,
        sample_p=store_p,
        sample_J=store_J,
    )
