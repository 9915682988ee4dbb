"""Figures 14 and 15 (issue 15): the fluctuation spectrum of the magnetisation in MD against
the bare and dressed bath spectra, and N*D_MD against N."""

from __future__ import annotations

import numpy as np

from .style import HMF, plt, save_figure, sci, tag_panels

__all__ = ["fig14_spectrum", "fig15_scaling"]

_DYN = (
    ("bath", "MD(bath)", "bare bath", "tab:blue"),
    ("full", "MD(full)", "dressed, $/|\\epsilon|^2$", "tab:red"),
)


def fig14_spectrum(inputs, pdf, png):
    """Fig. 14: N S_x and N S_y measured in MD(bath) and MD(full) (points with errors) against
    the bare and the dressed theory (lines; dashed: convolved with the Welch window), one row
    per inputs["spectrum"] dataset."""
    specs = inputs["spectrum"]
    fig, axes = plt.subplots(len(specs), 2, figsize=(9.0, 3.3 * len(specs)), squeeze=False)
    titles = []
    for row, ds in zip(axes, specs, strict=True):
        Om0 = np.sqrt(float(ds.attrs["M0"]))
        w_fine = ds["omega_theory"].values
        for ax, c in zip(row, "xy", strict=True):
            top, xmax = 0.0, 5.0 * Om0
            for dyn, label, theory, color in _DYN:
                om = ds[f"omega_{dyn}"].values
                k = f"NS{c}_{dyn}"
                y, e = ds[k].values, ds[f"{k}_err"].values
                sel = (om > 0) & (om <= xmax) & (y > 0)
                ax.errorbar(
                    om[sel],
                    y[sel],
                    yerr=np.minimum(e[sel], 0.9 * y[sel]),
                    fmt="o",
                    ms=2.5,
                    color=color,
                    capsize=1.5,
                    label=rf"{label}, $N={sci(ds.attrs[f'N_{dyn}'])}$, "
                    f"{int(ds.attrs[f'n_seeds_{dyn}'])} seeds",
                )
                f = w_fine <= xmax
                ax.plot(
                    w_fine[f],
                    ds[f"{k}_theory_fine"].values[f],
                    "-",
                    color=color,
                    lw=1.0,
                    label=f"theory, {theory}",
                )
                ax.plot(om[sel], ds[f"{k}_smoothed"].values[sel], "--", color=color, lw=0.8)
                top = max(top, np.nanmax(y[sel], initial=0.0))
            for n in (1, 2, 3):
                ax.axvline(n * Om0, color="0.7", lw=0.7, ls=":")
            ax.set_yscale("log")
            ax.set_ylim(top * 1e-5, top * 5)
            ax.set_xlim(0, xmax)
            ax.set_xlabel(rf"$\omega$ ({HMF}); dotted: $\Omega_0$, $2\Omega_0$, $3\Omega_0$")
            ax.set_ylabel(rf"$N S_{c}(\omega)$ ({HMF})")
            ax.legend(fontsize=5.5, loc="lower left")
            titles.append(
                rf"$\delta M_{c}$ ({'along' if c == 'x' else 'across'} $\mathbf{{M}}$), "
                rf"$M_0={sci(ds.attrs['M0'], 4)}$, {ds.attrs.get('case', '')}"
            )
    tag_panels(axes, titles)
    title = "Fig. 14: fluctuation spectrum of the magnetisation, MD against theory"
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, title)


def fig15_scaling(inputs, pdf, png):
    """Fig. 15: N*D_MD against N in a few bins (points with errors), MD(bath) and MD(full),
    from inputs["scaling_bath"][0] and inputs["scaling_full"][0]."""
    sets = [(inputs["scaling_bath"][0], "MD(bath)"), (inputs["scaling_full"][0], "MD(full)")]
    fig, axes = plt.subplots(1, 2, figsize=(9.0, 3.4), squeeze=False)
    titles = []
    for ax, (ds, label) in zip(axes[0], sets, strict=True):
        N = ds["N"].values
        ok = (ds["flag"].values == 0).all(axis=0)
        bins = np.flatnonzero(ok)
        n_pick = min(4, bins.size)
        pick = bins[np.linspace(0, bins.size - 1, n_pick).astype(int)] if n_pick else []
        colors = plt.cm.viridis(np.linspace(0, 0.85, max(len(pick), 1)))
        for b, col in zip(pick, colors, strict=False):
            y, e = ds["ND_md"].values[:, b], ds["ND_md_err"].values[:, b]
            ax.errorbar(
                N,
                y,
                yerr=np.where(np.isfinite(e), e, 0),
                fmt="o-",
                ms=3,
                lw=0.8,
                capsize=2,
                color=col,
                label=rf"$\kappa_0={float(ds['kappa0'][b]):.2f}$",
            )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(r"number of particles $N$")
        ax.set_ylabel(rf"$N D_{{MD}}$ ({HMF})")
        ax.legend(fontsize=6.5)
        w0, w1 = ds.attrs["fit_window"]
        titles.append(
            rf"{label}, $M_0={sci(ds['M0'], 4)}$, fit on $[{sci(w0)}, {sci(w1)}]$, "
            f"{int(ds.attrs['n_seeds'])} seeds"
        )
    tag_panels(axes, titles)
    title = "Fig. 15: N D from MD against N (flat where the kinetic theory's 1/N ordering holds)"
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, title)
