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

`quasilinear_dj2` is the time-domain counterpart for diffusion: the <dJ^2>(t) that unperturbed
orbits would accumulate in a measured field (quasi-linear response), with the finite-time
kernel of an MD fit rather than a spectral window.
"""

from __future__ import annotations

import numpy as np

__all__ = ["welch_spectrum", "quasilinear_dj2"]


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


def quasilinear_dj2(dmx, dmy, dt, kappa, M0, lags, origins, n_max=8):
    """<dJ^2>(lag) of orbits kappa on their unperturbed tori (angle w0 + Omega s, uniform w0)
    driven by the measured field fluctuations dmx(s), dmy(s) sampled every dt: the quasi-linear
    response to that field, realisation by realisation, with no spectral estimate in between.

    dJ/dt = sum_n i n (c_n dMx + s_n dMy) e^{i n (w0 + Omega s)} (s_n = -i sigma_n;
    `kinetic.spectrum`), so averaged over w0

        <dJ^2>(t0, t) = sum_{n != 0} n^2 |A_n|^2 = 2 sum_{n=1}^{n_max} n^2 |A_n|^2,
        A_n = int_{t0}^{t0 + t} (c_n dMx + s_n dMy) e^{i n Omega s} ds   (A_{-n} = conj(A_n)),

    the integral a left Riemann sum over the samples.  Averaged over the time origins `origins`
    (sample indices) for each lag in `lags` (in samples).  Its expectation tends to
    2 N D t with N D of `kinetic.spectrum.diffusion_from_spectrum`, and equals
    `kinetic.spectrum.windowed_diffusion`'s finite-time <dJ^2> for the field's true spectrum.

    dmx, dmy: (..., T) arrays (leading axes, e.g. realisations, are kept); kappa: orbits (K,).
    Returns (..., K, len(lags)), in the units of J^2 (for the field of N particles it is O(1/N)).
    """
    from ..meanfield import orbits
    from ..meanfield.fourier import cos_coefficient, sin_coefficient_imag

    dmx = np.asarray(dmx, dtype=float)
    dmy = np.asarray(dmy, dtype=float)
    if dmx.shape != dmy.shape:
        raise ValueError(f"dmx {dmx.shape} and dmy {dmy.shape} must have one shape")
    kappa = np.atleast_1d(np.asarray(kappa, dtype=float))
    lags = np.asarray(lags, dtype=int)
    origins = np.asarray(origins, dtype=int)
    T = dmx.shape[-1]
    if origins.min() < 0 or origins.max() + lags.max() > T:
        raise ValueError("an origin plus a lag runs past the end of the series")
    t = np.arange(T) * float(dt)
    Om = orbits.frequency(kappa, float(M0))
    out = np.zeros(dmx.shape[:-1] + (kappa.size, lags.size))
    for n in range(1, int(n_max) + 1):
        c = cos_coefficient(n, kappa)
        s = -1j * sin_coefficient_imag(n, kappa)
        phase = np.exp(1j * n * np.multiply.outer(Om, t))  # (K, T)
        f = (c[:, None] * phase) * dmx[..., None, :] + (s[:, None] * phase) * dmy[..., None, :]
        Z = np.concatenate([np.zeros(f.shape[:-1] + (1,)), np.cumsum(f, axis=-1)], axis=-1)
        A = Z[..., origins[:, None] + lags[None, :]] - Z[..., origins[:, None]]  # (..., K, O, L)
        out += 2.0 * n**2 * np.mean(np.abs(A) ** 2, axis=-2) * float(dt) ** 2
    return out
