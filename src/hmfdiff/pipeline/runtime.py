"""Run-time plumbing for the workflow scripts: the job's log file, its errors, thread counts.

`get_logger(name, log_path)` writes timestamped lines to the rule's log file and, on the
console (stderr), one line per job: its last informational line (the scripts end with what
they wrote), when the job ends, and any warning at once; with HMFDIFF_LOG_CONSOLE=all every
line goes to the console too (a smoke run's console held ~440 such lines among Snakemake's
own).  It also installs an exception hook: an uncaught exception writes its full traceback at
the end of the log file and one line on the console naming the rule, the error and the log
file.

`current_job()` is the `snakemake` object of the running script (Snakemake's script preamble
defines it in `__main__`), or None outside Snakemake: io uses it to name the rule in the
`history` attribute of the files the job writes.
"""

from __future__ import annotations

import atexit
import logging
import os
import sys
import time
import traceback
from pathlib import Path

#: set to "all" for every log line of a job on the console, not only its last
CONSOLE_ENV = "HMFDIFF_LOG_CONSOLE"

__all__ = [
    "CONSOLE_ENV",
    "get_logger",
    "set_threads",
    "current_job",
    "install_excepthook",
    "remove_stale_job_scripts",
    "drop_local_job_rate_limiter",
]


def current_job():
    """The Snakemake job object of the running script, or None outside a `script:` rule."""
    job = getattr(sys.modules.get("__main__"), "snakemake", None)
    return job if hasattr(job, "rule") and hasattr(job, "wildcards") else None


def _job_name():
    job = current_job()
    if job is None:
        return os.path.basename(sys.argv[0]) or "python"
    wc = ", ".join(f"{k}={v}" for k, v in job.wildcards.items())
    return f"rule {job.rule}" + (f" ({wc})" if wc else "")


class _LastLine(logging.StreamHandler):
    """A console handler that writes warnings and errors at once and keeps only the latest
    informational line, written when the process ends (`flush_last`) unless dropped."""

    def __init__(self, stream):
        super().__init__(stream)
        self.last = None

    def emit(self, record):
        if record.levelno >= logging.WARNING:
            super().emit(record)
        else:
            self.last = record

    def flush_last(self):
        if self.last is not None:
            record, self.last = self.last, None
            super().emit(record)


_CONSOLE = []  # the _LastLine handlers of this process, for the exit and the exception hook


@atexit.register
def _flush_console():
    for handler in _CONSOLE:
        handler.flush_last()


def install_excepthook(log_path=None):
    """On an uncaught exception: traceback at the end of `log_path`, one line on stderr."""

    def hook(exc_type, exc, tb):
        for handler in _CONSOLE:  # the failure is the job's one console line
            handler.last = None
        if issubclass(exc_type, KeyboardInterrupt):
            sys.__excepthook__(exc_type, exc, tb)
            return
        text = "".join(traceback.format_exception(exc_type, exc, tb))
        where = "the traceback follows" if not log_path else f"traceback in {log_path}"
        message = " ".join(str(exc).split()) or "(no message)"
        summary = f"{_job_name()} failed: {exc_type.__name__}: {message} ({where})"
        written = False
        if log_path:
            try:
                with open(log_path, "a") as fh:
                    stamp = time.strftime("%H:%M:%S", time.gmtime())
                    fh.write(f"{stamp} {summary}\n{text}")
                written = True
            except OSError:
                pass
        print(summary, file=sys.stderr, flush=True)
        if not written:
            print(text, file=sys.stderr, end="", flush=True)

    sys.excepthook = hook
    return hook


