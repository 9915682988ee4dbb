"""Kill and restart: SIGKILL `snakemake` (the whole process group) during a theory, an MD, a fit
and a figure job in turn, restart with the README's recipe each time, and check that the final
outputs equal those of an unkilled run, with no temporary file left behind.

Deterministic: every kill waits for an observable event, never for a fixed time, and no wait
polls.  The run's console (Snakemake's and its jobs' stdout and stderr) is a pipe that the test
reads line by line, blocking: the jobs are stopped at a known point by the HMFDIFF_TEST_HOLD
hook of hmfdiff.pipeline.io (a write matching a pattern announces itself on stderr and waits
to be killed), and the MD kill waits for the line the MD job logs as it starts integrating.
After the SIGKILL, the end of the pipe (every process of the run that held it has exited) and
a pidfd per process left with the run's token are waited on.  Each test builds what it needs
in its own temporary copy of the workflow, with a tiny configuration derived from
config/smoke.yaml.
"""

from __future__ import annotations

import os
import re
import select
import shutil
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

ROOT = Path(__file__).resolve().parents[1]
CASE = "thermal_u-0.1"
FIGURE = "fig08_dj2"
EVENT_TIMEOUT = 600.0  # a safety net for a broken pipeline, not a timing assumption
#: attributes that legitimately differ between two runs of the same job (and wall_*_s timings)
VOLATILE_ATTRS = {"created", "history"}
#: job slots: one more than the jobs held at once (theory and two MD seeds in the first run)
JOBS = 4
#: the README's restart recipe after a kill: unlock, then the same command with this flag
RESTART_FLAG = "--rerun-incomplete"


def _tiny_config():
    """config/smoke.yaml with small MD runs and a small theory grid, and figure 8 drawn for one
    case.  Only the targets (`_targets`) run: one theory grid, two tiny MD(full) seeds, their
    fit and figure 8; the other cases and sections stay as they are, unused."""
    cfg = yaml.safe_load((ROOT / "config/smoke.yaml").read_text())
    md = cfg["md"]
    md["runs"][CASE]["n_particles"] = 2000
    for key, value in dict(
        t_max=30.0,
        max_lag=10.0,
        fit_window=[2.0, 10.0],
        seeds=2,
        n_test_full=500,
        n_bins=4,
        origin_every=5.0,
        n_blocks=2,
    ).items():
        assert key in md, f"smoke config has no md.{key}: update this test"
        md[key] = value
    for key, value in dict(n_kappa=16, n_max=2, l_max=2).items():
        assert key in cfg["theory"], f"smoke config has no theory.{key}: update this test"
        cfg["theory"][key] = value
    cfg["figures"][FIGURE] = {"cases": [CASE]}
    # the 1/N study of the core-halo state inherits the 4 bins, where its two kappa0 would pick
    # the same bin (refused); it is not run here
    del cfg["md_scaling"]["studies"]["corehalo_ch2"]["kappa0"]
    return cfg


def _new_workdir(tmp_path_factory, name):
    d = tmp_path_factory.mktemp(name)
    for item in ("Snakefile", "config", "workflow", "src"):
        src = ROOT / item
        if src.is_dir():
            shutil.copytree(
                src, d / item, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info")
            )
        else:
            shutil.copy2(src, d / item)
    cfg = _tiny_config()
    (d / "config/kill.yaml").write_text(yaml.safe_dump(cfg))
    return d, Path(cfg.get("results_dir", "results"))


def _targets(results):
    return [str(results / f"theory/{CASE}.nc"), str(results / f"figures/{FIGURE}.png")]


def _command(results, *extra):
    # targets before --configfile (which takes one or more values)
    return [
        sys.executable,
        "-m",
        "snakemake",
        f"-j{JOBS}",
        *_targets(results),
        *extra,
        "--configfile",
        "config/kill.yaml",
    ]


UNLOCK = [sys.executable, "-m", "snakemake", "--unlock", "--configfile", "config/kill.yaml"]


