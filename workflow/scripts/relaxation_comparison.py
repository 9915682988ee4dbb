"""Rule relaxation_comparison: the N-body ensembles of every case against its kinetic
evolutions (results/relaxation_comparison.csv, _summary.txt, relaxation_comparison/{case}.nc)."""

import csv
import os
from pathlib import Path

from hmfdiff.analysis.kinetic_uncertainty import (
    layer_model_times,
    md_times_from_summary,
    read_uncertainty_table,
)
from hmfdiff.analysis.relaxation_compare import (
    COMPARISON_COLUMNS,
    band_lines,
    compare_relaxation,
    summary_lines,
    with_kinetic_bands,
    with_layer_model,
    with_reference_md,
)
from hmfdiff.meanfield.equilibrium import ThermalState
from hmfdiff.pipeline.io import atomic_path, read_dataset, write_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("relaxation_comparison", sm.log[0])
md = [read_dataset(p, required=["hist", "M_abs"]) for p in sm.input.md]
controls = [read_dataset(p, required=["hist", "overflow"]) for p in sm.input.control]
kinetic = [read_dataset(p, required=["f", "M0", "tau"]) for p in sm.input.kinetic]
# the kinetic times' numerical uncertainty and N-body times of runs not rebuilt here (reference
# copies under docs/reference, where the checkout has them)
table = read_uncertainty_table(sm.input.uncertainty[0]) if sm.input.uncertainty else []
references = [(p, Path(p).read_text()) for p in sm.input.reference_md]
layer_models = [(p, Path(p).read_text()) for p in sm.input.layer_model]
rows, lines = [], []
for case, out in zip(sm.params.cases, sm.output.datasets, strict=True):
    state = state_from_dataset(
        read_dataset(next(p for p in sm.input.equilibrium if os.path.basename(p) == f"{case}.nc"))
    )
    ens = [d for d in md if d.attrs["case"] == case]
    kin = {d.attrs["equation"]: d for d in kinetic if d.attrs["case"] == case}
    ctrl = [d for d in controls if d.attrs["case"] == case]
    ds, case_rows, summary = compare_relaxation(
        ens, kin, state, ThermalState(u=state.u), controls=ctrl
    )
    ds = with_kinetic_bands(ds, kin, table)
    for path, text in references:
        ds = with_reference_md(ds, md_times_from_summary(text, case), path)
    for path, text in layer_models:
        ds = with_layer_model(ds, layer_model_times(text, case), path)
    write_dataset(ds, out, {"cases": sm.params.cases}, case=case)
    rows += case_rows
    lines += summary_lines(summary) + band_lines(ds)
with atomic_path(sm.output.table) as tmp, open(tmp, "w", newline="") as fh:
    w = csv.DictWriter(fh, fieldnames=COMPARISON_COLUMNS)
    w.writeheader()
    w.writerows(rows)
with atomic_path(sm.output.summary) as tmp:
    tmp.write_text("\n".join(lines) + "\n")
for line in lines:
    log.info(line)
