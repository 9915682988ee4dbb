"""Every relation between fields of the config (`hmfdiff.pipeline.config.RELATIONS`) is refused
in one line naming the field and the allowed range, before any job.

One test per relation, generated from the table: each builds config/smoke.yaml with that
relation violated and asserts the refusal (a relation added to the table without a violation
here fails its own test).  Every field of the audited blocks' schemas is in a relation or listed
as free (`FREE_FIELDS`), so a new field cannot be added without saying how it relates to the
others; every ConfigError raised in the config module is reached from a relation's check.
"""

import ast
import copy
import inspect
from pathlib import Path

import pytest
import yaml

from hmfdiff.pipeline import config as config_module
from hmfdiff.pipeline.config import FREE_FIELDS, RELATIONS, ConfigError, check_config

ROOT = Path(__file__).resolve().parents[1]
SMOKE = yaml.safe_load((ROOT / "config" / "smoke.yaml").read_text())
SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"
#: the blocks audited: every field of their schema is in a relation or free
BLOCKS = ("md", "md_scaling", "relaxation", "relaxation_md", "relaxation_rates", "figures")
#: fields of the kinetic relaxation's settings that are being added to (or removed from) the
#: schema beside this table: named by the table, not necessarily in the schema yet (or still)
TRANSITIONAL = {"relaxation": {"early_window", "layer_eta_min", "dlog_omega", "min_per_decade"}}
#: memory of the machine in the memory relations' tests: the smoke config's jobs fit in it
SMALL_MACHINE = int(1.15e9)
DELETE = object()

RUN = ("md", "runs", "thermal_u-0.1")
STUDY = ("md_scaling", "studies", "thermal_u-0.1")
CH2_STUDY = ("md_scaling", "studies", "corehalo_ch2")
RMD = ("relaxation_md",)
RMD_CH2 = ("relaxation_md", "runs", "corehalo_ch2")
RR = ("relaxation_rates",)
RR_CH2 = ("relaxation_rates", "runs", "corehalo_ch2")
CASE_LIST = "cases: thermal_u-0.1, thermal_M0.9, corehalo_ch2, twostep_ch"

