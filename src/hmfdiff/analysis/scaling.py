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

__all__ = ["OTHER_THEORY", "scaling_theory", "drawn_bins"]

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
