"""Logs and provenance: every netCDF output of the smoke run carries CF metadata, checksums and a
history naming the rule, the package version and the git commit; a failed job's log ends with
its traceback while the console gets one line."""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap

import netCDF4
import pytest
import xarray as xr
from _smoke import ROOT, SMOKE, copy_workflow, smoke_workdir, snakemake

import hmfdiff

#: results sub-folder -> the rule that writes it (folders not listed: any rule name)
RULE_OF_FOLDER = {
    "equilibrium": "equilibrium",
    "orbits": "orbits",
    "theory": "theory",
    "analytic": "closed_forms",
    "md": "md",
    "fits": "fit",
}
HISTORY = re.compile(
    r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ hmfdiff (?P<version>\S+) \(git (?P<rev>\S+)\) "
    r"rule (?P<rule>\w+)"
)


@pytest.fixture(scope="module")
def smoke(tmp_path_factory):
    return smoke_workdir(tmp_path_factory)


def _outputs(workdir):
    return sorted(
        p for p in workdir.rglob("*.nc") if not {".snakemake", "src", "tests"} & set(p.parts)
    )


def test_every_netcdf_output_carries_cf_metadata_and_provenance(smoke):
    files = _outputs(smoke)
    results = smoke / "results/smoke"  # results_dir of the smoke config
    folders = {p.relative_to(results).parts[0] for p in files}
    assert set(RULE_OF_FOLDER) <= folders, folders
    in_git = (ROOT / ".git").exists()
    for path in files:
        name = str(path.relative_to(smoke))
        with xr.open_dataset(path) as ds:
            attrs, variables = dict(ds.attrs), {k: dict(v.attrs) for k, v in ds.variables.items()}
        assert attrs.get("Conventions") == "CF-1.10", name
        assert str(attrs.get("title", "")).strip(), name
        for var, a in variables.items():
            assert str(a.get("units", "")).strip() and a.get("long_name"), (name, var)
        m = HISTORY.match(attrs["history"])
        assert m, (name, attrs["history"])
        assert m["version"] == hmfdiff.__version__, name
        assert m["rev"] == attrs["git_revision"], name
        if in_git:
            assert re.fullmatch(r"[0-9a-f]{12}(-dirty)?", m["rev"]), (name, m["rev"])
        folder = path.relative_to(results).parts[0]
        assert m["rule"] == RULE_OF_FOLDER.get(folder, m["rule"]), (name, m["rule"])
        assert ".snakemake/scripts" not in attrs["history"], name
        with netCDF4.Dataset(path) as nc:
            for var, v in nc.variables.items():
                assert v.ndim == 0 or v.filters()["fletcher32"], (name, var)


def test_uncaught_error_goes_to_the_log_with_one_line_on_the_console(tmp_path):
    log = tmp_path / "logs" / "job.log"
    script = textwrap.dedent(
        f"""
        from hmfdiff.pipeline.runtime import get_logger
        log = get_logger("job", {str(log)!r})
        log.info("starting the long phase")
        def inner():
            raise ValueError("the input is wrong\\nin two lines")
        inner()
        """
    )
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert r.returncode == 1
    console = r.stderr.strip().splitlines()
    assert "Traceback" not in r.stderr
    assert console[-1].endswith(
        f"failed: ValueError: the input is wrong in two lines (traceback in {log})"
    )
    text = log.read_text().strip().splitlines()
    assert "starting the long phase" in text[0]
    assert "Traceback (most recent call last):" in text
    assert any("in inner" in line for line in text)
    assert text[-2:] == ["ValueError: the input is wrong", "in two lines"]


def test_failed_job_log_ends_with_its_traceback(tmp_path):
    """A job whose input is corrupt (32 bytes overwritten inside a checksummed variable) fails;
    its log ends with the traceback of the read error naming the file, and the console shows
    the one-line summary (and no Python traceback of the job)."""
    d = copy_workflow(tmp_path)
    case = "thermal_u-0.1"
    eq = f"results/smoke/equilibrium/{case}.nc"  # results_dir of the smoke config
    r = snakemake(["-j1", eq, "--configfile", SMOKE], d)
    assert r.returncode == 0, r.stderr[-3000:]
    with xr.open_dataset(d / eq) as ds:
        f = ds["f"].values.astype("<f8")
    raw = (d / eq).read_bytes()
    offset = raw.find(f.tobytes()[:64])
    assert offset > 0
    with open(d / eq, "r+b") as fh:
        fh.seek(offset + f.size * 4)
        fh.write(bytes(range(32)))
    target = f"results/smoke/orbits/{case}.nc"
    r = snakemake(["-j1", target, "--configfile", SMOKE], d)
    assert r.returncode != 0
    logs = [p for p in d.rglob(f"{case}.log") if "orbits" in p.parts]
    assert len(logs) == 1, logs
    log = logs[0].read_text().rstrip().splitlines()
    assert "Traceback (most recent call last):" in log
    assert log[-1].startswith("hmfdiff.pipeline.io.InputFileError: ")
    assert f"{eq}: not a readable netCDF file" in log[-1]
    summary = [
        line
        for line in (r.stdout + r.stderr).splitlines()
        if line.startswith(f"rule orbits (case={case}) failed: InputFileError: {eq}: ")
    ]
    assert len(summary) == 1, r.stderr[-3000:]
    assert summary[0].endswith(f"(traceback in {logs[0].relative_to(d)})")
    assert "Traceback (most recent call last)" not in r.stdout + r.stderr
    assert not (d / target).exists()