# relation name -> (edits (path, value; DELETE removes), the field the refusal names, the
# other parts it holds: the allowed range or set, and where); options: 'memory' (the machine's
# memory in bytes), 'loosen' (schema $defs/<def>/properties/<field> made a bare number, so that
# the check of the config module is reached, not the schema's range)
V = {
    # ---- cases
    "cases: case names differ by more than upper/lower case": (
        [(("cases", "THERMAL_M0.9"), {"kind": "thermal", "M0": 0.9})],
        "THERMAL_M0.9",
        ["case 'THERMAL_M0.9'", "differs from case 'thermal_M0.9' only by upper/lower case"],
    ),
    "cases: core below halo: mu1 < mu2": (
        [(("cases", "corehalo_ch2", "mu1"), 0.3)],
        "mu1",
        ["case 'corehalo_ch2'", "must be below mu2 = 0.19"],
    ),
    "cases: a core-halo state is not empty: eta1 + eta2 > 0": (
        [(("cases", "corehalo_ch2", "eta1"), 0.0), (("cases", "corehalo_ch2", "eta2"), 0.0)],
        "eta1",
        ["case 'corehalo_ch2'", "'eta2' = 0.0 + 0.0 must be > 0"],
    ),
    "cases: a self-consistent M0 exists": (
        [
            (
                ("cases", "corehalo_ch2"),
                {
                    "kind": "core_halo",
                    "eta1": 0.05,
                    "eta2": 0.01,
                    "mu1": 1.0,
                    "mu2": 2.0,
                    "beta1": 0.5,
                    "beta2": 0.5,
                },
            ),
        ],
        "corehalo_ch2",
        ["no magnetised self-consistent solution M0 in (0.01, 0.99)"],
    ),  # fmt: skip
    # ---- md
    "md: names a case under `cases`": (
        [(("md", "runs", "nonexistent"), {"n_particles": 5000})],
        "nonexistent",
        ["md run 'nonexistent'", "which is not in 'cases'", CASE_LIST],
    ),
    "md: its case has a smooth f (not two_step)": (
        [(("md", "runs", "twostep_ch"), {"n_particles": 5000})],
        "twostep_ch",
        ["md run 'twostep_ch'", "no smooth f", "use a thermal or core_halo state"],
    ),
    "md: dt <= 1/10 of the fastest orbital period (test particles up to kappa_max)": (
        [(("md", "dt"), 0.2)],
        "dt",
        ["md run 'thermal_u-0.1'", "= 0.2 is outside the allowed range (0, 0.1975]"],
    ),
    "md: n_particles >= (10/M0)^2": (
        [((*RUN, "n_particles"), 150)],
        "n_particles",
        ["md run 'thermal_u-0.1'", "= 150 must be >= 189"],
    ),
    "md: sample_every a whole multiple of dt": (
        [((*RUN, "sample_every"), 0.25)],
        "sample_every",
        ["md run 'thermal_u-0.1'", "= 0.25 must be a whole multiple of dt = 0.1"],
    ),
    "md: t_equilibrate a whole multiple of dt": (
        [((*RUN, "t_equilibrate"), 0.15)],
        "t_equilibrate",
        ["= 0.15 must be a whole multiple of dt = 0.1"],
    ),
    "md: m_every a whole multiple of dt": (
        [((*RUN, "m_every"), 0.25)],
        "m_every",
        ["= 0.25 must be a whole multiple of dt = 0.1"],
    ),
    "md: max_lag a whole multiple of sample_every": (
        [((*RUN, "max_lag"), 29.5)],
        "max_lag",
        ["= 29.5 must be a whole multiple of sample_every = 1.0"],
    ),
    "md: origin_every a whole multiple of sample_every": (
        [((*RUN, "origin_every"), 5.5)],
        "origin_every",
        ["= 5.5 must be a whole multiple of sample_every = 1.0"],
    ),
    "md: t_max a whole multiple of sample_every": (
        [((*RUN, "t_max"), 60.5)],
        "t_max",
        ["= 60.5 must be a whole multiple of sample_every = 1.0"],
    ),
    "md: max_lag <= t_max": (
        [((*RUN, "max_lag"), 100.0)],
        "max_lag",
        ["= 100.0 exceeds t_max = 60.0: allowed (0, t_max = 60.0]"],
    ),
    "md: 0 <= fit_window[0] < fit_window[1] <= max_lag": (
        [((*RUN, "fit_window"), [10.0, 40.0])],
        "fit_window",
        ["must satisfy 0 <= t_min < t_max <= max_lag = 30.0"],
    ),
    "md: n_blocks <= the number of time origins (t_max - max_lag) / origin_every + 1": (
        [((*RUN, "n_blocks"), 8)],
        "n_blocks",
        ["= 8 must be an integer in [1, number of origins = 7]"],
    ),
    "md: n_track in [1, n_particles]": (
        [((*RUN, "n_track"), 6000)],
        "n_track",
        ["must be null (all) or an integer in [1, n_particles = 5000]"],
    ),
    "md: 0 <= jbar_range[0] < jbar_range[1]": (
        [((*RUN, "jbar_range"), [0.5, 0.2])],
        "jbar_range",
        ["with 0 <= Jbar_min < Jbar_max"],
    ),
    "md: a run's memory estimate within this machine's": (
        [((*RUN, "n_particles"), 3_000_000)],
        "n_particles",
        ["md run 'thermal_u-0.1' (bath)", "more than this machine's 1.07 GiB"],
        {"memory": SMALL_MACHINE},
    ),
    "md: m_every <= t_max": (
        [((*RUN, "m_every"), 70.0)],
        "m_every",
        ["md run 'thermal_u-0.1' (bath)", "= 70.0 is outside the allowed range (0, t_max = 60.0]"],
    ),
    "md: jbar_range only with test_sampling 'uniform'": (
        [((*RUN, "test_sampling"), "f"), ((*RUN, "jbar_range"), [0.0, 0.5])],
        "jbar_range",
        ["md run 'thermal_u-0.1' (bath)", "is allowed only with test_sampling 'uniform'"],
    ),
    "md: jbar_range within [0, J-bar(kappa_max)]": (
        [((*RUN, "jbar_range"), [0.0, 5.0])],
        "jbar_range",
        ["md run 'thermal_u-0.1' (bath)", "must lie within [0, 3.18", "J-bar(kappa_max = 2.0)"],
    ),
    "md: min_particles <= seeds x tracked particles": (
        [((*RUN, "min_particles"), 20001)],
        "min_particles",
        [
            "md run 'thermal_u-0.1' (bath)",
            "= 20001 is outside the allowed range [0, 20000]: seeds x tracked particles = 10 x "
            "2000",
        ],
    ),
    "md: kappa_max <= theory.kappa_max": (
        [(("theory", "kappa_max"), 1.8)],
        "kappa_max",
        [
            "md run 'thermal_u-0.1' (bath)",
            "= 2.0 is outside the allowed range (0, theory.kappa_max = 1.8]",
        ],
    ),  # fmt: skip
    # ---- md_scaling
    "md_scaling: names a case under `cases`": (
        [(("md_scaling", "studies", "nonexistent"), {"sizes": [1000], "seeds": 2})],
        "nonexistent",
        ["md_scaling study 'nonexistent'", "which is not in 'cases'"],
    ),
    "md_scaling: its case has a smooth f (not two_step)": (
        [(("md_scaling", "studies", "twostep_ch"), {"sizes": [1000], "seeds": 2})],
        "twostep_ch",
        ["md_scaling study 'twostep_ch'", "no smooth f"],
    ),
    "md_scaling: seeds an integer >= 2 or a list parallel to sizes": (
        [((*STUDY, "seeds"), [3])],
        "seeds",
        ["md_scaling study 'thermal_u-0.1'", "or a list of one such per size (2 sizes)"],
    ),
    "md_scaling: run sets no field that sizes and seeds set": (
        [((*STUDY, "run", "seeds"), 3)],
        "seeds",
        ["md_scaling study 'thermal_u-0.1'", "are set by the study's 'sizes' and 'seeds'"],
    ),
    "md_scaling: run: fit_window within (0, max_lag]": (
        [((*STUDY, "run", "fit_window"), [5.0, 25.0])],
        "fit_window",
        ["thermal_u-0.1 (md_scaling)", "<= max_lag = 20.0"],
    ),
    "md_scaling: run: max_lag <= t_max": (
        [((*STUDY, "run", "max_lag"), 50.0)],
        "max_lag",
        ["thermal_u-0.1 (md_scaling)", "allowed (0, t_max = 40.0]"],
    ),
    "md_scaling: run: dt <= 1/10 of the fastest orbital period": (
        [((*STUDY, "run", "dt"), 0.2)],
        "dt",
        ["md_scaling run 'thermal_u-0.1' (bath, N = 1000)", "outside the allowed range (0, "],
    ),
    "md_scaling: every size >= (10/M0)^2": (
        [((*STUDY, "sizes"), [3000, 150])],
        "sizes",
        ["md_scaling run 'thermal_u-0.1' (bath, N = 150)", "= 150 must be >= 189"],
    ),
    "md_scaling: every size's memory estimate within this machine's": (
        [((*STUDY, "sizes"), [1000, 5_000_000])],
        "sizes",
        ["md_scaling run 'thermal_u-0.1' (bath, N = 5000000)", "more than this machine's"],
        {"memory": SMALL_MACHINE},
    ),
    "md_scaling: run: the md relations of this module (m_every <= t_max, ...) at every size": (
        [((*STUDY, "run", "m_every"), 50.0)],
        "m_every",
        ["md_scaling run 'thermal_u-0.1' (bath, N = 1000)", "(0, t_max = 40.0]"],
    ),
    "md_scaling: kappa0 within (0, kappa_max]": (
        [((*CH2_STUDY, "kappa0"), [0.4, 5.0])],
        "kappa0",
        ["md_scaling study 'corehalo_ch2'", "outside the allowed range (0, kappa_max = 2.0]"],
    ),
    "md_scaling: each kappa0 picks a bin of its own": (
        [((*CH2_STUDY, "kappa0"), [0.4, 0.45])],
        "kappa0",
        ["md_scaling study 'corehalo_ch2'", "0.4 and 0.45 pick the same bin", "one kappa0 per bin"],
    ),
    # ---- relaxation
    "relaxation: names a case under `cases`": (
        [(("relaxation", "runs", "nonexistent"), {})],
        "nonexistent",
        ["relaxation run 'nonexistent'", "which is not in 'cases'", CASE_LIST],
    ),
    "relaxation: its case has a smooth f (not two_step)": (
        [(("relaxation", "runs", "twostep_ch"), {})],
        "twostep_ch",
        ["relaxation run 'twostep_ch'", "no smooth f"],
    ),
    "relaxation: an evolution's memory estimate within this machine's": (
        [(("relaxation", "runs", "corehalo_ch2"), {"n_nodes": 600, "n_max": 16})],
        "n_nodes",
        ["relaxation run 'corehalo_ch2'", "with n_max = 16", "more than this machine's"],
        {"memory": SMALL_MACHINE},
    ),
    "relaxation: flux_times within [0, tau_max]": (
        [(("relaxation", "flux_times"), [0.0, 10.0, 30.0])],
        "flux_times",
        ["relaxation: ", "must lie within [0, tau_max = 20.0]: 30.0 is beyond the run"],
    ),
    "relaxation: early_window > 0": (
        [(("relaxation", "early_window"), 0.0)],
        "early_window",
        ["relaxation: ", "= 0.0 is outside the allowed range (0, inf)"],
        {"loosen": ("relaxation_settings", "early_window")},
    ),
    "relaxation: feature_share + separatrix_share <= 1": (
        [(("relaxation", "feature_share"), 0.7)],
        "feature_share",
        ["relaxation: ", "'separatrix_share' = 0.7 + 0.4 = 1.1 must be in [0, 1]"],
    ),
    # ---- relaxation_md
    "relaxation_md: names a case under `cases`": (
        [((*RMD, "runs", "nonexistent"), {"n_particles": [400]})],
        "nonexistent",
        ["relaxation_md run 'nonexistent'", "which is not in 'cases'"],
    ),
    "relaxation_md: its case has a smooth f (not two_step)": (
        [((*RMD, "runs", "twostep_ch"), {"n_particles": [400]})],
        "twostep_ch",
        ["relaxation_md run 'twostep_ch'", "no smooth f"],
    ),
    "relaxation_md: its case is under relaxation.runs": (
        [((*RMD, "runs", "thermal_u-0.1"), {"n_particles": [400]})],
        "thermal_u-0.1",
        ["relaxation_md run 'thermal_u-0.1'", "not under relaxation.runs", "runs: corehalo_ch2"],
    ),
    "relaxation_md: dt <= 1/10 of the fastest orbital period": (
        [((*RMD, "dt"), 0.45)],
        "dt",
        ["relaxation_md run 'corehalo_ch2'", "= 0.45 is outside the allowed range (0, "],
    ),
    "relaxation_md: every N >= (10/M0)^2": (
        [((*RMD_CH2, "n_particles"), [150, 400]), ((*RMD_CH2, "control_sizes"), [400])],
        "n_particles",
        ["relaxation_md run 'corehalo_ch2'", "= 150 must be >= 157"],
    ),
    "relaxation_md: every N <= particles_per_size": (
        [((*RMD_CH2, "n_particles"), [200, 8000])],
        "n_particles",
        [
            "relaxation_md run 'corehalo_ch2'",
            "= 8000 leaves 0 realisation(s)",
            "need N <= particles_per_size / 1",
        ],
    ),  # fmt: skip
    "relaxation_md: every ensemble's memory estimate within this machine's": (
        [((*RMD, "particles_per_size"), 2_000_000)],
        "n_particles",
        ["relaxation_md run 'corehalo_ch2'", "with particles_per_size = 2000000", "more than"],
        {"memory": SMALL_MACHINE},
    ),
    "relaxation_md: control_sizes among n_particles": (
        [((*RMD_CH2, "control_sizes"), [800])],
        "control_sizes",
        ["relaxation_md run 'corehalo_ch2'", "= [800] not among n_particles = [200, 400]"],
    ),
    "relaxation_md: tau_first < tau_max": (
        [((*RMD, "tau_first"), 0.5)],
        "tau_first",
        ["relaxation_md: ", "= 0.5 is outside the allowed range (0, tau_max = 0.5)"],
    ),
    "relaxation_md: tau_first x N >= dt at every N": (
        [((*RMD, "tau_first"), 0.0001)],
        "tau_first",
        ["relaxation_md: ", "outside the allowed range [dt / N = 0.1 / 200 = 0.0005, tau_max)"],
    ),
    "relaxation_md: n_times distinct measurement times at every N": (
        [((*RMD, "n_times"), 200)],
        "n_times",
        ["relaxation_md: ", "= 200 is outside the allowed range [2, ", "at N = 200"],
    ),
    "relaxation_md: tau_max <= the case's relaxation tau_max": (
        [((*RMD, "tau_max"), 25.0)],
        "tau_max",
        ["relaxation_md run 'corehalo_ch2'", "= 25.0 is outside the allowed range (0, 20.0]"],
    ),
    "relaxation_md: kappa_max <= the case's relaxation kappa_max": (
        [((*RMD, "kappa_max"), 2.6)],
        "kappa_max",
        ["relaxation_md run 'corehalo_ch2'", "= 2.6 is outside the allowed range (1, 2.5]"],
    ),
    # ---- relaxation_rates
    "relaxation_rates: the relaxation_md section exists": (
        [(RMD, DELETE)],
        "relaxation_md",
        ["relaxation_rates: needs the section", "allowed: relaxation_md with runs: {}"],
    ),
    "relaxation_rates: names a case under `cases`": (
        [((*RR, "runs", "nonexistent"), {"n_particles": [400]})],
        "nonexistent",
        ["relaxation_rates run 'nonexistent'", "which is not in 'cases'"],
    ),
    "relaxation_rates: its case has a smooth f (not two_step)": (
        [((*RR, "runs", "twostep_ch"), {"n_particles": [400]})],
        "twostep_ch",
        ["relaxation_rates run 'twostep_ch'", "no smooth f"],
    ),
    "relaxation_rates: its case is under relaxation.runs": (
        [((*RR, "runs", "thermal_M0.9"), {"n_particles": [400]})],
        "thermal_M0.9",
        ["relaxation_rates run 'thermal_M0.9'", "not under relaxation.runs"],
    ),
    "relaxation_rates: relaxation_md.dt <= 1/10 of the fastest orbital period": (
        [
            ((*RMD, "dt"), 0.3),
            (("relaxation", "runs", "thermal_u-0.1"), {}),
            ((*RR, "runs"), {"thermal_u-0.1": {"n_particles": [400]}}),
        ],
        "relaxation_md.dt",
        ["relaxation_rates run 'thermal_u-0.1'", "= 0.3 is outside the allowed range (0, 0.2"],
    ),
    "relaxation_rates: every N >= (10/M0)^2": (
        [((*RR_CH2, "n_particles"), [150])],
        "n_particles",
        ["relaxation_rates run 'corehalo_ch2'", "= 150 must be >= 157"],
    ),
    "relaxation_rates: every N <= particles_per_size / 2": (
        [((*RR_CH2, "n_particles"), [200, 1000])],
        "n_particles",
        [
            "relaxation_rates run 'corehalo_ch2'",
            "= 1000 leaves 1 realisation(s)",
            "need N <= particles_per_size / 2",
        ],
    ),  # fmt: skip
    "relaxation_rates: every ensemble's memory estimate within this machine's": (
        [((*RR, "particles_per_size"), 2_000_000)],
        "n_particles",
        ["relaxation_rates run 'corehalo_ch2'", "with particles_per_size = 2000000", "more than"],
        {"memory": SMALL_MACHINE},
    ),
    "relaxation_rates: tau_first < tau_max": (
        [((*RR, "tau_first"), 0.6)],
        "tau_first",
        ["relaxation_rates: ", "= 0.6 is outside the allowed range (0, tau_max = 0.5)"],
    ),
    "relaxation_rates: tau_first x N >= relaxation_md.dt at every N": (
        [((*RR, "tau_first"), 0.0001)],
        "tau_first",
        ["relaxation_rates: ", "[relaxation_md.dt / N = 0.1 / 400 = 0.00025, tau_max)"],
    ),
    "relaxation_rates: n_times distinct measurement times at every N": (
        [((*RR, "n_times"), 300)],
        "n_times",
        ["relaxation_rates: ", "= 300 is outside the allowed range [3, ", "at N = 400"],
    ),
    "relaxation_rates: tau_max <= the case's relaxation tau_max": (
        [((*RR, "tau_max"), 25.0)],
        "tau_max",
        ["relaxation_rates run 'corehalo_ch2'", "= 25.0 is outside the allowed range (0, 20.0]"],
    ),
    "relaxation_rates: relaxation_md.kappa_max <= the case's relaxation kappa_max": (
        [
            (("relaxation", "runs", "thermal_u-0.1"), {"kappa_max": 2.0}),
            ((*RR, "runs"), {"thermal_u-0.1": {"n_particles": [400]}}),
        ],
        "relaxation_md.kappa_max",
        ["relaxation_rates run 'thermal_u-0.1'", "= 2.5 is outside the allowed range (1, 2.0]"],
    ),
    # ---- figures
    "figures: a figure of the registry": (
        [(("figures", "fig09_md_thermel"), {"cases": ["thermal_u-0.1"]})],
        "fig09_md_thermel",
        ["figures: unknown figure", "did you mean 'fig09_md_thermal'?", "figures: fig01_orbits"],
    ),
    "figures: every case named exists": (
        [(("figures", "fig01_orbits", "case"), "nonexistent")],
        "case",
        ["figure 'fig01_orbits': names case 'nonexistent', which is not in 'cases'", CASE_LIST],
    ),
    "figures: fields core_halo, two_step, thermal name a case of that kind": (
        [(("figures", "fig07_closed_forms", "two_step"), "thermal_M0.9")],
        "two_step",
        ["figure 'fig07_closed_forms'", "names case 'thermal_M0.9' of kind 'thermal', not"],
    ),
    "figures: every input's fields given": (
        [(("figures", "fig07_closed_forms", "two_step"), DELETE)],
        "two_step",
        ["figures.fig07_closed_forms: no case for its 'closed_two_step' inputs; give"],
    ),
    "figures: every case has the run that makes each input": (
        [(("figures", "fig08_dj2", "cases"), ["thermal_u-0.1", "thermal_M0.9"])],
        "cases",
        [
            "figure 'fig08_dj2': case 'thermal_M0.9'",
            "has no run under md.runs",
            "allowed: corehalo_ch2, thermal_u-0.1",
        ],
    ),  # fmt: skip
    # ---- spectrum
    "spectrum: the case has runs under md.runs": (
        [(("figures", "fig14_spectrum", "cases"), ["thermal_M0.9"])],
        "cases",
        ["figure 'fig14_spectrum': case 'thermal_M0.9'", "spectrum/thermal_M0.9.nc cannot be made"],
    ),
    "spectrum: m_every <= 1/2 of the fastest orbital period (Nyquist)": (
        [(("md", "m_every"), 1.2)],
        "m_every",
        [
            "spectrum case 'thermal_u-0.1' (figure 'fig14_spectrum')",
            "(0, 1.172]",
            "the Nyquist frequency",
        ],
    ),  # fmt: skip
    "spectrum: m_every <= max_lag / 2": (
        [((*RUN, "max_lag"), 2.0), ((*RUN, "fit_window"), [1.0, 2.0]), ((*RUN, "m_every"), 1.1)],
        "m_every",
        [
            "spectrum case 'thermal_u-0.1'",
            "= 1.1 is outside the allowed range (0, max_lag / 2 = 1]",
        ],
    ),
    "spectrum: the job's memory estimate within this machine's": (
        [(("md", "seeds"), 2000)],
        "seeds",
        [
            "spectrum case 'thermal_u-0.1' (figure 'fig14_spectrum')",
            "= 10 + 2000 (bath + full)",
            "more than this machine's",
        ],
        {"memory": SMALL_MACHINE},
    ),  # fmt: skip
}


