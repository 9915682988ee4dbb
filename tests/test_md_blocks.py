"""MD jobs in blocks of seeds: the blocks' layout (`MDRun.seed_blocks`), the reading of a run's
seed files from its block folders (`layouts.md.seed_files`), the atomic folder a block is
written into (`io.atomic_directory`), and, in a copy of the smoke run, that a seed's file does
not depend on the block it ran in and that raising `seeds` runs only the new realisations."""

from __future__ import annotations

import dataclasses
import re
import shutil

import numpy as np
import pytest
import xarray as xr
import yaml
from _smoke import ROOT, job_counts, smoke_workdir, snakemake

from hmfdiff.dynamics.settings import NOMINAL_PARTICLE_STEPS_PER_S, MDRun
from hmfdiff.errors import ConfigError
from hmfdiff.pipeline.io import atomic_directory
from hmfdiff.pipeline.layouts.md import seed_files

SMOKE = yaml.safe_load((ROOT / "config/smoke.yaml").read_text())
CASE = "thermal_u-0.1"


def run(**changes):
    base = dict(
        case="c",
        dynamics="full",
        n_particles=10_000,
        n_test=0,
        dt=0.1,
        t_max=100.0,
        sample_every=1.0,
        max_lag=50.0,
        origin_every=5.0,
        n_blocks=2,
    )
    return MDRun(**{**base, **changes})


def test_blocks_hold_job_seconds_of_work_aligned_at_their_size():
    r = run(seeds=10)
    per_seed = 10_000 * 1000 / NOMINAL_PARTICLE_STEPS_PER_S  # 1e7 particle-steps
    assert r.particle_steps() == 1e7
    r = dataclasses.replace(r, job_seconds=3.5 * per_seed)
    assert r.seeds_per_job() == 3
    assert r.seed_blocks() == [(0, 2), (3, 5), (6, 8), (9, 9)]
    # raising seeds keeps every full block; the block size follows neither seeds nor threads
    more = dataclasses.replace(r, seeds=14, threads=4)
    assert more.seed_blocks()[:3] == r.seed_blocks()[:3]
    assert more.seed_blocks()[3:] == [(9, 11), (12, 13)]
    assert dataclasses.replace(r, job_seconds=0.5 * per_seed).seed_blocks() == [
        (s, s) for s in range(10)
    ]
    assert dataclasses.replace(r, job_seconds=1e9).seed_blocks() == [(0, 9)]
    # an exact bath counts 1/8 of its particles (its orbits are summed, not integrated)
    bath = run(dynamics="bath", n_test=2000, bath="exact", n_particles=80_000)
    assert bath.particle_steps() == (10_000 + 2000) * 1000
    # the wall-time request grows with the block
    big = run(n_particles=500_000, t_max=1000.0)
    assert big.runtime_min(30) > big.runtime_min(1) > 10


@pytest.mark.parametrize("value", [0, -60, float("nan"), "60"])
def test_job_seconds_must_be_positive(value):
    with pytest.raises(ConfigError, match=r"md run 'c': field 'job_seconds' = .*"):
        run(job_seconds=value)


def write_seed(folder, s):
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"seed{s}.nc"
    path.write_bytes(b"")
    return path


def test_seed_files_read_folders_and_files_in_seed_order(tmp_path):
    a, b = tmp_path / "seeds0-1", tmp_path / "seeds2-11"
    for s in (0, 1):
        write_seed(a, s)
    for s in range(2, 12):
        write_seed(b, s)
    got = seed_files([str(b), str(a)], 12)
    assert got == [str((a if s < 2 else b) / f"seed{s}.nc") for s in range(12)]  # 10 after 9
    single = write_seed(tmp_path / "loose", 0)
    assert seed_files(single, 1) == [str(single)]


def test_seed_files_refuse_missing_repeated_or_extra_seeds(tmp_path):
    a, b = tmp_path / "seeds0-1", tmp_path / "seeds2-3"
    for s in (0, 1):
        write_seed(a, s)
    write_seed(b, 3)
    with pytest.raises(RuntimeError, match=r"seeds \[2\] missing, \[\] unexpected"):
        seed_files([a, b], 4)
    with pytest.raises(RuntimeError, match=r"seeds \[\] missing, \[3\] unexpected"):
        seed_files([a, b], 2)
    write_seed(b, 1)
    with pytest.raises(RuntimeError, match="seed 1 twice"):
        seed_files([a, b], 4)
    (a / "seedX.nc").write_bytes(b"")
    with pytest.raises(RuntimeError, match="not a seed file"):
        seed_files([a], 2)


