"""The MD settings record (hmfdiff.dynamics.settings): one record per (case, dynamics) from the
config's md section, its one-line errors, derived step counts, JSON, and per-run threads in the
md rule."""

import copy
import dataclasses
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from hmfdiff.dynamics.runs import md_runs
from hmfdiff.dynamics.settings import WORKFLOW_FIELDS, MDRun
from hmfdiff.errors import ConfigError

ROOT = Path(__file__).resolve().parents[1]
SMOKE = yaml.safe_load((ROOT / "config" / "smoke.yaml").read_text())


def test_md_runs_merge_defaults_with_each_case():
    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["runs"]["corehalo_ch2"].update(threads=2, dt=0.05, fit_window=[5.0, 20.0])
    runs = md_runs(cfg)
    md = cfg["md"]
    assert set(runs) == {(c, d) for c in md["runs"] for d in ("bath", "full")}
    for (case, dynamics), run in runs.items():
        expected = {k: v for k, v in md.items() if k != "runs"}
        expected.update(md["runs"][case])
        expected["n_test"] = expected.pop(f"n_test_{dynamics}")
        del expected["n_test_bath" if dynamics == "full" else "n_test_full"]
        # seeds_bath / seeds_full override seeds for their dynamics (the smoke config sets one)
        expected["seeds"] = expected.pop(f"seeds_{dynamics}", expected["seeds"])
        expected.pop("seeds_bath" if dynamics == "full" else "seeds_full", None)
        got = run.to_dict()
        for key, value in expected.items():
            assert got[key] == value, (case, dynamics, key)
        assert run.case == case and run.dynamics == dynamics
    assert runs[("corehalo_ch2", "full")].threads == 2
    assert runs[("thermal_u-0.1", "full")].threads == md["threads"] == 1


@pytest.mark.parametrize(
    "field,value,match",
    [
        (
            "n_particles",
            -5,
            r"md run 'thermal_u-0.1': field 'n_particles' = -5 must be an integer >= 1",
        ),
        (
            "dt",
            0.0,
            r"md run 'thermal_u-0.1': field 'dt' = 0.0 is outside the allowed range \(0.0, inf\)",
        ),
        (
            "fit_window",
            [10.0, 500.0],
            r"field 'fit_window' = \[10.0, 500.0\] must satisfy .*max_lag",
        ),
        (
            "max_lag",
            100.0,
            r"field 'max_lag' = 100.0 exceeds t_max = 60.0: allowed \(0, t_max = 60.0\]",
        ),
        ("sample_every", 0.25, r"'sample_every' = 0.25 must be a whole multiple of dt = 0.1"),
        ("t_equilibrate", 0.15, r"'t_equilibrate' = 0.15 must be a whole multiple of dt = 0.1"),
        ("n_blocks", 8, r"'n_blocks' = 8 must be an integer in \[1, number of origins = 7\]"),
        ("n_test_bath", 0, r"field 'n_test' \(config key 'n_test_bath'\) = 0 must be .* >= 1"),
        ("separatrix_band_fit", 0.7, r"'separatrix_band_fit' = 0.7 is outside .*\[0.0, 0.5\)"),
        ("threads", "two", r"field 'threads' = 'two' must be an integer >= 1"),
    ],
)
def test_bad_settings_give_one_line_naming_case_field_value(field, value, match):
    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["runs"]["thermal_u-0.1"][field] = value
    with pytest.raises(ConfigError, match=match) as err:
        md_runs(cfg)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize(
    "edit,match",
    [
        (lambda c: c["md"]["runs"].update(nowhere={}), r"names case 'nowhere'"),
        (lambda c: c["md"]["runs"].update(twostep_ch={}), r"two-step state has no smooth f"),
        (lambda c: c["md"].update(tmax=5.0), r"unknown field\(s\) \['tmax'\]"),
        (lambda c: c["md"].pop("dt"), r"missing required field\(s\) \['dt'\]"),
        (lambda c: c["md"].pop("runs"), r"field 'runs' must be a mapping"),
    ],
)
def test_bad_md_section(edit, match):
    cfg = copy.deepcopy(SMOKE)
    edit(cfg)
    with pytest.raises(ConfigError, match=match):
        md_runs(cfg)


def test_derived_step_counts():
    run = MDRun(
        dynamics="full",
        n_particles=5000,
        n_test=1000,
        dt=0.1,
        t_max=60.0,
        t_equilibrate=2.0,
        sample_every=1.0,
        max_lag=30.0,
        origin_every=5.0,
        n_blocks=4,
    )
    assert run.steps_per_sample == 10
    assert run.equilibration_steps == 20
    assert run.n_samples == 60 and run.lag_samples == 30 and run.origin_samples == 5
    assert run.n_origins == 7  # origins at samples 0, 5, ..., 30: the last lag ends at 60
    assert run.n_steps == 20 + 600
    assert run.n_tracked == 6000
    assert dataclasses.replace(run, dynamics="bath").n_tracked == 1000


