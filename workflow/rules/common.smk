# Helpers shared by the rule files.

import json


def lib(*modules):
    """Library files imported by a step; editing one of them reruns the step."""
    return [f"src/hmfdiff/{m}.py" for m in modules]


def case_spec(wildcards):
    """The config fragment of one case as a JSON string; a change of it reruns the step."""
    return json.dumps(config["cases"][wildcards.case], sort_keys=True)


# figure name -> (short target name, kind of input file, library modules it draws with)
FIGURES = {
    "fig01_orbits": ("fig1", "orbits"),
    "fig02_action_frequency": ("fig2", "orbits"),
    "fig03_poles": ("fig3", "orbits"),
    "fig04_contributions": ("fig4", "theory"),
    "fig05_dielectric": ("fig5", "theory"),
    "fig06_landau_lenard_balescu": ("fig6", "theory"),
    "fig07_closed_forms": ("fig7", "closed_forms"),
}


def figure_cases(name):
    spec = config["figures"][name]
    if "cases" in spec:
        return spec["cases"]
    if "case" in spec:
        return [spec["case"]]
    return list(spec.get("core_halo", [])) + [
        spec[k] for k in ("two_step", "thermal") if k in spec
    ]


def figure_inputs(wildcards):
    """Input files of one figure: {kind}_{i} for each of its cases, and the plotting library."""
    kind = FIGURES[wildcards.name][1]
    if kind == "closed_forms":
        spec = config["figures"][wildcards.name]
        smooth = list(spec["core_halo"]) + [spec["thermal"]]
        files = {f"theory_{i}": f"results/theory/{c}.nc" for i, c in enumerate(smooth)}
        files["analytic_0"] = f"results/analytic/{spec['two_step']}.nc"
        files["analytic_1"] = f"results/analytic/{spec['thermal']}.nc"
        files["lib"] = lib("plotting", "orbits")
        return files
    files = {
        f"{kind}_{i}": f"results/{kind}/{case}.nc"
        for i, case in enumerate(figure_cases(wildcards.name))
    }
    files["lib"] = lib("plotting", "orbits")
    return files


def figure_targets():
    return expand(
        "results/figures/{name}.{ext}",
        name=[n for n in FIGURES if n in config["figures"]],
        ext=["pdf", "png"],
    )


def theory_cases():
    """Cases with a numerical theory grid (the two-step state has closed forms instead)."""
    return [c for c, s in config["cases"].items() if s["kind"] != "two_step"]
