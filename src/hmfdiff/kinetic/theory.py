"""Kinetic-theory grids of one equilibrium state (figs. 4, 5, 6, 9, 10), as arrays.

`theory_grid` evaluates, on a kappa grid on both sides of the separatrix, the Landau and
Lenard-Balescu diffusion (N D_dif) and polarisation (N D_pol) coefficients in the action J,
the resonance contributions gamma(kappa, kappa*) of fig. hmfcontribs, and the dielectric tensor
on an omega grid.  `hmfdiff.pipeline.layouts.theory.theory_dataset` lays the result out as a file.
"""

from __future__ import annotations

import json

import numpy as np

from ..meanfield import orbits
from .dielectric import DielectricTensor
from .diffusion import coefficients_from_table, resonance_table

__all__ = ["theory_grid", "default_omega"]


def default_omega(M0, n=401):
    """omega grid of fig. eps: 0 to 4 Omega_0 (Omega_0 = sqrt(M0))."""
    return np.linspace(0.0, 4.0 * np.sqrt(M0), n)


def theory_grid(
    state,
    *,
    n_kappa=400,
    kappa_min=0.01,
    kappa_max=3.0,
    separatrix_band=0.01,
    n_max=6,
    l_max=6,
    omega=None,
    n_panels=48,
    order=20,
):
    """Landau and Lenard-Balescu N D_dif, N D_pol and eps(omega) of `state` (ThermalState or
    CoreHaloState with shape='fermi').

    kappa = linspace(kappa_min, kappa_max, n_kappa); points with |kappa - 1| < separatrix_band are
    kept on the grid but every kappa-dependent array is NaN there (Omega -> 0 and the
    perturbative theory fails at the separatrix; the paper cuts its curves there too).  omega
    defaults to `default_omega(M0)`.  n_panels, order: quadrature of the dielectric integrals.

    Returns a dict: 'kappa', 'masked', 'omega', 'M0'; 'J', 'Jbar', 'Omega' on kappa;
    'landau' and 'lenard_balescu', each {'D', 'Dpol' (kappa,), 'gamma' (kappa, resonance)};
    'resonances' {'n', 'nprime', 'branch' (resonance,), 'kappa_star' (kappa, resonance)};
    'eps_cc', 'eps_ss' (complex, on omega); 'attrs', the settings and conventions.
    """
    if getattr(state, "shape", "fermi") == "step":
        raise NotImplementedError(
            "the two-step core-halo state (shape='step') has delta-function df/dkappa: its "
            "dielectric tensor and diffusion coefficients are the closed forms of kinetic.analytic"
        )
    M0 = state.M0
    kappa = np.linspace(kappa_min, kappa_max, int(n_kappa))
    masked = np.abs(kappa - 1.0) < separatrix_band
    kv = kappa[~masked]
    omega = default_omega(M0) if omega is None else np.asarray(omega, dtype=float)

    eps = DielectricTensor(state, l_max=l_max, n_panels=n_panels, order=order)
    table = resonance_table(state, kv, n_max)
    lan = coefficients_from_table(state, kv, table, n_max=n_max, l_max=l_max, collective=False)
    lb = coefficients_from_table(
        state, kv, table, n_max=n_max, l_max=l_max, collective=True, eps=eps
    )
    eps_cc, eps_ss = eps(omega)

    def full(vals):
        vals = np.asarray(vals)
        out = np.full((kappa.size,) + vals.shape[1:], np.nan, dtype=vals.dtype)
        out[~masked] = vals
        return out

    for name, arr in (("landau", lan), ("lenard_balescu", lb)):
        for key in ("D", "Dpol"):
            if not np.all(np.isfinite(arr[key])):
                raise FloatingPointError(f"non-finite {key} ({name}) outside the separatrix band")
    if not (np.all(np.isfinite(eps_cc)) and np.all(np.isfinite(eps_ss))):
        raise FloatingPointError("non-finite dielectric tensor on the omega grid")

    attrs = {
        "n_max": int(n_max),
        "l_max": int(l_max),
        "separatrix_band": float(separatrix_band),
        "separatrix_band_note": (
            f"NaN for |kappa - 1| < separatrix_band = {separatrix_band}: Omega -> 0 and the "
            "action-angle perturbation theory fails at the separatrix (the paper cuts its "
            "curves there)"
        ),
        "eps_quadrature": f"Gauss-Legendre in Omega per branch: n_panels={n_panels}, "
        f"order={order}; principal values by pole subtraction (hmfdiff.kinetic.dielectric)",
        "eps_kappa_max": float(eps.kappa_max),
        "D_convention": "<dJ^2> = 2 D dt; N*D stored; rotating orbits counted for both directions",
        "time_dependence": "exp(-i omega t)",
        "Omega0": float(np.sqrt(M0)),
        "state_kind": str(getattr(state, "kind", type(state).__name__)),
        "state_params": json.dumps(getattr(state, "params", {})),
    }
    if getattr(state, "beta", None) is not None:
        attrs["beta"] = float(state.beta)
    return {
        "kappa": kappa,
        "masked": masked,
        "omega": omega,
        "M0": M0,
        "J": full(orbits.action(kv, M0)),
        "Jbar": full(orbits.rescaled_action(kv, M0)),
        "Omega": full(orbits.frequency(kv, M0)),
        "landau": {"D": full(lan["D"]), "Dpol": full(lan["Dpol"]), "gamma": full(lan["gamma"])},
        "lenard_balescu": {
            "D": full(lb["D"]),
            "Dpol": full(lb["Dpol"]),
            "gamma": full(lb["gamma"]),
        },
        "resonances": {
            "n": table["n"],
            "nprime": table["nprime"],
            "branch": table["branch"],
            "kappa_star": full(table["kappa_star"]),
        },
        "eps_cc": eps_cc,
        "eps_ss": eps_ss,
        "attrs": attrs,
    }
