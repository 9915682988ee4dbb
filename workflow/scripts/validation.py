"""Rule validation: results/validation.csv (MD against theory) and a printed summary."""

from hmfdiff.analysis.agreement import summary_text
from hmfdiff.analysis.fits import validation_rows, write_validation_csv
from hmfdiff.analysis.windowed import add_windowed
from hmfdiff.pipeline.io import read_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("validation", sm.log[0])
rows = []
for case, fit_path, theory_path, eq_path, win_path in zip(
    sm.params.cases,
    sm.input.fits,
    sm.input.theory,
    sm.input.equilibrium,
    sm.input.windowed,
    strict=True,
):
    state = state_from_dataset(read_dataset(eq_path, required=["M0"]))
    case_rows = validation_rows(case, read_dataset(fit_path), read_dataset(theory_path), state.f)
    rows += add_windowed(case_rows, read_dataset(win_path, required=["ND_windowed"]))
write_validation_csv(rows, sm.output.table)
# below agreement.TOY_SIZE particles the summary says that it holds no statistics
summary = summary_text(rows, sizes=sm.params.sizes)
with open(sm.output.summary, "w") as fh:
    fh.write(summary + "\n")
for line in summary.splitlines():
    log.info(line)
log.info("wrote %s and %s (%d bins)", sm.output.table, sm.output.summary, len(rows))
