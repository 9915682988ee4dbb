# Helpers shared by the rule files.

import json


wildcard_constraints:
    case="|".join(re.escape(c) for c in CASES),


def lib(*modules):
    """Library files a rule depends on: editing one reruns the rule (scripts import them)."""
    return [f"src/hmfdiff/{m}.py" for m in modules]


def case_spec(wildcards):
    """The config fragment of one case, as a JSON string (a params change reruns the rule)."""
    return json.dumps(config["cases"][wildcards.case], sort_keys=True)


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
