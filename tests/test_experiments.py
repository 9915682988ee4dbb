"""The experiment configs under config/experiments/ run as their headers say: the command each
header gives is planned by Snakemake (dry run) without error, writes under the experiment's
own results_dir, and its targets are among the jobs it plans.  (A header that gives only the
experiment file to --configfile fails: --configfile replaces config/config.yaml, it does not
merge into it, and the experiment files hold only what they change.)"""

import shlex
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
EXPERIMENTS = sorted((ROOT / "config" / "experiments").glob("*.yaml"))


def header_command(path):
    """The snakemake command of the header comment, continuation lines joined."""
    lines = [ln[1:].strip() for ln in path.read_text().splitlines() if ln.startswith("#")]
    start = next(i for i, ln in enumerate(lines) if ln.startswith("snakemake "))
    cmd = []
    for ln in lines[start:]:
        cmd.append(ln.rstrip("\\").strip())
        if not ln.endswith("\\"):
            break
    return shlex.split(" ".join(cmd))


def test_there_are_experiments():
    assert EXPERIMENTS, "config/experiments/ holds no experiment"


@pytest.mark.parametrize("path", EXPERIMENTS, ids=[p.stem for p in EXPERIMENTS])
def test_header_command_plans(path):
    argv = header_command(path)
    assert argv[0] == "snakemake"
    targets = argv[argv.index("--") + 1 :]
    results_dir = yaml.safe_load(path.read_text())["results_dir"]
    assert targets and all(t.startswith(results_dir + "/") for t in targets), targets
    r = subprocess.run(
        [sys.executable, "-m", "snakemake", "-n", "--quiet", "rules", *argv[1:]],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
