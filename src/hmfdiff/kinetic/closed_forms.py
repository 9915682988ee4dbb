"""The paper's closed forms of one state tabulated on grids (results/analytic/{case}.nc), as
arrays: the functions of `kinetic.analytic` on librating orbits and on an omega grid.

`hmfdiff.pipeline.layouts.theory.closed_forms_dataset` lays the result out as a file.
"""

from __future__ import annotations

import numpy as np

from ..meanfield.equilibrium import thermal_beta
from . import analytic

__all__ = ["closed_forms", "APPENDIX_C_MAX_EXPANSION"]

#: appendix C expands in 1/(beta M0) (harmonic, deeply librating orbits, M0 -> 1): flagged as
#: applicable up to 0.2 (M0 >= 0.9; M0 = 0.95: 0.1), outside it stored but flagged
APPENDIX_C_MAX_EXPANSION = 0.2


def closed_forms(
    state, *, n_kappa=200, kappa_min=0.01, separatrix_band=0.01, omega=None, l_max=6, n_max=2
):
    """The paper's closed forms for one state, on librating orbits kappa < 1 - separatrix_band.

    Any state: the Landau sech^4 form (eq. coeff-analytic-ncoll) and its small-kappa expansion
    (eq. coeff-analytic-ncoll-exp), the |n|, |n'| <= n_max librating Landau sum; thermal and
    smooth core-halo states: the sech^4 D_pol (sign corrected).  A two-step state: its real
    dielectric tensor and the D built from it with kappa* = kappa (eq. hmfepscc/ss-ch); a
    thermal state: the appendix-C dielectric tensor and the D built from it (valid as M0 -> 1).

    Returns a dict: 'kappa', 'omega', 'M0'; 'D' {name: N D on kappa}; 'eps' {'cc', 'ss':
    complex on omega} (empty without a closed-form tensor); 'dielectric_method' (None without
    one); 'expansion_parameter' (1/(beta M0) for appendix C, else NaN) and 'applies' (False
    where appendix C is used beyond APPENDIX_C_MAX_EXPANSION); 'n_max', 'l_max',
    'separatrix_band'.
    """
    M0 = state.M0
    kappa = np.linspace(kappa_min, 1.0 - separatrix_band, int(n_kappa))
    omega = np.linspace(0.0, 4.0 * np.sqrt(M0), 401) if omega is None else np.asarray(omega)
    D = {
        "D_landau_sech4": analytic.landau_D_sech4(kappa, state),
        "D_landau_small_kappa": analytic.landau_D_small_kappa(kappa, state),
        "D_landau_librating_sum": analytic.landau_D_librating_sum(kappa, state, n_max=n_max),
    }
    if state.kind == "thermal" or getattr(state, "shape", "") == "fermi":
        D["Dpol_landau_sech4"] = analytic.landau_Dpol_sech4(kappa, state)
    eps = {}
    method = None
    expansion, applies = np.nan, True
    if getattr(state, "shape", "") == "step":
        ecc, ess = analytic.two_step_dielectric(omega, state, l_max=l_max)
        D["D_lenard_balescu_closed"] = analytic.two_step_D(
            kappa, state, n_max=n_max, collective=True, l_max=l_max
        )
        method = "two-step core-halo, eq. hmfepscc/ss-ch (corrected), kappa* = kappa"
    elif state.kind == "thermal":
        ecc, ess = analytic.mb_dielectric_appendix_c(omega, M0)
        D["D_lenard_balescu_closed"] = analytic.mb_D_appendix_c(kappa, M0)
        method = "Maxwell-Boltzmann M0 -> 1, appendix C (eps_cc_ap, eps_ss_ap, corrected)"
        expansion = 1.0 / (thermal_beta(M0) * M0)
        applies = bool(expansion <= APPENDIX_C_MAX_EXPANSION)
    if method is not None:
        eps = {"cc": np.asarray(ecc, dtype=complex), "ss": np.asarray(ess, dtype=complex)}
    return {
        "kappa": kappa,
        "omega": omega,
        "M0": M0,
        "D": D,
        "eps": eps,
        "dielectric_method": method,
        "expansion_parameter": float(expansion),
        "applies": applies,
        "applies_up_to": APPENDIX_C_MAX_EXPANSION,
        "n_max": n_max,
        "l_max": l_max,
        "separatrix_band": separatrix_band,
    }
