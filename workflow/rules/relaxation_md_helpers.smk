# Helpers of the N-body relaxation rules (relaxation_md.smk).
# INITIALS: an early-window ensemble is drawn from the state, or from its thermal control
import os

from hmfdiff.analysis.relaxation_rates import INITIALS


def relaxation_md_cases():
    return sorted(config.get("relaxation_md", {}).get("runs", {}))


def relaxation_md_sizes(case):
    return list(config["relaxation_md"]["runs"][case]["n_particles"])


def relaxation_md_files():
    return [
        f"{RES}/relaxation_md/{c}/N{n}.nc"
        for c in relaxation_md_cases()
        for n in relaxation_md_sizes(c)
    ]


def relaxation_md_controls(case=None):
    """The thermal-control ensembles (of every case, or of one)."""
    runs = config.get("relaxation_md", {}).get("runs", {})
    return [
        f"{RES}/relaxation_md/{c}/thermal/N{n}.nc"
        for c in ([case] if case else relaxation_md_cases())
        for n in runs[c].get("control_sizes", [])
    ]


def relaxation_md_run(case):
    """The ensemble settings of one case (defaults merged with the case's own), as JSON."""
    rmd = config["relaxation_md"]
    run = {k: v for k, v in rmd.items() if k != "runs"}
    skip = ("n_particles", "control_sizes")
    run.update({k: v for k, v in rmd["runs"][case].items() if k not in skip})
    return json.dumps(run, sort_keys=True)


def ensemble_runtime_min(run, n):
    """Wall-time request in minutes of an ensemble job at N = n (settings `run`: dt,
    particles_per_size, tau_max) from its particle-steps and a conservative 1e8 per s.
    """
    steps = run["particles_per_size"] * run["tau_max"] * int(n) / run["dt"]
    return int(10 + steps / 1e8 / 60 * 2)


def relaxation_md_runtime_min(case, n):
    return ensemble_runtime_min(config["relaxation_md"], n)


#: the kinetic relaxation times' numerical uncertainty (studies/separatrix_layer.py uncertainty)
KINETIC_UNCERTAINTY = "docs/reference/kinetic_time_uncertainty.csv"
#: the finite-N layer model's times (studies/separatrix_layer.py finite_n)
LAYER_MODEL = "docs/reference/finite_n_layer.txt"
#: N-body relaxation times of experiments the default reproduction does not rebuild
REFERENCE_MD_SUMMARIES = [
    "docs/reference/experiments/hothalo_large_n/relaxation_comparison_summary.txt"
]


def relaxation_comparison_inputs(wildcards=None):
    """Every ensemble, and the kinetic evolutions and initial state of every case."""
    cases = relaxation_md_cases()
    equations = config.get("relaxation", {}).get("equations", [])
    return {
        "md": relaxation_md_files(),
        "control": relaxation_md_controls(),
        "kinetic": [f"{RES}/relaxation/{c}_{e}.nc" for c in cases for e in equations],
        "equilibrium": [f"{RES}/equilibrium/{c}.nc" for c in cases],
        # reference copies, where the checkout has them (not in a bare copy of the workflow)
        "uncertainty": [p for p in [KINETIC_UNCERTAINTY] if os.path.exists(p)],
        "reference_md": [p for p in REFERENCE_MD_SUMMARIES if os.path.exists(p)],
        "layer_model": [p for p in [LAYER_MODEL] if os.path.exists(p)],
    }


def relaxation_comparison_outputs():
    cases = relaxation_md_cases()
    if not cases:
        return []
    return [
        f"{RES}/relaxation_comparison.csv",
        f"{RES}/relaxation_comparison_summary.txt",
    ] + [f"{RES}/relaxation_comparison/{c}.nc" for c in cases]


def relaxation_rates_cases():
    return sorted((config.get("relaxation_rates") or {}).get("runs", {}))


def relaxation_rates_sizes(case):
    return list(config["relaxation_rates"]["runs"][case]["n_particles"])


def relaxation_rates_run():
    """The early-window ensemble settings: relaxation_md's time step, bins and threads with
    relaxation_rates' window, schedule, sizes and seed, as JSON."""
    run = {k: v for k, v in config["relaxation_md"].items() if k != "runs"}
    run.update({k: v for k, v in config["relaxation_rates"].items() if k != "runs"})
    return json.dumps(run, sort_keys=True)


def relaxation_rates_runtime_min(n):
    return ensemble_runtime_min(json.loads(relaxation_rates_run()), n)


def relaxation_rates_ensembles(case):
    return [
        f"{RES}/relaxation_rates/{case}/{initial}/N{n}.nc"
        for initial in INITIALS
        for n in relaxation_rates_sizes(case)
    ]


def relaxation_rates_inputs(wildcards):
    equations = config.get("relaxation", {}).get("equations", [])
    return {
        "md": relaxation_rates_ensembles(wildcards.case),
        "kinetic": [f"{RES}/relaxation/{wildcards.case}_{e}.nc" for e in equations],
    }


def relaxation_rates_outputs():
    return [
        f"{RES}/relaxation_rates/{c}{suffix}"
        for c in relaxation_rates_cases()
        for suffix in (".nc", "_summary.txt")
    ]
