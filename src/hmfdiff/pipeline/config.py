"""The pipeline configuration, checked once before any job: files, schema, then physics.

`check_config_files(files)` then `prepare_config(config, schema)` run the whole chain, in place;
each failure is a one-line ConfigError naming the case or section, the field, the value and what
is allowed:

1. the config files themselves (`schema.load_yaml_file`): malformed YAML and duplicate keys
   (two cases with the same name) are refused, naming the file and line;
2. the JSON schema (workflow/schemas/config.schema.yaml, via `schema.apply_schema`): numbers
   written as strings coerced, types, ranges, required and unknown fields, thermal M0 xor u;
   then the schema's defaults are filled in;
3. the relations across fields and blocks, in this module (`check_physics`), listed as data in
   `RELATIONS` (block, fields, rule, the check that refuses a violation) and run from it, each
   check once in the table's order: case names that collide on a case-insensitive file system,
   mu1 < mu2 of a core-halo state, a self-consistent M0 for every state; per MD run (md.runs,
   and every size of md_scaling) a smooth case, dt against the fastest orbital period of the
   state, N against the noise of the magnetisation, the record's own relations
   (`hmfdiff.dynamics.settings.MDRun`: whole multiples, lags within the run, the fit window
   within the lags, blocks within the origins), the magnetisation stored within the run, test
   particles within the bins, min_particles reachable, bins within the theory grid, memory;
   the 1/N studies' seeds, sizes and kappa0 (a bin each); the kinetic relaxation's flux times
   within its run, early_window > 0, node shares at most 1, memory; the N-body ensembles
   (relaxation_md, relaxation_rates) of cases with a kinetic evolution that covers their
   window and bins, their schedule (tau_first < tau_max, one step at least, n_times distinct
   times at every N), realisations and memory; figures of the registry naming existing cases
   of the right kind that have the runs making each input (`_check_figures`); the spectrum of
   every case a figure draws it for (m_every below half the fastest orbital period and half
   max_lag, memory).  Fields that relate to no other are listed in `FREE_FIELDS`; a test
   holds every field of the audited blocks' schemas in one or the other, and builds one
   violation per relation (tests/test_config_relations.py).

`python -m hmfdiff.pipeline.config FILE...` checks config files outside Snakemake.
"""

from __future__ import annotations

import copy
import dataclasses
import difflib
import functools
import math
import os
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..dynamics.runs import md_runs, md_scaling_runs, scaling_kappa0
from ..errors import ConfigError
from .schema import apply_schema, load_schema, load_yaml_file

__all__ = [
    "ConfigError",
    "SCHEMA_FILE",
    "check_config_files",
    "prepare_config",
    "check_config",
    "check_physics",
    "machine_memory_bytes",
    "fastest_orbital_period",
    "check_smooth_case",
    "check_time_step",
    "check_particle_number",
    "check_memory",
    "check_run_physics",
    "spectrum_cases",
    "Relation",
    "RELATIONS",
    "FREE_FIELDS",
    "relation_checks",
]

SCHEMA_FILE = Path(__file__).resolve().parents[3] / "workflow" / "schemas" / "config.schema.yaml"
#: dt may be at most this fraction of the fastest orbital period of the state.
STEPS_PER_FASTEST_PERIOD = 10
#: the finite-N noise of the magnetisation, 1/sqrt(N), must be at most M0 / this.
M0_OVER_NOISE = 10.0
#: orbits holding less than this fraction of the particles do not set the fastest period.
TAIL_FRACTION = 1e-6


def check_config_files(files):
    """Read each config file as written, refusing malformed YAML and a key given twice in one
    mapping (two cases of the same name), with a ConfigError naming the file and line."""
    for f in files:
        if not isinstance(load_yaml_file(f), dict):
            raise ConfigError(f"{f}: the top level must be a mapping of sections")


def prepare_config(config, schema=None):
    """Apply the schema (coercion, validation, defaults) and the physics checks to `config` in
    place; ConfigError with one line on the first problem."""
    apply_schema(config, load_schema(schema or SCHEMA_FILE))
    check_physics(config)
    return config


def check_config(config, schema=None):
    """Check a configuration dictionary; returns a checked copy with the defaults filled in."""
    return prepare_config(copy.deepcopy(config), schema)


# ---- what the checks of one config share --------------------------------------------------
class _Checked:
    """One config under check: the config, and what several checks need, each computed once on
    first use: every case's state (its M0 solved), the MD records of md.runs (`md_runs`, whose
    construction refuses what `MDRun` refuses) and of the 1/N studies (`md_scaling_runs`)."""

    def __init__(self, config):
        self.config = config

    @functools.cached_property
    def states(self):
        return _states(self.config)

    @functools.cached_property
    def md_runs(self):
        return md_runs(self.config)

    @functools.cached_property
    def scaling_runs(self):
        return md_scaling_runs(self.config)


# ---- cases ------------------------------------------------------------------------------
def _states(config):
    """Each case's equilibrium state (its M0 solved now, so that a state with no
    self-consistent solution is refused before any job)."""
    from ..meanfield.equilibrium import EquilibriumError, make_state

    seen = {}
    for name in config["cases"]:
        other = seen.setdefault(name.lower(), name)
        if other != name:
            raise ConfigError(
                f"case '{name}': its name differs from case '{other}' only by upper/lower "
                "case; their files would collide on a case-insensitive file system"
            )
    states = {}
    for name, spec in config["cases"].items():
        if spec["kind"] in ("core_halo", "two_step") and not spec["mu1"] < spec["mu2"]:
            raise ConfigError(
                f"case '{name}': field 'mu1' = {spec['mu1']!r} must be below mu2 = "
                f"{spec['mu2']!r} (the core's energy level lies below the halo's)"
            )
        if spec["kind"] in ("core_halo", "two_step") and spec["eta1"] + spec["eta2"] <= 0:
            raise ConfigError(
                f"case '{name}': fields 'eta1' + 'eta2' = {spec['eta1']!r} + {spec['eta2']!r} "
                "must be > 0 (the state is empty)"
            )
        try:
            states[name] = make_state(spec)
        except EquilibriumError as e:
            raise ConfigError(f"case '{name}': {e}") from None
    return states


