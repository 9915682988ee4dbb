"""Separatrix crossings in the N-body: how far the separatrix kappa = 1 is smeared at finite N.

In the frame of the magnetisation M = |M| (cos phi, sin phi) a particle's one-particle energy is
h = p^2/2 - |M| cos(theta - phi) and its orbit label (eq. hmfkappa, `orbits.kappa_from_energy`)

    kappa^2 = (h + |M|) / (2 |M|) = p^2 / (4 |M|) + sin^2((theta - phi) / 2),

kappa < 1 librating, kappa > 1 rotating.  The orbit-averaged (kinetic) theory sees the separatrix
of the mean field M0 only; at finite N, |M|(t) = M0 + dM(t) with dM ~ N^-1/2, so the separatrix of
the instantaneous field moves, and particles near it change family.  This module measures that
from sampled trajectories; it holds no dynamics (`studies/separatrix_crossings.py` runs the
N-body).  Arrays of samples have time along axis 0 and particles along axis 1; a field series
(Mx, My) has time along axis 0 only and is broadcast over the particles.

Three definitions of a crossing, each with its bias:

* `crossing_times` of a sampled kappa series (instantaneous `instantaneous_kappa`, or with a
  fixed amplitude `kappa_in_field`): changes of the side of kappa = 1, with a hysteresis band
  |kappa - 1| <= band inside which the side is held.  Sampled at interval Delta, two crossings
  closer than Delta are missed (an undercount that grows with the flicker rate), and with
  band = 0 every flicker of kappa about 1 counts (an overcount when kappa only wobbles on the
  orbit: with |M|(t), kappa_inst moves by -dM kappa/(2 |M|) at the bottom of the well, where
  p^2 = 4 |M| kappa^2, and by nothing at the X point, where p = 0).
* `family_changes`: the change of the orbit's topology, read off the unwrapped angle
  psi = theta - phi.  Between two consecutive passages through the bottom of the well
  (psi = 0 mod 2 pi, `bottom_passages`) a particle either turned back (librating: the two
  passages have opposite directions) or went over the X point (rotating: same direction).  A
  crossing is a change of that behaviour between consecutive half-orbits.  It does not depend
  on the field's amplitude or on how kappa is defined, only on resolving the passages:
  |p| Delta < pi (so that psi unwraps) and more than one sample per half-orbit.
* the fixed separatrix: `kappa_in_field` with a constant amplitude (the run's mean |M|) and the
  instantaneous phase, for comparison.

The change of the rescaled action J-bar (`orbits.rescaled_action`, continuous across kappa = 1)
at a family change (`action_jumps`) is compared with the classical separatrix-crossing jump of a
slowly modulated Hamiltonian: O(eps) with eps the relative rate of change of the parameter per
orbital time, its value depending on the crossing phase xi through ln(2 sin pi xi), which has
zero mean and rms pi/sqrt(12) over a uniform xi (Timofeev 1978; Cary, Escande & Tennyson,
Phys. Rev. A 34, 4256, 1986; Neishtadt, Sov. J. Plasma Phys. 12, 568, 1986; the correlations
between successive crossings: Cary & Skodje, Physica D 36, 287, 1989).
"""

from __future__ import annotations

import numpy as np

from ..meanfield import orbits

__all__ = [
    "field_polar",
    "kappa_in_field",
    "instantaneous_kappa",
    "rescaled_action_in_field",
    "crossing_times",
    "crossing_rate",
    "bottom_passages",
    "family_changes",
    "segment_means",
    "action_jumps",
    "kappa_spread_over_period",
    "separatrix_motion",
    "scaling_exponent",
]


def _over_particles(a, ndim):
    """A time series (time,) reshaped to broadcast against (time, particle, ...) samples."""
    a = np.asarray(a, dtype=float)
    return a.reshape(a.shape + (1,) * max(ndim - a.ndim, 0))


def field_polar(Mx, My):
    """(|M|, phi): modulus and phase of the magnetisation Mx + i My."""
    Mx = np.asarray(Mx, dtype=float)
    My = np.asarray(My, dtype=float)
    return np.hypot(Mx, My), np.arctan2(My, Mx)


def kappa_in_field(theta, p, modulus, phase):
    """kappa of (theta, p) in the pendulum field of amplitude `modulus` along angle `phase`:
    kappa^2 = p^2 / (4 modulus) + sin^2((theta - phase) / 2) (eq. hmfkappa in the field's frame).

    Written without h + modulus, which cancels at the bottom of the well; periodic in theta, so
    wrapped and unwrapped angles give the same kappa.  modulus and phase: scalars or time series
    (time,) broadcast over the particles of (time, particle) samples."""
    theta = np.asarray(theta, dtype=float)
    p = np.asarray(p, dtype=float)
    modulus = _over_particles(modulus, theta.ndim)
    phase = _over_particles(phase, theta.ndim)
    return np.sqrt(p * p / (4.0 * modulus) + np.sin(0.5 * (theta - phase)) ** 2)


