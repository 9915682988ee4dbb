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
def _bin_sums(buf, col, idx, J0s):
    """sum (J - J0)^2, sum (Jbar - Jbar0)^2, sum (J - J0) over the particles idx of one bin at
    the held sample col (buf[i, col] the signed action of particle i there).

    Actions are held signed: -J on librating orbits (where J-bar = J/2), +J on rotating
    ones, so that one gathered number gives both J and J-bar; J0s the same at the origin, in
    the order of idx."""
    s2 = 0.0
    sb2 = 0.0
    s1 = 0.0
    for k in range(idx.size):
        j, jb = _unsigned(buf[idx[k], col])
        j0, jb0 = _unsigned(J0s[k])
        d = j - j0
        db = jb - jb0
        s2 += d * d
        sb2 += db * db
        s1 += d
    return s2, sb2, s1


@njit(parallel=True)
def _flush_kernel(buf, n_buf, s_first, origin_samples, slots, blocks, max_lag, idx, J0s, seg, acc):
    """Add the buffered samples s_first ... s_first + n_buf - 1 (buf[:, :n_buf]) to the sums:
    for each origin a (its first sample origin_samples[a], slot slots[a], block blocks[a]) whose
    lag window 0 ... max_lag meets the buffer, and each bin b, the sums over the origin's
    particles of bin b of (J - J0)^2, (Jbar - Jbar0)^2, J - J0 and their number go into
    acc[:, b, lag, block] at every buffered lag.  The slot holds its particles sorted by bin:
    idx[slot, seg[slot, b]: seg[slot, b + 1]], J0s in the same order.

    The parallel loop runs over bins: each writes its own acc[:, b], and adds the origins in
    increasing order, samples in increasing order, each sum over particles in slot order, so
    the result does not depend on the thread count."""
    n_bins = seg.shape[1] - 1
    for b in prange(n_bins):
        for a in range(slots.size):
            sl = slots[a]
            so = origin_samples[a]
            B = blocks[a]
            j_lo = max(0, so - s_first)
            j_hi = min(n_buf, so + max_lag + 1 - s_first)
            if j_hi <= j_lo:
                continue
            lo = seg[sl, b]
            hi = seg[sl, b + 1]
            for j in range(j_lo, j_hi):
                s2, sb2, s1 = _bin_sums(buf, j, idx[sl, lo:hi], J0s[sl, lo:hi])
                L = s_first + j - so
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
def _signed_actions(J, Jbar, order, out, buf, col):
    """out[k] = buf[k, col] = the signed action of particle order[k]: -J where J-bar = J/2 != J
    (librating), J where J-bar = J.  Returns the number of particles with J < 0 or J-bar
    neither J nor J/2 (NaN excepted: it stays NaN and falls in no bin)."""
    bad = 0
    for k in range(order.size):
        j = J[order[k]]
        jb = Jbar[order[k]]
        lib = jb != j
        v = -j if lib else j
        out[k] = v
        buf[k, col] = v
        if j < 0.0 or (lib and jb != 0.5 * j and not (math.isnan(j) and math.isnan(jb))):
            bad += 1
    return bad


