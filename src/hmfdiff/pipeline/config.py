"""Physics-level checks of a pipeline configuration, with messages that name case and field.

The JSON schema (workflow/schemas/config.schema.yaml) checks structure and types; this module
checks what a schema cannot say well: that a thermal state is given by exactly one of M0 and u,
that u lies below the magnetised branch, that figures name existing cases, and so on.  All checks
run when the workflow is parsed, before any job starts.
"""

from __future__ import annotations

import math
import re

from ..errors import ConfigError
from ..meanfield.equilibrium import U_CRITICAL, U_MINIMUM

__all__ = ["ConfigError", "check_config", "CASE_NAME"]

CASE_NAME = re.compile(r"^[A-Za-z0-9_.+-]+$")


def _number(where, field, value):
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ConfigError(f"{where}: field '{field}' = {value!r} must be a finite number")
    return float(value)


def _in_range(where, field, value, lo, hi, lo_open=True, hi_open=True, why=""):
    v = _number(where, field, value)
    bad_lo = v <= lo if lo_open else v < lo
    bad_hi = v >= hi if hi_open else v > hi
    if bad_lo or bad_hi:
        lb = "(" if lo_open else "["
        rb = ")" if hi_open else "]"
        raise ConfigError(
            f"{where}: field '{field}' = {value!r} is outside the allowed range {lb}{lo}, {hi}{rb}"
            + (f" ({why})" if why else "")
        )
    return v


def _require(where, spec, fields):
    missing = [f for f in fields if f not in spec]
    if missing:
        raise ConfigError(f"{where}: missing required field(s) {missing}")


def check_case(name, spec):
    """Check one equilibrium case of `cases:`."""
    where = f"case '{name}'"
    if not CASE_NAME.match(str(name)):
        raise ConfigError(f"{where}: case names may contain only letters, digits and _ . + -")
    if not isinstance(spec, dict):
        raise ConfigError(f"{where}: must be a mapping with a 'kind' field")
    _require(where, spec, ["kind"])
    kind = spec["kind"]
    if kind == "thermal":
        has_m, has_u = "M0" in spec, "u" in spec
        if has_m == has_u:
            raise ConfigError(f"{where}: a thermal state takes exactly one of 'M0' or 'u'")
        if has_m:
            _in_range(where, "M0", spec["M0"], 0.0, 1.0, why="magnetisation of a magnetised state")
        else:
            _in_range(
                where,
                "u",
                spec["u"],
                U_MINIMUM,
                U_CRITICAL,
                why="energy per particle on the magnetised thermal branch, u_c = 1/4",
            )
    elif kind in ("core_halo", "two_step"):
        fields = ["eta1", "eta2", "mu1", "mu2"] + (
            ["beta1", "beta2"] if kind == "core_halo" else []
        )
        _require(where, spec, fields)
        for f in ("eta1", "eta2"):
            _in_range(where, f, spec[f], 0.0, math.inf, lo_open=False, why="phase-space density")
        for f in ("mu1", "mu2"):
            _in_range(where, f, spec[f], -1.0, math.inf, why="energy level h >= -M0 > -1")
        if kind == "core_halo":
            for f in ("beta1", "beta2"):
                _in_range(where, f, spec[f], 0.0, math.inf, why="inverse temperature of a step")
        if spec["eta1"] + spec["eta2"] <= 0:
            raise ConfigError(f"{where}: eta1 + eta2 must be > 0")
    else:
        raise ConfigError(
            f"{where}: field 'kind' = {kind!r} must be 'thermal', 'core_halo' or 'two_step'"
        )


_MD_KEYS = (
    "dt",
    "t_equilibrate",
    "t_max",
    "sample_every",
    "max_lag",
    "origin_every",
    "n_blocks",
    "threads",
    "kappa_max",
    "n_bins",
    "n_test_bath",
    "n_test_full",
    "seeds",
    "fit_window",
    "min_particles",
    "separatrix_band_fit",
)


def _int_at_least(where, field, value, lo):
    if isinstance(value, bool) or not isinstance(value, int) or value < lo:
        raise ConfigError(f"{where}: field '{field}' = {value!r} must be an integer >= {lo}")


