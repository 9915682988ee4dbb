"""Rule scaling: N*D_MD per bin against N, from the fits of the 1/N study, beside the kinetic
theory of the dynamics and the other one, bin-averaged like validation.csv's ND_theory."""

import numpy as np

from hmfdiff.analysis.fits import THEORY_OF
from hmfdiff.analysis.scaling import OTHER_THEORY, drawn_bins, scaling_theory
from hmfdiff.pipeline.io import check_physical, read_dataset, write_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset
from hmfdiff.pipeline.layouts.fluctuations import scaling_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
log = get_logger("scaling", sm.log[0])
dyn = sm.wildcards.dynamics
fits = [read_dataset(p, required=["ND_md", "ND_md_err", "flag"]) for p in sm.input.fits]
theory = read_dataset(sm.input.theory, required=["D_landau", "D_lenard_balescu"])
check_physical(theory, increasing=("kappa",), nonnegative=("D_landau", "D_lenard_balescu"))
state = state_from_dataset(read_dataset(sm.input.equilibrium, required=["M0"]))
own, other = scaling_theory(fits, theory, state.f)
valid = np.all(
    [
        (f["flag"].values == 0) & np.isfinite(f["ND_md_err"].values) & np.isfinite(th)
        for f, th in zip(fits, own, strict=True)
    ],
    axis=0,
)
drawn = drawn_bins(fits[0]["kappa0"].values, valid, sm.params.kappa0)
ds = scaling_dataset(
    fits,
    sm.params.sizes,
    dynamics=dyn,
    theory=own,
    other=other,
    equations=(THEORY_OF[dyn], OTHER_THEORY[dyn]),
    drawn=drawn,
)
write_dataset(
    ds,
    sm.output[0],
    {"fits": list(map(str, sm.input.fits)), "kappa0": sm.params.kappa0},
    case=sm.wildcards.case,
)
log.info(
    "case %s, %s: N = %s, bins drawn kappa0 = %s -> %s",
    sm.wildcards.case,
    dyn,
    sm.params.sizes,
    [round(float(k), 3) for k in ds["kappa0"].values[drawn]],
    sm.output[0],
)
