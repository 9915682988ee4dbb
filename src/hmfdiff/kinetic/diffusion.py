"""Diffusion and polarisation coefficients in the action J (eqs. hmfCEdif, hmfCEpol, hmfD).

With <dJ^2> = 2 D dt and the factor 1/N taken out (every coefficient here is N * D):

    N D_dif(kappa) = 2 pi^2 sum_{n,n'} sum_{kappa*} n^2 W(kappa*) J'(kappa*) f(kappa*)
                     / |n' Omega'(kappa*)| * B_nn'(kappa, kappa*),
    N D_pol(kappa) = 2 pi^2 sum_{n,n'} sum_{kappa*} n n' W(kappa*) f'(kappa*)
                     / |n' Omega'(kappa*)| * B_nn'(kappa, kappa*),
    B_nn' = c_n(kappa)^2 c_n'(kappa*)^2 / |eps_cc(n Omega)|^2
            + sigma_n(kappa)^2 sigma_n'(kappa*)^2 / |eps_ss(n Omega)|^2,

where J' = dJ/dkappa, f' = df/dkappa, W = 2 on rotating orbits (both directions: the paper's
eq. hmfCEdif counts them once), kappa* runs over every root of n Omega(kappa) = n' Omega(kappa*)
and n, n' run over the non-zero integers of the same sign with |n|, |n'| <= n_max.  The paper's
|D_nn'|^-2 = |c_n c'_n'/eps_cc - s_n s'_n'/eps_ss|^2 also has cc-ss cross terms; they are odd in
the direction of rotation of kappa* (s'_n' flips sign, c'_n' does not) and vanish for librating
kappa* (c_n' and s_n' are never both non-zero), so they cancel in the sum.  The terms (n, n')
and (-n, -n') are equal (|eps(-omega)| = |eps(omega)|): only n, n' > 0 are computed, times 2.
Landau: eps = 1.  The Fokker-Planck flux is D_dif df/dJ - D_pol f; for a thermal state
f'/J' = -beta Omega f, hence D_pol = -beta Omega(kappa) D_dif term by term.
"""

from __future__ import annotations

import numpy as np

from ..meanfield import orbits
from ..meanfield.fourier import cos_coefficient, sin_coefficient_imag
from .dielectric import DielectricTensor
from .resonances import BRANCHES, resonant_kappas

__all__ = ["resonance_table", "coefficients_from_table", "diffusion_coefficients"]

#: kappa* closer than this to the separatrix contribute exactly 0 (their weight ~ |1 - kappa*|)
SEPARATRIX_ROUNDING = 1e-12


def resonance_table(state, kappa, n_max=6):
    """Bare (eps = 1) resonance terms of D_dif and D_pol for every (kappa, n, n', branch).

    Returns a dict of arrays: 'kappa_star' (K, R), 'n', 'nprime', 'branch' (R,) with
    R = 2 n_max^2 resonances ordered (n, n', branch), and the cc and ss parts of the bare terms
    'dif_cc', 'dif_ss', 'pol_cc', 'pol_ss' (K, R) (zero where there is no root), each including
    the factor 2 pi^2 and the factor 2 of the mirror resonance (-n, -n').
    """
    step = getattr(state, "shape", "fermi") == "step"
    M0 = state.M0
    kappa = np.atleast_1d(np.asarray(kappa, dtype=float))
    ns = np.arange(1, n_max + 1)
    n_g, np_g = np.meshgrid(ns, ns, indexing="ij")
    n_r = np.repeat(n_g.ravel(), 2)
    np_r = np.repeat(np_g.ravel(), 2)
    br_r = np.tile(np.arange(2), n_max * n_max)
    ks = resonant_kappas(kappa[:, None, None], n_g[None], np_g[None], M0)  # (K, n, n', 2)
    ks = ks.reshape(kappa.size, -1)  # (K, R) in (n, n', branch) order
    found = np.isfinite(ks)
    near = found & (np.abs(ks - 1.0) < SEPARATRIX_ROUNDING)
    use = found & ~near
    kss = np.where(use, ks, 0.5)  # dummy harmless value where there is no root
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        W = orbits.phase_space_weight(kss)
        dO = np.abs(np_r[None, :] * orbits.dOmega_dkappa(kss, M0))
        Jp = orbits.dJ_dkappa(kss, M0)
        f = state.f(kss)
        fp = state.dfdkappa(kss)
        c_t = cos_coefficient(n_r[None, :], kappa[:, None]) ** 2
        s_t = sin_coefficient_imag(n_r[None, :], kappa[:, None]) ** 2
        c_b = cos_coefficient(np_r[None, :], kss) ** 2
        s_b = sin_coefficient_imag(np_r[None, :], kss) ** 2
        pref = 2.0 * 2.0 * np.pi**2 * W / dO  # 2 pi^2 (eq. hmfCEdif) x 2 (mirror -n, -n')
        dif = pref * n_r[None, :] ** 2 * Jp * f
        # two-step state: f' is a sum of delta functions, D_pol is not a function of kappa
        pol = np.full(dif.shape, np.nan) if step else pref * (n_r * np_r)[None, :] * fp
        out = {
            "dif_cc": dif * c_t * c_b,
            "dif_ss": dif * s_t * s_b,
            "pol_cc": pol * c_t * c_b,
            "pol_ss": pol * s_t * s_b,
        }
    for key, val in out.items():
        if step and key.startswith("pol"):
            continue
        val = np.where(use, val, 0.0)
        if not np.all(np.isfinite(val)):
            raise FloatingPointError(f"non-finite resonance term {key}: kappa too close to 1?")
        out[key] = val
    out.update(kappa_star=ks, n=n_r, nprime=np_r, branch=br_r, branch_names=BRANCHES)
    return out


