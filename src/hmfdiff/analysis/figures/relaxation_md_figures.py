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
            d = ds["distance_lenard_balescu"].values[i]
            e = ds["distance_lenard_balescu_err"].values[i]
            ax.errorbar(tau[pos], d[pos], e[pos], color=cols[i], lw=0.8, ms=2, fmt="o-")
            ax.plot(tau[pos], ds["distance_noise_floor"].values[i][pos], color=cols[i], ls=":")
        ax.set_xscale("log")
        ax.set_xlabel(rf"$\tau = t/N$ ({HMF})")
        ax.set_ylabel(r"$\sum_b |P_b^{MD} - P_b^{LB}|$ (dotted: noise)")
        ax = row[3]
        jb = ds["jbar"].values
        width = np.diff(ds["jbar_edges"].values)
        snaps = np.unique(np.linspace(0, tau.size - 1, 3).round().astype(int))
        for k, j in enumerate(snaps):
            i = ds["N"].size - 1  # the largest N
            dens = ds["P_md"].values[i, j] / (4 * np.pi * width)
            err = ds["P_md_err"].values[i, j] / (4 * np.pi * width)
            c = plt.cm.plasma(0.15 + 0.3 * k)
            ax.errorbar(jb, dens, err, fmt="o", ms=2, color=c, label=rf"MD $\tau={sci(tau[j])}$")
            if "P_lenard_balescu" in ds:
                lb = ds["P_lenard_balescu"].values[j] / (4 * np.pi * width)
                ax.plot(jb, lb, color=c, lw=1)
        ax.plot(jb, ds["P_thermal"].values / (4 * np.pi * width), "r:", lw=1, label="thermal")
        ax.set_yscale("log")
        md_pos = ds["P_md"].values[-1] / (4 * np.pi * width)
        md_pos = md_pos[md_pos > 0]
        if md_pos.size:
            ax.set_ylim(0.3 * md_pos.min(), 3.0 * md_pos.max())
        ax.set_xlabel(rf"$\bar J$ ({HMF})")
        ax.set_ylabel(r"$f(\bar J)$ (lines: Lenard-Balescu)")
        ax.legend(fontsize=6)
        case = ds.attrs.get("case", "")
        titles += [
            f"{case}: magnetisation",
            "entropy",
            "distance to Lenard-Balescu",
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
            key = f"tau_relax_{eq}"
            if key in ds and np.isfinite(float(ds[key])):
                t_eq = float(ds[key])
                ax.plot(
                    grid, t_eq * grid, color=c, ls=ls, lw=1, label=rf"{label}: ${sci(t_eq)}\,N$"
                )
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
        ax.set_ylabel(rf"relaxation time $t_R$ ({HMF})")
        ax.legend(fontsize=7)
        titles.append(f"{ds.attrs.get('case', '')}: entropy deficit / e")
    tag_panels(axes, titles)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 13: relaxation time against N")
