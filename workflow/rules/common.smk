# Helpers shared by the rule files.

import json


def lib(*modules):
    """Library files imported by a step; editing one of them reruns the step."""
    return [f"src/hmfdiff/{m}.py" for m in modules]


def case_spec(wildcards):
    """The config fragment of one case as a JSON string; a change of it reruns the step."""
    return json.dumps(config["cases"][wildcards.case], sort_keys=True)


def figure_case(name):
    return config["figures"][name]["case"]


FIGURES = {
    "fig01_orbits": "fig1",
    "fig02_action_frequency": "fig2",
    "fig03_poles": "fig3",
}


def figure_targets():
    return expand(
        "results/figures/{name}.{ext}",
        name=[n for n in FIGURES if n in config["figures"]],
        ext=["pdf", "png"],
    )
