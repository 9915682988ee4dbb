"""Figures 12, 13 and 16: N-body relaxation ensembles against the kinetic evolutions.

All read results/relaxation_comparison/{case}.nc (`analysis.relaxation_compare`): the MD at
every N and the Lenard-Balescu and Landau evolutions on the MD's rescaled times t/N, all in the
coarse-graining of the MD's J-bar bins; figure 16 also the early window across N,
results/relaxation_rates/{case}.nc (`analysis.relaxation_rates`).
"""

from __future__ import annotations

import numpy as np

from .style import HMF, plt, save_figure, sci, tag_panels

__all__ = ["fig12_relaxation_md", "fig13_relaxation_time", "fig16_relaxation_rates"]

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
            if "S_control" in ds and np.isfinite(ds["S_control"].values[i]).any():
                sc = ds["S_control"].values[i]
                ax.plot(tau[pos], sc[pos], color=cols[i], lw=0.8, ls="--")
        for eq, label, c, ls in _KIN:
            if f"S_{eq}" in ds:
                ax.plot(tau[pos], ds[f"S_{eq}"].values[pos], color=c, ls=ls, lw=1.2, label=label)
        ax.axhline(float(ds["S_thermal"]), color="r", lw=0.8, ls=":", label="thermal, same $u$")
        ax.set_xscale("log")
        ax.set_xlabel(rf"$\tau = t/N$ ({HMF})")
        ax.set_ylabel(r"coarse-grained $S$")
        ax.legend(fontsize=6, title="dashed: thermal control, same $N$", title_fontsize=6)
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


def _band(ds, key):
    """(low, high) of the kinetic time `key`'s numerical uncertainty, or None."""
    name = f"{key}_band"
    if name not in ds:
        return None
    low, high = (float(v) for v in ds[name].values)
    return (low, high) if np.isfinite(low) and np.isfinite(high) else None


def fig13_relaxation_time(inputs, pdf, png):
    """The MD relaxation time per particle t_R/N against N (log N) with the fitted power law
    (and the times of runs not rebuilt here, from reference copies, open diamonds), and the
    kinetic predictions tau_R^coarse (order 1/N: independent of N) with their numerical
    uncertainty (grid and harmonics, shaded)."""
    cases = inputs["relaxation_comparison"]
    fig, axes = plt.subplots(1, len(cases), figsize=(8 * len(cases), 4.2), squeeze=False)
    titles = []
    for ax, ds in zip(axes[0], cases, strict=True):
        n = ds["N"].values.astype(float)
        tr, te = ds["t_relax_md"].values / n, ds["t_relax_md_err"].values / n
        ax.errorbar(n, tr, te, fmt="o", color="C0", label="MD(full) ensembles")
        if "t_relax_md_vs_control" in ds and np.isfinite(ds["t_relax_md_vs_control"]).any():
            ax.errorbar(
                n * 1.04,
                ds["t_relax_md_vs_control"].values / n,
                ds["t_relax_md_vs_control_err"].values / n,
                fmt="s",
                mfc="none",
                color="C0",
                label="MD, deficit to the thermal control's level",
            )
        grid = np.geomspace(n.min() / 1.5, n.max() * 1.5, 50)
        a, ae, amp = ds.attrs["exponent"], ds.attrs["exponent_err"], ds.attrs["prefactor"]
        if np.isfinite(a):
            ax.plot(
                grid,
                amp * grid ** (a - 1.0),
                "C0-",
                lw=1,
                label=rf"fit $t_R \propto N^{{{a:.2f}\pm{ae:.2f}}}$",
            )
        if "t_relax_md_reference" in ds:
            nr = ds["N_reference"].values.astype(float)
            ax.errorbar(
                nr,
                ds["t_relax_md_reference"].values / nr,
                ds["t_relax_md_reference_err"].values / nr,
                fmt="D",
                mfc="none",
                color="C0",
                label="MD(full), config/experiments (reference copy)",
            )
            n = np.concatenate((n, nr))
        for eq, label, c, ls in _KIN:
            key = f"tau_relax_coarse_{eq}"
            if key in ds and np.isfinite(float(ds[key])):
                t_eq = float(ds[key])
                tr_c = r"\tau_R^{\rm coarse}"
                ax.axhline(t_eq, color=c, ls=ls, lw=1, label=rf"{label}: ${tr_c}={sci(t_eq)}$")
                band = _band(ds, key)
                if band is not None:
                    ax.axhspan(*band, color=c, alpha=0.15, lw=0, label=f"{label}: grid, harmonics")
                _layer_model_line(ax, ds, eq, label, c, ls, lambda tau: tau)
        ax.set_xscale("log")
        if not np.isfinite(tr).any():
            ax.text(
                0.5,
                0.5,
                "no relaxation time reached\nwithin the runs",
                transform=ax.transAxes,
                ha="center",
                va="center",
            )
        ax.set_xlim(n.min() / 2, n.max() * 2)
        n = np.sort(n)
        ax.set_xticks(n, [f"{v:g}" for v in n])  # the sizes run, without crowded minor labels
        ax.minorticks_off()
        shown = [np.ravel(line.get_ydata()) for line in ax.get_lines()] + [tr + te]
        shown += [np.asarray(_band(ds, f"tau_relax_coarse_{eq}") or [np.nan]) for eq, *_ in _KIN]
        top = np.nanmax(np.concatenate(shown)) if np.isfinite(np.concatenate(shown)).any() else 1
        ax.set_ylim(0.0, 1.2 * top)
        ax.set_xlabel(r"$N$")
        ax.set_ylabel(r"relaxation time per particle $t_R/N$ (coarse-grained)")
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside the data
        titles.append(f"{ds.attrs.get('case', '')}: entropy deficit / e")
    tag_panels(axes, titles)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 13: relaxation time per particle against N")


