"""Figures 1-3 of the paper: pendulum orbits, action and frequency, poles of the dielectric
integrand.  Each reads inputs["orbits"] = [one orbits dataset] (results/orbits/{case}.nc)."""

from __future__ import annotations

import numpy as np

from ...meanfield import orbits
from .style import HMF, plt, save_figure, sci, tag_panels

__all__ = ["fig01_orbits", "fig02_action_frequency", "fig03_poles"]


def _orbits(inputs):
    (ds,) = inputs["orbits"]
    return ds, float(ds["M0"])


def fig01_orbits(inputs, pdf, png):
    """Fig. 1: a librating (kappa < 1), the separatrix and a rotating orbit (kappa > 1)."""
    _, M0 = _orbits(inputs)
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
    ax.set_ylabel(rf"momentum $p$ ({HMF})")
    ax.set_title(rf"Pendulum orbits, $h=p^2/2-M_0\cos\theta$, $M_0={sci(M0, 4)}$", fontsize=8)
    ax.set_ylim(-1.35 * 2 * np.sqrt(M0) * k_rot, 1.9 * 2 * np.sqrt(M0) * k_rot)
    ax.legend(fontsize=7, loc="upper center", framealpha=0.95, ncol=1)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 1: HMF pendulum orbits")


def fig02_action_frequency(inputs, pdf, png):
    """Fig. 2: (a) J(kappa); (b) Omega(J), inset Omega(kappa)."""
    ds, M0 = _orbits(inputs)
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
    a1.set_xlabel(r"orbit label $\kappa$")
    a1.set_ylabel(rf"action $J$ ({HMF})")
    a1.legend(fontsize=7)
    a2.set_xlabel(rf"action $J$ ({HMF})")
    a2.set_ylabel(rf"frequency $\Omega$ ({HMF})")
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
    tag_panels(
        [a1, a2],
        [
            r"$J$ jumps from $8\sqrt{M_0}/\pi$ to $4\sqrt{M_0}/\pi$ at $\kappa=1$",
            r"$\Omega(J)$; inset $\Omega(\kappa)$",
        ],
    )
    fig.suptitle(rf"Action and frequency, $M_0={sci(M0, 4)}$", fontsize=9)
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 2: action and frequency")


def fig03_poles(inputs, pdf, png):
    """Fig. 3: poles of the dielectric integrand, Omega(kappa) = omega/l."""
    ds, M0 = _orbits(inputs)
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
    ax.set_xlabel(r"orbit label $\kappa$")
    ax.set_ylabel(rf"$\Omega(\kappa)$ and $\omega/\ell$ ({HMF})")
    ax.set_title(rf"Poles of the dielectric integrand, $M_0={sci(M0, 4)}$", fontsize=8)
    ax.legend(fontsize=6.5, loc="upper left")
    fig.tight_layout()
    save_figure(fig, pdf, png, inputs, "Fig. 3: poles of the dielectric integrand")
