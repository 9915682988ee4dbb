"""N-body relaxation ensembles against the kinetic evolutions, at matched rescaled time t/N.

Everything is compared in the same coarse-graining: the J-bar bins of the MD histograms.  The
kinetic f(J-bar, tau) is integrated over those bins (`kinetic_bin_fractions`) and interpolated
in tau at the MD's t/N; entropies are the coarse-grained -sum P_b ln(P_b / (4 pi dJbar_b)) for
both; the equilibrium reference is the thermal state of the initial state's energy u0 (the
end point of both kinetic equations), binned the same way.

Relaxation time: the time at which the coarse-grained entropy deficit S_eq - S has fallen to
1/e of its initial value (the kinetic module's definition, on the binned f).  Errors of MD
quantities come from the spread between groups of realisations (jackknife).

Thermal control (optional, per N): an ensemble of the thermal state of the same energy with the
same N, realisations, bins, time step and schedule.  Its entropy should stay flat; its mean
offset from S_eq is the measurement floor of the deficit (finite sample: the plug-in entropy of
M counts in B bins is low by about (B - 1) / 2M; J-bar measured in a fluctuating field:
histograms broadened), and t_R is also given with the deficit measured against it.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from ..meanfield.equilibrium import thermal_M0_from_energy
from ..pipeline.layouts import variable
from ..pipeline.layouts.relaxation_md import MEASURE_NAMES
from .kinetic_uncertainty import time_band
from .relaxation_md import (
    PHASE_VOLUME_PER_JBAR,
    interpolate_in_time,
    jackknife,
    kinetic_bin_fractions,
    l1_distance,
    power_law_fit,
    relaxation_time,
    state_bin_fractions,
)

__all__ = [
    "compare_relaxation",
    "summary_lines",
    "COMPARISON_COLUMNS",
    "with_kinetic_bands",
    "with_reference_md",
    "band_lines",
    "with_layer_model",
]

N_GROUPS = 10  # groups of realisations for jackknife errors


COMPARISON_COLUMNS = [
    "case",
    "n_particles",
    "time",
    "tau",
    "M_md",
    "M_md_err",
    "M_lenard_balescu",
    "M_landau",
    "S_md",
    "S_md_err",
    "S_lenard_balescu",
    "S_landau",
    "l1_distance_lenard_balescu",
    "l1_distance_lenard_balescu_err",
    "l1_distance_landau",
    "l1_distance_landau_err",
    "l1_distance_noise_floor",
]


def _coarse_entropy(P, edges):
    f = P / (PHASE_VOLUME_PER_JBAR * np.diff(edges))
    with np.errstate(divide="ignore", invalid="ignore"):
        return -np.sum(np.where(P > 0, P * np.log(np.where(P > 0, f, 1.0)), 0.0), axis=-1)


def _groups(hist, overflow, n_groups):
    """Sum realisations into n_groups groups: (G, T, B + 1) counts, the last bin the overflow
    beyond the last edge (so that a group left out takes its overflow with it)."""
    R = hist.shape[1]
    g = min(n_groups, R)
    idx = np.arange(R) % g
    counts = np.concatenate([hist, overflow[..., None]], axis=-1).astype(float)
    return np.stack([counts[:, idx == k].sum(axis=1) for k in range(g)])


def _pooled_P(G):
    """Fractions per bin of the groups' pooled counts (overflow counted in the total)."""
    total = G.sum(axis=(0, -1))
    return G[..., :-1].sum(axis=0) / np.maximum(total, 1.0)[..., None]


_NO_OWN = {"M0_thermal_own": (np.nan, np.nan)}  # an ensemble without energies


def own_energy_thermal(energy0, M_end):
    """Each realisation relaxes towards the thermal state of its own energy, which scatters
    about u0 by O(1/sqrt N) (its N particles are drawn independently).  From the energies per
    particle at t = 0 and |M| at the last sample, per realisation: the mean over realisations
    of the thermal M0 of each one's energy, the mean |M| at the end, and the mean of their
    difference, each with its standard error over realisations."""
    e = np.asarray(energy0, dtype=float)
    m_th = np.array([thermal_M0_from_energy(x) for x in e])
    m_end = np.asarray(M_end, dtype=float)
    R = e.size

    def mean_err(v):
        return float(v.mean()), float(v.std(ddof=1) / np.sqrt(R)) if R > 1 else np.nan

    return {
        "energy0": mean_err(e),
        "M0_thermal_own": mean_err(m_th),
        "M_end": mean_err(m_end),
        "M_end_minus_own": mean_err(m_end - m_th),
    }


