"""Figures of the paper, drawn from the pipeline's netCDF datasets.

Each figure function takes a dict of datasets, the PDF and PNG paths and the rule's params.
Files are written atomically and carry provenance (config, versions, git revision) in their
metadata.  Axes are labelled with the paper's symbols; all quantities are dimensionless in the
HMF units (coupling, mass and system size set to one; time in units of 1/sqrt(coupling)).
"""

from __future__ import annotations

import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..meanfield import orbits  # noqa: E402
from ..pipeline.io import atomic_path, provenance  # noqa: E402

__all__ = ["FIGURES", "save_figure"]

plt.rcParams.update({"figure.dpi": 100, "savefig.dpi": 150, "font.size": 9, "axes.grid": False})


def save_figure(fig, pdf, png, inputs=None, title=""):
    """Save a figure as PDF and PNG atomically, with provenance in the metadata."""
    prov = provenance()
    sources = {
        k: {
            "case": ds.attrs.get("case", ""),
            "git_revision": ds.attrs.get("git_revision", ""),
            "config": json.loads(ds.attrs.get("config", "{}")),
        }
        for k, ds in (inputs or {}).items()
    }
    subject = json.dumps(
        {
            "inputs": sources,
            "software_versions": json.loads(prov["software_versions"]),
            "git_revision": prov["git_revision"],
            "history": prov["history"],
        },
        sort_keys=True,
    )
    meta_pdf = {
        "Title": title,
        "Subject": subject,
        "Keywords": f"hmfdiff git {prov['git_revision']}",
        "Creator": "hmfdiff",
    }
    meta_png = {
        "Title": title,
        "Description": subject,
        "Software": f"hmfdiff git {prov['git_revision']}",
    }
    with atomic_path(pdf) as tmp:
        fig.savefig(tmp, format="pdf", metadata=meta_pdf)
    with atomic_path(png) as tmp:
        fig.savefig(tmp, format="png", metadata=meta_png)
    plt.close(fig)


def _M0(inputs):
    return float(inputs["orbits_0"]["M0"])


def fig01_orbits(inputs, pdf, png, params=None):
    """Fig. 1: a librating (kappa < 1), the separatrix and a rotating orbit (kappa > 1)."""
    M0 = _M0(inputs)
    fig, ax = plt.subplots(figsize=(4.2, 3.2))
    w = np.linspace(0.0, 2.0 * np.pi, 801)
    k_lib, k_rot = 0.7, 1.25
    th, p = orbits.phase_point(w, k_lib, M0)
    ax.plot(th, p, "r-", lw=1.5, label=rf"librating, $\kappa={k_lib}$")
    thm = np.arccos(1 - 2 * k_lib**2)
    ax.plot([-thm, thm], [0, 0], "r|", ms=8)
    ax.annotate(r"$\pm\theta_m$", (thm, 0), xytext=(4, 4), textcoords="offset points", color="r")
    t = np.linspace(-np.pi, np.pi, 801)
    ps = 2.0 * np.sqrt(M0) * np.cos(0.5 * t)  # h = M0: p = +-2 sqrt(M0) cos(theta/2)
    ax.plot(t, ps, "g--", lw=1.5, label=r"separatrix, $\kappa=1$")
    ax.plot(t, -ps, "g--", lw=1.5)
    for sign in (1.0, -1.0):
        th, p = orbits.phase_point(w, k_rot, M0, sign)
        order = np.argsort(th)
        ax.plot(
            th[order],
            p[order],
            "b:",
            lw=1.8,
            label=rf"rotating, $\kappa={k_rot}$ ($p>0$ and $p<0$)" if sign > 0 else None,
        )
    ax.set_xlim(-np.pi, np.pi)
    ax.set_xticks(
        [-np.pi, -np.pi / 2, 0, np.pi / 2, np.pi],
        [r"$-\pi$", r"$-\pi/2$", "0", r"$\pi/2$", r"$\pi$"],
    )
    ax.set_xlabel(r"angle $\theta$ (rad)")
    ax.set_ylabel(r"momentum $p$")
    ax.set_title(rf"Pendulum orbits, $h=p^2/2-M_0\cos\theta$, $M_0={M0:.4g}$", fontsize=8)
    ax.set_ylim(-1.35 * 2 * np.sqrt(M0) * k_rot, 1.9 * 2 * np.sqrt(M0) * k_rot)
    ax.legend(fontsize=7, loc="upper center", framealpha=0.95, ncol=1)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 1: HMF pendulum orbits")


