"""Diffusion coefficients from molecular dynamics: fits of <dJ^2>(dt) and comparison with theory.

D_MD(J0) is half the slope of <dJ^2>(dt) over a fit window (eq. hmfmddif), fitted with a free
intercept (the short-lag, oscillatory part of <dJ^2> does not start at zero).  The displacement
is measured in the rescaled action J-bar (continuous across the separatrix) and converted to J:
J = 2 J-bar on librating orbits, so D_J = 4 D_Jbar there and D_J = D_Jbar on rotating orbits.
For a particle that stays in its orbit family this is identical to measuring J directly; a
particle that crosses the separatrix adds a bounded displacement instead of the jump of J.

Seeds (independent realisations of the bath) are pooled by adding their sums and counts; the
standard error comes from the spread of the per-seed slopes, or, with a single seed, from the
spread between blocks of time origins (which shares one bath realisation and so underestimates
the error: the method is recorded in the attributes).
"""

from __future__ import annotations

import numpy as np

from ..meanfield import orbits
from ..pipeline.io import check_physical
from ..pipeline.layouts.md import fit_dataset

__all__ = [
    "FitError",
    "FLAGS",
    "VALIDATION_FLAGS",
    "fit_slope",
    "diffusion_fit",
    "THEORY_OF",
    "theory_at_bins",
    "theory_bin_average",
    "validation_rows",
]

#: flag values of the fitted bins
FLAGS = {
    0: "ok",
    1: "too few particles",
    2: "within the separatrix band",
    3: "MD value not finite (no data in the fit window)",
}
#: flag values of results/validation.csv: those of the fit, then the first of these that holds
VALIDATION_FLAGS = {
    **FLAGS,
    4: "theory not finite (separatrix band or beyond the theory grid)",
    5: "error of the MD value not finite (fewer than two seeds or blocks with a slope)",
}


class FitError(ValueError):
    """An impossible fit request (window outside the lags, no seeds ...)."""


