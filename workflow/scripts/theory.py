"""Rule theory: the kinetic-theory grids of one case (results/theory/{case}.nc)."""

import json
import time

from hmfdiff.kinetic.theory import theory_grid
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset
from hmfdiff.pipeline.layouts.theory import theory_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("theory", sm.log[0])
grid = json.loads(sm.params.grid)
eq = read_dataset(sm.input.equilibrium, required=["M0"])
state = state_from_dataset(eq)
log.info("case %s: M0 = %.8f, grid %s", sm.wildcards.case, state.M0, grid)
t0 = time.perf_counter()
ds = theory_dataset(theory_grid(state, **grid))
log.info("computed in %.1f s", time.perf_counter() - t0)
write_dataset(ds, sm.output[0], {"theory": grid, "M0": state.M0}, case=sm.wildcards.case)
log.info("wrote %s", sm.output[0])