class DisplacementAccumulator:
    """Sums of squared action displacements per (J-bar_0 bin, lag, block of origins), eq. (dj2).

    Feed it the actions of all tracked particles at every sampling time index s = 0, 1, 2, ...
    with `add(s, J, Jbar)`.  An origin starts at every s that is a multiple of `origin_every`
    (in samples) while s + max_lag <= n_samples - 1, so every lag sees the same origins.  J(t0)
    is kept in a ring buffer of slots (per slot, the particles that lie in a bin, sorted by bin:
    an int32 index and J as a float64 whose sign is the librating flag, 12 bytes each).  Lags
    are 0 ... max_lag samples.  J >= 0; J-bar is J or J/2.

    The actions of `buffer` consecutive samples are held (one row of `buffer` float64 per
    particle) and added to the sums in one pass (`_flush_kernel`), which reads each origin's
    slot once per pass instead of once per sample: the slots of a run at the paper's sizes
    (tens of MB) are streamed from memory `buffer` times less often.  `acc` adds any samples
    still held before it returns the sums.
    """

    def __init__(
        self, n_track, jbar_edges, n_samples, max_lag, origin_every, n_blocks, *, buffer=8
    ):
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
        self.buffer = int(buffer)
        if self.buffer < 1:
            raise ValueError(f"buffer = {buffer!r} must be a positive number of samples")
        # every origin whose lag window meets one buffer of samples needs its own slot: at most
        # (buffer - 1 + max_lag) // origin_every + 1 of them (and the slot an origin fills is
        # never one still needed by the samples held)
        self.n_slots = min(
            (self.buffer - 1 + self.max_lag) // self.origin_every + 1, self.n_origins
        )
        # per slot, the particles in a bin sorted by bin (stable: index order within a bin):
        # their indices and signed J(t0); seg[slot, b] where bin b starts
        self.idx = np.zeros((self.n_slots, self.n_track), dtype=np.int32)
        self.J0s = np.zeros((self.n_slots, self.n_track))
        self.seg = np.zeros((self.n_slots, self.n_bins + 1), dtype=np.int64)
        self._acc = np.zeros((4, self.n_bins, self.max_lag + 1, self.n_blocks))
        self.seen = np.zeros((self.n_track, self.n_bins), dtype=np.uint8)
        self.origin_sample = np.arange(self.n_origins) * self.origin_every
        # the particles are held in the order of their J-bar at the first sample: a bin's
        # particles at a later origin then lie close together in memory (diffusion is slow),
        # and the kernel reads their signed actions almost sequentially instead of scattered
        self.order = None
        self._Js = np.zeros(self.n_track)
        # the held samples s_first ... s_first + n_held - 1: buf[k, j] the signed action of
        # particle order[k] at sample s_first + j
        self._buf = np.zeros((self.n_track, self.buffer))
        self._s_first = 0
        self._n_held = 0

    def block_of(self, origin):
        return origin * self.n_blocks // self.n_origins

    def origin_at(self, s):
        """The slot of the origin that starts at sample s, or None."""
        if s % self.origin_every == 0 and s // self.origin_every < self.n_origins:
            return (s // self.origin_every) % self.n_slots
        return None

    def origins_between(self, s_first, s_last):
        """The origins (increasing, int64) whose lag window meets samples s_first ... s_last."""
        o_first = max(0, -(-(s_first - self.max_lag) // self.origin_every))
        o_last = min(s_last // self.origin_every, self.n_origins - 1)
        return np.arange(o_first, max(o_first, o_last + 1), dtype=np.int64)

    def active_origins(self, s):
        """(slots, lags, blocks) of the origins whose lag window holds sample s (int64 arrays,
        possibly empty)."""
        orig = self.origins_between(s, s)
        lags = s - orig * self.origin_every
        blocks = np.array([self.block_of(o) for o in orig], dtype=np.int64)
        return (orig % self.n_slots).astype(np.int64), lags.astype(np.int64), blocks

    def add(self, s, J, Jbar):
        """Record the actions at sample index s (called for s = 0, 1, ... in order)."""
        if self.order is None:
            self.order = np.argsort(Jbar, kind="stable")
        if self._n_held and s != self._s_first + self._n_held:
            self.flush()  # not the next sample: the held ones first
        if not self._n_held:
            self._s_first = s
        bad = _signed_actions(
            np.ascontiguousarray(J, dtype=np.float64),
            np.ascontiguousarray(Jbar, dtype=np.float64),
            self.order,
            self._Js,
            self._buf,
            self._n_held,
        )
        if bad:
            raise ValueError(
                f"sample {s}: {bad} particles with J < 0 or J-bar neither J nor J/2 (actions "
                "are >= 0; J-bar = J/2 on librating orbits)"
            )
        self._n_held += 1
        sl = self.origin_at(s)
        if sl is not None:
            _fill_slot(self._Js, self.edges, self.idx[sl], self.J0s[sl], self.seg[sl], self.seen)
        if self._n_held == self.buffer or s >= self.n_samples - 1:
            self.flush()

    def flush(self):
        """Add the held samples to the sums (done by `add` when the buffer is full or at the
        last sample, and by `acc`)."""
        n = self._n_held
        if not n:
            return
        orig = self.origins_between(self._s_first, self._s_first + n - 1)
        if orig.size:
            blocks = np.array([self.block_of(o) for o in orig], dtype=np.int64)
            _flush_kernel(
                self._buf,
                n,
                self._s_first,
                orig * self.origin_every,
                orig % self.n_slots,
                blocks,
                self.max_lag,
                self.idx,
                self.J0s,
                self.seg,
                self._acc,
            )
        self._n_held = 0

    @property
    def acc(self):
        """(4, bin, lag, block): sums of (J - J0)^2, (Jbar - Jbar0)^2, J - J0 and 1."""
        self.flush()
        return self._acc

    @property
    def n_particles_in_bin(self):
        return self.seen.sum(axis=0, dtype=np.int64)
