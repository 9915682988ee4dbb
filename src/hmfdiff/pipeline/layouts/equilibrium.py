"""Layouts of the mean-field stage: results/equilibrium/{case}.nc (f and the density of states
on `orbits.kappa_grid`; `state_from_dataset` rebuilds the state of a file) and
results/orbits/{case}.nc (actions, frequencies and Fourier coefficients of the orbits)."""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from ...meanfield import orbits
from ...meanfield.equilibrium import CoreHaloState, ThermalState, make_state
from ...meanfield.fourier import cos_coefficient, sin_coefficient_imag
from .variables import COMPONENT, ENERGY_PER_PARTICLE, NONNEGATIVE, UNIT_INTERVAL, variable

__all__ = ["equilibrium_dataset", "state_from_dataset", "orbits_dataset"]


def equilibrium_dataset(state, n_kappa, kappa_max):
    """results/equilibrium/{case}.nc: scalars M0, u (beta), f and df/dkappa on a kappa grid."""
    kappa = orbits.kappa_grid(n_kappa, kappa_max)
    f = state.f(kappa)
    dos = 2.0 * np.pi * orbits.phase_space_weight(kappa) * orbits.dJ_dkappa(kappa, state.M0)
    k = ("kappa",)
    data = {
        "f": variable(
            k,
            f,
            "1",
            "phase-space density f(kappa), normalised to int f dtheta dp = 1",
            valid=NONNEGATIVE,
        ),
        "dfdkappa": variable(
            k, state.dfdkappa(kappa), "1", "df/dkappa (smooth part; steps in attribute 'steps')"
        ),
        "density_of_states": variable(
            k,
            dos,
            "1",
            "phase-space area per unit kappa, "
            "2 pi dJ/dkappa times 2 on rotating orbits (both directions)",
            valid=NONNEGATIVE,
        ),
        "kappa_distribution": variable(
            k,
            f * dos,
            "1",
            "probability density of kappa, f * density_of_states",
            valid=NONNEGATIVE,
        ),
        "M0": variable(
            (), float(state.M0), "1", "magnetisation M0 (self-consistent)", valid=UNIT_INTERVAL
        ),
        "u": variable(
            (),
            float(state.u),
            "1",
            "energy per particle u = <p^2>/2 - M0^2/2",
            valid=ENERGY_PER_PARTICLE,
        ),
    }
    if isinstance(state, ThermalState):
        data["beta"] = variable(
            (),
            float(state.beta),
            "1",
            "inverse temperature beta, M0 = I1(beta M0)/I0(beta M0)",
            valid=NONNEGATIVE,
        )
    if isinstance(state, CoreHaloState):
        data["mass"] = variable(
            (),
            float(state.mass),
            "1",
            "int f_raw dtheta dp before normalisation",
            valid=NONNEGATIVE,
        )
    kc = variable(
        k,
        kappa,
        "1",
        "orbit label kappa = sqrt((h + M0)/(2 M0)); < 1 librating",
        valid=NONNEGATIVE,
    )
    ds = xr.Dataset(data, coords={"kappa": kc})
    ds.attrs["kind"] = state.kind if not getattr(state, "shape", "") == "step" else "two_step"
    ds.attrs["state_params"] = json.dumps(state.params, sort_keys=True)
    if isinstance(state, CoreHaloState) and state.shape == "step":
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
    """results/orbits/{case}.nc: J, J-bar, Omega, dJ/dkappa, dOmega/dkappa, c_n, sigma_n for
    harmonics 0 ... n_max."""
    kappa = orbits.kappa_grid(n_kappa, kappa_max)
    n = np.arange(0, n_max + 1)
    k, nk = ("kappa",), ("n", "kappa")
    data = {
        "J": variable(k, orbits.action(kappa, M0), "1", "action J", valid=NONNEGATIVE),
        "Jbar": variable(
            k,
            orbits.rescaled_action(kappa, M0),
            "1",
            "rescaled action J-bar (J/2 for kappa < 1)",
            valid=NONNEGATIVE,
        ),
        "Omega": variable(
            k,
            orbits.frequency(kappa, M0),
            "1",
            "orbital frequency Omega = dh/dJ",
            valid=NONNEGATIVE,
        ),
        "dJ_dkappa": variable(k, orbits.dJ_dkappa(kappa, M0), "1", "dJ/dkappa", valid=NONNEGATIVE),
        "dOmega_dkappa": variable(k, orbits.dOmega_dkappa(kappa, M0), "1", "dOmega/dkappa"),
        "c": variable(
            nk,
            cos_coefficient(n[:, None], kappa[None, :]),
            "1",
            "c_n = (1/2pi) int cos(theta(w)) exp(-inw) dw (real; c_-n = c_n)",
            valid=COMPONENT,
        ),
        "sigma": variable(
            nk,
            sin_coefficient_imag(n[:, None], kappa[None, :], 1.0),
            "1",
            "s_n = -i sigma_n for p > 0 (sigma flips sign for p < 0; s_-n = -s_n)",
            valid=COMPONENT,
        ),
        "M0": variable((), float(M0), "1", "magnetisation M0", valid=UNIT_INTERVAL),
    }
    for name, var in data.items():
        if not np.all(np.isfinite(var.values)):
            raise FloatingPointError(f"orbits dataset: non-finite values in {name}")
    coords = {
        "kappa": variable(k, kappa, "1", "orbit label kappa", valid=NONNEGATIVE),
        "n": variable(("n",), n, "1", "Fourier harmonic n", valid=NONNEGATIVE),
    }
    return xr.Dataset(data, coords=coords)
