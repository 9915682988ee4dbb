"""netCDF input/output with provenance, atomic writes and clear errors on bad files.

One engine (netCDF4) is used throughout.  Complex arrays never reach a file: store real and
imaginary parts as separate variables.  Writes go to a temporary file in the target directory
that is renamed into place only when complete, so a killed job never leaves a file that looks
whole.
"""

from __future__ import annotations

import contextlib
import datetime
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr

ENGINE = "netcdf4"

__all__ = [
    "ENGINE",
    "InputFileError",
    "provenance",
    "git_revision",
    "atomic_path",
    "write_dataset",
    "read_dataset",
    "scalar",
]


class InputFileError(RuntimeError):
    """A netCDF input that is missing, truncated, corrupt or lacks a required variable."""


def git_revision(root=None):
    """The git revision of the source tree (with '-dirty' if modified), or 'unknown'."""
    root = Path(root) if root else Path(__file__).resolve().parents[2]
    try:
        rev = subprocess.run(
            ["git", "-C", str(root), "rev-parse", "--short=12", "HEAD"],
            capture_output=True,
            text=True,
            timeout=10,
            check=True,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "-C", str(root), "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            timeout=10,
            check=True,
        ).stdout.strip()
        return rev + ("-dirty" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def _versions():
    import matplotlib
    import netCDF4
    import numba
    import scipy

    from .. import __version__

    return {
        "hmfdiff": __version__,
        "python": sys.version.split()[0],
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "numba": numba.__version__,
        "xarray": xr.__version__,
        "netCDF4": netCDF4.__version__,
        "matplotlib": matplotlib.__version__,
    }


def provenance(config_fragment=None, case=None, history=None):
    """Attributes recording what made a file: config fragment, versions, git revision, time."""
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    attrs = {
        "software_versions": json.dumps(_versions(), sort_keys=True),
        "git_revision": git_revision(),
        "created": now,
        "history": f"{now} {history or ' '.join(sys.argv)}",
        "Conventions": "CF-1.8",
    }
    if case is not None:
        attrs["case"] = case
    if config_fragment is not None:
        attrs["config"] = json.dumps(config_fragment, sort_keys=True, default=str)
    return attrs


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside `path`; rename it onto `path` only if the block succeeds."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600 files; results are meant to be shared
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def write_dataset(ds, path, config_fragment=None, case=None, history=None):
    """Write `ds` to netCDF atomically, adding provenance attributes.

    Complex variables are refused (netCDF has no complex type); coordinates get no _FillValue.
    """
    for name, var in ds.variables.items():
        if np.iscomplexobj(var.values):
            raise TypeError(f"variable {name!r} is complex: store real and imaginary parts")
    ds = ds.copy()
    ds.attrs.update(provenance(config_fragment, case=case, history=history))
    encoding = {name: {"_FillValue": None} for name in ds.coords}
    for name in ds.data_vars:
        if ds[name].dtype.kind == "f":
            encoding[name] = {"_FillValue": np.nan}
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine=ENGINE, encoding=encoding)
    return Path(path)


def read_dataset(path, required=()):
    """Load a netCDF file fully into memory and close it.

    Raises InputFileError naming the file when it is missing, unreadable (truncated, corrupt)
    or lacks one of the `required` variables.
    """
    path = Path(path)
    if not path.exists():
        raise InputFileError(f"{path}: no such file")
    try:
        with xr.open_dataset(path, engine=ENGINE) as ds:
            ds.load()
    except Exception as exc:  # netCDF4 raises OSError, ValueError, RuntimeError ... on bad files
        raise InputFileError(
            f"{path}: not a readable netCDF file ({type(exc).__name__}: {exc}); "
            "it may be truncated or corrupt: delete it and rerun the rule that makes it"
        ) from exc
    missing = [v for v in required if v not in ds.variables]
    if missing:
        raise InputFileError(f"{path}: missing variable(s) {missing}")
    return ds


def scalar(value, units, long_name, **attrs):
    """A 0-d DataArray with units and long_name, for scalar results such as M0 or beta."""
    return xr.DataArray(float(value), attrs={"units": units, "long_name": long_name, **attrs})
