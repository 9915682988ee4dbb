"""Rule fit: N*D_MD per bin from the seeds of one case and dynamics (results/fits/...)."""

import json

from hmfdiff.analysis.fits import diffusion_fit
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("fit", sm.log[0])
spec = json.loads(sm.params.fit)
seeds = [read_dataset(p, required=["sum_dJbar2", "count"]) for p in sm.input.seeds]
fit = diffusion_fit(
    seeds,
    window=spec["fit_window"],
    min_particles=spec["min_particles"],
    separatrix_band=spec["separatrix_band_fit"],
)
write_dataset(
    fit,
    sm.output[0],
    {"fit": spec, "seeds": list(map(str, sm.input.seeds))},
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
