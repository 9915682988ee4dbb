"""xarray datasets of the pipeline's intermediates: named dimensions, units, long names.

Builders turn the array physics of `equilibrium`, `orbits` and `fourier` into the files that
users open; `state_from_dataset` rebuilds the exact state from a stored equilibrium file.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from ..meanfield import orbits
from ..meanfield.equilibrium import CoreHaloState, ThermalState, make_state
from ..meanfield.fourier import cos_coefficient, sin_coefficient_imag
from .io import scalar

__all__ = ["kappa_grid", "equilibrium_dataset", "state_from_dataset", "orbits_dataset"]


def kappa_grid(n_kappa, kappa_max, gap=1e-6):
    """A kappa grid on both sides of the separatrix, denser towards kappa = 1 and excluding it.

    Half the points lie on (0, 1 - gap], half on [1 + gap, kappa_max]; each half is uniform in
    a variable that clusters points towards the separatrix, where J and Omega vary fastest.
    """
    n_lib = n_kappa // 2
    n_rot = n_kappa - n_lib
    s = np.linspace(0.0, 1.0, n_lib)
    lib = (1.0 - gap) * np.sin(0.5 * np.pi * s)  # clusters near 1
    t = np.linspace(0.0, 1.0, n_rot)
    rot = 1.0 + gap + (kappa_max - 1.0 - gap) * t**2  # clusters near 1
    return np.concatenate([lib, rot])


def equilibrium_dataset(state, n_kappa, kappa_max):
    """results/equilibrium/{case}.nc: scalars M0, u (beta), f and df/dkappa on a kappa grid."""
    kappa = kappa_grid(n_kappa, kappa_max)
    f = state.f(kappa)
    dos = 2.0 * np.pi * orbits.phase_space_weight(kappa) * orbits.dJ_dkappa(kappa, state.M0)
    ds = xr.Dataset(
        {
            "f": (
                "kappa",
                f,
                {
                    "units": "1",
                    "long_name": "phase-space density f(kappa), normalised to int f dtheta dp = 1",
                },
            ),
            "dfdkappa": (
                "kappa",
                state.dfdkappa(kappa),
                {"units": "1", "long_name": "df/dkappa (smooth part; steps in attribute 'steps')"},
            ),
            "density_of_states": (
                "kappa",
                dos,
                {
                    "units": "1",
                    "long_name": "phase-space area per unit kappa, "
                    "2 pi dJ/dkappa times 2 on rotating orbits (both directions)",
                },
            ),
            "kappa_distribution": (
                "kappa",
                f * dos,
                {"units": "1", "long_name": "probability density of kappa, f * density_of_states"},
            ),
            "M0": scalar(state.M0, "1", "magnetisation M0 (self-consistent)"),
            "u": scalar(state.u, "1", "energy per particle u = <p^2>/2 - M0^2/2"),
        },
        coords={
            "kappa": (
                "kappa",
                kappa,
                {
                    "units": "1",
                    "long_name": "orbit label kappa = sqrt((h + M0)/(2 M0)); < 1 librating",
                },
            )
        },
    )
    ds.attrs["kind"] = state.kind if not getattr(state, "shape", "") == "step" else "two_step"
    ds.attrs["state_params"] = json.dumps(state.params, sort_keys=True)
    if isinstance(state, ThermalState):
        ds["beta"] = scalar(
            state.beta, "1", "inverse temperature beta, M0 = I1(beta M0)/I0(beta M0)"
        )
    if isinstance(state, CoreHaloState):
        ds["mass"] = scalar(state.mass, "1", "int f_raw dtheta dp before normalisation")
        if state.shape == "step":
            ds.attrs["steps"] = json.dumps(
                {
                    "kappa": list(map(float, state.step_kappas)),
                    "weight": list(map(float, state.step_weights)),
                    "meaning": "df/dkappa = -sum_i weight_i delta(kappa - kappa_i)",
                }
            )
    return ds


def state_from_dataset(ds):
    """Rebuild the equilibrium state stored in an equilibrium dataset (checks M0 agrees)."""
    spec = {"kind": ds.attrs["kind"], **json.loads(ds.attrs["state_params"])}
    state = make_state(spec)
    stored = float(ds["M0"])
    if not np.isclose(state.M0, stored, rtol=1e-10, atol=0):
        raise ValueError(
            f"equilibrium file gives M0 = {stored!r} but its parameters give {state.M0!r}: "
            "the file is stale; rerun the equilibrium rule"
        )
    return state


def orbits_dataset(M0, n_kappa, kappa_max, n_max):
    """results/orbits/{case}.nc: J, J-bar, Omega, dJ/dkappa, dOmega/dkappa, c_n, sigma_n."""
    kappa = kappa_grid(n_kappa, kappa_max)
    n = np.arange(0, n_max + 1)
    c = cos_coefficient(n[:, None], kappa[None, :])
    sig = sin_coefficient_imag(n[:, None], kappa[None, :], 1.0)
    ds = xr.Dataset(
        {
            "J": ("kappa", orbits.action(kappa, M0), {"units": "1", "long_name": "action J"}),
            "Jbar": (
                "kappa",
                orbits.rescaled_action(kappa, M0),
                {"units": "1", "long_name": "rescaled action J-bar (J/2 for kappa < 1)"},
            ),
            "Omega": (
                "kappa",
                orbits.frequency(kappa, M0),
                {"units": "1", "long_name": "orbital frequency Omega = dh/dJ"},
            ),
            "dJ_dkappa": (
                "kappa",
                orbits.dJ_dkappa(kappa, M0),
                {"units": "1", "long_name": "dJ/dkappa"},
            ),
            "dOmega_dkappa": (
                "kappa",
                orbits.dOmega_dkappa(kappa, M0),
                {"units": "1", "long_name": "dOmega/dkappa"},
            ),
            "c": (
                ("n", "kappa"),
                c,
                {
                    "units": "1",
                    "long_name": "c_n = (1/2pi) int cos(theta(w)) exp(-inw) dw (real; c_-n = c_n)",
                },
            ),
            "sigma": (
                ("n", "kappa"),
                sig,
                {
                    "units": "1",
                    "long_name": "s_n = -i sigma_n for p > 0 "
                    "(sigma flips sign for p < 0; s_-n = -s_n)",
                },
            ),
            "M0": scalar(M0, "1", "magnetisation M0"),
        },
        coords={
            "kappa": ("kappa", kappa, {"units": "1", "long_name": "orbit label kappa"}),
            "n": ("n", n, {"long_name": "Fourier harmonic n"}),
        },
    )
    for name, var in ds.data_vars.items():
        if not np.all(np.isfinite(var.values)):
            raise FloatingPointError(f"orbits dataset: non-finite values in {name}")
    return ds


def closed_forms_dataset(
    state, n_kappa=200, kappa_min=0.01, separatrix_band=0.01, omega=None, l_max=6, n_max=2
):
    """results/analytic/{case}.nc: the paper's closed forms for one state (module `analytic`).

    On librating orbits (kappa < 1 - separatrix_band): the Landau sech^4 form and its small-kappa
    expansion (any state), the |n|, |n'| <= n_max librating Landau sum; for a two-step state its
    real dielectric tensor and D with kappa* = kappa (eq. hmfepscc/ss-ch); for a thermal state the
    appendix-C dielectric tensor and the D built from it (valid as M0 -> 1).
    """
    from ..kinetic import analytic

    M0 = state.M0
    kappa = np.linspace(kappa_min, 1.0 - separatrix_band, int(n_kappa))
    omega = np.linspace(0.0, 4.0 * np.sqrt(M0), 401) if omega is None else np.asarray(omega)
    D_units = "action^2 / time (N * D, the 1/N factored out)"

    def kv(vals, long_name):
        return ("kappa", np.asarray(vals, dtype=float), {"units": D_units, "long_name": long_name})

    data = {
        "D_landau_sech4": kv(
            analytic.landau_D_sech4(kappa, state),
            "N D_dif, Landau, sech^4 closed form (eq. coeff-analytic-ncoll; the n = n' = +-1 term)",
        ),
        "D_landau_small_kappa": kv(
            analytic.landau_D_small_kappa(kappa, state),
            "N D_dif ~ 32 pi^2 kappa^4 f (eq. coeff-analytic-ncoll-exp)",
        ),
        "D_landau_librating_sum": kv(
            analytic.landau_D_librating_sum(kappa, state, n_max=n_max),
            f"N D_dif, Landau, librating resonances |n|,|n'| <= {n_max}",
        ),
        "M0": scalar(M0, "1", "magnetisation M0"),
    }
    if state.kind == "thermal" or getattr(state, "shape", "") == "fermi":
        data["Dpol_landau_sech4"] = kv(
            analytic.landau_Dpol_sech4(kappa, state),
            "N D_pol, Landau, sech^4 closed form, sign corrected",
        )
    method = None
    if getattr(state, "shape", "") == "step":
        ecc, ess = analytic.two_step_dielectric(omega, state, l_max=l_max)
        D_lb = analytic.two_step_D(kappa, state, n_max=n_max, collective=True, l_max=l_max)
        method = "two-step core-halo, eq. hmfepscc/ss-ch (corrected), kappa* = kappa"
    elif state.kind == "thermal":
        ecc, ess = analytic.mb_dielectric_appendix_c(omega, M0)
        D_lb = analytic.mb_D_appendix_c(kappa, M0)
        method = "Maxwell-Boltzmann M0 -> 1, appendix C (eps_cc_ap, eps_ss_ap, corrected)"
    if method is not None:
        ecc = np.asarray(ecc, dtype=complex)
        ess = np.asarray(ess, dtype=complex)
        for comp, e in (("cc", ecc), ("ss", ess)):
            data[f"eps_{comp}_real"] = (
                "omega",
                e.real,
                {"units": "1", "long_name": f"Re eps_{comp}(omega), closed form", "method": method},
            )
            data[f"eps_{comp}_imag"] = (
                "omega",
                e.imag,
                {"units": "1", "long_name": f"Im eps_{comp}(omega), closed form", "method": method},
            )
        data["D_lenard_balescu_closed"] = kv(
            D_lb, f"N D_dif with collective effects, {method}, |n|, |n'| <= {n_max}"
        )
    ds = xr.Dataset(
        data,
        coords={
            "kappa": ("kappa", kappa, {"units": "1", "long_name": "orbit label kappa (< 1)"}),
            "omega": ("omega", omega, {"units": "1/time", "long_name": "real frequency"}),
        },
    )
    ds.attrs.update(
        n_max=int(n_max),
        l_max=int(l_max),
        separatrix_band=float(separatrix_band),
        dielectric_method=method or "none",
        D_convention="<dJ^2> = 2 D dt; N*D stored",
    )
    return ds
