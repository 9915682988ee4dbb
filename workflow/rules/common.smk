# Helpers shared by the rule files.

import json


def lib(*modules):
    """Library files imported by a step; editing one of them reruns the step."""
    from pathlib import Path

    return sorted(
        str(p) for m in modules for p in Path("src/hmfdiff").glob(f"*/{m}.py")
    )


def case_spec(wildcards):
    """The config fragment of one case as a JSON string; a change of it reruns the step."""
    return json.dumps(config["cases"][wildcards.case], sort_keys=True)


def theory_cases():
    """Cases with a numerical theory grid (the two-step state has closed forms instead)."""
    return [c for c, s in config["cases"].items() if s["kind"] != "two_step"]
