"""Figures 4-7 of the paper, from the kinetic-theory grids (results/theory/{case}.nc) and the
closed forms (results/analytic/{case}.nc): resonance contributions, dielectric tensor, Landau
against Lenard-Balescu, and the closed forms against the numerical theory."""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from .style import HMF, plt, robust_ylim, save_figure, sci, separatrix_line, state_label, tag_panels

__all__ = [
    "fig04_contributions",
    "fig05_dielectric",
    "fig06_landau_lenard_balescu",
    "fig07_closed_forms",
]

_ND = rf"$N D_{{dif}}$ ({HMF})"


def _merge_same_kappa_star(ds):
    """Sum the contributions of resonances that share kappa* (the same ratio n'/n on the same
    branch, e.g. (1, 1) and (2, 2)), so that each point is one resonant orbit kappa*."""
    n = ds["resonance_n"].values
    npr = ds["resonance_nprime"].values
    br = ds["resonance_branch"].values
    keys = [(Fraction(int(b), int(a)), int(c)) for a, b, c in zip(n, npr, br, strict=True)]
    groups = {}
    for i, key in enumerate(keys):
        groups.setdefault(key, []).append(i)
    ks_all = ds["resonance_kappa_star"].values
    g_all = ds["gamma_lenard_balescu"].values
    ks = np.stack([ks_all[:, idx[0]] for idx in groups.values()], axis=1)
    g = np.stack([np.nansum(g_all[:, idx], axis=1) for idx in groups.values()], axis=1)
    g[~np.isfinite(ks)] = np.nan
    return ks, g


def fig04_contributions(inputs, pdf, png):
    """Fig. 4: normalised contribution gamma(kappa, kappa*)/D_dif(kappa), Lenard-Balescu, one
    panel per inputs["theory"] dataset."""
    ths = inputs["theory"]
    fig, axes = plt.subplots(len(ths), 1, figsize=(4.6, 3.0 * len(ths)), squeeze=False)
    for ax, ds in zip(axes[:, 0], ths, strict=True):
        k = ds["kappa"].values
        ks, g = _merge_same_kappa_star(ds)
        D = ds["D_lenard_balescu"].values
        frac = g / D[:, None]
        K = np.broadcast_to(k[:, None], ks.shape)
        ok = np.isfinite(frac) & np.isfinite(ks) & (frac > 1e-3)
        order = np.argsort(frac[ok])
        sc = ax.scatter(
            K[ok][order],
            ks[ok][order],
            c=frac[ok][order],
            s=4,
            cmap="viridis",
            vmin=0,
            vmax=1,
            rasterized=True,
        )
        separatrix_line(ax)
        separatrix_line(ax, vertical=False)
        ax.set_xlim(0, np.nanmax(k))
        ax.set_ylim(0, np.nanmax(k))
        ax.set_xlabel(r"orbit label $\kappa$ (test orbit)")
        ax.set_ylabel(r"$\kappa^\star$ (resonant bath orbit)")
        fig.colorbar(sc, ax=ax, label=r"$\gamma(\kappa,\kappa^\star)/D_{dif}(\kappa)$")
    tag_panels(axes[:, 0], [state_label(ds) for ds in ths])
    fig.suptitle(
        "Resonance contributions to $D_{dif}$ (Lenard-Balescu), "
        r"$n\Omega(\kappa)=n'\Omega(\kappa^\star)$",
        fontsize=8,
    )
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 4: resonance contributions to D (Lenard-Balescu)")


def fig05_dielectric(inputs, pdf, png):
    """Fig. 5: (a) eps_cc(omega), (b) eps_ss(omega): real and imaginary parts, modulus."""
    (ds,) = inputs["theory"]
    M0 = float(ds["M0"])
    om = ds["omega"].values
    fig, axes = plt.subplots(2, 1, figsize=(4.6, 5.4), sharex=True)
    for ax, comp, name in zip(axes, ("cc", "ss"), ("cosine", "sine"), strict=True):
        re_, im_ = ds[f"eps_{comp}_real"].values, ds[f"eps_{comp}_imag"].values
        ax.plot(om, re_, "b-", lw=1.2, label=r"Re $\epsilon$")
        ax.plot(om, im_, "r--", lw=1.2, label=r"Im $\epsilon$")
        ax.plot(om, np.hypot(re_, im_), "k:", lw=1.5, label=r"$|\epsilon|$")
        for m in (1, 2):
            ax.axvline(m * np.sqrt(M0), color="0.5", lw=0.8)
        ax.axhline(0, color="0.8", lw=0.6)
        ax.set_ylabel(rf"$\epsilon_{{{comp}}}(\omega)$ ({name})")
        ax.legend(fontsize=7, loc="lower right")
    axes[-1].set_xlabel(
        rf"frequency $\omega$ ({HMF}; lines at $\Omega_0$, $2\Omega_0$, $\Omega_0=\sqrt{{M_0}}$)"
    )
    tag_panels(
        axes,
        [
            f"cosine component, {state_label(ds)}, "
            rf"$\ell_{{max}}={ds.attrs.get('l_max', '?')}$",
            "sine component",
        ],
    )
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 5: dielectric tensor")