def fig02_action_frequency(inputs, pdf, png, params=None):
    """Fig. 2: J(kappa) (left); Omega(J) (right), inset Omega(kappa)."""
    ds = inputs["orbits_0"]
    M0 = _M0(inputs)
    k = ds["kappa"].values
    lib = k < 1
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(7.0, 3.0))
    for sel, style, lab in (
        (lib, "r-", r"librating ($\kappa<1$)"),
        (~lib, "b-", r"rotating ($\kappa>1$)"),
    ):
        a1.plot(k[sel], ds["J"].values[sel], style, label=lab)
        a2.plot(ds["J"].values[sel], ds["Omega"].values[sel], style, label=lab)
    a1.axvline(1.0, color="0.6", lw=0.8, ls="--")
    a1.set_xlabel(r"$\kappa$")
    a1.set_ylabel(r"action $J$")
    a1.legend(fontsize=7)
    a1.set_title(r"$J$ jumps from $8\sqrt{M_0}/\pi$ to $4\sqrt{M_0}/\pi$ at $\kappa=1$", fontsize=8)
    a2.set_xlabel(r"action $J$")
    a2.set_ylabel(r"frequency $\Omega$")
    a2.axhline(np.sqrt(M0), color="0.6", lw=0.8, ls=":")
    a2.text(
        0.02,
        np.sqrt(M0) * 1.03,
        r"$\Omega_0=\sqrt{M_0}$",
        fontsize=7,
        transform=a2.get_yaxis_transform(),
    )
    a2.set_ylim(0, None)
    a2.legend(fontsize=7, loc="lower right")
    ins = a2.inset_axes([0.1, 0.58, 0.36, 0.36])
    ins.plot(k[lib], ds["Omega"].values[lib], "r-")
    ins.plot(k[~lib], ds["Omega"].values[~lib], "b-")
    ins.set_xlabel(r"$\kappa$", fontsize=7, labelpad=1)
    ins.set_ylabel(r"$\Omega$", fontsize=7, labelpad=1)
    ins.tick_params(labelsize=6)
    fig.suptitle(rf"Action and frequency, $M_0={M0:.4g}$", fontsize=9)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 2: action and frequency")


def fig03_poles(inputs, pdf, png, params=None):
    """Fig. 3: poles of the dielectric integrand, Omega(kappa) = omega/l."""
    ds = inputs["orbits_0"]
    M0 = _M0(inputs)
    k = ds["kappa"].values
    Om = ds["Omega"].values
    O0 = np.sqrt(M0)
    fig, ax = plt.subplots(figsize=(4.2, 3.2))
    ax.plot(k[k < 1], Om[k < 1], "k-", lw=1.4, label=r"$\Omega(\kappa)$")
    ax.plot(k[k > 1], Om[k > 1], "k-", lw=1.4)
    ax.axvline(1.0, color="0.7", lw=0.8)
    for nu, ls, lab in (
        (0.8 * O0, "--", r"$0<\omega/\ell<\Omega_0$: poles $\kappa_1<1$, $\kappa_2>1$"),
        (1.5 * O0, "-.", r"$\omega/\ell>\Omega_0$: one pole $\kappa_2>1$"),
    ):
        ax.axhline(nu, ls=ls, color="tab:blue" if ls == "--" else "tab:red", lw=1.1, label=lab)
        k1 = orbits.kappa_from_frequency(nu, M0, "libration")
        k2 = orbits.kappa_from_frequency(nu, M0, "rotation")
        for kk, name, dx in ((k1, r"$\kappa_1$", -14), (k2, r"$\kappa_2$", 4)):
            if np.isfinite(kk):
                ax.plot([kk], [nu], "o", color="k", ms=4)
                ax.annotate(name, (kk, nu), xytext=(dx, 4), textcoords="offset points", fontsize=8)
    ax.set_xlim(0, k.max())
    ax.set_ylim(0, min(Om.max(), 2.6 * O0))
    ax.set_xlabel(r"$\kappa$")
    ax.set_ylabel(r"$\Omega(\kappa)$ and $\omega/\ell$")
    ax.set_title(rf"Poles of the dielectric integrand, $M_0={M0:.4g}$", fontsize=8)
    ax.legend(fontsize=6.5, loc="upper left")
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 3: poles of the dielectric integrand")