def instantaneous_kappa(theta, p, Mx, My):
    """kappa of (theta, p) in the instantaneous field (Mx, My): `kappa_in_field` with
    |M|(t) and phi(t).  kappa_inst - 1 has the sign of h_inst - |M|, h_inst = p^2/2 -
    |M| cos(theta - phi) (equivalently of p^2/2 + |M| (1 - cos(theta - phi)) - 2 |M|)."""
    modulus, phase = field_polar(Mx, My)
    return kappa_in_field(theta, p, modulus, phase)


def rescaled_action_in_field(kappa, modulus):
    """J-bar of orbit kappa in a field of amplitude `modulus` (scalar or series broadcast over
    particles): J-bar(kappa; M) = sqrt(M) J-bar(kappa; 1) (`orbits.rescaled_action`; J scales
    as sqrt(M) at fixed kappa, eq. hmfaction).  With the instantaneous |M|(t) and
    kappa_inst it is the frozen-field action, the adiabatic invariant of a slowly modulated
    field."""
    kappa = np.asarray(kappa, dtype=float)
    return np.sqrt(_over_particles(modulus, kappa.ndim)) * orbits.rescaled_action(kappa, 1.0)


def crossing_times(t, kappa, band=0.0):
    """Crossings of kappa = 1 in sampled series kappa (time, particle), with hysteresis.

    Each sample has a side: +1 if kappa > 1 + band, -1 if kappa < 1 - band; inside the band the
    side of the previous sample is kept (the first samples, if inside, take the side of
    sign(kappa - 1), kappa = 1 counting as +1).  A crossing is a change of side between
    consecutive samples i - 1, i.  Its time: for band = 0, the linear interpolation of
    kappa = 1 between the two samples; for band > 0, t[i], the sample at which kappa left the
    band on the new side (a delay of the time taken to cross half the band).

    Sampling bias: crossings closer together than the sampling interval are missed in pairs.
    Returns (particle, time, direction) arrays, direction +1 for crossings outwards (kappa
    increasing through 1, libration to rotation), ordered by particle then time."""
    t = np.asarray(t, dtype=float)
    kappa = np.asarray(kappa, dtype=float)
    if kappa.ndim == 1:
        kappa = kappa[:, None]
    if band < 0:
        raise ValueError(f"band = {band!r} must be >= 0")
    x = kappa - 1.0
    side = np.where(x > band, 1, np.where(x < -band, -1, 0)).astype(np.int8)
    first = np.where(x[0] >= 0.0, 1, -1).astype(np.int8)
    side[0] = np.where(side[0] == 0, first, side[0])
    # forward fill the band's zeros with the last side outside the band
    idx = np.where(side != 0, np.arange(side.shape[0])[:, None], 0)
    np.maximum.accumulate(idx, axis=0, out=idx)
    side = np.take_along_axis(side, idx, axis=0)
    i, j = np.nonzero(side[1:] != side[:-1])
    i = i + 1
    direction = side[i, j].astype(np.int64)
    if band == 0.0:
        x0, x1 = x[i - 1, j], x[i, j]
        with np.errstate(divide="ignore", invalid="ignore"):
            frac = np.where(x1 != x0, -x0 / (x1 - x0), 0.0)
        time = t[i - 1] + np.clip(frac, 0.0, 1.0) * (t[i] - t[i - 1])
    else:
        time = t[i]
    order = np.lexsort((time, j))
    return j[order].astype(np.int64), time[order], direction[order]


def crossing_rate(counts, exposure):
    """Crossings per particle per unit time and its standard error.

    counts[r]: crossings counted in realisation r; exposure[r]: its particle-time (particles x
    duration).  The rate is sum(counts)/sum(exposure); its error comes from the spread of the
    realisations' rates about it (the ratio estimator's delta-method variance,
    sum((c_r - rate e_r)^2) / (R (R - 1) mean(e)^2)), or from Poisson counting when R = 1."""
    c = np.atleast_1d(np.asarray(counts, dtype=float))
    e = np.atleast_1d(np.asarray(exposure, dtype=float))
    rate = c.sum() / e.sum()
    R = c.size
    if R < 2:
        return float(rate), float(np.sqrt(max(c.sum(), 1.0)) / e.sum())
    var = np.sum((c - rate * e) ** 2) / (R * (R - 1) * e.mean() ** 2)
    return float(rate), float(np.sqrt(var))


