"""Where the hot halo's early N-body entropy change falls short of Lenard-Balescu at N = 6.4e4.

    python studies/early_entropy_budget.py [--results results] [--out FILE]

Reads the early-window summaries of rule relaxation_rates: the default reproduction's
(results/relaxation_rates/corehalo_hothalo.nc, 8 realisations at N = 6.4e4) and the independent
ensemble of config/experiments/hothalo_early_64k.yaml (seed 3, 24 realisations), and the
kinetic evolutions results/relaxation/corehalo_hothalo_{landau,lenard_balescu}.nc.  Prints

1. the time profile: the N-body dS(tau) over Lenard-Balescu's at each sampled tau of the
   window, per ensemble and pooled (inverse-variance weights): a constant ratio is a slower
   rate, a ratio that rises towards 1 a delay;
2. the current profile: the change of the fraction of particles below each J-bar edge at
   tau* = 0.5 (the integrated current through it), N-body pooled against both kinetic
   equations, with the z of N-body - Lenard-Balescu;
3. the entropy budget per bin: s_b(tau*) - s_b(0), s_b = -P_b ln(P_b / (4 pi dJ_b)), with
   P_b(0) the kinetic initial fractions and P_b(tau*) = P_b(0) + the measured change, so that
   the initial sampling noise cancels; summed over contiguous ranges of bins.

No MD is run: the numbers are those of the files.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from hmfdiff.analysis.relaxation_md import kinetic_bin_fractions
from hmfdiff.kinetic.tabulated import PHASE_VOLUME_PER_JBAR

CASE = "corehalo_hothalo"
N = 64000
EQUATIONS = ("landau", "lenard_balescu")
RANGES = ((0.0, 0.1242), (0.1242, 0.4968), (0.4968, 0.9936), (0.9936, 1.2421), (1.2421, 5.0))


def pooled(values, errors):
    """Inverse-variance mean over the first axis and its error."""
    v, e = np.asarray(values, float), np.asarray(errors, float)
    w = np.where(e > 0, 1.0 / np.where(e > 0, e, 1.0) ** 2, 0.0)
    tot = w.sum(axis=0)
    mean = np.where(tot > 0, (w * v).sum(axis=0) / np.where(tot > 0, tot, 1.0), v.mean(axis=0))
    err = np.where(tot > 0, 1.0 / np.sqrt(np.where(tot > 0, tot, 1.0)), 0.0)
    return mean, err


def bin_entropy(P, edges):
    """-P_b ln(P_b / (4 pi dJ_b)) per bin (0 where P_b <= 0)."""
    dJ = np.diff(edges) * PHASE_VOLUME_PER_JBAR
    P = np.asarray(P, float)
    safe = np.where(P > 0, P, 1.0)
    return np.where(P > 0, -P * np.log(safe / dJ), 0.0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--results", default="results")
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    res = Path(args.results)
    files = {
        "default (seed 2, R = 8)": res / "relaxation_rates" / f"{CASE}.nc",
        "hothalo_early_64k (seed 3, R = 24)": res
        / "experiments/hothalo_early_64k/relaxation_rates"
        / f"{CASE}.nc",
    }
    ens = {k: xr.open_dataset(v) for k, v in files.items()}
    first = next(iter(ens.values()))
    tau = first["tau"].values
    edges = first["jbar_edges"].values
    for d in ens.values():
        if not (
            np.allclose(d["tau"].values, tau, rtol=1e-2)
            and np.allclose(d["jbar_edges"].values, edges)
        ):
            sys.exit("error: the two ensembles have different times or bins")
    kin = {eq: xr.open_dataset(res / "relaxation" / f"{CASE}_{eq}.nc") for eq in EQUATIONS}
    out = []
    p = out.append
    p(f"# Early-window entropy budget of {CASE} at N = {N} (studies/early_entropy_budget.py)")
    for k, v in files.items():
        p(f"# {k}: {v} (git {ens[k].attrs.get('git_revision', '?')})")
    lb_dS = first["dS_lenard_balescu"].values
    p("")
    p("1. Time profile: N-body dS(tau) / Lenard-Balescu dS(tau) (+- jackknife error)")
    p(
        "   "
        + "tau".rjust(8)
        + "".join(f"{k.split(' ')[0]:>22}" for k in ens)
        + "  pooled".rjust(18)
    )
    rows_v = np.array([d["dS_md"].sel(initial="state", N=N).values for d in ens.values()])
    rows_e = np.array([d["dS_md_err"].sel(initial="state", N=N).values for d in ens.values()])
    pm, pe = pooled(rows_v, rows_e)
    for i in range(1, tau.size):
        cells = "".join(
            f"{rows_v[j, i] / lb_dS[i]:>14.2f} +- {rows_e[j, i] / lb_dS[i]:.2f}"
            for j in range(len(ens))
        )
        p(f"   {tau[i]:8.4f}{cells}{pm[i] / lb_dS[i]:>11.2f} +- {pe[i] / lb_dS[i]:.2f}")
    late = tau >= 0.07
    r, re = pm[late] / lb_dS[late], pe[late] / lb_dS[late]
    w = 1.0 / re**2
    p(
        f"   mean of the pooled ratio over tau >= 0.07 (inverse-variance, samples correlated): "
        f"{np.sum(w * r) / np.sum(w):.3f}"
    )
    p("")
    p("2. Change of the fraction below each J-bar edge over tau* = 0.5 (minus: particles left)")
    p(
        "   "
        + "J-bar".rjust(7)
        + "landau".rjust(11)
        + "LB".rjust(11)
        + "N-body".rjust(11)
        + "err".rjust(9)
        + "z(LB)".rjust(8)
        + "control".rjust(10)
    )
    dC = np.array([d["dC_md"].sel(initial="state", N=N).values[-1] for d in ens.values()])
    dCe = np.array([d["dC_md_err"].sel(initial="state", N=N).values[-1] for d in ens.values()])
    cC = np.array([d["dC_md"].sel(initial="thermal", N=N).values[-1] for d in ens.values()])
    cCe = np.array([d["dC_md_err"].sel(initial="thermal", N=N).values[-1] for d in ens.values()])
    m, e = pooled(dC, dCe)
    cm, _ = pooled(cC, cCe)
    lb = first["dC_lenard_balescu"].values[-1]
    la = first["dC_landau"].values[-1]
    for i in range(1, edges.size):
        if np.all(dCe[:, i] == 0) or abs(lb[i]) < 5e-6 and abs(m[i]) < 5e-6:
            continue
        z = (m[i] - lb[i]) / e[i]
        p(
            f"   {edges[i]:7.4f}{la[i]:+11.5f}{lb[i]:+11.5f}{m[i]:+11.5f}{e[i]:9.5f}{z:+8.1f}"
            f"{cm[i]:+10.5f}"
        )
    p("")
    p("3. Entropy change per range of bins over tau* = 0.5 (s_b = -P_b ln(P_b / 4 pi dJ_b))")
    k0 = kin["lenard_balescu"]
    P0 = kinetic_bin_fractions(
        k0["Jbar"].values[0], k0["cell_width"].values[0], k0["f"].values[0], edges
    )
    s0 = bin_entropy(P0, edges)
    dP_md = np.diff(m)
    dP_md_err = np.sqrt(e[1:] ** 2 + e[:-1] ** 2)  # edges correlated: an upper bound
    ds_md = bin_entropy(P0 + dP_md, edges) - s0
    ds_kin = {
        eq: bin_entropy(P0 + np.diff(first[f"dC_{eq}"].values[-1]), edges) - s0 for eq in EQUATIONS
    }
    # first order in dP: ds_b = -dP_b (ln(P_b / 4 pi dJ_b) + 1): its error from dP's
    slope = np.where(
        P0 > 0,
        np.log(np.where(P0 > 0, P0, 1.0) / (np.diff(edges) * PHASE_VOLUME_PER_JBAR)) + 1,
        0.0,
    )
    p(
        "   "
        + "J-bar range".ljust(18)
        + "landau".rjust(10)
        + "LB".rjust(10)
        + "N-body".rjust(10)
        + "  N-body/LB"
    )
    centres = 0.5 * (edges[1:] + edges[:-1])
    for lo, hi in RANGES:
        sel = (centres > lo) & (centres < hi)
        md_sum = ds_md[sel].sum()
        md_err = np.sqrt(np.sum((slope[sel] * dP_md_err[sel]) ** 2))
        lbs = ds_kin["lenard_balescu"][sel].sum()
        p(
            f"   {lo:6.4f} - {hi:6.4f}   {ds_kin['landau'][sel].sum():+10.5f}{lbs:+10.5f}"
            f"{md_sum:+10.5f}  {md_sum / lbs if lbs else np.nan:6.2f} (+- {md_err:.5f} abs)"
        )
    p(
        f"   all bins           {ds_kin['landau'].sum():+10.5f}"
        f"{ds_kin['lenard_balescu'].sum():+10.5f}"
        f"{ds_md.sum():+10.5f}  {ds_md.sum() / ds_kin['lenard_balescu'].sum():6.2f}"
        f"   (files' dS: LB {lb_dS[-1]:+.5f}, N-body pooled {pm[-1]:+.5f} +- {pe[-1]:.5f})"
    )
    from _realisations import emit

    emit(out, args.out)


if __name__ == "__main__":
    main()