def thermal_control(ctrl, edges, S_eq):
    """The measurement floor from a thermal-control ensemble `ctrl` (a relaxation_md dataset
    drawn from the thermal state of the case's energy, binned on `edges`; S_eq: that state's
    coarse-grained entropy on them).  Returns a dict of (estimate, jackknife error) pairs:
    S (per sample), offset = time mean of S - S_eq, drift = S(last) - S(first)."""
    if not np.array_equal(ctrl["jbar_edges"].values, edges):
        raise ValueError("the thermal control must share the ensembles' J-bar bins")
    G = _groups(ctrl["hist"].values, ctrl["overflow"].values, N_GROUPS)

    def entropy(g):
        return _coarse_entropy(_pooled_P(g), edges)

    return {
        "t": np.asarray(ctrl["t"].values, dtype=float),
        "S": jackknife(G, entropy),
        "offset": tuple(float(x) for x in jackknife(G, lambda g: entropy(g).mean() - S_eq)),
        "drift": tuple(
            float(x) for x in jackknife(G, lambda g: (lambda S: S[-1] - S[0])(entropy(g)))
        ),
    }


def compare_relaxation(md, kinetic, state, thermal, controls=()):
    """Compare the ensembles `md` (list of relaxation_md datasets of one case, any N) with
    the kinetic evolutions `kinetic` ({equation: relaxation dataset}).

    state: the initial state; thermal: the thermal state of its energy; controls: thermal-
    control ensembles (any subset of the N of `md`, same schedule).  Returns (dataset, rows for
    the CSV, summary dict)."""
    md = sorted(md, key=lambda d: int(d.attrs["n_particles"]))
    ctrl_by_n = {int(c.attrs["n_particles"]): c for c in controls}
    unmatched = sorted(set(ctrl_by_n) - {int(d.attrs["n_particles"]) for d in md})
    if unmatched:
        raise ValueError(f"thermal controls at N = {unmatched} have no ensemble of the state")
    edges = np.asarray(md[0]["jbar_edges"].values, dtype=float)
    for d in md[1:]:
        if not np.array_equal(d["jbar_edges"].values, edges):
            raise ValueError("the ensembles of one case must share their J-bar bins")
    P_eq = state_bin_fractions(thermal, edges)
    S_eq = float(_coarse_entropy(P_eq, edges))
    P_0 = state_bin_fractions(state, edges)
    kin = {}
    for eq, ds in kinetic.items():
        Pk = kinetic_bin_fractions(
            ds["Jbar"].values, ds["cell_width"].values, ds["f"].values, edges
        )
        tau_k = ds["tau"].values
        Sk = _coarse_entropy(Pk, edges)
        kin[eq] = {
            "tau": tau_k,
            "P": Pk,
            "M0": ds["M0"].values,
            "S": Sk,
            "tau_relax_coarse": relaxation_time(tau_k, S_eq - Sk),
        }
    rows, per_n = [], []
    for d in md:
        n = int(d.attrs["n_particles"])
        t = d["t"].values
        tau = t / n
        G = _groups(d["hist"].values, d["overflow"].values, N_GROUPS)
        P_md, P_err = jackknife(G, _pooled_P)
        S_md, S_err = jackknife(G, lambda g: _coarse_entropy(_pooled_P(g), edges))
        dS_md, dS_err = jackknife(
            G, lambda g: (lambda S: S - S[0])(_coarse_entropy(_pooled_P(g), edges))
        )
        M = d["M_abs"].values
        M_md, M_err = M.mean(axis=1), M.std(axis=1, ddof=1) / np.sqrt(M.shape[1])
        own_eq = own_energy_thermal(d["energy"].values[0], M[-1]) if "energy" in d else None

        def t_relax_of(groups, t=t):
            return jackknife(
                groups, lambda g: relaxation_time(t, S_eq - _coarse_entropy(_pooled_P(g), edges))
            )

        t_relax, t_relax_err = t_relax_of(G)
        other = {  # t_R with J-bar measured with each realisation's |M|, the static M0
            m: tuple(
                float(x)
                for x in t_relax_of(
                    _groups(d["hist" + m].values, d["overflow" + m].values, N_GROUPS)
                )
            )
            for m in MEASURE_NAMES
            if "hist" + m in d
        }
        control = None
        if n in ctrl_by_n:
            control = thermal_control(ctrl_by_n[n], edges, S_eq)
            if not np.allclose(control["t"], t):
                raise ValueError(f"the thermal control at N = {n} has another schedule")
            # the deficit against the control's level S_eq + offset
            control["t_relax"] = tuple(
                float(x)
                for x in jackknife(
                    G,
                    lambda g, t=t, lvl=-control["offset"][0]: relaxation_time(
                        t,
                        S_eq - _coarse_entropy(_pooled_P(g), edges),
                        floor=lvl,
                    ),
                )
            )
        floor = np.sqrt(2.0 / np.pi) * P_err.sum(axis=-1)
        cols = {"M": {}, "S": {}, "d": {}, "d_err": {}, "P": {}}
        for eq, k in kin.items():
            Pk = interpolate_in_time(k["tau"], k["P"], tau)
            cols["P"][eq] = Pk
            cols["M"][eq] = np.interp(tau, k["tau"], k["M0"])
            cols["S"][eq] = np.interp(tau, k["tau"], k["S"])
            dist, dist_err = jackknife(G, lambda g, Pk=Pk: l1_distance(_pooled_P(g), Pk))
            cols["d"][eq], cols["d_err"][eq] = dist, dist_err
        for j in range(t.size):
            row = {
                "case": d.attrs["case"],
                "n_particles": n,
                "time": t[j],
                "tau": tau[j],
                "M_md": M_md[j],
                "M_md_err": M_err[j],
                "S_md": S_md[j],
                "S_md_err": S_err[j],
                "l1_distance_noise_floor": floor[j],
            }
            for eq in ("lenard_balescu", "landau"):
                row[f"M_{eq}"] = cols["M"][eq][j] if eq in kin else np.nan
                row[f"S_{eq}"] = cols["S"][eq][j] if eq in kin else np.nan
                row[f"l1_distance_{eq}"] = cols["d"][eq][j] if eq in kin else np.nan
                row[f"l1_distance_{eq}_err"] = cols["d_err"][eq][j] if eq in kin else np.nan
            rows.append(row)
        per_n.append(
            dict(
                n=n,
                tau=tau,
                t=t,
                P_md=P_md,
                P_err=P_err,
                S_md=S_md,
                S_err=S_err,
                dS_md=dS_md,
                dS_err=dS_err,
                M_md=M_md,
                M_err=M_err,
                t_relax=float(t_relax),
                t_relax_err=float(t_relax_err),
                n_groups=int(G.shape[0]),
                t_relax_measures=other,
                own_eq=own_eq,
                cols=cols,
                floor=floor,
                control=control,
            )
        )
    ns = np.array([p["n"] for p in per_n], dtype=float)
    tr = np.array([p["t_relax"] for p in per_n])
    tr_err = np.array([p["t_relax_err"] for p in per_n])
    ok = np.isfinite(tr) & np.isfinite(tr_err) & (tr_err > 0)
    if ok.sum() >= 2:
        alpha, alpha_err, amp = power_law_fit(ns[ok], tr[ok], tr_err[ok])
    else:
        alpha = alpha_err = amp = np.nan
    summary = {
        "case": md[0].attrs["case"],
        "S_eq_coarse": S_eq,
        "exponent": alpha,
        "exponent_err": alpha_err,
        "prefactor": amp,
        "tau_relax_coarse": {eq: k["tau_relax_coarse"] for eq, k in kin.items()},
        "t_relax_md": dict(zip(ns.astype(int).tolist(), tr.tolist(), strict=True)),
        "t_relax_md_err": dict(zip(ns.astype(int).tolist(), tr_err.tolist(), strict=True)),
        "jackknife_groups": {p["n"]: p["n_groups"] for p in per_n},
        "t_relax_md_measures": {p["n"]: p["t_relax_measures"] for p in per_n},
        "M0_thermal_u0": float(thermal.M0),
        "own_energy_thermal": {p["n"]: p["own_eq"] for p in per_n if p["own_eq"]},
        "thermal_control": {
            p["n"]: {k: p["control"][k] for k in ("offset", "drift", "t_relax")}
            for p in per_n
            if p["control"]
        },
    }
    ds = _comparison_dataset(per_n, kin, edges, P_eq, P_0, summary)
    return ds, rows, summary


