"""Layout of results/relaxation/{case}_{equation}.nc: one collisional relaxation by the Landau or
Lenard-Balescu equation (`kinetic.relaxation.evolve`).

Data contract (read by independent checks): coordinates `tau` (= t/N) and `eta` (= kappa - 1
of each grid node, the orbit's signed distance to the separatrix: the grid's cells are fixed
in eta and stretch in J-bar with sqrt(M0)); variables `M0(tau)`, `u(tau)` (energy per particle,
kinetic plus potential, u = 1/(2 beta) - M0^2/2 for a thermal state), `S(tau)` (fine-grained
entropy -int f ln f), `mass(tau)`; `thermal_distance_max(tau)` = max |f - f_eq| / max f_eq;
`f(tau, eta)` with the nodes' `Jbar(tau, eta)` and `cell_width(tau, eta)` and their offsets
from the separatrix `Jbar_offset(tau, eta)` (exact where J-bar itself rounds to J-bar_s);
`tau_relax_fine` (e-folding of the fine-grained entropy deficit); `dM0dtau_initial` and
`dM0dtau_early`; the current `flux(tau_flux, eta_face)` at the chosen times (tau = 0 first);
attributes `case`, `equation` and every numerical setting.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from .variables import ACTION, ENERGY_PER_PARTICLE, NONNEGATIVE, UNIT_INTERVAL, variable

#: J-bar of the separatrix over sqrt(M0): 4/pi (eq. (40))
JS_HAT = 4.0 / np.pi

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
    tau = out["tau"]
    grid = out["grid"]
    T, J, F = ("tau",), ("eta",), ("eta_face",)
    TJ = ("tau", "eta")
    tau_e, tau_rate = relaxation_times(out)
    sqM = np.sqrt(np.asarray(out["M0"]))[:, None]
    sqM_flux = np.sqrt(np.asarray(out["M0_flux"]))[:, None]
    xf = 0.5 * (grid.xhat[1:] + grid.xhat[:-1])
    f_th = thermal.f(1.0 + grid.eta)
    data = {
        "f": variable(
            TJ,
            out["f"],
            "1",
            "phase-space density f(J-bar, tau) on the grid's cells (fixed in eta, stretching "
            "in J-bar with sqrt(M0)), normalised to int f dtheta dp = 1 (rotating J-bar counts "
            "both directions of rotation)",
            valid=NONNEGATIVE,
        ),
        "Jbar": variable(
            TJ,
            sqM * (JS_HAT + grid.xhat)[None, :],
            ACTION,
            "rescaled action J-bar of the nodes at M0(tau) (rounds to J-bar_s next to the "
            "separatrix: see Jbar_offset)",
            valid=NONNEGATIVE,
        ),
        "Jbar_offset": variable(
            TJ,
            sqM * grid.xhat[None, :],
            ACTION,
            "J-bar - J-bar_s of the nodes at M0(tau), J-bar_s = 4 sqrt(M0)/pi the separatrix",
        ),
        "cell_width": variable(
            TJ,
            sqM * grid.width_hat[None, :],
            ACTION,
            "J-bar width of each node's cell at M0(tau)",
            valid=NONNEGATIVE,
        ),
        "Jbar_face": variable(
            ("tau_flux", "eta_face"),
            sqM_flux * (JS_HAT + xf)[None, :],
            ACTION,
            "J-bar of the faces between nodes (where the current is given) at M0(tau_flux)",
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
            ("tau_flux", "eta_face"),
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
        "f_thermal": variable(
            J,
            out["f_eq"],
            "1",
            "thermal state of energy u(0) on the grid (the end point), on its cells at "
            "M0_thermal_grid",
            valid=NONNEGATIVE,
        ),
        "f_thermal_analytic": variable(
            J,
            f_th,
            "1",
            "analytic thermal state of energy u(0) (thermal_M0_from_energy) on the orbits "
            "kappa = 1 + eta",
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
        "dM0dtau_initial": variable(
            (),
            out["dM0dtau_initial"],
            "1 / tau",
            "dM0/dtau at tau = 0: sum of the collision operator's dm_i/dtau times the cells' "
            "<cos theta>, over 1 - dF/dM0 (the response of the self-consistent M0); it includes "
            "the instantaneous current of the initial state's layer next to the separatrix, "
            "which adapts within a vanishing time",
        ),
        "dM0dtau_early": variable(
            (),
            out["dM0dtau_early"],
            "1 / tau",
            "(M0(tau_early) - M0(0)) / tau_early, tau_early = the setting early_window: the "
            "early rate of change of the magnetisation, after the layer next to the separatrix "
            "has adapted",
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
        "eta": variable(
            J,
            grid.eta,
            "1",
            "kappa - 1 of each grid node: its signed distance to the separatrix (< 0 "
            "librating, > 0 rotating); the cells are fixed in eta",
            valid=(-1, None),  # kappa >= 0
        ),
        "eta_face": variable(
            F,
            grid.eta_edges[1:-1],
            "1",
            "kappa - 1 at the faces between nodes (0: the separatrix)",
            valid=(-1, None),
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
                "the grid's cells are fixed in eta = kappa - 1 and stretch in J-bar with "
                "sqrt(M0), so that the separatrix J-bar_s = 4 sqrt(M0)/pi is always a face; "
                "f(J-bar) is held fixed while M0 changes (J an adiabatic invariant) and carried "
                "to the cells of the new M0 (the separatrix sweeps through f); a librating torus "
                "of action J becomes the two rotating tori of action J/2, half the particles in "
                "each direction; the current G-bar is continuous there"
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
