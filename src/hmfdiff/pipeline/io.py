"""netCDF input/output with provenance, checksums, atomic writes and clear errors on bad files.

One engine (netCDF4) is used throughout.  Complex arrays never reach a file: store real and
imaginary parts as separate variables.

Writing.  Every variable with at least one dimension is stored chunked with a Fletcher-32
checksum (HDF5 `fletcher32`), so that a corrupted chunk makes the read fail instead of
returning garbage; every variable must carry `units` and `long_name`, and the units are CF
units (`cf_units`: "1" or "rad"; an HMF quantity of `HMF_UNITS` is stored as "1" with the
quantity in `comment`; any other unit string is refused); the file gets
`Conventions = "CF-1.10"`, a `title`, the config fragment, the package versions, the git
revision and a `history` line naming the Snakemake rule (when written by one), the package
version and the git commit.  Integers are stored in 32 bits where their values fit (`_narrow`:
the MD counters, indices, sizes; CF before 1.9 knows no 64-bit type, and a checker run at its
default CF version refuses them), else in 64 bits, which the declared CF-1.10 allows; the
largest at paper size, an MD(full) count of (origin, particle) pairs, is 120 000 tracked
particles x 51 origins = 6.1e6 per seed file.  `read_dataset` gives them back as int64, so that
a sum over many files (the fits pool 20-40 seeds) cannot overflow.  Every text attribute that
cites the paper by a LaTeX label of its source ("eq. hmfCEdif", "fig. hmfcontribs", whichever
module wrote it) is stored with the published number instead ("eq. (49)", "fig. 4";
`hmfdiff.paper_equations.cite`).

Atomicity.  Data go to a hidden temporary file beside the target (`.{name}.{random}.part`),
renamed onto the target only when complete, so a killed job never leaves a file that looks
whole.  A writer first deletes the temporary files that a killed writer of the same target
left behind, so rerunning the killed job (Snakemake's `--rerun-incomplete`) leaves nothing
behind.  Two processes must not write the same target at the same time (Snakemake never does).

Reading.  `read_dataset` loads a file fully and closes it, and refuses, naming the file (and
the variable): a missing or unreadable file (truncated, failed checksum), missing variables,
a dimension coordinate that is not strictly monotonic (CF), a time axis that does not
increase, and values outside a variable's `valid_min` / `valid_max` / `valid_range`.
`check_physical` adds the checks a reader that turns data into a result needs (sums of
squares >= 0, counts whole and >= 0, axes increasing).

Testing hook.  With the environment variable HMFDIFF_TEST_HOLD="before:GLOB" (or
"after:GLOB", several separated by commas), a write whose target matches GLOB announces
"hmfdiff test hold ..." on stderr just before (after) the rename and then waits to be killed:
the kill-and-restart tests use it to stop a job at a known point without timing guesses.
"""

from __future__ import annotations

import contextlib
import datetime
import fnmatch
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import xarray as xr

from ..paper_equations import cite

ENGINE = "netcdf4"
CONVENTIONS = "CF-1.10"
HOLD_ENV = "HMFDIFF_TEST_HOLD"
PART_SUFFIX = ".part"

#: dimension coordinates that are time axes: they must increase strictly.  The MD time axis
#: is `t`, not `time`: CF reserves a `time` coordinate for '<unit> since <epoch>' units
TIME_AXES = ("t", "lag", "tau")

#: unit strings stored as they are: valid UDUNITS strings (CF 3.1)
CF_UNITS = ("1", "rad")
#: the HMF quantities a writer may name as units.  Mass and coupling are 1, so every quantity
#: is a pure number: it is stored with CF units "1" and the quantity in `comment` (HMF_COMMENT)
HMF_UNITS = {
    "action": "action",
    "action^2": "action^2",
    "action (dimensionless HMF units)": "action",
    "action (dimensionless HMF units)^2": "action^2",
    "action (dimensionless HMF units) / tau": "action / tau (flux in rescaled time tau = t/N)",
    "action^2/time": "action^2 / time; N * D, the 1/N factored out",
    "action^2 / time (N * D, the 1/N factored out)": "action^2 / time; N * D, the 1/N factored out",
    "time": "time",
    "time (1/sqrt(M=1) units)": "time",
    "time / N": "time / N (rescaled time tau)",
    "rescaled time tau = t/N (HMF time units / N)": "rescaled time tau = t / N",
    "1/time": "1 / time",
    "1 / tau": "1 / tau (rate in rescaled time tau = t/N)",
    "time (N S(omega): two-sided, int S domega/2pi = variance)": (
        "time; N S(omega), two-sided, int S domega / 2 pi = variance"
    ),
    "energy per particle": "energy per particle",
    "momentum per particle": "momentum per particle",
}
HMF_COMMENT = "HMF units (unit mass and coupling): "

