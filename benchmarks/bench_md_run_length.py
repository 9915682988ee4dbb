"""Benchmark of the u = 0.2475 MD's run length: one realisation of rule md with the earlier
length (config/experiments/u2475_long.yaml: t_max 1000, max_lag 500) against the present
defaults of config/config.yaml (t_max 700, max_lag 200), alternately in the same run.

    python benchmarks/bench_md_run_length.py [--json] [--dynamics full bath] [--reps 2]

The fit window of u = 0.2475 is lags 50-200 from origins 0-500 in both, so MD(full) gives the
same N D to the bit (tests/test_md.py) and the error at equal CPU time goes as sqrt(CPU):
its ratio present / earlier is sqrt(CPU ratio).  MD(bath)'s exact bath is synthesised over the
run's steps, so its realisations differ by rounding, its errors statistically equal.

Per length and dynamics: the wall time of one realisation on one thread (initial conditions
included) and its parts as run_md clocks them, the best of --reps.  Kernels are compiled on a
tiny run before any timing; no numba cache.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os

import numba
import yaml
from bench_md_sampling import CONFIG, PARTS, ROOT, best_alternating

from hmfdiff.dynamics.runs import md_runs
from hmfdiff.meanfield.equilibrium import make_state

CASE = "thermal_u0.2475"
EARLIER = os.path.join(ROOT, "config", "experiments", "u2475_long.yaml")


def lengths():
    """(earlier, present): t_max and max_lag of the case under each config."""
    keys = ("t_max", "max_lag")
    present = yaml.safe_load(open(CONFIG))["md"]["runs"][CASE]
    earlier = yaml.safe_load(open(EARLIER))["md"]["runs"][CASE]
    return {k: float(earlier[k]) for k in keys}, {k: float(present[k]) for k in keys}


def time_lengths(dynamics, reps):
    config = yaml.safe_load(open(CONFIG))
    base = md_runs(config)[(CASE, dynamics)]
    state = make_state(config["cases"][CASE])
    earlier, present = lengths()
    runs = {"earlier": dataclasses.replace(base, **earlier), "present": base}
    assert {k: getattr(base, k) for k in present} == present
    best = best_alternating(state, runs, reps)
    out = {"case": CASE, "dynamics": dynamics, "n_particles": base.n_particles}
    for name, (wall, parts) in best.items():
        out[f"{name}_t_max"] = runs[name].t_max
        out[f"{name}_max_lag"] = runs[name].max_lag
        out[f"{name}_n_origins"] = runs[name].n_origins
        out[f"{name}_wall_s"] = wall
        out.update({f"{name}_{k}_s": v for k, v in parts.items()})
    out["cpu_ratio"] = out["present_wall_s"] / out["earlier_wall_s"]
    out["error_at_equal_cpu_ratio"] = out["cpu_ratio"] ** 0.5
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--dynamics", nargs="+", default=["full", "bath"], choices=("bath", "full"))
    ap.add_argument("--reps", type=int, default=2)
    args = ap.parse_args(argv)
    numba.set_num_threads(1)
    res = {dyn: time_lengths(dyn, args.reps) for dyn in args.dynamics}
    res["load_average_1min"] = os.getloadavg()[0]
    if args.json:
        print(json.dumps(res))
        return
    earlier, present = lengths()
    print(f"{CASE}: earlier {earlier}, present {present}; one realisation, 1 thread")
    for dyn in args.dynamics:
        r = res[dyn]
        print(f"{dyn}, N = {r['n_particles']}:")
        for name in ("earlier", "present"):
            parts = ", ".join(f"{k} {r[f'{name}_{k}_s']:.2f}" for k in PARTS)
            print(
                f"  {name:8s} {r[f'{name}_wall_s']:6.2f} s  (t_max {r[f'{name}_t_max']:g}, "
                f"{r[f'{name}_n_origins']} origins; {parts})"
            )
        same = "the same N D" if dyn == "full" else "errors equal within their noise"
        print(
            f"  CPU present / earlier {r['cpu_ratio']:.3f}; error at equal CPU present / "
            f"earlier {r['error_at_equal_cpu_ratio']:.3f} ({same})"
        )
    print(f"(1-min load average at the end: {res['load_average_1min']:.2f})")


if __name__ == "__main__":
    main()