def _comparison_dataset(per_n, kin, edges, P_eq, P_0, summary):
    """All N on the tau grid of the first ensemble (the schedules are the same in t/N)."""
    tau = per_n[0]["tau"]
    ns = [p["n"] for p in per_n]
    a1 = "action (dimensionless HMF units)"

    def on_grid(key, p):
        return (
            np.interp(tau, p["tau"], p[key])
            if p[key].ndim == 1
            else interpolate_in_time(p["tau"], p[key], tau)
        )

    data = {
        "M_md": variable(
            ("N", "tau"), np.stack([on_grid("M_md", p) for p in per_n]), "1", "ensemble mean of |M|"
        ),
        "M_md_err": variable(
            ("N", "tau"),
            np.stack([on_grid("M_err", p) for p in per_n]),
            "1",
            "standard error of the ensemble mean of |M|",
        ),
        "S_md": variable(
            ("N", "tau"),
            np.stack([on_grid("S_md", p) for p in per_n]),
            "1",
            "coarse-grained entropy of the pooled MD histogram",
        ),
        "S_md_err": variable(
            ("N", "tau"),
            np.stack([on_grid("S_err", p) for p in per_n]),
            "1",
            "jackknife error of S_md",
        ),
        "S_md_change": variable(
            ("N", "tau"),
            np.stack([on_grid("dS_md", p) for p in per_n]),
            "1",
            "S_md(tau) - S_md(0): the entropy gained since t = 0 (the sampling noise of the "
            "initial histogram cancels)",
        ),
        "S_md_change_err": variable(
            ("N", "tau"),
            np.stack([on_grid("dS_err", p) for p in per_n]),
            "1",
            "jackknife error of S_md_change (of the difference, over the same groups)",
        ),
        "P_md": variable(
            ("N", "tau", "jbar"),
            np.stack([on_grid("P_md", p) for p in per_n]),
            "1",
            "fraction of particles per J-bar bin (MD, pooled)",
        ),
        "P_md_err": variable(
            ("N", "tau", "jbar"),
            np.stack([on_grid("P_err", p) for p in per_n]),
            "1",
            "jackknife error of P_md",
        ),
        "P_thermal": variable(
            ("jbar",), P_eq, "1", "fraction per bin of the thermal state of energy u0"
        ),
        "P_initial": variable(("jbar",), P_0, "1", "fraction per bin of the initial state"),
        "t_relax_md": variable(
            ("N",),
            [p["t_relax"] for p in per_n],
            "time",
            "MD relaxation time t_R in HMF time t (not t/N): the deficit S_eq - S of the "
            "coarse-grained histogram entropy fallen by a factor e",
        ),
        "t_relax_md_err": variable(
            ("N",),
            [p["t_relax_err"] for p in per_n],
            "time",
            f"jackknife error of t_relax_md over {N_GROUPS} groups of realisations",
        ),
        **{
            f"t_relax_md{m}": variable(
                ("N",),
                [p["t_relax_measures"].get(m, (np.nan, np.nan))[0] for p in per_n],
                "time",
                f"t_relax_md with J-bar measured with {how}",
            )
            for m, how in MEASURE_NAMES.items()
        },
        **{
            f"t_relax_md{m}_err": variable(
                ("N",),
                [p["t_relax_measures"].get(m, (np.nan, np.nan))[1] for p in per_n],
                "time",
                f"jackknife error of t_relax_md{m}",
            )
            for m in MEASURE_NAMES
        },
        "M0_thermal_own_energy": variable(
            ("N",),
            [(p["own_eq"] or _NO_OWN)["M0_thermal_own"][0] for p in per_n],
            "1",
            "mean over realisations of the thermal M0 of each realisation's own initial energy",
        ),
        "M0_thermal_own_energy_err": variable(
            ("N",),
            [(p["own_eq"] or _NO_OWN)["M0_thermal_own"][1] for p in per_n],
            "1",
            "standard error of M0_thermal_own_energy",
        ),
        "S_thermal": variable(
            (),
            summary["S_eq_coarse"],
            "1",
            "coarse-grained entropy of the thermal state of energy u0",
        ),
    }
    for eq, k in kin.items():
        data[f"M_{eq}"] = variable(
            ("tau",), np.interp(tau, k["tau"], k["M0"]), "1", f"M0(tau) of the {eq} evolution"
        )
        data[f"S_{eq}"] = variable(
            ("tau",),
            np.interp(tau, k["tau"], k["S"]),
            "1",
            f"coarse-grained entropy of the {eq} evolution",
        )
        data[f"P_{eq}"] = variable(
            ("tau", "jbar"),
            interpolate_in_time(k["tau"], k["P"], tau),
            "1",
            f"fraction per J-bar bin of the {eq} evolution",
        )
        data[f"tau_relax_coarse_{eq}"] = variable(
            (),
            k["tau_relax_coarse"],
            "time / N",
            f"coarse-grained relaxation time of the {eq} evolution, in tau = t/N: the deficit "
            "S_eq - S of the histogram entropy on the MD's J-bar bins fallen by a factor e (not "
            "the fine-grained tau_relax_fine of results/relaxation)",
        )
        data[f"l1_distance_{eq}"] = variable(
            ("N", "tau"),
            np.stack([np.interp(tau, p["tau"], p["cols"]["d"][eq]) for p in per_n]),
            "1",
            f"L1 distance sum_b |P_md - P_{eq}| of the fractions per J-bar bin at matched t/N "
            "(0 to 2)",
        )
        data[f"l1_distance_{eq}_err"] = variable(
            ("N", "tau"),
            np.stack([np.interp(tau, p["tau"], p["cols"]["d_err"][eq]) for p in per_n]),
            "1",
            f"jackknife error of l1_distance_{eq}",
        )
    nan_t = np.full(tau.shape, np.nan)

    def control_of(p, key, k):
        c = p["control"]
        return nan_t if c is None else np.interp(tau, p["tau"], c[key][k])

    def control_scalar(p, key, k):
        return np.nan if p["control"] is None else p["control"][key][k]

    data["S_control"] = variable(
        ("N", "tau"),
        np.stack([control_of(p, "S", 0) for p in per_n]),
        "1",
        "coarse-grained entropy of the thermal-control ensemble (thermal state of energy u0, "
        "same N, realisations, bins and schedule); NaN where none was run",
    )
    data["S_control_err"] = variable(
        ("N", "tau"),
        np.stack([control_of(p, "S", 1) for p in per_n]),
        "1",
        "jackknife error of S_control",
    )
    for key, long_name in (
        ("offset", "time mean of S_control - S_thermal: the floor of the entropy deficit"),
        ("drift", "S_control at the last sample minus at the first"),
        (
            "t_relax",
            "t_relax_md with the deficit measured against the control's level "
            "S_thermal + control_offset (time)",
        ),
    ):
        units = "time" if key == "t_relax" else "1"
        name = "t_relax_md_vs_control" if key == "t_relax" else f"control_{key}"
        data[name] = variable(("N",), [control_scalar(p, key, 0) for p in per_n], units, long_name)
        data[f"{name}_err"] = variable(
            ("N",), [control_scalar(p, key, 1) for p in per_n], units, f"jackknife error of {name}"
        )
    data["l1_distance_noise_floor"] = variable(
        ("N", "tau"),
        np.stack([np.interp(tau, p["tau"], p["floor"]) for p in per_n]),
        "1",
        "expected distance from sampling noise alone: sqrt(2/pi) sum_b err(P_b)",
    )
    ds = xr.Dataset(
        data,
        coords={
            "N": variable(("N",), ns, "1", "number of particles"),
            "tau": variable(("tau",), tau, "time / N", "rescaled time tau = t/N"),
            "jbar": variable(
                ("jbar",), 0.5 * (edges[1:] + edges[:-1]), a1, "centre of the J-bar bin"
            ),
            "jbar_edges": variable(("jbar_edge",), edges, a1, "edges of the J-bar bins"),
        },
    )
    ds.attrs.update(
        {
            "title": f"N-body relaxation against the kinetic equations, case {summary['case']}",
            "case": summary["case"],
            "exponent": summary["exponent"],
            "exponent_err": summary["exponent_err"],
            "exponent_definition": "t_relax_md = A N^exponent, weighted least squares in log-log",
            "prefactor": summary["prefactor"],
        }
    )
    return ds


