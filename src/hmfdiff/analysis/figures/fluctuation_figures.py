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


#: line styles of figure 15's theory: that of the panel's dynamics, the other one
_OWN, _OTHER = "-", "--"
_STYLE_LABELS = (
    (
        _OWN,
        "kinetic theory of the panel's MD, bin-averaged:\nLandau (bare) in MD(bath), "
        "Lenard-Balescu (dressed) in MD(full)",
    ),
    (_OTHER, "the other theory, bin-averaged:\nLenard-Balescu in MD(bath), Landau in MD(full)"),
)
#: MD points of neighbouring bins drawn this far apart (decades of N), not on top of each other
_SHIFT_DECADES = 0.02


def _scaling_panel(ax, ds, colors):
    """One study and dynamics: N D_MD (points, errors from the spread between seeds) in each
    drawn bin, the bin-averaged theory of the dynamics (solid) and the other theory (dashed),
    in the bin's colour.  Returns the bins' legend handles and labels."""
    N = ds["N"].values.astype(float)
    bins = np.flatnonzero(ds["drawn"].values)
    handles, labels = [], []
    for i, (b, col) in enumerate(zip(bins, colors, strict=False)):
        y, e = ds["ND_md"].values[:, b], ds["ND_md_err"].values[:, b]
        e = np.where(np.isfinite(e), np.minimum(e, 0.95 * np.abs(y)), 0.0)
        shift = 10 ** (_SHIFT_DECADES * (i - (len(bins) - 1) / 2))
        h = ax.errorbar(
            N * shift, y, yerr=e, fmt="o", ms=3.5, color=col, capsize=2, lw=0.9, zorder=3
        )
        ax.plot(N, ds["ND_theory"].values[:, b], _OWN, color=col, lw=1.3, zorder=2)
        ax.plot(N, ds["ND_theory_other"].values[:, b], _OTHER, color=col, lw=0.9, alpha=0.6)
        handles.append(h)
        k0, j0 = sci(ds["kappa0"][b], 2), sci(ds["jbar0"][b], 3)
        labels.append(rf"$\kappa_0={k0}$ ($\bar J_0={j0}$)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(N.min() / 10**0.15, N.max() * 10**0.15)
    ax.set_xticks(N, [f"${sci(n)}$" for n in N])
    ax.xaxis.set_minor_formatter(plt.NullFormatter())
    ax.set_xlabel(r"number of particles $N$")
    ax.set_ylabel(rf"$N D$ ({HMF})")
    return handles, labels


def fig15_scaling(inputs, pdf, png):
    """Fig. 15: N D_MD against N (points with errors from the spread between seeds) in the
    drawn bins of each study (one row per inputs["scaling_bath"] / ["scaling_full"] dataset:
    MD(bath), MD(full)), the kinetic theory averaged over each bin like validation.csv's
    ND_theory as lines in the bin's colour: solid the theory of the panel's dynamics (Landau
    for MD(bath), Lenard-Balescu for MD(full)), dashed the other one.  N D is independent of
    N, on the solid line, where the kinetic theory's 1/N ordering holds."""
    pairs = list(zip(inputs["scaling_bath"], inputs["scaling_full"], strict=True))
    rows = len(pairs)
    fig, axes = plt.subplots(rows, 2, figsize=(12.0, 3.6 * rows + 0.4), squeeze=False)
    titles = []
    for row, (bath, full) in zip(axes, pairs, strict=True):
        n_drawn = max(int(bath["drawn"].sum()), int(full["drawn"].sum()), 1)
        colors = plt.cm.viridis(np.linspace(0, 0.85, n_drawn))
        for ax, ds, label in ((row[0], bath, "MD(bath)"), (row[1], full, "MD(full)")):
            handles, labels = _scaling_panel(ax, ds, colors)
            w0, w1 = ds.attrs["fit_window"]
            lo, hi = int(ds["n_seeds"].min()), int(ds["n_seeds"].max())
            n_seeds = f"{lo}" if lo == hi else f"{lo}-{hi}"
            titles.append(
                rf"{label}, {ds.attrs.get('case', '')}: $M_0={sci(ds['M0'], 4)}$"
                "\n"
                rf"fit on $[{sci(w0)}, {sci(w1)}]$, {n_seeds} seeds per $N$"
            )
        # one legend per row, right of its panels (off the data)
        for style, text in _STYLE_LABELS:
            (line,) = row[1].plot([], [], style, color="0.2", lw=1.1)
            handles.append(line)
            labels.append(text)
        row[1].legend(
            handles,
            labels,
            loc="upper left",
            bbox_to_anchor=(1.03, 1.0),
            fontsize=7,
            frameon=False,
            title="bins (points: MD)",
            title_fontsize=7,
        )
    tag_panels(axes, titles, fontsize=7.5)
    title = (
        "Fig. 15: N D from MD against N, with the bin-averaged kinetic theory (flat where the "
        "1/N ordering holds)"
    )
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, title)
