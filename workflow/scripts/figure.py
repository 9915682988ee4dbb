"""Rule figure: draw one figure of the paper from its netCDF inputs (PDF and PNG)."""

from hmfdiff.analysis.figures.registry import FIGURES
from hmfdiff.pipeline.io import read_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
fig = FIGURES[sm.wildcards.name]
log = get_logger(fig.name, sm.log[0])
inputs = {kind: [read_dataset(p) for p in getattr(sm.input, kind)] for kind in fig.kinds}
fig.draw(inputs, pdf=sm.output.pdf, png=sm.output.png)
log.info(
    "%s from %s -> %s, %s",
    fig.name,
    {kind: [ds.attrs.get("case", "") for ds in dss] for kind, dss in inputs.items()},
    sm.output.pdf,
    sm.output.png,
)
