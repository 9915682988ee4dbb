"""Run-time plumbing for the workflow scripts: logging to the rule's log file, thread counts."""

from __future__ import annotations

import logging
import os
import sys
import time

__all__ = ["get_logger", "set_threads"]


def get_logger(name, log_path=None):
    """A logger that writes timestamped lines to stderr and, if given, to the rule's log file."""
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
    return logger


def set_threads(n):
    """Use n threads in numba kernels (Snakemake sets OMP_NUM_THREADS but not numba's)."""
    import numba

    n = max(1, min(int(n), numba.config.NUMBA_NUM_THREADS))
    numba.set_num_threads(n)
    return n
