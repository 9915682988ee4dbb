"""The theory's prediction of what the MD fit measures: the finite-time <dJ^2>(t) of the bath's
spectrum fitted over the MD fit's own lags and window (`kinetic.spectrum.windowed_diffusion`),
bare for MD(bath) and dressed for MD(full), averaged over each J-bar_0 bin with the density of
tracked particles like the asymptotic ND_theory of `fits.theory_bin_average` (issue 15).

The MD fits half the least-squares slope of <dJ^2>(t) over a window of a few hundred time
units; the asymptotic D is its limit t -> infinity.  Where the spectrum has structure narrower
than 2 pi / window (band edges n Omega_0, weakly damped modes) or D varies fast (the separatrix)
the two differ, and only the windowed one is a like-for-like prediction.  The asymptotic D
through the same tabulated spectrum (`diffusion_from_spectrum`) is given beside it, as a check
of the tabulation against the resonance sums of results/theory.
"""

from __future__ import annotations

import numpy as np

from ..kinetic.dielectric import DielectricTensor
from ..kinetic.spectrum import SpectrumTable, diffusion_from_spectrum, windowed_diffusion
from .fits import kappa_of_jbar, tracked_density
from .propagated import add_propagated

__all__ = ["windowed_at_bins", "spectrum_table"]


def spectrum_table(fit, state, *, n_max=6, l_max=6):
    """The bath's spectrum tabulated for the fit's dynamics: bare for MD(bath), dressed (the
    dielectric tensor with |l| <= l_max) for MD(full)."""
    eps = DielectricTensor(state, l_max=l_max) if fit.attrs["dynamics"] == "full" else None
    return SpectrumTable(state, n_max=n_max, eps=eps)


def windowed_at_bins(fit, state, *, n_max=6, l_max=6, separatrix_band=0.01, n_sub=7, table=None):
    """(ND_windowed, ND_spectrum) per bin of a fit dataset (`fits.diffusion_fit`).

    The lags are the fit's lags inside its fit window; each bin is sampled at n_sub points
    uniform in J-bar and weighted by the density of tracked particles (`fits.tracked_density`).
    Bins with a sample point within separatrix_band of kappa = 1 are NaN (as for ND_theory).
    `table`: a `spectrum_table` of this fit and state, if one is at hand."""
    table = table or spectrum_table(fit, state, n_max=n_max, l_max=l_max)
    M0 = float(fit["M0"])
    lag = fit["lag"].values
    w0, w1 = fit.attrs["fit_window"]
    lags = lag[(lag >= w0) & (lag <= w1)]
    edges = fit["jbar_edges"].values
    frac = (np.arange(n_sub) + 0.5) / n_sub
    jb = edges[:-1, None] + np.diff(edges)[:, None] * frac[None, :]  # (bin, sub)
    kappa = kappa_of_jbar(jb.ravel(), M0)
    near = np.abs(kappa - 1.0) < separatrix_band
    k_ok = np.where(near, 0.5, kappa)  # placeholder where masked
    win = windowed_diffusion(table, k_ok, M0, lags).reshape(jb.shape)
    asym = diffusion_from_spectrum(table, k_ok, M0).reshape(jb.shape)
    w = tracked_density(jb.ravel(), fit, state.f).reshape(jb.shape)
    bad = near.reshape(jb.shape).any(axis=1) | (w.sum(axis=1) <= 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        nd_win = np.where(bad, np.nan, (win * w).sum(1) / w.sum(1))
        nd_asym = np.where(bad, np.nan, (asym * w).sum(1) / w.sum(1))
    return nd_win, nd_asym


#: the columns this module adds to results/validation.csv
WINDOWED_COLUMNS = ("ND_windowed", "ratio_windowed", "z_windowed", "ND_spectrum")


def add_windowed(rows, windowed):
    """Add ND_windowed, its ratio and z (with the MD error), and ND_spectrum to the validation
    rows of one case and dynamics (in bin order), from a results/windowed dataset; and
    ND_propagated with its ratio and z where the dataset carries it (`analysis.propagated`)."""
    nw = windowed["ND_windowed"].values
    ns = windowed["ND_spectrum"].values
    if len(rows) != nw.size:
        raise ValueError(f"{len(rows)} validation rows but {nw.size} windowed bins")
    for r, w, s in zip(rows, nw, ns, strict=True):
        with np.errstate(invalid="ignore", divide="ignore"):
            r["ND_windowed"] = float(w)
            r["ratio_windowed"] = float(r["ND_md"] / w)
            r["z_windowed"] = float((r["ND_md"] - w) / r["ND_md_err"])
            r["ND_spectrum"] = float(s)
    if "ND_propagated" in windowed:
        add_propagated(rows, windowed["ND_propagated"].values)
    return rows
