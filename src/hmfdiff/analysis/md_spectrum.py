"""The measured fluctuation spectrum of the magnetisation in MD, against the kinetic theory's
bath spectrum: bare for MD(bath), dressed by the dielectric tensor for MD(full) (issue 15).

From the magnetisation stored every m_every (`Mx_fine`, `My_fine` of the md files), the
two-sided spectra N S_x(omega), N S_y(omega) are estimated by Welch's method
(`fluctuations.welch_spectrum`: segments of duration max_lag, the resolution of the <dJ^2> fit,
half overlapping, Hann taper), averaged over segments and seeds, and multiplied by N (N_b for
MD(bath)); x is along the magnetisation's direction averaged over one segment, y across it.
The theory is `kinetic.spectrum.SpectrumTable`: N S of the bare bath (a sum over
orbits of c_n'^2, sigma_n'^2 times f and the density of states at omega = n' Omega) and the
dressed one, divided by |eps_cc(omega)|^2 and |eps_ss(omega)|^2.  The Welch estimate is the
true spectrum convolved with the spectral window of the taper,

    <S_welch(omega)> = int S(omega') K(omega - omega') domega'/(2 pi),
    K(nu) = dt |sum_j w_j e^{i nu j dt}|^2 / sum_j w_j^2        (int K dnu/2pi = 1),

so the theory is also given convolved with K (`smoothed`), for a like-for-like comparison where
the spectrum has structure narrower than the resolution 4 pi / segment (band edges, modes).
"""

from __future__ import annotations

import functools

import numpy as np

from ..kinetic.dielectric import DielectricTensor
from ..kinetic.spectrum import SpectrumTable
from ..meanfield import orbits
from .fluctuations import welch_spectrum

__all__ = [
    "measured_spectra",
    "seed_spectra",
    "resonance_bands",
    "window_kernel",
    "smoothed",
    "agreement",
    "spectrum_comparison",
]

COMPONENTS = {"x": "cc", "y": "ss"}


def measured_spectra(datasets):
    """Welch N S_x and N S_y of the magnetisation of MD datasets (one per seed).

    Returns (omega, {"x": (NS, NS_err), "y": ...}, n_segments, segment_length, dt, N)."""
    if not datasets:
        raise ValueError("no MD datasets")
    ref = datasets[0]
    dt = float(ref.attrs["m_every"])
    N = float(ref.attrs["N"])
    seg = int(round(float(ref.attrs["max_lag"]) / dt))
    n_t = min(ds.sizes["time_fine"] for ds in datasets)
    seg = min(seg, n_t)
    out = {}
    frames = [
        _slow_frame(ds["Mx_fine"].values[:n_t], ds["My_fine"].values[:n_t], seg) for ds in datasets
    ]
    for i, comp in enumerate(COMPONENTS):
        x = np.stack([f[i] for f in frames])
        omega, S, err, n_seg = welch_spectrum(x, dt, seg)
        out[comp] = (N * S, N * err)
    return omega, out, n_seg, seg, dt, N


def seed_spectra(datasets):
    """Welch N S_x and N S_y of each MD dataset (realisation) separately, for resampling
    (jackknife) over realisations: their mean over realisations is `measured_spectra`'s.

    Returns (omega, {"x": (R, n_freq), "y": (R, n_freq)}, segment_length, dt, N)."""
    if not datasets:
        raise ValueError("no MD datasets")
    ref = datasets[0]
    dt = float(ref.attrs["m_every"])
    N = float(ref.attrs["N"])
    n_t = min(ds.sizes["time_fine"] for ds in datasets)
    seg = min(int(round(float(ref.attrs["max_lag"]) / dt)), n_t)
    out = {c: [] for c in COMPONENTS}
    for ds in datasets:
        frame = _slow_frame(ds["Mx_fine"].values[:n_t], ds["My_fine"].values[:n_t], seg)
        for i, comp in enumerate(COMPONENTS):
            omega, S, _, _ = welch_spectrum(frame[i][None, :], dt, seg)
            out[comp].append(N * S)
    return omega, {c: np.stack(v) for c, v in out.items()}, seg, dt, N


def resonance_bands(kappa_lo, kappa_hi, M0, n_max, pad=0.0):
    """{n: (omega_lo, omega_hi)}: the frequencies n Omega(kappa) swept by the orbits with kappa in
    [kappa_lo, kappa_hi] (one orbit family), widened by `pad` on each side (e.g. the Welch
    resolution), for n = 1 ... n_max."""
    om = orbits.frequency(np.array([float(kappa_lo), float(kappa_hi)]), float(M0))
    lo, hi = float(np.min(om)), float(np.max(om))
    return {n: (n * lo - pad, n * hi + pad) for n in range(1, int(n_max) + 1)}


