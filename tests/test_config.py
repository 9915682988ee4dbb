"""Bad configuration values stop the run at once, with a message naming case and field."""

import copy
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy import special

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
        (
            "max_lag",
            100.0,
            r"field 'max_lag' = 100.0 exceeds t_max = 60.0: allowed \(0, t_max = 60.0\]",
        ),
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


# ---- the schema: one place for types, ranges and defaults --------------------------------
def _schema():
    return yaml.safe_load(SCHEMA.read_text())


SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"


def test_schema_is_valid_json_schema():
    import jsonschema

    jsonschema.Draft202012Validator.check_schema(_schema())


def _without(cfg, *paths):
    for path in paths:
        d = cfg
        for k in path[:-1]:
            d = d[k]
        del d[path[-1]]
    return cfg


def test_schema_defaults_fill_in_what_is_left_out_and_equal_the_library_defaults():
    """Defaults come from the schema; each equals the default of the code that uses it, so a
    config that leaves a field out computes what the library would."""
    import inspect

    from hmfdiff.dynamics.settings import MDRun
    from hmfdiff.kinetic.closed_forms import closed_forms
    from hmfdiff.kinetic.theory import theory_grid

    cfg = copy.deepcopy(SMOKE)
    del cfg["closed_forms"]
    _without(cfg, ("grids", "orbits", "n_harmonics"), ("theory", "n_max"), ("theory", "l_max"))
    _without(cfg, ("theory", "separatrix_band"))
    md_defaults = {
        k: v
        for k, v in MDRun.defaults().items()
        if k in cfg["md"] and k not in ("fit_window", "n_blocks")
    }  # the smoke run has 7 time origins, fewer than the default 10 blocks
    for k in md_defaults:
        del cfg["md"][k]
    got = check_config(cfg)

    def kw(fun):
        return {
            k: p.default
            for k, p in inspect.signature(fun).parameters.items()
            if p.default is not inspect.Parameter.empty
        }

    cf = dict(got["closed_forms"])
    cf["n_max"] = cf.pop("n_max_librating")
    assert cf == {k: v for k, v in kw(closed_forms).items() if k in cf}
    assert set(cf) == {"n_kappa", "kappa_min", "separatrix_band", "l_max", "n_max"}
    th = kw(theory_grid)
    assert {k: got["theory"][k] for k in ("n_max", "l_max", "separatrix_band")} == {
        k: th[k] for k in ("n_max", "l_max", "separatrix_band")
    }
    assert got["grids"]["orbits"]["n_harmonics"] == 6  # the paper's |n| <= 6
    assert md_defaults and {k: got["md"][k] for k in md_defaults} == md_defaults
    # every schema default of the md section is MDRun's
    md_schema = _schema()["properties"]["md"]["properties"]
    schema_md = {k: v["default"] for k, v in md_schema.items() if "default" in v}
    assert schema_md == {k: MDRun.defaults()[k] for k in schema_md}


def test_run_overrides_inherit_the_md_section_not_the_schema_defaults():
    """The schema's md defaults fill the md section only: a run inherits the section's value."""
    from hmfdiff.dynamics.runs import md_runs

    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["t_equilibrate"] = 2.0
    cfg["md"]["n_blocks"] = 3
    got = check_config(cfg)
    assert "t_equilibrate" not in got["md"]["runs"]["thermal_u-0.1"]
    run = md_runs(got)[("thermal_u-0.1", "bath")]
    assert (run.t_equilibrate, run.n_blocks) == (2.0, 3)


def test_schema_bounds_agree_with_the_physics_and_the_md_record():
    """The schema's ranges are those of the code: u on the magnetised thermal branch, and each
    MD field's lower bound that of MDRun's validation."""
    from hmfdiff.dynamics import settings
    from hmfdiff.meanfield.equilibrium import U_CRITICAL, U_MINIMUM

    s = _schema()
    u = s["$defs"]["thermal"]["properties"]["u"]
    assert (u["exclusiveMinimum"], u["exclusiveMaximum"]) == (U_MINIMUM, U_CRITICAL)
    props = s["$defs"]["md_settings"]["properties"]
    props = {**props, **s["$defs"]["md_run"]["properties"]}
    for name, lo in settings._INTEGERS:
        key = {"n_test": "n_test_full"}.get(name, name)  # n_test_bath >= 1 is checked below
        assert props[key]["type"] == "integer" and props[key]["minimum"] == lo, name
    assert props["n_test_bath"]["minimum"] == 1
    for name, lo, closed, hi in settings._REALS:
        p = props[name]
        assert p.get("minimum" if closed else "exclusiveMinimum") == lo, name
        assert p.get("exclusiveMaximum", math.inf) == hi, name


