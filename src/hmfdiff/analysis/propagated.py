"""What the MD fit measures when its particles diffuse across structure in D during the fit's
lags: the theory's own D propagated by its Fokker-Planck equation over the fit's lags (issue 23
part 4).

The fit takes half the least-squares slope of <dJ^2>(lag) over a window of lags (tens to
hundreds of time units) for the particles whose J-bar lay in a bin at the time origin.  Over
that time a particle diffuses by sqrt(2 D lag) in action, about 0.03 in J-bar at N = 1e6 and
lag 200 (u = 0.2475), i.e. 0.05 in kappa: where D varies on that scale, as beside the
separatrix (on the librating side N D of Lenard-Balescu rises from 12 to 26 between
kappa = 0.975 and 0.99; on the rotating side it falls from 5 to 2.5 between 1.01 and 1.03), the
slope is not the D of the bin but an average over the region the particles cover, weighted by
the drift dD/dJ that carries them up the gradient.  The correction to D is of relative order
D lag / L^2 (L the scale of D): order 1/N where D is smooth, but order one within
sqrt(D lag) ~ N^-1/2 of the separatrix, where the 1/N expansion is not uniform.

Here each bin's particles (with the density of tracked particles of `fits.tracked_density`)
evolve by the kinetic equation of one particle in J-bar,

    dP/dt = d/dJbar [ D_Jbar dP/dJbar ]      (Ito drift dD_Jbar/dJbar, no friction),

with D_Jbar = D_J (dJbar/dJ)^2 = D_J / 4 below the separatrix and D_J above it, from the
theory's N D_J (Landau for MD(bath), Lenard-Balescu for MD(full)) divided by N.  No friction:
the test particles of MD(bath) and the extra test particles of MD(full) have none (they act on
nothing), and the friction of MD(full)'s own particles adds (Dpol lag)^2 to <dJ^2>, of
relative order (beta Omega)^2 D lag: with the thermal friction included the fine bins of the
u = 0.2475 study move by at most 1 % (2026-11-27).  J-bar is continuous across the separatrix
and the two rotating tori of a kappa > 1 hold as many states per dJ-bar as the librating
torus, so one variable serves both families.  <dJ^2>(lag) = <(Jbar - Jbar_0)^2> (dJ/dJbar)^2 of
the bin, fitted like the MD (`fits.fit_slope` over the fit window), gives ND_propagated.  The
propagator is exact in time (eigenvectors of the symmetric tridiagonal operator on cells
uniform in J-bar, aligned with the bins' edges; the discrete moments obey d<x>/dt = <D'> and
d<x^2>/dt = <2 x D' + 2 D> like the continuous ones).  Within SEPARATRIX_GAP of kappa = 1,
where the orbit-averaged theory has no value (and the fluctuating magnetisation moves the
separatrix by more at the paper's N), D is interpolated linearly in log D against J-bar; bins
that reach into the gap are NaN.

As N -> infinity ND_propagated -> the bin average of the theory (`fits.theory_bin_average`);
at the paper's N it differs from it by more than the MD's errors only in the bins beside the
separatrix band, where it is the like-for-like prediction of the kinetic theory.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import eigh_tridiagonal

from ..meanfield import orbits
from .fits import fit_slope, kappa_of_jbar, theory_at_bins, tracked_density

__all__ = [
    "propagated_at_bins",
    "propagated_msd_at_bins",
    "propagated_msd",
    "nd_from_theory",
    "PROPAGATED_COLUMNS",
    "add_propagated",
]

#: cells of the J-bar grid, about (aligned with the bins' edges)
N_CELLS = 3000
#: half-width in kappa of the gap round the separatrix where D is interpolated, not evaluated
SEPARATRIX_GAP = 1e-3


def nd_from_theory(theory, dynamics):
    """N D_J(kappa) of a results/theory dataset for `dynamics` (`fits.theory_at_bins`: Landau
    for MD(bath), Lenard-Balescu for MD(full); NaN in its masked band)."""
    return lambda kappa: theory_at_bins(theory, kappa, dynamics)


def _D_jbar(jbar, nd_of_kappa, M0, N, gap):
    """D in J-bar (not N D) at J-bar: N D_J from nd_of_kappa divided by N and by
    (dJ/dJ-bar)^2; where that is not finite or |kappa - 1| < gap, interpolated linearly in
    log D_Jbar against J-bar between the nearest usable values (held beyond the last)."""
    kappa = kappa_of_jbar(jbar, M0)
    with np.errstate(invalid="ignore"):
        D = np.asarray(nd_of_kappa(kappa), dtype=float) / N * np.where(kappa < 1.0, 0.25, 1.0)
    ok = np.isfinite(D) & (D > 0) & (np.abs(kappa - 1.0) >= gap)
    if ok.sum() < 2:
        raise ValueError("the theory's D has fewer than 2 usable values on the J-bar grid")
    return np.where(ok, D, np.exp(np.interp(jbar, jbar[ok], np.log(D[ok]))))


def _cells(fit, kappa_top):
    """Cell centres and width: uniform in J-bar from 0 to J-bar(kappa_top) (at least the fit's
    last edge), an integer number of cells per bin."""
    edges = fit["jbar_edges"].values
    M0 = float(fit["M0"])
    widths = np.diff(edges)
    if not np.allclose(widths, widths[0], rtol=1e-9) or abs(edges[0]) > 1e-12 * edges[-1]:
        raise ValueError("propagated_at_bins needs bins uniform in J-bar from 0")
    top = max(float(orbits.rescaled_action(kappa_top, M0)), edges[-1])
    per_bin = max(1, int(round(N_CELLS * widths[0] / top)))
    h = widths[0] / per_bin
    n = int(np.ceil(top / h))
    return (np.arange(n) + 0.5) * h, h, per_bin


def propagated_msd(x, h, D_faces, P0, lags, rho=None):
    """<(Jbar - Jbar_0)^2>(lag) for initial densities P0 (cell, set) on cells x of width h.

    D_faces: D_Jbar on the n - 1 inner faces; rho: the density the equation leaves
    stationary (default uniform: no friction); zero flux through the outer faces.  Exact in
    time: the operator symmetrised by rho^(1/2) is tridiagonal with off-diagonal D/h^2."""
    rho = np.ones_like(x) if rho is None else np.asarray(rho, dtype=float) / np.max(rho)
    if np.any(~np.isfinite(D_faces)) or np.any(D_faces < 0):
        raise ValueError("D on the faces must be finite and non-negative")
    if np.any(~(rho > 0)):
        raise ValueError("the stationary density must be positive on every cell")
    s = np.sqrt(rho)
    off = D_faces / h**2
    diag = np.zeros(x.size)
    diag[:-1] -= off * s[1:] / s[:-1]
    diag[1:] -= off * s[:-1] / s[1:]
    lam, V = eigh_tridiagonal(diag, off)
    lam = np.minimum(lam, 0.0)  # the operator is negative semi-definite; rounding aside
    P0 = np.asarray(P0, dtype=float)
    P0 = P0 / P0.sum(0)
    # P(t) = s V exp(lam t) V^T (P0 / s); the moments of X = x - <x>_0 (centred on each set's
    # initial mean, so that <(x - x0)^2> ~ 1e-4 <x^2> does not cancel against <x^2>)
    X = x[:, None] - (P0 * x[:, None]).sum(0)[None, :]
    a0 = V.T @ (P0 / s[:, None])
    a1 = V.T @ (P0 * X / s[:, None])
    c1 = V.T @ (s[:, None] * X)
    c2 = V.T @ (s[:, None] * X**2)
    m0 = (P0 * X**2).sum(0)
    e = np.exp(np.outer(lags, lam))  # (lag, mode)
    return e @ (c2 * a0) - 2.0 * (e @ (c1 * a1)) + m0[None, :]


def propagated_msd_at_bins(fit, nd_of_kappa, f_of_kappa, *, kappa_top=3.0, gap=SEPARATRIX_GAP):
    """<dJ^2>(lag) per bin of a fit dataset (`fits.diffusion_fit`), in J units like the fit's
    `msd`, as the theory's N D_J(kappa) (`nd_of_kappa`, of the fit's dynamics) gives it when
    propagated over the fit's lags from each bin's tracked density (module docstring); cells up
    to J-bar(kappa_top); no friction.  Returns (lag, msd (lag, bin)); NaN for bins with no
    tracked density."""
    N = float(fit.attrs["N"])
    M0 = float(fit["M0"])
    lag = fit["lag"].values
    x, h, per_bin = _cells(fit, kappa_top)
    D = _D_jbar(np.arange(1, x.size) * h, nd_of_kappa, M0, N, gap)
    n_bins = fit.sizes["bin"]
    w = tracked_density(x[: n_bins * per_bin], fit, f_of_kappa).reshape(n_bins, per_bin)
    P0 = np.zeros((x.size, n_bins))
    for b in range(n_bins):
        P0[b * per_bin : (b + 1) * per_bin, b] = w[b]
    live = P0.sum(0) > 0
    msd = np.full((lag.size, n_bins), np.nan)
    if np.any(live):
        jbar0 = fit["jbar0"].values[live]
        jac2 = np.where(jbar0 < orbits.jbar_separatrix(M0), 4.0, 1.0)
        msd[:, live] = propagated_msd(x, h, D, P0[:, live], lag) * jac2[None, :]
    return lag, msd


def propagated_at_bins(fit, nd_of_kappa, f_of_kappa, *, kappa_top=3.0, gap=SEPARATRIX_GAP):
    """ND_propagated per bin of a fit dataset (`fits.diffusion_fit`): half the slope over the
    fit's window of `propagated_msd_at_bins`, times N.  NaN for bins that reach into
    |kappa - 1| < gap or have no tracked density."""
    N = float(fit.attrs["N"])
    M0 = float(fit["M0"])
    window = tuple(float(w) for w in fit.attrs["fit_window"])
    lag, msd = propagated_msd_at_bins(fit, nd_of_kappa, f_of_kappa, kappa_top=kappa_top, gap=gap)
    out = np.full(msd.shape[1], np.nan)
    live = np.all(np.isfinite(msd), axis=0)
    if np.any(live):
        out[live] = 0.5 * N * fit_slope(lag, msd[:, live].T, window)[0]
    edges = fit["jbar_edges"].values
    k_lo, k_hi = kappa_of_jbar(edges[:-1], M0), kappa_of_jbar(edges[1:], M0)
    out[(k_hi > 1.0 - gap) & (k_lo < 1.0 + gap)] = np.nan
    return out


#: the columns this module adds to results/validation.csv
PROPAGATED_COLUMNS = ("ND_propagated", "ratio_propagated", "z_propagated")


def add_propagated(rows, nd_propagated):
    """Add ND_propagated, its ratio and z (with the MD error) to the validation rows of one case
    and dynamics (in bin order)."""
    if len(rows) != len(nd_propagated):
        raise ValueError(f"{len(rows)} validation rows but {len(nd_propagated)} propagated bins")
    for r, p in zip(rows, nd_propagated, strict=True):
        with np.errstate(invalid="ignore", divide="ignore"):
            r["ND_propagated"] = float(p)
            r["ratio_propagated"] = float(r["ND_md"] / p)
            r["z_propagated"] = float((r["ND_md"] - p) / r["ND_md_err"])
    return rows
