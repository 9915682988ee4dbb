"""Rule equilibrium: build the state of one case and store it (results/equilibrium/{case}.nc)."""

import json

from hmfdiff.meanfield.equilibrium import make_state
from hmfdiff.pipeline.io import write_dataset
from hmfdiff.pipeline.layouts.equilibrium import equilibrium_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("equilibrium", sm.log[0])
spec = json.loads(sm.params.spec)
grid = json.loads(sm.params.grid)
state = make_state(spec)
log.info(
    "case %s: kind %s, M0 = %.10f, u = %.10f", sm.wildcards.case, spec["kind"], state.M0, state.u
)
ds = equilibrium_dataset(state, grid["n_kappa"], grid["kappa_max"])
write_dataset(ds, sm.output[0], {"case": spec, "grid": grid}, case=sm.wildcards.case)
log.info("wrote %s", sm.output[0])
