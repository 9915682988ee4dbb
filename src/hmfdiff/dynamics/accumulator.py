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

from .elementary import _FM
from .jit import njit

__all__ = ["DisplacementAccumulator"]


@njit(fastmath=_FM)
def _bin_sums(J, Jbar, idx, J0, lib0):
    """sum (J - J0)^2, sum (Jbar - Jbar0)^2, sum (J - J0) over the particles idx of one bin
    (J0, lib0 their values at the origin, in the same order; Jbar0 = J0/2 if librating)."""
    s2 = 0.0
    sb2 = 0.0
    s1 = 0.0
    for k in range(idx.size):
        i = idx[k]
        j0 = J0[k]
        d = J[i] - j0
        db = Jbar[i] - j0 * (1.0 - 0.5 * lib0[k])
        s2 += d * d
        sb2 += db * db
        s1 += d
    return s2, sb2, s1


@njit(parallel=True)
def _accumulate_kernel(J, Jbar, slots, lags, blocks, idx, J0, lib0, seg, acc):
    """For each active origin a (slot slots[a], lag lags[a], block blocks[a]) add, per bin b,
    the sums over its particles of (J - J0)^2, (Jbar - Jbar0)^2, J - J0 and their number into
    acc[:, b, lag, block].  The slot holds its particles sorted by bin: idx[slot, seg[slot, b]:
    seg[slot, b + 1]] are the indices of bin b, J0 and lib0 in the same order, so each bin is one
    contiguous pass with its sums in registers (no scatter into acc per particle).

    Active origins have distinct lags, so the prange over origins never writes one cell twice;
    every sum runs in a fixed order (deterministic for any thread count)."""
    n_bins = seg.shape[1] - 1
    for a in prange(slots.size):
        sl = slots[a]
        L = lags[a]
        B = blocks[a]
        for b in range(n_bins):
            lo = seg[sl, b]
            hi = seg[sl, b + 1]
            s2, sb2, s1 = _bin_sums(J, Jbar, idx[sl, lo:hi], J0[sl, lo:hi], lib0[sl, lo:hi])
            acc[0, b, L, B] += s2
            acc[1, b, L, B] += sb2
            acc[2, b, L, B] += s1
            acc[3, b, L, B] += hi - lo


@njit
def _bin_of(x, edges):
    """The bin b with edges[b] <= x < edges[b + 1] (the last bin includes its upper edge), or
    -1 outside [edges[0], edges[-1]] or for NaN."""
    n_bins = edges.size - 1
    if not (edges[0] <= x <= edges[n_bins]):
        return -1
    lo = 0
    hi = n_bins  # edges[lo] <= x < edges[hi], or x == edges[n_bins]
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if edges[mid] <= x:
            lo = mid
        else:
            hi = mid
    return lo


@njit
def _fill_slot(J, Jbar, edges, idx, J0, lib0, seg, seen):
    """One origin's slot: the particles that lie in a bin, sorted by bin by a counting sort
    (stable: index order within a bin), with their J and librating flag (J-bar = J/2); seg[b]
    where bin b starts.  Marks seen[i, b] for each."""
    n_bins = edges.size - 1
    bins = np.empty(J.size, dtype=np.int64)
    count = np.zeros(n_bins + 1, dtype=np.int64)
    for i in range(J.size):
        b = _bin_of(Jbar[i], edges)
        bins[i] = b
        if b >= 0:
            count[b + 1] += 1
            seen[i, b] = 1
    seg[0] = 0
    for b in range(n_bins):
        seg[b + 1] = seg[b] + count[b + 1]
    fill = seg[:n_bins].copy()
    for i in range(J.size):
        b = bins[i]
        if b >= 0:
            k = fill[b]
            idx[k] = i
            J0[k] = J[i]
            lib0[k] = Jbar[i] != J[i]
            fill[b] = k + 1


@njit
def _permute(x, order, out):
    for i in range(order.size):
        out[i] = x[order[i]]