def bottom_passages(t, theta, phase=0.0):
    """Passages of each particle through the bottom of the well, psi = theta - phase = 0 mod 2 pi.

    psi is wrapped to (-pi, pi] and unwrapped along time (`numpy.unwrap`), which needs
    |d psi| < pi between samples: |p| Delta < pi at sampling interval Delta (at Delta = 0.5,
    |p| < 2 pi; near the separatrix |p| <= 2 sqrt(|M|) kappa).  A passage is a change of
    floor(psi_unwrapped / 2 pi); its time is interpolated linearly to psi = 2 pi k.  Angles that
    wrap at +-pi (the X point) make no passage.  phase: scalar or series (time,).
    Returns (particle, time, direction) ordered by particle then time, direction = sign of
    d psi/dt there (the sign of p at the bottom)."""
    t = np.asarray(t, dtype=float)
    theta = np.asarray(theta, dtype=float)
    if theta.ndim == 1:
        theta = theta[:, None]
    psi = np.angle(np.exp(1j * (theta - _over_particles(phase, theta.ndim))))
    psi = np.unwrap(psi, axis=0)
    n = np.floor(psi / (2.0 * np.pi)).astype(np.int64)
    i, j = np.nonzero(n[1:] != n[:-1])
    dn = n[i + 1, j] - n[i, j]
    direction = np.sign(dn)
    level = 2.0 * np.pi * np.where(dn > 0, n[i + 1, j], n[i, j])
    y0, y1 = psi[i, j], psi[i + 1, j]
    frac = np.clip((level - y0) / (y1 - y0), 0.0, 1.0)
    time = t[i] + frac * (t[i + 1] - t[i])
    order = np.lexsort((time, j))
    return j[order].astype(np.int64), time[order], direction[order].astype(np.int64)


def family_changes(particle, time, direction):
    """Changes of orbit family read from the bottom passages (`bottom_passages`, ordered by
    particle then time).

    Half-orbit k of a particle runs from its passage k to passage k + 1 and contains one
    approach to the X point; r_k = direction_k direction_{k+1} is -1 if the particle turned
    back there (libration), +1 if it went over (rotation).  A family change is r_k != r_{k-1}:
    the particle's energy crossed the separatrix between the X approaches of half-orbits k - 1
    and k, i.e. around passage k.  Returns (particle, time, direction, k): time = time[k],
    direction +1 for libration -> rotation, -1 for rotation -> libration, k the index of that
    passage in the input arrays (half-orbit k - 1 before, half-orbit k after)."""
    particle = np.asarray(particle)
    time = np.asarray(time, dtype=float)
    d = np.asarray(direction)
    same = particle[1:] == particle[:-1]
    r = d[1:] * d[:-1]  # half-orbit k (passage k -> k + 1), valid where same[k]
    # change between half-orbits k - 1 and k: both valid (same particle throughout)
    ok = same[1:] & same[:-1] & (r[1:] != r[:-1])
    k = np.nonzero(ok)[0] + 1
    return particle[k], time[k], r[k].astype(np.int64), k


def segment_means(t, q, particle, t_start, t_end):
    """Time averages of sampled q (time, particle) over intervals [t_start, t_end] of the given
    particles: the mean of the samples with t_start <= t <= t_end (NaN where there are none).
    Samples are equally weighted (uniform sampling makes it the time average)."""
    t = np.asarray(t, dtype=float)
    q = np.asarray(q, dtype=float)
    if q.ndim == 1:
        q = q[:, None]
    Q = np.concatenate([np.zeros((1, q.shape[1])), np.cumsum(q, axis=0)])
    a = np.searchsorted(t, t_start, side="left")
    b = np.searchsorted(t, t_end, side="right")
    n = b - a
    s = Q[b, particle] - Q[a, particle]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, s / np.maximum(n, 1), np.nan)


def action_jumps(t, jbar, passages, changes):
    """Change of J-bar across each family change: the time average of jbar (time, particle)
    over the half-orbit after the change minus that over the half-orbit before it.

    passages: (particle, time, direction) of `bottom_passages`; changes: the 4-tuple of
    `family_changes`.  With k the change's passage index, the half-orbit before is
    [time[k-1], time[k]], the one after [time[k], time[k+1]]; time averages over half-orbits
    are dominated by the slow approach to the X point, where the family is decided.  A change
    whose half-orbit after ends past the last passage of the particle is dropped.
    Returns (jump, jbar_before, keep) with keep the boolean mask of the changes kept."""
    p_part, p_time, _ = passages
    c_part, _, _, k = changes
    k = np.asarray(k, dtype=np.int64)
    keep = (k + 1 < p_part.size) & (k >= 1)
    kk = np.where(keep, k, 1)
    keep &= (p_part[np.minimum(kk + 1, p_part.size - 1)] == c_part) & (p_part[kk - 1] == c_part)
    kk = kk[keep]
    part = c_part[keep]
    before = segment_means(t, jbar, part, p_time[kk - 1], p_time[kk])
    after = segment_means(t, jbar, part, p_time[kk], p_time[kk + 1])
    return after - before, before, keep


