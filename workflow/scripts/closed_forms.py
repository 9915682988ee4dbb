"""Rule closed_forms: the paper's analytic results for one case (results/analytic/{case}.nc)."""

import json

from hmfdiff.kinetic.closed_forms import closed_forms
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset
from hmfdiff.pipeline.layouts.theory import closed_forms_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("closed_forms", sm.log[0])
grid = json.loads(sm.params.grid)
args = dict(grid)
args["n_max"] = args.pop("n_max_librating")  # sums over |n|, |n'| <= n_max_librating
state = state_from_dataset(read_dataset(sm.input.equilibrium, required=["M0"]))
ds = closed_forms_dataset(closed_forms(state, **args))
write_dataset(ds, sm.output[0], {"closed_forms": grid, "M0": state.M0}, case=sm.wildcards.case)
log.info(
    "case %s (M0 = %.6f): %s -> %s",
    sm.wildcards.case,
    state.M0,
    ds.attrs["dielectric_method"],
    sm.output[0],
)
