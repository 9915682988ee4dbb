"""Cost and convergence of the collisional relaxation (issue 13).

    python benchmarks/bench_relaxation.py                    # ch2*: one evolution per equation
    python benchmarks/bench_relaxation.py --study nmax       # ch2*: dependence on n_max
    python benchmarks/bench_relaxation.py --study convergence --case hot

Runs on one core (BLAS threads pinned to 1 before numpy is imported).  The default prints the
wall time of one evolution from ch2* to thermalisation (max |f - f_eq| < thermal_tol max f_eq)
at the default settings of config/config.yaml (600 J-bar nodes, n_max = l_max = 6,
rtol = thermal_tol = 1e-3) and the cost of one evaluation of the collision operator (orbits,
resonances and, for Lenard-Balescu, the dielectric tensor) and of the current it gives.
`--study nmax` prints the initial entropy production and the relaxation time against n_max;
`--study convergence` the largest change of M0(tau) when rtol is halved and when the grid is
refined from 600 to 900 nodes or coarsened to 300 (each line gives tau_R);
`--study separatrix` (issue 20) the initial rate dM0/dtau at tau = 0 on grids of 150-2400
nodes, the continuum numerator 4 pi int G-bar dc0 per decade of |kappa - 1| (Fokker-Planck
current of the analytic state) and the references of tests/test_relaxation_convergence.py.
`--study band` (issues 20, 21) the relaxation time with f lumped across |kappa - 1| <
separatrix_band = 1/(M0 sqrt N), the width over which N particles' fluctuating magnetisation
moves the separatrix, for N = 1e3, 4e3, 1.6e4 (and 0), on 300 and 600 nodes: tau_R (fine) and
tau_R^coarse on the N-body ensembles' J-bar bins (40 bins to kappa = 3 at the initial M0, as
relaxation_md), to set against the N-body t_R/N of results/relaxation_comparison_summary.txt.

Measured 2026-11-25 (issue 20; a 2-core machine under load ~14, so wall times are not costs):

* rtol: ch2* Lenard-Balescu at 600 nodes, rtol 1e-3 -> 5e-4: max |dM0(tau)| = 1.0e-5,
  tau_R 1846 -> 1865 (+1.0 %); the initial-rate time (S_eq - S0)/Sdot0 = 193.7-193.8 at 300-900.
* n_nodes: ch2* Lenard-Balescu tau_R (entropy deficit / e, thermal_tol 1e-3) = 1383, 1761,
  1983 at 300, 600, 900 nodes with the separatrix a face of the grid (1265, 1846 at 300, 600
  before); max |dM0(tau)| 1.2e-4 (300 -> 600) and 9.1e-5 (600 -> 900), M0 falls by 1.5e-3 in
  all.  M0(tau) meets 1e-3; tau_R is not converged: the default of 600 nodes is >= 13 % from
  900 nodes, not within 2-3 %.
* why (--study separatrix): dM0/dtau(0) = N / (1 - dF/dM0).  1 - dF/dM0 converges (ch2*
  0.87264, hot halo 0.90483 by quadrature; grid within 6e-4 at 150 nodes).  N does not: ch2*
  Landau N = 5.48e-4, 5.43e-4, 4.36e-4, 3.14e-4, 2.58e-4 at 150/300/600/1200/2400 nodes,
  Lenard-Balescu 4.90e-5, 5.00e-5, 4.94e-5, 4.71e-5, 2.68e-5.  The continuum N (Landau) per
  decade of |kappa - 1| from 0.1 down: librating -7e-6, -4.9e-5, -2.9e-4, -3.5e-5, -6e-6,
  -8.0e-5, -2.2e-5, then < 5e-7; rotating 1.6e-4, 3.1e-4, 1.3e-5, 8.8e-5, 9.5e-5, 6e-6, 4.2e-5,
  3.5e-5, 6.5e-6, 2.2e-5, 1.6e-5 (down to 1e-12, and on): rotating orbits within 1e-12 of the
  separatrix still resonate with the core through their harmonics n = 4-6 (n Omega = 2
  Omega', Omega ~ 1/ln(1/|kappa - 1|)), so the band carries the rate down to |kappa - 1| ~
  1e-25, below what kappa in double precision resolves.  The grid gives the continuum N cut
  at its innermost nodes (5.44e-4 for |kappa - 1| > 1e-3, 2.64e-4 for > 1e-4).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from hmfdiff.kinetic.dielectric import DielectricTensor  # noqa: E402
from hmfdiff.kinetic.flux import fokker_planck_current, jbar_current  # noqa: E402
from hmfdiff.kinetic.grid import action_grid, project_state, solve_grid_M0  # noqa: E402
from hmfdiff.kinetic.relaxation import (  # noqa: E402
    RelaxationSettings,
    _Operator,
    evolve,
)
from hmfdiff.meanfield import orbits  # noqa: E402
from hmfdiff.meanfield.equilibrium import make_state  # noqa: E402
from hmfdiff.meanfield.fourier import cos_coefficient  # noqa: E402
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
    state = make_state(CASES[case][0])
    s = settings(case, equation)
    grid = action_grid(state.M0, s.n_nodes, s.kappa_max, state, s.feature_share, s.separatrix_share)
    f, M0 = project_state(state, grid)
    t0 = time.perf_counter()
    for _ in range(repeat):
        op = _Operator(grid, f, M0, s).op
        op.face_flux(np.log(f))
    return (time.perf_counter() - t0) / repeat


def describe(out, wall):
    tau_e, tau_rate = relaxation_times(out)
    u = out["u"]
    return (
        f"{wall:7.1f} s, {out['n_steps']} steps ({out['n_rejected']} rejected), "
        f"tau_end = {out['tau'][-1]:.4g}, thermalised: {out['thermalised']}; "
        f"tau_R(entropy/e) = {tau_e:.4g}, (S_eq - S0)/Sdot0 = {tau_rate:.4g}; "
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


def grid_initial_rate(case, equation, n_nodes):
    """dM0/dtau at tau = 0 of the grid: sum_i c0_i dm_i/dtau / (1 - dF/dM0), and its parts."""
    state = make_state(CASES[case][0])
    s = settings(case, equation, n_nodes=n_nodes)
    grid = action_grid(state.M0, n_nodes, s.kappa_max, state, s.feature_share, s.separatrix_share)
    f, M0 = project_state(state, grid)
    op = _Operator(grid, f, M0, s).op

    def c0(M):
        return cos_coefficient(0, orbits.kappa_from_rescaled_action(grid.jbar, M))

    num = float(np.dot(op.rate(np.log(f)), c0(M0)))
    eps = 1e-4  # response of the grid's M0 to f -> f (1 +- eps c0): 1 - dF/dM0 from it
    dM = solve_grid_M0(grid, f * (1 + eps * c0(M0)), M0) - solve_grid_M0(
        grid, f * (1 - eps * c0(M0)), M0
    )
    m = grid.volume * f
    var = np.dot(m, c0(M0) ** 2) / m.sum() - M0**2
    denom = 2 * eps * var / dM
    return num, 1.0 - denom, num / denom


def _gauss_legendre(edges, order=8):
    x, w = np.polynomial.legendre.leggauss(order)
    a, b = edges[:-1, None], edges[1:, None]
    return (0.5 * (a + b) + 0.5 * (b - a) * x).ravel(), (0.5 * (b - a) * w).ravel()


def _dc0_dkappa(k):
    h = np.where(np.abs(k - 1) < 0.1, 1e-4 * np.abs(k - 1), 1e-5)
    return (cos_coefficient(0, k + h) - cos_coefficient(0, k - h)) / (2 * h)


def continuum_moment(case, collective, lo, hi, side, n_panel=40):
    """4 pi int G-bar dc0/dkappa dkappa over lo < |kappa - 1| < hi on one side (-1 librating,
    +1 rotating): Fokker-Planck current of the analytic state, Gauss-Legendre on panels
    geometric in |kappa - 1|."""
    state = make_state(CASES[case][0])
    eps = DielectricTensor(state, l_max=6) if collective else None
    x, w = _gauss_legendre(np.geomspace(lo, hi, n_panel + 1))
    k = 1.0 + side * x
    G = jbar_current(fokker_planck_current(state, k, collective=collective, eps=eps), k)
    return float(4 * np.pi * np.sum(w * G * _dc0_dkappa(k)))


def clipped_moment(case, collective, delta, n_panel=150, order=8):
    """The reference of the clipped-c0 current moment (tests/test_relaxation_convergence.py)."""
    from scipy.optimize import brentq

    state = make_state(CASES[case][0])
    kmax = CASES[case][1]
    clip = cos_coefficient(0, 1.0 + delta)
    klib = brentq(lambda k: cos_coefficient(0, k) - clip, 0.5, 1 - 1e-15)
    lib = np.concatenate(
        (np.linspace(0, 0.9, n_panel), 1 - np.geomspace(0.1, 1 - klib, n_panel // 3)[1:])
    )
    rot = np.concatenate(
        (1 + np.geomspace(delta, 0.1, n_panel // 3), np.linspace(1.1, kmax, n_panel)[1:])
    )
    k1, w1 = _gauss_legendre(lib, order)
    k2, w2 = _gauss_legendre(rot, order)
    k, w = np.concatenate((k1, k2)), np.concatenate((w1, w2))
    eps = DielectricTensor(state, l_max=6) if collective else None
    G = jbar_current(fokker_planck_current(state, k, collective=collective, eps=eps), k)
    return float(4 * np.pi * np.sum(w * G * _dc0_dkappa(k)))


def separatrix_study(case, equations):
    for eq in equations:
        for n in (150, 300, 600, 1200, 2400):
            num, dF, rate = grid_initial_rate(case, eq, n)
            print(
                f"{case} {eq} {n} nodes: N = {num:.4e}, dF/dM0 = {dF:.5f}, dM0/dtau(0) = {rate:.4e}"
            )
    for eq in equations:
        coll = eq == "lenard_balescu"
        for side in (-1, 1):
            parts = [
                continuum_moment(case, coll, 10.0**-d, 10.0 ** (1 - d), side) for d in range(1, 13)
            ]
            txt = ", ".join(f"{p:.2e}" for p in parts)
            print(
                f"{case} {eq} continuum N per decade of |kappa - 1| (1..0.1 down to "
                f"1e-11..1e-12), side {side}: {txt}"
            )
    if case == "hot":
        print(
            f"clipped moment references: landau delta=0.03 {clipped_moment(case, False, 0.03):.5e}"
        )
        print(f"  lenard_balescu delta=1e-3 {clipped_moment(case, True, 1e-3):.5e}")


def coarse_relaxation_time(case, out, kappa_max=3.0, n_bins=40):
    """tau_R^coarse of an evolution on the N-body ensembles' J-bar bins (relaxation_compare's
    definition: the deficit S_eq - S of the binned entropy fallen by e)."""
    from hmfdiff.analysis.relaxation_compare import _coarse_entropy as entropy
    from hmfdiff.analysis.relaxation_md import (
        kinetic_bin_fractions,
        relaxation_time,
        state_bin_fractions,
    )
    from hmfdiff.meanfield.equilibrium import ThermalState

    state = make_state(CASES[case][0])
    edges = np.linspace(0.0, float(orbits.rescaled_action(kappa_max, state.M0)), n_bins + 1)
    S_eq = entropy(state_bin_fractions(ThermalState(u=state.u), edges), edges)
    S = entropy(kinetic_bin_fractions(out["jbar"], out["width"], out["f"], edges), edges)
    return relaxation_time(out["tau"], S_eq - S)


def band_study(case, equations):
    M0 = make_state(CASES[case][0]).M0
    for eq in equations:
        for n_part in (0, 1000, 4000, 16000):
            band = 0.0 if n_part == 0 else 1.0 / (M0 * np.sqrt(n_part))
            for n_nodes in (300, 600):
                out, wall = run(case, eq, n_nodes=n_nodes, separatrix_band=band)
                tc = coarse_relaxation_time(case, out)
                print(
                    f"{case} {eq} N = {n_part or 'inf'} (separatrix_band {band:.4f}), "
                    f"{out['jbar'].size} nodes: tau_R^coarse = {tc:.4g}; {describe(out, wall)}",
                    flush=True,
                )


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--study", choices=["time", "nmax", "convergence", "separatrix", "band"], default="time"
    )
    ap.add_argument("--case", choices=sorted(CASES), default="ch2")
    ap.add_argument("--equations", nargs="+", choices=EQUATIONS, default=list(EQUATIONS))
    args = ap.parse_args()
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
    elif args.study == "separatrix":
        separatrix_study(args.case, args.equations)
    elif args.study == "band":
        band_study(args.case, args.equations)
    else:
        for eq in args.equations:
            ref, wall = run(args.case, eq)
            print(f"{args.case} {eq} reference: {describe(ref, wall)}")
            half, wall = run(args.case, eq, rtol=5e-4)
            print(
                f"  rtol/2: max |dM0(tau)| = {max_M0_change(ref, half):.2e}; {describe(half, wall)}"
            )
            for n in (300, 900):
                other, wall = run(args.case, eq, n_nodes=n)
                change = max_M0_change(ref, other)
                print(f"  {n} nodes: max |dM0(tau)| = {change:.2e}; {describe(other, wall)}")


if __name__ == "__main__":
    main()
