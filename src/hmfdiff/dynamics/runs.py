"""The MD runs a config asks for: `md_runs(config)`, one `MDRun` per (case, dynamics) from the
config's `md:` section (its defaults merged with each case's overrides), and
`md_scaling_runs(config)`, one per (dynamics, N) of the 1/N study (`md_scaling:`).

Bad values raise `ConfigError` with one line naming the case, the field, the value and the
allowed range (the record itself checks each value, `hmfdiff.dynamics.settings`).
"""

from __future__ import annotations

import dataclasses
from numbers import Real

from ..errors import ConfigError
from .settings import DYNAMICS, MDRun

__all__ = ["CONFIG_KEYS", "md_runs", "md_scaling_runs"]

#: keys of the config's md section (and of each run) other than 'runs'
CONFIG_KEYS = (
    tuple(f.name for f in dataclasses.fields(MDRun) if f.name not in ("case", "dynamics", "n_test"))
    + tuple(f"n_test_{d}" for d in DYNAMICS)
    + tuple(f"seeds_{d}" for d in DYNAMICS)
)


def md_runs(config):
    """{(case, dynamics): MDRun} of every case under md.runs and both dynamics.

    Each record takes the md section's values, overridden by the case's own; `n_test_bath` and
    `n_test_full` become the n_test of each dynamics, and `seeds_bath`, `seeds_full` (optional)
    its number of realisations in place of `seeds` (an MD(bath) realisation costs about a
    fifth of an MD(full) one, so the bath can buy its precision with more seeds).  Raises
    ConfigError naming the case and the field on the first bad value, unknown key or missing
    setting.
    """
    md = config.get("md")
    if md is None:
        raise ConfigError("config: missing required field(s) ['md']")
    runs = md.get("runs")
    if not isinstance(runs, dict):
        raise ConfigError("md: field 'runs' must be a mapping of case name -> run settings")
    cases = config.get("cases") or {}
    required = [
        f.name
        for f in dataclasses.fields(MDRun)
        if f.default is dataclasses.MISSING and f.name not in ("dynamics", "n_test")
    ]
    out = {}
    for case, overrides in runs.items():
        where = f"md run '{case}'"
        if case not in cases:
            raise ConfigError(f"{where}: names case '{case}', which is not in 'cases'")
        if cases[case].get("kind") == "two_step":
            raise ConfigError(f"{where}: a two-step state has no smooth f to sample MD from")
        if overrides is not None and not isinstance(overrides, dict):
            raise ConfigError(f"{where}: must be a mapping of settings")
        s = {k: v for k, v in md.items() if k != "runs"}
        s.update(overrides or {})
        unknown = sorted(set(s) - set(CONFIG_KEYS))
        if unknown:
            raise ConfigError(f"{where}: unknown field(s) {unknown}; known: {list(CONFIG_KEYS)}")
        missing = [k for k in (*required, *(f"n_test_{d}" for d in DYNAMICS)) if k not in s]
        if missing:
            raise ConfigError(f"{where}: missing required field(s) {missing}")
        fields = {k: v for k, v in s.items() if not k.startswith(("n_test_", "seeds_"))}
        for dynamics in DYNAMICS:
            seeds = s.get(f"seeds_{dynamics}")
            per_dynamics = {} if seeds is None else {"seeds": seeds}
            out[(case, dynamics)] = MDRun(
                case=case,
                dynamics=dynamics,
                n_test=s[f"n_test_{dynamics}"],
                **{**fields, **per_dynamics},
            )
    return out


#: keys of the config's md_scaling section
SCALING_KEYS = ("case", "sizes", "seeds", "run")


def md_scaling_runs(config):
    """{(dynamics, N): MDRun} of the 1/N scaling study (config section md_scaling), or {} when
    the section is absent.

    md_scaling: case (an MD case under md.runs), sizes (the N, each >= 1), seeds, and run:
    settings that override the case's MD settings for these runs (e.g. a shorter t_max and
    fit_window).  Raises ConfigError naming the field on a bad value."""
    sc = config.get("md_scaling")
    if not sc:
        return {}
    where = "md_scaling"
    unknown = sorted(set(sc) - set(SCALING_KEYS))
    if unknown:
        raise ConfigError(f"{where}: unknown field(s) {unknown}; known: {list(SCALING_KEYS)}")
    case = sc.get("case")
    runs = md_runs(config)
    if (case, "bath") not in runs:
        raise ConfigError(f"{where}: field 'case' = {case!r} must name a case under md.runs")
    sizes = sc.get("sizes")
    ok = isinstance(sizes, list) and len(sizes) >= 1
    ok = ok and all(isinstance(n, Real) and float(n).is_integer() and n >= 1 for n in sizes)
    if not ok or len(set(sizes)) != len(sizes):
        raise ConfigError(f"{where}: field 'sizes' = {sizes!r} must be distinct integers >= 1")
    over = dict(sc.get("run") or {})
    bad = sorted(set(over) - set(CONFIG_KEYS))
    if bad:
        raise ConfigError(f"{where}: unknown field(s) {bad} under 'run'")
    out = {}
    for dynamics in DYNAMICS:
        base = runs[(case, dynamics)].to_dict()
        base.update({k: v for k, v in over.items() if not k.startswith(("n_test_", "seeds_"))})
        if f"n_test_{dynamics}" in over:
            base["n_test"] = over[f"n_test_{dynamics}"]
        if f"seeds_{dynamics}" in over:
            base["seeds"] = over[f"seeds_{dynamics}"]
        base["seeds"] = sc.get("seeds", base["seeds"])
        base["case"] = f"{case} (md_scaling)"
        track = base.get("n_track")
        for n in sizes:
            base["n_particles"] = int(n)
            if track is not None:  # a subset larger than N tracks all N
                base["n_track"] = min(int(track), int(n))
            out[(dynamics, int(n))] = MDRun(**base)
    return out
