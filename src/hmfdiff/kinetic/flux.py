"""The collisional current G(J) of a frozen state by two independent routes (eq. hmflb, fp).

With df/dtau = -dG/dJ (tau = t/N) on each orbit family:

* `hmflb_current`: the resonance sum of eq. hmflb written out term by term, over every
  n, n' != 0 of the same sign, every root kappa* of n Omega(kappa) = n' Omega(kappa*) and both
  directions of rotation of a rotating partner, with the paper's full
  |1/D_nn'|^2 = |c_n c'_n'/eps_cc - s_n conj(s'_n')/eps_ss|^2 (cross terms included):

      G = -2 pi^2 sum n |J'_kappa*| / |n' Omega'(kappa*)| |1/D|^2
              (n f'(kappa)/J_kappa f(kappa*) - n' f(kappa) f'(kappa*)/J'_kappa*);

* `fokker_planck_current`: G = D_pol f - D_dif df/dJ (eq. fp) with the coefficients of
  `diffusion.diffusion_coefficients` (factored bracket, mirror resonances doubled).

The current in J-bar, continuous across the separatrix, is G-bar = G/2 on librating orbits and
G on rotating ones (`jbar_current`).  For a thermal state both routes vanish identically.
"""

from __future__ import annotations

import numpy as np

from ..meanfield import orbits
from ..meanfield.fourier import cos_coefficient, sin_coefficient
from .dielectric import DielectricTensor
from .diffusion import diffusion_coefficients
from .resonances import resonant_kappas

__all__ = [
    "hmflb_current",
    "fokker_planck_current",
    "jbar_current",
    "fokker_planck_jbar_current",
]


def _dielectric(state, collective, l_max, eps):
    if not collective:
        return lambda omega: (np.ones(np.shape(omega), complex), np.ones(np.shape(omega), complex))
    return eps if eps is not None else DielectricTensor(state, l_max=l_max)


def hmflb_current(state, kappa, n_max=6, l_max=6, collective=True, eps=None):
    """G(kappa) in J (per torus) from the term-by-term resonance sum of eq. hmflb."""
    kappa = np.atleast_1d(np.asarray(kappa, dtype=float))
    M0 = state.M0
    eps_fun = _dielectric(state, collective, l_max, eps)
    J_k = orbits.dJ_dkappa(kappa, M0)
    f, fp = state.f(kappa), state.dfdkappa(kappa)
    Om = orbits.frequency(kappa, M0)
    G = np.zeros(kappa.size)
    for n in [m for m in range(-n_max, n_max + 1) if m != 0]:
        e_cc, e_ss = eps_fun(n * Om)
        for npr in [m for m in range(-n_max, n_max + 1) if m * n > 0]:
            roots = resonant_kappas(kappa, n, npr, M0)
            for branch in range(roots.shape[-1]):
                ks = roots[..., branch]
                ok = np.isfinite(ks) & (np.abs(ks - 1.0) > 1e-12)
                if not np.any(ok):
                    continue
                k, kst = kappa[ok], ks[ok]
                Jst = orbits.dJ_dkappa(kst, M0)
                dOm = np.abs(npr * orbits.dOmega_dkappa(kst, M0))
                fst, fpst = state.f(kst), state.dfdkappa(kst)
                directions = (1.0, -1.0) if branch == 1 else (1.0,)
                inv_d2 = 0.0
                for sgn in directions:
                    amp = (
                        cos_coefficient(n, k) * cos_coefficient(npr, kst) / e_cc[ok]
                        - sin_coefficient(n, k) * np.conj(sin_coefficient(npr, kst, sgn)) / e_ss[ok]
                    )
                    inv_d2 = inv_d2 + np.abs(amp) ** 2
                bracket = n * fp[ok] / J_k[ok] * fst - npr * f[ok] * fpst / Jst
                G[ok] -= 2.0 * np.pi**2 * n * Jst / dOm * inv_d2 * bracket
    return G


def fokker_planck_current(state, kappa, n_max=6, l_max=6, collective=True, eps=None):
    """G(kappa) = D_pol f - D_dif df/dJ with `diffusion_coefficients` (eq. fp)."""
    kappa = np.atleast_1d(np.asarray(kappa, dtype=float))
    r = diffusion_coefficients(
        state, kappa, n_max=n_max, l_max=l_max, collective=collective, eps=eps
    )
    dfdJ = state.dfdkappa(kappa) / orbits.dJ_dkappa(kappa, state.M0)
    return r["Dpol"] * state.f(kappa) - r["D"] * dfdJ


def jbar_current(G, kappa):
    """The current in J-bar, G-bar = G/2 (librating) or G (rotating): continuous at kappa = 1."""
    return np.where(np.asarray(kappa) < 1.0, 0.5, 1.0) * np.asarray(G)


def fokker_planck_jbar_current(state, jbar, n_max=6, l_max=6, collective=True, band=1e-4):
    """G-bar (the current in J-bar) of `state` at rescaled actions `jbar` by the Fokker-Planck
    route (`fokker_planck_current`), NaN where |kappa - 1| < band (the coefficients diverge
    at the separatrix)."""
    kappa = orbits.kappa_from_rescaled_action(np.asarray(jbar, dtype=float), state.M0)
    out = np.full(kappa.shape, np.nan)
    ok = np.abs(kappa - 1.0) >= band
    G = fokker_planck_current(state, kappa[ok], n_max=n_max, l_max=l_max, collective=collective)
    out[ok] = jbar_current(G, kappa[ok])
    return out