# ---- numbers, unknown keys, duplicate keys ------------------------------------------------
def test_numbers_written_as_strings_are_numbers():
    """YAML 1.1 reads 1e-1 as a string, and --config reads every nested value as one."""
    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["dt"] = "1e-1"
    cfg["md"]["fit_window"] = ["10", "3e1"]
    cfg["md"]["runs"]["thermal_u-0.1"]["n_particles"] = "5e3"
    cfg["theory"]["n_max"] = 3.0
    got = check_config(cfg)
    assert got["md"]["dt"] == 0.1 and isinstance(got["md"]["dt"], float)
    assert got["md"]["fit_window"] == [10.0, 30.0]
    n = got["md"]["runs"]["thermal_u-0.1"]["n_particles"]
    assert n == 5000 and isinstance(n, int)
    assert got["theory"]["n_max"] == 3 and isinstance(got["theory"]["n_max"], int)
    cfg["md"]["seeds"] = "2.5"
    with pytest.raises(ConfigError, match=r"^md: field 'seeds' = 2.5 must be an integer >= 1"):
        check_config(cfg)


@pytest.mark.parametrize(
    "path,key,match",
    [
        (("md",), "n_seed", r"^md: unknown field 'n_seed' \(did you mean 'seeds'\?\); allowed: "),
        (("cases", "thermal_M0.9"), "m0", r"^case 'thermal_M0.9': unknown field 'm0' \(did you "),
        (("md", "runs", "thermal_u-0.1"), "n_particle", r"^md run 'thermal_u-0.1': unknown .*"),
        (("theory",), "n_harmonics", r"^theory: .*'n_harmonics', a field of grids.orbits\?"),
        ((), "thoery", r"^config: unknown field 'thoery' \(did you mean 'theory'\?\)"),
    ],
)
def test_unknown_field_is_refused_with_the_nearest_name(path, key, match):
    cfg = copy.deepcopy(SMOKE)
    d = cfg
    for k in path:
        d = d[k]
    d[key] = 1
    with pytest.raises(ConfigError, match=match):
        check_config(cfg)


def test_loader_refuses_duplicate_keys_naming_file_and_lines(tmp_path):
    from hmfdiff.pipeline.schema import load_yaml_file

    f = tmp_path / "twice.yaml"
    f.write_text("md:\n  dt: 0.1\n  runs:\n    a: {n_particles: 5}\n  dt: 0.2\n")
    with pytest.raises(ConfigError, match=rf"^{re.escape(str(f))}, line 5: key 'dt' is given "):
        load_yaml_file(f)
    f.write_text("cases:\n  a: {kind: thermal, M0: 0.5, M0: 0.6}\n")
    with pytest.raises(ConfigError, match=r"line 2: key 'M0' is given twice \(first at line 2\)"):
        load_yaml_file(f)
    f.write_text("cases:\n  a: {kind: thermal, M0: 0.5}\n  b: {kind: thermal, M0: 0.5}\n")
    assert set(load_yaml_file(f)["cases"]) == {"a", "b"}


# ---- physics across fields ---------------------------------------------------------------
def _period_by_quadrature(kappa, M0):
    """Rotation period T = 2 int_0^pi dtheta / p(theta), p = sqrt(2 (h + M0 cos theta)),
    h = M0 (2 kappa^2 - 1): no elliptic function involved."""
    from scipy.integrate import quad

    h = M0 * (2.0 * kappa**2 - 1.0)
    return 2.0 * quad(lambda t: 1.0 / np.sqrt(2.0 * (h + M0 * np.cos(t))), 0.0, np.pi)[0]


