"""Rule kernels: compile every MD kernel once into the shared numba cache of this kernel
version (results/kernels/{version}/), before any MD job starts."""

from hmfdiff.dynamics.kernel_cache import warm
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("kernels", sm.log[0])
info = warm(sm.output[0])
log.info("compiled MD kernels into %s: %s", sm.output[0], info)