def _run(cmd, cwd, timeout=900):
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The unkilled run: (workdir, results dir)."""
    d, results = _new_workdir(tmp_path_factory, "unkilled")
    r = _run(_command(results), d)
    assert r.returncode == 0, r.stderr[-4000:]
    return d, results


def _processes_with(token):
    """PIDs of live processes whose environment contains `token`."""
    pids = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            if token.encode() in (entry / "environ").read_bytes():
                pids.append(int(entry.name))
        except OSError:
            continue
    return pids


def _read_console(fd, deadline, text=""):
    """The next chunk written to the console pipe `fd` (a blocking wait, bounded by the
    safety-net `deadline`), appended to `text`; None at the end of the pipe."""
    ready, _, _ = select.select([fd], [], [], max(0.0, deadline - time.monotonic()))
    if not ready:
        pytest.fail(f"the console stayed silent until the safety net:\n{text[-4000:]}")
    chunk = os.read(fd, 1 << 16)
    return text + chunk.decode(errors="replace") if chunk else None


def _wait_for_exit(pids, deadline):
    """Wait for each process to exit (a pidfd becomes readable when its process ends)."""
    for pid in pids:
        try:
            fd = os.pidfd_open(pid)
        except ProcessLookupError:
            continue  # already gone
        try:
            ready, _, _ = select.select([fd], [], [], max(0.0, deadline - time.monotonic()))
            assert ready, f"process {pid} of the killed run survived SIGKILL"
        finally:
            os.close(fd)


def _run_until_killed(cmd, cwd, hold, event, what):
    """Start `cmd` in its own process group with HMFDIFF_TEST_HOLD=hold, its console a pipe;
    read the console until event(text) holds, SIGKILL the whole group and wait until every
    process of the run is gone.  Returns the console text."""
    token = f"hmfdiff-kill-test-{uuid.uuid4().hex}"
    # every job's log line on the console (by default the console carries only the jobs' end
    # lines and warnings): the events below are read from there
    env = dict(
        os.environ, HMFDIFF_TEST_HOLD=hold, HMFDIFF_KILL_TEST_TOKEN=token, HMFDIFF_LOG_CONSOLE="all"
    )
    deadline = time.monotonic() + EVENT_TIMEOUT  # a safety net, not a timing assumption
    proc = subprocess.Popen(
        cmd,
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        env=env,
        start_new_session=True,
    )
    fd = proc.stdout.fileno()
    text = ""
    try:
        while not event(text):
            more = _read_console(fd, deadline, text)
            if more is None:
                pytest.fail(f"snakemake exited before {what}:\n{text[-4000:]}")
            text = more
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        # the end of the pipe: every process that inherited the console has exited
        while (more := _read_console(fd, deadline, text)) is not None:
            text = more
        proc.stdout.close()
    _wait_for_exit(_processes_with(token), deadline)
    assert not _processes_with(token), "processes of the killed run survived SIGKILL"
    return text


def _restart(cwd, results, hold=None, event=None, what=None):
    """The README's recipe: `snakemake --unlock`, then the same command with --rerun-incomplete
    (killed again at the next point when `hold` is given; returns that run's console)."""
    r = _run(UNLOCK, cwd)
    assert r.returncode == 0, r.stderr[-3000:]
    cmd = _command(results, RESTART_FLAG)
    if hold is None:
        r = _run(cmd, cwd)
        assert r.returncode == 0, r.stderr[-4000:]
        return r.stdout + r.stderr
    return _run_until_killed(cmd, cwd, hold, event, what)


def _held(pattern):
    return lambda text: f"hmfdiff test hold before rename: {pattern}" in text


def _files(root):
    return sorted(str(p.relative_to(root)) for p in root.rglob("*") if p.is_file())


def _assert_same_dataset(a, b, name):
    with xr.open_dataset(a) as x, xr.open_dataset(b) as y:
        x.load()
        y.load()
    assert set(x.variables) == set(y.variables), name
    for v in x.variables:
        xv, yv = x[v].values, y[v].values
        if xv.dtype.kind in "fc":
            assert np.array_equal(xv, yv, equal_nan=True), (name, v)
        else:
            assert np.array_equal(xv, yv), (name, v)
        assert x[v].attrs.keys() == y[v].attrs.keys(), (name, v)
    keep = {k for k in x.attrs if not (k in VOLATILE_ATTRS or re.fullmatch(r"wall_\w*_s", k))}
    assert set(x.attrs) == set(y.attrs), name
    for k in keep:
        assert str(x.attrs[k]) == str(y.attrs[k]), (name, k)


def test_kill_during_each_step_then_restart_matches_unkilled_run(reference, tmp_path_factory):
    import matplotlib.image as mpimg

    ref_dir, results = reference
    d, _ = _new_workdir(tmp_path_factory, "killed")
    out = d / results
    theory = out / f"theory/{CASE}.nc"

    # 1. theory: killed right after its output was renamed into place, before Snakemake could
    #    record the job as finished: the file is whole but Snakemake marks it incomplete.  The
    #    MD seeds, which may run beside it, are held before their rename: they cannot finish.
    _run_until_killed(
        _command(results),
        d,
        "after:*/theory/*.nc,before:*/md/*/seed*.nc",
        lambda text: f"hmfdiff test hold after rename: {results}/theory/{CASE}.nc" in text,
        "the theory job's rename",
    )
    assert theory.exists()
    assert not list((out / "md").rglob("seed*.nc"))
    r = _run(UNLOCK, d)
    assert r.returncode == 0
    r = _run([*_command(results), "-n"], d)  # why the recipe needs --rerun-incomplete
    assert r.returncode != 0 and "incomplete" in (r.stdout + r.stderr).lower()

    # 2. MD: killed while integrating: the line its logger writes as it starts, read from this
    #    run's console (the logger writes stderr before the log file, which the kill may beat;
    #    a log file may also hold the line from run 1), both seeds held before their rename so
    #    that neither can finish
    integrating = re.compile(rf"md: case {re.escape(CASE)}, full, seed \d+: .*threads = \d+")
    console = _restart(
        d,
        results,
        "before:*/md/*/seed*.nc",
        integrating.search,
        "an MD job integrating",
    )
    assert integrating.search(console), "the MD job announced no integration"
    assert not list((out / "md").rglob("seed*.nc")), "a killed MD job left an output"

    # 3. fit: killed with its output written to the temporary file, not yet renamed
    fit = f"{results}/fits/{CASE}_full.nc"
    _restart(d, results, "before:*/fits/*.nc", _held(fit), "the fit job's write")
    assert not (out / "fits" / f"{CASE}_full.nc").exists()
    assert list((out / "fits").glob(".*.part")), "the hold did not stop the fit mid-write"

    # 4. figure: the PDF renamed, the PNG written but not renamed
    png = f"{results}/figures/{FIGURE}.png"
    _restart(d, results, "before:*/figures/*.png", _held(png), "the figure job's write")
    assert (out / "figures" / f"{FIGURE}.pdf").exists()
    assert list((out / "figures").glob(".*.part"))

    # 5. the recipe once more, unkilled: everything equals the unkilled run, nothing left over
    _restart(d, results)
    assert _files(out) == _files(ref_dir / results)  # hidden .part files included
    assert not list(out.rglob("*.part"))
    assert not any((d / ".snakemake/incomplete").rglob("*"))
    assert not any((d / ".snakemake/locks").rglob("*"))
    assert not any((d / ".snakemake/scripts").rglob("*")), "job scripts of killed jobs remain"
    for name in _files(out):
        if name.endswith(".nc"):
            _assert_same_dataset(out / name, ref_dir / results / name, name)
        elif name.endswith(".png"):
            assert np.array_equal(mpimg.imread(out / name), mpimg.imread(ref_dir / results / name))
        elif name.endswith(".pdf"):
            data = (out / name).read_bytes()
            assert data.startswith(b"%PDF") and data.rstrip().endswith(b"%%EOF")
