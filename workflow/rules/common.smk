# Helpers shared by the rule files.

import json


def lib(script):
    """The src/hmfdiff files that workflow/scripts/{script} imports, directly or through other
    modules (read from the code by hmfdiff.pipeline.deps): editing one reruns the step.
    """
    import os

    from hmfdiff.pipeline.deps import library_files

    base = workflow.basedir
    files = library_files(
        os.path.join(base, "workflow", "scripts", script), os.path.join(base, "src")
    )
    return [os.path.relpath(f) for f in files]


def case_spec(wildcards):
    """The config fragment of one case as a JSON string; a change of it reruns the step."""
    return json.dumps(config["cases"][wildcards.case], sort_keys=True)


def theory_cases():
    """Cases with a numerical theory grid (the two-step state has closed forms instead)."""
    return [c for c, s in config["cases"].items() if s["kind"] != "two_step"]