def violated(name):
    """config/smoke.yaml with the relation `name` violated, and the options of its test."""
    edits, _, _, *opts = V[name]
    cfg = copy.deepcopy(SMOKE)
    for path, value in edits:
        d = cfg
        for k in path[:-1]:
            d = d[k]
        if value is DELETE:
            del d[path[-1]]
        else:
            d[path[-1]] = value
    return cfg, (opts[0] if opts else {})


def loosened_schema(tmp_path, loosen):
    """The schema with $defs/<def>/properties/<field> a bare number (no range)."""
    schema = yaml.safe_load(SCHEMA.read_text())
    definition, field = loosen
    schema["$defs"][definition]["properties"][field] = {"type": "number"}
    path = tmp_path / "schema.yaml"
    path.write_text(yaml.safe_dump(schema))
    return path


def refusal(name, monkeypatch, tmp_path):
    """The one line refusing the smoke config with relation `name` violated."""
    cfg, opts = violated(name)
    if "memory" in opts:
        monkeypatch.setattr(config_module, "machine_memory_bytes", lambda: opts["memory"])
    schema = loosened_schema(tmp_path, opts["loosen"]) if "loosen" in opts else None
    with pytest.raises(ConfigError) as err:
        check_config(cfg, schema)
    return str(err.value)