def _check_cases(ck):
    """Every case's state exists (`_states`)."""
    ck.states  # noqa: B018 (solved here, refused here)


# ---- molecular dynamics -----------------------------------------------------------------
def _md_value(config, case, key):
    return config["md"]["runs"][case].get(key, config["md"].get(key))


def fastest_orbital_period(state, kappa_test):
    """2 pi / the largest orbital frequency among the orbits of the state that hold more than
    TAIL_FRACTION of its particles, and the test-particle orbits up to kappa_test.

    Librating frequencies fall from Omega_0 = sqrt(M0) at kappa = 0 to 0 at the separatrix;
    rotating ones grow with kappa, so the fastest orbit is kappa = 0 or the largest kappa."""
    from ..meanfield import orbits

    q = state.quadrature()
    order = np.argsort(q.kappa)[::-1]
    mass = (q.weights * state.f(q.kappa))[order]
    tail = np.cumsum(mass) / mass.sum()
    kappa_f = float(q.kappa[order][min(np.searchsorted(tail, TAIL_FRACTION), len(tail) - 1)])
    kappa = max(kappa_f, float(kappa_test))
    omega = math.sqrt(state.M0)
    if kappa > 1.0:
        omega = max(omega, float(orbits.frequency(kappa, state.M0)))
    return 2.0 * math.pi / omega, kappa


def machine_memory_bytes():
    """Physical memory of this machine (os.sysconf), or the cgroup limit if lower."""
    total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        if limit.isdigit():
            total = min(total, int(limit))
    except OSError:
        pass
    return total


def _gib(x):
    return f"{x / 2**40:.3g} TiB" if x >= 2**40 else f"{x / 2**30:.3g} GiB"


# ---- one run's physics: the checks every block that runs dynamics shares ----------------
def check_smooth_case(config, where, case, needs):
    """`case` names a case of the config, and one with a smooth f (not two-step): `needs` says
    what for."""
    if case not in config["cases"]:
        raise ConfigError(
            f"{where}: names case '{case}', which is not in 'cases' (cases: "
            f"{', '.join(config['cases'])})"
        )
    if config["cases"][case]["kind"] == "two_step":
        raise ConfigError(
            f"{where}: case '{case}': a two-step state has no smooth f (a delta-function "
            f"df/dkappa) for {needs}; use a thermal or core_halo state"
        )


def check_time_step(where, field, value, state, kappa_test=0.0, per_period=None, why=""):
    """`value` (a time step or a sampling interval) at most 1/per_period of the fastest orbital
    period of the state (orbits up to kappa_test included); default STEPS_PER_FASTEST_PERIOD."""
    per_period = per_period or STEPS_PER_FASTEST_PERIOD
    period, kappa = fastest_orbital_period(state, kappa_test)
    dt_max = period / per_period
    if value > dt_max:
        raise ConfigError(
            f"{where}: field '{field}' = {value!r} is outside the allowed range (0, {dt_max:.4g}]: "
            f"at most 1/{per_period:g} of the fastest orbital period {period:.4g} of the state "
            f"(kappa = {kappa:.6g}, M0 = {state.M0:.6g}){why}"
        )


def check_particle_number(where, field, n, state):
    """N large enough for a mean field: the noise 1/sqrt(N) of the magnetisation <= M0/10."""
    n_min = math.ceil((M0_OVER_NOISE / state.M0) ** 2)
    if n < n_min:
        raise ConfigError(
            f"{where}: field '{field}' = {n!r} must be >= {n_min} (the finite-N "
            f"noise 1/sqrt(N) of the magnetisation must be <= M0/{M0_OVER_NOISE:g}, "
            f"M0 = {state.M0:.4g})"
        )


def check_memory(where, need_bytes, what):
    """A job's memory estimate against this machine's, before anything is allocated."""
    total = machine_memory_bytes()
    if need_bytes > total:
        raise ConfigError(
            f"{where}: {what} needs about {_gib(need_bytes)} of memory, more than this "
            f"machine's {_gib(total)}"
        )


def check_run_physics(where, state, *, dt, n_particles, kappa_test=0.0, n_field="n_particles"):
    """One N-body run: dt resolves the fastest orbit of the state and of its test particles
    (up to kappa_test), and N is large enough for a mean field."""
    check_time_step(where, "dt", dt, state, kappa_test)
    check_particle_number(where, n_field, n_particles, state)


# ---- molecular dynamics -----------------------------------------------------------------
def _check_md_physics(ck):
    """Per MD run: the case can be sampled, dt resolves its fastest orbit, N is large enough
    for a mean field.  Runs before the settings record, so a wild dt is named as such."""
    config = ck.config
    for case in config["md"]["runs"]:
        where = f"md run '{case}'"
        check_smooth_case(config, where, case, "sampling MD")
        check_run_physics(
            where,
            ck.states[case],
            dt=_md_value(config, case, "dt"),
            n_particles=_md_value(config, case, "n_particles"),
            kappa_test=_md_value(config, case, "kappa_max"),
        )


def _check_md_records(ck):
    """Every MD run's record (`md_runs`: MDRun refuses what does not fit together within one
    run: whole multiples, lags within the run, the fit window within the lags, ...)."""
    ck.md_runs  # noqa: B018 (built here, refused here)


def _check_md_memory(ck):
    """Each run's memory estimate (MDRun.memory_mb: N, test particles, the ring buffer of
    J(t0)) against this machine's."""
    for (case, dynamics), run in ck.md_runs.items():
        what = f"field 'n_particles' = {run.n_particles!r} with n_test_{dynamics} = {run.n_test!r}"
        check_memory(f"md run '{case}' ({dynamics})", run.memory_mb() * 1e6, what)


def _every_md_run(ck):
    """(where, run, state) of every MD record: md.runs, then the 1/N studies at every size."""
    for (case, dynamics), run in ck.md_runs.items():
        yield f"md run '{case}' ({dynamics})", run, ck.states[case]
    for (case, dynamics, n), run in ck.scaling_runs.items():
        yield f"md_scaling run '{case}' ({dynamics}, N = {n})", run, ck.states[case]