def _check_md(config):
    """MD section: every run's settings (defaults merged with the run's own) are checked."""
    md = config.get("md")
    if md is None:
        raise ConfigError("config: missing required field(s) ['md']")
    runs = md.get("runs")
    if not isinstance(runs, dict):
        raise ConfigError("md: field 'runs' must be a mapping of case name -> run settings")
    for case, run in runs.items():
        where = f"md run '{case}'"
        if case not in config["cases"]:
            raise ConfigError(f"{where}: names case '{case}', which is not in 'cases'")
        if config["cases"][case]["kind"] == "two_step":
            raise ConfigError(f"{where}: a two-step state has no smooth f to sample MD from")
        s = {k: md[k] for k in _MD_KEYS if k in md}
        s.update(run or {})
        missing = [k for k in ("n_particles", *_MD_KEYS) if k not in s]
        if missing:
            raise ConfigError(f"{where}: missing required field(s) {missing}")
        _int_at_least(where, "n_particles", s["n_particles"], 1)
        for f, lo in (
            ("n_test_bath", 1),
            ("n_test_full", 0),
            ("seeds", 1),
            ("n_bins", 1),
            ("n_blocks", 1),
            ("threads", 1),
            ("min_particles", 0),
        ):
            _int_at_least(where, f, s[f], lo)
        for f in ("dt", "t_max", "sample_every", "max_lag", "origin_every", "kappa_max"):
            _in_range(where, f, s[f], 0.0, math.inf)
        _in_range(where, "t_equilibrate", s["t_equilibrate"], 0.0, math.inf, lo_open=False)
        if s["max_lag"] > s["t_max"]:
            raise ConfigError(f"{where}: max_lag = {s['max_lag']} exceeds t_max = {s['t_max']}")
        w = s["fit_window"]
        if not isinstance(w, list | tuple) or len(w) != 2:
            raise ConfigError(f"{where}: field 'fit_window' = {w!r} must be [t_min, t_max]")
        t0 = _in_range(where, "fit_window[0]", w[0], 0.0, math.inf, lo_open=False)
        t1 = _number(where, "fit_window[1]", w[1])
        if not t0 < t1 <= s["max_lag"]:
            raise ConfigError(
                f"{where}: field 'fit_window' = {list(w)} must satisfy 0 <= t_min < t_max <= "
                f"max_lag = {s['max_lag']} (the fit needs measured lags; the run is "
                f"t_max = {s['t_max']} long)"
            )
        for f, base in (
            ("sample_every", "dt"),
            ("max_lag", "sample_every"),
            ("origin_every", "sample_every"),
            ("t_max", "sample_every"),
        ):
            ratio = s[f] / s[base]
            if abs(ratio - round(ratio)) > 1e-9 * max(1.0, ratio):
                raise ConfigError(
                    f"{where}: field '{f}' = {s[f]} must be a whole multiple of {base} = {s[base]}"
                )


def check_config(config):
    """Check a whole configuration dictionary; raise ConfigError on the first problem."""
    if not isinstance(config, dict):
        raise ConfigError("config: top level must be a mapping")
    _require("config", config, ["cases", "grids", "theory", "figures"])
    cases = config["cases"]
    if not isinstance(cases, dict) or not cases:
        raise ConfigError("config: 'cases' must be a non-empty mapping of case name -> state")
    for name, spec in cases.items():
        check_case(name, spec)

    grids = config["grids"]
    for section in ("equilibrium", "orbits"):
        _require("config: grids", grids, [section])
        g = grids[section]
        where = f"grids.{section}"
        _require(where, g, ["n_kappa", "kappa_max"])
        n = g["n_kappa"]
        if isinstance(n, bool) or not isinstance(n, int) or n < 16:
            raise ConfigError(f"{where}: field 'n_kappa' = {n!r} must be an integer >= 16")
        _in_range(
            where, "kappa_max", g["kappa_max"], 1.0, 1e3, why="must lie beyond the separatrix"
        )
    if "n_max" in grids["orbits"]:
        n = grids["orbits"]["n_max"]
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 64:
            raise ConfigError(f"grids.orbits: field 'n_max' = {n!r} must be an integer in [1, 64]")

    th = config["theory"]
    where = "theory"
    _require(where, th, ["n_kappa", "kappa_min", "kappa_max", "separatrix_band", "n_max", "l_max"])
    for f, lo in (("n_kappa", 8), ("n_max", 1), ("l_max", 1)):
        v = th[f]
        if isinstance(v, bool) or not isinstance(v, int) or v < lo:
            raise ConfigError(f"{where}: field '{f}' = {v!r} must be an integer >= {lo}")
    _in_range(where, "kappa_min", th["kappa_min"], 0.0, 1.0)
    _in_range(where, "kappa_max", th["kappa_max"], 1.0, 1e3)
    _in_range(
        where,
        "separatrix_band",
        th["separatrix_band"],
        0.0,
        0.5,
        why="half-width of the masked band around kappa = 1",
    )

    _check_md(config)

    for fig, spec in config["figures"].items():
        where = f"figure '{fig}'"
        if not isinstance(spec, dict):
            raise ConfigError(f"{where}: must be a mapping")
        names = list(spec.get("cases", [spec["case"]] if "case" in spec else []))
        names += list(spec.get("core_halo", []))
        names += [spec[k] for k in ("two_step", "thermal") if k in spec]
        for c in names:
            if c not in cases:
                raise ConfigError(f"{where}: names case '{c}', which is not in 'cases'")
