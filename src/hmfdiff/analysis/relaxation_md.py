"""N-body relaxation measured on ensembles: J-bar histograms as densities, their entropy, the
distance to another distribution, and relaxation times.

Phase-space volume per unit J-bar is 4 pi on both sides of the separatrix (librating: dw dJ
with J = 2 J-bar; rotating: two directions of rotation with J = J-bar), so the fraction P_b of
particles in a J-bar bin of width dJbar_b estimates f = P_b / (4 pi dJbar_b) there, and
S = -int f ln f dtheta dp = -sum_b P_b ln f_b (the coarse-grained entropy of the binned f,
which is >= the fine-grained one).
"""

from __future__ import annotations

import numpy as np

from ..dynamics import sampling

__all__ = [
    "bin_fractions",
    "density_from_histogram",
    "entropy_from_histogram",
    "state_bin_fractions",
    "l1_distance",
    "relaxation_time",
    "power_law_fit",
]

PHASE_VOLUME_PER_JBAR = 4.0 * np.pi


def bin_fractions(hist, overflow=None):
    """Fractions of particles per bin (last axis), counting overflow in the total."""
    hist = np.asarray(hist, dtype=float)
    total = hist.sum(axis=-1)
    if overflow is not None:
        total = total + np.asarray(overflow, dtype=float)
    return hist / np.maximum(total, 1.0)[..., None]


def density_from_histogram(hist, edges, overflow=None):
    """f(J-bar) per bin (same shape as hist), normalised to one particle."""
    width = np.diff(np.asarray(edges, dtype=float))
    return bin_fractions(hist, overflow) / (PHASE_VOLUME_PER_JBAR * width)


def entropy_from_histogram(hist, edges, overflow=None):
    """S = -sum_b P_b ln(P_b / (4 pi dJbar_b)) over the last axis (empty bins contribute 0)."""
    P = bin_fractions(hist, overflow)
    f = P / (PHASE_VOLUME_PER_JBAR * np.diff(np.asarray(edges, dtype=float)))
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = np.where(P > 0, P * np.log(np.where(P > 0, f, 1.0)), 0.0)
    return -terms.sum(axis=-1)


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
    each node, phase volume 4 pi width) in the bins `edges`: the cumulative mass at the cell
    faces, interpolated linearly at the edges.  f may carry leading axes (e.g. tau)."""
    jbar = np.asarray(jbar, dtype=float)
    width = np.asarray(width, dtype=float)
    f = np.asarray(f, dtype=float)
    lo = jbar[0] - (width[0] - 0.5 * (jbar[1] - jbar[0]))  # first cell ends half-way to node 1
    faces = lo + np.concatenate([[0.0], np.cumsum(width)])
    mass = PHASE_VOLUME_PER_JBAR * width * f
    cum = np.concatenate([np.zeros(f.shape[:-1] + (1,)), np.cumsum(mass, axis=-1)], axis=-1)
    e = np.asarray(edges, dtype=float)
    at = np.apply_along_axis(lambda c: np.interp(e, faces, c), -1, cum)
    return np.diff(at, axis=-1)


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
