"""Rule windowed: the theory's finite-time <dJ^2> fitted over the MD fit's own lags and window,
per bin (results/windowed/{case}_{dynamics}.nc)."""

from hmfdiff.analysis.propagated import propagated_at_bins
from hmfdiff.analysis.windowed import spectrum_table, windowed_at_bins
from hmfdiff.kinetic.spectrum import diffusion_from_spectrum
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset
from hmfdiff.pipeline.layouts.fluctuations import windowed_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("windowed", sm.log[0])
state = state_from_dataset(read_dataset(sm.input.equilibrium, required=["M0"]))
fit = read_dataset(sm.input.fit, required=["ND_md", "lag", "jbar_edges"])
p = sm.params
table = spectrum_table(fit, state, n_max=p.n_max, l_max=p.l_max)
nd_w, nd_s = windowed_at_bins(fit, state, separatrix_band=p.separatrix_band, table=table)
nd_p = propagated_at_bins(fit, lambda k: diffusion_from_spectrum(table, k, state.M0), state.f)
ds = windowed_dataset(nd_w, nd_s, fit, n_max=p.n_max, l_max=p.l_max, nd_propagated=nd_p)
write_dataset(
    ds,
    sm.output[0],
    {"n_max": p.n_max, "l_max": p.l_max, "separatrix_band": p.separatrix_band},
    case=sm.wildcards.case,
)
log.info("case %s, %s -> %s", sm.wildcards.case, sm.wildcards.dynamics, sm.output[0])
