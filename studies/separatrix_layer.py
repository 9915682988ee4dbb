"""The kinetic relaxation time and the early rate of M0 against the grid's resolution of the layer
next to the separatrix.

    python studies/separatrix_layer.py eta_min CASE EQUATION [ETA_MIN ...]
    python studies/separatrix_layer.py grid CASE EQUATION [FACTOR ...]
    python studies/separatrix_layer.py derivative CASE EQUATION [face|interpolated|mixed ...]
    python studies/separatrix_layer.py n_max CASE EQUATION [N_MAX ...]
    python studies/separatrix_layer.py all                     # the table of the docs
    python studies/separatrix_layer.py --derivative=mixed grid CASE EQUATION [FACTOR ...]
    python studies/separatrix_layer.py uncertainty OUT.csv [CASE:EQUATION ...]
    python studies/separatrix_layer.py finite_n EQUATION [N ...]
    python studies/separatrix_layer.py early CASE EQUATION FACTOR:EARLY_RTOL[:DLOG_OMEGA] ...
    python studies/separatrix_layer.py early_entropy CASE EQUATION

CASE: ch2 (the paper's ch2*) or hot (the hot halo of figures 11-13); EQUATION: landau or
lenard_balescu.  Each line is one evolution from the state to thermalisation (rtol = thermal_tol
= 1e-3, the reproduction's settings) with the default grid of config/config.yaml but for the one
setting varied: the innermost node pair at kappa = 1 -+ eta_min (`layer_eta_min`); the whole
grid refined by a FACTOR (`n_nodes` times it, and with it the resolution in ln Omega,
`dlog_omega` = 6/n_nodes: that resolution grades the grid next to the separatrix, where
Omega -> 0 as 1/ln(1/|kappa - 1|));
or how the resonances read d ln f/dh within a face (`kinetic.relaxation.DERIVATIVE`: the face's
own difference quotient, first order, or interpolated to the resonance, second order, with the
current shared between faces or, 'mixed', handed to the resonance's face); or the harmonics
kept (`n_max` and `l_max` together).  It prints tau_R (fine-grained entropy deficit / e),
tau_R^coarse (the same on the N-body ensembles' 40 J-bar bins to kappa = 3, as
results/relaxation_comparison), dM0/dtau at tau = 0 (`dM0dtau_initial`), the mean rate over
tau <= 0.5 (`dM0dtau_early`, the window of results/relaxation_rates), the number of
nodes and the wall time.  Runs on one core.  Output of `all`: docs/reference/separatrix_layer.txt.

`uncertainty`: for each case and equation (default: both of both), three evolutions with the
reproduction's own settings (config/config.yaml's relaxation block and the case's run, so that
its default line is the pipeline's number): as they are, with 1.5 times the nodes, and with the
harmonics n_max = l_max = 8.  It prints their lines and writes OUT.csv, the table from which
results/relaxation_comparison draws the kinetic times' uncertainty bands (figures 13 and 16):
docs/reference/kinetic_time_uncertainty.csv.

`early`: the early window alone (tau_max = 0.6): dM0/dtau over tau <= 0.5 with the grid refined
by FACTOR (or only its layer: DLOG_OMEGA given) and the early window's step tolerance
EARLY_RTOL, to separate the time step's error from the grid's.

`early_entropy`: the kinetic change of the coarse-grained entropy over tau <= 0.5 per unit tau
(dS/tau*, on the early-window ensembles' 40 J-bar bins up to kappa = 3, as
results/relaxation_rates computes it) with the reproduction's settings, with 1.5 times the
nodes, with n_max = l_max = 8, and with the window's steps at early_rtol = 1e-6: the numerical
uncertainty of the kinetic value the N-body's early entropy change is divided by.

`finite_n`: the finite-N layer model of the hot halo.  The N-body's separatrix is smeared over
|kappa - 1| < delta(N) (docs/reference/separatrix_crossings.txt: delta_rate, the step of the
random walk in kappa that gives the measured rate of family changes, 0.273 N^-0.490); the model
is the kinetic equation on the reproduction's grid with the innermost cells spanning that layer
(layer_eta_min = delta(N): one cell a side, f uniform within it, no orbit closer to the
separatrix than the cell's average).  No parameter is fitted: delta(N) is the N-body's.  It
prints tau_R^coarse (the prediction of the N-body t_R/N) and dM0/dtau over tau <= 0.5.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from hmfdiff.analysis.relaxation_compare import _coarse_entropy  # noqa: E402
from hmfdiff.analysis.relaxation_md import (  # noqa: E402
    kinetic_bin_fractions,
    relaxation_time,
    state_bin_fractions,
)
from hmfdiff.analysis.relaxation_rates import entropy_from_histogram  # noqa: E402
from hmfdiff.kinetic import relaxation  # noqa: E402
from hmfdiff.kinetic.relaxation import RelaxationSettings, evolve  # noqa: E402
from hmfdiff.meanfield import orbits  # noqa: E402
from hmfdiff.meanfield.equilibrium import ThermalState, make_state  # noqa: E402
from hmfdiff.pipeline.layouts.kinetic_relaxation import relaxation_times  # noqa: E402

CASES = {
    "ch2": (
        dict(
            kind="core_halo", eta1=0.298, eta2=0.051, mu1=-0.517, mu2=0.19, beta1=30.0, beta2=10.0
        ),
        2.5,
    ),
    "hot": (
        dict(kind="core_halo", eta1=0.3, eta2=0.01, mu1=-0.5, mu2=1.2, beta1=40.0, beta2=2.0),
        3.5,
    ),
}
#: the reproduction's settings (config/config.yaml relaxation block)
BASE = dict(rtol=1e-3, thermal_tol=1e-3, tau_max=1e5)
VARY = ("eta_min", "grid", "derivative", "n_max")
#: the pipeline's names of the cases
CASE_NAMES = {"ch2": "corehalo_ch2", "hot": "corehalo_hothalo"}
#: the uncertainty table: refinement factor of the grid and the harmonics of the check
GRID_CHECK, N_MAX_CHECK = 1.5, 8
UNCERTAINTY_COLUMNS = (
    "case equation derivative settings tau_R_fine tau_R_fine_grid tau_R_fine_harmonics "
    "tau_R_coarse tau_R_coarse_grid tau_R_coarse_harmonics dM0dtau_early dM0dtau_early_grid "
    "dM0dtau_early_harmonics grid_factor n_max_check"
).split()


def pipeline_settings(case):
    """The relaxation settings of config/config.yaml for the case (block, then the run)."""
    import yaml

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with open(os.path.join(root, "config", "config.yaml")) as fh:
        block = dict(yaml.safe_load(fh)["relaxation"])
    run = (block.pop("runs", None) or {}).get(CASE_NAMES[case]) or {}
    for key in ("equations", "check_stability"):
        block.pop(key, None)
    return {**block, **run}


def layer_width(n, path=None):
    """delta(N) of the hot halo: the power law fitted to delta_rate in
    docs/reference/separatrix_crossings.txt (the line '#   hot     delta_rate   b = ...')."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = path or os.path.join(root, "docs", "reference", "separatrix_crossings.txt")
    with open(path) as fh:
        for text in fh:
            words = text.split()
            if words[:3] == ["#", "hot", "delta_rate"]:
                b = float(words[words.index("b") + 2])
                a = float(words[words.index("a") + 2])
                return a * float(n) ** b
    raise ValueError(f"{path}: no hot delta_rate line")


