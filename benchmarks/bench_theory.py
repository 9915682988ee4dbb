"""Wall time of one case's full theory grid against a straightforward scipy.quad baseline.

    python benchmarks/bench_theory.py [--case fig6a|fig6b|ch2|M0.05|M0.9] [--n-kappa 400]

Runs on one core (BLAS threads pinned to 1 before numpy is imported).  The grid is
`hmfdiff.kinetic.theory.theory_grid` with n_max = l_max = 6: Landau and Lenard-Balescu D_dif and
D_pol at n_kappa points plus eps on 401 frequencies.  The baseline, timed in the same run on a
few points and extrapolated, is what one would write first: eps(omega) by scipy.integrate.quad
in kappa (QAWC Cauchy weight at each pole, found by brentq) for every frequency n Omega(kappa)
that the grid needs, and the resonance roots by brentq for every (kappa, n, n').
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from scipy import integrate, optimize  # noqa: E402

from hmfdiff.kinetic.theory import theory_grid  # noqa: E402
from hmfdiff.meanfield import orbits  # noqa: E402
from hmfdiff.meanfield.equilibrium import CoreHaloState, ThermalState  # noqa: E402
from hmfdiff.meanfield.fourier import cos_coefficient, sin_coefficient_imag  # noqa: E402
from hmfdiff.pipeline.layouts.theory import theory_dataset  # noqa: E402

CASES = {
    "fig6a": lambda: ThermalState(u=-0.1),
    "fig6b": lambda: ThermalState(u=0.2475),
    "ch2": lambda: CoreHaloState(0.298, 0.051, -0.517, 0.19, 30, 10),
    "M0.05": lambda: ThermalState(M0=0.05),
    "M0.9": lambda: ThermalState(M0=0.9),
}


def baseline_eps(state, omega, l_max, kmax):
    """eps_cc, eps_ss at one omega by scipy.quad in kappa (the straightforward method)."""
    M0 = state.M0
    out = []
    for coef in (cos_coefficient, sin_coefficient_imag):
        total = 1.0 + 0.0j
        for l in [s * j for j in range(1, l_max + 1) for s in (1, -1)]:
            x0 = omega / l

            def g(k, l=l, coef=coef):
                return float(orbits.phase_space_weight(k) * coef(l, k) ** 2 * state.dfdkappa(k))

            def Om(k):
                return float(orbits.frequency(k, M0))

            for a, b in ((1e-12, 1.0 - 1e-15), (1.0 + 1e-15, kmax)):
                fa, fb = Om(a) - x0, Om(b) - x0
                if x0 > 0 and fa * fb < 0:
                    kp = optimize.brentq(lambda k, x0=x0: Om(k) - x0, a, b, xtol=1e-15)

                    def h(k, kp=kp, x0=x0, g=g):
                        return g(k) * (k - kp) / (Om(k) - x0)

                    pv, _ = integrate.quad(h, a, b, weight="cauchy", wvar=kp, limit=200)
                    dO = abs(float(orbits.dOmega_dkappa(kp, M0)))
                    total += 2 * np.pi * (pv + 1j * np.pi * np.sign(l) * g(kp) / dO)
                else:
                    v, _ = integrate.quad(
                        lambda k, x0=x0, g=g: g(k) / (Om(k) - x0), a, b, limit=200
                    )
                    total += 2 * np.pi * v
        out.append(total)
    return out


def baseline_roots(kappa, n_max, M0):
    """Resonance roots by brentq for every (n, n') and branch at one kappa."""
    Om0 = np.sqrt(M0)
    x = float(orbits.frequency(kappa, M0))
    roots = []
    for n in range(1, n_max + 1):
        for npr in range(1, n_max + 1):
            y = n * x / npr
            brackets = [(1 + 1e-15, 1 + 10 * y / Om0)] + ([(1e-12, 1 - 1e-15)] if y < Om0 else [])
            for a, b in brackets:
                try:  # (no resolvable root within 1e-15 of the separatrix: skipped)
                    roots.append(
                        optimize.brentq(
                            lambda k, y=y: float(orbits.frequency(k, M0)) - y, a, b, xtol=1e-15
                        )
                    )
                except ValueError:
                    pass
    return roots


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", default="fig6a", choices=sorted(CASES))
    ap.add_argument("--n-kappa", type=int, default=400)
    ap.add_argument("--baseline-points", type=int, default=3)
    args = ap.parse_args()

    t0 = time.perf_counter()
    state = CASES[args.case]()
    t_state = time.perf_counter() - t0

    t0 = time.perf_counter()
    ds = theory_dataset(theory_grid(state, n_kappa=args.n_kappa, n_max=6, l_max=6))
    t_grid = time.perf_counter() - t0
    n_ok = int((ds["separatrix_mask"] == 0).sum())
    n_freq = 6 * n_ok + ds.sizes["omega"]

    # baseline on a few points, extrapolated to the same grid
    rng = np.random.default_rng(0)
    Om = ds["Omega_orbit"].values[ds["separatrix_mask"].values == 0]
    oms = rng.choice(Om, args.baseline_points) * rng.integers(1, 7, args.baseline_points)
    t0 = time.perf_counter()
    for w in oms:
        baseline_eps(state, w, 6, float(ds.attrs["eps_kappa_max"]))
    t_eps = (time.perf_counter() - t0) / len(oms)
    ks = rng.choice(ds.kappa.values[ds["separatrix_mask"].values == 0], args.baseline_points)
    t0 = time.perf_counter()
    for k in ks:
        baseline_roots(k, 6, state.M0)
    t_root = (time.perf_counter() - t0) / len(ks)
    t_base = n_freq * t_eps + n_ok * t_root

    print(f"case {args.case}: M0 = {state.M0:.5f} (state built in {t_state:.2f} s)")
    print(
        f"grid: {args.n_kappa} kappa ({n_ok} outside the separatrix band), "
        f"{ds.sizes['omega']} omega, n_max = l_max = 6, Landau + Lenard-Balescu, D_dif + D_pol"
    )
    print(f"hmfdiff.kinetic.theory.theory_grid: {t_grid:8.2f} s (one core)")
    print(
        f"baseline scipy.quad: {t_eps * 1e3:.0f} ms per eps(omega) x {n_freq} frequencies + "
        f"{t_root * 1e3:.0f} ms of brentq roots per kappa x {n_ok} kappa"
    )
    print(f"baseline (extrapolated):      {t_base:8.0f} s")
    print(f"speed-up: {t_base / t_grid:.0f}x")


if __name__ == "__main__":
    main()
