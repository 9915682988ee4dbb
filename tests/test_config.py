"""Bad configuration values stop the run at once, with a message naming case and field."""

import copy
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from hmfdiff.pipeline.config import ConfigError, check_config

ROOT = Path(__file__).resolve().parents[1]
SMOKE = yaml.safe_load((ROOT / "config" / "smoke.yaml").read_text())


def test_paper_and_smoke_configs_are_valid():
    check_config(SMOKE)
    check_config(yaml.safe_load((ROOT / "config" / "config.yaml").read_text()))


@pytest.mark.parametrize(
    "path,value,match",
    [
        (
            ("cases", "thermal_M0.9", "M0"),
            1.5,
            r"case 'thermal_M0.9': field 'M0' = 1.5 is outside the allowed range \(0.0, 1.0\)",
        ),
        (("cases", "thermal_M0.9", "M0"), -0.1, r"field 'M0' = -0.1 is outside"),
        (("cases", "thermal_M0.9", "M0"), "high", r"field 'M0' = 'high' must be a finite number"),
        (
            ("cases", "corehalo_ch2", "beta1"),
            -30.0,
            r"case 'corehalo_ch2': field 'beta1' = -30.0 is outside the allowed range \(0.0, inf\)",
        ),
        (("cases", "corehalo_ch2", "kind"), "plasma", r"field 'kind' = 'plasma' must be"),
        (
            ("grids", "orbits", "n_kappa"),
            -5,
            r"grids.orbits: field 'n_kappa' = -5 must be an integer >= 16",
        ),
        (("grids", "equilibrium", "kappa_max"), 0.5, r"field 'kappa_max' = 0.5 is outside"),
        (
            ("figures", "fig01_orbits", "case"),
            "nonexistent",
            r"figure 'fig01_orbits': names case 'nonexistent'",
        ),
    ],
)
def test_bad_values_name_case_and_field(path, value, match):
    cfg = copy.deepcopy(SMOKE)
    d = cfg
    for k in path[:-1]:
        d = d[k]
    d[path[-1]] = value
    with pytest.raises(ConfigError, match=match):
        check_config(cfg)


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
        ("max_lag", 100.0, r"max_lag = 100.0 exceeds t_max = 60.0"),
        ("sample_every", 0.25, r"'sample_every' = 0.25 must be a whole multiple of dt = 0.1"),
    ],
)
def test_bad_md_settings(field, value, match):
    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["runs"]["thermal_u-0.1"][field] = value
    with pytest.raises(ConfigError, match=match):
        check_config(cfg)


def test_u_above_magnetised_branch():
    cfg = copy.deepcopy(SMOKE)
    cfg["cases"]["thermal_u-0.1"] = {"kind": "thermal", "u": 0.26}
    with pytest.raises(ConfigError, match=r"case 'thermal_u-0.1': field 'u' = 0.26 .*magnetised"):
        check_config(cfg)


def test_thermal_needs_exactly_one_of_M0_u():
    cfg = copy.deepcopy(SMOKE)
    cfg["cases"]["thermal_M0.9"] = {"kind": "thermal"}
    with pytest.raises(ConfigError, match="exactly one of 'M0' or 'u'"):
        check_config(cfg)


def test_missing_key():
    cfg = copy.deepcopy(SMOKE)
    del cfg["cases"]["corehalo_ch2"]["mu2"]
    with pytest.raises(
        ConfigError, match=r"case 'corehalo_ch2': missing required field\(s\) \['mu2'\]"
    ):
        check_config(cfg)
    cfg = copy.deepcopy(SMOKE)
    del cfg["grids"]
    with pytest.raises(ConfigError, match="missing required field"):
        check_config(cfg)


def _snakemake_dry_run(configfile, cwd):
    return subprocess.run(
        [sys.executable, "-m", "snakemake", "-n", "--configfile", str(configfile)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_snakemake_stops_before_any_job(tmp_path):
    bad = copy.deepcopy(SMOKE)
    bad["cases"]["thermal_M0.9"]["M0"] = 1.2
    cfgfile = tmp_path / "bad.yaml"
    cfgfile.write_text(yaml.safe_dump(bad))
    r = _snakemake_dry_run(cfgfile, ROOT)
    assert r.returncode != 0
    assert (
        "case 'thermal_M0.9': field 'M0' = 1.2 is outside the allowed range" in r.stderr + r.stdout
    )
    assert "Job stats" not in r.stdout + r.stderr  # stopped while parsing, before planning jobs


def test_malformed_yaml_is_reported(tmp_path):
    cfgfile = tmp_path / "broken.yaml"
    cfgfile.write_text("cases: {thermal: {kind: thermal, M0: 0.5\ngrids: [\n")
    r = _snakemake_dry_run(cfgfile, ROOT)
    assert r.returncode != 0
    assert "not valid JSON or YAML" in r.stderr + r.stdout
    assert "Job stats" not in r.stdout + r.stderr