def _layer_model_line(ax, ds, eq, label, c, ls, transform):
    """The finite-N layer model's tau_R^coarse(N) of `eq` (`tau_relax_coarse_{eq}_layer_model`
    on `N_layer_{eq}`), drawn as transform(tau) against N if the dataset has it; returns the
    sizes drawn (empty if none)."""
    model = f"tau_relax_coarse_{eq}_layer_model"
    if model not in ds:
        return np.empty(0)
    n = ds[f"N_layer_{eq}"].values.astype(float)
    ax.plot(
        n,
        transform(ds[model].values),
        color=c,
        ls=ls,
        marker="v",
        ms=4,
        lw=0.8,
        label=rf"{label}, layer $|\kappa-1|<\delta(N)$ mixed",
    )
    return n


def _rate_panel(ax, ds, key, ylabel):
    """A rate over the early window against N: the state's ensembles, the thermal control, and
    each kinetic equation's value over the same window as a horizontal line."""
    n = ds["N"].values.astype(float)
    st, th = ds.sel(initial="state"), ds.sel(initial="thermal")
    ax.errorbar(n, st[f"{key}_md"], st[f"{key}_md_err"], fmt="o", color="C3", label="N-body")
    ax.errorbar(
        n * 1.08,
        th[f"{key}_md"],
        th[f"{key}_md_err"],
        fmt="s",
        color="0.55",
        ms=4,
        label="thermal control (floor)",
    )
    for eq, label, c, ls in _KIN:
        if f"{key}_{eq}" in ds:
            ax.axhline(float(ds[f"{key}_{eq}"]), color=c, ls=ls, lw=1, label=label)
    ax.axhline(0.0, color="0.8", lw=0.6, zorder=0)
    ax.set_xscale("log")
    # a factor 2 beyond the sizes on each side, as in (d): with one size (the smoke config) the
    # autoscaled log axis spanned 400-432 and its minor tick labels ran into each other
    ax.set_xlim(n.min() / 2, n.max() * 2)
    ax.set_xlabel(r"$N$")
    ax.set_ylabel(ylabel)


