"""Benchmark of the HMF molecular dynamics kernels (hmfdiff.dynamics) at the paper's N = 5e5.

Prints particle-steps per second of the full dynamics (eq. hmfmdfull) and of the bath dynamics
(eq. hmfmdbath: N_b bath particles in the static field plus test particles), the cost of one
action evaluation of 5e5 particles, and the same for a plain vectorised numpy implementation
(the baseline), with ratios; with --memory, the peak RSS of a short N = 5e5 run_md with 100
active time origins (measured in a fresh subprocess).

    python benchmarks/bench_md.py [--json] [--threads 2] [--n 500000] [--memory] [--no-ensemble]

It also times the bath of one MD(bath) realisation (t = 1000, dt = 0.05) at N_b = n both ways,
exact orbits against integration (`exact_bath_speedup` in --json, CPU time), and includes the
ensemble engine's figure of issue 14 (benchmarks/bench_ensemble.py, keys `ensemble_*`).  The
full dynamics is also timed against the float32 step as it ran until issue 39
(`previous_kernels.full_steps_float32_taylor`: Taylor sincos, kick with h rounded), alternately
with the present one in the same run (`full_speed_vs_float32_taylor`: above 1, present faster).

The numba kernels are compiled (warmed) on small arrays before any timing; no numba cache is
used.  Timings are the best of several repetitions of wall-clock time.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time

import numba
import numpy as np
import previous_kernels

from hmfdiff.dynamics import accumulator, elementary, exact_bath, integrator, md, sampling
from hmfdiff.dynamics.settings import MDRun
from hmfdiff.meanfield import equilibrium, orbits

M0 = 0.72846


def best_of(fn, reps=3):
    best = np.inf
    for _ in range(reps):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


# ------------------------------------------------------------------ numpy baselines
def numpy_full_steps(theta, p, n_steps, dt):
    """Velocity Verlet of eq. hmfmdfull in plain numpy (sin, cos once per step)."""
    s, c = np.sin(theta), np.cos(theta)
    mx, my = c.mean(), s.mean()
    for _ in range(n_steps):
        p += 0.5 * dt * (my * c - mx * s)
        theta += dt * p
        s, c = np.sin(theta), np.cos(theta)
        mx, my = c.mean(), s.mean()
        p += 0.5 * dt * (my * c - mx * s)
    return theta, p


def numpy_bath_steps(th_b, p_b, th_t, p_t, n_steps, dt):
    """Velocity Verlet of eq. hmfmdbath in plain numpy."""
    s, c = np.sin(th_b), np.cos(th_b)
    st, ct = np.sin(th_t), np.cos(th_t)
    mx, my = c.mean(), s.mean()
    for _ in range(n_steps):
        p_b -= 0.5 * dt * M0 * s
        p_t += 0.5 * dt * (my * ct - mx * st)
        th_b += dt * p_b
        th_t += dt * p_t
        s, c = np.sin(th_b), np.cos(th_b)
        st, ct = np.sin(th_t), np.cos(th_t)
        mx, my = c.mean(), s.mean()
        p_b -= 0.5 * dt * M0 * s
        p_t += 0.5 * dt * (my * ct - mx * st)


def numpy_actions(theta, p):
    kappa = np.sqrt(p**2 / (4 * M0) + np.sin(0.5 * theta) ** 2)
    return orbits.action(kappa, M0)


# ------------------------------------------------------------------ measurements
def accumulation_cost(P, n_track=120_000, n_samples=160, max_lag=100, origin_every=5, n_bins=30):
    """Seconds per (active origin, tracked particle) of feeding the <dJ^2> accumulator, the
    present and the previous one alternately, over a run of n_samples samples of n_track
    particles (as MD(full)'s 1e5 tracked + 2e4 test particles) whose J-bar random-walk by
    1e-3 per sample (as in MD(full) at N = 5e5: N D ~ 0.1, sampled every 2 time units): every
    add timed, origins included; on one thread, as the MD jobs run (md.threads = 1).  Returns
    (present, previous, whether the two sums agree to 1e-10)."""
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    J, Jb = elementary.frame_actions(P.S, P.C, P.p, M0, 0.01)
    n = min(n_track, J.size)
    J, Jb = J[:n], Jb[:n]
    lib = Jb != J
    rng = np.random.default_rng(5)
    edges = np.linspace(0.0, 2.0, n_bins + 1)
    args = (n, edges, n_samples, max_lag, origin_every, 4)
    small = (64, edges, 12, 6, 3, 2)  # compile both on small arrays first
    for cls in (
        accumulator.DisplacementAccumulator,
        previous_kernels.PreviousDisplacementAccumulator,
    ):
        a = cls(*small)
        for s in range(12):
            a.add(s, J[:64].copy(), Jb[:64].copy())
    present = accumulator.DisplacementAccumulator(*args)
    previous = previous_kernels.PreviousDisplacementAccumulator(*args)
    t = {present: 0.0, previous: 0.0}
    jb = Jb.copy()
    for s in range(n_samples):
        jb = np.abs(jb + rng.normal(0.0, 1e-3, n))
        j = np.where(lib, 2.0 * jb, jb)
        for a in (present, previous) if s % 2 else (previous, present):
            t0 = time.perf_counter()
            a.add(s, j, jb)
            t[a] += time.perf_counter() - t0
    pairs = present.acc[3].sum()
    equal = bool(np.allclose(present.acc, previous.acc, rtol=1e-10, atol=0.0))
    numba.set_num_threads(threads)
    return t[present] / pairs, t[previous] / pairs, equal


def measure(n, threads, n_test_bath):
    numba.set_num_threads(threads)
    state = equilibrium.ThermalState(M0=M0)
    rng = sampling.make_rng(0)
    th, p = sampling.sample_thermal(state, n, rng)
    th_t, p_t = sampling.sample_thermal(state, n_test_bath, rng)
    dt = 0.05
    # warm the compiler on small arrays (same types)
    small = integrator.Particles(th[:100], p[:100])
    for dynamics in ("full", "bath"):
        integrator.advance_system(
            small,
            integrator.Particles(th[:10], p[:10]),
            dynamics=dynamics,
            M=small.moments()[:2],
            n_steps=3,
            dt=dt,
            M0=M0,
        )
    elementary.actions(th[:100], p[:100], M0, 0.1)

    n_steps = 200
    P = integrator.Particles(th, p)
    empty = integrator.Particles(np.zeros(0), np.zeros(0))
    M = P.moments()[:2]
    steps = dict(M=M, n_steps=n_steps, dt=dt, M0=M0)
    # the previous kernel on the same particles; the two timed alternately, so that a
    # machine whose speed drifts (a shared one) affects both alike
    tha, pa = sampling.wrap_angle(th), p.copy()
    Sa, Ca = np.sin(tha), np.cos(tha)
    previous_kernels.full_steps(tha[:100].copy(), pa[:100].copy(), Sa[:100].copy(), Ca[:100].copy(),
                            2, dt, M[0], M[1])  # fmt: skip

    # and the float32 step as it ran until issue 39 (Taylor sincos, kick with h rounded), on a
    # copy of the same float32 state
    p32, S32, C32 = P.p.copy(), P.S.copy(), P.C.copy()
    previous_kernels.full_steps_float32_taylor(p32[:100].copy(), S32[:100].copy(),
                                               C32[:100].copy(), 2, dt, M[0], M[1])  # fmt: skip

    def present():
        integrator.advance_system(P, empty, dynamics="full", **steps)

    def previous():
        previous_kernels.full_steps(tha, pa, Sa, Ca, n_steps, dt, M[0], M[1])

    def before_fix():
        previous_kernels.full_steps_float32_taylor(p32, S32, C32, n_steps, dt, M[0], M[1])

    wall = {present: np.inf, previous: np.inf, before_fix: np.inf}
    cpu = {present: np.inf, previous: np.inf, before_fix: np.inf}
    for _ in range(5):
        for fn in (present, previous, before_fix):
            wall[fn] = min(wall[fn], best_of(fn, reps=1))
            # load-robust figure: one thread, CPU time of this process (what a core delivers)
            numba.set_num_threads(1)
            c0 = time.process_time()
            fn()
            cpu[fn] = min(cpu[fn], time.process_time() - c0)
            numba.set_num_threads(threads)
    t_full, t_prev, cpu_prev = wall[present], wall[previous], cpu[previous]
    t_fix, cpu_fix = wall[before_fix], cpu[before_fix]
    cpu = cpu[present]
    B, T = integrator.Particles(th, p), integrator.Particles(th_t, p_t)
    t_bath = best_of(lambda: integrator.advance_system(B, T, dynamics="bath", **steps))
    elementary.frame_actions(P.S[:100], P.C[:100], P.p[:100], M0, 0.1)
    t_act = best_of(lambda: elementary.frame_actions(P.S, P.C, P.p, M0, 0.01), reps=5)
    t_acc, t_acc_prev, acc_equal = accumulation_cost(P)

    n_np = 20
    thn, pn = th.copy(), p.copy()
    t_np_full = best_of(lambda: numpy_full_steps(thn, pn, n_np, dt), reps=2)
    thb, pb, tht, ptt = th.copy(), p.copy(), th_t.copy(), p_t.copy()
    t_np_bath = best_of(lambda: numpy_bath_steps(thb, pb, tht, ptt, n_np, dt), reps=2)
    t_np_act = best_of(lambda: numpy_actions(th, p), reps=2)
    res = {
        "n": n,
        "threads": threads,
        "n_test_bath": n_test_bath,
        "full_psteps_per_s": n * n_steps / t_full,
        "full_psteps_per_cpu_s_1thread": n * n_steps / cpu,
        "previous_full_psteps_per_s": n * n_steps / t_prev,
        "previous_full_psteps_per_cpu_s_1thread": n * n_steps / cpu_prev,
        "float32_taylor_full_psteps_per_s": n * n_steps / t_fix,
        "float32_taylor_full_psteps_per_cpu_s_1thread": n * n_steps / cpu_fix,
        "bath_psteps_per_s": (n + n_test_bath) * n_steps / t_bath,
        "numpy_psteps_per_s": n * n_np / t_np_full,
        "numpy_bath_psteps_per_s": (n + n_test_bath) * n_np / t_np_bath,
        "actions_seconds_per_5e5": t_act * 5e5 / n,
        "numpy_actions_seconds_per_5e5": t_np_act * 5e5 / n,
        "accumulate_ns_per_origin_particle": t_acc * 1e9,
        "previous_accumulate_ns_per_origin_particle": t_acc_prev * 1e9,
        "accumulate_speedup_vs_previous": t_acc_prev / t_acc,
        "accumulate_sums_equal_previous": acc_equal,
        "load_average_1min": os.getloadavg()[0],
        "omp_wait_policy": os.environ.get("OMP_WAIT_POLICY", ""),
        "threading_layer": numba.threading_layer(),
    }
    res["full_speedup_vs_numpy"] = res["full_psteps_per_s"] / res["numpy_psteps_per_s"]
    res["full_speedup_vs_previous"] = res["full_psteps_per_s"] / res["previous_full_psteps_per_s"]
    res["full_speed_vs_float32_taylor"] = t_fix / t_full
    res["full_speed_vs_float32_taylor_cpu_1thread"] = cpu_fix / cpu
    res["bath_speedup_vs_numpy"] = res["bath_psteps_per_s"] / res["numpy_bath_psteps_per_s"]
    res["actions_speedup_vs_numpy"] = (
        res["numpy_actions_seconds_per_5e5"] / res["actions_seconds_per_5e5"]
    )
    return res


def exact_bath_cost(n, threads, t_run=1000.0, dt=0.05, short_steps=200):
    """Cost of the bath of one MD(bath) realisation of t_run at N_b = n, both ways, on the same
    initial conditions: the integrated bath (velocity Verlet of n particles, timed over
    `short_steps` steps and scaled to t_run / dt) and the exact bath (orbits, harmonics and the
    non-uniform FFT of the whole run, timed whole).  CPU seconds of this process (robust to
    the load of a shared machine) and wall seconds."""
    numba.set_num_threads(threads)
    state = equilibrium.ThermalState(M0=M0)
    th, p = sampling.sample_thermal(state, n, sampling.make_rng(3))
    th, _ = sampling.rotate_to_x_axis(th)
    n_steps = int(round(t_run / dt))
    exact_bath.ExactBath(th[:200], p[:200], M0, dt=dt, n_steps=10)  # compile
    B = integrator.Particles(th, p)
    integrator.leapfrog(integrator.Particles(th[:100], p[:100]), 3, dt, "static", fx=M0)

    def timed(fn):
        c0, w0 = time.process_time(), time.perf_counter()
        out = fn()
        return time.process_time() - c0, time.perf_counter() - w0, out

    cpu_i, wall_i, _ = min(
        (timed(lambda: integrator.leapfrog(B, short_steps, dt, "static", fx=M0)) for _ in range(3)),
        key=lambda r: r[0],
    )
    scale = n_steps / short_steps
    cpu_e, wall_e, eb = timed(
        lambda: exact_bath.ExactBath(th, p, M0, dt=dt, n_steps=n_steps, tolerance=1e-9)
    )
    return {
        "exact_bath_n": n,
        "exact_bath_t_run": t_run,
        "exact_bath_dt": dt,
        "integrated_bath_cpu_s_per_realisation": cpu_i * scale,
        "integrated_bath_wall_s_per_realisation": wall_i * scale,
        "exact_bath_cpu_s_per_realisation": cpu_e,
        "exact_bath_wall_s_per_realisation": wall_e,
        "exact_bath_speedup": cpu_i * scale / cpu_e,
        "exact_bath_harmonics_per_particle": eb.n_points / n,
        "exact_bath_harmonics_max": eb.max_harmonics_used,
        "exact_bath_n_direct": eb.n_direct,
    }


def memory_run(n, threads):
    """A short run_md at N = n with 100 active origins; returns (peak RSS in GB, wall s)."""
    state = equilibrium.ThermalState(M0=M0)
    t = time.perf_counter()
    # 100 slots of the ring buffer: max_lag / origin_every + 1 = 100, and t_max >= 2 max_lag
    # so that more than 100 origins complete their window
    run = MDRun(
        dynamics="full",
        n_particles=n,
        n_test=0,
        dt=0.25,
        t_max=100.0,
        sample_every=0.5,
        max_lag=49.5,
        origin_every=0.5,
        kappa_max=float(orbits.kappa_from_rescaled_action(2.0, M0)),
        n_bins=40,
        n_blocks=2,
    )
    res = md.run_md(state, run, seed=0, threads=threads, progress=None)
    wall = time.perf_counter() - t
    assert res.attrs["n_origins"] >= 100
    rss_gb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e9  # KiB on Linux
    return rss_gb, wall


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--n", type=int, default=500_000)
    ap.add_argument("--n-test-bath", type=int, default=50_000)
    ap.add_argument(
        "--memory",
        action="store_true",
        help="also measure the peak RSS of a short run (in a subprocess)",
    )
    ap.add_argument("--memory-child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--no-ensemble", action="store_true", help="skip the ensemble engine's figure")
    args = ap.parse_args(argv)
    if args.memory_child:
        rss, wall = memory_run(args.n, args.threads)
        print(json.dumps({"peak_rss_gb": rss, "memory_run_wall_s": wall}))
        return
    res = measure(args.n, args.threads, args.n_test_bath)
    res.update(exact_bath_cost(args.n, args.threads))
    if not args.no_ensemble:  # issue 14's figure, from benchmarks/bench_ensemble.py
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import bench_ensemble

        ens = bench_ensemble.measure(threads=args.threads)
        res.update(
            {f"ensemble_{k}" if not k.startswith("ensemble") else k: v for k, v in ens.items()}
        )
    if args.memory:
        out = subprocess.run(
            [
                sys.executable,
                __file__,
                "--memory-child",
                "--n",
                str(args.n),
                "--threads",
                str(args.threads),
            ],
            capture_output=True,
            text=True,
            check=True,
        )
        res.update(json.loads(out.stdout.strip().splitlines()[-1]))
    if args.json:
        print(json.dumps(res))
        return
    print(
        f"N = {res['n']}, threads = {res['threads']}, machine: {numba.config.NUMBA_NUM_THREADS}"
        " cores visible to numba"
    )
    print(
        f"full dynamics:  {res['full_psteps_per_s']:.3g} particle-steps/s   "
        f"(numpy {res['numpy_psteps_per_s']:.3g}, x{res['full_speedup_vs_numpy']:.1f})"
    )
    print(
        f"full dynamics, 1 thread, per CPU second (insensitive to other load): "
        f"{res['full_psteps_per_cpu_s_1thread']:.3g}"
    )
    print(
        f"previous kernel (angle stored, sincos every step): "
        f"{res['previous_full_psteps_per_s']:.3g} particle-steps/s, 1 thread per CPU second "
        f"{res['previous_full_psteps_per_cpu_s_1thread']:.3g}  "
        f"(present x{res['full_speedup_vs_previous']:.2f})"
    )
    print(
        f"float32 step until issue 39 (Taylor sincos, kick with h rounded): "
        f"{res['float32_taylor_full_psteps_per_s']:.3g} particle-steps/s, 1 thread per CPU "
        f"second {res['float32_taylor_full_psteps_per_cpu_s_1thread']:.3g}  (present "
        f"x{res['full_speed_vs_float32_taylor']:.3f}, per CPU second "
        f"x{res['full_speed_vs_float32_taylor_cpu_1thread']:.3f})"
    )
    print(
        f"bath dynamics:  {res['bath_psteps_per_s']:.3g} particle-steps/s   "
        f"(N_b = {res['n']} + {res['n_test_bath']} test; numpy "
        f"{res['numpy_bath_psteps_per_s']:.3g}, x{res['bath_speedup_vs_numpy']:.1f})"
    )
    print(
        f"actions of 5e5: {res['actions_seconds_per_5e5']:.3g} s   "
        f"(numpy/scipy {res['numpy_actions_seconds_per_5e5']:.3g} s, "
        f"x{res['actions_speedup_vs_numpy']:.1f})"
    )
    print(
        f"<dJ^2> accumulation: {res['accumulate_ns_per_origin_particle']:.3g} ns per "
        f"(active origin, particle) and sampling time on 1 thread, previous "
        f"{res['previous_accumulate_ns_per_origin_particle']:.3g} "
        f"(present x{res['accumulate_speedup_vs_previous']:.2f}; the sums agree: "
        f"{res['accumulate_sums_equal_previous']})"
    )
    print(
        f"(1-min load average of the machine at the end: {res['load_average_1min']:.2f}; "
        f"numba threading layer {res['threading_layer']}, OMP_WAIT_POLICY "
        f"{res['omp_wait_policy']})"
    )
    print(
        f"bath of one MD(bath) realisation (N_b = {res['exact_bath_n']}, t = "
        f"{res['exact_bath_t_run']:g}, dt = {res['exact_bath_dt']:g}), CPU s: integrated "
        f"{res['integrated_bath_cpu_s_per_realisation']:.3g}, exact orbits "
        f"{res['exact_bath_cpu_s_per_realisation']:.3g}  (x{res['exact_bath_speedup']:.1f}; "
        f"{res['exact_bath_harmonics_per_particle']:.1f} harmonics per particle, at most "
        f"{res['exact_bath_harmonics_max']}, {res['exact_bath_n_direct']} integrated directly)"
    )
    if "ensemble_particle_steps_per_s" in res:
        print(
            f"ensemble (issue 14): N = {res['ensemble_n']}, R = {res['ensemble_r']}: "
            f"{res['ensemble_particle_steps_per_s']:.3g} particle-steps/s aggregate "
            f"(single-system kernel x{res['ensemble_speedup']:.2f} slower)"
        )
    if "peak_rss_gb" in res:
        print(
            f"peak RSS of a short run_md at N = {res['n']} with 100 active origins: "
            f"{res['peak_rss_gb']:.2f} GB (run wall {res['memory_run_wall_s']:.1f} s)"
        )


if __name__ == "__main__":
    main()