def test_atomic_directory_appears_whole_or_not_at_all(tmp_path):
    target = tmp_path / "md" / "seeds0-1"
    with pytest.raises(ZeroDivisionError):
        with atomic_directory(target) as d:
            write_seed(d, 0)
            raise ZeroDivisionError  # the job dies after its first seed
    assert not target.exists()
    assert [p.name for p in target.parent.iterdir()] == []  # no temporary folder left
    # a folder a killed writer left is cleared; an old output is replaced
    stale = target.parent / f".{target.name}.part"
    write_seed(stale, 7)
    write_seed(target, 9)
    with atomic_directory(target) as d:
        assert d == stale and not any(d.iterdir())
        write_seed(d, 0)
        assert not (target / "seed0.nc").exists()  # not visible before the block ends
    assert sorted(p.name for p in target.iterdir()) == ["seed0.nc"]
    assert not stale.exists()


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return smoke_workdir(tmp_path_factory)


def config_with(tmp, **md_case):
    cfg = yaml.safe_load((ROOT / "config/smoke.yaml").read_text())
    cfg["md"]["runs"][CASE].update(md_case)
    path = tmp / "blocks.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path.name


def planned_md_folders(output, dynamics="full"):
    pattern = rf"output: \S+/md/{re.escape(CASE)}/{dynamics}/(seeds\d+-\d+)"
    return sorted(re.findall(pattern, output), key=lambda f: int(f[5:].split("-")[0]))


def test_a_seed_gives_the_same_file_in_any_block_and_new_seeds_run_alone(workdir, tmp_path):
    """The smoke run made MD(full) seeds 0 and 1 of thermal_u-0.1 in one job (folder seeds0-1).
    In a copy, one seed per job (job_seconds below one seed's work) makes folders seeds0-0 and
    seeds1-1 whose files equal the smoke run's, bit for bit; raising seeds to 3 then plans
    exactly one MD(full) job, seeds2-2 (MD(bath), whose blocks job_seconds regrouped, runs
    all its seeds again, one per job)."""
    copy = tmp_path / "copy"
    shutil.copytree(workdir, copy, symlinks=True)
    res = copy / SMOKE["results_dir"] / "md" / CASE / "full"
    assert sorted(p.name for p in res.iterdir()) == ["seeds0-1"]
    name = config_with(tmp_path, job_seconds=1e-6)
    shutil.copy(tmp_path / name, copy / name)
    r = snakemake(["-n", "--configfile", name], copy)
    assert r.returncode == 0, r.stderr[-3000:]
    assert planned_md_folders(r.stdout + r.stderr) == ["seeds0-0", "seeds1-1"]
    targets = [str(res.relative_to(copy) / f) for f in ("seeds0-0", "seeds1-1")]
    r = snakemake(["-j2", "--configfile", name, "--", *targets], copy)
    assert r.returncode == 0, r.stderr[-3000:]
    for s in (0, 1):
        with (
            xr.open_dataset(res / "seeds0-1" / f"seed{s}.nc") as a,
            xr.open_dataset(res / f"seeds{s}-{s}" / f"seed{s}.nc") as b,
        ):
            assert set(a.data_vars) == set(b.data_vars)
            for v in a.data_vars:
                assert np.array_equal(a[v].values, b[v].values, equal_nan=True), (s, v)
            assert a.attrs["seed"] == b.attrs["seed"] == s
    name = config_with(tmp_path, job_seconds=1e-6, seeds=3)
    shutil.copy(tmp_path / name, copy / name)
    r = snakemake(["-n", "--configfile", name], copy)
    assert r.returncode == 0, r.stderr[-3000:]
    out = r.stdout + r.stderr
    assert planned_md_folders(out) == ["seeds2-2"]
    # MD(bath) of the case (10 seeds, one block in the smoke run) is regrouped by job_seconds
    assert planned_md_folders(out, "bath") == [f"seeds{s}-{s}" for s in range(10)]
    assert job_counts(out)["md"] == 11
