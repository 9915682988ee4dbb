"""Figures 12 and 13: N-body relaxation ensembles against the kinetic evolutions.

Both read results/relaxation_comparison/{case}.nc (`analysis.relaxation_compare`): the MD at
every N and the Lenard-Balescu and Landau evolutions on the MD's rescaled times t/N, all in the
coarse-graining of the MD's J-bar bins.
"""

from __future__ import annotations

import numpy as np

from .style import HMF, plt, save_figure, sci, tag_panels

__all__ = ["fig12_relaxation_md", "fig13_relaxation_time"]

_KIN = (("lenard_balescu", "Lenard-Balescu", "k", "-"), ("landau", "Landau", "0.45", "--"))


def _colours(n):
    return plt.cm.viridis(np.linspace(0.0, 0.85, max(n, 1)))


def _snapshot_colours(n):
    """n well-separated steps of a sequential colormap (early: dark, late: light)."""
    return plt.cm.viridis(np.linspace(0.0, 0.8, max(n, 1)))


_SNAPSHOT_MARKERS = ("o", "s", "^", "D", "v")


def _snapshot_panel(ax, ds):
    """f(J-bar) = P_b / (4 pi dJbar_b) of the largest N at three times (first, middle, last)
    against Lenard-Balescu (lines) and the thermal state: only the bins where the MD has
    particles are drawn (an empty bin has no logarithm), the J-bar range is that of the MD's
    occupied bins at these times, and the log axis's floor is set by the smallest MD density
    drawn."""
    tau = ds["tau"].values
    jb = ds["jbar"].values
    edges = ds["jbar_edges"].values
    vol = 4 * np.pi * np.diff(edges)
    i = ds["N"].size - 1  # the largest N
    snaps = np.unique(np.linspace(0, tau.size - 1, 3).round().astype(int))
    P = ds["P_md"].values[i, snaps]
    occupied = np.flatnonzero((P > 0).any(axis=0))
    if occupied.size == 0:
        ax.text(0.5, 0.5, "no MD particles in the bins", transform=ax.transAxes, ha="center")
        return
    lo, hi = occupied[0], occupied[-1]
    span = slice(lo, hi + 1)
    shown = []
    cols = _snapshot_colours(snaps.size)
    for k, (j, c) in enumerate(zip(snaps, cols, strict=True)):
        dens = P[k] / vol
        err = ds["P_md_err"].values[i, j] / vol
        has = dens > 0
        mk = _SNAPSHOT_MARKERS[k % len(_SNAPSHOT_MARKERS)]
        ax.errorbar(
            jb[has], dens[has], err[has], fmt=mk, ms=3, color=c, label=rf"MD $\tau={sci(tau[j])}$"
        )
        shown.append(dens[has])
        if "P_lenard_balescu" in ds:
            lb = ds["P_lenard_balescu"].values[j] / vol
            ax.plot(jb[span], np.where(lb[span] > 0, lb[span], np.nan), color=c, lw=1)
    th = ds["P_thermal"].values / vol
    ax.plot(jb[span], np.where(th[span] > 0, th[span], np.nan), "r:", lw=1, label="thermal")
    ax.set_yscale("log")
    shown = np.concatenate(shown)
    ax.set_ylim(0.3 * shown.min(), 3.0 * max(shown.max(), np.max(th[span])))
    ax.set_xlim(edges[lo], edges[hi + 1])
    ax.set_xlabel(rf"$\bar J$ ({HMF})")
    ax.set_ylabel(r"$f(\bar J)$ (lines: Lenard-Balescu)")
    ax.legend(fontsize=6)


