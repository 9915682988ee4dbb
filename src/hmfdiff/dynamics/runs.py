"""The MD runs a config asks for: `md_runs(config)`, one `MDRun` per (case, dynamics) from the
config's `md:` section (its defaults merged with each case's overrides), and
`md_scaling_runs(config)`, one per (case, dynamics, N) of the 1/N studies (`md_scaling:`).

Bad values raise `ConfigError` with one line naming the case, the field, the value and the
allowed range (the record itself checks each value, `hmfdiff.dynamics.settings`).
"""

from __future__ import annotations

import dataclasses
from numbers import Real

from ..errors import ConfigError
from .settings import DYNAMICS, MDRun

__all__ = ["CONFIG_KEYS", "md_runs", "md_scaling_runs", "scaling_kappa0", "scaling_seeds"]

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


#: keys of the config's md_scaling section, and of each of its studies
SCALING_KEYS = ("studies",)
STUDY_KEYS = ("sizes", "seeds", "run", "kappa0")
#: fields of `run` that the study sets itself (sizes, seeds)
_STUDY_SET = ("n_particles", "seeds", "seeds_bath", "seeds_full")


def _scaling_studies(config):
    """The md_scaling section's {case: study}, its shape checked, or {} when absent."""
    sc = config.get("md_scaling")
    if not sc:
        return {}
    if not isinstance(sc, dict):
        raise ConfigError("md_scaling: must be a mapping with the field 'studies'")
    unknown = sorted(set(sc) - set(SCALING_KEYS))
    if unknown:
        raise ConfigError(
            f"md_scaling: unknown field(s) {unknown}; known: {list(SCALING_KEYS)} "
            "(one study per case: md_scaling: {studies: {<case>: {sizes, seeds, run}}})"
        )
    studies = sc.get("studies")
    if not isinstance(studies, dict) or not studies:
        raise ConfigError(
            f"md_scaling: field 'studies' = {studies!r} must be a non-empty mapping of case "
            "name -> {sizes, seeds, run, kappa0}"
        )
    return studies


def _whole_numbers(values, lo):
    return all(
        isinstance(n, Real) and not isinstance(n, bool) and float(n).is_integer() and n >= lo
        for n in values
    )


def scaling_seeds(study, sizes, where):
    """{N: seeds} of one study: `seeds` one integer >= 2 for every size, or a list of one per
    size (in the order of `sizes`)."""
    seeds = study.get("seeds")
    per = seeds if isinstance(seeds, list) else [seeds] * len(sizes)
    if len(per) != len(sizes) or not _whole_numbers(per, 2):
        raise ConfigError(
            f"{where}: field 'seeds' = {seeds!r} must be an integer >= 2 (the error of N*D comes "
            f"from the spread between seeds) or a list of one such per size ({len(sizes)} sizes)"
        )
    return {int(n): int(s) for n, s in zip(sizes, per, strict=True)}


def scaling_kappa0(config):
    """{case: [kappa0, ...] or None} of the md_scaling studies: the bins that figure 15 draws
    (those whose centres lie nearest each kappa0), None for the default choice."""
    out = {}
    for case, study in _scaling_studies(config).items():
        k = (study or {}).get("kappa0")
        if k is not None and not (isinstance(k, list) and k and _positive(k)):
            raise ConfigError(
                f"md_scaling study '{case}': field 'kappa0' = {k!r} must be a non-empty list of "
                "numbers > 0 (the bins drawn in figure 15)"
            )
        out[case] = None if k is None else [float(x) for x in k]
    return out


def _positive(values):
    return all(isinstance(x, Real) and not isinstance(x, bool) and x > 0 for x in values)


def md_scaling_runs(config):
    """{(case, dynamics, N): MDRun} of the 1/N scaling studies (config section md_scaling), or
    {} when the section is absent.

    md_scaling: studies: {case: {sizes, seeds, run, kappa0}}: for each case (a case with a
    smooth f; it need not be under md.runs) the sizes N (distinct integers >= 1), the seeds
    per size (an integer >= 2, or a list parallel to sizes), and `run`: MD settings that
    override, for these runs, the md section's defaults and the case's own settings under
    md.runs (if any), e.g. a shorter t_max, fewer test particles; kappa0 picks the bins that
    figure 15 draws (`scaling_kappa0`).  Raises ConfigError naming the study and the field on
    a bad value."""
    md = config.get("md")
    if md is None:
        raise ConfigError("config: missing required field(s) ['md']")
    cases = config.get("cases") or {}
    out = {}
    for case, study in _scaling_studies(config).items():
        where = f"md_scaling study '{case}'"
        if not isinstance(study, dict):
            raise ConfigError(f"{where}: must be a mapping with the fields {list(STUDY_KEYS)}")
        unknown = sorted(set(study) - set(STUDY_KEYS))
        if unknown:
            raise ConfigError(f"{where}: unknown field(s) {unknown}; known: {list(STUDY_KEYS)}")
        if case not in cases:
            raise ConfigError(f"{where}: names case '{case}', which is not in 'cases'")
        if cases[case].get("kind") == "two_step":
            raise ConfigError(f"{where}: a two-step state has no smooth f to sample MD from")
        sizes = study.get("sizes")
        ok = isinstance(sizes, list) and len(sizes) >= 1 and _whole_numbers(sizes, 1)
        if not ok or len(set(sizes)) != len(sizes):
            raise ConfigError(f"{where}: field 'sizes' = {sizes!r} must be distinct integers >= 1")
        seeds = scaling_seeds(study, sizes, where)
        over = dict(study.get("run") or {})
        bad = sorted(set(over) - set(CONFIG_KEYS))
        if bad:
            raise ConfigError(f"{where}: unknown field(s) {bad} under 'run'")
        bad = sorted(set(over) & set(_STUDY_SET))
        if bad:
            raise ConfigError(
                f"{where}: field(s) {bad} under 'run' are set by the study's 'sizes' and 'seeds'"
            )
        s = {k: v for k, v in md.items() if k != "runs"}
        s.update((md.get("runs") or {}).get(case) or {})
        s.update(over)
        # the MDRun fields; n_particles, n_test and seeds are set per dynamics and size below
        keep = set(CONFIG_KEYS) - {"n_particles", "seeds", *_STUDY_SET}
        fields = {k: v for k, v in s.items() if k in keep and not k.startswith("n_test_")}
        for dynamics in DYNAMICS:
            if f"n_test_{dynamics}" not in s:
                raise ConfigError(f"{where}: missing required field 'n_test_{dynamics}'")
            track = fields.get("n_track")
            for n in sizes:
                n = int(n)
                base = {
                    **fields,
                    "case": f"{case} (md_scaling)",
                    "dynamics": dynamics,
                    "n_test": s[f"n_test_{dynamics}"],
                    "n_particles": n,
                    "seeds": seeds[n],
                }
                if track is not None:  # a subset larger than N tracks all N
                    base["n_track"] = min(int(track), n)
                out[(case, dynamics, n)] = MDRun(**base)
    return out