#: title of a file when the dataset carries none, by the Snakemake rule that writes it
DEFAULT_TITLES = {
    "equilibrium": "Equilibrium state of the HMF model, case {case}",
    "orbits": "Action-angle variables and Fourier coefficients of the HMF pendulum, case {case}",
    "theory": "Dielectric tensor and Landau / Lenard-Balescu diffusion coefficients, case {case}",
    "closed_forms": "Closed forms of Benetti & Marcos (2017) for case {case}: sech^4, two-step, "
    "appendix C",
    "md": "Molecular dynamics MD({dynamics}) of case {case}, seed {seed}: <dJ^2> accumulated "
    "per initial-action bin and lag",
    "fit": "Diffusion coefficients of MD({dynamics}), case {case}, fitted to <dJ^2>(dt)",
    "windowed": "Windowed theory of MD({dynamics}) for case {case}: N D over the fit window "
    "from the measured and the bath spectra",
    "spectrum": "Magnetisation spectra N S(omega) of case {case}: MD(bath) and MD(full) "
    "against the bare and dressed bath spectra",
    "relaxation": "Collisional relaxation of case {case} by the {equation} equation",
    "md_scaling": "Molecular dynamics MD({dynamics}) of case {case} at N = {n}, seed {seed}: "
    "<dJ^2> per initial-action bin and lag (N scaling)",
    "fit_scaling": "Diffusion coefficients of MD({dynamics}), case {case}, N = {n}, fitted to "
    "<dJ^2>(dt) (N scaling)",
    "scaling": "N D_MD per bin against N for MD({dynamics}) of case {case} (N scaling)",
}
#: how a wildcard value reads in a title
TITLE_WORDS = {"landau": "Landau", "lenard_balescu": "Lenard-Balescu"}

__all__ = [
    "ENGINE",
    "CONVENTIONS",
    "InputFileError",
    "provenance",
    "git_revision",
    "atomic_path",
    "atomic_directory",
    "write_dataset",
    "read_dataset",
    "check_physical",
    "scalar",
    "cf_units",
]


class InputFileError(RuntimeError):
    """A netCDF input that is missing, truncated, corrupt, lacks a required variable or holds
    physically impossible values."""


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


#: the libraries whose versions a file records (module and distribution names alike)
VERSIONED = ("numpy", "scipy", "numba", "xarray", "netCDF4", "matplotlib")


def _version(name):
    """The version of library `name`: its `__version__` when a module of the job imported it,
    else its installed distribution's (the same string, read without importing it: numba and
    matplotlib take 0.3-0.4 s each to import, which a job that writes a file but uses neither
    paid only for this line of provenance); the import is the last resort."""
    module = sys.modules.get(name)
    if module is None:
        import importlib.metadata

        try:
            return importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            module = importlib.import_module(name)
    return module.__version__


def _versions():
    from .. import __version__

    return {
        "hmfdiff": __version__,
        "python": sys.version.split()[0],
        **{name: _version(name) for name in VERSIONED},
    }


def _history_line(now, revision, history):
    """'<time> hmfdiff <version> (git <rev>) rule <rule> [wildcards]: <what>'."""
    from .. import __version__
    from .runtime import current_job

    job = current_job()
    if job is not None:
        wc = ", ".join(f"{k}={v}" for k, v in job.wildcards.items())
        who = f"rule {job.rule}" + (f" ({wc})" if wc else "")
    else:
        who = f"{Path(sys.argv[0]).name or 'python'} (outside Snakemake)"
    line = f"{now} hmfdiff {__version__} (git {revision}) {who}"
    return f"{line}: {history}" if history else line


