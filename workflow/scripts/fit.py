"""Rules fit and fit_scaling: N*D_MD per bin from the seeds of one case and dynamics (its
folders of blocks of seeds, results/fits/...), or of one size of a 1/N study (its seeds/
folder of rule md_scaling)."""

import json

from hmfdiff.analysis.fits import diffusion_fit
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.layouts.md import seed_files
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("fit", sm.log[0])
spec = json.loads(sm.params.fit)
paths = seed_files(sm.input.seeds, int(sm.params.n_seeds))
seeds = [read_dataset(p, required=["sum_dJbar2", "count"]) for p in paths]
fit = diffusion_fit(
    seeds,
    window=spec["fit_window"],
    min_particles=spec["min_particles"],
    separatrix_band=spec["separatrix_band_fit"],
)
write_dataset(
    fit,
    sm.output[0],
    {"fit": spec, "seeds": paths},
    case=sm.wildcards.case,
)
log.info(
    "case %s, %s: %d seeds, window %s -> %s",
    sm.wildcards.case,
    sm.wildcards.dynamics,
    len(seeds),
    spec["fit_window"],
    sm.output[0],
)
