"""The numerical uncertainty of the kinetic relaxation times, and N-body relaxation times kept as
reference copies.

The kinetic relaxation time of a state is a number once the grid resolves the layer next to the
separatrix, but the default grid and harmonics leave an error of a few per cent
(docs/findings.md).  It is measured once, by `studies/separatrix_layer.py uncertainty`, with
the reproduction's own settings: each case and equation evolved as the pipeline does, with 1.5
times the nodes, and with the harmonics n_max = l_max = 8.  That table
(docs/reference/kinetic_time_uncertainty.csv) is read here:

    rel_grid = tau(grid x1.5) / tau - 1,    rel_harmonics = tau(n_max = 8) / tau - 1,

and the band drawn round a time tau is [tau (1 + sum of the negative rel), tau (1 + sum of the
positive rel)]: from the default's value towards the refined ones, both directions added.  The
band applies only to an evolution with the table's settings and the same value: a run whose
settings differ gets none, and one whose value moved by more than `STALE` from the table's
(the code changed since the table was made) gets none and a warning, never a band that belongs
to another calculation.
"""

from __future__ import annotations

import csv
import json
import re
import warnings

import numpy as np

__all__ = [
    "STALE",
    "SETTINGS_COMPARED",
    "read_uncertainty_table",
    "time_band",
    "md_times_from_summary",
    "layer_model_times",
]

#: relative difference between an evolution's time and the table's above which the table is
#: taken as stale (the study and the pipeline run the same code with the same settings and
#: agree to the step control's tolerance)
STALE = 0.01
#: the settings that must agree for the table to apply
SETTINGS_COMPARED = (
    "n_nodes",
    "kappa_max",
    "n_max",
    "l_max",
    "rtol",
    "thermal_tol",
    "early_rtol",
    "layer_eta_min",
    "dlog_omega",
    "min_per_decade",
    "feature_share",
    "separatrix_share",
    "eps_panels",
    "eps_order",
    "eps_refresh",
)
_QUANTITIES = ("tau_R_fine", "tau_R_coarse", "dM0dtau_early")
_COLUMNS = ("case", "equation", "settings") + tuple(
    f"{q}{s}" for q in _QUANTITIES for s in ("", "_grid", "_harmonics")
)


def read_uncertainty_table(path):
    """Rows of the table as dicts (numbers as floats, settings as a dict); a one-line error
    naming the file and the missing columns if it is not the table."""
    with open(path, newline="") as fh:
        reader = csv.DictReader(fh)
        missing = [c for c in _COLUMNS if c not in (reader.fieldnames or ())]
        if missing:
            raise ValueError(f"{path}: not the kinetic uncertainty table (missing {missing})")
        rows = []
        for r in reader:
            row = dict(r)
            row["settings"] = json.loads(r["settings"])
            for c in _COLUMNS[3:]:
                row[c] = float(r[c])
            rows.append(row)
    return rows


def _same_settings(a, b):
    for key in SETTINGS_COMPARED:
        x, y = a.get(key), b.get(key)
        if x is None or y is None:
            if x is not y:
                return False
        elif not np.isclose(float(x), float(y), rtol=1e-12, atol=0.0):
            return False
    return True


def time_band(rows, case, equation, settings, quantity, value):
    """(low, high, rel_grid, rel_harmonics) of `quantity` ('tau_R_fine', 'tau_R_coarse' or
    'dM0dtau_early') of the evolution of `case` by `equation` with `settings`
    (RelaxationSettings.as_dict) whose value is `value`; None where the table has no row for
    it, its settings differ, or (with a warning) its value differs from `value` by more than
    STALE."""
    if quantity not in _QUANTITIES:
        raise ValueError(f"quantity = {quantity!r}: one of {_QUANTITIES}")
    row = next((r for r in rows if r["case"] == case and r["equation"] == equation), None)
    if row is None or not _same_settings(row["settings"], settings):
        return None
    ref = row[quantity]
    if not (np.isfinite(ref) and np.isfinite(value)) or abs(value / ref - 1.0) > STALE:
        warnings.warn(
            f"kinetic uncertainty table: {case} {equation} {quantity} = {ref:.6g} there, "
            f"{value:.6g} here: the table is stale (rerun studies/separatrix_layer.py "
            "uncertainty); no band drawn",
            stacklevel=2,
        )
        return None
    rel = np.array([row[f"{quantity}_grid"] / ref - 1.0, row[f"{quantity}_harmonics"] / ref - 1.0])
    low = value * (1.0 + np.sum(np.minimum(rel, 0.0)))
    high = value * (1.0 + np.sum(np.maximum(rel, 0.0)))
    return float(low), float(high), float(rel[0]), float(rel[1])


_MD_LINE = re.compile(
    r"^\s*MD N = (\d+): t_R = ([0-9.eE+-]+|nan) \+- ([0-9.eE+-]+|nan), t_R/N = ([0-9.eE+-]+|nan)"
)


def md_times_from_summary(text, case):
    """{N: (t_R, error)} of `case` read from a relaxation_comparison_summary.txt (the lines
    'MD N = ...: t_R = ... +- ...' under 'case <case>:')."""
    out, current = {}, None
    for line in text.splitlines():
        if line.startswith("case "):
            current = line[5:].split(":", 1)[0].strip()
            continue
        m = _MD_LINE.match(line)
        if m and current == case:
            out[int(m.group(1))] = (float(m.group(2)), float(m.group(3)))
    return out


#: the finite-N layer model's case in studies/separatrix_layer.py finite_n
LAYER_MODEL_CASES = {"hot": "corehalo_hothalo"}
_LAYER_LINE = re.compile(
    r"^(\w+)\s+(landau|lenard_balescu)\s+N=(\d+)\s+delta=([0-9.eE+-]+)\s+(\d+)\s+([0-9.eE+-]+|nan)"
    r"\s+([0-9.eE+-]+|nan)\s+([0-9.eE+-]+|nan)\s+([0-9.eE+-]+|nan)"
)


def layer_model_times(text, case):
    """{equation: {N: (delta, tau_R^coarse, dM0/dtau early)}} of `case` from the output of
    `studies/separatrix_layer.py finite_n` (docs/reference/finite_n_layer.txt)."""
    out = {}
    for line in text.splitlines():
        m = _LAYER_LINE.match(line)
        if not m or LAYER_MODEL_CASES.get(m.group(1)) != case:
            continue
        delta, tau_coarse, early = float(m.group(4)), float(m.group(7)), float(m.group(9))
        out.setdefault(m.group(2), {})[int(m.group(3))] = (delta, tau_coarse, early)
    return out