def _check_md_sampling(ck):
    """Per MD record: the magnetisation stored within the run (m_every <= t_max); the test
    particles' J-bar range used (test_sampling 'uniform') and within the bins; a bin can reach
    min_particles; the bins within the theory grid they are compared with."""
    kappa_theory = ck.config["theory"]["kappa_max"]
    for where, run, state in _every_md_run(ck):
        if run.m_every > run.t_max:
            raise ConfigError(
                f"{where}: field 'm_every' = {run.m_every!r} is outside the allowed range "
                f"(0, t_max = {run.t_max!r}]: the magnetisation is stored every m_every over "
                "the production run"
            )
        if run.jbar_range is not None and run.n_test > 0:
            if run.test_sampling != "uniform":
                raise ConfigError(
                    f"{where}: field 'jbar_range' = {list(run.jbar_range)!r} is allowed only "
                    f"with test_sampling 'uniform' (test_sampling = {run.test_sampling!r} draws "
                    "the test particles from f, and the range would be ignored)"
                )
            jmax = run.jbar_max(state.M0)
            if run.jbar_range[1] > jmax * (1 + 1e-12):
                raise ConfigError(
                    f"{where}: field 'jbar_range' = {list(run.jbar_range)!r} must lie within "
                    f"[0, {jmax:.6g}] = [0, J-bar(kappa_max = {run.kappa_max!r})] at M0 = "
                    f"{state.M0:.6g}: test particles beyond the last bin are never measured"
                )
        most = run.seeds * run.n_tracked
        if run.min_particles > most:
            raise ConfigError(
                f"{where}: field 'min_particles' = {run.min_particles!r} is outside the allowed "
                f"range [0, {most}]: seeds x tracked particles = {run.seeds} x {run.n_tracked} "
                "(no bin can hold more, so every bin would be flagged)"
            )
        if run.kappa_max > kappa_theory:
            raise ConfigError(
                f"{where}: field 'kappa_max' = {run.kappa_max!r} is outside the allowed range "
                f"(0, theory.kappa_max = {kappa_theory!r}]: bins beyond the theory grid have no "
                "theory to be compared with"
            )


# ---- 1/N studies ------------------------------------------------------------------------
def _check_md_scaling(ck):
    """The 1/N studies: each case smooth (`md_scaling_runs`), at every size the checks of an
    MD run (dt with the `run` overrides, N, memory).  (A figure drawing a case that has no
    study is refused by `_check_figures`.)"""
    runs = ck.scaling_runs
    scaling_kappa0(ck.config)  # its shape, before any job
    for (case, dynamics, n), run in runs.items():
        where = f"md_scaling run '{case}' ({dynamics}, N = {n})"
        check_run_physics(
            where,
            ck.states[case],
            dt=run.dt,
            n_particles=n,
            kappa_test=run.kappa_max,
            n_field="sizes",
        )
        what = f"field 'sizes' = {n!r} with n_test = {run.n_test!r}"
        check_memory(where, run.memory_mb() * 1e6, what)


def _check_scaling_bins(ck):
    """Each kappa0 of a study picks a bin of its own among the study's bins (their centres, in
    kappa, of the J-bar bins up to J-bar(kappa_max)): figure 15 draws the bin whose centre lies
    nearest each kappa0 (`analysis.scaling.drawn_bins`)."""
    from ..meanfield import orbits

    first = {}
    for (case, _, _), run in ck.scaling_runs.items():
        first.setdefault(case, run)
    for case, targets in scaling_kappa0(ck.config).items():
        if not targets:
            continue
        run = first[case]
        where = f"md_scaling study '{case}'"
        out = [k for k in targets if not 0 < k <= run.kappa_max]
        if out:
            raise ConfigError(
                f"{where}: field 'kappa0' = {targets!r} is outside the allowed range (0, "
                f"kappa_max = {run.kappa_max!r}]: {out[0]!r} lies beyond the bins (they end at "
                "kappa_max)"
            )
        edges = run.jbar_edges(ck.states[case].M0)
        centres = orbits.kappa_from_rescaled_action(
            0.5 * (edges[1:] + edges[:-1]), ck.states[case].M0
        )
        picked = {}
        for k in targets:
            b = int(np.argmin(np.abs(centres - k)))
            if b in picked:
                raise ConfigError(
                    f"{where}: field 'kappa0' = {targets!r}: {picked[b]!r} and {k!r} pick the "
                    f"same bin (centre kappa = {centres[b]:.4g}); allowed: one kappa0 per bin of "
                    f"the {run.n_bins} (centres {', '.join(f'{c:.3g}' for c in centres)})"
                )
            picked[b] = k


# ---- spectrum of the magnetisation ------------------------------------------------------
#: the magnetisation is stored at least this many times per fastest orbital period, so that the
#: line n' = 1 of every orbit lies below the Nyquist frequency pi / m_every (no aliasing)
SAMPLES_PER_FASTEST_PERIOD = 2


def spectrum_cases(config):
    """{case: figure} of every case whose magnetisation spectrum a figure of the config draws
    (its registry entry has 'spectrum' inputs)."""
    return _cases_of_kind(config, "spectrum", exact=True)


def _cases_of_kind(config, kind, exact=False):
    """{case: figure} of every case that a figure of the config draws inputs of `kind` for
    (kinds starting with `kind`, or equal to it if `exact`)."""
    from ..analysis.figures.registry import FIGURES

    out = {}
    for fig, spec in config["figures"].items():
        if fig in FIGURES:
            for inp in FIGURES[fig].inputs:
                match = inp.kind == kind if exact else inp.kind.startswith(kind)
                if not match:
                    continue
                try:
                    out.update({c: fig for c in inp.cases(fig, spec) if c not in out})
                except KeyError as e:
                    raise ConfigError(e.args[0]) from None
    return out


