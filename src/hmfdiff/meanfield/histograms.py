"""J-bar histograms of particles read as the phase-space density f and its entropy.

Phase-space volume per unit J-bar is 4 pi on both sides of the separatrix (librating: dw dJ
with J = 2 J-bar; rotating: two directions of rotation with J = J-bar), so the fraction P_b of
particles in a J-bar bin of width dJbar_b estimates f = P_b / (4 pi dJbar_b) there, and
S = -int f ln f dtheta dp = -sum_b P_b ln f_b (the coarse-grained entropy of the binned f,
which is >= the fine-grained one).

Pure functions of the counts (numpy only), below both the file layouts of `pipeline`, which
store f and S of the N-body ensembles, and `analysis.relaxation_md`, which compares them.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "PHASE_VOLUME_PER_JBAR",
    "bin_fractions",
    "density_from_histogram",
    "entropy_from_histogram",
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
