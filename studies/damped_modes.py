"""Least-damped collective modes of the paper's states and of the relaxation study's core-halo
states: zeros of eps_cc and eps_ss continued below the real axis (kinetic.modes).

The question: the N-body relaxation of the hot halo outruns Lenard-Balescu at small N
(2.4, 1.1, 0.9, 0.7 times at N = 1e3 ... 6.4e4) while the warm core's stays within 10% of it.
Weakly damped modes near marginal stability amplify the fluctuations beyond the order-1/N
theory (Weinberg 1998; Lau & Binney 2019; Yamaguchi & Barre 2026): does the hot halo have one
that the warm core lacks?

Prints, in order: the validation of the continuation on the homogeneous HMF (AAA zero against
Newton's root of the exact Z-function formula, and the real-axis half width); the table of the
least-damped stable zero of each state and component; the complex Fermi-edge singularities of
the core-halo states against the nearest pole of the AAA fit; and the hot halo with its core
temperature 1/beta1 varied.  Run from the repository root:

    OMP_NUM_THREADS=1 python studies/damped_modes.py > docs/reference/damped_modes.txt

(about 3 CPU-minutes).
"""

from __future__ import annotations

import subprocess
import sys
import time
from datetime import UTC, datetime

import numpy as np

from hmfdiff.kinetic.dielectric import DielectricTensor
from hmfdiff.kinetic.modes import (
    fermi_edge_singularities,
    fit_real_axis,
    homogeneous_eps,
    homogeneous_roots,
    least_damped_modes,
    lorentzian_peak,
)
from hmfdiff.kinetic.stability import vlasov_stability
from hmfdiff.meanfield.equilibrium import make_state

CORE_HALO = dict(kind="core_halo", eta1=0.3, eta2=0.01, mu1=-0.5, mu2=1.2, beta2=2.0)
STATES = {
    "hot_halo": dict(CORE_HALO, beta1=40.0),
    "warm_core": dict(CORE_HALO, beta1=5.0),
    "ch2*": dict(
        kind="core_halo", eta1=0.298, eta2=0.051, mu1=-0.517, mu2=0.19, beta1=30.0, beta2=10.0
    ),
    "thermal_u-0.1": dict(kind="thermal", u=-0.1),
    "thermal_u0.0": dict(kind="thermal", u=0.0),
    "thermal_u0.2475": dict(kind="thermal", u=0.2475),
}
BETA1_SWEEP = (80.0, 60.0, 40.0, 30.0, 20.0, 15.0, 10.0, 7.0, 5.0)

HEADER = """\
# Least-damped collective modes: zeros of eps_cc, eps_ss continued below the real axis
# command: OMP_NUM_THREADS=1 python studies/damped_modes.py > docs/reference/damped_modes.txt
# date (UTC): {date}
# commit: {commit}
# code: src/hmfdiff/kinetic/modes.py (AAA, Nakatsukasa, Sete & Trefethen 2018), l_max = 6,
#   eps sampled at 1500 uniform real frequencies on (0, 4 Omega_0] (eps_ss: from the radius r
#   that excludes its neutral rotation) mirrored with eps(-w) = conj eps(w), AAA tol 1e-10.
#   A zero is kept when it is no Froissart doublet, lies within Re <= 3.6 Omega_0 and depth
#   <= 0.5 Omega_0, and refits (1.37 x the grid density; 0.75 x and 1.5 x the range; 10 x the
#   tolerance) reproduce it to 5% of its depth, and no pole of the fit lies within a tenth of
#   its depth: the pole-zero strings hanging down from the branch points omega = l Omega_0 of
#   the continued eps (bottom of the well) fail this and are dropped.
#
# Columns of the mode table:
#   state, comp      state and component (cc: even/cos response, ss: odd/sin response)
#   M0, Om0          magnetisation and Omega_0 = sqrt(M0)
#   omega0, gamma    the least-damped stable zero omega0 - i gamma (time as exp(-i omega t))
#   g/w0             gamma/omega0
#   spread           largest distance of that zero to the nearest zero of a refit (stability)
#   pole_dist        distance from the zero to the nearest pole of the continued eps
#   peak_w           frequency of the highest interior peak of |1/eps|^2 on the real axis
#   max|1/eps|^2     its height (the peak amplification of the dressed fluctuations)
#   hwhm             its half width at half maximum (= gamma for an isolated weakly damped mode)
#   fit_err          max |eps - r| / max |eps| of the AAA fit on its sample
#   uhp_err          max |r - eps| above the real axis (Im w = 0.02 ... 0.1 Omega_0) against the
#                    direct quadrature DielectricTensor.upper_half_plane (4 x its panels)
#   n_uhp            zeros in the upper half plane (argument principle, kinetic.stability)
"""