def fig16_relaxation_rates(inputs, pdf, png):
    """Fig. 16: the N-body relaxation rate against N: (a) entropy change over the early window
    at each N with the kinetic curves, (b) its rate over the window, (c) the current through the
    core edge, (d) N / t_R of the full relaxation; kinetic predictions as lines, thermal control
    as the floor."""
    ds = inputs["relaxation_rates"][0]
    cmp_ = inputs["relaxation_comparison"][0]
    fig, axes = plt.subplots(2, 2, figsize=(10.0, 7.6), squeeze=False)
    ax = axes[0, 0]
    tau = ds["tau"].values
    cols = _colours(ds.sizes["N"])
    for j, n in enumerate(ds["N"].values):
        for initial, mk, ls in (("state", "o", "-"), ("thermal", "", ":")):
            y = ds["dS_md"].sel(initial=initial).isel(N=j).values
            e = ds["dS_md_err"].sel(initial=initial).isel(N=j).values
            lab = f"$N = {sci(n)}$" if initial == "state" else None
            ax.plot(tau[1:], y[1:], ls=ls, marker=mk, ms=3, color=cols[j], lw=1, label=lab)
            ax.fill_between(tau[1:], (y - e)[1:], (y + e)[1:], color=cols[j], alpha=0.2, lw=0)
    for eq, label, c, ls in _KIN:
        if f"dS_{eq}" in ds:
            ax.plot(tau[1:], ds[f"dS_{eq}"].values[1:], color=c, ls=ls, lw=1.5, label=label)
    ax.set_xscale("log")
    ax.set_xlabel(r"$\tau = t/N$")
    ax.set_ylabel(r"$S(\tau) - S(0)$ (coarse-grained, per particle)")
    ax.legend(fontsize=7, loc="upper left", title="dotted: thermal control", title_fontsize=7)
    tw = sci(ds.attrs["tau_window"])
    _rate_panel(axes[0, 1], ds, "entropy_rate", rf"$[S(\tau_*) - S(0)]/\tau_*$, $\tau_* = {tw}$")
    axes[0, 1].legend(fontsize=7)
    jb = sci(ds.attrs["core_edge_jbar"])
    _rate_panel(
        axes[1, 0],
        ds,
        "current",
        rf"particles out through $\bar J = {jb}$ per unit $\tau$, over $[0, \tau_*]$",
    )
    ax = axes[1, 1]
    n = cmp_["N"].values.astype(float)
    rate = n / cmp_["t_relax_md"].values
    err = rate * cmp_["t_relax_md_err"].values / cmp_["t_relax_md"].values
    ax.errorbar(n, rate, err, fmt="o", color="C3", label=r"N-body $N/t_R$")
    n_all = n
    if "t_relax_md_reference" in cmp_:  # the sizes an experiment ran (figure 13 draws them too)
        nr = cmp_["N_reference"].values.astype(float)
        tr = cmp_["t_relax_md_reference"].values
        rr = nr / tr
        ax.errorbar(
            nr,
            rr,
            rr * cmp_["t_relax_md_reference_err"].values / tr,
            fmt="D",
            mfc="none",
            color="C3",
            label="N-body, config/experiments (reference copy)",
        )
        n_all = np.concatenate((n, nr))
    if not np.isfinite(rate).any():
        ax.text(
            0.5,
            0.5,
            "no data at this size:\nno ensemble relaxed (deficit / e) within its run",
            transform=ax.transAxes,
            ha="center",
            va="center",
            fontsize=8,
        )
    for eq, label, c, ls in _KIN:
        key = f"tau_relax_coarse_{eq}"
        if key in cmp_ and np.isfinite(float(cmp_[key])):
            ax.axhline(1.0 / float(cmp_[key]), color=c, ls=ls, lw=1, label=rf"{label} $1/\tau_R$")
            band = _band(cmp_, key)
            if band is not None:
                ax.axhspan(1.0 / band[1], 1.0 / band[0], color=c, alpha=0.15, lw=0)
            n_layer = _layer_model_line(ax, cmp_, eq, label, c, ls, lambda tau: 1.0 / tau)
            n_all = np.concatenate((n_all, n_layer))
    ax.set_xscale("log")
    ax.set_xlim(n_all.min() / 2, max(n_all.max() * 2, ds["N"].values.max() * 1.5))
    ax.set_ylim(0.0, None)
    ax.set_xlabel(r"$N$")
    ax.set_ylabel(r"relaxation rate $N/t_R$ (per unit $t/N$)")
    ax.legend(fontsize=7)
    case = ds.attrs.get("case", "")
    tag_panels(
        axes,
        [
            f"{case}: entropy over the early window",
            "entropy production over the window",
            "current through the core edge",
            "full relaxation (entropy deficit / e)",
        ],
    )
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 16: N-body relaxation rate against N")
