"""Rule figure: draw one figure of the paper from its netCDF inputs (PDF and PNG)."""

from hmfdiff.analysis.plotting import FIGURES
from hmfdiff.pipeline.io import read_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
name = sm.params.name
log = get_logger(name, sm.log[0])
inputs = {k: read_dataset(v) for k, v in sm.input.items() if k != "lib"}
FIGURES[name](inputs, pdf=sm.output.pdf, png=sm.output.png, params=dict(sm.params))
log.info("wrote %s and %s", sm.output.pdf, sm.output.png)