def test_time_step_bounded_by_the_fastest_orbital_period():
    from hmfdiff.meanfield.equilibrium import ThermalState
    from hmfdiff.pipeline.config import fastest_orbital_period

    st = ThermalState(u=-0.1)
    T, kappa = fastest_orbital_period(st, 2.0)
    assert kappa == 2.0  # the test particles reach further than 1e-6 of the thermal particles
    assert T == pytest.approx(_period_by_quadrature(2.0, st.M0), rel=1e-9)
    # the thermal tail: the orbit above which 1e-6 of the particles lie (quadrature of f)
    T0, k0 = fastest_orbital_period(st, 0.5)
    assert T0 == pytest.approx(_period_by_quadrature(k0, st.M0), rel=1e-9)
    from scipy.integrate import quad

    def above(k):
        """Fraction of the particles with h > h(k): the p-integral of exp(-beta p^2/2) over
        p^2 > 2 (h + M0 cos theta) is sqrt(2 pi/beta) erfc(p_min sqrt(beta/2))."""
        h = st.M0 * (2.0 * k**2 - 1.0)

        def weight(t):
            return np.exp(st.beta * st.M0 * np.cos(t))

        def tail(t):
            p_min = np.sqrt(2.0 * max(h + st.M0 * np.cos(t), 0.0))
            return weight(t) * special.erfc(p_min * np.sqrt(st.beta / 2.0))

        return quad(tail, -np.pi, np.pi)[0] / quad(weight, -np.pi, np.pi)[0]

    assert above(k0) == pytest.approx(1e-6, rel=0.03)
    # dt = 0.2 divides sample_every = 1 but exceeds T/10 = 0.1975: refused, range stated
    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["dt"] = 0.2
    dt_max = _period_by_quadrature(2.0, st.M0) / 10
    with pytest.raises(ConfigError, match=rf"field 'dt' = 0.2 .*\(0, {dt_max:.4g}\]"):
        check_config(cfg)


def test_n_particles_at_least_the_mean_field_minimum():
    from hmfdiff.meanfield.equilibrium import ThermalState

    n_min = math.ceil(100.0 / ThermalState(u=-0.1).M0 ** 2)  # 1/sqrt(N) <= M0/10
    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["runs"]["thermal_u-0.1"]["n_particles"] = n_min
    check_config(cfg)
    cfg["md"]["runs"]["thermal_u-0.1"]["n_particles"] = n_min - 1
    with pytest.raises(ConfigError, match=rf"'n_particles' = {n_min - 1} must be >= {n_min}"):
        check_config(cfg)


def test_memory_refused_before_allocation(monkeypatch):
    """A run whose memory estimate (MDRun.memory_mb) exceeds the machine's is refused while
    checking, before anything is allocated."""
    from hmfdiff.dynamics.runs import md_runs
    from hmfdiff.pipeline import config as config_module

    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["runs"]["thermal_u-0.1"]["n_particles"] = 3_000_000
    runs = md_runs(check_config(cfg))
    need = max(r.memory_mb() for r in runs.values()) * 1e6
    assert need > 1e6 * (1000 + 48 * 3e6 / 1e6)  # libraries + 48 B per particle at least
    monkeypatch.setattr(config_module, "machine_memory_bytes", lambda: int(need) - 1)
    with pytest.raises(ConfigError, match=r"md run 'thermal_u-0.1' \(full\): field 'n_particles'"):
        check_config(cfg)
    monkeypatch.setattr(config_module, "machine_memory_bytes", lambda: int(need))
    check_config(cfg)


@pytest.mark.parametrize(
    "edit,match",
    [
        (
            {"mu1": 0.3},
            r"^case 'corehalo_ch2': field 'mu1' = 0.3 must be below mu2 = 0.19",
        ),
        ({"mu1": 0.19}, r"field 'mu1' = 0.19 must be below mu2 = 0.19"),
    ],
)
def test_core_below_halo(edit, match):
    cfg = copy.deepcopy(SMOKE)
    cfg["cases"]["corehalo_ch2"].update(edit)
    with pytest.raises(ConfigError, match=match):
        check_config(cfg)


