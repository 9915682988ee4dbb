"""Figures 8-10 of the paper, from the fits of the molecular dynamics (results/fits/...) and
the kinetic theory: <dJ^2>(dt) with its linear fits, and N D from MD against theory."""

from __future__ import annotations

import numpy as np

from ...meanfield import orbits
from .style import HMF, plt, save_figure, sci, state_label, tag_panels

__all__ = ["fig08_dj2", "fig09_md_thermal", "fig10_md_corehalo"]


def fig08_dj2(inputs, pdf, png):
    """Fig. 8: <dJ^2>(dt) for several J0 (MD(full)), points, with the linear fits; one panel
    per inputs["fit_full"] dataset."""
    fits = inputs["fit_full"]
    fig, axes = plt.subplots(1, len(fits), figsize=(4.6 * len(fits), 3.3), squeeze=False)
    titles = []
    for ax, fit in zip(axes[0], fits, strict=True):
        lag = fit["lag"].values
        N = float(fit.attrs["N"])
        w0, w1 = fit.attrs["fit_window"]
        good = np.flatnonzero((fit["flag"].values == 0) & np.isfinite(fit["ND_md"].values))
        pick = (
            good[np.linspace(0, good.size - 1, min(4, good.size)).astype(int)] if good.size else []
        )
        step = max(1, lag.size // 40)
        # the power of ten goes into the axis label (matplotlib's offset text would sit on the
        # panel title)
        top = np.nanmax(fit["msd"].values[pick]) if len(pick) else 1.0
        k = int(np.floor(np.log10(top))) if np.isfinite(top) and top > 0 else 0
        scale = 10.0**-k
        for i, col in zip(pick, plt.cm.viridis(np.linspace(0, 0.85, len(pick))), strict=False):
            y = fit["msd"].values[i] * scale
            ax.plot(
                lag[::step],
                y[::step],
                "o",
                ms=3,
                color=col,
                label=rf"$J_0={sci(fit['J0'][i])}$ ($\kappa_0={float(fit['kappa0'][i]):.2f}$)",
            )
            slope = 2.0 * float(fit["ND_md"][i]) / N * scale
            b = float(fit["intercept"][i]) * scale
            x = np.linspace(0, lag.max(), 50)
            ax.plot(x, slope * x + b, "--", color=col, lw=0.8)
            xs = np.linspace(w0, w1, 20)
            ax.plot(xs, slope * xs + b, "-", color=col, lw=1.4)
        ax.axvspan(w0, w1, color="0.92", zorder=0)
        ax.set_xlabel(rf"time lag $\Delta t$ ({HMF})")
        unit = rf"$10^{{{k}}}$ {HMF}" if k else HMF
        ax.set_ylabel(rf"$\langle\delta J^2\rangle(\Delta t)$ ({unit})")
        ax.legend(fontsize=6.5)
        titles.append(
            rf"MD(full), $M_0={sci(fit['M0'], 4)}$, $N={sci(N)}$; "
            rf"fit on $[{sci(w0)}, {sci(w1)}]$"
        )
    tag_panels(axes, titles)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 8: mean square action displacement and linear fits")


def _md_vs_theory(inputs, pdf, png, title):
    """Two rows: MD(bath) against Landau, MD(full) against Lenard-Balescu; one column per case
    (inputs["theory"][j], inputs["fit_bath"][j], inputs["fit_full"][j]); where the figure has
    the windowed datasets (inputs["windowed_bath"][j], ...), the theory propagated over the
    fit's lags at each usable bin (`analysis.propagated`) as black crosses."""
    ths = inputs["theory"]
    n = len(ths)
    if not len(inputs["fit_bath"]) == len(inputs["fit_full"]) == n:
        raise ValueError(
            f"{title}: {n} theory, {len(inputs['fit_bath'])} MD(bath) and "
            f"{len(inputs['fit_full'])} MD(full) inputs; one of each per case"
        )
    fig, axes = plt.subplots(2, n, figsize=(4.0 * n, 6.0), squeeze=False)
    rows = (
        ("fit_bath", "D_landau", "MD(bath)", "Landau", "tab:blue"),
        ("fit_full", "D_lenard_balescu", "MD(full)", "Lenard-Balescu", "tab:red"),
    )
    for kind in ("windowed_bath", "windowed_full"):
        if kind in inputs and len(inputs[kind]) != n:
            raise ValueError(f"{title}: {len(inputs[kind])} {kind} inputs for {n} cases")
    for j, th in enumerate(ths):
        jsep = orbits.action_separatrix(float(th["M0"]), +1)
        for r, (kind, var, md_label, th_label, color) in enumerate(rows):
            ax = axes[r, j]
            fit = inputs[kind][j]
            x = fit["jbar0"].values
            xmax = np.nanmax(x) * 1.05
            inside = th["Jbar"].values <= xmax
            ax.semilogy(
                th["Jbar"].values[inside], th[var].values[inside], "k-", lw=1.2, label=th_label
            )
            y = fit["ND_md"].values
            e = fit["ND_md_err"].values
            ok = (fit["flag"].values == 0) & np.isfinite(y) & (y > 0)
            ax.errorbar(
                x[ok],
                y[ok],
                yerr=np.where(np.isfinite(e[ok]), e[ok], 0),
                fmt="o",
                ms=3.5,
                color=color,
                capsize=2,
                label=rf"{md_label}, $N={sci(fit.attrs['N'])}$, "
                f"{int(fit.attrs['n_seeds'])} seeds",
            )
            win = inputs.get(kind.replace("fit", "windowed"))
            if win is not None and "ND_propagated" in win[j]:
                prop = win[j]["ND_propagated"].values
                has = ok & np.isfinite(prop) & (prop > 0)
                ax.plot(
                    x[has],
                    prop[has],
                    "x",
                    ms=4,
                    mew=0.9,
                    color="k",
                    label=f"{th_label} propagated over the fit's lags",
                )
            bad = ~ok & np.isfinite(y) & (y > 0)
            if bad.any():
                ax.plot(
                    x[bad],
                    y[bad],
                    "o",
                    mfc="none",
                    ms=3.5,
                    color="0.5",
                    label="flagged bins (few particles / separatrix)",
                )
            ax.axvline(jsep, color="0.6", lw=0.9)
            if ok.any():  # the y range of the MD points (the theory can fall far below them)
                low = np.nanmin((y - np.where(np.isfinite(e), e, 0))[ok])
                ax.set_ylim(bottom=max(low, np.nanmin(y[ok]) / 10) / 3)
            ax.set_xlabel(rf"$\bar J$ ($J/2$ for $\kappa<1$; {HMF})")
            ax.set_ylabel(rf"$N D_{{dif}}$ ({HMF})")
            ax.set_xlim(0, xmax)
            ax.legend(fontsize=6)
    tag_panels(
        axes,
        [f"{label}, {state_label(th)}" for label in ("MD(bath)", "MD(full)") for th in ths],
    )
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, title)


def fig09_md_thermal(inputs, pdf, png):
    """Fig. 9: N D from MD vs theory for thermal states (top: bath/Landau; bottom: full/LB)."""
    _md_vs_theory(inputs, pdf, png, "Fig. 9: diffusion from MD vs kinetic theory, thermal states")


def fig10_md_corehalo(inputs, pdf, png):
    """Fig. 10: the same for the core-halo state ch2*."""
    _md_vs_theory(inputs, pdf, png, "Fig. 10: diffusion from MD vs kinetic theory, core-halo")