def fit_slope(lag, msd, window):
    """Least-squares slope and intercept of msd(lag) over lag in [window[0], window[1]].

    msd may have leading dimensions; the fit runs along the last axis.  Returns (slope,
    intercept) with NaN where fewer than 3 finite points lie in the window.
    """
    lag = np.asarray(lag, dtype=float)
    msd = np.asarray(msd, dtype=float)
    sel = (lag >= window[0]) & (lag <= window[1])
    x = lag[sel]
    y = msd[..., sel]
    ok = np.isfinite(y)
    n = ok.sum(-1)
    xm = np.where(ok, x, 0.0)
    ym = np.where(ok, y, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        mx = xm.sum(-1) / n
        my = ym.sum(-1) / n
        sxx = (np.where(ok, (x - mx[..., None]) ** 2, 0.0)).sum(-1)
        sxy = (np.where(ok, (x - mx[..., None]) * (y - my[..., None]), 0.0)).sum(-1)
        slope = sxy / sxx
        intercept = my - slope * mx
    bad = n < 3
    return np.where(bad, np.nan, slope), np.where(bad, np.nan, intercept)


def _action_jacobian_sq(jbar0, M0):
    """(dJ/dJbar)^2 at each bin centre: 4 on librating orbits, 1 on rotating ones."""
    return np.where(np.asarray(jbar0) < orbits.action_separatrix(M0, +1), 4.0, 1.0)


#: kappa of the orbit with rescaled action J-bar (the one inverse lives in `orbits`)
kappa_of_jbar = orbits.kappa_from_rescaled_action


def diffusion_fit(datasets, window, min_particles=200, separatrix_band=0.02):
    """Fit N*D_MD per J-bar_0 bin from MD datasets of one case and dynamics (one per seed).

    window: (t_min, t_max) of the linear fit.  Returns a Dataset with N*D per bin (`ND_md`), its
    standard error (`ND_md_err`), the per-seed values, the pooled <dJ^2>(lag) in J units, the
    number of particles per bin, kappa0 and a `flag` per bin (see FLAGS).
    """
    if not datasets:
        raise FitError("no MD datasets to fit")
    for ds in datasets:  # a corrupt file must stop the fit, not become a number
        check_physical(
            ds,
            sums_of_squares=("sum_dJbar2", "sum_dJbar2_block"),
            counts=("count", "count_block", "n_particles_in_bin"),
            increasing=("lag", "jbar_edges"),
        )
    ref = datasets[0]
    lag = ref["lag"].values
    if window[0] >= window[1]:
        raise FitError(f"fit window {window}: t_min must be below t_max")
    if window[1] > lag.max() + 1e-9 or window[0] < 0:
        raise FitError(
            f"fit window {tuple(window)} lies outside the measured lags [0, {lag.max():g}]: "
            "shorten the window or raise md.max_lag"
        )
    for ds in datasets[1:]:
        if not (
            np.array_equal(ds["lag"].values, lag)
            and np.array_equal(ds["jbar_edges"].values, ref["jbar_edges"].values)
        ):
            raise FitError("MD datasets of one fit must share lags and bin edges")
    N = float(ref.attrs["N"])
    M0 = float(ref.attrs["M0_actions"]) if "M0_actions" in ref.attrs else float(ref["M0"])
    jbar0 = ref["jbar0"].values
    jac = _action_jacobian_sq(jbar0, M0)

    def msd(sum_, count):
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(count > 0, sum_ / count, np.nan)

    s = sum(ds["sum_dJbar2"].values for ds in datasets)
    c = sum(ds["count"].values for ds in datasets)
    msd_pooled = msd(s, c) * jac[:, None]
    slope, intercept = fit_slope(lag, msd_pooled, window)
    ND = 0.5 * slope * N

    if len(datasets) >= 2:
        per = np.stack(
            [
                0.5
                * N
                * fit_slope(
                    lag, msd(ds["sum_dJbar2"].values, ds["count"].values) * jac[:, None], window
                )[0]
                for ds in datasets
            ]
        )
        method = f"standard error of the mean over {len(datasets)} independent seeds"
    else:
        blk = ref["sum_dJbar2_block"].values  # (bin, lag, block)
        cb = ref["count_block"].values
        per = np.stack(
            [
                0.5 * N * fit_slope(lag, msd(blk[..., b], cb[..., b]) * jac[:, None], window)[0]
                for b in range(blk.shape[-1])
            ]
        )
        method = (
            f"standard error over {blk.shape[-1]} blocks of time origins of one seed "
            "(one bath realisation: underestimates the error)"
        )
    n_ok = np.isfinite(per).sum(0)
    with np.errstate(invalid="ignore"):
        err = np.nanstd(per, axis=0, ddof=1) / np.sqrt(n_ok)
    err = np.where(n_ok >= 2, err, np.nan)

    n_part = sum(ds["n_particles_in_bin"].values for ds in datasets)
    kappa0 = kappa_of_jbar(jbar0, M0)
    flag = np.zeros(jbar0.size, dtype=np.int8)
    flag[n_part < min_particles] = 1
    flag[np.abs(kappa0 - 1.0) < separatrix_band] = 2
    flag[~np.isfinite(ND)] = 3

    seeds = [int(ds.attrs.get("seed", i)) for i, ds in enumerate(datasets)]
    jrange = ref.attrs.get("jbar_range", "none")
    jrange = "none" if isinstance(jrange, str) else [float(x) for x in np.atleast_1d(jrange)]
    return fit_dataset(
        {
            "ND_md": ND,
            "ND_md_err": err,
            "ND_md_seed": per
            if len(datasets) >= 2
            else np.full((len(datasets), jbar0.size), np.nan),
            "intercept": intercept,
            "msd": msd_pooled,
            "n_particles_in_bin": n_part,
            "kappa0": kappa0,
            "J0": orbits.action(kappa0, M0),
            "flag": flag,
            "flags": FLAGS,
            "M0": M0,
            "jbar0": jbar0,
            "jbar_edges": ref["jbar_edges"].values,
            "lag": lag,
            "seed": seeds,
            "attrs": dict(
                fit_window=list(map(float, window)),
                N=N,
                n_seeds=len(datasets),
                min_particles=int(min_particles),
                separatrix_band=float(separatrix_band),
                error_method=method,
                dynamics=str(ref.attrs.get("dynamics", "")),
                D_convention="<dJ^2> = 2 D dt; N*D stored",
                n_test=int(ref.attrs.get("n_test", 0)),
                n_tracked_from_f=int(ref.attrs.get("n_tracked_from_f", N)),
                test_sampling=str(ref.attrs.get("test_sampling", "none")),
                jbar_range=jrange,
            ),
        }
    )


#: the kinetic equation whose D each dynamics measures: bare for MD(bath), dressed for MD(full)
THEORY_OF = {"bath": "landau", "full": "lenard_balescu"}


def theory_at_bins(theory, kappa0, dynamics, equation=None):
    """N*D of the theory at kappa0: Landau for MD(bath), Lenard-Balescu for MD(full), or the
    `equation` ('landau', 'lenard_balescu') named.

    Interpolates log(N D) linearly in kappa on the theory grid within each orbit family; NaN in
    the masked separatrix band or outside the grid.
    """
    name = f"D_{equation or THEORY_OF[dynamics]}"
    k = theory["kappa"].values
    D = theory[name].values
    out = np.full(np.shape(kappa0), np.nan)
    for fam in (k < 1, k > 1):
        kk, dd = k[fam], D[fam]
        ok = np.isfinite(dd) & (dd > 0)
        kk, dd = kk[ok], dd[ok]
        if kk.size < 2:
            continue
        sel = (kappa0 >= kk.min()) & (kappa0 <= kk.max())
        out[sel] = np.exp(np.interp(kappa0[sel], kk, np.log(dd)))
    return out


def tracked_density(jbar, fit, f_of_kappa):
    """Number of tracked particles per unit J-bar at J-bar (up to a constant), for the bin average.

    Particles drawn from f contribute 4 pi N f(kappa(J-bar)) per unit J-bar on both orbit
    families (dJ/dJ-bar = 2 on librating orbits, where a kappa labels one torus; 1 on rotating
    orbits, where it labels two); test particles drawn uniformly in J-bar contribute
    n_test / (J-bar range).  MD(bath) tracks its test particles only; MD(full) tracks n_track
    of its N particles (all N by default), drawn at random.
    """
    M0 = float(fit["M0"])
    k = kappa_of_jbar(jbar, M0)
    # MD(full) may track a random subset of its N particles (md.n_track)
    N = float(fit.attrs.get("n_tracked_from_f", fit.attrs["N"]))
    n_test = int(fit.attrs.get("n_test", 0))
    rho = np.zeros_like(jbar, dtype=float)
    if fit.attrs["dynamics"] == "full":
        rho += 4.0 * np.pi * N * f_of_kappa(k)
    if n_test:
        rng = fit.attrs.get("jbar_range", "none")
        if fit.attrs.get("test_sampling") == "uniform" and not isinstance(rng, str):
            lo, hi = np.asarray(rng, dtype=float)[:2]
            rho += np.where((jbar >= lo) & (jbar <= hi), n_test / (hi - lo), 0.0)
        else:
            rho += 4.0 * np.pi * n_test * f_of_kappa(k)
    return rho


def theory_bin_average(theory, fit, f_of_kappa, n_sub=41, equation=None):
    """N*D of the theory averaged over each J-bar_0 bin with the density of tracked particles.

    The MD measures the mean of dJ^2 over the particles of a bin, i.e. the density-weighted
    average of D over the bin; where D has narrow structure (weakly damped modes, steps of the
    resonance staircase) this differs from D at the bin centre.  NaN for bins that reach into
    the masked separatrix band or beyond the theory grid.  The theory is that of the fit's
    dynamics (`THEORY_OF`) unless `equation` names the other, averaged with the same density.
    """
    edges = fit["jbar_edges"].values
    M0 = float(fit["M0"])
    out = np.full(edges.size - 1, np.nan)
    for i, (a, b) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        jb = np.linspace(a, b, n_sub + 2)[1:-1]
        D = theory_at_bins(theory, kappa_of_jbar(jb, M0), fit.attrs["dynamics"], equation)
        w = tracked_density(jb, fit, f_of_kappa)
        if np.all(np.isfinite(D)) and w.sum() > 0:
            out[i] = np.sum(D * w) / np.sum(w)
    return out


def validation_rows(case, fit, theory, f_of_kappa=None):
    """Rows of results/validation.csv for one case and dynamics.

    ND_theory is the bin average of the theory (`theory_bin_average`) when f_of_kappa is given,
    else the theory at the bin centre.  `flag` is the fit's, else 3, 4 or 5 (VALIDATION_FLAGS)
    when the MD value, the theory or the error of the MD value is not finite.
    """
    check_physical(
        fit, counts=("n_particles_in_bin",), increasing=("jbar_edges",), nonnegative=("ND_md_err",)
    )
    check_physical(theory, increasing=("kappa",), nonnegative=("D_landau", "D_lenard_balescu"))
    dyn = fit.attrs["dynamics"]
    if f_of_kappa is not None:
        th = theory_bin_average(theory, fit, f_of_kappa)
    else:
        th = theory_at_bins(theory, fit["kappa0"].values, dyn)
    nd, err = fit["ND_md"].values, fit["ND_md_err"].values
    rows = []
    for i in range(fit.sizes["bin"]):
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = nd[i] / th[i]
            z = (nd[i] - th[i]) / err[i]
        flag = int(fit["flag"].values[i])
        if flag == 0:
            checks = ((3, nd[i]), (4, th[i]), (5, err[i]))
            flag = next((code for code, value in checks if not np.isfinite(value)), 0)
        rows.append(
            {
                "case": case,
                "dynamics": dyn,
                "M0": float(fit["M0"]),
                "J0": float(fit["J0"].values[i]),
                "kappa0": float(fit["kappa0"].values[i]),
                "n_particles_in_bin": int(fit["n_particles_in_bin"].values[i]),
                "ND_md": float(nd[i]),
                "ND_md_err": float(err[i]),
                "ND_theory": float(th[i]),
                "ratio": float(ratio),
                "z": float(z),
                "flag": flag,
                "n_seeds": int(fit.attrs["n_seeds"]),
                "min_particles": int(fit.attrs["min_particles"]),
                "separatrix_band": float(fit.attrs["separatrix_band"]),
            }
        )
    return rows


VALIDATION_COLUMNS = [
    "case",
    "dynamics",
    "M0",
    "J0",
    "kappa0",
    "n_particles_in_bin",
    "ND_md",
    "ND_md_err",
    "ND_theory",
    "ratio",
    "z",
    "flag",
    # the theory fitted like the MD (analysis.windowed; absent when not computed)
    "ND_windowed",
    "ratio_windowed",
    "z_windowed",
    "ND_spectrum",
    # the theory propagated over the fit's lags (analysis.propagated; absent when not computed)
    "ND_propagated",
    "ratio_propagated",
    "z_propagated",
    # the realisations behind ND_md_err (the degrees of freedom of z: n_seeds - 1)
    "n_seeds",
]


def write_validation_csv(rows, path):
    """Write the validation rows as CSV, atomically."""
    import csv

    from ..pipeline.io import atomic_path

    with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=VALIDATION_COLUMNS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
