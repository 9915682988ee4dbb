"""Rule md: one MD realisation of one case (results/md/{case}/{dynamics}/seed{seed}.nc)."""

import json

import numpy as np

from hmfdiff.dynamics.md import run_md
from hmfdiff.meanfield import orbits
from hmfdiff.pipeline.datasets import state_from_dataset
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.runtime import get_logger, set_threads

sm = snakemake  # noqa: F821
log = get_logger("md", sm.log[0])
run = json.loads(sm.params.run)
threads = set_threads(sm.threads)
state = state_from_dataset(read_dataset(sm.input.equilibrium, required=["M0"]))
jbar_max = float(orbits.rescaled_action(run["kappa_max"], state.M0))
edges = np.linspace(0.0, jbar_max, run["n_bins"] + 1)
log.info(
    "case %s, %s, seed %d: M0 = %.6f, N = %d, n_test = %d, threads = %d",
    sm.wildcards.case,
    run["dynamics"],
    run["seed"],
    state.M0,
    run["n_particles"],
    run["n_test"],
    threads,
)
ds = run_md(
    state,
    dynamics=run["dynamics"],
    n_particles=run["n_particles"],
    n_test=run["n_test"],
    test_sampling="uniform",
    jbar_range=(0.0, jbar_max),
    dt=run["dt"],
    t_max=run["t_max"],
    t_equilibrate=run["t_equilibrate"],
    sample_every=run["sample_every"],
    max_lag=run["max_lag"],
    origin_every=run["origin_every"],
    jbar_edges=edges,
    seed=run["seed"],
    threads=threads,
    n_blocks=run["n_blocks"],
    progress=log.info,
)
write_dataset(ds, sm.output[0], {"md": run, "M0": state.M0}, case=sm.wildcards.case)
log.info("wrote %s (%.1f s)", sm.output[0], ds.attrs.get("wall_time_s", float("nan")))
