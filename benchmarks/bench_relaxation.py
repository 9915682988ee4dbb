"""Cost and convergence of the collisional relaxation.

    python benchmarks/bench_relaxation.py                    # ch2*: one evolution per equation
    python benchmarks/bench_relaxation.py --study nmax       # ch2*: dependence on n_max
    python benchmarks/bench_relaxation.py --study convergence --case hot
    python benchmarks/bench_relaxation.py --study newton     # the Newton matrix, old and new
    python benchmarks/bench_relaxation.py --study cost --case hot warm ch2  # the pipeline's runs
    python benchmarks/bench_relaxation.py --study inversion --case hot  # kappa(Omega) by Newton

Runs on one core (BLAS threads pinned to 1 before numpy is imported).  The default prints the
wall time of one evolution from ch2* to thermalisation (max |f - f_eq| < thermal_tol max f_eq)
at the default settings of config/config.yaml (600 outer nodes, dlog_omega = 6/600, the layer
next to the separatrix down to |kappa - 1| = 1e-16, n_max = l_max = 6, rtol = thermal_tol =
1e-3) and the cost of one collision operator (orbits, resonances and, for Lenard-Balescu, the
dielectric tensor) and of the current it gives.  `--study nmax` prints the initial entropy
production and the relaxation time against n_max; `--study convergence` the largest change of
M0(tau) and of tau_R when rtol is halved and when the grid is refined by 1.5 (the grid's
convergence in the layer next to the separatrix: studies/separatrix_layer.py); `--study newton`
the time of one Newton matrix assembled by sparse products and by the precomputed event map
(`collision.jacobian_assembly`), the baseline measured in the same run; `--study cost` the
CPU time of the pipeline's evolutions (rule relaxation: config/config.yaml's settings and
flux_times, the warm core to tau = 1) by the present code and by the solves it replaced
(benchmarks/previous_relaxation.py), in the same run, with the largest differences of their
results: tau_R, dM0/dtau (initial, early), M0 at the end, the current at the stored times and
f at the end; `--study inversion` the same, with only kappa(Omega) (bisection before Newton's
iteration) and the tabulated state's M0 bracket swapped back.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import previous_relaxation  # noqa: E402
from previous_relaxation import previous_path, swapped  # noqa: E402

from hmfdiff.kinetic import tabulated  # noqa: E402
from hmfdiff.kinetic.grid import project_state  # noqa: E402
from hmfdiff.kinetic.relaxation import (  # noqa: E402
    Kinetics,
    RelaxationSettings,
    evolve,
    make_grid,
)
from hmfdiff.meanfield import orbits  # noqa: E402
from hmfdiff.meanfield.equilibrium import make_state  # noqa: E402
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
    "warm": (
        dict(kind="core_halo", eta1=0.3, eta2=0.01, mu1=-0.5, mu2=1.2, beta1=5.0, beta2=2.0),
        3.5,
    ),
}
#: the pipeline's runs (config/config.yaml, relaxation: runs)
PIPELINE = {"ch2": {}, "hot": {}, "warm": {"tau_max": 1.0}}
FLUX_TIMES = (0.0, 1.0, 10.0, 100.0)
EQUATIONS = ("landau", "lenard_balescu")


def settings(case, equation, **kw):
    base = dict(equation=equation, n_nodes=600, kappa_max=CASES[case][1], tau_max=1e5)
    base.update(rtol=1e-3, thermal_tol=1e-3)
    base.update(kw)
    return RelaxationSettings(**base)


def run(case, equation, **kw):
    state = make_state(CASES[case][0])
    t0 = time.perf_counter()
    out = evolve(state, settings(case, equation, **kw))
    return out, time.perf_counter() - t0


def flux_cost(case, equation, repeat=3):
    """Seconds for the grid's resonances and one collision operator and current."""
    state = make_state(CASES[case][0])
    s = settings(case, equation)
    grid = make_grid(state, s)
    f, M0 = project_state(state, grid)
    t0 = time.perf_counter()
    for _ in range(repeat):
        Kinetics(grid, s).operator(f, M0).face_flux(np.log(f))
    return (time.perf_counter() - t0) / repeat