def kappa_spread_over_period(t, kappa, window, near=0.05, reference=None):
    """rms of kappa(t) minus its centred running mean over `window` (one orbital period), over
    the samples whose running mean lies within |kappa - 1| < near.

    kappa: (time, particle) on a uniform time grid.  The running mean is the mean of the
    n_w = round(window / dt) samples centred on each sample (n_w made odd; samples closer than
    n_w/2 to either end are dropped).  On an unperturbed orbit kappa is constant and the
    spread is 0; a sinusoid of period `window` and amplitude A gives A/sqrt(2); white noise of
    rms s gives s sqrt(1 - 1/n_w).  reference: an optional series of the same shape whose
    running mean selects the samples instead of kappa's own.
    Returns (spread, number of samples used)."""
    t = np.asarray(t, dtype=float)
    kappa = np.asarray(kappa, dtype=float)
    if kappa.ndim == 1:
        kappa = kappa[:, None]
    dt = float(t[1] - t[0])
    n_w = max(int(round(window / dt)), 1)
    n_w += 1 - n_w % 2
    h = n_w // 2
    if kappa.shape[0] <= n_w:
        return float("nan"), 0
    C = np.concatenate([np.zeros((1, kappa.shape[1])), np.cumsum(kappa, axis=0)])
    mean = (C[n_w:] - C[:-n_w]) / n_w  # mean[i] centred on sample i + h
    centre = kappa[h : h + mean.shape[0]]
    if reference is None:
        sel_mean = mean
    else:
        ref = np.asarray(reference, dtype=float).reshape(kappa.shape)
        R = np.concatenate([np.zeros((1, ref.shape[1])), np.cumsum(ref, axis=0)])
        sel_mean = (R[n_w:] - R[:-n_w]) / n_w
    sel = np.abs(sel_mean - 1.0) < near
    n = int(sel.sum())
    if n == 0:
        return float("nan"), 0
    d = (centre - mean)[sel]
    return float(np.sqrt(np.mean(d * d))), n


def separatrix_motion(modulus, n_particles, M0=None):
    """How far the magnetisation's fluctuations move the separatrix.

    modulus: series |M|(t); M0: the reference amplitude (default: the series' time mean).
    Returns a dict: M0; rms_dM, the rms of dM = |M| - M0; kappa_width, rms(dM) / (2 M0), the
    kappa-width it implies at kappa = 1 (at fixed (theta, p) at the bottom of the well, where
    p^2 = 4 |M|, d kappa = -dM / (2 M0); at the X point 0); sqrtN_rms_dM = sqrt(N) rms(dM)."""
    m = np.asarray(modulus, dtype=float)
    M0 = float(np.mean(m)) if M0 is None else float(M0)
    rms = float(np.sqrt(np.mean((m - M0) ** 2)))
    return {
        "M0": M0,
        "rms_dM": rms,
        "kappa_width": rms / (2.0 * M0),
        "sqrtN_rms_dM": float(np.sqrt(n_particles)) * rms,
    }


def scaling_exponent(N, y, yerr=None):
    """Fit y = a N^b by weighted least squares in (ln N, ln y), weights from the relative errors
    yerr / y.  Returns (b, b_err, a, chi2 per degree of freedom); b_err from the fit's covariance
    (not rescaled by chi2; with no errors, unit weights and the residual scatter)."""
    x = np.log(np.asarray(N, dtype=float))
    ly = np.log(np.asarray(y, dtype=float))
    if yerr is None:
        s = np.ones_like(x)
        scale = True
    else:
        s = np.asarray(yerr, dtype=float) / np.asarray(y, dtype=float)
        scale = False
    w = 1.0 / s**2
    A = np.stack([np.ones_like(x), x], axis=1)
    cov = np.linalg.inv(A.T @ (A * w[:, None]))
    coef = cov @ (A.T @ (w * ly))
    res = ly - A @ coef
    dof = max(x.size - 2, 1)
    chi2 = float(np.sum(w * res**2) / dof)
    if scale:
        cov = cov * chi2
    return float(coef[1]), float(np.sqrt(cov[1, 1])), float(np.exp(coef[0])), chi2