@pytest.mark.parametrize("rel", RELATIONS, ids=[r.name for r in RELATIONS])
def test_every_relation_is_refused_in_one_line_naming_the_field_and_the_allowed_range(
    rel, monkeypatch, tmp_path
):
    assert rel.name in V, f"no violation written for the relation {rel.name!r}"
    msg = refusal(rel.name, monkeypatch, tmp_path)
    _, field, parts, *_ = V[rel.name]
    assert "\n" not in msg and "Traceback" not in msg, msg
    assert f"'{field}'" in msg, (field, msg)
    for part in parts:
        assert part in msg, (part, msg)


def test_the_smoke_config_passes_on_the_small_machine_and_with_the_loosened_schema(
    monkeypatch, tmp_path
):
    """What the violations start from is accepted under each test's options."""
    monkeypatch.setattr(config_module, "machine_memory_bytes", lambda: SMALL_MACHINE)
    check_config(SMOKE)
    check_config(SMOKE, loosened_schema(tmp_path, ("relaxation_settings", "early_window")))


def test_every_violation_belongs_to_a_relation_and_names_are_unique():
    names = [r.name for r in RELATIONS]
    assert len(names) == len(set(names))
    assert set(V) == set(names)


# ---- every field of every audited block: in a relation, or free -------------------------------
def _schema():
    return yaml.safe_load(SCHEMA.read_text())


