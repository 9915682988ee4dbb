"""Rules fit and fit_scaling: N*D_MD per bin from the seeds of one case and dynamics
(results/fits/...), or of one size of a 1/N study (its seeds/ folder of rule md_scaling)."""

import json
import os
from pathlib import Path

from hmfdiff.analysis.fits import diffusion_fit
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("fit", sm.log[0])
spec = json.loads(sm.params.fit)


def seed_files(inputs):
    """The seed files: the inputs themselves, or the seed{s}.nc of an input folder in the
    order of s."""
    inputs = [inputs] if isinstance(inputs, str) else list(inputs)
    out = []
    for p in inputs:
        if os.path.isdir(p):
            found = sorted(Path(p).glob("seed*.nc"), key=lambda q: int(q.stem.removeprefix("seed")))
            if len(found) != int(sm.params.n_seeds):
                raise RuntimeError(f"{p}: {len(found)} seed files, expected {sm.params.n_seeds}")
            out += [str(q) for q in found]
        else:
            out.append(p)
    return out


paths = seed_files(sm.input.seeds)
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