def test_seeds_per_dynamics():
    """seeds_bath / seeds_full override seeds for one dynamics (md section or one case); a bad
    value is refused naming that field."""
    from hmfdiff.dynamics.runs import md_runs

    cfg = copy.deepcopy(SMOKE)
    cfg["md"]["seeds"] = 3
    cfg["md"]["seeds_bath"] = 7
    first = next(iter(cfg["md"]["runs"]))
    cfg["md"]["runs"][first] = {**(cfg["md"]["runs"][first] or {}), "seeds_full": 5}
    check_config(cfg)
    runs = md_runs(cfg)
    for (case, dynamics), run in runs.items():
        expected = 7 if dynamics == "bath" else (5 if case == first else 3)
        assert run.seeds == expected, (case, dynamics)
    cfg["md"]["seeds_bath"] = 0
    with pytest.raises(ConfigError, match=r"^md: field 'seeds_bath' = 0 must be an integer >= 1"):
        check_config(cfg)


# ---- the same checks in every block that runs dynamics (issue 20 part 8) -----------------
def _refused(cfg, *parts):
    """check_config refuses `cfg` in one line holding every string of `parts`."""
    with pytest.raises(ConfigError) as err:
        check_config(cfg)
    msg = str(err.value)
    assert "\n" not in msg, msg
    for part in parts:
        assert part in msg, (part, msg)
    return msg


def _thermal_M0(u):
    """M0 of the thermal state of energy u, solved here: M0 = I1(beta M0)/I0(beta M0) with
    u = 1/(2 beta) - M0^2/2 (the paper's thermal branch), by bisection in M0 above
    sqrt(-2u), where beta > 0."""
    from scipy.optimize import brentq

    def gap(m):
        beta = 1.0 / (2.0 * (u + m * m / 2.0))
        return special.i1e(beta * m) / special.i0e(beta * m) - m

    return brentq(gap, math.sqrt(max(-2.0 * u, 0.0)) + 1e-9, 1.0 - 1e-9, xtol=1e-14)


def _edit(cfg, path, value):
    d = cfg
    for k in path[:-1]:
        d = d[k]
    d[path[-1]] = value


CH2_SIZES = ("relaxation_md", "runs", "corehalo_ch2", "n_particles")
FIG14 = ("figures", "fig14_spectrum", "cases")
FIG15 = ("figures", "fig15_scaling", "cases")
SCALING = ("md_scaling", "studies", "thermal_u-0.1")


@pytest.mark.parametrize(
    "path,value,parts",
    [
        (
            ("relaxation", "runs", "nonexistent"),
            {},
            ["relaxation run 'nonexistent'", "names case 'nonexistent', which is not in 'cases'"],
        ),
        (
            ("relaxation", "runs", "twostep_ch"),
            {},
            ["relaxation run 'twostep_ch'", "two-step state has no smooth f", "core_halo"],
        ),
        (
            ("relaxation_md", "runs", "nonexistent"),
            {"n_particles": [400]},
            ["relaxation_md run 'nonexistent'", "which is not in 'cases'"],
        ),
        (
            ("relaxation_md", "runs", "twostep_ch"),
            {"n_particles": [400]},
            ["relaxation_md run 'twostep_ch'", "two-step state has no smooth f"],
        ),
        (
            ("relaxation_md", "runs", "thermal_u-0.1"),
            {"n_particles": [400]},
            ["relaxation_md run 'thermal_u-0.1'", "not under relaxation.runs"],
        ),
        (
            ("relaxation_md", "runs", "corehalo_ch2"),
            {"n_particles": [200, 400], "control_sizes": [800]},
            ["relaxation_md run 'corehalo_ch2': field 'control_sizes' = [800] not among"],
        ),
        (
            ("md_scaling", "studies", "nonexistent"),
            {"sizes": [1000], "seeds": 2},
            ["md_scaling study 'nonexistent': names case 'nonexistent', which is not in 'cases'"],
        ),
        (
            ("md_scaling", "studies", "twostep_ch"),
            {"sizes": [1000], "seeds": 2},
            ["md_scaling study 'twostep_ch': a two-step state has no smooth f"],
        ),
        (
            FIG15,
            ["thermal_u-0.1", "thermal_M0.9"],
            [
                "figure 'fig15_scaling': case 'thermal_M0.9' (field 'cases') has no study under "
                "md_scaling.studies"
            ],
        ),
        (
            ("relaxation_rates", "runs", "thermal_M0.9"),
            {"n_particles": [400]},
            ["relaxation_rates run 'thermal_M0.9'", "not under relaxation.runs"],
        ),
        (
            ("figures", "fig16_relaxation_rates", "case"),
            "thermal_M0.9",
            [
                "figure 'fig16_relaxation_rates': case 'thermal_M0.9' (field 'case') has no run "
                "under relaxation_rates.runs"
            ],
        ),
        (
            FIG14,
            ["thermal_u-0.1", "twostep_ch"],
            ["figure 'fig14_spectrum': case 'twostep_ch' (field 'cases') has no run under md.runs"],
        ),
        (
            FIG14,
            ["thermal_M0.9"],
            ["figure 'fig14_spectrum': case 'thermal_M0.9'", "has no run under md.runs"],
        ),
    ],
)
def test_every_block_refuses_an_unknown_or_two_step_case(path, value, parts):
    cfg = copy.deepcopy(SMOKE)
    _edit(cfg, path, value)
    _refused(cfg, *parts)