def _fields(node, root, skip=(), seen=None):
    """Every property name in the subtree of `node` (through $ref, allOf, additionalProperties,
    items), not entering the $defs named in `skip`."""
    seen = set() if seen is None else seen
    out = set()
    if not isinstance(node, dict) or id(node) in seen:
        return out
    seen.add(id(node))
    if "$ref" in node:
        name = node["$ref"].split("/")[-1]
        if name not in skip:
            out |= _fields(root["$defs"][name], root, skip, seen)
    for key, sub in node.get("properties", {}).items():
        out.add(key)
        out |= _fields(sub, root, skip, seen)
    for sub in node.get("allOf", []) + node.get("anyOf", []) + node.get("oneOf", []):
        out |= _fields(sub, root, skip, seen)
    for key in ("additionalProperties", "items", "then", "else"):
        out |= _fields(node.get(key), root, skip, seen)
    return out


def block_fields(block):
    """The fields of a block's schema; md_scaling's `run` takes md's settings, whose relations
    are md's."""
    root = _schema()
    skip = ("md_settings",) if block == "md_scaling" else ()
    return _fields(root["properties"][block], root, skip)


def _mentioned(block):
    """Fields of `block` named by a relation (its own, or dotted by another block's) or free."""
    out = set(FREE_FIELDS.get(block, {}))
    for rel in RELATIONS:
        for f in rel.fields:
            head, _, tail = f.rpartition(".")
            if rel.block == block and not head:
                out.add(f)
            elif head.split(".")[0] == block:
                out.add(tail)
    return out


