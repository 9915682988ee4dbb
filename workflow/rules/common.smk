# Helpers shared by the rule files.

import json


def library(script):
    """A digest of the src/hmfdiff files that workflow/scripts/{script} imports, directly or
    through other modules (read from the code by hmfdiff.pipeline.deps), for the rule's
    `library` parameter: editing one of them reruns the step (Snakemake's params rerun trigger,
    on by default; not with --rerun-triggers mtime), without listing the files in the log.
    """
    import os

    from hmfdiff.pipeline.deps import library_digest

    base = workflow.basedir
    return library_digest(
        os.path.join(base, "workflow", "scripts", script), os.path.join(base, "src")
    )


def case_spec(wildcards):
    """The config fragment of one case as a JSON string; a change of it reruns the step."""
    return json.dumps(config["cases"][wildcards.case], sort_keys=True)


def theory_cases():
    """Cases with a numerical theory grid (the two-step state has closed forms instead)."""
    return [c for c, s in config["cases"].items() if s["kind"] != "two_step"]
