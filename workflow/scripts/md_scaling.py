"""Rule md_scaling: every MD realisation of one size of a 1/N study, one after the other in one
job (results/scaling/{case}/{dynamics}/N{n}/seeds/seed{s}.nc, s = 0 ... seeds - 1).  A small-N
realisation takes less than a second, less than starting a job; each file is the one that
rule md would write for that seed (same seed, same numbers)."""

# numba reads its cache directory when the kernels are imported: set it first (a private copy
# of the shared cache warmed by rule kernels, so that parallel jobs never write one directory)
from hmfdiff.dynamics.kernel_cache import cache_counts, use_kernel_cache

sm = snakemake  # noqa: F821
use_kernel_cache(sm.input.kernels)

import os  # noqa: E402

from hmfdiff.dynamics.md import run_md  # noqa: E402
from hmfdiff.dynamics.settings import MDRun  # noqa: E402
from hmfdiff.pipeline.io import DEFAULT_TITLES, read_dataset, write_dataset  # noqa: E402
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset  # noqa: E402
from hmfdiff.pipeline.layouts.md import md_dataset  # noqa: E402
from hmfdiff.pipeline.runtime import get_logger, set_threads  # noqa: E402

log = get_logger("md_scaling", sm.log[0])
run = MDRun.from_json(sm.params.run)
seeds = int(sm.params.seeds)
threads = set_threads(sm.threads)
state = state_from_dataset(read_dataset(sm.input.equilibrium, required=["M0"]))
case, n = sm.wildcards.case, int(sm.wildcards.n)
out = sm.output[0]
os.makedirs(out, exist_ok=True)
log.info(
    "case %s, %s, N = %d, %d seeds: M0 = %.6f, n_test = %d, threads = %d",
    case,
    run.dynamics,
    n,
    seeds,
    state.M0,
    run.n_test,
    threads,
)
for seed in range(seeds):
    ds = md_dataset(run_md(state, run, seed, threads, progress=log.info))
    provenance = {"md": run.to_dict(realisation_only=True), "seed": seed, "M0": state.M0}
    path = os.path.join(out, f"seed{seed}.nc")
    title = DEFAULT_TITLES["md_scaling"].format(dynamics=run.dynamics, case=case, n=n, seed=seed)
    write_dataset(ds, path, provenance, case=case, title=title)
    log.info("wrote %s (%.1f s)", path, ds.attrs["wall_time_s"])
log.info("compiled-kernel cache %s", cache_counts())
