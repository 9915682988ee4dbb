"""Every bad configuration stops `snakemake` at once with ONE line (no traceback) naming the case
or section, the field, the value and what is allowed, and writes nothing (issue 12, part 6).

Each case runs `snakemake -n` in a temporary copy of the workflow on a variant of
config/smoke.yaml; the copy's files are listed before and after, and must not change (a dry
run that gets past the config check creates .snakemake/).
"""

import copy
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
SMOKE_TEXT = (ROOT / "config" / "smoke.yaml").read_text()
SMOKE = yaml.safe_load(SMOKE_TEXT)


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    d = tmp_path_factory.mktemp("config_cli")
    for item in ("Snakefile", "config", "workflow", "src"):
        src = ROOT / item
        if src.is_dir():
            shutil.copytree(
                src, d / item, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info")
            )
        else:
            shutil.copy2(src, d / item)
    return d


def files_under(d):
    return sorted(str(p.relative_to(d)) for p in d.rglob("*") if "__pycache__" not in p.parts)


def snakemake(workdir, args, timeout=300):
    return subprocess.run(
        [sys.executable, "-m", "snakemake", *args],
        cwd=workdir,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def edited(**paths):
    """The smoke config as YAML text with `a__b__c=value` set (None deletes the key)."""
    cfg = copy.deepcopy(SMOKE)
    for path, value in paths.items():
        keys = path.split("__")
        d = cfg
        for k in keys[:-1]:
            d = d[k]
        if value is None:
            del d[keys[-1]]
        else:
            d[keys[-1]] = value
    return yaml.safe_dump(cfg, sort_keys=False)


def text_with(old, new):
    assert old in SMOKE_TEXT
    return SMOKE_TEXT.replace(old, new, 1)


CH2 = {"kind": "core_halo", "eta1": 0.298, "eta2": 0.051, "mu1": -0.517, "mu2": 0.19}
RUN = "md__runs__thermal_u-0.1"
M09 = "  thermal_M0.9: {kind: thermal, M0: 0.9}\n"
TWICE = text_with(M09, M09 + "  thermal_M0.9: {kind: thermal, M0: 0.5}\n")
M09_LINE = TWICE.splitlines().index(M09.rstrip("\n")) + 1  # 1-based line of the first one
CASE_ONLY = text_with(M09, M09 + "  Thermal_M0.9: {kind: thermal, M0: 0.5}\n")
NO_M0 = {**CH2, "mu1": 1.0, "mu2": 2.0, "eta1": 0.05, "eta2": 0.01, "beta1": 0.5, "beta2": 0.5}
FIG7 = {"core_halo": ["corehalo_ch2"], "two_step": "thermal_M0.9", "thermal": "thermal_M0.9"}

# (id, config text, extra arguments, substrings the one line must hold)
BAD = [
    (
        "dt_huge",
        text_with("dt: 0.1", "dt: 1e9"),
        [],
        ["md run 'thermal_u-0.1'", "'dt'", "1000000000.0", "(0, 0.19", "orbital period"],
    ),
    (
        "n_particles_memory",
        edited(**{f"{RUN}__n_particles": "1e12"}),
        [],
        [
            "md run 'thermal_u-0.1'",
            "'n_particles' = 1000000000000",
            "GiB",
            "more than this machine",
        ],
    ),
    (
        "n_particles_one",
        edited(**{f"{RUN}__n_particles": 1}),
        [],
        ["md run 'thermal_u-0.1'", "'n_particles' = 1 ", "must be >= 1"],
    ),
    (
        "mu1_above_mu2",
        edited(cases__corehalo_ch2={**CH2, "mu1": 0.3, "beta1": 30.0, "beta2": 10.0}),
        [],
        ["case 'corehalo_ch2'", "'mu1' = 0.3", "below mu2 = 0.19"],
    ),
    (
        "duplicate_case",
        TWICE,
        [],
        [f"line {M09_LINE + 1}", "'thermal_M0.9' is given twice", f"first at line {M09_LINE}"],
    ),
    (
        "unknown_key_typo",
        text_with("  seeds: 2\n", "  n_seed: 2\n"),
        [],
        ["md: unknown field 'n_seed'", "did you mean 'seeds'"],
    ),
    (
        "unknown_section_typo",
        text_with("theory:", "thoery:"),
        [],
        ["config: unknown field 'thoery'", "did you mean 'theory'"],
    ),
    (
        "old_name_n_max",
        text_with("n_harmonics: 4", "n_max: 4"),
        [],
        ["grids.orbits: field 'n_max' is now called 'n_harmonics'"],
    ),
    (
        "M0_above_one",
        edited(**{"cases__thermal_M0.9__M0": 1.2}),
        [],
        ["case 'thermal_M0.9'", "'M0' = 1.2", "(0.0, 1.0)"],
    ),
    (
        "u_above_branch",
        edited(**{"cases__thermal_u-0.1": {"kind": "thermal", "u": 0.26}}),
        [],
        ["case 'thermal_u-0.1'", "'u' = 0.26", "(-0.5, 0.25)", "magnetised"],
    ),
    (
        "M0_and_u",
        edited(**{"cases__thermal_M0.9__u": -0.1}),
        [],
        ["case 'thermal_M0.9'", "exactly one of 'M0' or 'u'"],
    ),
    (
        "kind_unknown",
        edited(**{"cases__corehalo_ch2__kind": "plasma"}),
        [],
        ["case 'corehalo_ch2'", "'kind' = 'plasma'", "'thermal', 'core_halo', 'two_step'"],
    ),
    (
        "missing_mu2",
        edited(**{"cases__corehalo_ch2__mu2": None}),
        [],
        ["case 'corehalo_ch2'", "missing required field(s) ['mu2']"],
    ),
    (
        "case_name_chars",
        text_with("thermal_M0.9: {", "thermal M0/9: {"),
        [],
        ["cases: name 'thermal M0/9' is not allowed", "letters, digits"],
    ),
    (
        "case_names_collide",
        CASE_ONLY,
        [],
        ["case 'Thermal_M0.9'", "case 'thermal_M0.9'", "upper/lower case"],
    ),
    (
        "no_self_consistent_M0",
        edited(cases__corehalo_ch2=NO_M0),
        [],
        ["case 'corehalo_ch2'", "no magnetised self-consistent solution"],
    ),
    (
        "n_kappa_negative",
        edited(grids__orbits__n_kappa=-5),
        [],
        ["grids.orbits", "'n_kappa' = -5", "integer >= 16"],
    ),
    ("theory_n_max_zero", edited(theory__n_max=0), [], ["theory", "'n_max' = 0", ">= 1 and <= 32"]),
    (
        "t_max_infinite",
        text_with("t_max: 60.0", "t_max: .inf"),
        [],
        ["md", "'t_max' = inf", "finite"],
    ),
    ("seeds_word", edited(md__seeds="three"), [], ["md", "'seeds' = 'three'", "integer >= 1"]),
    (
        "fit_window_short",
        edited(md__fit_window=[10.0]),
        [],
        ["md", "'fit_window' = [10.0]", "[t_min, t_max]"],
    ),
    (
        "fit_window_beyond_lag",
        edited(**{f"{RUN}__fit_window": [10.0, 500.0]}),
        [],
        ["md run 'thermal_u-0.1'", "'fit_window' = [10.0, 500.0]", "max_lag = 30.0"],
    ),
    (
        "sample_every_not_multiple",
        edited(md__sample_every=0.25),
        [],
        ["md run", "'sample_every' = 0.25", "whole multiple of dt = 0.1"],
    ),
    (
        "n_blocks_above_origins",
        edited(md__n_blocks=100),
        [],
        ["md run", "'n_blocks' = 100", "[1,", "origins"],
    ),
    (
        "threads_zero",
        edited(**{f"{RUN}__threads": 0}),
        [],
        ["md run 'thermal_u-0.1'", "'threads' = 0", "integer >= 1"],
    ),
    (
        "md_two_step",
        edited(**{"md__runs__twostep_ch": {"n_particles": 5000}}),
        [],
        ["md run 'twostep_ch'", "two-step"],
    ),
    (
        "relaxation_two_step",
        edited(**{"relaxation__runs__twostep_ch": {}}),
        [],
        ["relaxation run 'twostep_ch'", "delta-function"],
    ),
    (
        "relaxation_typo",
        edited(**{"relaxation__runs__corehalo_ch2": {"n_node": 48}}),
        [],
        ["relaxation run 'corehalo_ch2': unknown field 'n_node'", "did you mean 'n_nodes'"],
    ),
    (
        "relaxation_old_band",
        edited(**{"relaxation__separatrix_band": 0.01}),
        [],
        ["relaxation: field 'separatrix_band' is now called 'layer_eta_min"],
    ),
    (
        "md_scaling_single_case_form",
        edited(md_scaling={"case": "thermal_u-0.1", "sizes": [1000], "seeds": 2}),
        [],
        ["md_scaling: field 'case' is now called 'studies", "{studies: {<case>:"],
    ),
    (
        "md_scaling_one_seed",
        edited(**{"md_scaling__studies__thermal_u-0.1__seeds": 1}),
        [],
        ["md_scaling.studies.thermal_u-0.1: field 'seeds' = 1 must be an integer >= 2"],
    ),
    (
        "md_scaling_seeds_per_size",
        edited(**{"md_scaling__studies__thermal_u-0.1__seeds": [2, 2, 2]}),
        [],
        ["md_scaling study 'thermal_u-0.1': field 'seeds' = [2, 2, 2]", "one such per size"],
    ),
    (
        "spectrum_not_md",
        edited(figures__fig14_spectrum={"cases": ["thermal_u-0.1", "thermal_M0.9"]}),
        [],
        ["figure 'fig14_spectrum': case 'thermal_M0.9'", "has no run under md.runs"],
    ),
    (
        "relaxation_md_dt",
        edited(relaxation_md__dt=0.45),
        [],
        ["relaxation_md run 'corehalo_ch2'", "'dt' = 0.45", "(0, 0.43", "orbital period"],
    ),
    (
        "figure_missing_case",
        edited(figures__fig01_orbits={"case": "nonexistent"}),
        [],
        ["figure 'fig01_orbits'", "'nonexistent'", "not in 'cases'"],
    ),
    (
        "figure_wrong_kind",
        edited(figures__fig07_closed_forms=FIG7),
        [],
        ["figure 'fig07_closed_forms'", "'two_step'", "'thermal_M0.9' of kind 'thermal'"],
    ),
    (
        # issue 36: once accepted, the job failed after 5 s ("Missing files") and deleted the figure
        "override_figure_case_without_md",
        SMOKE_TEXT,
        ["--config", "figures={fig09_md_thermal: {cases: [thermal_u-0.1, thermal_M0.9]}}"],
        [
            "figure 'fig09_md_thermal': case 'thermal_M0.9' (field 'cases') has no run under "
            "md.runs",
            "allowed: corehalo_ch2, thermal_u-0.1",
        ],
    ),
    (
        "override_not_multiple",
        SMOKE_TEXT,
        ["--config", "md={dt: 0.07}"],
        ["'sample_every' = 1.0", "whole multiple of dt = 0.07"],
    ),
    (
        "override_huge_dt",
        SMOKE_TEXT,
        ["--config", "md={dt: 1e9}"],
        ["md run 'thermal_u-0.1'", "'dt' = 1000000000.0"],
    ),
]


#: the bad configurations also run through `snakemake -n` in a copy of the workflow: one for
#: each place a check lives (the file reader, the schema, the states, the MD runs, the figures)
#: and every --config override (Snakemake's own parsing).  Every one is checked in process
#: through the Snakefile's own two calls (`refusal_in_process`), a second apiece instead of a
#: Snakemake start of several.
THROUGH_SNAKEMAKE = {
    "duplicate_case",
    "unknown_key_typo",
    "no_self_consistent_M0",
    "dt_huge",
    "figure_wrong_kind",
} | {b[0] for b in BAD if b[2]}


def refusal_in_process(path):
    """What the Snakefile does with `--configfile path`: check_config_files on the file, then
    prepare_config on Snakemake's reading of it; the line it prints, or None if accepted."""
    from snakemake.common.configfile import load_configfile

    from hmfdiff.pipeline.config import ConfigError, check_config_files, prepare_config

    try:
        check_config_files([str(path)])
        prepare_config(
            load_configfile(str(path)), str(ROOT / "workflow/schemas/config.schema.yaml")
        )
    except ConfigError as e:
        return f"Config error: {e}"
    return None


FILE_ONLY = [b for b in BAD if not b[2]]


@pytest.mark.parametrize(
    "text,expected", [(b[1], b[3]) for b in FILE_ONLY], ids=[b[0] for b in FILE_ONLY]
)
def test_bad_config_is_refused_in_one_line(tmp_path, text, expected):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text(text)
    out = refusal_in_process(cfg)
    assert out is not None and "\n" not in out, out
    for s in expected:
        assert s in out, (s, out)


THROUGH = [b for b in BAD if b[0] in THROUGH_SNAKEMAKE]


@pytest.mark.parametrize(
    "text,extra,expected", [b[1:] for b in THROUGH], ids=[b[0] for b in THROUGH]
)
def test_bad_config_stops_snakemake_in_one_line_and_writes_nothing(
    workdir, tmp_path, text, extra, expected
):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text(text)
    before = files_under(workdir)
    r = snakemake(workdir, ["-n", "--configfile", str(cfg), *extra])
    out = (r.stdout + r.stderr).strip()
    assert r.returncode == 1, out[-3000:]
    assert "Traceback" not in out and len(out.splitlines()) == 1, out[-3000:]
    assert out.startswith("Config error: ")
    for s in expected:
        assert s in out, (s, out)
    assert files_under(workdir) == before
    if not extra:  # the in-process check is the Snakefile's: the same line, word for word
        assert refusal_in_process(cfg) == out


def test_every_place_a_check_lives_goes_through_snakemake():
    """The subset run through Snakemake holds all the overrides and exists in BAD."""
    names = {b[0] for b in BAD}
    assert THROUGH_SNAKEMAKE <= names and len(THROUGH) >= 7


@pytest.mark.parametrize(
    "text,extra",
    [
        (text_with("dt: 0.1", "dt: 1e-1"), []),  # YAML 1.1 reads 1e-1 as a string
        (text_with("t_max: 60.0", "t_max: 6e1"), []),
        (SMOKE_TEXT, ["--config", "md={dt: 0.05, runs: {thermal_u-0.1: {n_particles: 6e3}}}"]),
    ],
    ids=["sci_notation_dt", "sci_notation_t_max", "nested_override"],
)
def test_numbers_in_any_notation_and_nested_overrides_are_accepted(workdir, tmp_path, text, extra):
    cfg = tmp_path / "good.yaml"
    cfg.write_text(text)
    r = snakemake(workdir, ["-n", "--configfile", str(cfg), *extra])
    assert r.returncode == 0, (r.stdout + r.stderr)[-3000:]
    md = yaml.safe_load(text)["md"]
    # at smoke size every case and dynamics runs its seeds in one job (md.job_seconds)
    n_md = len(md["runs"]) * 2
    assert re.search(rf"\bmd\s+{n_md}\b", r.stdout + r.stderr)
    seeds = md.get("seeds_bath", md["seeds"])
    assert f"md/thermal_u-0.1/bath/seeds0-{seeds - 1}" in r.stdout + r.stderr


def test_malformed_default_config_names_the_file(tmp_path):
    """Without --configfile the Snakefile reads config/config.yaml itself: a broken one is named
    with its line.  (A broken --configfile is read by Snakemake before the Snakefile runs, and
    Snakemake's own message names no file.)"""
    d = tmp_path / "wf"
    shutil.copytree(ROOT / "workflow", d / "workflow", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(
        ROOT / "src", d / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info")
    )
    shutil.copy2(ROOT / "Snakefile", d / "Snakefile")
    (d / "config").mkdir()
    (d / "config" / "config.yaml").write_text("cases: {a: {kind: thermal, M0: 0.5}\ngrids: [\n")
    before = files_under(d)
    r = snakemake(d, ["-n"])
    out = (r.stdout + r.stderr).strip()
    assert r.returncode == 1 and len(out.splitlines()) == 1, out[-3000:]
    assert out.startswith("Config error: config/config.yaml, line 2, column")
    assert "malformed YAML" in out
    assert files_under(d) == before


def test_bad_config_in_a_real_run_writes_no_results_or_logs(workdir, tmp_path):
    """Not a dry run: the config is refused before Snakemake plans a job, so no results/ and no
    logs/ appear (Snakemake's own empty session log under .snakemake/log is all)."""
    cfg = tmp_path / "bad.yaml"
    cfg.write_text(edited(**{f"{RUN}__n_particles": "1e12"}))
    before = set(files_under(workdir))
    r = snakemake(workdir, ["-j1", "--configfile", str(cfg)])
    out = (r.stdout + r.stderr).strip()
    assert r.returncode == 1 and len(out.splitlines()) == 1, out[-3000:]
    assert "'n_particles' = 1000000000000" in out
    assert not (workdir / "results").exists() and not (workdir / "logs").exists()
    new = sorted(set(files_under(workdir)) - before)
    assert all(p.startswith(".snakemake/log") for p in new), new
    assert all((workdir / p).is_dir() or (workdir / p).stat().st_size == 0 for p in new), new


def test_config_module_checks_files_outside_snakemake(tmp_path):
    """python -m hmfdiff.pipeline.config FILE...: the same checks, files merged in order."""
    cmd = [sys.executable, "-m", "hmfdiff.pipeline.config"]
    r = subprocess.run([*cmd, str(ROOT / "config" / "smoke.yaml")], capture_output=True, text=True)
    assert r.returncode == 0 and "valid (4 cases)" in r.stdout, r.stderr
    extra = tmp_path / "faster.yaml"
    extra.write_text("md: {dt: 0.3}\n")  # merged onto the smoke config: 0.3 > T/10
    r = subprocess.run(
        [*cmd, str(ROOT / "config" / "smoke.yaml"), str(extra)], capture_output=True, text=True
    )
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert "md run 'thermal_u-0.1': field 'dt' = 0.3 is outside the allowed range" in r.stderr
    broken = tmp_path / "broken.yaml"
    broken.write_text("cases: {a: {kind: thermal, M0: 0.5}\ngrids: [\n")
    r = subprocess.run([*cmd, str(broken)], capture_output=True, text=True)
    assert r.returncode == 1 and f"Config error: {broken}, line 2, column" in r.stderr