_RANGE = re.compile(
    r"field '(\w+)' = ([\d.e+-]+) is outside the allowed range \(0, ([\d.e+-]+)\]: at most "
    r"1/(\d+) of the fastest orbital period ([\d.e+-]+) of the state \(kappa = ([\d.e+-]+), "
    r"M0 = ([\d.e+-]+)\)"
)


@pytest.mark.parametrize(
    "path,bad,good,where,per_period",
    [
        # the ensemble's own particles, no test particles: the tail of ch2* sets the period
        (("relaxation_md", "dt"), 0.45, 0.42, "relaxation_md run 'corehalo_ch2'", 10),
        # the `run` override of the 1/N study: test particles up to kappa_max = 2
        ((*SCALING, "run", "dt"), 0.2, 0.1, "md_scaling run 'thermal_u-0.1' (bath", 10),
        # the magnetisation's sampling: the bath's fastest orbit below the Nyquist frequency
        (("md", "m_every"), 1.2, 1.1, "spectrum case 'thermal_u-0.1'", 2),
    ],
)
def test_every_block_bounds_its_time_step_by_the_fastest_orbit(path, bad, good, where, per_period):
    """The allowed range in the message is the orbital period at the stated kappa, computed
    here by quadrature (independent of the elliptic functions), over 10 (time steps) or 2 (the
    sampling of the magnetisation, Nyquist); a value just inside passes."""
    cfg = copy.deepcopy(SMOKE)
    _edit(cfg, path, bad)
    msg = _refused(cfg, where)
    field, value, hi, per, period, kappa, M0 = _RANGE.search(msg).groups()
    assert field == path[-1] and float(value) == bad and int(per) == per_period
    T = _period_by_quadrature(float(kappa), float(M0))
    assert float(period) == pytest.approx(T, rel=1e-3)
    assert float(hi) == pytest.approx(T / per_period, rel=1e-3)
    assert bad > T / per_period > good
    _edit(cfg, path, good)
    check_config(cfg)


def test_every_block_needs_enough_particles_for_a_mean_field():
    """N >= (10/M0)^2 for each size of the N-body relaxation and of the 1/N study, the field
    and the minimum named; M0 of the thermal state solved here."""
    from hmfdiff.meanfield.equilibrium import make_state

    n_min = math.ceil((10.0 / make_state(SMOKE["cases"]["corehalo_ch2"]).M0) ** 2)
    cfg = copy.deepcopy(SMOKE)
    _edit(cfg, (*CH2_SIZES[:-1], "control_sizes"), [400])  # a control needs its size kept
    _edit(cfg, CH2_SIZES, [n_min - 1, 400])
    _refused(
        cfg,
        "relaxation_md run 'corehalo_ch2': field 'n_particles' =",
        f"= {n_min - 1} must be >= {n_min}",
    )
    _edit(cfg, CH2_SIZES, [n_min, 400])
    check_config(cfg)
    n_min = math.ceil((10.0 / _thermal_M0(-0.1)) ** 2)
    _edit(cfg, (*SCALING, "sizes"), [3000, n_min - 1])
    _refused(
        cfg,
        f"md_scaling run 'thermal_u-0.1' (bath, N = {n_min - 1}): field 'sizes' = {n_min - 1} "
        f"must be >= {n_min}",
    )
    _edit(cfg, (*SCALING, "sizes"), [3000, n_min])
    check_config(cfg)