def _git_commit():
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        return out + (" (with uncommitted changes)" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def homogeneous_validation():
    print("## Validation: homogeneous HMF (M0 = 0), eps = 1 - (1 + zeta Z(zeta))/(2T)")
    print("#  T: temperature; newton: least-damped root of the exact formula (Newton);")
    print("#  aaa: the AAA continuation of real-axis samples |w| <= 8 (2000 points a side);")
    print("#  |d|: their distance; 2nd: the same for the next root pair; hwhm: real-axis")
    print("#  half width of |1/eps|^2 (peak at w = 0), against gamma")
    cols = ("T", "newton", "aaa", "|d|", "newton_2nd", "|d_2nd|", "hwhm", "hwhm/gamma")
    print("{:>6} {:>24} {:>24} {:>8} {:>24} {:>8} {:>10} {:>10}".format(*cols))
    for T in (0.505, 0.51, 0.6, 0.75, 1.0):
        roots = homogeneous_roots(T)
        r, _, _ = fit_real_axis(lambda w, T=T: homogeneous_eps(w, T), 0.004, 8.0, 2000, tol=1e-13)
        zs = r.zeros()
        zs = zs[(zs.imag < 0) & (zs.real >= -1e-9)]
        z1 = zs[np.argmin(np.abs(zs - roots[0]))]
        z2 = zs[np.argmin(np.abs(zs - roots[1]))]
        g = -roots[0].imag
        w = np.linspace(-40 * g, 40 * g, 8001)
        _, _, hw = lorentzian_peak(w, 1.0 / np.abs(homogeneous_eps(w, T)) ** 2)
        print(
            f"{T:6.3f} {roots[0]:24.12f} {z1:24.12f} {abs(z1 - roots[0]):8.1e} "
            f"{roots[1]:24.9f} {abs(z2 - roots[1]):8.1e} {hw:10.6f} {hw / g:10.4f}"
        )
    print()


ROW = "{:<18} {:>4} {:>7} {:>7} {:>9} {:>9} {:>8} {:>8} {:>9} {:>8} {:>11} {:>9} {:>8} {:>8} {:>5}"


def mode_row(name, comp, state, rep, n_uhp):
    return ROW.format(
        name,
        comp,
        f"{state.M0:.4f}",
        f"{np.sqrt(state.M0):.4f}",
        f"{rep.omega0:.5f}",
        f"{rep.gamma:.5f}",
        f"{rep.quality:.4f}" if np.isfinite(rep.quality) else "nan",
        f"{rep.spread:.1e}",
        f"{np.abs(np.complex128(complex(rep.omega0, -rep.gamma) - rep.nearest_pole)):.4f}",
        f"{rep.peak_omega:.4f}",
        f"{rep.peak_amp:.4g}",
        f"{rep.half_width:.5f}",
        f"{rep.fit_error:.0e}",
        f"{rep.uhp_error:.0e}",
        str(n_uhp),
    )


def header_row():
    cols = (
        "state",
        "comp",
        "M0",
        "Om0",
        "omega0",
        "gamma",
        "g/w0",
        "spread",
        "pole_dist",
        "peak_w",
        "max|1/eps|^2",
        "hwhm",
        "fit_err",
        "uhp_err",
        "n_uhp",
    )
    return ROW.format(*cols)


def run_states(states):
    out = {}
    for name, spec in states.items():
        state = make_state(spec)
        tensor = DielectricTensor(state)
        stab = vlasov_stability(state)
        for comp in ("cc", "ss"):
            rep = least_damped_modes(state, comp, tensor=tensor)
            n_uhp = stab.zeros_cc if comp == "cc" else stab.zeros_ss
            print(mode_row(name, comp, state, rep, n_uhp), flush=True)
            out[name, comp] = (state, rep)
    return out


def main():
    t0 = time.process_time()
    date = datetime.now(UTC).strftime("%Y-%m-%d %H:%M:%S")
    print(HEADER.format(date=date, commit=_git_commit()))
    homogeneous_validation()

    print("## Least-damped stable zero of each state and component")
    print(header_row())
    res = run_states(STATES)
    print()

    print("## Other stable zeros (Re >= 0, depth <= 0.5 Omega_0, least damped first, <= 4)")
    for (name, comp), (_, rep) in res.items():
        zs = ", ".join(f"{z:.5f}" for z in rep.zeros[rep.stable_mask][:4]) or "none"
        print(f"{name:<18} {comp:>3}: {zs}")
    print()

    print("## Fermi edges: double poles of f'(h) at h = mu + i pi/beta, mapped to l Omega(h),")
    print("#  against the nearest pole of the AAA fit (l = 2 for cc, l = 1 for ss: the lowest")
    print("#  harmonics of the librating orbits, even for cos, odd for sin)")
    for (name, comp), (state, _) in res.items():
        l = 2 if comp == "cc" else 1
        sing = fermi_edge_singularities(state, l)
        if not sing.size:
            continue
        tensor = DielectricTensor(state)
        idx = 0 if comp == "cc" else 1
        Om0 = np.sqrt(state.M0)
        r, _, _ = fit_real_axis(lambda w, t=tensor, i=idx: t(w)[i], 1e-3 * Om0, 4 * Om0, 1500)
        p = r.poles()
        for s in sing:
            q = p[np.argmin(np.abs(p - s))]
            print(
                f"{name:<18} {comp:>3}: l Omega(h*) = {s:.6f}   AAA pole {q:.6f}   |d| = "
                f"{abs(q - s):.1e}"
            )
    print()

    print("## The hot halo with its core temperature varied (beta1; everything else fixed)")
    print(header_row().replace("state             ", "beta1             "))
    for b1 in BETA1_SWEEP:
        run_states({f"beta1={b1:g}": dict(CORE_HALO, beta1=b1)})
    print()
    print(f"# CPU time: {time.process_time() - t0:.0f} s")


if __name__ == "__main__":
    sys.exit(main())