@pytest.mark.parametrize("block", BLOCKS)
def test_every_field_of_a_block_is_in_a_relation_or_free(block):
    missing = sorted(block_fields(block) - _mentioned(block))
    assert not missing, f"{block}: fields in no relation and not free: {missing}"


def test_spectrum_has_no_section_of_its_own():
    """The spectrum's settings are md's (m_every, seeds, max_lag) and the figures'; a spectrum
    section in the schema would need its fields audited here."""
    assert "spectrum" not in _schema()["properties"]
    assert any(r.block == "spectrum" for r in RELATIONS)


def test_every_field_a_relation_names_exists():
    """No relation or free entry names a field that is not in the schema (a typo would cover
    nothing), but the relaxation settings being added beside this table."""
    top = set(_schema()["properties"])
    for rel in RELATIONS:
        for f in rel.fields:
            head, _, tail = f.rpartition(".")
            block = head.split(".")[0] if head else rel.block
            known = block_fields(block) if block in top else set()
            if block == "md_scaling":
                known |= block_fields("md")
            ok = tail in known | TRANSITIONAL.get(block, set()) or (not head and tail in top)
            assert ok, (rel.name, f)
    for block, free in FREE_FIELDS.items():
        stale = set(free) - block_fields(block) - TRANSITIONAL.get(block, set())
        stale -= {"separatrix_band"}  # the relaxation settings' former name, leaving the schema
        assert not stale, (block, stale)