@pytest.mark.parametrize(
    "path,value,parts",
    [
        (
            # ~10 n_nodes n_max^2 = 1.5e6 resonances of ~200 B: 0.3 GB on top of 1 GB
            ("relaxation", "runs", "corehalo_ch2"),
            {"n_nodes": 600, "n_max": 16},
            ["relaxation run 'corehalo_ch2': field 'n_nodes' = 600 with n_max = 16"],
        ),
        (
            # R = 10^4 realisations of N = 200: 2e6 particles of ~64 B (+30 %) on top of 1 GB
            ("relaxation_md", "particles_per_size"),
            2_000_000,
            ["relaxation_md run 'corehalo_ch2': field 'n_particles' = 200 with particles_per"],
        ),
        (
            (*SCALING, "sizes"),
            [1000, 5_000_000],
            ["md_scaling run 'thermal_u-0.1' (bath, N = 5000000): field 'sizes' = 5000000"],
        ),
        (
            ("md", "seeds"),
            2000,
            [
                "spectrum case 'thermal_u-0.1' (figure 'fig14_spectrum'): field 'seeds' = "
                f"{SMOKE['md']['seeds_bath']} + 2000 (bath + full)"
            ],
        ),
    ],
)
def test_every_block_refuses_a_job_beyond_the_machines_memory(monkeypatch, path, value, parts):
    """On a machine of 1.15 GB the smoke config passes (every job ~1.0 GB: 1 GB of interpreter
    and libraries plus a few MB); each change below makes one job of the block larger:
    estimates of what it holds (resonances ~ 10 n_nodes n_max^2 of ~200 B, 64 B per
    ensemble particle, 48 B per MD particle, every seed's file for the spectrum)."""
    from hmfdiff.pipeline import config as config_module

    monkeypatch.setattr(config_module, "machine_memory_bytes", lambda: int(1.15e9))
    check_config(SMOKE)
    cfg = copy.deepcopy(SMOKE)
    _edit(cfg, path, value)
    _refused(cfg, *parts, "of memory, more than this machine's 1.07 GiB")


def test_relaxation_rates_needs_two_realisations_at_every_size():
    """The early-window errors are the spread between realisations: one is refused, naming
    the size and the largest N that particles_per_size allows."""
    cfg = copy.deepcopy(SMOKE)
    _edit(cfg, ("relaxation_rates", "runs", "corehalo_ch2", "n_particles"), [200, 1000])
    _refused(
        cfg,
        "relaxation_rates run 'corehalo_ch2': field 'n_particles' = 1000 leaves 1 realisation(s)",
        "need N <= particles_per_size / 2",
    )
    _edit(cfg, ("relaxation_rates", "runs", "corehalo_ch2", "n_particles"), [200, 800])
    check_config(cfg)


# ---- every figure's cases have the runs that make its inputs (issue 36) -------------------
#: per figure of the registry, a smoke case that lacks what one of its inputs is made from, and
#: the words of the refusal: MD runs (fits, windowed, spectrum), 1/N studies, kinetic
#: relaxations, N-body relaxations, early-window ensembles, a theory grid (smooth states only)
FIG_LACKS = {
    "fig04_contributions": ("cases", "twostep_ch", "no theory grid", "theory/twostep_ch.nc"),
    "fig05_dielectric": ("case", "twostep_ch", "no theory grid", "theory/twostep_ch.nc"),
    "fig06_landau_lenard_balescu": ("cases", "twostep_ch", "no theory grid", "theory/"),
    "fig08_dj2": ("cases", "thermal_M0.9", "no run under md.runs", "fits/thermal_M0.9_full.nc"),
    "fig09_md_thermal": ("cases", "thermal_M0.9", "no run under md.runs", "fits/thermal_M0.9_"),
    "fig10_md_corehalo": ("cases", "thermal_M0.9", "no run under md.runs", "fits/thermal_M0.9_"),
    "fig14_spectrum": ("cases", "thermal_M0.9", "no run under md.runs", "spectrum/thermal_M0.9"),
    "fig15_scaling": ("cases", "thermal_M0.9", "no study under md_scaling.studies", "scaling/"),
    "fig11_relaxation": ("cases", "thermal_u-0.1", "no run under relaxation.runs", "relaxation/"),
    "fig12_relaxation_md": ("cases", "thermal_u-0.1", "no run under relaxation_md.runs", "rel"),
    "fig13_relaxation_time": ("cases", "thermal_u-0.1", "no run under relaxation_md.runs", "re"),
    "fig16_relaxation_rates": ("case", "thermal_u-0.1", "no run under relaxation_rates.runs", ""),
}
#: figures whose inputs any case of the right kind can have: orbits and closed forms of any
#: state, fig07's theory of a core_halo or thermal state (the kind is checked per field)
FIG_ANY_CASE = {"fig01_orbits", "fig02_action_frequency", "fig03_poles", "fig07_closed_forms"}