def describe(out, wall):
    tau_e, tau_rate = relaxation_times(out)
    u = out["u"]
    return (
        f"{wall:7.1f} s, {out['eta'].size} nodes, {out['n_steps']} steps ({out['n_rejected']} "
        f"rejected), tau_end = {out['tau'][-1]:.4g}, thermalised: {out['thermalised']}; "
        f"tau_R(entropy/e) = {tau_e:.5g}, (S_eq - S0)/Sdot0 = {tau_rate:.4g}; "
        f"dM0/dtau over tau <= 0.5 = {out['dM0dtau_early']:.5g}; "
        f"M0 {out['M0'][0]:.6f} -> {out['M0'][-1]:.6f} (thermal on the grid {out['M0_eq']:.6f}); "
        f"|d mass| = {np.max(np.abs(out['mass'] - out['mass'][0])):.1e}, "
        f"|d u|/|u| = {np.max(np.abs(u - u[0])) / abs(u[0]):.1e}"
    )


def max_M0_change(a, b):
    """Largest |M0_a(tau) - M0_b(tau)| over the common tau range (interpolated in log tau)."""
    ta, tb = a["tau"][1:], b["tau"][1:]
    lo, hi = max(ta[0], tb[0]), min(ta[-1], tb[-1])
    t = np.geomspace(lo, hi, 400)
    Ma = np.interp(np.log(t), np.log(ta), a["M0"][1:])
    Mb = np.interp(np.log(t), np.log(tb), b["M0"][1:])
    return float(np.max(np.abs(Ma - Mb)))


def newton_cost(case, equation, repeat=5):
    """One dense Newton Jacobian: sparse products then toarray (the baseline) against the
    precomputed event map, same operator and state, same run."""
    state = make_state(CASES[case][0])
    s = settings(case, equation)
    grid = make_grid(state, s)
    f, M0 = project_state(state, grid)
    op = Kinetics(grid, s).operator(f, M0)
    y = np.log(f)
    op.jacobian_dense(y)  # the map is built once per grid
    t0 = time.perf_counter()
    for _ in range(repeat):
        op.jacobian(y).toarray()
    t_sparse = (time.perf_counter() - t0) / repeat
    t0 = time.perf_counter()
    for _ in range(repeat):
        op.jacobian_dense(y)
    t_map = (time.perf_counter() - t0) / repeat
    print(
        f"{case} {equation}, {grid.size} nodes: Jacobian by sparse products {t_sparse * 1e3:.1f} "
        f"ms, by the event map {t_map * 1e3:.1f} ms (x{t_sparse / t_map:.1f})"
    )