def fig12_relaxation_md(inputs, pdf, png):
    """Per case: <|M|>(t/N), the coarse-grained entropy, the distance of f_MD to the kinetic
    f at matched t/N, and f(J-bar) snapshots; MD at every N against the kinetic evolutions."""
    cases = inputs["relaxation_comparison"]
    fig, axes = plt.subplots(len(cases), 4, figsize=(15, 3.4 * len(cases)), squeeze=False)
    titles = []
    for row, ds in zip(axes, cases, strict=True):
        tau = ds["tau"].values
        pos = tau > 0
        cols = _colours(ds["N"].size)
        ax = row[0]
        for i, n in enumerate(ds["N"].values):
            m, e = ds["M_md"].values[i], ds["M_md_err"].values[i]
            ax.fill_between(tau[pos], (m - e)[pos], (m + e)[pos], color=cols[i], alpha=0.3, lw=0)
            ax.plot(tau[pos], m[pos], color=cols[i], lw=1, label=rf"MD $N={sci(n)}$")
        for eq, label, c, ls in _KIN:
            if f"M_{eq}" in ds:
                ax.plot(tau[pos], ds[f"M_{eq}"].values[pos], color=c, ls=ls, lw=1.2, label=label)
        ax.set_xscale("log")
        ax.set_xlabel(rf"$\tau = t/N$ ({HMF})")
        ax.set_ylabel(r"$\langle|M|\rangle$")
        ax.legend(fontsize=6)
        ax = row[1]
        for i in range(ds["N"].size):
            s, e = ds["S_md"].values[i], ds["S_md_err"].values[i]
            ax.errorbar(tau[pos], s[pos], e[pos], color=cols[i], lw=0.8, ms=2, fmt="o-")
        for eq, label, c, ls in _KIN:
            if f"S_{eq}" in ds:
                ax.plot(tau[pos], ds[f"S_{eq}"].values[pos], color=c, ls=ls, lw=1.2, label=label)
        ax.axhline(float(ds["S_thermal"]), color="r", lw=0.8, ls=":", label="thermal, same $u$")
        ax.set_xscale("log")
        ax.set_xlabel(rf"$\tau = t/N$ ({HMF})")
        ax.set_ylabel(r"coarse-grained $S$")
        ax.legend(fontsize=6)
        ax = row[2]
        for i in range(ds["N"].size):
            d = ds["l1_distance_lenard_balescu"].values[i]
            e = ds["l1_distance_lenard_balescu_err"].values[i]
            ax.errorbar(tau[pos], d[pos], e[pos], color=cols[i], lw=0.8, ms=2, fmt="o-")
            floor = ds["l1_distance_noise_floor"].values[i]
            ax.plot(tau[pos], floor[pos], color=cols[i], ls=":")
        ax.set_xscale("log")
        ax.set_xlabel(rf"$\tau = t/N$ ({HMF})")
        ax.set_ylabel(r"$\sum_b |P_b^{MD} - P_b^{LB}|$ (dotted: noise)")
        _snapshot_panel(row[3], ds)
        case = ds.attrs.get("case", "")
        titles += [
            f"{case}: magnetisation",
            "entropy",
            "L1 distance to Lenard-Balescu",
            rf"snapshots, $N={sci(ds['N'].values[-1])}$",
        ]
    tag_panels(axes, titles)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 12: N-body relaxation against the kinetic equations")


def fig13_relaxation_time(inputs, pdf, png):
    """The MD relaxation time against N (log axes) with the fitted exponent, and the kinetic
    predictions t_R = tau_R N."""
    cases = inputs["relaxation_comparison"]
    fig, axes = plt.subplots(1, len(cases), figsize=(5 * len(cases), 4), squeeze=False)
    titles = []
    for ax, ds in zip(axes[0], cases, strict=True):
        n = ds["N"].values.astype(float)
        tr, te = ds["t_relax_md"].values, ds["t_relax_md_err"].values
        ax.errorbar(n, tr, te, fmt="o", color="C0", label="MD(full) ensembles")
        grid = np.geomspace(n.min() / 1.5, n.max() * 1.5, 50)
        a, ae, amp = ds.attrs["exponent"], ds.attrs["exponent_err"], ds.attrs["prefactor"]
        if np.isfinite(a):
            ax.plot(
                grid, amp * grid**a, "C0-", lw=1, label=rf"fit $\propto N^{{{a:.2f}\pm{ae:.2f}}}$"
            )
        for eq, label, c, ls in _KIN:
            key = f"tau_relax_coarse_{eq}"
            if key in ds and np.isfinite(float(ds[key])):
                t_eq = float(ds[key])
                tr_c = r"\tau_R^{\rm coarse}"
                lab = rf"{label}: $t_R = {tr_c} N$, ${tr_c}={sci(t_eq)}$"
                ax.plot(grid, t_eq * grid, color=c, ls=ls, lw=1, label=lab)
        ax.set_xscale("log")
        shown = [line.get_ydata() for line in ax.get_lines()] + [tr]
        if np.any(np.concatenate([np.ravel(y) for y in shown]) > 0):
            ax.set_yscale("log")
        else:
            ax.text(
                0.5,
                0.5,
                "no relaxation time reached\nwithin the runs",
                transform=ax.transAxes,
                ha="center",
                va="center",
            )
        ax.set_xlabel(r"$N$")
        ax.set_ylabel(rf"coarse-grained relaxation time $t_R$ ({HMF})")
        ax.legend(fontsize=7)
        titles.append(f"{ds.attrs.get('case', '')}: entropy deficit / e")
    tag_panels(axes, titles)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 13: relaxation time against N")
