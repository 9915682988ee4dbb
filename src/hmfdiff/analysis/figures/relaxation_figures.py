"""Figure 11: collisional relaxation by the Landau and Lenard-Balescu equations.

Reads results/relaxation/{case}_{equation}.nc (`kinetic.relaxation.evolve`, laid out by
`pipeline.layouts.kinetic_relaxation`): per case, f(J-bar) at several tau = t/N against the thermal
state of the same energy, and M0(tau), S(tau) for both equations.
"""

from __future__ import annotations

import numpy as np
from matplotlib.ticker import FixedLocator, NullLocator

from .style import HMF, plt, save_figure, sci, tag_panels

__all__ = ["fig11_relaxation"]

_STYLE = {"landau": ("Landau", "--"), "lenard_balescu": ("Lenard-Balescu", "-")}


def _snapshot_indices(ds, n=5):
    """Steps at tau = 0 and where the entropy deficit has fallen to 1/2, 1/5, 1/20, ... of its
    initial value, and the last step."""
    S, S_eq = ds["S"].values, float(ds["S_thermal_grid"])
    deficit = (S_eq - S) / (S_eq - S[0])
    idx = [0]
    for level in (0.5, 0.2, 0.05, 0.01)[: n - 2]:
        below = np.flatnonzero(deficit <= level)
        if below.size:
            idx.append(int(below[0]))
    idx.append(S.size - 1)
    return sorted(set(idx))


def _tau_r_label(label, ds):
    """The legend entry of one equation: its fine-grained relaxation time, or, where the run
    ended before the entropy deficit fell by e (tau_relax_fine is NaN), that it was not
    reached by the run's last tau."""
    tau_r = float(ds["tau_relax_fine"])
    if np.isfinite(tau_r):
        return rf"{label} ($\tau_R^{{\rm fine}}={sci(tau_r, 3)}$)"
    tau_end = float(ds["tau"].values[-1])
    return rf"{label} ($\tau_R^{{\rm fine}}$ not reached by $\tau={sci(tau_end, 3)}$)"


def _time_axis(ax, taus):
    """tau on a symmetric-log axis, linear from tau = 0 (the initial state, which a log axis
    would hide) to the first positive tau of the runs, logarithmic beyond; the label says
    where the scale changes."""
    positive = np.concatenate([t[t > 0] for t in taus])
    if positive.size:
        lin, end = float(positive.min()), float(positive.max())
        ax.set_xscale("symlog", linthresh=lin, linscale=0.5)
        ax.set_xlim(0.0, end * 1.2)
        # ticks at 0 and at the decades of the log part (symlog's own put some in the linear
        # part, where they crowd the 0)
        decades = 10.0 ** np.arange(np.ceil(np.log10(lin)), np.floor(np.log10(end)) + 1)
        ax.xaxis.set_major_locator(FixedLocator([0.0, *decades]))
        ax.xaxis.set_minor_locator(NullLocator())
        ax.set_xlabel(rf"$\tau = t/N$ ({HMF}; linear up to ${sci(lin, 2)}$, log beyond)")
    else:
        ax.set_xlabel(rf"$\tau = t/N$ ({HMF})")


def _by_case(datasets):
    cases = {}
    for ds in datasets:
        cases.setdefault(ds.attrs["case"], {})[ds.attrs["equation"]] = ds
    return cases


def fig11_relaxation(inputs, pdf, png):
    """Per case (rows): f(J-bar) snapshots under each equation against the thermal f of the same
    energy, M0(tau) and S(tau) for both equations."""
    cases = _by_case(inputs["relaxation"])
    fig, axes = plt.subplots(len(cases), 4, figsize=(15, 3.3 * len(cases)), squeeze=False)
    titles = []
    for row, (case, eqs) in zip(axes, cases.items(), strict=True):
        for ax, eq in zip(row[:2], ("landau", "lenard_balescu"), strict=True):
            label = _STYLE[eq][0]
            if eq not in eqs:
                ax.set_axis_off()
                titles.append(f"{case}: no {label} run")
                continue
            ds = eqs[eq]
            # the nodes' J-bar at each tau (the grid stretches with sqrt(M0))
            jbar = np.atleast_2d(ds["Jbar"].values)
            jbar = np.broadcast_to(jbar, ds["f"].shape)
            idx = _snapshot_indices(ds)
            cols = plt.cm.viridis(np.linspace(0.0, 0.85, len(idx)))
            for c, i in zip(cols, idx, strict=True):
                tau = float(ds["tau"][i])
                ax.plot(jbar[i], ds["f"].values[i], color=c, lw=1, label=rf"$\tau={sci(tau, 3)}$")
            ax.plot(
                jbar[-1], ds["f_thermal_analytic"].values, "r:", lw=1.2, label="thermal, same $u$"
            )
            jbar = jbar[0]
            ax.set_xlim(
                0, jbar[np.flatnonzero(ds["f"].values[0] > 1e-4 * ds["f"].values[0].max())[-1]]
            )
            ax.set_xlabel(rf"$\bar J$ ({HMF})")
            ax.set_ylabel(r"$f(\bar J)$")
            ax.legend(fontsize=6)
            titles.append(f"{case}, {label}: $f$")
        ax_m, ax_s = row[2], row[3]
        for eq, ds in eqs.items():
            label, ls = _STYLE[eq]
            tau = ds["tau"].values
            ax_m.plot(tau, ds["M0"].values, "k", ls=ls, lw=1.2, label=_tau_r_label(label, ds))
            ax_s.plot(tau, ds["S"].values, "k", ls=ls, lw=1.2, label=label)
        first = next(iter(eqs.values()))
        ax_m.axhline(float(first["M0_thermal"]), color="r", ls=":", lw=1, label="thermal, same $u$")
        ax_s.axhline(
            float(first["S_thermal_grid"]), color="r", ls=":", lw=1, label="thermal, same $u$"
        )
        for ax, ylabel in ((ax_m, "$M_0$"), (ax_s, r"fine-grained $S = -\int f \ln f$")):
            _time_axis(ax, [ds["tau"].values for ds in eqs.values()])
            ax.set_ylabel(ylabel)
            ax.legend(fontsize=6)
        titles += [f"{case}: magnetisation", f"{case}: fine-grained entropy"]
    tag_panels(axes, titles)
    fig.tight_layout()
    title = "Fig. 11: collisional relaxation by the Landau and Lenard-Balescu equations"
    save_figure(fig, pdf, png, inputs, title=title)
