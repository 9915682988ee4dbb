"""Benchmark of the MD's sampling settings (issue 36, precision per CPU-second): one realisation
of rule md with the earlier sampling (config/experiments/md_dense_sampling.yaml: 100 000 of the
N tracked in MD(full), actions every 2 time units) against the present defaults of
config/config.yaml (10 000 tracked, every 10), alternately in the same run, and the error per
CPU-second that follows.

    python benchmarks/bench_md_sampling.py [--json] [--case thermal_u0.0]
                                           [--dynamics full bath] [--t-max T] [--reps 1]

Per setting and dynamics: the wall time of one realisation on one thread (initial conditions
included) and its parts as run_md clocks them (integration, actions, accumulation, bath
synthesis), the best of --reps.  The errors are not measured here (that needs 20 seeds of each
setting): the per-bin error ratios of the two settings on the same seeds are read from the
studies' outputs, docs/reference/track_count_u0.0_full.txt (tracked particles) and
sample_every_u0.0_full.txt (sampling interval), both MD(full) of u = 0 (studies/fit_precision.py).
The figure of merit is the error at equal CPU time, err x sqrt(CPU): its ratio present /
earlier is (error ratio) x sqrt(CPU ratio), below 1 when the present settings buy more
precision per CPU-second.  The two error ratios were measured one lever at a time; their
product stands for both together.  MD(bath) tracks only its test particles, so only the
sampling interval applies to it, and its error ratio is borrowed from the MD(full) study
(studies/validation_runs.py on two full runs measures it directly).

Kernels are compiled on a tiny run before any timing; no numba cache.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import re
import time

import numba
import yaml

from hmfdiff.dynamics import md
from hmfdiff.dynamics.runs import md_runs
from hmfdiff.meanfield.equilibrium import make_state

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
CONFIG = os.path.join(ROOT, "config", "config.yaml")
EARLIER = os.path.join(ROOT, "config", "experiments", "md_dense_sampling.yaml")
STUDIES = {
    "n_track": os.path.join(ROOT, "docs", "reference", "track_count_u0.0_full.txt"),
    "sample_every": os.path.join(ROOT, "docs", "reference", "sample_every_u0.0_full.txt"),
}
PARTS = ("integration", "actions", "accumulation", "bath_synthesis")


def settings():
    """(earlier, present): the md fields the two settings give."""
    present = yaml.safe_load(open(CONFIG))["md"]
    earlier = yaml.safe_load(open(EARLIER))["md"]
    keys = ("n_track", "sample_every")
    return {k: earlier[k] for k in keys}, {k: present[k] for k in keys}


def error_ratio(path):
    """Median and mean of error B / error A over the study's bins (B the fewer samples)."""
    text = open(path).read()
    m = re.search(r"error B / error A: median ([\d.]+), range [\d.-]+, mean ([\d.]+)", text)
    if m is None:
        raise SystemExit(f"{path}: no 'error B / error A' line; rerun studies/fit_precision.py")
    return float(m.group(1)), float(m.group(2))


def one_realisation(state, run, seed=0):
    t = time.perf_counter()
    res = md.run_md(state, run, seed, 1, progress=None)
    wall = time.perf_counter() - t
    return wall, {k: res.attrs[f"wall_{k}_s"] for k in PARTS}


def best_alternating(state, runs, reps):
    """{name: (wall, parts)}: the best of `reps` realisations of each run of `runs` ({name:
    MDRun}), run alternately (the order reversed every other repetition), after a tiny run of
    each has compiled every kernel it uses."""
    for run in runs.values():
        tiny = dataclasses.replace(
            run, n_particles=256, n_test=64, n_track=None, t_max=4.0 * run.max_lag, n_blocks=1
        )
        one_realisation(state, tiny)
    best = {k: (float("inf"), None) for k in runs}
    for rep in range(reps):
        for name in runs if rep % 2 == 0 else reversed(list(runs)):
            wall, parts = one_realisation(state, runs[name])
            if wall < best[name][0]:
                best[name] = (wall, parts)
    return best


def time_settings(case, dynamics, t_max=None, reps=1):
    config = yaml.safe_load(open(CONFIG))
    base = md_runs(config)[(case, dynamics)]
    if t_max is not None:
        base = dataclasses.replace(base, t_max=float(t_max))
    state = make_state(config["cases"][case])
    earlier, present = settings()
    runs = {}
    for name, s in (("earlier", earlier), ("present", present)):
        track = None if dynamics == "bath" else min(int(s["n_track"]), base.n_particles)
        runs[name] = dataclasses.replace(base, n_track=track, sample_every=float(s["sample_every"]))
    best = best_alternating(state, runs, reps)
    out = {"case": case, "dynamics": dynamics, "n_particles": base.n_particles, "t_max": base.t_max}
    for name, (wall, parts) in best.items():
        out[f"{name}_n_tracked"] = runs[name].n_tracked
        out[f"{name}_n_samples"] = runs[name].n_samples
        out[f"{name}_wall_s"] = wall
        out.update({f"{name}_{k}_s": v for k, v in parts.items()})
    out["cpu_ratio"] = out["present_wall_s"] / out["earlier_wall_s"]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--case", default="thermal_u0.0")
    ap.add_argument("--dynamics", nargs="+", default=["full", "bath"], choices=("bath", "full"))
    ap.add_argument("--t-max", type=float, default=None, help="shorter production run")
    ap.add_argument("--reps", type=int, default=1)
    args = ap.parse_args(argv)
    numba.set_num_threads(1)
    earlier, present = settings()
    errors = {k: error_ratio(p) for k, p in STUDIES.items()}
    err = errors["n_track"][0] * errors["sample_every"][0]
    res = {"earlier": earlier, "present": present, "error_ratio_median": errors}
    for dyn in args.dynamics:
        r = time_settings(args.case, dyn, args.t_max, args.reps)
        # MD(bath) tracks only its test particles: the tracked-count lever does not apply
        e = errors["sample_every"][0] if dyn == "bath" else err
        r["error_ratio"] = e
        r["error_at_equal_cpu_ratio"] = e * r["cpu_ratio"] ** 0.5
        res[dyn] = r
    res["load_average_1min"] = os.getloadavg()[0]
    if args.json:
        print(json.dumps(res))
        return
    print(f"earlier sampling {earlier}, present {present}; one realisation, 1 thread")
    for dyn in args.dynamics:
        r = res[dyn]
        print(f"{args.case} {dyn}, N = {r['n_particles']}, t_max = {r['t_max']:g}:")
        for name in ("earlier", "present"):
            parts = ", ".join(f"{k} {r[f'{name}_{k}_s']:.2f}" for k in PARTS)
            print(
                f"  {name:8s} {r[f'{name}_wall_s']:6.2f} s  ({r[f'{name}_n_tracked']} tracked, "
                f"{r[f'{name}_n_samples']} samples; {parts})"
            )
        print(
            f"  CPU present / earlier {r['cpu_ratio']:.3f}; error present / earlier (median, "
            f"from the studies) {r['error_ratio']:.3f}; error at equal CPU present / earlier "
            f"{r['error_at_equal_cpu_ratio']:.3f}"
        )
    med = ", ".join(f"{k}: median {v[0]:.3f}, mean {v[1]:.3f}" for k, v in errors.items())
    print(f"(error ratios of the studies, MD(full) u = 0, same seeds: {med})")
    print(f"(1-min load average at the end: {res['load_average_1min']:.2f})")


if __name__ == "__main__":
    main()