def summary_lines(summary):
    """Human-readable lines of a comparison summary, opening with what t_R, its error and
    tau_R^coarse are."""
    groups = summary.get("jackknife_groups", {})
    g = sorted(set(groups.values())) or [N_GROUPS]
    out = [
        f"case {summary['case']}: coarse-grained thermal S_eq = {summary['S_eq_coarse']:.5f} "
        "(histogram entropy -sum_b P_b ln(P_b / (4 pi dJbar_b)) on the MD's J-bar bins)",
        "  t_R: MD relaxation time in HMF time t (not t/N), the first t at which the "
        "coarse-grained entropy deficit S_eq - S(t) has fallen to 1/e of its value at t = 0 "
        "(linear interpolation between samples); +- its jackknife standard error over "
        f"{'/'.join(map(str, g))} groups of realisations (one group left out at a time)",
        "  tau_R^coarse: the same definition on the kinetic f binned on the same J-bar bins, in "
        "tau = t/N (kinetic prediction t_R = tau_R^coarse N; not the fine-grained "
        "tau_relax_fine of results/relaxation)",
    ]
    for eq, tau in summary["tau_relax_coarse"].items():
        out.append(f"  {eq}: tau_R^coarse = {tau:.4g}")
    for n, t in summary["t_relax_md"].items():
        err = summary["t_relax_md_err"][n]
        ratio = {eq: t / (tau * n) for eq, tau in summary["tau_relax_coarse"].items()}
        rs = ", ".join(f"t_R/(tau_R^coarse N) = {r:.3f} ({eq})" for eq, r in ratio.items())
        out.append(f"  MD N = {n}: t_R = {t:.4g} +- {err:.2g}, t_R/N = {t / n:.4g}; {rs}")
    own = summary.get("own_energy_thermal", {})
    if own:
        out.append(
            "  end state: each realisation relaxes to the thermal state of its own energy (drawn "
            "with scatter O(1/sqrt N) about u0; thermal M0 of u0 = "
            f"{summary['M0_thermal_u0']:.5f}); +- standard errors over realisations:"
        )
        for n, o in own.items():
            e, mt, me, dm = (
                o[k] for k in ("energy0", "M0_thermal_own", "M_end", "M_end_minus_own")
            )
            out.append(
                f"    N = {n}: <u_r> = {e[0]:.5f} +- {e[1]:.5f}, <M0_thermal(u_r)> = "
                f"{mt[0]:.5f} +- {mt[1]:.5f}, <|M|> at the last sample {me[0]:.5f} +- {me[1]:.5f}, "
                f"difference {dm[0]:+.5f} +- {dm[1]:.5f}"
            )
    ctrl = summary.get("thermal_control", {})
    if ctrl:
        out.append(
            "  thermal control (the thermal state of energy u0, same N, realisations, bins and "
            "schedule): its entropy offset from S_eq (time mean; the floor of the deficit), its "
            "drift from the first to the last sample, and t_R with the deficit measured against "
            "the control's level:"
        )
        for n, c in ctrl.items():
            (o, oe), (d, de), (tr, tre) = c["offset"], c["drift"], c["t_relax"]
            out.append(
                f"    N = {n}: offset {o:+.5f} +- {oe:.5f}, drift {d:+.5f} +- {de:.5f}, "
                f"t_R/N = {tr / n:.4g} +- {tre / n:.2g}"
            )
    meas = summary.get("t_relax_md_measures", {})
    if any(meas.values()):
        out.append(
            "  t_R with J-bar measured otherwise (the default above: the ensemble mean <|M|>(t)):"
        )
        for n, per in meas.items():
            parts = [
                f"{MEASURE_NAMES[m]}: t_R/N = {v[0] / n:.4g} +- {v[1] / n:.2g}"
                for m, v in per.items()
            ]
            out.append(f"    N = {n}: " + "; ".join(parts))
    out.append(
        f"  exponent of t_R = A N^alpha: alpha = {summary['exponent']:.3f} +- "
        f"{summary['exponent_err']:.3f} (kinetic theory at order 1/N: alpha = 1)"
    )
    return out


