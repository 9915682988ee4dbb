"""Figure 11: collisional relaxation by the Landau and Lenard-Balescu equations.

Reads results/relaxation/{case}_{equation}.nc (`kinetic.relaxation.evolve`, laid out by
`pipeline.layouts.kinetic_relaxation`): per case, f(J-bar) at several tau = t/N against the thermal
state of the same energy, and M0(tau), S(tau) for both equations.
"""

from __future__ import annotations

import numpy as np

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
            jbar = ds["Jbar"].values
            idx = _snapshot_indices(ds)
            cols = plt.cm.viridis(np.linspace(0.0, 0.85, len(idx)))
            for c, i in zip(cols, idx, strict=True):
                tau = float(ds["tau"][i])
                ax.plot(jbar, ds["f"].values[i], color=c, lw=1, label=rf"$\tau={sci(tau, 3)}$")
            ax.plot(jbar, ds["f_thermal_analytic"].values, "r:", lw=1.2, label="thermal, same $u$")
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
            pos = tau > 0
            tau_r = float(ds["tau_relax_fine"])
            lab = rf"{label} ($\tau_R^{{\rm fine}}={sci(tau_r, 3)}$)"
            ax_m.plot(tau[pos], ds["M0"].values[pos], "k", ls=ls, lw=1.2, label=lab)
            ax_s.plot(tau[pos], ds["S"].values[pos], "k", ls=ls, lw=1.2, label=label)
        first = next(iter(eqs.values()))
        ax_m.axhline(float(first["M0_thermal"]), color="r", ls=":", lw=1, label="thermal, same $u$")
        ax_s.axhline(
            float(first["S_thermal_grid"]), color="r", ls=":", lw=1, label="thermal, same $u$"
        )
        for ax, ylabel in ((ax_m, "$M_0$"), (ax_s, r"fine-grained $S = -\int f \ln f$")):
            ax.set_xscale("log")
            ax.set_xlabel(rf"$\tau = t/N$ ({HMF})")
            ax.set_ylabel(ylabel)
            ax.legend(fontsize=6)
        titles += [f"{case}: magnetisation", f"{case}: fine-grained entropy"]
    tag_panels(axes, titles)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, title="Fig. 11: collisional relaxation")
