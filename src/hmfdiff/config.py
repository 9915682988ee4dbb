"""Physics-level checks of a pipeline configuration, with messages that name case and field.

The JSON schema (workflow/schemas/config.schema.yaml) checks structure and types; this module
checks what a schema cannot say well: that a thermal state is given by exactly one of M0 and u,
that u lies below the magnetised branch, that figures name existing cases, and so on.  All checks
run when the workflow is parsed, before any job starts.
"""

from __future__ import annotations

import math
import re

from .equilibrium import U_CRITICAL, U_MINIMUM

__all__ = ["ConfigError", "check_config", "CASE_NAME"]

CASE_NAME = re.compile(r"^[A-Za-z0-9_.+-]+$")


class ConfigError(ValueError):
    """An invalid configuration value; the message names the case (or section) and the field."""


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