def _relative(a, b):
    """max |a - b| / max |b| (0 if both vanish; NaN where both are NaN counts as equal)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    both = np.isnan(a) & np.isnan(b)
    a, b = np.where(both, 0.0, a), np.where(both, 0.0, b)
    scale = np.max(np.abs(b))
    return float(np.max(np.abs(a - b)) / scale) if scale > 0 else float(np.max(np.abs(a - b)))


def agreement(new, old):
    """Largest relative differences of the results the pipeline uses, and whether all of
    them are bitwise equal."""
    quantities = {
        "tau_R": (relaxation_times(new)[0], relaxation_times(old)[0]),
        "dM0dtau_initial": (new["dM0dtau_initial"], old["dM0dtau_initial"]),
        "dM0dtau_early": (new["dM0dtau_early"], old["dM0dtau_early"]),
        "M0_end": (new["M0"][-1], old["M0"][-1]),
        "tau_end": (new["tau"][-1], old["tau"][-1]),
    }
    out = {k: _relative(a, b) for k, (a, b) in quantities.items()}
    same_shape = new["flux"].shape == old["flux"].shape
    out["flux"] = max(_relative(a, b) for a, b in zip(new["flux"], old["flux"], strict=True))
    out["flux"] = out["flux"] if same_shape else np.inf
    out["f_end"] = _relative(new["f"][-1], old["f"][-1])
    out["f_end_nodewise"] = float(np.max(np.abs(new["f"][-1] / old["f"][-1] - 1.0)))
    bitwise = same_shape and all(np.array_equal(a, b, True) for a, b in quantities.values())
    bitwise = bitwise and np.array_equal(new["flux"], old["flux"])
    out["bitwise"] = bool(bitwise and np.array_equal(new["f"][-1], old["f"][-1]))
    return out


def timed_pair(case, equation, baseline):
    """One pipeline evolution by the present code and one inside the context `baseline` (same
    run), in CPU seconds of this process (BLAS on one thread: what a job pays on a shared
    machine): (new, old, t_new, t_old, agreement, worst relative difference)."""
    kw = dict(PIPELINE[case], flux_times=FLUX_TIMES)
    t0 = time.process_time()
    new, _ = run(case, equation, **kw)
    t_new = time.process_time() - t0
    with baseline:
        t0 = time.process_time()
        old, _ = run(case, equation, **kw)
        t_old = time.process_time() - t0
    agree = agreement(new, old)
    worst = max(v for k, v in agree.items() if k not in ("bitwise", "f_end_nodewise"))
    return new, old, t_new, t_old, agree, worst


def cost(case, equation):
    """The present code against the solves it replaced (`previous_path`)."""
    new, old, t_new, t_old, agree, worst = timed_pair(case, equation, previous_path())
    print(
        f"{case} {equation}: CPU previous {t_old:.1f} s, present {t_new:.1f} s "
        f"(x{t_old / t_new:.2f}); {new['n_steps']} steps ({old['n_steps']} before); results "
        + ("bitwise equal" if agree["bitwise"] else f"agree to {worst:.1e} relative")
    )
    print("    " + ", ".join(f"{k} {v:.1e}" for k, v in agree.items() if k != "bitwise"))
    return t_old, t_new


def inversion_cost(case, equation):
    """The present kappa(Omega) (Newton's iteration) and tabulated M0 bracket against the
    bisection and 9-point bracket before them (only those two swapped back)."""
    baseline = swapped(
        (orbits, "kappa_from_frequency", previous_relaxation.kappa_from_frequency),
        (tabulated, "solve_M0", previous_relaxation.tabulated_solve_M0),
    )
    new, old, t_new, t_old, agree, worst = timed_pair(case, equation, baseline)
    print(
        f"{case} {equation}: CPU with bisection {t_old:.1f} s, with Newton {t_new:.1f} s "
        f"(x{t_old / t_new:.2f}); {new['n_steps']} steps ({old['n_steps']}); results "
        + ("bitwise equal" if agree["bitwise"] else f"agree to {worst:.1e} relative")
    )
    return t_old, t_new


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--study",
        choices=["time", "nmax", "convergence", "newton", "cost", "inversion"],
        default="time",
    )
    ap.add_argument("--case", nargs="+", choices=sorted(CASES), default=["ch2"])
    ap.add_argument("--equations", nargs="+", choices=EQUATIONS, default=list(EQUATIONS))
    args = ap.parse_args()
    if args.study in ("cost", "inversion"):
        total = np.zeros(2)
        for case in args.case:
            for eq in args.equations:
                total += (cost if args.study == "cost" else inversion_cost)(case, eq)
        old, new = total
        print(f"all: CPU previous {old:.1f} s, present {new:.1f} s (x{old / new:.2f})")
        return
    args.case = args.case[0]
    if args.study == "time":
        for eq in args.equations:
            print(f"{args.case} {eq}: one operator + current {flux_cost(args.case, eq):.3f} s")
            out, wall = run(args.case, eq)
            print(f"{args.case} {eq}: evolution {describe(out, wall)}")
    elif args.study == "nmax":
        for eq in args.equations:
            for n_max in (4, 6, 8):
                out, wall = run(args.case, eq, n_max=n_max)
                head = f"{args.case} {eq} n_max={n_max}: Sdot0 = {out['Sdot'][0]:.4g}"
                print(f"{head}; {describe(out, wall)}")
    elif args.study == "newton":
        for eq in args.equations:
            newton_cost(args.case, eq)
    else:
        for eq in args.equations:
            ref, wall = run(args.case, eq)
            print(f"{args.case} {eq} reference: {describe(ref, wall)}")
            half, wall = run(args.case, eq, rtol=5e-4)
            print(
                f"  rtol/2: max |dM0(tau)| = {max_M0_change(ref, half):.2e}; {describe(half, wall)}"
            )
            finer, wall = run(args.case, eq, n_nodes=900)
            change = max_M0_change(ref, finer)
            print(f"  900 nodes: max |dM0(tau)| = {change:.2e}; {describe(finer, wall)}")


if __name__ == "__main__":
    main()