def with_kinetic_bands(ds, kinetic, rows):
    """`ds` (a comparison dataset) with tau_relax_coarse_{eq}_band: the numerical uncertainty
    of each kinetic time from the table `rows` (`kinetic_uncertainty.time_band`; NaN where the
    table does not apply to the evolution)."""
    ds = ds.copy()
    case = ds.attrs["case"]
    for eq, kds in kinetic.items():
        key = f"tau_relax_coarse_{eq}"
        if key not in ds:
            continue
        settings = json.loads(kds.attrs["settings"]) if "settings" in kds.attrs else {}
        band = time_band(rows, case, eq, settings, "tau_R_coarse", float(ds[key]))
        low, high, rel_g, rel_h = band if band is not None else (np.nan,) * 4
        ds[f"{key}_band"] = variable(
            ("bound",),
            [low, high],
            "time / N",
            f"numerical uncertainty of {key}: from the default grid's value towards 1.5 times "
            "its nodes and towards harmonics n_max = l_max = 8, both added "
            "(docs/reference/kinetic_time_uncertainty.csv; NaN: the table does not apply)",
        )
        ds[f"{key}_band"].attrs.update(rel_grid=rel_g, rel_harmonics=rel_h)
    return ds


def with_reference_md(ds, times, source):
    """`ds` with the N-body relaxation times {N: (t_R, error)} of a run not rebuilt here (a
    reference copy: `source`), at the N that `ds` does not have itself."""
    ds = ds.copy()
    own = {int(n) for n in ds["N"].values}
    ns = sorted(n for n in times if n not in own)
    if not ns:
        return ds
    coord = {"N_reference": variable(("N_reference",), ns, "1", "number of particles")}
    ds = ds.assign_coords(coord)
    ds["t_relax_md_reference"] = variable(
        ("N_reference",),
        [times[n][0] for n in ns],
        "time",
        f"N-body relaxation time t_R (entropy deficit / e) of a run not rebuilt by this "
        f"configuration: reference copy {source}",
    )
    ds["t_relax_md_reference_err"] = variable(
        ("N_reference",),
        [times[n][1] for n in ns],
        "time",
        "jackknife error of t_relax_md_reference",
    )
    return ds