def early(case, equation, specs):
    """The `early` lines (see the module's docstring)."""
    default = RelaxationSettings()
    for spec in specs:
        parts = spec.split(":")
        factor, early_rtol = float(parts[0]), float(parts[1])
        kw = {"n_nodes": int(round(default.n_nodes * factor)), "early_rtol": early_rtol}
        kw["tau_max"] = 0.6
        label = f"x{factor:g} early_rtol={early_rtol:g}"
        if len(parts) > 2:
            kw["dlog_omega"] = float(parts[2])
            label += f" dlog_omega={float(parts[2]):g}"
        print(line(case, equation, label, one(case, equation, **kw)), flush=True)


def finite_n(equation, sizes):
    """The `finite_n` lines (see the module's docstring)."""
    base = pipeline_settings("hot")
    base["flux_times"] = tuple(float(t) for t in base.get("flux_times", (0.0,)))
    spec, _ = CASES["hot"]
    for n in sizes:
        delta = layer_width(n)
        settings = RelaxationSettings(equation=equation, **{**base, "layer_eta_min": delta})
        state = make_state(spec)
        r = measured(state, settings)
        print(line("hot", equation, f"N={int(n)} delta={delta:.3e}", r), flush=True)


def uncertainty(out_path, pairs):
    """The `uncertainty` table (see the module's docstring)."""
    import csv
    import json

    rows = []
    for case, equation in pairs:
        base = pipeline_settings(case)
        if "flux_times" in base:
            base["flux_times"] = tuple(float(t) for t in base["flux_times"])
        runs = {
            "": dict(base),
            "_grid": {**base, "n_nodes": int(round(base.get("n_nodes", 600) * GRID_CHECK))},
            "_harmonics": {**base, "n_max": N_MAX_CHECK, "l_max": N_MAX_CHECK},
        }
        labels = {"": "pipeline", "_grid": f"grid x{GRID_CHECK:g}", "_harmonics": "n_max=8"}
        row = {
            "case": CASE_NAMES[case],
            "equation": equation,
            "derivative": relaxation.DERIVATIVE,
            "grid_factor": GRID_CHECK,
            "n_max_check": N_MAX_CHECK,
        }
        for suffix, kw in runs.items():
            spec, _ = CASES[case]
            settings = RelaxationSettings(equation=equation, **kw)
            state = make_state(spec)
            r = measured(state, settings)
            print(line(case, equation, labels[suffix], r), flush=True)
            if suffix == "":
                row["settings"] = json.dumps(settings.as_dict(), sort_keys=True, default=list)
            row[f"tau_R_fine{suffix}"] = r["tau_fine"]
            row[f"tau_R_coarse{suffix}"] = r["tau_coarse"]
            row[f"dM0dtau_early{suffix}"] = r["dM0_early"]
        rows.append(row)
        with open(out_path, "w", newline="") as fh:  # rewritten after each pair: partial runs
            w = csv.DictWriter(fh, fieldnames=UNCERTAINTY_COLUMNS)
            w.writeheader()
            w.writerows(rows)


