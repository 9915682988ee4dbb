"""Early relaxation of N-body ensembles across N against the kinetic equations (issue 21).

The N-body relaxation time needs t/N of order 100, so it is affordable only at small N; the
early relaxation needs t/N of order 0.1-1 and is measured here up to N ~ 1e5.  For each N, two
ensembles of the same N, number of realisations, bins and measurement times: one drawn from the
case's state, one from the thermal state of the same energy (the control: its histograms must
not move, and whatever they do is the measurement's floor).

Measured per realisation r and time tau = t/N, as changes from tau = 0 (so that the sampling
noise of the initial histogram cancels):

- dS(tau): the coarse-grained entropy -sum_b P_b ln(P_b / (4 pi dJbar_b)) of the histogram
  pooled over realisations (its finite-sample bias, about -(B_occupied - 1)/(2 N R), is
  negligible there, while that of one realisation, (B_occupied - 1)/(2N), changes as the
  relaxation fills empty bins), with its jackknife error leaving one realisation out at a time;
- dC_r(tau, e): the fraction of its particles below the J-bar edge e, so that -dC/dtau is the
  number current through that edge (the kinetic files' 4 pi G-bar);
- |M_r|(tau) - M0 of the state.

The means of the others over realisations carry the standard error of a mean of R independent values
(realisations are independent; the values of one realisation at different times are not, so
no error is taken from the spread in time).  The kinetic prediction at the same tau comes from
the kinetic f binned on the same bins (`kinetic_bin_fractions`).  The rate over the window
[0, tau*] is dX(tau*) / tau*: at a sharp step of f (the hot halo's core edge) the kinetic
entropy grows like sqrt(tau) at first, so the instantaneous dS/dtau at tau = 0 (stored in the
kinetic files) is not what a window of finite length measures; the same window is applied to
both.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..pipeline.layouts import variable
from .relaxation_md import (
    entropy_from_histogram,
    interpolate_in_time,
    jackknife,
    kinetic_bin_fractions,
)

__all__ = [
    "INITIALS",
    "compare_rates",
    "rates_summary_lines",
    "mean_and_error",
    "ensemble_changes",
    "kinetic_changes",
    "steepest_edge",
]


def mean_and_error(values):
    """Mean over axis 1 (realisations) and its standard error (NaN with one realisation)."""
    v = np.asarray(values, dtype=float)
    R = v.shape[1]
    err = (
        v.std(axis=1, ddof=1) / np.sqrt(R) if R > 1 else np.full(v.shape[:1] + v.shape[2:], np.nan)
    )
    return v.mean(axis=1), err


def cumulative_below_edges(hist, overflow):
    """Fraction of each realisation's particles below each edge (last axis: the B + 1 edges;
    0 at the first edge, 1 - overflow / total at the last)."""
    hist = np.asarray(hist, dtype=float)
    total = hist.sum(axis=-1) + np.asarray(overflow, dtype=float)
    cum = np.concatenate([np.zeros(hist.shape[:-1] + (1,)), np.cumsum(hist, axis=-1)], axis=-1)
    return cum / np.maximum(total, 1.0)[..., None]


def ensemble_changes(hist, overflow, M_abs, edges, M0):
    """Per-realisation changes since tau = 0 of one ensemble.

    hist (T, R, B) counts, overflow (T, R), M_abs (T, R), edges (B + 1,), M0 of the state.
    Returns a dict of (estimate, error) pairs: 'dS' (T,) of the pooled histogram (jackknife
    over realisations), and means over realisations 'dC' (T, B + 1),
    'dM' (T,) = <|M|>(tau) - M0, and 'M_offset' the time average of |M| - M0 over the
    samples after tau = 0 (one value per realisation, then averaged)."""
    hist = np.asarray(hist)
    C = cumulative_below_edges(hist, overflow)  # (T, R, B + 1)
    M = np.asarray(M_abs, dtype=float) - M0
    counts = np.concatenate([hist, np.asarray(overflow)[..., None]], axis=-1).astype(float)

    def pooled_change(c):  # c: (R', T, B + 1) counts of the realisations kept
        pooled = c.sum(axis=0)
        S = entropy_from_histogram(pooled[:, :-1], edges, pooled[:, -1])
        return S - S[0]

    return {
        "dS": jackknife(np.moveaxis(counts, 1, 0), pooled_change),
        "dC": mean_and_error(C - C[:1]),
        "dM": mean_and_error(M),
        "M_offset": tuple(
            np.asarray(x).item() for x in mean_and_error(M[1:].mean(axis=0)[None, :])
        ),
    }


def kinetic_changes(ds, edges, tau):
    """The same changes for a kinetic evolution (results/relaxation/{case}_{eq}.nc) at the
    times tau: 'dS' (T,) coarse-grained on the bins, 'dC' (T, B + 1), 'dM' (T,) = M0(tau) -
    M0(0)."""
    P = kinetic_bin_fractions(ds["Jbar"].values, ds["cell_width"].values, ds["f"].values, edges)
    P = interpolate_in_time(ds["tau"].values, P, tau)  # (T, B)
    outside = np.clip(1.0 - P.sum(axis=-1), 0.0, None)
    S = entropy_from_histogram(P, edges, outside)
    C = np.concatenate([np.zeros((P.shape[0], 1)), np.cumsum(P, axis=-1)], axis=-1)
    M0 = np.interp(tau, ds["tau"].values, ds["M0"].values)
    return {"dS": S - S[0], "dC": C - C[0], "dM": M0 - M0[0]}


def steepest_edge(dC):
    """Index of the edge through which the most particles have passed (largest |dC|)."""
    return int(np.argmax(np.abs(np.asarray(dC))))


INITIALS = ("state", "thermal")


def compare_rates(md, kinetic):
    """The early-window ensembles `md` (relaxation_md datasets of one case with attrs
    'initial' in INITIALS and 'n_particles'; both initials at every N) against the kinetic
    evolutions `kinetic` ({equation: relaxation dataset}).  Returns (dataset, summary lines)."""
    by = {(d.attrs["initial"], int(d.attrs["n_particles"])): d for d in md}
    sizes = sorted({n for _, n in by})
    missing = [(i, n) for i in INITIALS for n in sizes if (i, n) not in by]
    if missing:
        raise ValueError(f"early-window ensembles missing for (initial, N) = {missing}")
    first = by[("state", sizes[0])]
    edges = np.asarray(first["jbar_edges"].values, dtype=float)
    for d in md:
        if not np.array_equal(d["jbar_edges"].values, edges):
            raise ValueError("the early-window ensembles of one case must share their J-bar bins")
    tau = first["tau"].values
    T, E = tau.size, edges.size
    shape = (len(INITIALS), len(sizes))
    acc = {k: np.full(shape + (T,), np.nan) for k in ("dS", "dS_err", "dM", "dM_err")}
    acc["dC"] = np.full(shape + (T, E), np.nan)
    acc["dC_err"] = np.full(shape + (T, E), np.nan)
    off = np.full(shape, np.nan)
    off_err = np.full(shape, np.nan)
    n_real = np.zeros(len(sizes), dtype=int)
    for i, initial in enumerate(INITIALS):
        for j, n in enumerate(sizes):
            d = by[(initial, n)]
            ch = ensemble_changes(
                d["hist"].values,
                d["overflow"].values,
                d["M_abs"].values,
                edges,
                float(d.attrs["M0_initial_state"]),
            )
            t_n = d["tau"].values  # differs from tau only by the rounding of t to whole steps
            for k in ("dS", "dC", "dM"):
                acc[k][i, j] = interpolate_in_time(t_n, ch[k][0], tau)
                acc[k + "_err"][i, j] = interpolate_in_time(t_n, ch[k][1], tau)
            off[i, j], off_err[i, j] = ch["M_offset"]
            n_real[j] = d.sizes["realisation"]
    kin = {eq: kinetic_changes(ds, edges, tau) for eq, ds in kinetic.items()}
    ref = kin.get("landau") or next(iter(kin.values()))
    core = steepest_edge(ref["dC"][-1])
    tau_w = float(tau[-1])
    rate_S = acc["dS"][..., -1] / tau_w
    rate_S_err = acc["dS_err"][..., -1] / tau_w
    cur = -acc["dC"][..., -1, core] / tau_w
    cur_err = acc["dC_err"][..., -1, core] / tau_w

    a1 = "action (dimensionless HMF units)"
    dims = ("initial", "N")
    data = {
        "dS_md": variable(
            dims + ("tau",),
            acc["dS"],
            "1",
            "S(tau) - S(0) of the coarse-grained entropy of the J-bar histogram pooled over "
            "realisations",
        ),
        "dS_md_err": variable(
            dims + ("tau",), acc["dS_err"], "1", "jackknife error of dS_md over realisations"
        ),
        "dC_md": variable(
            dims + ("tau", "jbar_edge"),
            acc["dC"],
            "1",
            "mean change since tau = 0 of the fraction of particles below each J-bar edge "
            "(minus the particles carried out through it per particle)",
        ),
        "dC_md_err": variable(
            dims + ("tau", "jbar_edge"), acc["dC_err"], "1", "standard error of dC_md"
        ),
        "dM_md": variable(
            dims + ("tau",),
            acc["dM"],
            "1",
            "<|M|>(tau) - M0 of the state the ensemble is drawn from",
        ),
        "dM_md_err": variable(dims + ("tau",), acc["dM_err"], "1", "standard error of dM_md"),
        "M_offset_md": variable(
            dims,
            off,
            "1",
            "time average of |M| - M0 over the samples after tau = 0, averaged over realisations",
        ),
        "M_offset_md_err": variable(
            dims, off_err, "1", "standard error of M_offset_md (one value per realisation)"
        ),
        "entropy_rate_md": variable(
            dims, rate_S, "1 / tau", "dS_md at the window's end over the window, dS(tau*)/tau*"
        ),
        "entropy_rate_md_err": variable(
            dims, rate_S_err, "1 / tau", "standard error of entropy_rate_md"
        ),
        "current_md": variable(
            dims,
            cur,
            "1 / tau",
            "particles per particle carried out through the core-edge J-bar edge per unit tau, "
            "-dC(tau*)/tau* at edge core_edge",
        ),
        "current_md_err": variable(dims, cur_err, "1 / tau", "standard error of current_md"),
        "n_realisations": variable(("N",), n_real, "1", "realisations per ensemble"),
    }
    for eq, k in kin.items():
        ds = kinetic[eq]
        data[f"dS_{eq}"] = variable(
            ("tau",), k["dS"], "1", f"S(tau) - S(0) of the {eq} f binned on the same J-bar bins"
        )
        data[f"dC_{eq}"] = variable(
            ("tau", "jbar_edge"), k["dC"], "1", f"dC of the {eq} evolution on the same edges"
        )
        data[f"dM_{eq}"] = variable(
            ("tau",), k["dM"], "1", f"M0(tau) - M0(0) of the {eq} evolution"
        )
        data[f"entropy_rate_{eq}"] = variable(
            (), k["dS"][-1] / tau_w, "1 / tau", f"dS(tau*)/tau* of the {eq} evolution"
        )
        data[f"current_{eq}"] = variable(
            (), -k["dC"][-1, core] / tau_w, "1 / tau", f"-dC(tau*)/tau* of the {eq} evolution"
        )
        data[f"Sdot_tau0_{eq}"] = variable(
            (),
            float(ds["Sdot"].values[0]),
            "1 / tau",
            f"instantaneous dS/dtau at tau = 0 of the {eq} evolution (fine-grained entropy)",
        )
    coords = {
        "initial": variable(
            ("initial",),
            np.array(INITIALS),
            "1",
            "drawn from: the case's state, or the thermal state of the same energy (control)",
        ),
        "N": variable(("N",), sizes, "1", "number of particles"),
        "tau": variable(("tau",), tau, "time / N", "rescaled time tau = t/N"),
        "jbar_edges": variable(("jbar_edge",), edges, a1, "edges of the J-bar bins"),
    }
    case = first.attrs["case"]
    out = xr.Dataset(data, coords=coords)
    out.attrs.update(
        {
            "title": f"Early N-body relaxation across N against the kinetic equations, case {case}",
            "case": case,
            "tau_window": tau_w,
            "core_edge": int(core),
            "core_edge_jbar": float(edges[core]),
            "M0_state": float(first.attrs["M0_initial_state"]),
            "M0_thermal": float(by[("thermal", sizes[0])].attrs["M0_initial_state"]),
        }
    )
    return out, rates_summary_lines(out, list(kin))


def rates_summary_lines(ds, equations):
    """The summary of `compare_rates`: what is measured, then per N the entropy and current over
    the window against each equation, the thermal control beside them, and <|M|> - M0."""
    tw = ds.attrs["tau_window"]
    out = [
        f"case {ds.attrs['case']}: early N-body relaxation over the window tau = t/N in "
        f"[0, {tw:.3g}], ensembles drawn from the state (M0 = {ds.attrs['M0_state']:.5f}) and, "
        f"as control, from the thermal state of its energy (M0 = {ds.attrs['M0_thermal']:.5f}); "
        "same N, realisations, bins and times",
        "  dS/tau*: change of the coarse-grained entropy of the J-bar histogram pooled over "
        "realisations from tau = 0 to tau*, over tau* (+- jackknife error, one realisation left "
        "out at a time); current: particles (per particle) carried out through J-bar = "
        f"{ds.attrs['core_edge_jbar']:.4f} (the edge the Landau evolution drains most) over tau* "
        "(+- standard error over realisations); <|M|> - M0: |M| - M0 averaged over the samples "
        "after tau = 0, then over realisations, and at tau* against the kinetic M0(tau*) - "
        "M0(0); the kinetic values over the same window on the same bins",
    ]
    for eq in equations:
        out.append(
            f"  {eq}: dS/tau* = {float(ds[f'entropy_rate_{eq}']):.4g}, current = "
            f"{float(ds[f'current_{eq}']):.4g} (instantaneous fine-grained dS/dtau at tau = 0: "
            f"{float(ds[f'Sdot_tau0_{eq}']):.4g})"
        )
    for j, n in enumerate(ds["N"].values):
        s, c = ds.sel(initial="state").isel(N=j), ds.sel(initial="thermal").isel(N=j)
        rat = ", ".join(
            f"/{eq} {float(s.entropy_rate_md) / float(ds[f'entropy_rate_{eq}']):.2f} +- "
            f"{float(s.entropy_rate_md_err) / abs(float(ds[f'entropy_rate_{eq}'])):.2f}"
            for eq in equations
        )
        crat = ", ".join(
            f"/{eq} {float(s.current_md) / float(ds[f'current_{eq}']):.2f} +- "
            f"{float(s.current_md_err) / abs(float(ds[f'current_{eq}'])):.2f}"
            for eq in equations
        )
        out.append(
            f"  N = {n} (R = {int(ds.n_realisations[j])}): dS/tau* = "
            f"{float(s.entropy_rate_md):.4g} +- {float(s.entropy_rate_md_err):.2g} ({rat}; "
            f"control {float(c.entropy_rate_md):.2g} +- {float(c.entropy_rate_md_err):.2g}); "
            f"current = {float(s.current_md):.4g} +- {float(s.current_md_err):.2g} ({crat}; "
            f"control {float(c.current_md):.2g} +- {float(c.current_md_err):.2g}); "
            f"<|M|> - M0 = {float(s.M_offset_md):+.5f} +- {float(s.M_offset_md_err):.5f} "
            f"(control {float(c.M_offset_md):+.5f} +- {float(c.M_offset_md_err):.5f}); "
            f"<|M|>(tau*) - M0 = {float(s.dM_md[-1]):+.5f} +- {float(s.dM_md_err[-1]):.5f} ("
            + ", ".join(f"{eq} {float(ds[f'dM_{eq}'][-1]):+.5f}" for eq in equations)
            + ")"
        )
    return out
