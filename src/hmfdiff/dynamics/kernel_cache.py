"""Compiled MD kernels reused safely across jobs: one shared numba cache per kernel version,
written once, and a private copy per job.

numba's on-disk cache (`cache=True`) is not safe when several processes compile the same
kernel into one directory at once (corrupted index, crashes).  So:

* the shared cache of a kernel version (`kernel_version`: a hash of the dynamics sources, of
  numba's and Python's versions and of the CPU) is written by one job (`warm`), which compiles
  every MD kernel in a scratch directory and renames it into place, atomically, when done;
* every MD job calls `use_kernel_cache(shared)` before it imports a kernel: the shared cache is
  copied into a private scratch directory and numba is pointed at the copy.  A job loads the
  kernels from its copy (no compilation) and, should one be missing (another CPU, a new
  signature), compiles it into its own copy: no two processes ever write the same directory.

Outside the workflow (tests, benchmarks, interactive use) nothing is cached: the environment
variable `ENABLE` is unset and `njit` is numba's with `cache=False`.  `njit` and `ENABLE` live in
`jit`, which the kernels import: this module imports the kernels (to compile them), not the
other way round.
"""

from __future__ import annotations

import atexit
import hashlib
import json
import os
import platform
import shutil
import sys
import tempfile
from pathlib import Path

from .jit import ENABLE

_KERNEL_MODULES = ("elementary", "integrator", "accumulator", "exact_bath", "ensemble")
_SOURCES = Path(__file__).resolve().parent

__all__ = ["ENABLE", "kernel_version", "use_kernel_cache", "warm", "cache_counts"]


def kernel_version():
    """A short hash of what the compiled kernels depend on: the dynamics sources, numba's and
    Python's versions and the machine's CPU."""
    import numba

    h = hashlib.sha256()
    for name in sorted(p.name for p in _SOURCES.glob("*.py")):
        h.update(name.encode())
        h.update((_SOURCES / name).read_bytes())
    cpu = platform.processor() or platform.machine()
    h.update(f"{numba.__version__} {sys.version} {cpu}".encode())
    return h.hexdigest()[:16]


def _kernels_imported():
    return [m for m in _KERNEL_MODULES if f"hmfdiff.dynamics.{m}" in sys.modules]


def use_kernel_cache(shared):
    """Point numba at a private copy of the shared cache directory `shared` (copied if it
    exists; an empty cache otherwise), removed when the process ends.  Must run before any
    kernel module is imported; returns the private directory."""
    imported = _kernels_imported()
    if imported:
        raise RuntimeError(
            f"use_kernel_cache must run before the kernels are imported (already: {imported})"
        )
    private = tempfile.mkdtemp(prefix="hmfdiff-kernels-")
    atexit.register(shutil.rmtree, private, ignore_errors=True)
    shared = Path(shared)
    if shared.is_dir():
        shutil.copytree(shared, private, dirs_exist_ok=True)
    os.environ["NUMBA_CACHE_DIR"] = private
    os.environ[ENABLE] = private
    import numba.core.config

    numba.core.config.reload_config()
    return private


def _compile_everything():
    """Run a tiny realisation of every MD variant so that each kernel compiles (same types as
    a real run)."""
    import numpy as np

    from ..meanfield.equilibrium import ThermalState
    from . import elementary, ensemble, md
    from .settings import MDRun

    state = ThermalState(M0=0.7)
    common = dict(
        n_particles=64, dt=0.1, t_max=2.0, sample_every=0.5, max_lag=1.0, origin_every=0.5
    )
    for dynamics, bath in (("bath", "exact"), ("bath", "integrated"), ("full", "exact")):
        md.run_md(
            state,
            MDRun(dynamics=dynamics, bath=bath, n_test=8, n_blocks=1, **common),
            seed=0,
            progress=None,
        )
    # the relaxation ensembles (rules relaxation_md, relaxation_md_control, relaxation_rates_md)
    ensemble.run_ensemble(
        state,
        n_particles=64,
        n_realisations=2,
        dt=0.1,
        times=np.array([0.0, 0.5, 1.0]),
        jbar_edges=np.linspace(0.0, 1.0, 5),
        seed=0,
        progress=lambda msg: None,
    )
    elementary.sincos_array(np.zeros(4))
    elementary.sincos_wrapped_array(np.zeros(4))
    elementary.actions_from_kappa(np.full(4, 0.5), 0.7)


def warm(shared):
    """Compile every MD kernel into the shared cache directory `shared` (a scratch directory
    renamed into place when complete; a killed warm-up leaves no `shared`).  Run it in a
    process that has not imported a kernel.  Returns what it wrote in `shared`/ready.json."""
    shared = Path(shared)
    shared.parent.mkdir(parents=True, exist_ok=True)
    scratch = Path(tempfile.mkdtemp(prefix=f".{shared.name}.tmp-", dir=shared.parent))
    try:
        use_kernel_cache(scratch / "none")  # an empty private cache
        private = os.environ["NUMBA_CACHE_DIR"]
        _compile_everything()
        shutil.copytree(private, scratch, dirs_exist_ok=True)
        info = {"kernel_version": kernel_version(), "counts": cache_counts()}
        (scratch / "ready.json").write_text(json.dumps(info, sort_keys=True))
        if shared.exists():  # written meanwhile by another warm-up: keep that one
            shutil.rmtree(scratch)
        else:
            os.replace(scratch, shared)
    except BaseException:
        shutil.rmtree(scratch, ignore_errors=True)
        raise
    return info


def cache_counts():
    """{'hits': n, 'misses': n} of the on-disk cache over the kernels loaded in this process."""
    from numba.core.registry import CPUDispatcher

    hits = misses = 0
    for m in _kernels_imported():
        mod = sys.modules[f"hmfdiff.dynamics.{m}"]
        for obj in vars(mod).values():
            if isinstance(obj, CPUDispatcher):
                hits += sum(obj.stats.cache_hits.values())
                misses += sum(obj.stats.cache_misses.values())
    return {"hits": hits, "misses": misses}
