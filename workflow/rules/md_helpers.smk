# ---- molecular dynamics -------------------------------------------------------------
# One MDRun record per (case, dynamics), built once from the config's md section (defaults
# merged with each case's overrides); every md/fit rule setting below is read from it.
from hmfdiff.dynamics.kernel_cache import kernel_version
from hmfdiff.dynamics.runs import md_runs, md_scaling_runs, scaling_kappa0

MD_RUNS = md_runs(config)
# {(case, dynamics, N): MDRun} of the 1/N studies, or {}
MD_SCALING = md_scaling_runs(config)
SCALING_KAPPA0 = scaling_kappa0(config)  # {case: bins figure 15 draws (kappa0) or None}
# the shared numba cache of the MD kernels of this version of the dynamics sources
KERNELS = f"{RES}/kernels/{kernel_version()}"


def md_cases():
    """MD cases in a fixed order, so that reordering the config reruns nothing."""
    return sorted({case for case, _ in MD_RUNS})


def md_run(case, dynamics):
    """The MDRun record of one case and dynamics."""
    return MD_RUNS[(case, dynamics)]


def md_folders(case, dynamics):
    """The folders of seed files of one case and dynamics, one per MD job (block of seeds)."""
    blocks = md_run(case, dynamics).seed_blocks()
    return [f"{RES}/md/{case}/{dynamics}/seeds{a}-{b}" for a, b in blocks]


def md_block(case, dynamics, first, last):
    """[first, last] of a block of seeds, refused unless it is one of the run's blocks (a
    folder asked for by hand with other bounds would mix block layouts)."""
    block = (int(first), int(last))
    blocks = md_run(case, dynamics).seed_blocks()
    if block not in blocks:
        raise ValueError(
            f"md {case} {dynamics}: seeds{first}-{last} is not a block of this run "
            f"(blocks: {', '.join(f'seeds{a}-{b}' for a, b in blocks)})"
        )
    return list(block)


def md_fit_spec(case):
    """The fit settings of a case (the same for both dynamics)."""
    return md_run(case, "bath").fit_settings()


def md_mem_mb(case, dynamics):
    return md_run(case, dynamics).memory_mb()


def md_runtime_min(case, dynamics, first, last):
    return md_run(case, dynamics).runtime_min(int(last) - int(first) + 1)


def scaling_run(case, dynamics, n):
    """The MDRun record of the 1/N study of `case` at N = n."""
    return MD_SCALING[(case, dynamics, int(n))]


def scaling_sizes(case):
    """The sizes of the 1/N study of `case`, increasing."""
    return sorted({n for c, _, n in MD_SCALING if c == case})