# ---- the table drives the checks ------------------------------------------------------------
def test_check_physics_runs_every_check_of_the_table_once_in_order(monkeypatch):
    from hmfdiff.pipeline.config import prepare_config, relation_checks

    called = []
    wrapped = {
        c: (lambda ck, c=c: called.append(c) or c(ck))
        for c in dict.fromkeys(r.check for r in RELATIONS)
    }
    rows = tuple(r.__class__(r.block, r.fields, r.rule, wrapped[r.check]) for r in RELATIONS)
    monkeypatch.setattr(config_module, "RELATIONS", rows)
    prepare_config(copy.deepcopy(SMOKE))
    original = list(dict.fromkeys(r.check for r in RELATIONS))
    assert called == original and len(relation_checks()) == len(original)


def test_every_refusal_of_the_config_module_is_reached_from_a_relation():
    """A function of the config module that raises ConfigError is a relation's check, or is
    called from one (by name, or as a cached property of the shared `_Checked`): a check added
    outside the table would not run."""
    tree = ast.parse(inspect.getsource(config_module))
    funcs = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            funcs[node.name] = node

    def calls(fn):
        names = set()
        for n in ast.walk(fn):
            if isinstance(n, ast.Call) and isinstance(n.func, ast.Name):
                names.add(n.func.id)
            elif isinstance(n, ast.Attribute):
                names.add(n.attr)  # ck.states, ck.md_runs: the cached properties
        return names & set(funcs)

    reached, todo = set(), [r.check.__name__ for r in RELATIONS]
    while todo:
        name = todo.pop()
        if name not in reached:
            reached.add(name)
            todo.extend(calls(funcs[name]))
    raising = {
        name
        for name, fn in funcs.items()
        if any(
            isinstance(n, ast.Raise)
            and isinstance(n.exc, ast.Call)
            and getattr(n.exc.func, "id", None) == "ConfigError"
            for n in ast.walk(fn)
        )
    }
    entry = {"check_config_files", "main"}  # the files themselves, before the schema
    assert raising - entry <= reached, sorted(raising - entry - reached)