def fig06_landau_lenard_balescu(inputs, pdf, png):
    """Fig. 6: N D_dif(kappa), Landau (dashed) vs Lenard-Balescu (solid), one panel per
    inputs["theory"] dataset."""
    ths = inputs["theory"]
    fig, axes = plt.subplots(len(ths), 1, figsize=(4.6, 2.8 * len(ths)), squeeze=False)
    for ax, ds in zip(axes[:, 0], ths, strict=True):
        k = ds["kappa"].values
        ax.semilogy(k, ds["D_lenard_balescu"].values, "r-", lw=1.3, label="Lenard-Balescu")
        ax.semilogy(k, ds["D_landau"].values, "b--", lw=1.3, label="Landau")
        separatrix_line(ax)
        ax.set_xlabel(r"orbit label $\kappa$")
        ax.set_ylabel(_ND)
        ax.legend(fontsize=7)
    tag_panels(axes[:, 0], [state_label(ds) for ds in ths])
    fig.suptitle(
        r"$\langle\delta J^2\rangle = 2D\,\delta t$, with and without collective effects",
        fontsize=8,
    )
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 6: diffusion coefficient, Landau vs Lenard-Balescu")


def fig07_closed_forms(inputs, pdf, png):
    """Fig. 7: (a-c) the smooth core-halo states (inputs["theory_core_halo"]) against the
    two-step closed form (inputs["closed_two_step"]); (d-f) the thermal state M0 -> 1
    (inputs["theory_thermal"]) against appendix C (inputs["closed_thermal"]): eps_cc, eps_ss
    and N D_dif (Lenard-Balescu)."""
    smooth = inputs["theory_core_halo"]
    (thermal,) = inputs["theory_thermal"]
    (step,) = inputs["closed_two_step"]
    (mb,) = inputs["closed_thermal"]
    fig, axes = plt.subplots(2, 3, figsize=(10.5, 5.6))
    colors = ["tab:red", "tab:orange", "tab:purple", "tab:brown"]
    # (a), (b): Re eps of the smooth states and the two-step closed form
    for j, comp in enumerate(("cc", "ss")):
        ax = axes[0, j]
        curves = []
        for ds, col in zip(smooth, colors, strict=False):
            y = ds[f"eps_{comp}_real"].values
            ax.plot(ds["omega"], y, "-", color=col, lw=1.2, label=f"{ds.attrs.get('case', '')}")
            curves.append(y)
        ax.plot(
            step["omega"], step[f"eps_{comp}_real"], "k--", lw=1.0, label="two-step (closed form)"
        )
        robust_ylim(ax, curves)
        ax.set_xlabel(rf"frequency $\omega$ ({HMF})")
        ax.set_ylabel(rf"Re $\epsilon_{{{comp}}}(\omega)$")
        ax.legend(fontsize=6)
    ax = axes[0, 2]
    for ds, col in zip(smooth, colors, strict=False):
        ax.semilogy(
            ds["kappa"],
            ds["D_lenard_balescu"],
            "-",
            color=col,
            lw=1.2,
            label=f"{ds.attrs.get('case', '')} (numerical)",
        )
    ax.semilogy(
        step["kappa"],
        step["D_lenard_balescu_closed"],
        "k--",
        lw=1.0,
        label=r"two-step, $\kappa^\star=\kappa$",
    )
    ax.set_xlim(0, 1)
    ax.set_xlabel(r"orbit label $\kappa$")
    ax.set_ylabel(rf"{_ND} (Lenard-Balescu)")
    ax.legend(fontsize=6)
    # (d), (e): thermal state, numerical vs appendix C
    M0 = float(thermal["M0"])
    for j, comp in enumerate(("cc", "ss")):
        ax = axes[1, j]
        for part, style in (("real", "-"), ("imag", "--")):
            ax.plot(
                thermal["omega"],
                thermal[f"eps_{comp}_{part}"],
                "b" + style,
                lw=1.2,
                label=f"numerical, {'Re' if part == 'real' else 'Im'}",
            )
            ax.plot(
                mb["omega"],
                mb[f"eps_{comp}_{part}"],
                "k" + style,
                lw=0.9,
                alpha=0.7,
                label=f"appendix C, {'Re' if part == 'real' else 'Im'}",
            )
        for m in (1, 2):
            ax.axvline(m * np.sqrt(M0), color="0.7", lw=0.7)
        robust_ylim(ax, [thermal[f"eps_{comp}_real"].values, thermal[f"eps_{comp}_imag"].values])
        ax.set_xlabel(rf"frequency $\omega$ ({HMF})")
        ax.set_ylabel(rf"$\epsilon_{{{comp}}}(\omega)$")
        ax.legend(fontsize=6)
    ax = axes[1, 2]
    ax.semilogy(thermal["kappa"], thermal["D_lenard_balescu"], "b-", lw=1.2, label="numerical")
    ax.semilogy(
        mb["kappa"],
        mb["D_lenard_balescu_closed"],
        "k--",
        lw=1.0,
        label=r"appendix C, $|n|,|n'|\leq 2$",
    )
    ax.set_xlim(0, 1)
    ax.set_xlabel(r"orbit label $\kappa$")
    ax.set_ylabel(rf"{_ND} (Lenard-Balescu)")
    ax.legend(fontsize=6)
    mb_state = rf"thermal $M_0={sci(M0, 3)}$"
    tag_panels(
        axes,
        [
            r"core-halo, $\epsilon_{cc}$",
            r"core-halo, $\epsilon_{ss}$",
            "core-halo, diffusion",
            rf"{mb_state}, $\epsilon_{{cc}}$",
            rf"{mb_state}, $\epsilon_{{ss}}$",
            f"{mb_state}, diffusion",
        ],
    )
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 7: closed forms against the numerical theory")
