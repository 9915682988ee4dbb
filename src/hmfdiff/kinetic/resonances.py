"""Resonances n Omega(kappa) = n' Omega(kappa*) between a test orbit and the bath (fig. hmfpoles).

Omega(kappa) decreases from Omega_0 = sqrt(M0) to 0 on librating orbits and increases from 0
to infinity on rotating orbits, so a frequency 0 < x < Omega_0 has two pre-images
(kappa_1 < 1 < kappa_2) and x >= Omega_0 has one (kappa_2 > 1).  n and n' must have the same
sign (Omega > 0).
"""

from __future__ import annotations

import numpy as np

from ..meanfield import orbits

__all__ = ["resonant_kappas", "BRANCHES"]

#: order of the last axis of `resonant_kappas`
BRANCHES = ("libration", "rotation")


def resonant_kappas(kappa, n, nprime, M0):
    """All roots kappa* of n Omega(kappa) = n' Omega(kappa*).

    Broadcasts kappa, n, nprime; returns an array of shape broadcast + (2,): [..., 0] the
    librating root (kappa* < 1), [..., 1] the rotating root (kappa* > 1), NaN where there is
    none (n n' <= 0, or n Omega(kappa)/n' >= Omega_0 for the librating root).
    """
    kappa, n, nprime = np.broadcast_arrays(
        np.asarray(kappa, dtype=float), np.asarray(n), np.asarray(nprime)
    )
    ok = (n * nprime > 0) & np.isfinite(kappa)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = n / np.where(nprime == 0, 1, nprime)
        target = np.where(ok, ratio * orbits.frequency(kappa, M0), np.nan)
    target = np.where(ok & (target > 0), target, np.nan)
    k_lib = orbits.kappa_from_frequency(np.nan_to_num(target, nan=-1.0), M0, "libration")
    k_rot = orbits.kappa_from_frequency(np.nan_to_num(target, nan=-1.0), M0, "rotation")
    return np.stack([k_lib, k_rot], axis=-1)
