"""Rule spectrum: the measured spectrum of the magnetisation of MD(bath) and MD(full) against
the bare and dressed bath spectra of the theory (results/spectrum/{case}.nc)."""

from hmfdiff.analysis.md_spectrum import spectrum_comparison
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset
from hmfdiff.pipeline.layouts.fluctuations import spectrum_dataset
from hmfdiff.pipeline.layouts.md import seed_files
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("spectrum", sm.log[0])
state = state_from_dataset(read_dataset(sm.input.equilibrium, required=["M0"]))
need = ["Mx_fine", "My_fine"]
bath_files = seed_files(sm.input.bath, sm.params.seeds_bath)
full_files = seed_files(sm.input.full, sm.params.seeds_full)
bath = [read_dataset(p, required=need) for p in bath_files]
full = [read_dataset(p, required=need) for p in full_files]
comp = spectrum_comparison(state, bath, full, n_max=sm.params.n_max, l_max=sm.params.l_max)
ds = spectrum_dataset(comp)
write_dataset(
    ds,
    sm.output[0],
    {"n_max": sm.params.n_max, "l_max": sm.params.l_max, "md": bath_files + full_files},
    case=sm.wildcards.case,
)
log.info(
    "case %s: spectra of %d + %d seeds -> %s", sm.wildcards.case, len(bath), len(full), sm.output[0]
)
