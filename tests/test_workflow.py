"""The pipeline end to end on config/smoke.yaml, in a temporary copy of the workflow."""

import csv
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from _smoke import copy_workflow, smoke_workdir

from hmfdiff.analysis.figures.registry import FIGURES
from hmfdiff.pipeline.io import read_dataset

ROOT = Path(__file__).resolve().parents[1]


def snakemake(args, cwd, timeout=1500):
    r = subprocess.run(
        [sys.executable, "-m", "snakemake", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    return r


def job_counts(output):
    """Parse Snakemake's 'Job stats' table into {rule: count}."""
    m = re.search(r"Job stats:\n.*?\n-+\s+-+\n(.*?)\ntotal", output, re.S)
    if not m:
        return {}
    return {line.split()[0]: int(line.split()[1]) for line in m.group(1).strip().splitlines()}


def md_against_theory_medians(rows):
    """{(dynamics, column): median} of the MD's N D over the theory's (`ratio`: asymptotic,
    `ratio_windowed`: fitted over the MD's own lags), over the flag-0 bins of both MD cases.

    The smoke MD is toy-sized (N = 5000, 2 seeds, t <= 60): one bin's ratio scatters by tens
    of % and the rotating bins (N D ~ 1e-4 ... 1e-7, below the MD's noise) by any factor, so
    a bin-wise check would be noise; the median of 12 bins is robust to those.  Measured on
    the smoke run of 0af361a: MD(full) 1.21 (asymptotic Lenard-Balescu) and 0.94 (windowed);
    with the MD's or the theory's N D doubled 2.41 / 1.88, halved 0.60 / 0.47, with the
    Lenard-Balescu dressing dropped (bare Landau values, 1.6-60 times larger in these bins)
    0.58 -- each out of the band |median - 1| < 0.3 that the tests ask for.

    MD(bath): at 2 seeds its median was 0.69 against Landau (the thermal case's two core bins
    at 0.20 and 0.40, a fluctuation of 2 seeds), so no band that held it also excluded a factor
    of two; the smoke config therefore runs md.seeds_bath: 10, with which the same run gave
    1.07 (windowed 1.03; those two bins 0.49 +- 0.18 and 0.88 +- 0.19).

    `ratio_propagated` (the theory carried over the fit's lags, analysis.propagated), smoke run
    of 2026-11-27: 1.10 (bath) and 1.15 (full), against 1.07 and 1.21 asymptotic."""
    out = {}
    for dyn in ("bath", "full"):
        for col in ("ratio", "ratio_windowed", "ratio_propagated"):
            v = np.array([float(r[col]) for r in rows if r["dynamics"] == dyn and r["flag"] == "0"])
            v = v[np.isfinite(v)]
            out[dyn, col] = float(np.median(v)) if v.size else np.nan
    return out


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """The copy of the workflow in which `snakemake -j2 --configfile config/smoke.yaml` ran to
    completion (the session's one smoke build, shared with the other tests that read it)."""
    return smoke_workdir(tmp_path_factory)


@pytest.mark.parametrize("config", ["config/config.yaml", "config/smoke.yaml"])
def test_dry_run_plans_whole_workflow(tmp_path, config):
    workdir = copy_workflow(tmp_path)  # nothing built: the dry run plans every job
    r = snakemake(["-n", "--configfile", config], workdir, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    counts = job_counts(r.stdout + r.stderr)
    n_cases = len(yaml.safe_load((workdir / config).read_text())["cases"])
    assert counts.get("equilibrium") == n_cases
    assert counts.get("all") == 1


def test_smoke_pipeline_end_to_end_and_rerun_rules(workdir, tmp_path):
    """The smoke build (`snakemake -j2 --configfile config/smoke.yaml` from an empty results/,
    made by the `workdir` fixture, which fails unless it succeeded) wrote every output, MD agrees
    with theory within the smoke band, and the reruns after edits are exactly the dependent
    ones."""
    smoke = yaml.safe_load((workdir / "config/smoke.yaml").read_text())
    for case in smoke["cases"]:
        eq = read_dataset(
            workdir / f"results/smoke/equilibrium/{case}.nc", required=["M0", "u", "f"]
        )
        assert 0 < float(eq["M0"]) < 1
        assert eq["f"].attrs["units"] == "1" and "long_name" in eq["f"].attrs
        assert "git_revision" in eq.attrs and "config" in eq.attrs
        orb = read_dataset(
            workdir / f"results/smoke/orbits/{case}.nc", required=["J", "Omega", "c", "sigma"]
        )
        assert float(orb["M0"]) == float(eq["M0"])
    for case in smoke["md"]["runs"]:
        for dyn in ("bath", "full"):
            fit = read_dataset(workdir / f"results/smoke/fits/{case}_{dyn}.nc", required=["ND_md"])
            seeds = smoke["md"].get(f"seeds_{dyn}", smoke["md"]["seeds"])
            assert fit.attrs["n_seeds"] == seeds
            assert np.isfinite(fit["ND_md"].values).any()
        th = read_dataset(workdir / f"results/smoke/theory/{case}.nc", required=["D_landau"])
        for v in ("D_landau", "D_lenard_balescu", "Dpol_landau", "Dpol_lenard_balescu"):
            vals = th[v].values[th["separatrix_mask"].values == 0]
            assert np.all(np.isfinite(vals)), v  # no NaN/inf outside the masked band
    with open(workdir / "results/smoke/validation.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == [
        "case",
        "dynamics",
        "M0",
        "J0",
        "kappa0",
        "n_particles_in_bin",
        "ND_md",
        "ND_md_err",
        "ND_theory",
        "ratio",
        "z",
        "flag",
        "ND_windowed",
        "ratio_windowed",
        "z_windowed",
        "ND_spectrum",
        "ND_propagated",
        "ratio_propagated",
        "z_propagated",
        "n_seeds",
    ]
    assert {r["dynamics"] for r in rows} == {"bath", "full"}
    # MD against theory, end to end: a factor of two anywhere (MD, theory, a lost dressing)
    # moves these medians out of the band; see md_against_theory_medians
    medians = md_against_theory_medians(rows)
    for dyn in ("bath", "full"):
        assert abs(medians[dyn, "ratio"] - 1) < 0.3, medians
        assert abs(medians[dyn, "ratio_windowed"] - 1) < 0.3, medians
        assert abs(medians[dyn, "ratio_propagated"] - 1) < 0.3, medians
    figures = [name for name in FIGURES if name in smoke["figures"]]
    assert len(figures) == len(FIGURES)  # the smoke config draws every figure of the registry
    for name in figures:
        for ext in ("pdf", "png"):
            path = workdir / f"results/smoke/figures/{name}.{ext}"
            assert path.stat().st_size > 5000
        pdf = (workdir / f"results/smoke/figures/{name}.pdf").read_bytes()
        assert b"software_versions" in pdf and b"git_revision" in pdf  # provenance metadata
    # no temporary part-files left behind
    assert not list((workdir / "results/smoke").rglob("*.part"))
    # the smoke config writes only under its own results_dir and log_dir, and says that its
    # statistics validate nothing
    assert sorted(p.name for p in (workdir / "results").iterdir()) == ["smoke"]
    assert sorted(p.name for p in (workdir / "logs").iterdir()) == ["smoke"]
    summary = (workdir / "results/smoke/validation_summary.txt").read_text()
    assert summary.startswith("TOY SIZE, NO STATISTICS") and "+-" not in summary

    # nothing to do on a second run
    r = snakemake(["-n", "--configfile", "config/smoke.yaml"], workdir, timeout=300)
    assert r.returncode == 0
    assert "Nothing to be done" in r.stdout + r.stderr

    # editing one case's parameter reruns that case's chain, and only that
    cfg = yaml.safe_load((workdir / "config/smoke.yaml").read_text())
    cfg["cases"]["thermal_M0.9"]["M0"] = 0.85
    edited = tmp_path / "edited.yaml"
    edited.write_text(yaml.safe_dump(cfg))
    r = snakemake(["-n", "--configfile", str(edited)], workdir, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    counts = job_counts(r.stdout + r.stderr)
    # thermal_M0.9 feeds fig. 4 and fig. 7 in the smoke config, nothing else
    assert counts == {
        "equilibrium": 1,
        "orbits": 1,
        "theory": 1,
        "closed_forms": 1,
        "figure": 2,
        "all": 1,
    }, counts

    # editing the library a rule imports reruns the rules that depend on it (Snakemake compares
    # checksums, so a bare touch without a change of content rightly reruns nothing); every
    # module against every rule: tests/test_deps.py
    registry = workdir / "src/hmfdiff/analysis/figures/registry.py"
    original = registry.read_bytes()
    try:
        registry.write_bytes(original + b"\n# edited by test_workflow\n")
        r = snakemake(["-n", "--configfile", "config/smoke.yaml"], workdir, timeout=300)
    finally:
        registry.write_bytes(original)
    counts = job_counts(r.stdout + r.stderr)
    assert counts == {"figure": len(figures), "all": 1}, counts


# The SLURM profile's dry run and real runs: tests/test_slurm.py


def test_one_figure_by_name(workdir):
    r = snakemake(["-n", "fig2", "--configfile", "config/smoke.yaml"], workdir, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]


def test_truncated_netcdf_input_is_named(workdir, tmp_path):
    """A truncated intermediate stops the dependent rule with a message naming the file (in a
    copy of the smoke build: the forced rerun would leave the shared one out of date)."""
    copy = tmp_path / "copy"
    shutil.copytree(workdir, copy, symlinks=True)
    eq = copy / "results/smoke/equilibrium/thermal_M0.9.nc"
    eq.write_bytes(eq.read_bytes()[: eq.stat().st_size // 3])
    r = snakemake(
        ["-j1", "results/smoke/orbits/thermal_M0.9.nc", "-f", "--configfile", "config/smoke.yaml"],
        copy,
        timeout=300,
    )
    assert r.returncode != 0
    log = (copy / "logs/smoke/orbits/thermal_M0.9.log").read_text() + r.stderr
    assert "thermal_M0.9.nc: not a readable netCDF file" in log
    assert "truncated or corrupt" in log