def test_every_figure_of_the_registry_has_its_refusal_tested():
    from hmfdiff.analysis.figures.registry import FIGURES

    assert set(FIG_LACKS) | FIG_ANY_CASE == set(FIGURES)
    assert not set(FIG_LACKS) & FIG_ANY_CASE


def test_every_input_of_the_registry_has_a_maker_checked():
    """Each input pattern of the registry names the run it comes from in the config check (a
    new kind of input needs its entry, or every figure drawing it is refused as unknown)."""
    from hmfdiff.analysis.figures.registry import FIGURES
    from hmfdiff.pipeline.config import _input_makers, check_config, input_maker

    makers = _input_makers(check_config(SMOKE))
    for fig in FIGURES.values():
        for inp in fig.inputs:
            assert input_maker(inp.pattern) in makers, (fig.name, inp.pattern)


@pytest.mark.parametrize("fig", sorted(FIG_LACKS))
def test_figure_naming_a_case_without_its_inputs_is_refused(fig):
    """The smoke config with one figure naming a case that exists but has no run making one of
    the figure's inputs: refused in one line naming the figure, the case, the field, what it
    lacks, the input and the allowed cases (which, put in its place, pass)."""
    key, case, lacks, path = FIG_LACKS[fig]
    cfg = copy.deepcopy(SMOKE)
    good = cfg["figures"][fig][key]
    cfg["figures"][fig][key] = case if key == "case" else [*good, case]
    msg = _refused(cfg, f"figure '{fig}': case '{case}' (field '{key}') has {lacks}", path)
    allowed = msg.split("; allowed: ")[1].split(", ")
    assert case not in allowed
    for c in [good] if isinstance(good, str) else good:
        assert c in allowed
    cfg["figures"][fig][key] = allowed[0] if key == "case" else allowed
    if "theory" not in lacks:  # every smooth case has a theory grid, not every case an MD run
        check_config(cfg)


def test_early_window_figure_needs_the_full_relaxation_too():
    """Figure 16 draws both the early-window study and the full N-body relaxation (figure 13's
    rate): a case with the first and not the second is refused by its second input."""
    cfg = copy.deepcopy(SMOKE)
    cfg["relaxation"]["runs"]["thermal_u-0.1"] = {}
    cfg["relaxation_rates"]["runs"] = {"thermal_u-0.1": {"n_particles": [400]}}
    cfg["figures"]["fig16_relaxation_rates"] = {"case": "thermal_u-0.1"}
    _refused(
        cfg,
        "figure 'fig16_relaxation_rates': case 'thermal_u-0.1' (field 'case') has no run under "
        "relaxation_md.runs, so its input relaxation_comparison/thermal_u-0.1.nc cannot be made",
        "allowed: corehalo_ch2",
    )


def test_unknown_figure_is_refused_with_the_nearest_name():
    cfg = copy.deepcopy(SMOKE)
    cfg["figures"]["fig09_md_thermel"] = cfg["figures"].pop("fig09_md_thermal")
    _refused(cfg, "figures: unknown figure 'fig09_md_thermel'", "did you mean 'fig09_md_thermal'")
