"""Run-time plumbing for the workflow scripts: the job's log file, its errors, thread counts.

`get_logger(name, log_path)` writes timestamped lines to stderr and to the rule's log file, and
installs an exception hook: an uncaught exception writes its full traceback at the end of the
log file and one line on the console (stderr) naming the rule, the error and the log file.

`current_job()` is the `snakemake` object of the running script (Snakemake's script preamble
defines it in `__main__`), or None outside Snakemake: io uses it to name the rule in the
`history` attribute of the files the job writes.
"""

from __future__ import annotations

import logging
import os
import sys
import time
import traceback
from pathlib import Path

__all__ = [
    "get_logger",
    "set_threads",
    "current_job",
    "install_excepthook",
    "remove_stale_job_scripts",
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


def install_excepthook(log_path=None):
    """On an uncaught exception: traceback at the end of `log_path`, one line on stderr."""

    def hook(exc_type, exc, tb):
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
    """A logger that writes timestamped lines to stderr and, if given, to the rule's log file.

    Also installs `install_excepthook(log_path)`, so a failing script leaves its traceback in
    the log file."""
    logger = logging.getLogger(name)
    logger.setLevel(logging.INFO)
    logger.handlers.clear()
    fmt = logging.Formatter("%(asctime)s %(name)s: %(message)s", "%H:%M:%S")
    fmt.converter = time.gmtime
    handlers = [logging.StreamHandler(sys.stderr)]
    if log_path:
        os.makedirs(os.path.dirname(str(log_path)) or ".", exist_ok=True)
        handlers.append(logging.FileHandler(str(log_path), mode="w"))
    for h in handlers:
        h.setFormatter(fmt)
        logger.addHandler(h)
    logger.propagate = False
    install_excepthook(str(log_path) if log_path else None)
    return logger


def remove_stale_job_scripts(workdir="."):
    """Delete the temporary job scripts that killed jobs left in `.snakemake/scripts`; return
    them.

    For the Snakefile's `onstart:` handler: a run that starts holds the directory lock, so no
    job of another run is alive in this directory, and a job that ends removes its own script
    (a SIGKILL does not let it).  Not for runs started with --nolock beside another run."""
    scripts = Path(workdir) / ".snakemake" / "scripts"
    stale = sorted(scripts.glob("tmp*")) if scripts.is_dir() else []
    for path in stale:
        path.unlink(missing_ok=True)
    return stale


def set_threads(n):
    """Use n threads in numba kernels (Snakemake sets OMP_NUM_THREADS but not numba's)."""
    import numba

    n = max(1, min(int(n), numba.config.NUMBA_NUM_THREADS))
    numba.set_num_threads(n)
    return n
