"""Snakemake's job-rate limiter is off in local runs (`runtime.drop_local_job_rate_limiter`, from
the Snakefile's onstart): with it on, every ended job starts another endless chain of 1-second
re-evaluation timers, and the scheduler's own CPU use grows with the jobs done."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from types import SimpleNamespace

from _smoke import SMOKE, copy_workflow

from hmfdiff.pipeline.runtime import drop_local_job_rate_limiter

#: runs Snakemake's command line with threading.Timer counted; prints "timers <n>" at the end
COUNTING = textwrap.dedent(
    """
    import sys, threading
    count = [0]
    class Counting(threading.Timer):
        def __init__(self, *a, **k):
            count[0] += 1
            super().__init__(*a, **k)
    threading.Timer = Counting
    import snakemake.cli
    sys.argv = ["snakemake", *sys.argv[1:]]
    try:
        snakemake.cli.main()
    finally:
        print(f"timers {count[0]}", file=sys.__stderr__)
    """
)


def workflow(non_local):
    plugin = SimpleNamespace(common_settings=SimpleNamespace(non_local_exec=non_local))
    return SimpleNamespace(
        scheduler=SimpleNamespace(job_rate_limiter=object()), executor_plugin=plugin
    )


def test_limiter_dropped_for_local_runs_only():
    local = workflow(non_local=False)
    assert drop_local_job_rate_limiter(local) is True
    assert local.scheduler.job_rate_limiter is None
    cluster = workflow(non_local=True)
    assert drop_local_job_rate_limiter(cluster) is False
    assert cluster.scheduler.job_rate_limiter is not None
    assert drop_local_job_rate_limiter(SimpleNamespace()) is False  # no scheduler yet


def test_a_local_run_of_the_workflow_arms_no_reevaluation_timer(tmp_path):
    """Two jobs of the real workflow (equilibrium, orbits of one smoke case): no timer."""
    workdir = copy_workflow(tmp_path)
    script = tmp_path / "counting.py"
    script.write_text(COUNTING)
    target = "results/smoke/orbits/thermal_u-0.1.nc"
    r = subprocess.run(
        [sys.executable, str(script), "-j2", target, "--configfile", SMOKE],
        cwd=workdir,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    assert (workdir / target).is_file()
    assert "timers 0" in r.stderr.splitlines()[-1], r.stderr[-500:]
