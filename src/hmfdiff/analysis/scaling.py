"""The 1/N study (figure 15): N*D_MD per bin at each N beside the kinetic theory averaged over the
same bins exactly as `results/validation.csv` averages it (`fits.theory_bin_average`: the
density of the tracked particles of that N's runs), and the bins the figure draws.

Where the kinetic theory's 1/N ordering holds, N*D_MD is independent of N and equals the
theory of its dynamics: the bare (Landau) D for MD(bath), the dressed (Lenard-Balescu) D for
MD(full).
"""

from __future__ import annotations

import numpy as np

from .fits import THEORY_OF, theory_bin_average

__all__ = ["OTHER_THEORY", "scaling_theory", "drawn_bins", "excess_power_law"]

#: the other kinetic equation of each dynamics (drawn for comparison)
OTHER_THEORY = {"bath": "lenard_balescu", "full": "landau"}
#: bins drawn when the study names none
N_DRAWN = 4


def scaling_theory(fits, theory, f_of_kappa):
    """(ND_theory, ND_other), each (N, bin): the theory of the fits' dynamics and the other one,
    bin-averaged with the tracked density of each fit (one per N)."""
    dyn = {str(f.attrs["dynamics"]) for f in fits}
    if len(dyn) != 1 or not dyn <= set(THEORY_OF):
        raise ValueError(f"fits of one dynamics, 'bath' or 'full', expected: got {sorted(dyn)}")
    (dyn,) = dyn
    own = np.stack([theory_bin_average(theory, f, f_of_kappa) for f in fits])
    other = np.stack(
        [theory_bin_average(theory, f, f_of_kappa, equation=OTHER_THEORY[dyn]) for f in fits]
    )
    return own, other


def drawn_bins(kappa0, valid, targets=None, n=N_DRAWN):
    """Indices of the bins to draw, in increasing kappa0: the bin whose centre lies nearest each
    of `targets`, else `n` bins spread evenly over the `valid` ones (flag 0, finite theory
    and error at every N)."""
    kappa0 = np.asarray(kappa0, dtype=float)
    if targets:
        pick = {int(np.argmin(np.abs(kappa0 - t))) for t in targets}
        return sorted(pick, key=lambda b: kappa0[b])
    bins = np.flatnonzero(np.asarray(valid, dtype=bool))
    if bins.size == 0:
        return []
    idx = np.unique(np.linspace(0, bins.size - 1, min(n, bins.size)).round().astype(int))
    return sorted(bins[idx].tolist(), key=lambda b: kappa0[b])


def excess_power_law(N, excess, err, exponents=(0.5, 1.0), n_ref=1e4):
    """Fit a finite-N excess over the order-1/N theory, excess = A (N / n_ref)^-a, by weighted
    least squares on the excess itself (not its logarithm: an excess of a few per cent with an
    error of its own size has no usable logarithm), and the profiled chi^2 of fixed exponents.

    A boundary layer of width N^-1/2 predicts a = 1/2; the order-1/N^2 collision terms predict a
    relative excess ~1/N, a = 1.  Returns a dict: `a`, `a_err` (from the fit's covariance, not
    rescaled by chi^2), `A`, `A_err`, `chi2`, `dof` (points - 2), and `fixed`: for each exponent
    in `exponents`, (chi^2 with A refitted, its p-value on points - 1 degrees of freedom)."""
    from scipy.optimize import least_squares
    from scipy.stats import chi2 as chi2_dist

    x = np.asarray(N, dtype=float) / n_ref
    y = np.asarray(excess, dtype=float)
    s = np.asarray(err, dtype=float)
    if not (x.shape == y.shape == s.shape) or x.size < 3:
        raise ValueError(f"excess_power_law: at least 3 points of N, excess, err; got {x.shape}")
    if np.any(~np.isfinite(y)) or np.any(~(s > 0)) or np.any(~(x > 0)):
        raise ValueError("excess_power_law: N > 0, finite excess and err > 0 expected")

    def model(p):
        return p[0] * x ** (-p[1])

    def fixed(a):
        g = x ** (-a)
        amp = np.sum(y * g / s**2) / np.sum(g**2 / s**2)
        c2 = float(np.sum(((y - amp * g) / s) ** 2))
        return c2, float(chi2_dist.sf(c2, x.size - 1))

    # start from the better of the fixed exponents, amplitude refitted
    a0 = min(exponents, key=lambda a: fixed(a)[0]) if exponents else 0.5
    g0 = x ** (-a0)
    p0 = [np.sum(y * g0 / s**2) / np.sum(g0**2 / s**2), a0]
    fit = least_squares(lambda p: (y - model(p)) / s, p0, method="lm")
    J = fit.jac
    cov = np.linalg.inv(J.T @ J)
    return {
        "a": float(fit.x[1]),
        "a_err": float(np.sqrt(cov[1, 1])),
        "A": float(fit.x[0]),
        "A_err": float(np.sqrt(cov[0, 0])),
        "chi2": float(np.sum(fit.fun**2)),
        "dof": x.size - 2,
        "fixed": {a: fixed(a) for a in exponents},
    }
