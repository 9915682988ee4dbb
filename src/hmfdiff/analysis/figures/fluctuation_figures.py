"""Figures 14 and 15 (issue 15): the fluctuation spectrum of the magnetisation in MD against
the bare and dressed bath spectra, and N*D_MD against N."""

from __future__ import annotations

import numpy as np

from .style import HMF, plt, save_figure, sci, tag_panels

__all__ = ["fig14_spectrum", "fig15_scaling"]

_DYN = (("bath", "MD(bath)", "tab:blue"), ("full", "MD(full)", "tab:red"))
THEORY = (
    "kinetic theory: bare bath spectrum (MD(bath) panels), dressed by "
    "$1/|\\epsilon|^2$ (MD(full) panels)"
)
#: the lowest Welch frequencies, omega < ROTATION_BINS x 2 pi / segment, shaded in MD(full) S_y
ROTATION_BINS = 2


def _spectrum_panel(ax, ds, dyn, c, xmax):
    """One dynamics and component: MD points, the asymptotic theory (black line) and the theory
    convolved with the Welch window (open diamonds at the Welch frequencies)."""
    _, label, color = next(d for d in _DYN if d[0] == dyn)
    om = ds[f"omega_{dyn}"].values
    k = f"NS{c}_{dyn}"
    y, e = ds[k].values, ds[f"{k}_err"].values
    sel = (om > 0) & (om <= xmax) & (y > 0)
    ax.errorbar(
        om[sel],
        y[sel],
        yerr=np.minimum(e[sel], 0.9 * y[sel]),
        fmt="o",
        ms=3,
        color=color,
        capsize=1.5,
        zorder=2,
        label=f"{label} (Welch estimate, mean of seeds)",
    )
    w = ds["omega_theory"].values
    f = (w > 0) & (w <= xmax)
    ax.plot(w[f], ds[f"{k}_theory_fine"].values[f], "-", color="k", lw=1.0, zorder=3, label=THEORY)
    ax.plot(
        om[sel],
        ds[f"{k}_smoothed"].values[sel],
        "D",
        mfc="none",
        mec="0.35",
        ms=4,
        mew=0.8,
        zorder=4,
        label="theory convolved with the Welch window",
    )
    return np.nanmax(y[sel], initial=0.0)


def fig14_spectrum(inputs, pdf, png):
    """Fig. 14: N S_x and N S_y measured in MD(bath) and MD(full) (points with errors) against
    the bare and the dressed theory (black lines; open diamonds: convolved with the Welch
    window), one row per inputs["spectrum"] dataset, one panel per component and dynamics.
    In MD(full) S_y the lowest Welch frequencies are shaded: the direction of M wanders freely
    (eps_ss(0) = 0), which the linear bath spectrum does not contain (the theory vanishes as
    omega -> 0, exponentially: the orbits with Omega -> 0 sit at the separatrix)."""
    specs = inputs["spectrum"]
    fig, axes = plt.subplots(len(specs), 4, figsize=(13.0, 3.3 * len(specs) + 0.7), squeeze=False)
    titles = []
    for row, ds in zip(axes, specs, strict=True):
        Om0 = np.sqrt(float(ds.attrs["M0"]))
        xmax = 5.0 * Om0
        panels = [("x", "bath"), ("x", "full"), ("y", "bath"), ("y", "full")]
        for ax, (c, dyn) in zip(row, panels, strict=True):
            top = _spectrum_panel(ax, ds, dyn, c, xmax)
            for n in (1, 2, 3):
                ax.axvline(n * Om0, color="0.75", lw=0.7, ls=":", zorder=1)
            if (c, dyn) == ("y", "full"):
                lowest = ROTATION_BINS * 2 * np.pi / float(ds.attrs["segment_time_full"])
                ax.axvspan(
                    0,
                    lowest,
                    color="0.9",
                    zorder=0,
                    label=rf"$\omega < {ROTATION_BINS}\times 2\pi/T_{{seg}}$: free rotation "
                    r"of $\mathbf{M}$ ($\epsilon_{ss}(0)=0$), not in the bath spectrum",
                )
            ax.set_yscale("log")
            ax.set_ylim(top * 1e-5, top * 5)
            ax.set_xlim(0, xmax)
            ax.set_xlabel(rf"$\omega$ ({HMF}); dotted: $\Omega_0$, $2\Omega_0$, $3\Omega_0$")
            ax.set_ylabel(rf"$N S_{c}(\omega)$ ({HMF})")
            name = "MD(bath)" if dyn == "bath" else "MD(full)"
            titles.append(
                rf"{name}, $\delta M_{c}$ ({'along' if c == 'x' else 'across'} $\mathbf{{M}}$)"
                "\n"
                rf"{ds.attrs.get('case', '')}, $M_0={sci(ds.attrs['M0'], 4)}$, "
                rf"$N={sci(ds.attrs[f'N_{dyn}'])}$, {int(ds.attrs[f'n_seeds_{dyn}'])} seeds"
            )
    tag_panels(axes, titles, fontsize=7)
    handles = {}
    for ax in axes[0]:
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(lab, h)
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=2, fontsize=7)
    title = "Fig. 14: fluctuation spectrum of the magnetisation, MD against theory"
    fig.suptitle(title, fontsize=9)
    fig.tight_layout(rect=(0, 0.8 / (3.3 * len(specs) + 0.7), 1, 1))
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
