"""<dJ^2> accumulated while the run goes (eq. dj2).

At every origin t0 (every `origin_every`) J(t0) and the J-bar bin of each tracked particle are
stored in a ring buffer; at every sampling time the squared displacements of all active origins
are added to sums per (bin, lag, block).  Only origins whose whole lag window fits in the run are
used, so every lag averages the same set of origins.  Origins are split into `n_blocks`
contiguous blocks for error estimates.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from .elementary import _FM
from .jit import njit

__all__ = ["DisplacementAccumulator"]


@njit(fastmath=_FM)
def _unsigned(js):
    """(J, J-bar) of a signed action: js = -J on librating orbits (J-bar = J/2), +J else."""
    j = abs(js)
    return j, 0.5 * j if js < 0.0 else j


@njit(fastmath=_FM)
def _bin_sums(Js, idx, J0s):
    """sum (J - J0)^2, sum (Jbar - Jbar0)^2, sum (J - J0) over the particles idx of one bin.

    Actions are held signed: Js = -J on librating orbits (where J-bar = J/2), +J on rotating
    ones, so that one gathered number gives both J and J-bar; J0s the same at the origin, in
    the order of idx."""
    s2 = 0.0
    sb2 = 0.0
    s1 = 0.0
    for k in range(idx.size):
        j, jb = _unsigned(Js[idx[k]])
        j0, jb0 = _unsigned(J0s[k])
        d = j - j0
        db = jb - jb0
        s2 += d * d
        sb2 += db * db
        s1 += d
    return s2, sb2, s1


@njit(parallel=True)
def _accumulate_kernel(Js, slots, lags, blocks, idx, J0s, seg, acc):
    """For each active origin a (slot slots[a], lag lags[a], block blocks[a]) add, per bin b,
    the sums over its particles of (J - J0)^2, (Jbar - Jbar0)^2, J - J0 and their number into
    acc[:, b, lag, block].  The slot holds its particles sorted by bin: idx[slot, seg[slot, b]:
    seg[slot, b + 1]] are the indices of bin b, J0s in the same order, so each bin is one
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
            s2, sb2, s1 = _bin_sums(Js, idx[sl, lo:hi], J0s[sl, lo:hi])
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
def _fill_slot(Js, edges, idx, J0s, seg, seen):
    """One origin's slot: the particles that lie in a bin of J-bar, sorted by bin by a counting
    sort (stable: index order within a bin), with their signed action Js; seg[b] where bin b
    starts.  Marks seen[i, b] for each."""
    n_bins = edges.size - 1
    bins = np.empty(Js.size, dtype=np.int64)
    count = np.zeros(n_bins + 1, dtype=np.int64)
    for i in range(Js.size):
        b = _bin_of(_unsigned(Js[i])[1], edges)
        bins[i] = b
        if b >= 0:
            count[b + 1] += 1
            seen[i, b] = 1
    seg[0] = 0
    for b in range(n_bins):
        seg[b + 1] = seg[b] + count[b + 1]
    fill = seg[:n_bins].copy()
    for i in range(Js.size):
        b = bins[i]
        if b >= 0:
            k = fill[b]
            idx[k] = i
            J0s[k] = Js[i]
            fill[b] = k + 1


@njit
def _signed_actions(J, Jbar, order, out):
    """out[k] = the signed action of particle order[k]: -J where J-bar = J/2 != J (librating),
    J where J-bar = J.  Returns the number of particles with J < 0 or J-bar neither J nor J/2
    (NaN excepted: it stays NaN and falls in no bin)."""
    bad = 0
    for k in range(order.size):
        j = J[order[k]]
        jb = Jbar[order[k]]
        lib = jb != j
        out[k] = -j if lib else j
        if j < 0.0 or (lib and jb != 0.5 * j and not (math.isnan(j) and math.isnan(jb))):
            bad += 1
    return bad


class DisplacementAccumulator:
    """Sums of squared action displacements per (J-bar_0 bin, lag, block of origins), eq. (dj2).

    Feed it the actions of all tracked particles at every sampling time index s = 0, 1, 2, ...
    with `add(s, J, Jbar)`.  An origin starts at every s that is a multiple of `origin_every`
    (in samples) while s + max_lag <= n_samples - 1, so every lag sees the same origins.  J(t0)
    is kept in a ring buffer of max_lag // origin_every + 1 slots (per slot, the particles that
    lie in a bin, sorted by bin: an int32 index and J as a float64 whose sign is the librating
    flag, 12 bytes each).  Lags are 0 ... max_lag samples.  J >= 0; J-bar is J or J/2.
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
        # their indices and signed J(t0); seg[slot, b] where bin b starts
        self.idx = np.zeros((self.n_slots, self.n_track), dtype=np.int32)
        self.J0s = np.zeros((self.n_slots, self.n_track))
        self.seg = np.zeros((self.n_slots, self.n_bins + 1), dtype=np.int64)
        self.acc = np.zeros((4, self.n_bins, self.max_lag + 1, self.n_blocks))
        self.seen = np.zeros((self.n_track, self.n_bins), dtype=np.uint8)
        self.origin_sample = np.arange(self.n_origins) * self.origin_every
        # the particles are held in the order of their J-bar at the first sample: a bin's
        # particles at a later origin then lie close together in memory (diffusion is slow),
        # and the kernel reads their signed actions almost sequentially instead of scattered
        self.order = None
        self._Js = np.zeros(self.n_track)

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
        bad = _signed_actions(
            np.ascontiguousarray(J, dtype=np.float64),
            np.ascontiguousarray(Jbar, dtype=np.float64),
            self.order,
            self._Js,
        )
        if bad:
            raise ValueError(
                f"sample {s}: {bad} particles with J < 0 or J-bar neither J nor J/2 (actions "
                "are >= 0; J-bar = J/2 on librating orbits)"
            )
        sl = self.origin_at(s)
        if sl is not None:
            _fill_slot(self._Js, self.edges, self.idx[sl], self.J0s[sl], self.seg[sl], self.seen)
        slots, lags, blocks = self.active_origins(s)
        if slots.size:
            _accumulate_kernel(
                self._Js, slots, lags, blocks, self.idx, self.J0s, self.seg, self.acc
            )

    @property
    def n_particles_in_bin(self):
        return self.seen.sum(axis=0, dtype=np.int64)
