"""The energy of the N-body relaxation ensembles against time (issue 39 part 1).

Runs the ensembles of the config's `relaxation_md` block as the rule relaxation_md runs them
(`dynamics.ensemble.run_ensemble`, the same state, seed, dt, realisations and measurement
schedule; the state from `make_state` of the case, as the equilibrium rule solves it) and
reports their energy per particle u against time: at each N the mean over realisations of
u(t_max) - u(0) with its spread (standard deviation between realisations), the largest
|mean u(t) - u(0)| over the schedule, relative to |u|, and the secular slope of u against t
(least squares per realisation over the times after t_max / 100, past the first steps'
O(dt^2) transient; the mean of the slopes +- its standard error over the realisations).

    python studies/energy_relaxation_md.py [--config config/config.yaml] [--case corehalo_hothalo]
        [--sizes 1000,2000,4000] [--thermal] [--tau-max 150] [--out FILE.npz]

--thermal runs the control (the thermal state of the case's energy) instead of the state.
Wall time at the default config: 2.1e11 particle-steps, about 25 min on one core.
"""

from __future__ import annotations

import argparse
import math

import numpy as np
import yaml

from hmfdiff.dynamics.ensemble import measurement_times, run_ensemble
from hmfdiff.meanfield import orbits
from hmfdiff.meanfield.equilibrium import ThermalState, make_state


def energy_stats(t, u, t_from):
    """Energy statistics of one ensemble: u of shape (T, R) at times t."""
    du = u - u[0]
    mean = du.mean(axis=1)
    R = u.shape[1]
    use = t >= t_from
    tc = t[use] - t[use].mean()
    slopes = tc @ (du[use] - du[use].mean(axis=0)) / (tc @ tc)
    return {
        "du_end": du[-1].mean(),
        "du_end_spread": du[-1].std(ddof=1) if R > 1 else 0.0,
        "max_abs_mean_du": np.max(np.abs(mean)),
        "u0": u[0].mean(),
        "slope": slopes.mean(),
        "slope_se": slopes.std(ddof=1) / math.sqrt(R) if R > 1 else math.nan,
        "R": R,
    }


def run_case(config, case, n, thermal=False, tau_max=None):
    """(times, energy (T, R)) of the relaxation_md ensemble of `case` at N = n."""
    rmd = config["relaxation_md"]
    run = {k: v for k, v in rmd.items() if k != "runs"}
    run.update(
        {k: v for k, v in rmd["runs"][case].items() if k not in ("n_particles", "control_sizes")}
    )
    if tau_max is not None:
        run["tau_max"] = tau_max
    state = make_state(config["cases"][case])
    drawn = ThermalState(u=state.u) if thermal else state
    n_real = max(1, run["particles_per_size"] // n)
    times = measurement_times(
        run["tau_max"] * n, run["n_times"], run["dt"], t_first=run["tau_first"] * n
    )
    edges = np.linspace(
        0.0, float(orbits.rescaled_action(run["kappa_max"], state.M0)), run["n_bins"] + 1
    )
    out = run_ensemble(
        drawn,
        n_particles=n,
        n_realisations=n_real,
        dt=run["dt"],
        times=times,
        jbar_edges=edges,
        seed=run["seed"],
        threads=run["threads"],
        progress=lambda msg: None,
    )
    return out["time"], out["energy"], out["wall_time_s"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default="config/config.yaml")
    ap.add_argument("--case", default="corehalo_hothalo")
    ap.add_argument("--sizes", default=None)
    ap.add_argument("--thermal", action="store_true")
    ap.add_argument("--tau-max", type=float, default=None)
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    with open(args.config) as f:
        config = yaml.safe_load(f)
    sizes = (
        [int(s) for s in args.sizes.split(",")]
        if args.sizes
        else config["relaxation_md"]["runs"][args.case]["n_particles"]
    )
    print(
        f"relaxation_md {args.case}{' (thermal control)' if args.thermal else ''}: energy per "
        "particle u; du = u(t) - u(0) per realisation"
    )
    print(
        f"{'N':>6s} {'R':>4s} {'t_max':>8s} {'mean du(t_max)':>15s} {'spread':>9s} "
        f"{'max|<du>|/|u|':>14s} {'slope (1/time)':>15s} {'+-':>9s} {'z':>6s} {'wall s':>7s}"
    )
    saved = {}
    for n in sizes:
        t, u, wall = run_case(config, args.case, n, args.thermal, args.tau_max)
        s = energy_stats(t, u, t[-1] / 100)
        z = s["slope"] / s["slope_se"] if s["slope_se"] > 0 else math.nan
        print(
            f"{n:6d} {s['R']:4d} {t[-1]:8.3g} {s['du_end']:+15.3e} {s['du_end_spread']:9.2e} "
            f"{s['max_abs_mean_du'] / abs(s['u0']):14.2e} {s['slope']:+15.3e} "
            f"{s['slope_se']:9.2e} {z:+6.1f} {wall:7.0f}",
            flush=True,
        )
        saved[f"time_N{n}"] = t
        saved[f"energy_N{n}"] = u
    if args.out:
        np.savez(args.out, **saved)


if __name__ == "__main__":
    main()