def early_entropy(case, equation):
    """The `early_entropy` lines (see the module's docstring)."""
    base = pipeline_settings(case)
    if "flux_times" in base:
        base["flux_times"] = tuple(float(t) for t in base["flux_times"])
    spec, _ = CASES[case]
    state = make_state(spec)
    edges = np.linspace(0.0, float(orbits.rescaled_action(3.0, state.M0)), 41)
    n_nodes = base.get("n_nodes", 600)
    variants = [
        ("pipeline", {}),
        (f"grid x{GRID_CHECK:g}", {"n_nodes": int(round(n_nodes * GRID_CHECK))}),
        (f"n_max={N_MAX_CHECK}", {"n_max": N_MAX_CHECK, "l_max": N_MAX_CHECK}),
        ("early_rtol=1e-6", {"early_rtol": 1e-6}),
    ]
    head = f"{'case':5s} {'equation':15s} {'setting':>16s} {'tau*':>8s} {'dS/tau*':>11s}"
    print(f"{head} {'wall/s':>7s}")
    for label, kw in variants:
        settings = RelaxationSettings(equation=equation, **{**base, **kw, "tau_max": 0.6})
        t0 = time.perf_counter()
        out = evolve(state, settings)
        wall = time.perf_counter() - t0
        tau = np.asarray(out["tau"])
        P = kinetic_bin_fractions(out["jbar"], out["width"], out["f"], edges)
        k = int(np.argmin(np.abs(tau - settings.early_window)))
        S0, S1 = (entropy_from_histogram(P[i], edges, max(0.0, 1.0 - P[i].sum())) for i in (0, k))
        rate = (S1 - S0) / tau[k]
        print(
            f"{case:5s} {equation:15s} {label:>16s} {tau[k]:8.6f} {rate:11.6g} {wall:7.0f}",
            flush=True,
        )


def coarse_time(out, state):
    """tau_R^coarse: the coarse-grained entropy deficit on the ensembles' 40 J-bar bins up to
    J-bar(kappa = 3) at the state's M0 fallen by e (as `analysis.relaxation_compare`)."""
    edges = np.linspace(0.0, float(orbits.rescaled_action(3.0, state.M0)), 41)
    thermal = ThermalState(u=float(out["u"][0]))
    S_eq = float(_coarse_entropy(state_bin_fractions(thermal, edges), edges))
    P = kinetic_bin_fractions(out["jbar"], out["width"], out["f"], edges)
    return relaxation_time(out["tau"], S_eq - _coarse_entropy(P, edges))


def one(case, equation, **kw):
    spec, kappa_max = CASES[case]
    state = make_state(spec)
    settings = RelaxationSettings(equation=equation, kappa_max=kappa_max, **{**BASE, **kw})
    return measured(state, settings)