def _theories(inputs):
    return [inputs[k] for k in sorted(k for k in inputs if k.startswith("theory_"))]


def _state_label(ds):
    M0 = float(ds["M0"])
    cfg = json.loads(ds.attrs.get("config", "{}"))
    label = rf"$M_0={M0:.4g}$"
    if "beta" in ds.attrs:
        u = round(0.5 / ds.attrs["beta"] - 0.5 * M0**2, 10) + 0.0  # no -0 or 1e-17
        label = rf"$(u, M_0)=({u:.4g}, {M0:.4g})$"
    return f"{ds.attrs.get('case', '')}: {label}" if not cfg else label


def _separatrix(ax, vertical=True):
    (ax.axvline if vertical else ax.axhline)(1.0, color="0.6", lw=0.8, zorder=0)


def _merge_same_kappa_star(ds):
    """Sum the contributions of resonances that share kappa* (the same ratio n'/n on the same
    branch, e.g. (1, 1) and (2, 2)), so that each point is one resonant orbit kappa*."""
    from fractions import Fraction

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


def fig04_contributions(inputs, pdf, png, params=None):
    """Fig. 4: normalised contribution gamma(kappa, kappa*)/D_dif(kappa), Lenard-Balescu."""
    ths = _theories(inputs)
    fig, axes = plt.subplots(len(ths), 1, figsize=(4.6, 3.0 * len(ths)), squeeze=False)
    for ax, ds, tag in zip(axes[:, 0], ths, "abcdef", strict=False):
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
        _separatrix(ax)
        _separatrix(ax, vertical=False)
        ax.set_xlim(0, np.nanmax(k))
        ax.set_ylim(0, np.nanmax(k))
        ax.set_xlabel(r"$\kappa$ (test orbit)")
        ax.set_ylabel(r"$\kappa^\star$ (resonant bath orbit)")
        ax.set_title(f"({tag}) {_state_label(ds)}", fontsize=8)
        fig.colorbar(sc, ax=ax, label=r"$\gamma(\kappa,\kappa^\star)/D_{dif}(\kappa)$")
    fig.suptitle(
        "Resonance contributions to $D_{dif}$ (Lenard-Balescu), "
        r"$n\Omega(\kappa)=n'\Omega(\kappa^\star)$",
        fontsize=8,
    )
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 4: resonance contributions to D (Lenard-Balescu)")


def fig05_dielectric(inputs, pdf, png, params=None):
    """Fig. 5: eps_cc(omega) (top) and eps_ss(omega) (bottom): real, imaginary parts, modulus."""
    ds = _theories(inputs)[0]
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
        r"$\omega$ (vertical lines: $\Omega_0$, $2\Omega_0$; $\Omega_0=\sqrt{M_0}$)"
    )
    axes[0].set_title(
        f"Dielectric tensor, {_state_label(ds)}, "
        rf"$\ell_{{max}}={ds.attrs.get('l_max', '?')}$",
        fontsize=8,
    )
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 5: dielectric tensor")