def _combine(table, inv_cc, inv_ss):
    """Sum the bare terms weighted by 1/|eps|^2 at omega = n Omega(kappa) (shape (K, R))."""
    gam = table["dif_cc"] * inv_cc + table["dif_ss"] * inv_ss
    gam_pol = table["pol_cc"] * inv_cc + table["pol_ss"] * inv_ss
    return gam, gam_pol


def diffusion_coefficients(state, kappa, n_max=6, l_max=6, collective=True, eps=None, **accuracy):
    """N D_dif and N D_pol at the test orbits kappa (eqs. hmfCEdif, hmfCEpol, hmfD).

    collective=False gives the Landau coefficients (eps = 1); collective=True the
    Lenard-Balescu ones, with eps a callable omega -> (eps_cc, eps_ss) (default: the
    `DielectricTensor` of the state with l_max and `accuracy`).

    A two-step core-halo state (shape='step') is accepted with collective=False or an explicit
    eps (its dielectric tensor is the closed form of kinetic.analytic); its 'Dpol' is NaN, since
    df/dkappa is a sum of delta functions and D_pol is not a function of kappa.

    Returns a dict: 'D', 'Dpol' (K,); per resonance 'gamma' (contribution of each resonance to
    D, the paper's gamma(kappa, kappa*)), 'gamma_pol', 'kappa_star' (K, R) with NaN where the
    resonance has no root; 'n', 'nprime', 'branch' (R,); 'eps_cc', 'eps_ss' (n_max, K) at
    omega = n Omega(kappa) (ones for Landau).
    """
    kappa = np.atleast_1d(np.asarray(kappa, dtype=float))
    table = resonance_table(state, kappa, n_max)
    return coefficients_from_table(
        state, kappa, table, n_max=n_max, l_max=l_max, collective=collective, eps=eps, **accuracy
    )


def coefficients_from_table(state, kappa, table, *, n_max, l_max, collective, eps=None, **accuracy):
    """N D_dif and N D_pol at the test orbits kappa from a precomputed `resonance_table(state,
    kappa, n_max)`: the bare terms weighted by 1/|eps(n Omega(kappa))|^2 and summed.

    One table serves both the Landau (collective=False) and the Lenard-Balescu
    (collective=True) coefficients; eps, l_max and `accuracy` as in `diffusion_coefficients`,
    which returns the same dict.
    """
    Om = orbits.frequency(kappa, state.M0)
    omega = np.arange(1, n_max + 1)[:, None] * Om[None, :]  # (n_max, K)
    if collective:
        if eps is None and getattr(state, "shape", "fermi") == "step":
            raise NotImplementedError(
                "two-step core-halo state: pass eps= the closed-form dielectric tensor of "
                "kinetic.analytic (df/dkappa is a sum of delta functions)"
            )
        if eps is None:
            eps = DielectricTensor(state, l_max=l_max, **accuracy)
        e_cc, e_ss = eps(omega)
        e_cc = np.asarray(e_cc, dtype=complex)
        e_ss = np.asarray(e_ss, dtype=complex)
    else:
        e_cc = np.ones(omega.shape, dtype=complex)
        e_ss = np.ones(omega.shape, dtype=complex)
    idx = table["n"] - 1
    inv_cc = 1.0 / np.abs(e_cc[idx, :].T) ** 2  # (K, R)
    inv_ss = 1.0 / np.abs(e_ss[idx, :].T) ** 2
    gam, gam_pol = _combine(table, inv_cc, inv_ss)
    absent = ~np.isfinite(table["kappa_star"])
    return {
        "D": gam.sum(axis=1),
        "Dpol": gam_pol.sum(axis=1),
        "gamma": np.where(absent, np.nan, gam),
        "gamma_pol": np.where(absent, np.nan, gam_pol),
        "kappa_star": table["kappa_star"],
        "n": table["n"],
        "nprime": table["nprime"],
        "branch": table["branch"],
        "eps_cc": e_cc,
        "eps_ss": e_ss,
    }
