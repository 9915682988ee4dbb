"""xarray datasets of the pipeline's intermediates: named dimensions, units, long names.

Builders turn the array physics of `equilibrium`, `orbits` and `fourier` into the files that
users open; `state_from_dataset` rebuilds the exact state from a stored equilibrium file.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from . import orbits
from .equilibrium import CoreHaloState, ThermalState, make_state
from .fourier import cos_coefficient, sin_coefficient_imag
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