def with_layer_model(ds, times, source):
    """`ds` with the finite-N layer model's tau_R^coarse {equation: {N: (delta, tau, rate)}}
    (`kinetic_uncertainty.layer_model_times`), for the equations whose kinetic time has its
    uncertainty band (the band's table and the model's runs are of the same code and settings:
    where the band is stale or absent, so is the model)."""
    ds = ds.copy()
    for eq, by_n in times.items():
        band = f"tau_relax_coarse_{eq}_band"
        if band not in ds or not np.isfinite(ds[band].values).all() or not by_n:
            continue
        ns = sorted(by_n)
        dim = f"N_layer_{eq}"
        ds = ds.assign_coords({dim: variable((dim,), ns, "1", "number of particles")})
        ds[f"layer_delta_{eq}"] = variable(
            (dim,),
            [by_n[n][0] for n in ns],
            "1",
            "width delta(N) in kappa of the N-body's separatrix layer (docs/reference/"
            "separatrix_crossings.txt), the layer model's innermost cells",
        )
        ds[f"tau_relax_coarse_{eq}_layer_model"] = variable(
            (dim,),
            [by_n[n][1] for n in ns],
            "time / N",
            f"tau_R^coarse of the {eq} equation with the separatrix layer |kappa - 1| < "
            f"delta(N) mixed (one cell a side): the finite-N layer model's t_R/N ({source})",
        )
    return ds


def band_lines(ds):
    """Summary lines for the kinetic times' bands of `ds` (from `with_kinetic_bands`)."""
    out = []
    for name in ds.data_vars:
        if not name.endswith("_band"):
            continue
        low, high = (float(v) for v in ds[name].values)
        eq = name[len("tau_relax_coarse_") : -len("_band")]
        if np.isfinite(low):
            a = ds[name].attrs
            out.append(
                f"  {eq}: tau_R^coarse = {float(ds[name[:-5]]):.4g}, numerical uncertainty "
                f"[{low:.4g}, {high:.4g}] (grid x1.5: {a['rel_grid']:+.2%}, n_max 8: "
                f"{a['rel_harmonics']:+.2%}; docs/reference/kinetic_time_uncertainty.csv)"
            )
        else:
            out.append(
                f"  {eq}: no numerical uncertainty band (docs/reference/"
                "kinetic_time_uncertainty.csv is absent or for other settings)"
            )
    return out