def provenance(config_fragment=None, case=None, history=None):
    """Attributes recording what made a file: config fragment, versions, git revision, time,
    and a history line with the rule, the package version and the git commit."""
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    rev = git_revision()
    attrs = {
        "software_versions": json.dumps(_versions(), sort_keys=True),
        "git_revision": rev,
        "created": now,
        "history": _history_line(now, rev, history),
        "Conventions": CONVENTIONS,
    }
    if case is not None:
        attrs["case"] = case
    if config_fragment is not None:
        attrs["config"] = json.dumps(config_fragment, sort_keys=True, default=str)
    return attrs


def _test_hold(path, moment):
    """The HMFDIFF_TEST_HOLD hook (see the module docstring); a no-op when the variable is unset."""
    spec = os.environ.get(HOLD_ENV, "")
    for item in filter(None, spec.split(",")):
        when, _, pattern = item.partition(":")
        if when == moment and fnmatch.fnmatch(str(path), pattern):
            print(f"hmfdiff test hold {moment} rename: {path}", file=sys.stderr, flush=True)
            time.sleep(900.0)  # one wait, ended by the test's SIGKILL; no polling
            raise RuntimeError(f"{HOLD_ENV}: held {path} for 900 s and nobody killed the job")


def _glob_escape(name):
    """`name` with the glob metacharacters *, ?, [ made literal."""
    return "".join(f"[{c}]" if c in "*?[" else c for c in name)


def _stale_parts(path):
    """Temporary files of earlier writers of `path` (mkstemp: 8 random characters)."""
    return list(path.parent.glob(f".{_glob_escape(path.name)}.{'?' * 8}{PART_SUFFIX}"))


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside `path`; rename it onto `path` only if the block succeeds.

    Temporary files that a killed writer of the same target left behind are deleted first;
    the temporary file is deleted if the block fails.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    for stale in _stale_parts(path):
        stale.unlink(missing_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=PART_SUFFIX, dir=path.parent)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600 files; results are meant to be shared
    try:
        yield Path(tmp)
        _test_hold(path, "before")
        os.replace(tmp, path)
        _test_hold(path, "after")
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


