"""Power spectra of measured time series (the magnetisation of MD runs).

Convention (the one of `hmfdiff.kinetic.spectrum`): the two-sided spectrum
S(omega) = int <x(t) x(t + s)> e^{i omega s} ds of a stationary signal with zero mean, so that
int S domega / (2 pi) = <x^2>.  Estimated by Welch's method: the series is cut into segments
(half-overlapping), each is detrended by its mean, tapered by a Hann window, and
S(omega_k) = dt |sum_j w_j x_j e^{i omega_k j dt}|^2 / sum_j w_j^2 is averaged over segments
(and over realisations by the caller).  The error of the mean is the spread between segments
divided by sqrt(number of segments) (overlapping Hann segments are nearly independent).
"""

from __future__ import annotations

import numpy as np

__all__ = ["welch_spectrum"]


def welch_spectrum(x, dt, segment_length):
    """Two-sided power spectrum of x sampled every dt, at omega_k = 2 pi k / (segment_length dt)
    for k = 0 ... segment_length // 2.

    x: (..., T) array, the last axis is time (leading axes are averaged too, e.g. realisations).
    Returns (omega, S_mean, S_err, n_segments)."""
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
    power = power.reshape(-1, power.shape[-1])
    omega = 2.0 * np.pi * np.fft.rfftfreq(n, d=dt)
    m = power.shape[0]
    mean = power.mean(axis=0)
    err = power.std(axis=0, ddof=1) / np.sqrt(m) if m > 1 else np.full_like(mean, np.nan)
    return omega, mean, err, m