def fig06_landau_lenard_balescu(inputs, pdf, png, params=None):
    """Fig. 6: N D_dif(kappa), Landau (dashed) vs Lenard-Balescu (solid)."""
    ths = _theories(inputs)
    fig, axes = plt.subplots(len(ths), 1, figsize=(4.6, 2.8 * len(ths)), squeeze=False)
    for ax, ds, tag in zip(axes[:, 0], ths, "abcdef", strict=False):
        k = ds["kappa"].values
        ax.semilogy(k, ds["D_lenard_balescu"].values, "r-", lw=1.3, label="Lenard-Balescu")
        ax.semilogy(k, ds["D_landau"].values, "b--", lw=1.3, label="Landau")
        _separatrix(ax)
        ax.set_xlabel(r"$\kappa$")
        ax.set_ylabel(r"$N D_{dif}(\kappa)$  ($\langle\delta J^2\rangle = 2D\,\delta t$)")
        ax.set_title(f"({tag}) {_state_label(ds)}", fontsize=8)
        ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 6: diffusion coefficient, Landau vs Lenard-Balescu")


def _robust_ylim(ax, arrays, pad=0.25):
    vals = np.concatenate([np.ravel(a)[np.isfinite(np.ravel(a))] for a in arrays])
    if vals.size:
        lo, hi = np.percentile(vals, [1, 99])
        span = max(hi - lo, 1e-12)
        ax.set_ylim(lo - pad * span, hi + pad * span)


def fig07_closed_forms(inputs, pdf, png, params=None):
    """Fig. 7: (a-c) smooth core-halo vs the two-step closed form; (d-f) thermal M0 -> 1, numerical
    vs appendix C: eps_cc, eps_ss and N D_dif (Lenard-Balescu)."""
    ths = _theories(inputs)
    smooth, thermal = ths[:-1], ths[-1]
    step, mb = inputs["analytic_0"], inputs["analytic_1"]
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
        _robust_ylim(ax, curves)
        ax.set_xlabel(r"$\omega$")
        ax.set_ylabel(rf"Re $\epsilon_{{{comp}}}(\omega)$")
        ax.set_title(f"({'ab'[j]}) core-halo, " + rf"$\epsilon_{{{comp}}}$", fontsize=8)
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
    ax.set_xlabel(r"$\kappa$")
    ax.set_ylabel(r"$N D_{dif}$ (Lenard-Balescu)")
    ax.set_title("(c) core-halo, diffusion", fontsize=8)
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
        _robust_ylim(ax, [thermal[f"eps_{comp}_real"].values, thermal[f"eps_{comp}_imag"].values])
        ax.set_xlabel(r"$\omega$")
        ax.set_ylabel(rf"$\epsilon_{{{comp}}}(\omega)$")
        ax.set_title(
            f"({'de'[j]}) thermal $M_0={M0:.3g}$, " + rf"$\epsilon_{{{comp}}}$", fontsize=8
        )
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
    ax.set_xlabel(r"$\kappa$")
    ax.set_ylabel(r"$N D_{dif}$ (Lenard-Balescu)")
    ax.set_title(f"(f) thermal $M_0={M0:.3g}$, diffusion", fontsize=8)
    ax.legend(fontsize=6)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 7: closed forms against the numerical theory")


def _fits(inputs, dyn):
    keys = sorted(k for k in inputs if k.startswith(f"fit_{dyn}_"))
    return [inputs[k] for k in keys]