@contextlib.contextmanager
def atomic_directory(path):
    """Yield a temporary directory beside `path` (`.<name>.part`); rename it onto `path` only if
    the block succeeds, so that a killed writer never leaves a directory that looks complete.

    A temporary directory that a killed writer of the same target left behind is deleted
    first; the temporary directory is deleted if the block fails.  An existing `path` (an old
    output, or the empty directory a scheduler may make) is replaced.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.parent / f".{path.name}{PART_SUFFIX}"
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir()
    try:
        yield tmp
        if path.is_dir():
            shutil.rmtree(path)
        os.replace(tmp, path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def cf_units(units, attrs=None):
    """The attributes to store for a variable given in `units`: CF units (`CF_UNITS` kept as
    they are; an HMF quantity of `HMF_UNITS` becomes "1" with the quantity in `comment`).

    Refuses (ValueError) any other unit string: no writer can store a unit a CF checker
    rejects."""
    attrs = dict(attrs or {})
    units = str(units).strip()
    if units in CF_UNITS:
        attrs["units"] = units
        return attrs
    if units not in HMF_UNITS:
        raise ValueError(
            f"units {units!r} are neither CF units {CF_UNITS} nor an HMF quantity of "
            "io.HMF_UNITS: add the quantity there (it is stored as units '1' with a comment)"
        )
    note = HMF_COMMENT + HMF_UNITS[units]
    comment = attrs.get("comment")
    attrs["comment"] = f"{note}. {comment}" if comment and note not in comment else comment or note
    attrs["units"] = "1"
    return attrs


def _missing_metadata(ds):
    return [
        name
        for name, var in ds.variables.items()
        if not (str(var.attrs.get("units", "")).strip() and var.attrs.get("long_name"))
    ]


def write_dataset(ds, path, config_fragment=None, case=None, history=None, title=None):
    """Write `ds` to netCDF atomically, with checksums and provenance attributes.

    Refused (ValueError, before anything is written): complex variables (netCDF has no complex
    type), variables without `units` and `long_name`, and unit strings that are neither CF
    units nor an HMF quantity (`cf_units`, which also maps the latter to "1" and a comment).
    Integers that fit are stored in 32 bits (`_narrow`); text attributes cite the paper's
    equations and figures by their published numbers (`paper_equations.cite`).
    Coordinates get no _FillValue; every variable with a dimension gets a Fletcher-32
    checksum.  The title is `title`, else the
    dataset's own, else the default of the writing rule.
    """
    for name, var in ds.variables.items():
        if np.iscomplexobj(var.values):
            raise TypeError(f"variable {name!r} is complex: store real and imaginary parts")
    missing = _missing_metadata(ds)
    if missing:
        raise ValueError(
            f"{path}: variable(s) {missing} lack 'units' or 'long_name' "
            "(every netCDF variable carries both; use units '1' for pure numbers)"
        )
    ds = ds.copy()
    for var in ds.variables.values():
        var.attrs = cf_units(var.attrs["units"], var.attrs)  # CF units, or ValueError
    ds = _narrow(ds)
    ds.attrs.update(provenance(config_fragment, case=case, history=history))
    ds.attrs["title"] = title or ds.attrs.get("title") or _default_title(path)
    for var in ds.variables.values():
        var.attrs = {k: cite(v) for k, v in var.attrs.items()}
    ds.attrs = {k: cite(v) for k, v in ds.attrs.items()}
    encoding = {}
    for name, var in ds.variables.items():
        enc = {}
        if name in ds.coords:
            enc["_FillValue"] = None
        elif var.dtype.kind == "f":
            enc["_FillValue"] = np.nan
        if var.ndim > 0:
            enc["fletcher32"] = True  # HDF5 stores it chunked; a scalar has no checksum
        encoding[name] = enc
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine=ENGINE, encoding=encoding)
    return Path(path)


#: attributes that CF wants in the type of their variable
_TYPED_ATTRS = ("valid_min", "valid_max", "valid_range", "flag_values", "flag_masks")
_INT32 = np.iinfo(np.int32)


def _narrow(ds):
    """`ds` with every 64-bit integer variable whose values fit in int32 stored as int32, its
    typed attributes (`_TYPED_ATTRS`) with it; a variable beyond int32 stays int64."""
    for name, var in list(ds.variables.items()):
        if var.dtype.kind not in "iu" or var.dtype.itemsize <= 4:
            continue
        values = var.values
        if values.size and (values.min() < _INT32.min or values.max() > _INT32.max):
            continue
        attrs = {
            k: np.asarray(v).astype(np.int32) if k in _TYPED_ATTRS else v
            for k, v in var.attrs.items()
        }
        ds = _replace(ds, name, xr.Variable(var.dims, values.astype(np.int32), attrs))
    return ds


def _widen(ds):
    """`ds` with its int32 variables as int64 (see the module docstring)."""
    for name, var in list(ds.variables.items()):
        if var.dtype.kind == "i" and var.dtype.itemsize == 4:
            ds = _replace(ds, name, var.astype(np.int64))
    return ds


def _replace(ds, name, var):
    if name in ds.coords:
        return ds.assign_coords({name: var})
    ds[name] = var
    return ds


def _default_title(path):
    from .runtime import current_job

    job = current_job()
    rule = job.rule if job is not None else None
    if rule not in DEFAULT_TITLES:
        return f"hmfdiff output {Path(path).name}"
    words = {k: TITLE_WORDS.get(str(v), v) for k, v in dict(job.wildcards.items()).items()}
    try:
        return DEFAULT_TITLES[rule].format(**words)
    except (KeyError, IndexError):  # a rule whose wildcards the title does not know
        return DEFAULT_TITLES[rule].replace("{", "").replace("}", "")


def read_dataset(path, required=()):
    """Load a netCDF file fully into memory and close it.

    Raises InputFileError naming the file when it is missing, unreadable (truncated, corrupt:
    a failed checksum), lacks one of the `required` variables, or fails the generic sanity
    checks of the module docstring (naming the variable).
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
    ds = _widen(ds)
    ds.encoding["source"] = str(path)
    missing = [v for v in required if v not in ds.variables]
    if missing:
        raise InputFileError(f"{path}: missing variable(s) {missing}")
    _check_generic(ds, path)
    return ds