def _spectrum_memory_bytes(runs):
    """The spectrum job loads every seed of both dynamics whole (sums per bin, lag and block,
    the time series, the stored tracks, Mx and My every m_every) and Welch-transforms the fine
    magnetisation; 30 % margin and 1 GB of interpreter."""
    need = 0.0
    for run in runs:
        per_seed = 8.0 * (
            4 * run.n_bins * (run.lag_samples + 1) * (run.n_blocks + 1)
            + (run.n_samples + 1) * (4 + 3 * run.n_store)
            + 2 * run.n_m_samples
        )
        need += run.seeds * (per_seed + 64.0 * run.n_m_samples)
    return 1e9 + 1.3 * need


def _check_spectrum(ck):
    """Each spectrum case (one with MD runs: `_check_figures` runs first) samples its
    magnetisation finely enough for its fastest orbits and for a Welch segment of max_lag, and
    its job fits in memory."""
    runs = ck.md_runs
    for case, fig in spectrum_cases(ck.config).items():
        where = f"spectrum case '{case}' (figure '{fig}')"
        full = runs[(case, "full")]
        check_time_step(
            where,
            "m_every",
            full.m_every,
            ck.states[case],
            per_period=SAMPLES_PER_FASTEST_PERIOD,
            why=": the Nyquist frequency pi/m_every must lie above its frequency",
        )
        if full.m_every > full.max_lag / 2:
            raise ConfigError(
                f"{where}: field 'm_every' = {full.m_every!r} is outside the allowed range "
                f"(0, max_lag / 2 = {full.max_lag / 2:.6g}]: a Welch segment of max_lag = "
                f"{full.max_lag!r} must hold two samples at least (the Nyquist frequency "
                "pi/m_every above the resolution 2 pi/max_lag)"
            )
        pair = (runs[(case, "bath")], full)
        what = f"field 'seeds' = {pair[0].seeds!r} + {pair[1].seeds!r} (bath + full)"
        check_memory(where, _spectrum_memory_bytes(pair), what)


# ---- relaxation ---------------------------------------------------------------------------
#: elementary resonances per node and per (n, n') of the kinetic relaxation's collision
#: operator (measured 8.0-9.5 on the hot-halo grids of 300-2400 nodes, n_max 3-12), and bytes
#: per elementary resonance at the peak (measured 151, with the Jacobian; margin included)
RESONANCES_PER_NODE = 10
BYTES_PER_RESONANCE = 200
#: RelaxationSettings.early_window where the settings have none (before it exists there)
EARLY_WINDOW_DEFAULT = 0.5


def _relaxation_settings(config, case):
    rel = config["relaxation"]
    run = {k: v for k, v in rel.items() if k not in ("runs", "equations")}
    run.update(rel["runs"][case] or {})
    return run


def _check_relaxation(ck):
    """Each case evolved by the kinetic equations exists, has a smooth f, and its evolution
    fits in memory (the collision operator's resonances, f at every accepted step)."""
    config = ck.config
    for case in (config.get("relaxation") or {}).get("runs", {}):
        where = f"relaxation run '{case}'"
        check_smooth_case(config, where, case, "the kinetic relaxation")
        s = _relaxation_settings(config, case)
        n, n_max, steps = s["n_nodes"], s["n_max"], s["max_steps"]
        need = 1e9 + n * (RESONANCES_PER_NODE * BYTES_PER_RESONANCE * n_max**2 + 16 * (steps + 2))
        what = f"field 'n_nodes' = {n!r} with n_max = {n_max!r} and max_steps = {steps!r}"
        check_memory(where, need, what)


def _check_relaxation_times(ck):
    """The relaxation section's settings, then each run's (the section's merged with its own):
    flux times within [0, tau_max], early_window > 0, the grid's node shares at most 1 in all.
    A run that shortens tau_max keeps the section's flux times up to its own tau_max (the
    evolution stores the current at those within the run); flux times written beside a
    tau_max they exceed are refused."""
    rel = ck.config.get("relaxation") or {}
    if not rel:
        return
    section = {k: v for k, v in rel.items() if k not in ("runs", "equations")}
    places = [("relaxation", section, section)]
    for case, own in (rel.get("runs") or {}).items():
        own = own or {}
        places.append((f"relaxation run '{case}'", {**section, **own}, own))
    for where, s, own in places:
        times = own.get("flux_times")
        if times is not None:
            tau_max = s["tau_max"]
            out = [t for t in times if not 0 <= t <= tau_max]
            if out:
                raise ConfigError(
                    f"{where}: field 'flux_times' = {list(times)!r} must lie within [0, tau_max = "
                    f"{tau_max!r}]: {out[0]!r} is beyond the run (the current is stored at "
                    "these rescaled times of the evolution)"
                )
        window = s.get("early_window", EARLY_WINDOW_DEFAULT)
        if not window > 0:
            raise ConfigError(
                f"{where}: field 'early_window' = {window!r} is outside the allowed range (0, "
                "inf): the early rate of M0 is (M0(early_window) - M0(0)) / early_window"
            )
        shares = s["feature_share"] + s["separatrix_share"]
        if shares > 1 + 1e-12:
            raise ConfigError(
                f"{where}: fields 'feature_share' + 'separatrix_share' = "
                f"{s['feature_share']!r} + {s['separatrix_share']!r} = {shares:.6g} must be in "
                "[0, 1] (shares of the grid's nodes; the rest is uniform in kappa)"
            )


