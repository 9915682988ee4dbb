"""Rule md: one MD realisation of one case (results/md/{case}/{dynamics}/seed{seed}.nc)."""

# numba reads its cache directory when the kernels are imported: set it first (a private copy
# of the shared cache warmed by rule kernels, so that parallel jobs never write one directory)
from hmfdiff.dynamics.kernel_cache import cache_counts, use_kernel_cache

sm = snakemake  # noqa: F821
use_kernel_cache(sm.input.kernels)

from hmfdiff.dynamics.md import run_md  # noqa: E402
from hmfdiff.dynamics.settings import MDRun  # noqa: E402
from hmfdiff.pipeline.io import read_dataset, write_dataset  # noqa: E402
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset  # noqa: E402
from hmfdiff.pipeline.layouts.md import md_dataset  # noqa: E402
from hmfdiff.pipeline.runtime import get_logger, set_threads  # noqa: E402

log = get_logger("md", sm.log[0])
run = MDRun.from_json(sm.params.run)
seed = int(sm.wildcards.seed)
threads = set_threads(sm.threads)
state = state_from_dataset(read_dataset(sm.input.equilibrium, required=["M0"]))
log.info(
    "case %s, %s, seed %d: M0 = %.6f, N = %d, n_test = %d, threads = %d",
    sm.wildcards.case,
    run.dynamics,
    seed,
    state.M0,
    run.n_particles,
    run.n_test,
    threads,
)
ds = md_dataset(run_md(state, run, seed, threads, progress=log.info))
provenance = {"md": run.to_dict(realisation_only=True), "seed": seed, "M0": state.M0}
write_dataset(ds, sm.output[0], provenance, case=sm.wildcards.case)
log.info(
    "wrote %s (%.1f s); compiled-kernel cache %s",
    sm.output[0],
    ds.attrs["wall_time_s"],
    cache_counts(),
)