def fig08_dj2(inputs, pdf, png, params=None):
    """Fig. 8: <dJ^2>(dt) for several J0 (MD(full)), points, with the linear fits."""
    fits = _fits(inputs, "full")
    fig, axes = plt.subplots(1, len(fits), figsize=(4.2 * len(fits), 3.3), squeeze=False)
    for ax, fit, tag in zip(axes[0], fits, "abcdef", strict=False):
        lag = fit["lag"].values
        N = float(fit.attrs["N"])
        w0, w1 = fit.attrs["fit_window"]
        good = np.flatnonzero((fit["flag"].values == 0) & np.isfinite(fit["ND_md"].values))
        pick = (
            good[np.linspace(0, good.size - 1, min(4, good.size)).astype(int)] if good.size else []
        )
        step = max(1, lag.size // 40)
        for i, col in zip(pick, plt.cm.viridis(np.linspace(0, 0.85, len(pick))), strict=False):
            y = fit["msd"].values[i]
            ax.plot(
                lag[::step],
                y[::step],
                "o",
                ms=3,
                color=col,
                label=rf"$J_0={float(fit['J0'][i]):.3g}$ "
                rf"($\kappa_0={float(fit['kappa0'][i]):.2f}$)",
            )
            slope = 2.0 * float(fit["ND_md"][i]) / N
            x = np.linspace(0, lag.max(), 50)
            ax.plot(x, slope * x + float(fit["intercept"][i]), "--", color=col, lw=0.8)
            xs = np.linspace(w0, w1, 20)
            ax.plot(xs, slope * xs + float(fit["intercept"][i]), "-", color=col, lw=1.4)
        ax.axvspan(w0, w1, color="0.92", zorder=0)
        ax.set_xlabel(r"$\Delta t$")
        ax.set_ylabel(r"$\langle\delta J^2\rangle(\Delta t)$")
        ax.set_title(
            rf"({tag}) MD(full), $M_0={float(fit['M0']):.4g}$, $N={N:.3g}$; "
            rf"fit on $[{w0:g}, {w1:g}]$ (shaded)",
            fontsize=8,
        )
        ax.legend(fontsize=6.5)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 8: mean square action displacement and linear fits")


def _md_vs_theory(inputs, pdf, png, title):
    n = len([k for k in inputs if k.startswith("theory_")])
    fig, axes = plt.subplots(2, n, figsize=(4.0 * n, 6.0), squeeze=False)
    rows = (
        ("bath", "D_landau", "MD(bath)", "Landau"),
        ("full", "D_lenard_balescu", "MD(full)", "Lenard-Balescu"),
    )
    for j in range(n):
        th = inputs[f"theory_{j}"]
        M0 = float(th["M0"])
        jsep = orbits.action_separatrix(M0, +1)
        for r, (dyn, var, md_label, th_label) in enumerate(rows):
            ax = axes[r, j]
            fit = inputs[f"fit_{dyn}_{j}"]
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
                color="tab:red" if dyn == "full" else "tab:blue",
                capsize=2,
                label=f"{md_label}, N={float(fit.attrs['N']):.3g}, "
                f"{int(fit.attrs['n_seeds'])} seeds",
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
            ax.set_xlabel(r"$\bar J$ ($J/2$ for $\kappa<1$)")
            ax.set_ylabel(r"$N D_{dif}$")
            ax.set_xlim(0, xmax)
            ax.set_title(f"({'abcdef'[j]}) {_state_label(th)}", fontsize=8)
            ax.legend(fontsize=6)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, title)


def fig09_md_thermal(inputs, pdf, png, params=None):
    """Fig. 9: N D from MD vs theory for thermal states (top: bath/Landau; bottom: full/LB)."""
    _md_vs_theory(inputs, pdf, png, "Fig. 9: diffusion from MD vs kinetic theory, thermal states")


def fig10_md_corehalo(inputs, pdf, png, params=None):
    """Fig. 10: the same for the core-halo state ch2*."""
    _md_vs_theory(inputs, pdf, png, "Fig. 10: diffusion from MD vs kinetic theory, core-halo")


FIGURES = {
    "fig01_orbits": fig01_orbits,
    "fig02_action_frequency": fig02_action_frequency,
    "fig03_poles": fig03_poles,
    "fig04_contributions": fig04_contributions,
    "fig05_dielectric": fig05_dielectric,
    "fig06_landau_lenard_balescu": fig06_landau_lenard_balescu,
    "fig07_closed_forms": fig07_closed_forms,
    "fig08_dj2": fig08_dj2,
    "fig09_md_thermal": fig09_md_thermal,
    "fig10_md_corehalo": fig10_md_corehalo,
}
