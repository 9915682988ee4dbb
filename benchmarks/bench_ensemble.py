"""Benchmark of the ensemble engine (hmfdiff.dynamics.ensemble) for relaxation at small N.

Aggregate particle-steps per second of R = 100 realisations of N = 2000 particles (full
dynamics, eq. hmfmdfull) advanced together, against the single-system kernel
(`integrator.leapfrog`, field 'self') doing the same work realisation after realisation, in the
same run.  Target (issue 14): at least 5e8 particle-steps/s aggregate on 2 threads.

    python benchmarks/bench_ensemble.py [--json] [--threads 2] [--n 2000] [--r 100] [--steps 200]

Also against the previous ensemble kernel (angle stored, float64) and the float32 step as it
ran until issue 39 (`previous_kernels.ensemble_steps_float32_taylor`: Taylor sincos, kick with
h rounded), timed alternately with the present one in the same run.
Kernels are compiled on small arrays before any timing; timings are the best of 3 repetitions.
"""

from __future__ import annotations

import argparse
import json
import time

import numba
import numpy as np
import previous_kernels

from hmfdiff.dynamics import ensemble, integrator
from hmfdiff.meanfield.equilibrium import ThermalState


def best_of(fn, reps=3):
    best = np.inf
    for _ in range(reps):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def measure(n=2000, r=100, n_steps=200, threads=2, dt=0.05):
    numba.set_num_threads(threads)
    state = ThermalState(M0=0.72846)
    ens = ensemble._initial_ensemble(state, n, r, seed=1)
    th0, p0 = ens.theta.copy(), ens.p.copy()
    # warm both kernels (same types)
    ensemble._initial_ensemble(state, 50, 2, seed=2).advance(2, dt)
    integrator.leapfrog(integrator.Particles(th0[0, :50], p0[0, :50]), 2, dt, "self")

    # the previous ensemble kernel (angle stored) on the same initial conditions, timed
    # alternately with the present one
    tha, pa = th0.copy(), p0.copy()
    Sa, Ca = np.sin(tha), np.cos(tha)
    Ma = ens.M.copy()
    previous_kernels.ensemble_steps(tha[:2, :50].copy(), pa[:2, :50].copy(), Sa[:2, :50].copy(),
                                    Ca[:2, :50].copy(), Ma[:2].copy(), 2, dt)  # fmt: skip
    # the float32 step as it ran until issue 39 (Taylor sincos, kick with h rounded)
    pf, Sf, Cf, Mf = ens.p.copy(), ens.S.copy(), ens.C.copy(), ens.M.copy()
    small = (pf[:2, :50].copy(), Sf[:2, :50].copy(), Cf[:2, :50].copy(), Mf[:2].copy())
    previous_kernels.ensemble_steps_float32_taylor(*small, 2, dt)
    t_ens = t_prev = t_fix = np.inf
    for _ in range(3):
        t_ens = min(t_ens, best_of(lambda: ens.advance(n_steps, dt), reps=1))
        t_prev = min(
            t_prev,
            best_of(lambda: previous_kernels.ensemble_steps(tha, pa, Sa, Ca, Ma, n_steps, dt), 1),
        )
        t_fix = min(
            t_fix,
            best_of(
                lambda: previous_kernels.ensemble_steps_float32_taylor(pf, Sf, Cf, Mf, n_steps, dt),
                1,
            ),
        )
    singles = [integrator.Particles(th0[k], p0[k]) for k in range(r)]

    def run_singles():
        for P in singles:
            integrator.leapfrog(P, n_steps, dt, "self")

    t_single = best_of(run_singles)
    work = float(n) * r * n_steps
    return {
        "ensemble_particle_steps_per_s": work / t_ens,
        "single_kernel_particle_steps_per_s": work / t_single,
        "ensemble_speedup": t_single / t_ens,
        "previous_ensemble_particle_steps_per_s": work / t_prev,
        "ensemble_speedup_vs_previous": t_prev / t_ens,
        "float32_taylor_ensemble_particle_steps_per_s": work / t_fix,
        "ensemble_speed_vs_float32_taylor": t_fix / t_ens,
        "n": n,
        "r": r,
        "n_steps": n_steps,
        "threads": threads,
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--n", type=int, default=2000)
    ap.add_argument("--r", type=int, default=100)
    ap.add_argument("--steps", type=int, default=200)
    args = ap.parse_args(argv)
    res = measure(args.n, args.r, args.steps, args.threads)
    if args.json:
        print(json.dumps(res))
        return res
    print(
        f"ensemble N = {res['n']}, R = {res['r']}, {res['threads']} threads: "
        f"{res['ensemble_particle_steps_per_s']:.3g} particle-steps/s aggregate"
    )
    print(
        f"single-system kernel, same work: {res['single_kernel_particle_steps_per_s']:.3g} "
        f"particle-steps/s  (ensemble x{res['ensemble_speedup']:.2f})"
    )
    print(
        f"previous ensemble kernel (angle stored): "
        f"{res['previous_ensemble_particle_steps_per_s']:.3g} particle-steps/s  "
        f"(present x{res['ensemble_speedup_vs_previous']:.2f})"
    )
    print(
        f"float32 step until issue 39 (Taylor sincos, kick with h rounded): "
        f"{res['float32_taylor_ensemble_particle_steps_per_s']:.3g} particle-steps/s  "
        f"(present x{res['ensemble_speed_vs_float32_taylor']:.3f})"
    )
    return res


if __name__ == "__main__":
    main()