# ---- the semantics of particular relations ------------------------------------------------------
def test_a_run_that_shortens_tau_max_keeps_the_flux_times_within_it():
    """The section's flux times beyond a run's own shorter tau_max are dropped for that run (the
    paper's warm core runs to tau = 1 with the section's [0, 1, 10, 100]); flux times written
    beside a tau_max they exceed are refused, in the section or in the run."""
    cfg = copy.deepcopy(SMOKE)
    cfg["relaxation"]["runs"]["corehalo_ch2"] = {"tau_max": 5.0}
    check_config(cfg)
    cfg["relaxation"]["runs"]["corehalo_ch2"] = {"tau_max": 5.0, "flux_times": [0.0, 10.0]}
    with pytest.raises(ConfigError, match=r"^relaxation run 'corehalo_ch2': field 'flux_times'"):
        check_config(cfg)
    cfg["relaxation"]["runs"]["corehalo_ch2"] = {"flux_times": [0.0, 20.0]}
    check_config(cfg)  # the end of the run is within it


def test_the_ensembles_schedule_check_is_the_jobs_schedule():
    """n_times is refused exactly when measurement_times (what the job runs) gives fewer
    distinct times, and the largest allowed n_times stated passes."""
    import re

    from hmfdiff.dynamics.ensemble import measurement_times

    cfg = copy.deepcopy(SMOKE)
    cfg["relaxation_md"]["n_times"] = 200
    with pytest.raises(ConfigError) as err:
        check_config(cfg)
    most = int(re.search(r"allowed range \[2, (\d+)\]", str(err.value)).group(1))
    assert len(measurement_times(0.5 * 200, most, 0.1, t_first=0.01 * 200)) == most
    assert len(measurement_times(0.5 * 200, most + 1, 0.1, t_first=0.01 * 200)) < most + 1
    cfg["relaxation_md"]["n_times"] = most
    check_config(cfg)


def test_early_window_is_read_with_its_default_where_the_settings_have_none():
    """Until the kinetic relaxation's settings have early_window, its check reads 0.5 and the
    smoke and paper configs pass; given, a positive value passes."""
    from hmfdiff.pipeline.config import EARLY_WINDOW_DEFAULT

    assert EARLY_WINDOW_DEFAULT > 0
    check_config(yaml.safe_load((ROOT / "config" / "config.yaml").read_text()))


def test_relaxation_rates_without_relaxation_md_was_a_traceback():
    """It raised KeyError('dt') while checking; now one line, before any other check of the
    block."""
    cfg, _ = violated("relaxation_rates: the relaxation_md section exists")
    for fig in ("fig12_relaxation_md", "fig13_relaxation_time", "fig16_relaxation_rates"):
        del cfg["figures"][fig]
    with pytest.raises(ConfigError, match=r"^relaxation_rates: needs the section 'relaxation_md'"):
        check_config(cfg)
