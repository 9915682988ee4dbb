"""Rule scaling: N*D_MD per bin against N, from the fits of the 1/N study."""

from hmfdiff.pipeline.fluctuation_layouts import scaling_dataset
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("scaling", sm.log[0])
fits = [read_dataset(p, required=["ND_md", "ND_md_err", "flag"]) for p in sm.input.fits]
ds = scaling_dataset(fits, sm.params.sizes, dynamics=sm.wildcards.dynamics)
write_dataset(ds, sm.output[0], {"fits": list(map(str, sm.input.fits))}, case=sm.wildcards.case)
log.info(
    "case %s, %s: N = %s -> %s",
    sm.wildcards.case,
    sm.wildcards.dynamics,
    sm.params.sizes,
    sm.output[0],
)