def _relaxation_md_memory_bytes(rmd, n):
    """One ensemble at N = n: R = particles_per_size // n realisations of n particles (theta, p,
    sin, cos and the sampling's temporaries, 64 B each) and per measurement time the J-bar
    histogram of each realisation (int64 and int32 copies, the entropy's floats) and its |M|,
    phase, energy, momentum; 30 % margin and 1 GB of interpreter."""
    r = max(1, rmd["particles_per_size"] // n)
    per_time = r * (32 * (rmd["n_bins"] + 1) + 48)
    return 1e9 + 1.3 * (64 * r * n + rmd["n_times"] * per_time)


def _ensemble_settings(config, block):
    """The settings of the ensembles of `block` as the jobs get them: relaxation_md's, or for
    relaxation_rates relaxation_md's dt, bins, kappa_max and threads with relaxation_rates'
    window, schedule, sizes and seed (`relaxation_rates_run` in the workflow)."""
    rmd = config.get("relaxation_md")
    if block == "relaxation_md":
        return {k: v for k, v in (rmd or {}).items() if k != "runs"}
    if rmd is None:
        raise ConfigError(
            "relaxation_rates: needs the section 'relaxation_md' (its dt, n_bins, kappa_max and "
            "threads are the early-window ensembles'); allowed: relaxation_md with runs: {} "
            "for its defaults"
        )
    rr = config.get(block) or {}
    return {
        **{k: v for k, v in rmd.items() if k != "runs"},
        **{k: v for k, v in rr.items() if k != "runs"},
    }


def _check_ensembles(ck, block, min_realisations):
    """The runs of an ensemble block (relaxation_md, relaxation_rates): a smooth case with a
    kinetic evolution to be compared with, dt against its fastest orbit, every N against the
    noise of the magnetisation, at least `min_realisations` realisations at every N (their
    spread is the error), memory."""
    config = ck.config
    settings = _ensemble_settings(config, block)
    relaxed = (config.get("relaxation") or {}).get("runs", {})
    per_size = settings.get("particles_per_size")
    for case, spec in (config.get(block) or {}).get("runs", {}).items():
        where = f"{block} run '{case}'"
        check_smooth_case(config, where, case, "the N-body relaxation")
        if case not in relaxed:
            raise ConfigError(
                f"{where}: case '{case}' is not under relaxation.runs (its kinetic evolutions "
                f"are what the ensembles are compared with; relaxation.runs: "
                f"{', '.join(relaxed) or 'none'})"
            )
        dt_name = "dt" if block == "relaxation_md" else "relaxation_md.dt"
        check_time_step(where, dt_name, settings["dt"], ck.states[case])
        for n in spec["n_particles"]:
            check_particle_number(where, "n_particles", n, ck.states[case])
            if per_size // n < min_realisations:
                raise ConfigError(
                    f"{where}: field 'n_particles' = {n!r} leaves {per_size // n} realisation(s) "
                    f"with particles_per_size = {per_size!r}; need N <= particles_per_size / "
                    f"{min_realisations}"
                )
            what = f"field 'n_particles' = {n!r} with particles_per_size = {per_size!r}"
            check_memory(where, _relaxation_md_memory_bytes(settings, n), what)


def _check_relaxation_md(ck):
    """Each N-body relaxation (`_check_ensembles`, one realisation allowed); thermal controls
    only at sizes that have an ensemble of the state."""
    _check_ensembles(ck, "relaxation_md", 1)
    for case, spec in (ck.config.get("relaxation_md") or {}).get("runs", {}).items():
        extra = sorted(set(spec.get("control_sizes", [])) - set(spec["n_particles"]))
        if extra:
            raise ConfigError(
                f"relaxation_md run '{case}': field 'control_sizes' = {extra!r} not among "
                f"n_particles = {list(spec['n_particles'])!r} (a control is compared with the "
                "state's ensemble of the same N)"
            )


def _check_relaxation_rates(ck):
    """Each early-window study (`_check_ensembles` with relaxation_md's dt and bins, two
    realisations at least)."""
    if ck.config.get("relaxation_rates"):
        _check_ensembles(ck, "relaxation_rates", 2)


def _check_ensemble_window(ck, block):
    """The schedule of the ensembles of `block` and what they are compared with: the first
    measurement tau_first before tau_max and at least one time step after t = 0 at every N;
    n_times distinct measurement times at every N once rounded to whole steps
    (`dynamics.ensemble.measurement_times`); the kinetic evolution of each case running to
    tau_max at least, on a grid reaching the ensembles' last bin edge (kappa_max)."""
    from ..dynamics.ensemble import measurement_times

    config = ck.config
    runs = (config.get(block) or {}).get("runs") or {}
    if not runs:
        return
    s = _ensemble_settings(config, block)
    tau_first, tau_max, n_times, dt = s["tau_first"], s["tau_max"], s["n_times"], s["dt"]
    if not tau_first < tau_max:
        raise ConfigError(
            f"{block}: field 'tau_first' = {tau_first!r} is outside the allowed range (0, "
            f"tau_max = {tau_max!r}): the first measurement after t = 0 must come before the "
            "end of the run"
        )
    sizes = sorted({int(n) for spec in runs.values() for n in spec["n_particles"]})
    dt_name = "dt" if block == "relaxation_md" else "relaxation_md.dt"
    if tau_first * sizes[0] < dt * (1 - 1e-12):
        raise ConfigError(
            f"{block}: field 'tau_first' = {tau_first!r} is outside the allowed range "
            f"[{dt_name} / N = {dt!r} / {sizes[0]} = {dt / sizes[0]:.4g}, tau_max): at N = "
            f"{sizes[0]} the first measurement t = tau_first N = {tau_first * sizes[0]:.4g} "
            "would come before the first time step"
        )
    lowest = 2 if block == "relaxation_md" else 3  # the schema's minimum of n_times
    for n in sizes:
        got = len(measurement_times(tau_max * n, n_times, dt, t_first=tau_first * n))
        if got < n_times:
            fits = [
                k
                for k in range(lowest, n_times)
                if len(measurement_times(tau_max * n, k, dt, t_first=tau_first * n)) == k
            ]
            allowed = f"[{lowest}, {max(fits)}]" if fits else "empty (widen tau_first to tau_max)"
            raise ConfigError(
                f"{block}: field 'n_times' = {n_times!r} is outside the allowed range {allowed} "
                f"at N = {n}: its geometric schedule from t = tau_first N = "
                f"{tau_first * n:.4g} to tau_max N = {tau_max * n:.4g}, rounded to whole steps "
                f"of {dt_name} = {dt!r}, has only {got} distinct times"
            )
    kappa_name = "kappa_max" if block == "relaxation_md" else "relaxation_md.kappa_max"
    for case in runs:
        kin = _relaxation_settings(config, case)
        where = f"{block} run '{case}'"
        if tau_max > kin["tau_max"]:
            raise ConfigError(
                f"{where}: field 'tau_max' = {tau_max!r} is outside the allowed range (0, "
                f"{kin['tau_max']!r}], the tau_max of relaxation run '{case}': the kinetic "
                "evolutions the ensembles are compared with end there"
            )
        if s["kappa_max"] > kin["kappa_max"]:
            raise ConfigError(
                f"{where}: field '{kappa_name}' = {s['kappa_max']!r} is outside the allowed "
                f"range (1, {kin['kappa_max']!r}], the kappa_max of relaxation run '{case}': "
                "the kinetic f the histograms are compared with ends there"
            )


def _check_relaxation_md_window(ck):
    _check_ensemble_window(ck, "relaxation_md")


def _check_relaxation_rates_window(ck):
    _check_ensemble_window(ck, "relaxation_rates")


# ---- figures ----------------------------------------------------------------------------
#: the run that makes each kind of figure input, by the first folder of the input's path under
#: the results directory (`registry.Inputs.pattern`): (what a case lacks when it has none, the
#: cases that have one).  Every input pattern of the registry has its entry here (a test
#: holds the two together), so a figure cannot ask for a file that no rule makes for its case.
def _input_makers(config):
    cases = config["cases"]
    smooth = sorted(c for c, s in cases.items() if s["kind"] != "two_step")

    def runs(block):
        return sorted((config.get(block) or {}).get("runs") or {})

    md = sorted(config["md"]["runs"])
    studies = sorted(((config.get("md_scaling") or {}).get("studies")) or {})
    return {
        "orbits": ("no orbits", sorted(cases)),
        "analytic": ("no closed forms", sorted(cases)),
        "theory": ("no theory grid (a two-step state: delta-function df/dkappa)", smooth),
        "fits": ("no run under md.runs", md),
        "windowed": ("no run under md.runs", md),
        "spectrum": ("no run under md.runs", md),
        "scaling": ("no study under md_scaling.studies", studies),
        "relaxation": ("no run under relaxation.runs", runs("relaxation")),
        "relaxation_comparison": ("no run under relaxation_md.runs", runs("relaxation_md")),
        "relaxation_rates": ("no run under relaxation_rates.runs", runs("relaxation_rates")),
    }


def input_maker(pattern):
    """The key of `_input_makers` for a registry input pattern: its first folder."""
    return pattern.split("/", 1)[0]


def _check_figures(ck):
    """Every figure of the config is one of the registry's; every case it names exists, is of
    the kind its field asks for (fig07's two_step, thermal, core_halo) and has the run that
    makes each of the figure's inputs (MD fits, 1/N studies, relaxations, ...)."""
    from ..analysis.figures.registry import FIGURES

    config = ck.config
    cases = config["cases"]
    makers = _input_makers(config)
    for fig, spec in config["figures"].items():
        if fig not in FIGURES:
            near = difflib.get_close_matches(fig, list(FIGURES), n=1, cutoff=0.6)
            hint = f"did you mean '{near[0]}'? " if near else ""
            raise ConfigError(
                f"figures: unknown figure '{fig}' ({hint}figures: {', '.join(FIGURES)})"
            )
        where = f"figure '{fig}'"
        for key, names in spec.items():
            for c in [names] if isinstance(names, str) else names:
                if c not in cases:
                    raise ConfigError(
                        f"{where}: names case '{c}', which is not in 'cases' (field '{key}'; "
                        f"cases: {', '.join(cases)})"
                    )
                kind = cases[c]["kind"]
                if key in ("two_step", "thermal", "core_halo") and kind != key:
                    raise ConfigError(
                        f"{where}: field '{key}' names case '{c}' of kind '{kind}', not '{key}'"
                    )
        for inp in FIGURES[fig].inputs:
            lacks, allowed = makers[input_maker(inp.pattern)]
            try:
                inp.files(fig, spec)  # a case for every kind of input, every field given
            except KeyError as e:
                raise ConfigError(e.args[0]) from None
            others = {k: v for k, v in spec.items() if k not in inp.keys}
            for key in inp.keys:
                names = spec.get(key, [])
                for c in [names] if isinstance(names, str) else names:
                    if c not in allowed:
                        first = inp.files(fig, {**others, key: [c]})[0]
                        raise ConfigError(
                            f"{where}: case '{c}' (field '{key}') has {lacks}, so its input "
                            f"{first} cannot be made; allowed: {', '.join(allowed) or 'none'}"
                        )


def check_physics(config):
    """Checks across fields of a schema-valid config with its defaults: every check of
    `RELATIONS`, each once, in the table's order (see the module docstring)."""
    ck = _Checked(config)
    for check in relation_checks():
        check(ck)


# ---- the relations, as data -------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class Relation:
    """One relation between fields of the config that `check_physics` enforces.

    block: the config block it belongs to (`where` its refusal names: md run, md_scaling,
    relaxation, relaxation_md, relaxation_rates, figure, spectrum case; 'cases' for the
    states); fields: the fields it ties together, the block's own by name (nested ones by
    their own name: 'n_particles' of a run) and other blocks' dotted ('theory.kappa_max');
    rule: the relation, as the refusal states it; check: the function of this module that
    runs it (several relations share one); by: where the refusal is written when not in
    `check` itself: 'MDRun' (`dynamics.settings`), 'runs' (`dynamics.runs`)."""

    block: str
    fields: tuple[str, ...]
    rule: str
    check: Callable[[_Checked], None]
    by: str = ""

    @property
    def name(self):
        return f"{self.block}: {self.rule}"


def _r(block, fields, rule, check, by=""):
    return Relation(block, tuple(fields.split()), rule, check, by)


RUN_CASE = "names a case under `cases`"
SMOOTH = "its case has a smooth f (not two_step)"

#: every relation between fields of a block, and with other blocks, in the order they are
#: checked.  A field of a block's schema is in a relation here or in FREE_FIELDS (a test holds
#: the three together, and one test per relation builds a config that violates it).
RELATIONS = (
    # ---- cases: the equilibrium states every block draws from
    _r("cases", "cases", "case names differ by more than upper/lower case", _check_cases),
    _r("cases", "cases", "core below halo: mu1 < mu2", _check_cases),
    _r("cases", "cases", "a core-halo state is not empty: eta1 + eta2 > 0", _check_cases),
    _r("cases", "cases", "a self-consistent M0 exists", _check_cases),
    # ---- md: each run of md.runs, the md section's settings merged with its own
    _r("md", "runs cases", RUN_CASE, _check_md_physics),
    _r("md", "runs cases", SMOOTH, _check_md_physics),
    _r("md", "dt kappa_max", "dt <= 1/10 of the fastest orbital period (test particles up to "
       "kappa_max)", _check_md_physics),
    _r("md", "n_particles", "n_particles >= (10/M0)^2", _check_md_physics),
    _r("md", "sample_every dt", "sample_every a whole multiple of dt", _check_md_records,
       "MDRun"),
    _r("md", "t_equilibrate dt", "t_equilibrate a whole multiple of dt", _check_md_records,
       "MDRun"),
    _r("md", "m_every dt", "m_every a whole multiple of dt", _check_md_records, "MDRun"),
    _r("md", "max_lag sample_every", "max_lag a whole multiple of sample_every",
       _check_md_records, "MDRun"),
    _r("md", "origin_every sample_every", "origin_every a whole multiple of sample_every",
       _check_md_records, "MDRun"),
    _r("md", "t_max sample_every", "t_max a whole multiple of sample_every", _check_md_records,
       "MDRun"),
    _r("md", "max_lag t_max", "max_lag <= t_max", _check_md_records, "MDRun"),
    _r("md", "fit_window max_lag", "0 <= fit_window[0] < fit_window[1] <= max_lag",
       _check_md_records, "MDRun"),
    _r("md", "n_blocks t_max max_lag origin_every", "n_blocks <= the number of time origins "
       "(t_max - max_lag) / origin_every + 1", _check_md_records, "MDRun"),
    _r("md", "n_track n_particles", "n_track in [1, n_particles]", _check_md_records, "MDRun"),
    _r("md", "jbar_range", "0 <= jbar_range[0] < jbar_range[1]", _check_md_records, "MDRun"),
    _r("md", "n_particles n_test_bath n_test_full max_lag origin_every", "a run's memory "
       "estimate within this machine's", _check_md_memory),
    _r("md", "m_every t_max", "m_every <= t_max", _check_md_sampling),
    _r("md", "jbar_range test_sampling", "jbar_range only with test_sampling 'uniform'",
       _check_md_sampling),
    _r("md", "jbar_range kappa_max", "jbar_range within [0, J-bar(kappa_max)]",
       _check_md_sampling),
    _r("md", "min_particles seeds seeds_bath seeds_full n_test_bath n_test_full n_track",
       "min_particles <= seeds x tracked particles", _check_md_sampling),
    _r("md", "kappa_max theory.kappa_max", "kappa_max <= theory.kappa_max", _check_md_sampling),
    # ---- md_scaling: each study, at every size (the md relations hold for its `run` too)
    _r("md_scaling", "studies cases", RUN_CASE, _check_md_scaling, "runs"),
    _r("md_scaling", "studies cases", SMOOTH, _check_md_scaling, "runs"),
    _r("md_scaling", "seeds sizes", "seeds an integer >= 2 or a list parallel to sizes",
       _check_md_scaling, "runs"),
    _r("md_scaling", "run sizes seeds", "run sets no field that sizes and seeds set",
       _check_md_scaling, "runs"),
    _r("md_scaling", "run md.fit_window md.max_lag", "run: fit_window within (0, max_lag]",
       _check_md_scaling, "MDRun"),
    _r("md_scaling", "run md.max_lag md.t_max", "run: max_lag <= t_max", _check_md_scaling,
       "MDRun"),
    _r("md_scaling", "run md.dt md.kappa_max", "run: dt <= 1/10 of the fastest orbital period",
       _check_md_scaling),
    _r("md_scaling", "sizes", "every size >= (10/M0)^2", _check_md_scaling),
    _r("md_scaling", "sizes run", "every size's memory estimate within this machine's",
       _check_md_scaling),
    _r("md_scaling", "run md.m_every md.t_max", "run: the md relations of this module "
       "(m_every <= t_max, ...) at every size", _check_md_sampling),
    _r("md_scaling", "kappa0 run md.kappa_max", "kappa0 within (0, kappa_max]",
       _check_scaling_bins),
    _r("md_scaling", "kappa0 run md.n_bins", "each kappa0 picks a bin of its own",
       _check_scaling_bins),
    # ---- relaxation: the kinetic evolutions, the section's settings merged with each run's
    _r("relaxation", "runs cases", RUN_CASE, _check_relaxation),
    _r("relaxation", "runs cases", SMOOTH, _check_relaxation),
    _r("relaxation", "n_nodes n_max max_steps", "an evolution's memory estimate within this "
       "machine's", _check_relaxation),
    _r("relaxation", "flux_times tau_max", "flux_times within [0, tau_max]",
       _check_relaxation_times),
    _r("relaxation", "early_window", "early_window > 0", _check_relaxation_times),
    _r("relaxation", "feature_share separatrix_share", "feature_share + separatrix_share <= 1",
       _check_relaxation_times),
    # ---- relaxation_md: the N-body ensembles, compared with the kinetic evolutions
    _r("relaxation_md", "runs cases", RUN_CASE, _check_relaxation_md),
    _r("relaxation_md", "runs cases", SMOOTH, _check_relaxation_md),
    _r("relaxation_md", "runs relaxation.runs", "its case is under relaxation.runs",
       _check_relaxation_md),
    _r("relaxation_md", "dt", "dt <= 1/10 of the fastest orbital period", _check_relaxation_md),
    _r("relaxation_md", "n_particles", "every N >= (10/M0)^2", _check_relaxation_md),
    _r("relaxation_md", "n_particles particles_per_size", "every N <= particles_per_size",
       _check_relaxation_md),
    _r("relaxation_md", "n_particles particles_per_size n_times n_bins", "every ensemble's "
       "memory estimate within this machine's", _check_relaxation_md),
    _r("relaxation_md", "control_sizes n_particles", "control_sizes among n_particles",
       _check_relaxation_md),
    _r("relaxation_md", "tau_first tau_max", "tau_first < tau_max", _check_relaxation_md_window),
    _r("relaxation_md", "tau_first dt n_particles", "tau_first x N >= dt at every N",
       _check_relaxation_md_window),
    _r("relaxation_md", "n_times tau_first tau_max dt n_particles", "n_times distinct "
       "measurement times at every N", _check_relaxation_md_window),
    _r("relaxation_md", "tau_max relaxation.tau_max", "tau_max <= the case's relaxation tau_max",
       _check_relaxation_md_window),
    _r("relaxation_md", "kappa_max relaxation.kappa_max", "kappa_max <= the case's relaxation "
       "kappa_max", _check_relaxation_md_window),
    # ---- relaxation_rates: the early window, with relaxation_md's dt, bins and kappa_max
    _r("relaxation_rates", "relaxation_md", "the relaxation_md section exists",
       _check_relaxation_rates),
    _r("relaxation_rates", "runs cases", RUN_CASE, _check_relaxation_rates),
    _r("relaxation_rates", "runs cases", SMOOTH, _check_relaxation_rates),
    _r("relaxation_rates", "runs relaxation.runs", "its case is under relaxation.runs",
       _check_relaxation_rates),
    _r("relaxation_rates", "relaxation_md.dt", "relaxation_md.dt <= 1/10 of the fastest "
       "orbital period", _check_relaxation_rates),
    _r("relaxation_rates", "n_particles", "every N >= (10/M0)^2", _check_relaxation_rates),
    _r("relaxation_rates", "n_particles particles_per_size", "every N <= particles_per_size / 2",
       _check_relaxation_rates),
    _r("relaxation_rates", "n_particles particles_per_size n_times relaxation_md.n_bins",
       "every ensemble's memory estimate within this machine's", _check_relaxation_rates),
    _r("relaxation_rates", "tau_first tau_max", "tau_first < tau_max",
       _check_relaxation_rates_window),
    _r("relaxation_rates", "tau_first relaxation_md.dt n_particles", "tau_first x N >= "
       "relaxation_md.dt at every N", _check_relaxation_rates_window),
    _r("relaxation_rates", "n_times tau_first tau_max n_particles", "n_times distinct "
       "measurement times at every N", _check_relaxation_rates_window),
    _r("relaxation_rates", "tau_max relaxation.tau_max", "tau_max <= the case's relaxation "
       "tau_max", _check_relaxation_rates_window),
    _r("relaxation_rates", "relaxation_md.kappa_max relaxation.kappa_max", "relaxation_md."
       "kappa_max <= the case's relaxation kappa_max", _check_relaxation_rates_window),
    # ---- figures: the registry's, naming cases that have what each input is made from
    _r("figures", "case cases", "a figure of the registry", _check_figures),
    _r("figures", "case cases core_halo two_step thermal", "every case named exists",
       _check_figures),
    _r("figures", "core_halo two_step thermal", "fields core_halo, two_step, thermal name a "
       "case of that kind", _check_figures),
    _r("figures", "case cases core_halo two_step thermal", "every input's fields given",
       _check_figures),
    _r("figures", "case cases md.runs md_scaling.studies relaxation.runs relaxation_md.runs "
       "relaxation_rates.runs", "every case has the run that makes each input", _check_figures),
    # ---- spectrum: the magnetisation of every case a figure draws its spectrum for
    _r("spectrum", "figures md.runs", "the case has runs under md.runs", _check_figures),
    _r("spectrum", "md.m_every", "m_every <= 1/2 of the fastest orbital period (Nyquist)",
       _check_spectrum),
    _r("spectrum", "md.m_every md.max_lag", "m_every <= max_lag / 2", _check_spectrum),
    _r("spectrum", "md.seeds md.seeds_bath md.seeds_full md.n_bins md.n_blocks md.n_store "
       "md.t_max md.m_every", "the job's memory estimate within this machine's",
       _check_spectrum),
)  # fmt: skip

#: fields with no relation to another field: their range alone (the schema's) says what is
#: allowed
FREE_FIELDS = {
    "md": {
        "threads": "threads per job: no effect on the numbers",
        "zero_momentum": "a switch of MD(full)'s initial state",
        "bath": "how MD(bath) moves its bath",
        "bath_tolerance": "the exact bath's truncation error per particle",
        "job_seconds": "groups the seeds into jobs; any positive value works",
        "separatrix_band_fit": "flags bins within it of kappa = 1",
    },
    "relaxation": {
        "equations": "the comparisons and figures take any non-empty subset",
        "check_stability": "a switch",
        "l_max": "the dielectric tensor's cut-off",
        "rtol": "the step's error control",
        "early_rtol": "the step's error control within the early window",
        "thermal_tol": "the stopping criterion",
        "eps_refresh": "when the dielectric tensor is recomputed",
        "layer_eta_min": "the grid next to the separatrix",
        "dlog_omega": "the grid next to the separatrix",
        "min_per_decade": "the grid next to the separatrix",
    },
    "relaxation_md": {"seed": "the ensembles' random seed", "threads": "threads per job"},
    "relaxation_rates": {"seed": "the ensembles' random seed"},
}


def relation_checks():
    """The distinct checks of RELATIONS, in the table's order: what `check_physics` runs."""
    return list(dict.fromkeys(r.check for r in RELATIONS))


def _merge(into, new):
    """Recursive update, as Snakemake merges several config files and --config."""
    for k, v in new.items():
        if isinstance(v, dict) and isinstance(into.get(k), dict):
            _merge(into[k], v)
        else:
            into[k] = v


def main(argv=None):
    """python -m hmfdiff.pipeline.config FILE...: check config files, merged in order, as
    `snakemake --configfile FILE...` would see them; one line per outcome."""
    files = sys.argv[1:] if argv is None else argv
    if not files:
        print("usage: python -m hmfdiff.pipeline.config CONFIG.yaml [MORE.yaml ...]")
        return 2
    config = {}
    try:
        for f in files:
            check_config_files([f])
            _merge(config, load_yaml_file(f))
        prepare_config(config)
    except ConfigError as e:
        print(f"Config error: {e}", file=sys.stderr)
        return 1
    print(f"{' + '.join(map(str, files))}: valid ({len(config['cases'])} cases)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
