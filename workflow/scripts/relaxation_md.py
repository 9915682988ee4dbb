"""Rules relaxation_md and relaxation_rates_md: an ensemble of N-body relaxations of one case
at one N (results/relaxation_md/{case}/N{N}.nc), or of its initial state or the thermal state
of the same energy over the early window (results/relaxation_rates/{case}/{initial}/N{N}.nc).
The J-bar bins are the case's in both, so that the thermal control is binned as the state."""

# numba reads its cache directory when the kernels are imported: set it first (a private copy
# of the shared cache warmed by rule kernels; compiling the ensemble's kernels took ~8 s a job)
from hmfdiff.dynamics.kernel_cache import cache_counts, use_kernel_cache

sm = snakemake  # noqa: F821
use_kernel_cache(sm.input.kernels)

import json  # noqa: E402

import numpy as np  # noqa: E402

from hmfdiff.dynamics.ensemble import measurement_times, run_ensemble  # noqa: E402
from hmfdiff.meanfield import orbits  # noqa: E402
from hmfdiff.meanfield.equilibrium import ThermalState  # noqa: E402
from hmfdiff.pipeline.io import read_dataset, write_dataset  # noqa: E402
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset  # noqa: E402
from hmfdiff.pipeline.layouts.relaxation_md import relaxation_md_dataset  # noqa: E402
from hmfdiff.pipeline.runtime import get_logger, set_threads  # noqa: E402

log = get_logger("relaxation_md", sm.log[0])
run = json.loads(sm.params.run)
threads = set_threads(sm.threads)
state = state_from_dataset(read_dataset(sm.input.equilibrium, required=["M0"]))
initial = sm.params.initial
drawn = ThermalState(u=state.u) if initial == "thermal" else state
n = int(sm.wildcards.n)
n_real = max(1, run["particles_per_size"] // n)
t_max = run["tau_max"] * n
times = measurement_times(t_max, run["n_times"], run["dt"], t_first=run["tau_first"] * n)
edges = np.linspace(
    0.0, float(orbits.rescaled_action(run["kappa_max"], state.M0)), run["n_bins"] + 1
)
log.info(
    "case %s (%s, M0 = %.6f): N = %d, R = %d realisations, t_max = %.6g (tau = %.3g), dt = %g, "
    "threads = %d",
    sm.wildcards.case,
    "thermal state of its energy" if initial == "thermal" else "its state",
    drawn.M0,
    n,
    n_real,
    t_max,
    run["tau_max"],
    run["dt"],
    threads,
)
out = run_ensemble(
    drawn,
    n_particles=n,
    n_realisations=n_real,
    dt=run["dt"],
    times=times,
    jbar_edges=edges,
    seed=run["seed"],
    threads=threads,
    progress=log.info,
)
ds = relaxation_md_dataset(out, edges, case=sm.wildcards.case, state=drawn, n_particles=n, run=run)
ds.attrs["initial"] = initial
write_dataset(
    ds, sm.output[0], {"relaxation_md": run, "N": n, "initial": initial}, case=sm.wildcards.case
)
log.info(
    "wrote %s (%.1f s); compiled-kernel cache %s", sm.output[0], out["wall_time_s"], cache_counts()
)
