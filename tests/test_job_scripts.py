"""The start of a run deletes the job scripts that killed jobs left in .snakemake/scripts, and
only those: a script that a live job of another run in the same directory runs is kept (its
disappearance made that run fail at the job's end and delete the job's finished output)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from hmfdiff.pipeline import runtime


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="lists live processes through /proc")
def test_a_script_in_use_is_kept_and_a_stale_one_removed(tmp_path):
    scripts = tmp_path / ".snakemake" / "scripts"
    scripts.mkdir(parents=True)
    alive = scripts / "tmpalive01.relaxation_md.py"
    # announces itself, then runs until its stdin closes
    alive.write_text("import sys\nprint('running', flush=True)\nsys.stdin.read()\n")
    stale = scripts / "tmpkilled2.fit.py"
    stale.write_text("pass\n")
    job = subprocess.Popen(
        [sys.executable, str(alive)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
    )
    try:
        assert job.stdout.readline().strip() == "running"  # the job runs its script now
        assert alive.name in runtime.scripts_in_use()
        removed = runtime.remove_stale_job_scripts(tmp_path)
        assert removed == [stale]
        assert alive.exists() and not stale.exists()
    finally:
        job.stdin.close()
        job.wait()
    # the job has ended: its script (had it not removed it) is stale now
    assert runtime.remove_stale_job_scripts(tmp_path) == [alive]
    assert not any(scripts.iterdir())


def test_nothing_is_deleted_where_processes_cannot_be_listed(tmp_path, monkeypatch):
    scripts = tmp_path / ".snakemake" / "scripts"
    scripts.mkdir(parents=True)
    (scripts / "tmpunknown.py").write_text("pass\n")
    monkeypatch.setattr(runtime, "scripts_in_use", lambda proc="/proc": None)
    assert runtime.remove_stale_job_scripts(tmp_path) == []
    assert (scripts / "tmpunknown.py").exists()
