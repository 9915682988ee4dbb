"""The pipeline configuration, checked once before any job: files, schema, then physics.

`check_config_files(files)` then `prepare_config(config, schema)` run the whole chain, in place;
each failure is a one-line ConfigError naming the case or section, the field, the value and what
is allowed:

1. the config files themselves (`schema.load_yaml_file`): malformed YAML and duplicate keys
   (two cases with the same name) are refused, naming the file and line;
2. the JSON schema (workflow/schemas/config.schema.yaml, via `schema.apply_schema`): numbers
   written as strings coerced, types, ranges, required and unknown fields, thermal M0 xor u;
   then the schema's defaults are filled in;
3. the physics across fields, in this module (`check_physics`): case names that collide on a
   case-insensitive file system, mu1 < mu2 of a core-halo state, a self-consistent M0 for
   every state, MD only for states with a smooth f, the MD time step against the fastest
   orbital period of the state, N against the noise of the magnetisation, every MD run's
   settings (`hmfdiff.dynamics.runs.md_runs`: whole multiples of dt, ...), its memory
   estimate against this machine's, relaxation runs of smooth states, figures naming existing
   cases of the right kind.

`python -m hmfdiff.pipeline.config FILE...` checks config files outside Snakemake.
"""

from __future__ import annotations

import copy
import math
import os
import sys
from pathlib import Path

import numpy as np

from ..dynamics.runs import md_runs
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
            raise ConfigError(f"case '{name}': eta1 + eta2 must be > 0 (the state is empty)")
        try:
            states[name] = make_state(spec)
        except EquilibriumError as e:
            raise ConfigError(f"case '{name}': {e}") from None
    return states


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


def _check_md_physics(config, states):
    """Per MD run: the case can be sampled, dt resolves its fastest orbit, N is large enough
    for a mean field.  Runs before the settings record, so a wild dt is named as such."""
    for case in config["md"]["runs"]:
        where = f"md run '{case}'"
        if case not in config["cases"]:
            raise ConfigError(f"{where}: names case '{case}', which is not in 'cases'")
        if config["cases"][case]["kind"] == "two_step":
            raise ConfigError(f"{where}: a two-step state has no smooth f to sample MD from")
        state = states[case]
        dt = _md_value(config, case, "dt")
        period, kappa = fastest_orbital_period(state, _md_value(config, case, "kappa_max"))
        dt_max = period / STEPS_PER_FASTEST_PERIOD
        if dt > dt_max:
            raise ConfigError(
                f"{where}: field 'dt' = {dt!r} is outside the allowed range (0, {dt_max:.4g}]: "
                f"at most 1/{STEPS_PER_FASTEST_PERIOD} of the fastest orbital period "
                f"{period:.4g} of the state (kappa = {kappa:.3g}, M0 = {state.M0:.4g})"
            )
        n = _md_value(config, case, "n_particles")
        n_min = math.ceil((M0_OVER_NOISE / state.M0) ** 2)
        if n < n_min:
            raise ConfigError(
                f"{where}: field 'n_particles' = {n!r} must be >= {n_min} (the finite-N "
                f"noise 1/sqrt(N) of the magnetisation must be <= M0/{M0_OVER_NOISE:g}, "
                f"M0 = {state.M0:.4g})"
            )


def _check_md_memory(runs):
    """Each run's memory estimate (MDRun.memory_mb: N, test particles, the ring buffer of
    J(t0)) against this machine's, before anything is allocated."""
    total = machine_memory_bytes()
    for (case, dynamics), run in runs.items():
        need = run.memory_mb() * 1e6
        if need > total:
            raise ConfigError(
                f"md run '{case}' ({dynamics}): field 'n_particles' = {run.n_particles!r} "
                f"with n_test_{dynamics} = {run.n_test!r} needs about {_gib(need)} of "
                f"memory, more than this machine's {_gib(total)}"
            )


# ---- relaxation ---------------------------------------------------------------------------
def _check_relaxation(config):
    """Each case evolved by the kinetic equations exists and has a smooth f."""
    for case in (config.get("relaxation") or {}).get("runs", {}):
        where = f"relaxation run '{case}'"
        if case not in config["cases"]:
            raise ConfigError(f"{where}: names case '{case}', which is not in 'cases'")
        if config["cases"][case]["kind"] == "two_step":
            raise ConfigError(
                f"{where}: a two-step state has a delta-function df/dkappa; evolve a smooth "
                "state (thermal or core_halo)"
            )


# ---- figures ----------------------------------------------------------------------------
def _check_figures(config):
    cases = config["cases"]
    for fig, spec in config["figures"].items():
        where = f"figure '{fig}'"
        for key, names in spec.items():
            for c in [names] if isinstance(names, str) else names:
                if c not in cases:
                    raise ConfigError(f"{where}: names case '{c}', which is not in 'cases'")
                kind = cases[c]["kind"]
                if key in ("two_step", "thermal", "core_halo") and kind != key:
                    raise ConfigError(
                        f"{where}: field '{key}' names case '{c}' of kind '{kind}', not '{key}'"
                    )


def check_physics(config):
    """Checks across fields of a schema-valid config with its defaults (see the docstring)."""
    states = _states(config)
    _check_md_physics(config, states)
    _check_md_memory(md_runs(config))
    _check_relaxation(config)
    _check_figures(config)


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
