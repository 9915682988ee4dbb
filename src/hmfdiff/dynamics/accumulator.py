"""<dJ^2> accumulated while the run goes (eq. dj2).

At every origin t0 (every `origin_every`) J(t0) and the J-bar bin of each tracked particle are
stored in a ring buffer; at every sampling time the squared displacements of all active origins
are added to sums per (bin, lag, block).  Only origins whose whole lag window fits in the run are
used, so every lag averages the same set of origins.  Origins are split into `n_blocks`
contiguous blocks for error estimates.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from .jit import njit

__all__ = ["DisplacementAccumulator"]


@njit(parallel=True)
def _accumulate_kernel(J, Jbar, slots, lags, blocks, J0, lib0, bin0, acc):
    """For each active origin a (slot slots[a], lag lags[a], block blocks[a]) add, per particle
    with bin0 >= 0: (J - J0)^2, (Jbar - Jbar0)^2, J - J0 and 1 into acc[:, bin, lag, block].

    Active origins have distinct lags, so the prange over origins never writes one cell twice;
    each cell sums its particles in index order (deterministic)."""
    n = J.size
    for a in prange(slots.size):
        sl = slots[a]
        L = lags[a]
        B = blocks[a]
        for i in range(n):
            b = bin0[sl, i]
            if b >= 0:
                j0 = J0[sl, i]
                jb0 = 0.5 * j0 if lib0[sl, i] else j0
                d = J[i] - j0
                db = Jbar[i] - jb0
                acc[0, b, L, B] += d * d
                acc[1, b, L, B] += db * db
                acc[2, b, L, B] += d
                acc[3, b, L, B] += 1.0


@njit
def _mark_seen(bins, seen):
    for i in range(bins.size):
        if bins[i] >= 0:
            seen[i, bins[i]] = 1


class DisplacementAccumulator:
    """Sums of squared action displacements per (J-bar_0 bin, lag, block of origins), eq. (dj2).

    Feed it the actions of all tracked particles at every sampling time index s = 0, 1, 2, ...
    with `add(s, J, Jbar)`.  An origin starts at every s that is a multiple of `origin_every`
    (in samples) while s + max_lag <= n_samples - 1, so every lag sees the same origins.  J(t0)
    is kept in a ring buffer of max_lag // origin_every + 1 slots (float64 J, an int16 bin and a
    librating flag per particle and slot).  Lags are 0 ... max_lag samples.
    """

    def __init__(self, n_track, jbar_edges, n_samples, max_lag, origin_every, n_blocks):
        self.edges = np.asarray(jbar_edges, dtype=float)
        self.n_bins = self.edges.size - 1
        if self.n_bins < 1 or np.any(np.diff(self.edges) <= 0):
            raise ValueError("jbar_edges must be increasing with at least 2 entries")
        if self.n_bins > 32767:
            raise ValueError("at most 32767 bins")
        self.n_track = int(n_track)
        self.n_samples = int(n_samples)
        self.max_lag = int(max_lag)
        self.origin_every = int(origin_every)
        self.n_origins = (self.n_samples - 1 - self.max_lag) // self.origin_every + 1
        if self.n_origins < 1:
            raise ValueError("the run is too short for one origin with the full lag window")
        self.n_blocks = int(n_blocks)
        if not 1 <= self.n_blocks <= self.n_origins:
            raise ValueError(
                f"n_blocks = {n_blocks} must lie in [1, number of origins = {self.n_origins}]"
            )
        self.n_slots = min(self.max_lag // self.origin_every + 1, self.n_origins)
        self.J0 = np.zeros((self.n_slots, self.n_track))
        self.lib0 = np.zeros((self.n_slots, self.n_track), dtype=np.bool_)
        self.bin0 = np.full((self.n_slots, self.n_track), -1, dtype=np.int16)
        self.acc = np.zeros((4, self.n_bins, self.max_lag + 1, self.n_blocks))
        self.seen = np.zeros((self.n_track, self.n_bins), dtype=np.uint8)
        self.origin_sample = np.arange(self.n_origins) * self.origin_every

    def block_of(self, origin):
        return origin * self.n_blocks // self.n_origins

    def bins_of(self, Jbar):
        b = np.searchsorted(self.edges, Jbar, side="right") - 1
        b[(b >= self.n_bins) | (Jbar < self.edges[0])] = -1
        b[Jbar == self.edges[-1]] = self.n_bins - 1
        return b.astype(np.int16)

    def add(self, s, J, Jbar):
        """Record the actions at sample index s (called for s = 0, 1, ... in order)."""
        if s % self.origin_every == 0 and s // self.origin_every < self.n_origins:
            o = s // self.origin_every
            sl = o % self.n_slots
            self.J0[sl] = J
            self.lib0[sl] = Jbar != J  # J-bar = J/2 on librating orbits
            self.bin0[sl] = self.bins_of(Jbar)
            _mark_seen(self.bin0[sl], self.seen)
        o_last = min(s // self.origin_every, self.n_origins - 1)
        o_first = max(0, -(-(s - self.max_lag) // self.origin_every))
        if o_last < o_first:
            return
        orig = np.arange(o_first, o_last + 1)
        lags = s - orig * self.origin_every
        keep = (lags >= 0) & (lags <= self.max_lag)
        orig, lags = orig[keep], lags[keep]
        if orig.size == 0:
            return
        slots = (orig % self.n_slots).astype(np.int64)
        blocks = np.array([self.block_of(o) for o in orig], dtype=np.int64)
        _accumulate_kernel(
            np.ascontiguousarray(J),
            np.ascontiguousarray(Jbar),
            slots,
            lags.astype(np.int64),
            blocks,
            self.J0,
            self.lib0,
            self.bin0,
            self.acc,
        )

    @property
    def n_particles_in_bin(self):
        return self.seen.sum(axis=0, dtype=np.int64)
