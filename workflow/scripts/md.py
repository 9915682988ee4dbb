"""Rules md and md_scaling: a block of MD realisations of one case and dynamics, seed after seed
in one job, into one folder of seed{s}.nc files (rule md: results/md/{case}/{dynamics}/
seeds{first}-{last}/, a block of about md.job_seconds of work; rule md_scaling: every seed of
one size of a 1/N study, results/scaling/{case}/{dynamics}/N{n}/seeds/).  Each file is what one
realisation of that seed gives (same seed, same numbers, whatever the block); the folder
appears only once the whole block is written."""

# numba reads its cache directory when the kernels are imported: set it first (a private copy
# of the shared cache warmed by rule kernels, so that parallel jobs never write one directory)
from hmfdiff.dynamics.kernel_cache import cache_counts, use_kernel_cache

sm = snakemake  # noqa: F821
use_kernel_cache(sm.input.kernels)

import time  # noqa: E402

from hmfdiff.dynamics.md import run_md  # noqa: E402
from hmfdiff.dynamics.settings import MDRun  # noqa: E402
from hmfdiff.pipeline.io import (  # noqa: E402
    DEFAULT_TITLES,
    TITLE_WORDS,
    atomic_directory,
    read_dataset,
    write_dataset,
)
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset  # noqa: E402
from hmfdiff.pipeline.layouts.md import md_dataset  # noqa: E402
from hmfdiff.pipeline.runtime import get_logger, set_threads  # noqa: E402

log = get_logger(sm.rule, sm.log[0])
run = MDRun.from_json(sm.params.run)
first, last = sm.params.seeds
threads = set_threads(sm.threads)
state = state_from_dataset(read_dataset(sm.input.equilibrium, required=["M0"]))
case = sm.wildcards.case
words = {k: TITLE_WORDS.get(str(v), v) for k, v in dict(sm.wildcards.items()).items()}
start = time.perf_counter()
with atomic_directory(sm.output[0]) as folder:
    for seed in range(first, last + 1):
        log.info(
            "case %s, %s, seed %d: M0 = %.6f, N = %d, n_test = %d, threads = %d (block %d ... %d)",
            case,
            run.dynamics,
            seed,
            state.M0,
            run.n_particles,
            run.n_test,
            threads,
            first,
            last,
        )
        ds = md_dataset(run_md(state, run, seed, threads, progress=log.info))
        provenance = {"md": run.to_dict(realisation_only=True), "seed": seed, "M0": state.M0}
        title = DEFAULT_TITLES[sm.rule].format(**words, seed=seed)
        write_dataset(ds, folder / f"seed{seed}.nc", provenance, case=case, title=title)
        log.info("seed %d done (%.1f s)", seed, ds.attrs["wall_time_s"])
log.info(
    "wrote %s: seeds %d ... %d in %.1f s; compiled-kernel cache %s",
    sm.output[0],
    first,
    last,
    time.perf_counter() - start,
    cache_counts(),
)
