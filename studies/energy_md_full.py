"""The energy of the MD(full) production runs against time (issue 39 part 2).

Runs realisations of MD(full) of the config's `md` block (`dynamics.md.run_md`, each case's
run as the md rule runs it: N, dt, t_max, seeds 1, 2, ...) and reports the energy per
particle u(t), which the run records at every sample (series 'energy', every sample_every):
per case, over the realisations, the mean of u(t_max) - u(0) and its spread (standard deviation
between realisations), the largest |u(t) - u(0)| of any realisation relative to |u|, and the
secular slope of u against t (least squares per realisation, the mean of the slopes +- its
standard error over the realisations; with one realisation, +- the least-squares error of the
slope from the residuals' scatter, which takes them as independent and so understates it).
The drift of the MD's energy over the run, slope x t_max, is set beside the quantities the
diffusion measurement reads: u itself and the thermal energy scale T (the rms momentum squared).

    python studies/energy_md_full.py [--config config/config.yaml] [--cases a,b] [--seeds 2]
        [--threads 1] [--out FILE]

At the default config one realisation is 5e5 (1e6 for thermal_u0.2475) particles x 20 000
steps: about 12 s on one core of an idle machine.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import yaml

from hmfdiff.dynamics.md import run_md
from hmfdiff.dynamics.runs import md_runs
from hmfdiff.meanfield.equilibrium import make_state


def stats(t, u):
    """Statistics of the energy series u of shape (T, R) at times t."""
    du = u - u[0]
    tc = t - t.mean()
    slopes = tc @ (du - du.mean(axis=0)) / (tc @ tc)
    R = u.shape[1]
    if R > 1:
        se = slopes.std(ddof=1) / math.sqrt(R)
    else:
        res = du[:, 0] - du[:, 0].mean() - slopes[0] * tc
        se = math.sqrt(res @ res / (t.size - 2) / (tc @ tc))
    return {
        "du_end": du[-1].mean(),
        "du_end_spread": du[-1].std(ddof=1) if R > 1 else math.nan,
        "max_rel": np.max(np.abs(du)) / abs(u[0].mean()),
        "slope": slopes.mean(),
        "slope_se": se,
        "u0": u[0].mean(),
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default="config/config.yaml")
    ap.add_argument("--cases", default=None)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    with open(args.config) as f:
        config = yaml.safe_load(f)
    runs = md_runs(config)
    cases = args.cases.split(",") if args.cases else sorted({c for c, _ in runs})
    lines = [
        f"MD(full) energy per particle u over the production run, {args.seeds} realisation(s) "
        "per case (seeds 1...); du = u(t) - u(0)",
        f"{'case':18s} {'N':>8s} {'dt':>5s} {'t_max':>6s} {'u':>9s} {'T':>7s} "
        f"{'mean du(t_max)':>15s} {'spread':>9s} {'max|du|/|u|':>12s} "
        f"{'slope (1/time)':>15s} {'+-':>9s} {'slope*t_max/T':>14s} {'wall s':>7s}",
    ]
    print("\n".join(lines), flush=True)
    for case in cases:
        run = runs[(case, "full")]
        state = make_state(config["cases"][case])
        us = []
        t0 = time.perf_counter()
        for seed in range(1, args.seeds + 1):
            res = run_md(state, run, seed, args.threads, progress=None)
            us.append(res.series["energy"])
        wall = (time.perf_counter() - t0) / args.seeds
        u = np.array(us).T
        t = np.arange(u.shape[0]) * run.sample_every
        s = stats(t, u)
        T = 2.0 * (s["u0"] + 0.5 * state.M0**2)  # <p^2> = 2 (u + M0^2/2) (mean field)
        line = (
            f"{case:18s} {run.n_particles:8d} {run.dt:5.3g} {run.t_max:6.4g} {s['u0']:+9.5f} "
            f"{T:7.4f} {s['du_end']:+15.3e} {s['du_end_spread']:9.2e} {s['max_rel']:12.2e} "
            f"{s['slope']:+15.3e} {s['slope_se']:9.2e} {s['slope'] * run.t_max / T:+14.2e} "
            f"{wall:7.1f}"
        )
        lines.append(line)
        print(line, flush=True)
    if args.out:
        with open(args.out, "w") as f:
            f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