def get_logger(name, log_path=None):
    """A logger that writes timestamped lines to the rule's log file, if given, and to stderr
    the last informational line at the end and warnings at once (every line with
    HMFDIFF_LOG_CONSOLE=all, or without a log file).

    Also installs `install_excepthook(log_path)`, so a failing script leaves its traceback in
    the log file."""
    logger = logging.getLogger(name)
    logger.setLevel(logging.INFO)
    for h in logger.handlers:
        if h in _CONSOLE:
            _CONSOLE.remove(h)
    logger.handlers.clear()
    fmt = logging.Formatter("%(asctime)s %(name)s: %(message)s", "%H:%M:%S")
    fmt.converter = time.gmtime
    if log_path and os.environ.get(CONSOLE_ENV, "").strip().lower() != "all":
        console = _LastLine(sys.stderr)
        _CONSOLE.append(console)
    else:
        console = logging.StreamHandler(sys.stderr)
    handlers = [console]
    if log_path:
        os.makedirs(os.path.dirname(str(log_path)) or ".", exist_ok=True)
        handlers.append(logging.FileHandler(str(log_path), mode="w"))
    for h in handlers:
        h.setFormatter(fmt)
        logger.addHandler(h)
    logger.propagate = False
    install_excepthook(str(log_path) if log_path else None)
    return logger


def scripts_in_use(proc="/proc"):
    """Names of the `.snakemake/scripts` files that a live process of this machine runs (read
    from every /proc/<pid>/cmdline), or None where there is no /proc."""
    root = Path(proc)
    if not root.is_dir():
        return None
    used = set()
    for d in root.iterdir():
        if not d.name.isdigit():
            continue
        try:
            args = (d / "cmdline").read_bytes().split(b"\0")
        except OSError:  # the process ended, or is not ours to read
            continue
        for a in args:
            if b".snakemake/scripts/" in a:
                used.add(os.path.basename(a.decode(errors="replace")))
    return used


def remove_stale_job_scripts(workdir="."):
    """Delete the temporary job scripts that killed jobs left in `.snakemake/scripts`; return
    them.

    For the Snakefile's `onstart:` handler.  A job that ends removes its own script (a SIGKILL
    does not let it).  Snakemake's lock covers only the files of a run, so another run with
    other targets may be alive in the same directory: a script that a live process of this
    machine runs is kept (its run would fail at the job's end, deleting the finished output,
    if it vanished), and where the processes cannot be listed (no /proc) nothing is deleted.
    Jobs of a concurrent run on other machines (a cluster) are not visible here: do not start
    a second run in a directory whose first run has cluster jobs alive."""
    scripts = Path(workdir) / ".snakemake" / "scripts"
    candidates = sorted(scripts.glob("tmp*")) if scripts.is_dir() else []
    if not candidates:
        return []
    used = scripts_in_use()
    if used is None:
        return []
    stale = [p for p in candidates if p.name not in used]
    for path in stale:
        path.unlink(missing_ok=True)
    return stale


def drop_local_job_rate_limiter(workflow):
    """Turn off Snakemake's job-rate limiter for a run on this machine; True if it was on.

    For the Snakefile's `onstart:` handler (which runs once the scheduler exists).  Snakemake
    9's limiter (`--max-jobs-per-timespan`, default 100/1s, meant to spare a cluster's queue)
    arms a 1-second timer on each pass of the scheduling loop, and the pass that timer causes
    arms the next: every job that ends starts one more such chain, so the passes per second
    grow with the jobs done (737 timers for 40 two-second jobs, quadratic in the run's
    length).  Each pass that finds jobs waiting for a core re-selects among them, stat-ing the
    inputs of every ready job: in the paper's reproduction Snakemake itself used 25-45 % of one
    of the two cores.  A local run needs no submission limit (job ends wake the scheduler);
    a cluster run (a non-local executor) keeps it."""
    scheduler = getattr(workflow, "scheduler", None)
    plugin = getattr(workflow, "executor_plugin", None)
    if scheduler is None or plugin is None or plugin.common_settings.non_local_exec:
        return False
    was_on = getattr(scheduler, "job_rate_limiter", None) is not None
    scheduler.job_rate_limiter = None
    return was_on


def set_threads(n):
    """Use n threads in numba kernels (Snakemake sets OMP_NUM_THREADS but not numba's)."""
    import numba

    n = max(1, min(int(n), numba.config.NUMBA_NUM_THREADS))
    numba.set_num_threads(n)
    return n
