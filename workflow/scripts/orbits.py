"""Rule orbits: action-angle variables and Fourier coefficients on a kappa grid."""

import json

from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.layouts.equilibrium import orbits_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("orbits", sm.log[0])
grid = json.loads(sm.params.grid)
eq = read_dataset(sm.input.equilibrium, required=["M0"])
M0 = float(eq["M0"])
ds = orbits_dataset(M0, grid["n_kappa"], grid["kappa_max"], grid["n_harmonics"])
ds.attrs["equilibrium_kind"] = eq.attrs.get("kind", "")
write_dataset(ds, sm.output[0], {"grid": grid, "M0": M0}, case=sm.wildcards.case)
log.info(
    "case %s: M0 = %.8f, %d kappa points -> %s",
    sm.wildcards.case,
    M0,
    ds.sizes["kappa"],
    sm.output[0],
)
