"""A job's console output is one line (issue 36: the smoke run's console held ~440 lines of the
scripts' own progress among Snakemake's): the last informational line of the job when it ends,
warnings at once; every line stays in the job's log file, and HMFDIFF_LOG_CONSOLE=all puts
every line on the console too."""

import os
import subprocess
import sys
import textwrap


def _run(tmp_path, body, **env):
    log = tmp_path / "logs" / "job.log"
    script = "from hmfdiff.pipeline.runtime import get_logger\n"
    script += f"log = get_logger('job', {str(log)!r})\n" + textwrap.dedent(body)
    r = subprocess.run(
        [sys.executable, "-c", script],
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ, **env},
    )
    console = [line.split(" ", 1)[1] for line in r.stderr.strip().splitlines()]
    return r, console, log.read_text().strip().splitlines()


BODY = """
log.info("case a: starting")
log.info("seed 0 done")
log.warning("the run is short")
log.info("wrote results/a.nc")
"""


def test_console_holds_the_last_line_and_warnings_the_log_every_line(tmp_path):
    r, console, logged = _run(tmp_path, BODY)
    assert r.returncode == 0, r.stderr
    assert console == ["job: the run is short", "job: wrote results/a.nc"]
    assert [line.split(" ", 1)[1] for line in logged] == [
        "job: case a: starting",
        "job: seed 0 done",
        "job: the run is short",
        "job: wrote results/a.nc",
    ]


def test_every_line_on_the_console_when_asked(tmp_path):
    _, console, logged = _run(tmp_path, BODY, HMFDIFF_LOG_CONSOLE="all")
    assert console == [line.split(" ", 1)[1] for line in logged] and len(console) == 4


def test_a_failing_job_shows_only_its_failure(tmp_path):
    r, console, logged = _run(tmp_path, BODY + 'raise ValueError("bad input")\n')
    assert r.returncode == 1
    assert console[0] == "job: the run is short" and len(console) == 2
    assert console[1].startswith("failed: ValueError: bad input (traceback in ")
    assert any("wrote results/a.nc" in line for line in logged)
