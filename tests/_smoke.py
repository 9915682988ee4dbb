"""One smoke run of the pipeline per pytest session, shared by the test modules that read its
outputs (this module is imported once, so its cache outlives each module's fixtures).

Tests that change the shared copy must put it back as it was (a `finally` block)."""

import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SMOKE = "config/smoke.yaml"
_RUNS = {}


def copy_workflow(dest):
    """Copy what the workflow needs (Snakefile, config, workflow, src) into `dest`."""
    dest = Path(dest)
    for item in ("Snakefile", "config", "workflow", "src"):
        src = ROOT / item
        if src.is_dir():
            shutil.copytree(
                src, dest / item, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info")
            )
        else:
            shutil.copy2(src, dest / item)
    return dest


def snakemake(args, cwd, timeout=600):
    return subprocess.run(
        [sys.executable, "-m", "snakemake", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def job_counts(output):
    """Parse Snakemake's 'Job stats' table into {rule: count} ({} when nothing is to be done)."""
    m = re.search(r"Job stats:\n.*?\n-+\s+-+\n(.*?)\ntotal", output, re.S)
    if not m:
        return {}
    return {line.split()[0]: int(line.split()[1]) for line in m.group(1).strip().splitlines()}


def smoke_workdir(tmp_path_factory):
    """A copy of the workflow in which `snakemake -j2 --configfile config/smoke.yaml` has run
    to completion (built on first use in the session, then reused)."""
    if "smoke" not in _RUNS:
        d = copy_workflow(tmp_path_factory.mktemp("smoke"))
        _RUNS["smoke"] = (d, snakemake(["-j2", "--configfile", SMOKE], d, timeout=3600))
    d, r = _RUNS["smoke"]
    assert r.returncode == 0, r.stderr[-5000:]
    return d
