"""N-body relaxation measured on ensembles: J-bar histograms as densities, their entropy, the
distance to another distribution, and relaxation times.

The density and entropy of a histogram (`density_from_histogram`, `entropy_from_histogram`:
f = P_b / (4 pi dJbar_b), the phase-space volume per unit J-bar being 4 pi) live in
`meanfield.histograms`, which the file layouts of `pipeline` use too; they are re-exported here.
"""

from __future__ import annotations

import numpy as np

from ..dynamics import sampling
from ..meanfield.histograms import (
    PHASE_VOLUME_PER_JBAR,
    bin_fractions,
    density_from_histogram,
    entropy_from_histogram,
)

__all__ = [
    "bin_fractions",
    "density_from_histogram",
    "entropy_from_histogram",
    "state_bin_fractions",
    "l1_distance",
    "relaxation_time",
    "power_law_fit",
]


def state_bin_fractions(state, edges):
    """Fractions of a state's particles in the J-bar bins (exact CDF of J-bar, tabulated)."""
    jg, cdf = sampling.jbar_cdf_table(state)
    return np.diff(np.interp(np.asarray(edges, dtype=float), jg, cdf / cdf[-1]))


def l1_distance(P, Q):
    """sum_b |P_b - Q_b| over the last axis: 0 for equal histograms, 2 at most."""
    return np.abs(np.asarray(P) - np.asarray(Q)).sum(axis=-1)


def relaxation_time(t, d, floor=0.0):
    """First time at which the excess distance d(t) - floor has fallen to 1/e of d(0) - floor,
    by linear interpolation between samples; NaN if it never does."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(d, dtype=float) - floor
    target = x[0] / np.e
    below = np.nonzero(x <= target)[0]
    if x[0] <= 0 or below.size == 0:
        return np.nan
    k = below[0]
    if k == 0:
        return t[0]
    return float(t[k - 1] + (target - x[k - 1]) * (t[k] - t[k - 1]) / (x[k] - x[k - 1]))


def power_law_fit(n, tau, tau_err=None):
    """Fit tau = A n^alpha by least squares in log-log (weights from tau_err if given).

    Returns (alpha, alpha_err, A)."""
    n = np.asarray(n, dtype=float)
    tau = np.asarray(tau, dtype=float)
    x, y = np.log(n), np.log(tau)
    if tau_err is None:
        w = np.ones_like(x)
    else:
        w = 1.0 / np.maximum(np.asarray(tau_err, dtype=float) / tau, 1e-12) ** 2
    X = np.stack([np.ones_like(x), x], axis=1)
    cov = np.linalg.inv(X.T @ (w[:, None] * X))
    coef = cov @ (X.T @ (w * y))
    resid = y - X @ coef
    dof = max(x.size - 2, 1)
    if tau_err is None:
        cov = cov * float(np.sum(resid**2) / dof)
    return float(coef[1]), float(np.sqrt(cov[1, 1])), float(np.exp(coef[0]))


def kinetic_bin_fractions(jbar, width, f, edges):
    """Fractions of particles of a kinetic f on J-bar nodes (cells of width `width` around
    each node, contiguous, phase volume 4 pi width) in the bins `edges`: the cumulative mass at
    the cell faces, interpolated linearly at the edges.  f may carry leading axes (e.g. tau);
    jbar and width are either one grid (N,) or one per leading index, shaped like f (the
    kinetic grid stretches in J-bar with sqrt(M0(tau)))."""
    jbar = np.asarray(jbar, dtype=float)
    width = np.asarray(width, dtype=float)
    f = np.asarray(f, dtype=float)
    e = np.asarray(edges, dtype=float)
    if jbar.ndim == 1:
        jbar = np.broadcast_to(jbar, f.shape)
        width = np.broadcast_to(width, f.shape)
    flat_j = jbar.reshape(-1, jbar.shape[-1])
    flat_w = width.reshape(-1, width.shape[-1])
    flat_f = f.reshape(-1, f.shape[-1])
    out = np.empty((flat_f.shape[0], e.size - 1))
    for k, (jb, w, ff) in enumerate(zip(flat_j, flat_w, flat_f, strict=True)):
        lo = jb[0] - (w[0] - 0.5 * (jb[1] - jb[0]))  # first cell ends half-way to node 1
        faces = lo + np.concatenate([[0.0], np.cumsum(w)])
        cum = np.concatenate([[0.0], np.cumsum(PHASE_VOLUME_PER_JBAR * w * ff)])
        out[k] = np.diff(np.interp(e, faces, cum))
    return out.reshape(f.shape[:-1] + (e.size - 1,))


def interpolate_in_time(t_src, values, t):
    """Values (time along axis 0) interpolated linearly at times t; constant beyond the ends."""
    values = np.asarray(values, dtype=float)
    flat = values.reshape(values.shape[0], -1)
    out = np.stack([np.interp(t, t_src, flat[:, j]) for j in range(flat.shape[1])], axis=-1)
    return out.reshape((np.size(t),) + values.shape[1:])


def jackknife(values_per_group, estimator):
    """Estimate and jackknife standard error of `estimator` over groups (axis 0 of the input),
    leaving one group out at a time."""
    v = np.asarray(values_per_group)
    g = v.shape[0]
    full = np.asarray(estimator(v))
    if g < 2:
        return full, np.full(full.shape, np.nan)
    loo = np.stack([np.asarray(estimator(np.delete(v, k, axis=0))) for k in range(g)])
    err = np.sqrt((g - 1) / g * np.sum((loo - loo.mean(axis=0)) ** 2, axis=0))
    return full, err
