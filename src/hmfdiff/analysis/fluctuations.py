"""Power spectra of measured time series (the magnetisation of MD runs).

Convention (the one of `hmfdiff.kinetic.spectrum`): the two-sided spectrum
S(omega) = int <x(t) x(t + s)> e^{i omega s} ds of a stationary signal with zero mean, so that
int S domega / (2 pi) = <x^2>.  Estimated by Welch's method: the series is cut into segments
(half-overlapping), each is detrended by its mean, tapered by a Hann window, and
S(omega_k) = dt |sum_j w_j x_j e^{i omega_k j dt}|^2 / sum_j w_j^2 is averaged over segments
and over the realisations (leading axes of the input).

Error of the mean.  With R >= 2 independent realisations it is the spread of the R
per-realisation means divided by sqrt(R): honest whatever the correlations between segments of
one realisation.  (The spread between segments divided by sqrt(number of segments) assumes
independent segments: half-overlapping Hann segments of a Gaussian signal inflate the variance of
their mean only by 1 + 2 c^2 (K - 1)/K, c = sum_j w_j w_{j+n/2} / sum_j w_j^2 = 0.168, a factor
1.03 on the error; but the bath of an MD run is one finite set of orbits whose spectral lines
recur in every segment, so its segments are not independent.)
With one realisation the segment spread is used with that correction.
"""

from __future__ import annotations

import numpy as np

__all__ = ["welch_spectrum"]


def welch_spectrum(x, dt, segment_length):
    """Two-sided power spectrum of x sampled every dt, at omega_k = 2 pi k / (segment_length dt)
    for k = 0 ... segment_length // 2.

    x: (..., T) array, the last axis is time (leading axes are averaged too, e.g. realisations).
    Returns (omega, S_mean, S_err, n_segments): n_segments counts all segments of all
    realisations; S_err is the error of S_mean (module docstring)."""
    x = np.asarray(x, dtype=float)
    n = int(segment_length)
    T = x.shape[-1]
    if not 8 <= n <= T:
        raise ValueError(f"segment_length = {segment_length} must lie in [8, length = {T}]")
    if not dt > 0:
        raise ValueError(f"dt = {dt} must be > 0")
    starts = np.arange(0, T - n + 1, n // 2)
    win = np.hanning(n + 2)[1:-1]  # no zero end points
    norm = dt / np.sum(win**2)
    segs = np.stack([x[..., s : s + n] for s in starts], axis=-2)  # (..., n_seg, n)
    segs = segs - segs.mean(axis=-1, keepdims=True)
    power = norm * np.abs(np.fft.rfft(segs * win, axis=-1)) ** 2
    per_real = power.reshape(-1, len(starts), power.shape[-1])  # (R, K, n_freq)
    omega = 2.0 * np.pi * np.fft.rfftfreq(n, d=dt)
    R, K = per_real.shape[:2]
    mean = per_real.mean(axis=(0, 1))
    if R >= 2:
        err = per_real.mean(axis=1).std(axis=0, ddof=1) / np.sqrt(R)
    elif K >= 2:
        half = n // 2
        c = np.sum(win[:-half] * win[half:]) / np.sum(win**2)
        inflation = 1.0 + 2.0 * c**2 * (K - 1) / K
        err = per_real[0].std(axis=0, ddof=1) * np.sqrt(inflation / K)
    else:
        err = np.full_like(mean, np.nan)
    return omega, mean, err, R * K
