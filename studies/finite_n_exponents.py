"""How fast do the finite-N departures from the order-1/N theory fall?  Their exponents in N,
with errors, and whether N^-1/2 (a boundary layer of width N^-1/2 at the separatrix) or N^-1
(the order-1/N^2 collision terms: a relative excess ~1/N) describes them.

    python studies/finite_n_exponents.py > docs/reference/finite_n_exponents.txt

Reads only reference files under docs/reference (no simulation; seconds):

1. the hot halo's N-body relaxation against Lenard-Balescu: the rate excess
   tau_R^coarse(LB) N / t_R - 1 at N = 1000, 2000, 4000 (relaxation_comparison_summary.txt) and
   8000, 16000 (experiments/hothalo_large_n/relaxation_comparison_summary.txt), tau_R^coarse of
   the present code from kinetic_time_uncertainty.csv (its uncertainty is common to every N: it
   moves the amplitude, not the points against each other, and is not in the errors);
2. (MD(full) N D at the hot halo's core edge, bin kappa0 = 0.43, is split into field and response
   with its own exponents by studies/spectrum_scaling.py: spectrum_scaling_hothalo.txt);
3. at u = 0, the deficit of the measured N D of the bin kappa0 = 1.039 below N D computed from
   the MD's own measured spectrum, 1 - ratio (spectrum_diffusion_u0.0_full.txt; both sets of
   seeds at N = 5e5 as separate points);
4. at u = 0.2475 (1 % below the critical energy), the deficit of the power of the least-damped
   even mode in MD(full) below the linear dressed theory's over omega0 -+ 4 gamma, 1 - band
   (mode_separatrix_u0.2475.txt, N = 3.1e4 ... 4e6);
5. there, the floor of the MD's N S of |M| over omega = 0.05-0.1, where the linear theory has
   N S_x ~ 6e-4: not an excess over a ratio but the floor itself, which a departure of order
   1/N^2 in S would give as N^-1, a population of width N^-1/2 as N^-1/2.

Each excess is fitted as A (N/n_ref)^-a by weighted least squares on the excess itself
(`hmfdiff.analysis.scaling.excess_power_law`), with the chi^2 of a = 1/5, 1/2 and 1 (amplitude
refitted) and its p-value.
"""

from __future__ import annotations

import csv
import re
import sys
from pathlib import Path

import numpy as np

from hmfdiff.analysis.scaling import excess_power_law

#: N^-1/5: the marginal-stability window (Yamaguchi & Barre 2026); N^-1/2: a boundary layer of
#: width N^-1/2; N^-1: the order-1/N^2 collision terms (Fouvry, Bar-Or & Chavanis 2019)
EXPONENTS = (0.2, 0.5, 1.0)
REF = Path(__file__).resolve().parents[1] / "docs" / "reference"
TR = re.compile(r"MD N = (\d+): t_R = ([0-9.e+]+) \+- ([0-9.e+]+)")


def kinetic_tau(case="corehalo_hothalo", equation="lenard_balescu"):
    with open(REF / "kinetic_time_uncertainty.csv") as fh:
        for row in csv.DictReader(fh):
            if row["case"] == case and row["equation"] == equation:
                return float(row["tau_R_coarse"])
    raise LookupError(f"{case} {equation}: not in kinetic_time_uncertainty.csv")


def relaxation_times():
    """(N, t_R, its error) of the hot halo's N-body ensembles, all five N."""
    rows = []
    for name in (
        "relaxation_comparison_summary.txt",
        "experiments/hothalo_large_n/relaxation_comparison_summary.txt",
    ):
        rows += [tuple(map(float, m)) for m in TR.findall((REF / name).read_text())]
    return np.array(sorted(rows)).T


def item_relaxation():
    tau = kinetic_tau()
    N, t, dt = relaxation_times()
    ratio = tau * N / t
    return N, ratio - 1, ratio * dt / t, f"tau_R^coarse(LB) N / t_R - 1, tau_R^coarse = {tau}"


#: the header numbers the sets of runs, "(k) N = 2.5e5 ...", in the order of the result lines
#: (whose own "N = 2e+05" is rounded to one digit)
SETS = re.compile(r"\((\d)\) N = ([0-9.e+]+)")
RESPONSE = re.compile(r"measured / from MD's spectrum ([0-9.]+) \+- ([0-9.]+)")