class DisplacementAccumulator:
    """Sums of squared action displacements per (J-bar_0 bin, lag, block of origins), eq. (dj2).

    Feed it the actions of all tracked particles at every sampling time index s = 0, 1, 2, ...
    with `add(s, J, Jbar)`.  An origin starts at every s that is a multiple of `origin_every`
    (in samples) while s + max_lag <= n_samples - 1, so every lag sees the same origins.  J(t0)
    is kept in a ring buffer of max_lag // origin_every + 1 slots (per slot, the particles that
    lie in a bin, sorted by bin: an int32 index, float64 J and a librating flag each).
    Lags are 0 ... max_lag samples.
    """

    def __init__(self, n_track, jbar_edges, n_samples, max_lag, origin_every, n_blocks):
        self.edges = np.asarray(jbar_edges, dtype=float)
        self.n_bins = self.edges.size - 1
        if self.n_bins < 1 or np.any(np.diff(self.edges) <= 0):
            raise ValueError("jbar_edges must be increasing with at least 2 entries")
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
        # per slot, the particles in a bin sorted by bin (stable: index order within a bin):
        # their indices, J(t0), librating flag; seg[slot, b] where bin b starts
        self.idx = np.zeros((self.n_slots, self.n_track), dtype=np.int32)
        self.J0 = np.zeros((self.n_slots, self.n_track))
        self.lib0 = np.zeros((self.n_slots, self.n_track), dtype=np.uint8)
        self.seg = np.zeros((self.n_slots, self.n_bins + 1), dtype=np.int64)
        self.acc = np.zeros((4, self.n_bins, self.max_lag + 1, self.n_blocks))
        self.seen = np.zeros((self.n_track, self.n_bins), dtype=np.uint8)
        self.origin_sample = np.arange(self.n_origins) * self.origin_every
        # the particles are held in the order of their J-bar at the first sample: a bin's
        # particles at a later origin then lie close together in memory (diffusion is slow),
        # and the kernel reads J, J-bar almost sequentially instead of scattered
        self.order = None
        self._J = np.zeros(self.n_track)
        self._Jbar = np.zeros(self.n_track)

    def block_of(self, origin):
        return origin * self.n_blocks // self.n_origins

    def origin_at(self, s):
        """The slot of the origin that starts at sample s, or None."""
        if s % self.origin_every == 0 and s // self.origin_every < self.n_origins:
            return (s // self.origin_every) % self.n_slots
        return None

    def active_origins(self, s):
        """(slots, lags, blocks) of the origins whose lag window holds sample s (int64 arrays,
        possibly empty)."""
        o_last = min(s // self.origin_every, self.n_origins - 1)
        o_first = max(0, -(-(s - self.max_lag) // self.origin_every))
        orig = np.arange(o_first, max(o_first, o_last + 1))
        lags = s - orig * self.origin_every
        keep = (lags >= 0) & (lags <= self.max_lag)
        orig, lags = orig[keep], lags[keep]
        blocks = np.array([self.block_of(o) for o in orig], dtype=np.int64)
        return (orig % self.n_slots).astype(np.int64), lags.astype(np.int64), blocks

    def add(self, s, J, Jbar):
        """Record the actions at sample index s (called for s = 0, 1, ... in order)."""
        if self.order is None:
            self.order = np.argsort(Jbar, kind="stable")
        _permute(np.ascontiguousarray(J, dtype=np.float64), self.order, self._J)
        _permute(np.ascontiguousarray(Jbar, dtype=np.float64), self.order, self._Jbar)
        J, Jbar = self._J, self._Jbar
        sl = self.origin_at(s)
        if sl is not None:
            _fill_slot(
                J,
                Jbar,
                self.edges,
                self.idx[sl],
                self.J0[sl],
                self.lib0[sl],
                self.seg[sl],
                self.seen,
            )
        slots, lags, blocks = self.active_origins(s)
        if slots.size:
            _accumulate_kernel(
                J, Jbar, slots, lags, blocks, self.idx, self.J0, self.lib0, self.seg, self.acc
            )

    @property
    def n_particles_in_bin(self):
        return self.seen.sum(axis=0, dtype=np.int64)
