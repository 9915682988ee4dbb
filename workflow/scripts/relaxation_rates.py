"""Rule relaxation_rates: the early-window ensembles of one case across N (state and thermal
control) against its kinetic evolutions (results/relaxation_rates/{case}.nc, _summary.txt)."""

from hmfdiff.analysis.relaxation_rates import compare_rates
from hmfdiff.pipeline.io import atomic_path, read_dataset, write_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("relaxation_rates", sm.log[0])
md = [read_dataset(p, required=["hist", "overflow", "M_abs"]) for p in sm.input.md]
kinetic = {}
for p in sm.input.kinetic:
    ds = read_dataset(p, required=["f", "M0", "tau", "Sdot"])
    kinetic[ds.attrs["equation"]] = ds
ds, lines = compare_rates(md, kinetic)
write_dataset(
    ds, sm.output.dataset, {"ensembles": list(map(str, sm.input.md))}, case=sm.wildcards.case
)
with atomic_path(sm.output.summary) as tmp:
    tmp.write_text("\n".join(lines) + "\n")
for line in lines:
    log.info(line)