def _slow_frame(mx, my, seg):
    """(M_parallel, M_perpendicular): the magnetisation in the frame of its direction averaged
    over `seg` samples (a running mean of the unwrapped angle).  In MD(full) the direction
    wanders without bound (the neutral rotational mode, eps_ss(0) = 0), which in the fixed
    frame would mix the two components; only frequencies below the resolution 2 pi / segment
    are removed from the angle.  For MD(bath) (static field on x) the angle stays ~1e-3 and
    this is the fixed frame to that order."""
    phi = np.unwrap(np.arctan2(my, mx))
    k = np.ones(seg) / seg
    pad = np.concatenate([np.full(seg // 2, phi[0]), phi, np.full(seg - 1 - seg // 2, phi[-1])])
    slow = np.convolve(pad, k, mode="valid")
    c, s = np.cos(slow), np.sin(slow)
    return mx * c + my * s, my * c - mx * s


def window_kernel(nu, segment_length, dt):
    """K(nu) of the module docstring for the Hann taper of `welch_spectrum`."""
    win = np.hanning(segment_length + 2)[1:-1]
    j = np.arange(segment_length)
    nu = np.asarray(nu, dtype=float)
    amp = np.exp(1j * np.multiply.outer(nu, j * dt)) @ win
    return dt * np.abs(amp) ** 2 / np.sum(win**2)


def smoothed(spectrum, omega, segment_length, dt, oversample=8, lobes=12):
    """The spectrum (a callable of omega) convolved with the window's K, at each omega: the
    expectation of the Welch estimate.  The integral runs over +-`lobes` resolution widths
    (2 pi / segment) with `oversample` points per width (the far side lobes of the Hann
    window fall as nu^-6)."""
    nu, K = _smoothing_weights(int(segment_length), float(dt), int(oversample), int(lobes))
    omega = np.asarray(omega, dtype=float)
    return np.array([spectrum(w - nu) @ K for w in omega])


@functools.lru_cache(maxsize=16)
def _smoothing_weights(segment_length, dt, oversample, lobes):
    """(nu, K dnu / 2 pi) of `smoothed`, computed once per window (read-only arrays)."""
    width = 2.0 * np.pi / (segment_length * dt)
    d = width / oversample
    nu = np.arange(-lobes * width, lobes * width + d / 2, d)
    K = window_kernel(nu, segment_length, dt) * d / (2.0 * np.pi)
    nu.flags.writeable = K.flags.writeable = False
    return nu, K


AGREEMENT_NOTE = (
    "median_ratio, frac_z_lt_2, n_compared: measured N S against the window-smoothed theory over "
    "the Welch frequencies with 0.05 < omega < 4 where the smoothed theory exceeds 1e-3 of its "
    "maximum there (below, the spectrum is at the numerical floor of the bath synthesis); "
    "z = (measured - theory) / error. The per-seed estimates are chi-square-like (skewed), so z "
    "is a left-skewed Student t: with 20 seeds about 92-93 % of bins, not 95 %, lie within 2."
)


def agreement(omega, measured, error, theory, *, band=(0.05, 4.0), floor=1e-3):
    """{'median_ratio', 'frac_z_lt_2', 'n_compared'} of a measured spectrum against the theory
    (see AGREEMENT_NOTE for the selection of frequencies)."""
    omega, measured, error, theory = (
        np.asarray(a, dtype=float) for a in (omega, measured, error, theory)
    )
    inband = (omega > band[0]) & (omega < band[1])
    if not np.any(inband & np.isfinite(theory)):
        return {"median_ratio": np.nan, "frac_z_lt_2": np.nan, "n_compared": 0}
    peak = np.nanmax(np.where(inband, theory, np.nan))
    sel = inband & (theory > floor * peak) & (error > 0) & np.isfinite(measured)
    if not np.any(sel):
        return {"median_ratio": np.nan, "frac_z_lt_2": np.nan, "n_compared": 0}
    z = (measured[sel] - theory[sel]) / error[sel]
    return {
        "median_ratio": float(np.median(measured[sel] / theory[sel])),
        "frac_z_lt_2": float(np.mean(np.abs(z) < 2.0)),
        "n_compared": int(sel.sum()),
    }


def spectrum_comparison(state, bath, full, *, n_max=6, l_max=6):
    """Measured and theoretical N S_x, N S_y of MD(bath) (bare theory) and MD(full) (dressed).

    bath, full: lists of md datasets (seeds) of one case.  Returns a dict of arrays: per
    dynamics d and component c, `NS{c}_{d}` and `_err` at the Welch frequencies `omega_{d}`,
    the theory `NS{c}_{d}_theory` (bare for bath, dressed for full) there and smoothed by the
    window (`_smoothed`), and the theory on a fine grid `omega_theory` for the curves."""
    tables = {
        "bath": SpectrumTable(state, n_max=n_max),
        "full": SpectrumTable(state, n_max=n_max, eps=DielectricTensor(state, l_max=l_max)),
    }
    out = {"attrs": {"n_max": int(n_max), "l_max": int(l_max), "M0": float(state.M0)}}
    om_max = 0.0
    for dyn, dss in (("bath", bath), ("full", full)):
        omega, meas, n_seg, seg, dt, N = measured_spectra(dss)
        out[f"omega_{dyn}"] = omega
        tab = tables[dyn]
        for c, comp in COMPONENTS.items():
            out[f"NS{c}_{dyn}"], out[f"NS{c}_{dyn}_err"] = meas[c]
            out[f"NS{c}_{dyn}_theory"] = tab(omega, comp)
            out[f"NS{c}_{dyn}_smoothed"] = smoothed(
                lambda w, t=tab, k=comp: t(w, k), omega, seg, dt
            )
            stats = agreement(omega, *meas[c], out[f"NS{c}_{dyn}_smoothed"])
            out["attrs"].update({f"{k}_{c}_{dyn}": v for k, v in stats.items()})
        out["attrs"].update(
            {
                f"N_{dyn}": N,
                f"n_seeds_{dyn}": len(dss),
                f"n_segments_{dyn}": int(n_seg),
                f"segment_time_{dyn}": seg * dt,
                f"m_every_{dyn}": dt,
            }
        )
        om_max = max(om_max, float(omega.max()))
    out["attrs"]["agreement_note"] = AGREEMENT_NOTE
    grid = np.linspace(0.0, om_max, 4001)
    out["omega_theory"] = grid
    for dyn in ("bath", "full"):
        for c, comp in COMPONENTS.items():
            out[f"NS{c}_{dyn}_theory_fine"] = tables[dyn](grid, comp)
    return out
