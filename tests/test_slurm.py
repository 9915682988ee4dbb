"""The SLURM profile on a real Slurm.

A single-node Slurm cluster on localhost (munged, slurmctld and slurmd from Debian's `munge`
and `slurm-wlm` packages, with their own key, slurm.conf, ports and state in a temporary
folder) runs a reduced smoke pipeline through `--workflow-profile workflow/profiles/slurm` and
the executor plugin. Its outputs must equal those of a local run, and a job that fails must be
reported as failed, by Slurm and by Snakemake.

Where Slurm is not installed or cannot start, the tests skip and say why. `.ci/run` installs
Slurm and then sets HMFDIFF_REQUIRE_SLURM=1, which turns such a skip into a failure, so that CI
really runs them.
"""

import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
import yaml

from hmfdiff.pipeline.io import read_dataset

ROOT = Path(__file__).resolve().parents[1]
PROFILE = ROOT / "workflow/profiles/slurm"
SMOKE = "config/smoke.yaml"
DAEMONS = ("munged", "mungekey", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo", "srun")
START_TIMEOUT = 120  # s for the daemons to come up; measured: about 1 s on an idle machine
FAILING_RULE = "deliberately_failing"


# ---- a single-node Slurm on localhost -----------------------------------------------------
def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(condition, timeout, what, alive=()):
    """Poll `condition` until it holds; fail early if a daemon in `alive` has exited."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return
        for name, proc in alive:
            if proc.poll() is not None:
                raise RuntimeError(f"{name} exited with status {proc.returncode} ({what})")
        time.sleep(0.2)
    raise RuntimeError(f"timed out after {timeout} s waiting for {what}")


class LocalSlurm:
    """munged + slurmctld + slurmd, all in `root`, stopped by stop() whatever happened."""

    def __init__(self, root):
        self.root = root
        self.conf = root / "slurm.conf"
        self.procs = []  # (name, Popen), in start order
        bindir = root / "bin"
        bindir.mkdir()
        # The jobstep executor strips every SLURM_* variable (SLURM_CONF too) before it calls
        # srun inside the job; on a real cluster srun then reads /etc/slurm/slurm.conf. This
        # cluster's configuration lives here instead, so srun is found through a shim.
        shim = bindir / "srun"
        shim.write_text(f'#!/bin/sh\nSLURM_CONF="{self.conf}" exec "{shutil.which("srun")}" "$@"\n')
        shim.chmod(0o755)
        self.env = dict(
            os.environ, SLURM_CONF=str(self.conf), PATH=f"{bindir}{os.pathsep}{os.environ['PATH']}"
        )

    def command(self, *args, check=True):
        r = subprocess.run(args, env=self.env, capture_output=True, text=True, timeout=60)
        if check and r.returncode:
            raise RuntimeError(f"{' '.join(args)}: {r.stderr.strip()}")
        return r

    def spawn(self, name, *args):
        log = open(self.root / f"{name}.out", "w")
        proc = subprocess.Popen(
            args, env=self.env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True
        )
        log.close()
        self.procs.append((name, proc))
        return proc

    def start(self):
        root = self.root
        # munged wants execute permission for all on every folder above its socket and a
        # private folder for its key.
        root.chmod(0o755)
        for sub, mode in (("munge", 0o700), ("run", 0o755), ("state", 0o700), ("spool", 0o700)):
            (root / sub).mkdir(mode=mode)
        key = root / "munge/munge.key"
        sock = root / "run/munge.sock"
        self.command("mungekey", "--create", f"--keyfile={key}")
        munged = self.spawn(
            "munged",
            "munged",
            "--foreground",
            f"--socket={sock}",
            f"--key-file={key}",
            f"--pid-file={root}/munge/munged.pid",
            f"--log-file={root}/munge/munged.log",
            f"--seed-file={root}/munge/munged.seed",
        )
        wait_for(
            lambda: self.command("munge", "-n", f"--socket={sock}", check=False).returncode == 0,
            START_TIMEOUT,
            "munged to issue a credential",
            [("munged", munged)],
        )
        # The node as slurmd sees it (CPUs, sockets, memory), so that its registration matches.
        node_line = self.command("slurmd", "-C").stdout.splitlines()[0]
        self.node = re.match(r"NodeName=(\S+)", node_line).group(1)
        self.conf.write_text(
            "\n".join(
                [
                    "ClusterName=hmfdifftest",
                    f"SlurmctldHost={self.node}(127.0.0.1)",
                    f"SlurmctldPort={free_port()}",
                    f"SlurmdPort={free_port()}",
                    "SlurmUser=root",
                    "SlurmdUser=root",
                    "AuthType=auth/munge",
                    "CredType=cred/munge",
                    f"AuthInfo=socket={sock}",
                    f"StateSaveLocation={root}/state",
                    f"SlurmdSpoolDir={root}/spool",
                    f"SlurmctldPidFile={root}/slurmctld.pid",
                    f"SlurmdPidFile={root}/slurmd.pid",
                    f"SlurmctldLogFile={root}/slurmctld.log",
                    f"SlurmdLogFile={root}/slurmd.log",
                    # what works in a container: no cgroups
                    "ProctrackType=proctrack/linuxproc",
                    "TaskPlugin=task/none",
                    "JobAcctGatherType=jobacct_gather/none",
                    # no accounting: finished jobs stay visible to squeue for MinJobAge seconds,
                    # longer than the plugin's status checks need (otherwise it waits forever)
                    "AccountingStorageType=accounting_storage/none",
                    "JobCompType=jobcomp/none",
                    "MinJobAge=300",
                    "MpiDefault=none",
                    "ReturnToService=2",
                    "SchedulerType=sched/backfill",
                    "SelectType=select/cons_tres",
                    "SelectTypeParameters=CR_Core_Memory",
                    f"{node_line.split(' UpTime=')[0]} NodeAddr=127.0.0.1 State=UNKNOWN",
                    f"PartitionName=debug Nodes={self.node} Default=YES MaxTime=INFINITE State=UP",
                    "",
                ]
            )
        )
        ctld = self.spawn("slurmctld", "slurmctld", "-D", "-f", str(self.conf))
        slurmd = self.spawn("slurmd", "slurmd", "-D", "-f", str(self.conf), "-N", self.node)
        wait_for(
            lambda: (
                self.command("sinfo", "-h", "-n", self.node, "-o", "%T", check=False)
                .stdout.strip()
                .startswith("idle")
            ),
            START_TIMEOUT,
            f"node {self.node} idle in sinfo",
            [("munged", munged), ("slurmctld", ctld), ("slurmd", slurmd)],
        )

    def jobs(self):
        """Every job this cluster knows: [(id, state, comment)], oldest first."""
        out = self.command("squeue", "-h", "--states=all", "-o", "%i|%T|%k").stdout
        rows = [line.split("|", 2) for line in out.splitlines() if line]
        return sorted((int(i), state, comment) for i, state, comment in rows)

    def stop(self):
        """Cancel every job, wait until none runs, then stop the daemons, newest first."""
        try:
            if any(name == "slurmctld" for name, _ in self.procs):
                ids = [str(i) for i, state, _ in self.jobs() if state in ("PENDING", "RUNNING")]
                if ids:
                    self.command("scancel", *ids, check=False)
                    wait_for(
                        lambda: not any(s in ("RUNNING", "COMPLETING") for _, s, _ in self.jobs()),
                        60,
                        "cancelled jobs to end",
                    )
        except (RuntimeError, subprocess.TimeoutExpired):
            pass  # the daemons go down below all the same
        for _, proc in reversed(self.procs):
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)
                try:
                    proc.wait(timeout=30)
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, signal.SIGKILL)
                    proc.wait(timeout=30)

    def logs(self):
        return "\n".join(
            f"--- {p.name}:\n{p.read_text(errors='replace')[-1500:]}"
            for p in sorted(self.root.glob("*.out")) + sorted(self.root.glob("*.log"))
        )


def unavailable(reason):
    if os.environ.get("HMFDIFF_REQUIRE_SLURM") == "1":
        pytest.fail(f"{reason} (HMFDIFF_REQUIRE_SLURM=1)")
    pytest.skip(reason)


@pytest.fixture(scope="module")
def slurm():
    missing = [d for d in DAEMONS if shutil.which(d) is None]
    if missing:
        unavailable(
            f"Slurm is not installed (missing {', '.join(missing)}; "
            "apt-get install slurm-wlm munge provides them)"
        )
    if os.geteuid() != 0:
        unavailable("a local Slurm needs root: slurmd runs jobs as their user")
    cluster = LocalSlurm(Path(tempfile.mkdtemp(prefix="hmfdiff-slurm-")))
    try:
        t0 = time.monotonic()
        try:
            cluster.start()
        except (RuntimeError, OSError, subprocess.SubprocessError) as exc:
            unavailable(f"the local Slurm did not start: {exc}\n{cluster.logs()}")
        cluster.startup_s = time.monotonic() - t0
        print(f"local Slurm up in {cluster.startup_s:.1f} s (node {cluster.node})")
        # The cluster user's own profile, as the README asks for beside the workflow profile:
        # no accounting here, so the plugin asks squeue (and early, for a short test).
        cluster.profile = cluster.root / "profile"
        cluster.profile.mkdir()
        (cluster.profile / "config.yaml").write_text(
            "slurm-status-command: squeue\nslurm-init-seconds-before-status-checks: 2\n"
        )
        yield cluster
    finally:
        cluster.stop()
        shutil.rmtree(cluster.root, ignore_errors=True)


# ---- the workflow in temporary copies ----------------------------------------------------
def copy_workflow(dest):
    for item in ("Snakefile", "config", "workflow", "src"):
        src = ROOT / item
        if src.is_dir():
            shutil.copytree(
                src, dest / item, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info")
            )
        else:
            shutil.copy2(src, dest / item)
    return dest


def snakemake(args, cwd, env=None, timeout=1200):
    # The jobs import the library copied beside the workflow they run, in both runs.
    env = dict(env or os.environ, PYTHONPATH=str(cwd / "src"), MPLBACKEND="Agg")
    return subprocess.run(
        [sys.executable, "-m", "snakemake", *args],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def tail(r):
    return f"{r.stdout[-2000:]}\n{r.stderr[-4000:]}"


def reduced_smoke_targets(workdir):
    """A cut of the smoke pipeline with one job of each kind: for the first MD case, its
    equilibrium, orbits and theory, its MD(bath) seeds, their fit, and figure 2."""
    r = snakemake(["--summary", "--configfile", SMOKE], workdir, timeout=300)
    assert r.returncode == 0, tail(r)
    rows = [line.split("\t") for line in r.stdout.splitlines()[1:] if "\t" in line]
    case = next(iter(yaml.safe_load((workdir / SMOKE).read_text())["md"]["runs"]))
    wanted = {
        "theory": {case},
        "fit": {f"{case}_bath"},
        "figure": {"fig02_action_frequency"},
    }
    targets = [path for path, _, rule, *_ in rows if Path(path).stem in wanted.get(rule, ())]
    assert len(targets) == 4, (targets, r.stdout[:2000])
    return targets


def job_counts(output):
    """Snakemake's 'Job stats' table as {rule: count}."""
    m = re.search(r"Job stats:\n.*?\n-+\s+-+\n(.*?)\ntotal", output, re.S)
    assert m, output[-3000:]
    return {line.split()[0]: int(line.split()[1]) for line in m.group(1).strip().splitlines()}


def netcdf_outputs(workdir):
    return {
        p.relative_to(workdir)
        for p in workdir.rglob("*.nc")
        if not p.relative_to(workdir).parts[0].startswith(".") and "src" not in p.parts
    }


@pytest.fixture(scope="module")
def local_run(tmp_path_factory):
    """The same reduced target set, run locally: the reference."""
    workdir = copy_workflow(tmp_path_factory.mktemp("local"))
    targets = reduced_smoke_targets(workdir)
    r = snakemake(["-j2", *targets, "--configfile", SMOKE], workdir)
    assert r.returncode == 0, tail(r)
    return workdir, targets, job_counts(r.stdout + r.stderr)


# ---- the tests ---------------------------------------------------------------------------
def test_slurm_profile_dry_run(tmp_path):
    """The cluster profile is valid: a dry run through the SLURM executor plugin plans every
    job (no Slurm needed)."""
    workdir = copy_workflow(tmp_path)
    r = snakemake(["-n", "--workflow-profile", str(PROFILE), "--configfile", SMOKE], workdir)
    assert r.returncode == 0, tail(r)
    assert job_counts(r.stdout + r.stderr)["all"] == 1


def test_slurm_profile_leaves_account_and_partition_to_the_user():
    def keys(node):
        if isinstance(node, dict):
            for k, v in node.items():
                yield str(k)
                yield from keys(v)
        elif isinstance(node, list):
            for v in node:
                yield from keys(v)

    profile = yaml.safe_load((PROFILE / "config.yaml").read_text())
    assert profile["executor"] == "slurm"
    found = [k for k in keys(profile) if re.search(r"account|partition", k)]
    assert not found, f"the workflow profile must not choose {found}"


def test_smoke_targets_through_slurm_equal_a_local_run(slurm, local_run, tmp_path):
    """Every job goes through sbatch and completes; the netCDF outputs hold the same data as
    those of the local run (MD does not depend on threads or on where it ran)."""
    ref_dir, targets, local_jobs = local_run
    workdir = copy_workflow(tmp_path)
    before = max((i for i, *_ in slurm.jobs()), default=0)
    t0 = time.monotonic()
    r = snakemake(
        [*targets, "--workflow-profile", str(PROFILE), "--profile", str(slurm.profile)]
        + ["--configfile", SMOKE],
        workdir,
        env=slurm.env,
    )
    print(f"reduced smoke run through Slurm: {time.monotonic() - t0:.0f} s")
    assert r.returncode == 0, tail(r) + slurm.logs()

    # Slurm ran each job, and each completed
    jobs = [(i, state, comment) for i, state, comment in slurm.jobs() if i > before]
    assert {state for _, state, _ in jobs} == {"COMPLETED"}, jobs
    ran = Counter(re.match(r"rule_(\w+?)(_wildcards_|$)", c).group(1) for *_, c in jobs)
    assert ran == Counter(local_jobs), (ran, local_jobs)

    # the same files, with the same data
    outputs = netcdf_outputs(workdir)
    assert outputs == netcdf_outputs(ref_dir)
    # every job writes one netCDF file, but the figure (PNG/PDF) and the kernel cache (a
    # directory); the MD job(s) write one per seed of the fitted MD(bath) run, in block folders
    no_netcdf = {"figure", "kernels", "md"}
    md = yaml.safe_load((workdir / SMOKE).read_text())["md"]
    n_seed_files = md.get("seeds_bath", md["seeds"])
    assert len(outputs) == n_seed_files + sum(
        n for rule, n in local_jobs.items() if rule not in no_netcdf
    )
    for rel in sorted(outputs):
        ours, ref = read_dataset(workdir / rel), read_dataset(ref_dir / rel)
        assert sorted(ours.data_vars) == sorted(ref.data_vars), rel
        for name in ref.data_vars:
            a, b = ours[name].values, ref[name].values
            assert a.dtype == b.dtype and a.shape == b.shape, (rel, name)
            assert np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"), (rel, name)
    for target in targets:
        assert (workdir / target).stat().st_size > 0
    assert not list(workdir.rglob("*.part"))


def test_failing_job_is_reported_failed(slurm, tmp_path):
    """A job whose command fails ends FAILED in Slurm (once per attempt the profile allows),
    Snakemake reports the rule and the Slurm job as failed and exits non-zero, and the output
    the job wrote before failing is removed."""
    workdir = copy_workflow(tmp_path)
    with open(workdir / "Snakefile", "a") as fh:
        fh.write(
            f"\n\nrule {FAILING_RULE}:\n"
            '    output: "failing/output.txt"\n'
            '    log: "logs/failing.log"\n'
            "    resources: mem_mb=100, runtime=5\n"
            "    shell: \"echo half > {output}; echo 'deliberate failure' > {log}; exit 3\"\n"
        )
    before = max((i for i, *_ in slurm.jobs()), default=0)
    r = snakemake(
        ["failing/output.txt", "--workflow-profile", str(PROFILE), "--profile", str(slurm.profile)]
        + ["--configfile", SMOKE],
        workdir,
        env=slurm.env,
        timeout=600,
    )
    out = r.stdout + r.stderr
    assert r.returncode != 0, out[-3000:]
    jobs = [(i, state, comment) for i, state, comment in slurm.jobs() if i > before]
    attempts = 1 + yaml.safe_load((PROFILE / "config.yaml").read_text()).get("retries", 0)
    assert [(s, c) for _, s, c in jobs] == [("FAILED", f"rule_{FAILING_RULE}")] * attempts, jobs
    assert f"Error in rule {FAILING_RULE}" in out
    for i, *_ in jobs:
        assert f"SLURM-job '{i}' failed, SLURM status is: 'FAILED'" in out
    assert "deliberate failure" in (workdir / "logs/failing.log").read_text()
    assert not (workdir / "failing/output.txt").exists()
