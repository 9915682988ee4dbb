"""Benchmark of what an MD job pays besides the integration (issue 36): one realisation of rule
md at config/config.yaml's size, the previous path against the present one in the same run,
and the set-up of a relaxation_rates_md ensemble the same way.

    python benchmarks/bench_md_job.py [--json] [--case thermal_u0.0] [--dynamics bath]
                                      [--t-max T] [--reps 1] [--no-ensemble]

MD: `run_md` (one thread, as the md jobs run) as it is and within
`previous_kernels.previous_orbits()` (the orbit functions and the exact bath's set-up until
2026-11-28: both branches of K and J evaluated everywhere, Omega and c_0 of the bath evaluated
anew), alternately; per path the wall time of the realisation (initial conditions included)
and of its parts as run_md clocks them (bath synthesis, integration, actions, accumulation),
the best of --reps each, and whether the two paths' sums and magnetisation are bitwise equal.
--t-max shortens the run (default: the config's t_max); the lags, origins and particle numbers
are the config's.  MD(bath) by default: its set-up is what changed; MD(full) changed only in
drawing its test particles.

Ensemble: `ensemble._initial_ensemble` of the hot halo at N = 1000, R = 512 (the largest R of
relaxation_rates) against `previous_kernels.initial_ensemble_per_realisation_table` within
`previous_orbits()`, and whether the two ensembles are bitwise equal.

Kernels are compiled on a tiny run before any timing; no numba cache.  Ratios are old / new
(above 1: present faster).
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import os
import time

import numba
import numpy as np
import previous_kernels
import yaml

from hmfdiff.dynamics import ensemble, md
from hmfdiff.dynamics.runs import md_runs
from hmfdiff.meanfield.equilibrium import make_state

CONFIG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "config", "config.yaml")
PARTS = ("integration", "actions", "accumulation", "bath_synthesis")


def _run_with(context, state, run, seed):
    with context():
        t = time.perf_counter()
        res = md.run_md(state, run, seed, 1, progress=None)
        wall = time.perf_counter() - t
    return wall, {k: res.attrs[f"wall_{k}_s"] for k in PARTS}, (res.sums, res.m_fine)


def md_job(case, dynamics, t_max=None, reps=1, seed=0):
    config = yaml.safe_load(open(CONFIG))
    run = md_runs(config)[(case, dynamics)]
    if t_max is not None:
        run = dataclasses.replace(run, t_max=float(t_max))
    state = make_state(config["cases"][case])
    paths = {"previous": previous_kernels.previous_orbits, "present": contextlib.nullcontext}
    tiny = dataclasses.replace(
        run, n_particles=256, n_test=64, n_track=None,
        t_max=4.0 * run.max_lag, n_blocks=1,
    )  # fmt: skip
    for cls in paths.values():  # compile every kernel of both paths
        _run_with(cls, state, tiny, seed)
    best = {k: (np.inf, None) for k in paths}
    sums = {}
    for rep in range(reps):
        for name in paths if rep % 2 == 0 else reversed(list(paths)):
            wall, parts, sums[name] = _run_with(paths[name], state, run, seed)
            if wall < best[name][0]:
                best[name] = (wall, parts)
    out = {
        "case": case,
        "dynamics": dynamics,
        "n_particles": run.n_particles,
        "n_tracked": run.n_tracked,
        "t_max": run.t_max,
        "n_samples": run.n_samples,
        "sums_bitwise_equal": all(
            np.array_equal(a, b) for a, b in zip(sums["previous"], sums["present"], strict=True)
        ),
    }
    for name, (wall, parts) in best.items():
        out[f"{name}_wall_s"] = wall
        out.update({f"{name}_{k}_s": v for k, v in parts.items()})
    out["wall_ratio"] = out["previous_wall_s"] / out["present_wall_s"]
    if out["present_bath_synthesis_s"] > 0:
        out["bath_synthesis_ratio"] = (
            out["previous_bath_synthesis_s"] / out["present_bath_synthesis_s"]
        )
    return out


def ensemble_setup(n=1000, r=512, seed=2):
    config = yaml.safe_load(open(CONFIG))
    state = make_state(config["cases"]["corehalo_hothalo"])
    ensemble._initial_ensemble(state, 64, 2, seed)  # compile
    with previous_kernels.previous_orbits():
        t = time.perf_counter()
        old = previous_kernels.initial_ensemble_per_realisation_table(state, n, r, seed)
        t_old = time.perf_counter() - t
    t = time.perf_counter()
    new = ensemble._initial_ensemble(state, n, r, seed)
    t_new = time.perf_counter() - t
    equal = all(np.array_equal(getattr(old, k), getattr(new, k)) for k in ("p", "S", "C", "M"))
    return {
        "ensemble_setup_n": n,
        "ensemble_setup_r": r,
        "ensemble_setup_previous_s": t_old,
        "ensemble_setup_present_s": t_new,
        "ensemble_setup_ratio": t_old / t_new,
        "ensemble_setup_bitwise_equal": equal,
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--case", default="thermal_u0.0")
    ap.add_argument("--dynamics", default="bath", choices=("bath", "full"))
    ap.add_argument("--t-max", type=float, default=None, help="shorter production run")
    ap.add_argument("--reps", type=int, default=1)
    ap.add_argument("--no-ensemble", action="store_true", help="skip the ensemble set-up")
    args = ap.parse_args(argv)
    numba.set_num_threads(1)
    res = md_job(args.case, args.dynamics, args.t_max, args.reps)
    if not args.no_ensemble:
        res.update(ensemble_setup())
    res["load_average_1min"] = os.getloadavg()[0]
    if args.json:
        print(json.dumps(res))
        return
    print(
        f"one md realisation: {res['case']} {res['dynamics']}, N = {res['n_particles']}, "
        f"{res['n_tracked']} tracked, t_max = {res['t_max']:g} ({res['n_samples']} samples), "
        "1 thread"
    )
    for name in ("previous", "present"):
        parts = ", ".join(f"{k} {res[f'{name}_{k}_s']:.2f}" for k in PARTS)
        print(f"  {name:8s} {res[f'{name}_wall_s']:6.2f} s  ({parts})")
    synthesis = (
        f", bath synthesis x{res['bath_synthesis_ratio']:.2f}"
        if "bath_synthesis_ratio" in res
        else ""
    )
    print(
        f"  ratio previous / present: wall x{res['wall_ratio']:.2f}{synthesis}; sums and "
        f"magnetisation bitwise equal: {res['sums_bitwise_equal']}"
    )
    if "ensemble_setup_ratio" in res:
        print(
            f"ensemble set-up, hot halo N = {res['ensemble_setup_n']}, R = "
            f"{res['ensemble_setup_r']}: previous {res['ensemble_setup_previous_s']:.2f} s, "
            f"present {res['ensemble_setup_present_s']:.2f} s (x{res['ensemble_setup_ratio']:.2f}"
            f"; bitwise equal: {res['ensemble_setup_bitwise_equal']})"
        )
    print(f"(1-min load average at the end: {res['load_average_1min']:.2f})")


if __name__ == "__main__":
    main()