def _bad(path, name, what, values, index):
    idx = np.unravel_index(int(index), np.shape(values)) if np.ndim(values) else ()
    value = np.asarray(values)[idx] if np.ndim(values) else values
    return InputFileError(
        f"{path}: variable {name!r} {what} (value {value!r} at index {tuple(map(int, idx))}); "
        "the file is corrupt or was written by a faulty run: delete it and rerun the rule "
        "that makes it"
    )


def _check_generic(ds, path):
    """CF sanity: monotonic dimension coordinates, increasing time axes, valid ranges."""
    for name in ds.dims:
        if name not in ds.coords or ds[name].ndim != 1 or ds[name].dtype.kind not in "iuf":
            continue
        x = ds[name].values
        if x.size < 2:
            continue
        d = np.diff(x)
        ok = d > 0 if (name in TIME_AXES or d[0] > 0) else d < 0
        if not np.all(ok):
            what = "is not strictly increasing" if name in TIME_AXES else "is not monotonic"
            raise _bad(path, name, what, x, np.flatnonzero(~ok)[0] + 1)
    for name, var in ds.variables.items():
        lo, hi = _valid_range(var.attrs)
        if (lo is None and hi is None) or var.dtype.kind not in "iuf":
            continue
        v = var.values
        out = np.zeros(v.shape, dtype=bool)
        if lo is not None:
            out |= v < lo
        if hi is not None:
            out |= v > hi
        if np.any(out):
            rng = f"[{_bound(lo, '-inf')}, {_bound(hi, 'inf')}]"
            raise _bad(path, name, f"lies outside its valid range {rng}", v, np.argmax(out))


def _bound(value, open_side):
    return open_side if value is None else f"{np.asarray(value).item():.6g}"


def _valid_range(attrs):
    if "valid_range" in attrs:
        lo, hi = np.asarray(attrs["valid_range"], dtype=float)[:2]
        return lo, hi
    return attrs.get("valid_min"), attrs.get("valid_max")


def check_physical(ds, *, sums_of_squares=(), counts=(), increasing=(), nonnegative=()):
    """Refuse physically impossible values, naming the file (ds.encoding['source']) and variable.

    sums_of_squares: finite and >= 0; counts: finite whole numbers >= 0; increasing: finite
    and strictly increasing (1-d); nonnegative: >= 0 where not NaN (NaN marks masked values),
    never infinite.  Variables absent from `ds` are skipped.  Returns `ds`.
    """
    path = ds.encoding.get("source", "<dataset not read from a file>")
    for name in sums_of_squares:
        if name in ds.variables:
            v = np.asarray(ds[name].values, dtype=float)
            bad = ~np.isfinite(v) | (v < 0)
            if bad.any():
                what = "is a sum of squares but negative or not finite"
                raise _bad(path, name, what, v, np.argmax(bad))
    for name in counts:
        if name in ds.variables:
            v = np.asarray(ds[name].values, dtype=float)
            bad = ~np.isfinite(v) | (v < 0) | (v != np.round(v))
            if bad.any():
                raise _bad(path, name, "is a count but not a whole number >= 0", v, np.argmax(bad))
    for name in increasing:
        if name in ds.variables:
            v = np.asarray(ds[name].values, dtype=float).ravel()
            bad = ~np.isfinite(v)
            bad[1:] |= ~(np.diff(v) > 0)
            if bad.any():
                raise _bad(path, name, "is not finite and strictly increasing", v, np.argmax(bad))
    for name in nonnegative:
        if name in ds.variables:
            v = np.asarray(ds[name].values, dtype=float)
            bad = np.isinf(v) | (v < 0)
            if bad.any():
                raise _bad(path, name, "is negative or infinite", v, np.argmax(bad))
    return ds


def scalar(value, units, long_name, **attrs):
    """A 0-d DataArray with units and long_name, for scalar results such as M0 or beta."""
    attrs = cf_units(units, attrs)
    return xr.DataArray(float(value), attrs={"long_name": long_name, **attrs})