def test_json_round_trip_and_realisation_fields():
    run = md_runs(SMOKE)[("corehalo_ch2", "bath")]
    assert MDRun.from_json(run.to_json()) == run
    # the md rule's params: what changes the numbers of a realisation, nothing else
    real = MDRun.from_json(run.realisation_json())
    for f in dataclasses.fields(MDRun):
        if f.name in WORKFLOW_FIELDS:
            assert getattr(real, f.name) == f.default
        else:
            assert getattr(real, f.name) == getattr(run, f.name)
    other_fit = dataclasses.replace(run, fit_window=(5.0, 20.0), seeds=7, threads=2)
    assert other_fit.realisation_json() == run.realisation_json()
    assert dataclasses.replace(run, dt=0.05).realisation_json() != run.realisation_json()


def test_md_rule_takes_the_threads_of_its_run(tmp_path):
    """A per-case `threads` reaches the md rule's `threads:` (seen in a dry run's job list)."""
    for item in ("Snakefile", "config", "workflow", "src"):
        src = ROOT / item
        if src.is_dir():
            shutil.copytree(src, tmp_path / item, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy2(src, tmp_path / item)
    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["runs"]["corehalo_ch2"]["threads"] = 2
    (tmp_path / "threads.yaml").write_text(yaml.safe_dump(cfg))
    targets = [
        f"{SMOKE['results_dir']}/md/{c}/full/seeds0-1" for c in ("corehalo_ch2", "thermal_u-0.1")
    ]
    r = subprocess.run(
        [sys.executable, "-m", "snakemake", "-n", "--cores", "4"]
        + ["--configfile=threads.yaml", "--", *targets],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    jobs = re.findall(r"rule md:\n(.*?)(?:\n\n|\n\[|\nJob stats)", r.stdout + r.stderr, re.S)
    threads = {}
    for job in jobs:
        case = re.search(r"case=([^,\s]+)", job).group(1)
        m = re.search(r"threads: (\d+)", job)
        threads[case] = int(m.group(1)) if m else 1
    assert threads == {"corehalo_ch2": 2, "thermal_u-0.1": 1}


@pytest.mark.parametrize(
    "field,value,match",
    [
        ("n_track", 0, r"field 'n_track' = 0 must be null \(all\) or an integer in \[1, n_partic"),
        ("n_track", 6000, r"field 'n_track' = 6000 must be .* \[1, n_particles = 5000\]"),
        ("bath", "fast", r"field 'bath' = 'fast' must be 'exact' or 'integrated'"),
        ("bath_tolerance", 0.1, r"field 'bath_tolerance' = 0.1 is outside .*\(0.0, 0.001\)"),
        ("m_every", 0.25, r"field 'm_every' = 0.25 must be a whole multiple of dt = 0.1"),
    ],
)
def test_bad_precision_settings_give_one_line(field, value, match):
    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["runs"]["thermal_u-0.1"][field] = value
    with pytest.raises(ConfigError, match=match) as err:
        md_runs(cfg)
    assert "\n" not in str(err.value)


def test_precision_settings_and_their_derived_counts():
    run = md_runs(SMOKE)[("thermal_u-0.1", "full")]
    assert run.m_every == SMOKE["md"]["m_every"] and run.m_steps == 2
    assert run.n_m_samples == 301  # t_max = 60 every 0.2
    sub = dataclasses.replace(run, n_track=100)
    assert sub.n_tracked == 100 + run.n_test and sub.n_tracked_from_f == 100
    bath = md_runs(SMOKE)[("thermal_u-0.1", "bath")]
    assert bath.exact_bath and not dataclasses.replace(bath, bath="integrated").exact_bath
    assert bath.n_tracked_from_f == 0
    # an exact bath asks the scheduler for far less time than an integrated one
    big = dataclasses.replace(bath, n_particles=10**6, dt=0.05, sample_every=5.0, t_max=2000.0)
    assert big.runtime_min() < dataclasses.replace(big, bath="integrated").runtime_min()
    # m_every defaults to sample_every
    cfg = copy.deepcopy(SMOKE)
    del cfg["md"]["m_every"]
    assert md_runs(cfg)[("thermal_u-0.1", "bath")].m_every == cfg["md"]["sample_every"]


def test_md_scaling_runs():
    """One record per (study, dynamics, N): the md section's settings, the case's own under
    md.runs (if any), then the study's `run`; seeds one per size or a list; bad input refused
    in one line naming the study and the field."""
    from hmfdiff.dynamics.runs import md_scaling_runs, scaling_kappa0

    runs = md_scaling_runs(SMOKE)
    studies = SMOKE["md_scaling"]["studies"]
    assert len(studies) >= 2  # the smoke config exercises several studies
    assert set(runs) == {
        (c, d, n) for c, st in studies.items() for d in ("bath", "full") for n in st["sizes"]
    }
    for (case, dyn, n), run in runs.items():
        st = studies[case]
        seeds = st["seeds"][st["sizes"].index(n)] if isinstance(st["seeds"], list) else st["seeds"]
        assert run.n_particles == n and run.seeds == seeds and run.dynamics == dyn
        assert run.n_test == SMOKE["md"][f"n_test_{dyn}"]
        for k, v in st["run"].items():
            if k == "n_track":
                assert run.n_track == min(v, n), k
            else:
                assert getattr(run, k) == (tuple(v) if isinstance(v, list) else v), k
    assert any(isinstance(st["seeds"], list) for st in studies.values())
    assert md_scaling_runs({k: v for k, v in SMOKE.items() if k != "md_scaling"}) == {}
    assert scaling_kappa0(SMOKE) == {c: st.get("kappa0") for c, st in studies.items()}
    # a case need not be under md.runs; its own settings there apply when it is
    cfg = copy.deepcopy(SMOKE)
    cfg["md_scaling"]["studies"] = {"thermal_M0.9": {"sizes": [2000], "seeds": 2}}
    assert md_scaling_runs(cfg)[("thermal_M0.9", "bath", 2000)].t_max == SMOKE["md"]["t_max"]
    cfg["md"]["runs"]["thermal_M0.9"] = {"n_particles": 10, "t_max": 50.0}
    cfg["md_scaling"]["studies"]["thermal_M0.9"]["run"] = {"n_test_bath": 300}
    run = md_scaling_runs(cfg)[("thermal_M0.9", "bath", 2000)]
    assert (run.t_max, run.n_particles, run.n_test) == (50.0, 2000, 300)
    # a tracked subset larger than the smallest N tracks all of that N
    cfg = copy.deepcopy(SMOKE)
    cfg["md_scaling"]["studies"]["thermal_u-0.1"]["run"]["n_track"] = 2000
    clipped = md_scaling_runs(cfg)
    assert clipped[("thermal_u-0.1", "full", 1000)].n_track == 1000
    assert clipped[("thermal_u-0.1", "full", 3000)].n_track == 2000
    w = r"md_scaling study 'thermal_u-0.1': "
    for edit, match in (
        ({"sizes": [1000, 1000]}, w + r"field 'sizes' = \[1000, 1000\] must be distinct"),
        ({"seeds": 1}, w + r"field 'seeds' = 1 must be an integer >= 2 .* \(2 sizes\)"),
        ({"seeds": [3, 2, 2]}, w + r"field 'seeds' = \[3, 2, 2\] must be .* one such per size"),
        ({"run": {"tmax": 3}}, w + r"unknown field\(s\) \['tmax'\] under 'run'"),
        ({"run": {"seeds": 3}}, w + r"field\(s\) \['seeds'\] under 'run' are set by the study"),
        ({"extra": 1}, w + r"unknown field\(s\) \['extra'\]"),
    ):
        cfg = copy.deepcopy(SMOKE)
        cfg["md_scaling"]["studies"]["thermal_u-0.1"].update(edit)
        with pytest.raises(ConfigError, match=match):
            md_scaling_runs(cfg)
    for studies_edit, match in (
        ({"twostep_ch": {"sizes": [1000], "seeds": 2}}, r"study 'twostep_ch': a two-step"),
        ({"nonexistent": {"sizes": [1000], "seeds": 2}}, r"names case 'nonexistent', which is not"),
    ):
        cfg = copy.deepcopy(SMOKE)
        cfg["md_scaling"]["studies"].update(studies_edit)
        with pytest.raises(ConfigError, match=match):
            md_scaling_runs(cfg)
    # the single-case form of before is refused, saying what to write instead
    cfg = copy.deepcopy(SMOKE)
    cfg["md_scaling"] = {"case": "thermal_u-0.1", "sizes": [1000], "seeds": 2}
    with pytest.raises(ConfigError, match=r"md_scaling: unknown field\(s\) .*studies: \{<case>"):
        md_scaling_runs(cfg)
    cfg = copy.deepcopy(SMOKE)
    cfg["md_scaling"]["studies"]["corehalo_ch2"]["kappa0"] = [0.4, -1]
    with pytest.raises(ConfigError, match=r"study 'corehalo_ch2': field 'kappa0' = \[0.4, -1\]"):
        scaling_kappa0(cfg)