def item_response():
    text = (REF / "spectrum_diffusion_u0.0_full.txt").read_text()
    header = "\n".join(line for line in text.splitlines() if line.startswith("#"))
    sizes = [float(n) for _, n in SETS.findall(header)]
    ratios = [(float(r), float(e)) for r, e in RESPONSE.findall(text)]
    if len(sizes) != len(ratios):
        raise ValueError(f"{len(sizes)} sets of runs in the header, {len(ratios)} results")
    N, r, e = np.array(sorted((n, *x) for n, x in zip(sizes, ratios, strict=True))).T
    return N, 1 - r, e, "1 - N D_MD / N D(MD's spectrum), u = 0, bin kappa0 = 1.039"


#: `analyse` lines of studies/mode_trapping.py in mode_separatrix_u0.2475.txt
MODE_POWER = re.compile(
    r"N = (\d+) \((\d+) realisations\): at mode [^;]+; band ([0-9.]+) \+- ([0-9.]+);"
)


def item_mode_power():
    text = (REF / "mode_separatrix_u0.2475.txt").read_text()
    rows = sorted((float(n), float(b), float(e)) for n, _, b, e in MODE_POWER.findall(text))
    if len(rows) < 3:
        raise ValueError(f"{len(rows)} mode-power lines in mode_separatrix_u0.2475.txt")
    N, band, e = np.array(rows).T
    return (
        N,
        1 - band,
        e,
        "1 - mode power MD / linear over omega0 -+ 4 gamma, u = 0.2475 (MD(full))",
    )


FLOOR_MOD = re.compile(
    r"N = (\d+) \((\d+) realisations\): M-bar .*?, \|M\| ([0-9.]+) \+- ([0-9.]+);"
)


def item_floor():
    text = (REF / "mode_separatrix_u0.2475.txt").read_text()
    text = text.split("## Controls")[0]  # the u = 0.2475 lines only
    rows = sorted((float(n), float(f), float(e)) for n, _, f, e in FLOOR_MOD.findall(text))
    if len(rows) < 3:
        raise ValueError(f"{len(rows)} floor lines in mode_separatrix_u0.2475.txt")
    N, floor, e = np.array(rows).T
    return (
        N,
        floor,
        e,
        "N S of |M| over omega 0.05-0.1, u = 0.2475 (MD(full); linear N S_x 0.000585)",
    )


def report(N, y, err, label, n_ref, last=None):
    """Print the points and the fit; `last`: also fit the largest `last` N alone."""
    r = excess_power_law(N, y, err, exponents=EXPONENTS, n_ref=n_ref)
    print(f"\n{label}")
    print("         N       excess      error")
    for n, v, s in zip(N, y, err, strict=True):
        print(f"  {n:9.4g}  {v:11.4g}  {s:9.3g}")
    print(
        f"  fit excess = A (N/{n_ref:g})^-a: a = {r['a']:.3f} +- {r['a_err']:.3f}, "
        f"A = {r['A']:.4g} +- {r['A_err']:.2g}, chi2 = {r['chi2']:.2f} on {r['dof']} dof"
    )
    for a, (c2, p) in r["fixed"].items():
        print(f"  a = {a:g} (A refitted): chi2 = {c2:.2f} on {len(N) - 1} dof, p = {p:.3g}")
    if last is not None and len(N) > last:
        k = np.argsort(N)[-last:]
        q = excess_power_law(N[k], y[k], err[k], exponents=EXPONENTS, n_ref=n_ref)
        fixed = ", ".join(
            f"a = {a:g}: chi2 = {c2:.2f}, p = {p:.3g}" for a, (c2, p) in q["fixed"].items()
        )
        print(
            f"  the largest {last} N alone (N = {N[k][0]:g}-{N[k][-1]:g}): a = {q['a']:.3f} +- "
            f"{q['a_err']:.3f}, chi2 = {q['chi2']:.2f} on {q['dof']} dof; {fixed}"
        )
    return r


def main(argv):
    if argv:
        sys.exit(__doc__)
    print("# python studies/finite_n_exponents.py (reads docs/reference only)")
    report(*item_relaxation(), n_ref=1e4, last=3)
    print(
        "\n(the hot halo's core edge, MD(full) N D at kappa0 = 0.43: its exponents, field and "
        "response apart, are in spectrum_scaling_hothalo.txt)"
    )
    report(*item_response(), n_ref=1e6)
    report(*item_mode_power(), n_ref=1e6, last=5)
    report(*item_floor(), n_ref=1e6)


if __name__ == "__main__":
    main(sys.argv[1:])
