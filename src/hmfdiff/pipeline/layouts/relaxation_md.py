"""Layout of the N-body relaxation: results/relaxation_md/{case}/N{N}.nc, an ensemble of
realisations of MD(full) from one initial state.

The density and entropy of the histograms come from `meanfield.histograms` (mean-field physics,
like the rest of the layouts)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from ...meanfield.histograms import density_from_histogram, entropy_from_histogram
from ...paper_equations import eq
from .variables import ENERGY_PER_PARTICLE, NONNEGATIVE, UNIT_INTERVAL
from .variables import variable as _var

__all__ = ["MEASURE_NAMES", "relaxation_md_dataset"]

#: the J-bar measures besides the mean field's (`dynamics.ensemble.ACTION_MEASURES`)
MEASURE_NAMES = {"_own": "each realisation's own |M|", "_static": "the initial state's static M0"}


def relaxation_md_dataset(out, edges, *, case, state, n_particles, run):
    """Dataset of `dynamics.ensemble.run_ensemble` output: histograms, |M|, energy, momentum
    per realisation, ensemble means and spreads, the entropy of the pooled histogram."""
    edges = np.asarray(edges, dtype=float)
    t = out["time"]
    R = out["M_abs"].shape[1]
    hist, overflow = out["hist"], out["overflow"]
    pooled = hist.sum(axis=1)
    pooled_over = overflow.sum(axis=1)
    a1 = "action (dimensionless HMF units)"
    e0 = out["energy"][0]
    ds = xr.Dataset(
        {
            "M_abs": _var(
                ("t", "realisation"),
                out["M_abs"],
                "1",
                "modulus of the magnetisation |M| of each realisation",
                valid=UNIT_INTERVAL,
            ),
            "M_phase": _var(
                ("t", "realisation"),
                out["M_phase"],
                "rad",
                "direction of the magnetisation arg(Mx + i My)",
                valid=(-np.pi, np.pi),
            ),
            "energy": _var(
                ("t", "realisation"),
                out["energy"],
                "energy per particle",
                f"H/N = sum p^2/(2N) - |M|^2/2 ({eq('hmfhamiltonian')})",
                valid=ENERGY_PER_PARTICLE,
            ),
            "momentum": _var(
                ("t", "realisation"),
                out["momentum"],
                "momentum per particle",
                "total momentum per particle sum p_i / N",
            ),
            "energy_drift": _var(
                ("t", "realisation"),
                out["energy"] - e0[None, :],
                "energy per particle",
                "H/N(t) - H/N(0)",
            ),
            "M_abs_mean": _var(
                ("t",),
                out["M_abs"].mean(axis=1),
                "1",
                "ensemble mean of |M|",
                valid=UNIT_INTERVAL,
            ),
            "M_abs_std": _var(
                ("t",),
                out["M_abs"].std(axis=1, ddof=1) if R > 1 else np.zeros(t.size),
                "1",
                "standard deviation of |M| between realisations",
                valid=UNIT_INTERVAL,
            ),
            "M0_actions": _var(
                ("t",),
                out["M0_actions"],
                "1",
                "magnetisation defining the actions: ensemble mean of |M| at that time",
                valid=UNIT_INTERVAL,
            ),
            "hist": _var(
                ("t", "realisation", "jbar"),
                hist.astype(np.int32),
                "1",
                "number of particles per J-bar bin, in the realisation's magnetisation frame",
                valid=(0, n_particles),
            ),
            "overflow": _var(
                ("t", "realisation"),
                overflow.astype(np.int32),
                "1",
                "number of particles beyond the last J-bar edge",
                valid=(0, n_particles),
            ),
            "f_jbar": _var(
                ("t", "jbar"),
                density_from_histogram(pooled, edges, pooled_over),
                "1",
                "phase-space density f(J-bar) of the pooled histogram, normalised to one particle",
                valid=NONNEGATIVE,
            ),
            "entropy": _var(
                ("t",),
                entropy_from_histogram(pooled, edges, pooled_over),
                "1",
                "coarse-grained entropy -sum_b P_b ln(P_b / (4 pi dJbar_b)), pooled histogram",
            ),
            "entropy_realisation": _var(
                ("t", "realisation"),
                entropy_from_histogram(hist, edges, overflow),
                "1",
                "coarse-grained entropy of each realisation's histogram",
            ),
        },
        coords={
            "t": _var(("t",), t, "time", "time t in HMF units (not rescaled)", valid=NONNEGATIVE),
            "tau": _var(
                ("t",), t / n_particles, "time", "rescaled time tau = t / N", valid=NONNEGATIVE
            ),
            "realisation": _var(
                ("realisation",),
                np.arange(R),
                "1",
                "index of the realisation (its seed member)",
                valid=NONNEGATIVE,
            ),
            "jbar": _var(
                ("jbar",),
                0.5 * (edges[1:] + edges[:-1]),
                a1,
                "centre of the J-bar bin",
                valid=NONNEGATIVE,
            ),
            "jbar_edges": _var(
                ("jbar_edge",), edges, a1, "edges of the J-bar bins", valid=NONNEGATIVE
            ),
        },
    )
    for measure, how in MEASURE_NAMES.items():
        if "hist" + measure not in out:
            continue
        h, o = out["hist" + measure], out["overflow" + measure]
        ds["hist" + measure] = _var(
            ("t", "realisation", "jbar"),
            h.astype(np.int32),
            "1",
            f"number of particles per J-bar bin, J-bar measured with {how}",
            valid=(0, n_particles),
        )
        ds["overflow" + measure] = _var(
            ("t", "realisation"),
            o.astype(np.int32),
            "1",
            f"number of particles beyond the last J-bar edge, J-bar measured with {how}",
            valid=(0, n_particles),
        )
        ds["entropy" + measure] = _var(
            ("t",),
            entropy_from_histogram(h.sum(axis=1), edges, o.sum(axis=1)),
            "1",
            f"coarse-grained entropy of the pooled histogram, J-bar measured with {how}",
        )
    ds.attrs.update(
        {
            "title": f"N-body relaxation ensemble of case {case} at N = {n_particles}",
            "case": case,
            "n_particles": int(n_particles),
            "n_realisations": int(R),
            "dt": float(run["dt"]),
            "tau_max": float(run["tau_max"]),
            "seed": int(run["seed"]),
            "seeding": "realisation r draws from default_rng(SeedSequence([seed, r]))",
            "dynamics": f"full N-body HMF ({eq('hmfmdfull')}), velocity Verlet",
            "action_frame": "each realisation's magnetisation direction; modulus M0_actions",
            "M0_initial_state": float(state.M0),
            "wall_time_s": float(out["wall_time_s"]),
        }
    )
    return ds
