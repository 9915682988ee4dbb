"""Rule relaxation: one collisional relaxation by the Landau or Lenard-Balescu equation
(results/relaxation/{case}_{equation}.nc)."""

import json

from hmfdiff.kinetic.flux import fokker_planck_jbar_current
from hmfdiff.kinetic.relaxation import RelaxationSettings, evolve, face_jbar
from hmfdiff.kinetic.stability import check_vlasov_stable
from hmfdiff.meanfield.equilibrium import ThermalState
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset
from hmfdiff.pipeline.layouts.kinetic_relaxation import kinetic_relaxation_dataset
from hmfdiff.pipeline.runtime import get_logger

sm = snakemake  # noqa: F821
case, equation = sm.wildcards.case, sm.wildcards.equation
log = get_logger("relaxation", sm.log[0])
run = json.loads(sm.params.run)
check = run.pop("check_stability", True)
settings = RelaxationSettings.from_mapping(equation, run)
state = state_from_dataset(read_dataset(sm.input.equilibrium, required=["M0"]))
log.info("case %s, %s: M0 = %.8f, u = %.8f; %s", case, equation, state.M0, state.u, run)
report = None
if check:
    report = check_vlasov_stable(state, case, l_max=settings.l_max)
    log.info("Vlasov-stable: no zero of eps_cc or eps_ss in the upper half plane (%s)", report)


def progress(d):
    log.info(
        "tau = %-10.5g M0 = %.8f  S = %.10f  u = %.10f  max|f - f_eq|/max f_eq = %.2e",
        d["tau"],
        d["M0"],
        d["S"],
        d["u"],
        d["thermal_distance_max"],
    )


out = evolve(state, settings, progress)
log.info(
    "%d steps (%d rejected) in %.1f s; thermalised: %s",
    out["n_steps"],
    out["n_rejected"],
    out["wall_time"],
    out["thermalised"],
)
fp0 = fokker_planck_jbar_current(
    state,
    face_jbar(out["grid"], out["M0"][0]),
    settings.n_max,
    settings.l_max,
    equation == "lenard_balescu",
)
ds = kinetic_relaxation_dataset(
    out,
    case=case,
    equation=equation,
    state=state,
    thermal=ThermalState(u=float(out["u"][0])),
    stability=report,
    fp0=fp0,
)
log.info(
    "tau_relax_fine (fine-grained entropy deficit / e) = %.4g; dM0/dtau at 0: %.4g, over "
    "tau <= %g: %.4g",
    float(ds["tau_relax_fine"]),
    float(ds["dM0dtau_initial"]),
    settings.early_window,
    float(ds["dM0dtau_early"]),
)
write_dataset(ds, sm.output[0], {"relaxation": run, "check_stability": check}, case=case)
log.info("wrote %s", sm.output[0])