def measured(state, settings):
    """One evolution and what the table prints of it."""
    t0 = time.perf_counter()
    out = evolve(state, settings)
    wall = time.perf_counter() - t0
    tau_fine, _ = relaxation_times(out)
    return {
        "tau_fine": tau_fine,
        "tau_coarse": coarse_time(out, state),
        "dM0_initial": float(out["dM0dtau_initial"]),
        "dM0_early": float(out["dM0dtau_early"]),
        "nodes": int(out["eta"].size),
        "thermalised": out["thermalised"],
        "du": float(np.max(np.abs(out["u"] - out["u"][0]))),
        "wall": wall,
    }


HEADER = (
    f"{'case':5s} {'equation':15s} {'setting':>22s} {'nodes':>6s} {'tau_R':>9s} "
    f"{'tau_R^coarse':>12s} {'dM0/dtau(0)':>12s} {'dM0/dtau<=0.5':>13s} {'|du|':>8s} {'wall/s':>7s}"
)


def line(case, equation, label, r):
    return (
        f"{case:5s} {equation:15s} {label:>22s} {r['nodes']:6d} {r['tau_fine']:9.2f} "
        f"{r['tau_coarse']:12.3f} {r['dM0_initial']:12.5e} {r['dM0_early']:13.5e} "
        f"{r['du']:8.1e} {r['wall']:7.0f}" + ("" if r["thermalised"] else "  (not thermalised)")
    )


def sweep(kind, case, equation, values, derivative=None):
    """One line per value; `derivative` (a `kinetic.relaxation.DERIVATIVE` option) for every
    line of a sweep of another setting."""
    default = RelaxationSettings()
    for v in values:
        if kind == "eta_min":
            kw, label = {"layer_eta_min": float(v)}, f"eta_min={float(v):g}"
        elif kind == "grid":
            factor = float(v)
            kw = {"n_nodes": int(round(default.n_nodes * factor))}  # dlog_omega = 6/n_nodes
            label = f"grid x{factor:g}"
        elif kind == "n_max":  # the resonances' and the dielectric's harmonics together
            kw, label = {"n_max": int(v), "l_max": int(v)}, f"n_max={int(v)}"
        else:
            kw, label = {}, f"derivative={v}"
        saved = relaxation.DERIVATIVE
        relaxation.DERIVATIVE = v if kind == "derivative" else (derivative or saved)
        if derivative and kind != "derivative":
            label = f"{derivative} {label}"
        try:
            r = one(case, equation, **kw)
        finally:
            relaxation.DERIVATIVE = saved
        print(line(case, equation, label, r), flush=True)


#: the table of docs/reference/separatrix_layer.txt
ALL = [
    ("eta_min", ["1e-2", "1e-4", "1e-8", "1e-16", "1e-32", "1e-64"]),
    ("grid", ["0.5", "1", "1.5", "2"]),
    ("derivative", ["face", "mixed"]),
    ("n_max", ["4", "6", "8"]),
]


def main(argv):
    derivative = None
    if argv and argv[0].startswith("--derivative="):
        derivative, argv = argv[0].split("=", 1)[1], argv[1:]
        if derivative not in ("face", "interpolated", "mixed"):
            print(f"--derivative: {derivative!r} is not one of face, interpolated, mixed")
            return 2
    if not argv:
        print(__doc__)
        return 2
    if argv[0] == "early" and len(argv) >= 4 and argv[1] in CASES:
        print(HEADER)
        early(argv[1], argv[2], argv[3:])
        return 0
    if argv[0] == "early_entropy" and len(argv) == 3 and argv[1] in CASES:
        early_entropy(argv[1], argv[2])
        return 0
    if argv[0] == "finite_n" and len(argv) >= 2:
        print(HEADER)
        finite_n(argv[1], [float(n) for n in argv[2:]] or [1e3, 2e3, 4e3, 8e3, 1.6e4, 6.4e4])
        return 0
    if argv[0] == "uncertainty" and len(argv) >= 2:
        pairs = [tuple(a.split(":")) for a in argv[2:]] or [
            (c, e) for c in ("ch2", "hot") for e in ("landau", "lenard_balescu")
        ]
        if not all(len(p) == 2 and p[0] in CASES for p in pairs):
            print(__doc__)
            return 2
        print(HEADER)
        uncertainty(argv[1], pairs)
        return 0
    if argv[0] == "all":
        print(HEADER)
        for case in ("ch2", "hot"):
            for equation in ("landau", "lenard_balescu"):
                for kind, values in ALL:
                    sweep(kind, case, equation, values)
        return 0
    kind, case, equation, values = argv[0], argv[1], argv[2], argv[3:]
    if kind not in VARY or case not in CASES or equation not in ("landau", "lenard_balescu"):
        print(__doc__)
        return 2
    print(HEADER)
    sweep(kind, case, equation, values, derivative)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
