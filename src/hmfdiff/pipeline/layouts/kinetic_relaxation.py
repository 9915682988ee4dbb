"""Layout of results/relaxation/{case}_{equation}.nc: one collisional relaxation by the Landau or
Lenard-Balescu equation (`kinetic.relaxation.evolve`).

Data contract (read by independent checks): coordinate `tau` (= t/N); variables `M0(tau)`,
`u(tau)` (energy per particle, kinetic plus potential, u = 1/(2 beta) - M0^2/2 for a thermal
state), `S(tau)` (fine-grained entropy -int f ln f), `mass(tau)`; `thermal_distance_max(tau)` =
max |f - f_eq| / max f_eq; `f(tau, Jbar)`; `tau_relax_fine` (e-folding of the fine-grained
entropy deficit); the current `flux(tau_flux, Jbar_face)` at the
chosen times (tau = 0 first); attributes `case`, `equation` and every numerical setting.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from ...meanfield import orbits
from .variables import ACTION, ENERGY_PER_PARTICLE, NONNEGATIVE, UNIT_INTERVAL, variable

__all__ = ["relaxation_times", "kinetic_relaxation_dataset"]

TAU_UNITS = "rescaled time tau = t/N (HMF time units / N)"


def relaxation_times(out):
    """Relaxation times of an evolution: the time at which the fine-grained entropy deficit
    S_eq - S has fallen by a factor e (`tau_relax_fine`), and the initial-rate estimate
    (S_eq - S(0)) / (dS/dtau)(0)."""
    tau, S, S_eq = out["tau"], out["S"], out["S_eq"]
    deficit = (S_eq - S) / (S_eq - S[0])
    below = np.flatnonzero(deficit <= np.exp(-1.0))
    if below.size and below[0] > 0:
        i = below[0]
        x0, x1 = np.log(deficit[i - 1]), np.log(max(deficit[i], 1e-300))
        tau_e = tau[i - 1] + (tau[i] - tau[i - 1]) * (-1.0 - x0) / (x1 - x0)
    else:
        tau_e = np.nan
    return float(tau_e), float((S_eq - S[0]) / out["Sdot"][0])


def kinetic_relaxation_dataset(out, *, case, equation, state, thermal, stability=None, fp0=None):
    """The dataset of one evolution.

    out: `evolve`'s dict; state: the initial state (its analytic M0, u); thermal: the analytic
    `ThermalState` of the same energy; stability: a `StabilityReport` or None; fp0: the
    Fokker-Planck current G-bar at tau = 0 on the faces (existing coefficient code), or None.
    """
    tau, jbar, jface = out["tau"], out["jbar"], out["jbar_face"]
    T, J, F = ("tau",), ("Jbar",), ("Jbar_face",)
    tau_e, tau_rate = relaxation_times(out)
    f_th = thermal.f(orbits.kappa_from_rescaled_action(jbar, thermal.M0))
    data = {
        "f": variable(
            ("tau", "Jbar"),
            out["f"],
            "1",
            "phase-space density f(J-bar, tau), normalised to int f dtheta dp = 1 "
            "(rotating J-bar counts both directions of rotation)",
            valid=NONNEGATIVE,
        ),
        "M0": variable(
            T, out["M0"], "1", "magnetisation M0(tau), self-consistent with f", valid=UNIT_INTERVAL
        ),
        "u": variable(
            T, out["u"], "1", "energy per particle u = <p^2>/2 - M0^2/2", valid=ENERGY_PER_PARTICLE
        ),
        "S": variable(T, out["S"], "1", "entropy S = -int f ln f dtheta dp"),
        "mass": variable(T, out["mass"], "1", "int f dtheta dp", valid=NONNEGATIVE),
        "thermal_distance_max": variable(
            T,
            out["distance"],
            "1",
            "largest deviation from equilibrium max_J |f - f_eq| / max f_eq on the grid, f_eq "
            "the thermal state of u(0) (not the sum_b |dP| of relaxation_comparison)",
            valid=NONNEGATIVE,
        ),
        "beta_fit": variable(T, out["beta_fit"], "1", "beta of a fit ln f = a - beta h"),
        "flux": variable(
            ("tau_flux", "Jbar_face"),
            out["flux"],
            f"{ACTION} / tau",
            "collisional current G-bar through the J-bar grid faces (G/2 librating, G rotating; "
            "4 pi G-bar particles per unit tau), df/dtau = -dG-bar/dJ-bar",
        ),
        "Sdot": variable(
            ("tau_flux",),
            out["Sdot"],
            "1 / tau",
            "entropy production dS/dtau",
            valid=NONNEGATIVE,  # H theorem: sum over resonances of W F X^2 >= 0
        ),
        "cell_width": variable(
            J, out["width"], ACTION, "J-bar width of each node's cell", valid=NONNEGATIVE
        ),
        "f_thermal": variable(
            J,
            out["f_eq"],
            "1",
            "thermal state of energy u(0) on the grid (the end point)",
            valid=NONNEGATIVE,
        ),
        "f_thermal_analytic": variable(
            J,
            f_th,
            "1",
            "analytic thermal state of energy u(0) (thermal_M0_from_energy)",
            valid=NONNEGATIVE,
        ),
        "M0_thermal": variable(
            (), thermal.M0, "1", "M0 of the analytic thermal state of u(0)", valid=UNIT_INTERVAL
        ),
        "beta_thermal": variable(
            (), thermal.beta, "1", "beta of the analytic thermal state", valid=NONNEGATIVE
        ),
        "M0_thermal_grid": variable(
            (), out["M0_eq"], "1", "M0 of the thermal state on the grid", valid=UNIT_INTERVAL
        ),
        "beta_thermal_grid": variable((), out["beta_eq"], "1", "beta of it", valid=NONNEGATIVE),
        "S_thermal_grid": variable((), out["S_eq"], "1", "entropy of it"),
        "tau_relax_fine": variable(
            (),
            tau_e,
            TAU_UNITS,
            "fine-grained relaxation time: tau at which the deficit S_eq - S of the fine-grained "
            "entropy S = -int f ln f dtheta dp (on the kinetic grid) fell by a factor e (not the "
            "coarse-grained tau_relax_coarse_* of relaxation_comparison)",
            valid=NONNEGATIVE,
        ),
        "tau_relax_initial_rate": variable(
            (),
            tau_rate,
            TAU_UNITS,
            "(S_eq - S(0)) / (dS/dtau)(0) of the fine-grained entropy, the initial-rate estimate",
        ),
    }
    if fp0 is not None:
        data["flux_fokker_planck_tau0"] = variable(
            F,
            fp0,
            f"{ACTION} / tau",
            "G-bar at tau = 0 from G = D_pol f - D_dif df/dJ (kinetic.diffusion coefficients of "
            "the initial state); NaN within 1e-4 of the separatrix",
        )
    coords = {
        "tau": variable(T, tau, TAU_UNITS, "rescaled time tau = t/N", valid=NONNEGATIVE),
        "tau_flux": variable(
            ("tau_flux",),
            out["tau_flux"],
            TAU_UNITS,
            "times at which the current is stored",
            valid=NONNEGATIVE,
        ),
        "Jbar": variable(J, jbar, ACTION, "rescaled action J-bar of nodes", valid=NONNEGATIVE),
        "Jbar_face": variable(
            F, jface, ACTION, "J-bar of the faces between nodes", valid=NONNEGATIVE
        ),
    }
    ds = xr.Dataset(data, coords=coords)
    settings = dict(out["settings"])
    settings["flux_times"] = list(settings.get("flux_times", ()))
    ds.attrs.update(
        {
            "case": case,
            "equation": equation,
            "settings": json.dumps(settings, sort_keys=True),
            **{
                f"setting_{k}": (json.dumps(v) if isinstance(v, list | tuple) else v)
                for k, v in settings.items()
            },
            "M0_initial_state": float(state.M0),
            "u_initial_state": float(state.u),
            "n_steps": int(out["n_steps"]),
            "n_rejected": int(out["n_rejected"]),
            "thermalised": int(out["thermalised"]),
            "wall_time_s": float(out["wall_time"]),
            "mass_drift": float(np.max(np.abs(out["mass"] - out["mass"][0]))),
            "u_drift_relative": float(np.max(np.abs(out["u"] - out["u"][0])) / abs(out["u"][0])),
            "separatrix_treatment": (
                "f is held fixed at fixed J-bar while M0 changes; a node passed by the moving "
                "separatrix J-bar_s = 4 sqrt(M0)/pi changes family at fixed J-bar (a librating "
                "torus of action J becomes the two rotating tori of action J/2, half the "
                "particles in each direction); the current G-bar is continuous there"
            ),
        }
    )
    if stability is not None:
        ds.attrs.update(
            {
                "vlasov_zeros_eps_cc": stability.zeros_cc,
                "vlasov_zeros_eps_ss": stability.zeros_ss,
                "vlasov_winding_cc": stability.winding_cc,
                "vlasov_winding_ss": stability.winding_ss,
            }
        )
    return ds
