"""The bath's fluctuation spectrum and the finite-time <dJ^2>(t) it drives.

A bath of N independent orbits (uniform angles) has magnetisation fluctuations
dM_x = (1/N) sum_i [cos theta_i(t) - <cos theta>], and likewise dM_y, with the two-sided power
spectra (S(omega) = int <dM(t) dM(t + s)> e^{i omega s} ds, even in omega)

    N S_x(omega) = 4 pi^2 sum_{n' >= 1} sum_{kappa': n' Omega(kappa') = |omega|}
                   W(kappa') J'(kappa') f(kappa') c_n'(kappa')^2 / |n' Omega'(kappa')|,

and N S_y the same with sigma_n'^2 (s_n' = -i sigma_n') in place of c_n'^2; W = 2 counts
both directions of rotation, J' = dJ/dkappa.  Collective effects dress them:
S -> S / |eps(omega)|^2 (eps_cc for x, eps_ss for y).  A test orbit kappa feels
dJ/dt = dM_x sum_n i n c_n e^{i n w} + dM_y sum_n i n s_n e^{i n w}, so

    <dJ^2>(t) = 2 sum_{n >= 1} n^2 int domega/(2 pi) [c_n^2 S_x(omega) + sigma_n^2 S_y(omega)]
                                         2 (1 - cos((n Omega - omega) t)) / (n Omega - omega)^2

(both signs of omega: the non-resonant omega < 0 part stays bounded).  As t -> infinity the
kernel tends to 2 pi t delta(n Omega - omega) and <dJ^2> -> 2 D t with

    N D(kappa) = sum_{n >= 1} n^2 [c_n(kappa)^2 N S_x(n Omega) + sigma_n(kappa)^2 N S_y(n Omega)],

which is eq. hmfCEdif written through the spectrum: `diffusion_from_spectrum` gives it by a
route (tabulated spectrum, no resonance roots kappa*(kappa)) independent of
`diffusion.resonance_table`.  `windowed_diffusion` fits the finite-time <dJ^2>(t) over the
lags of an MD fit window exactly as the MD fit does (least squares with a free intercept), so
that theory and MD are compared like for like.
"""

from __future__ import annotations

import numpy as np

from ..meanfield import orbits
from ..meanfield.fourier import cos_coefficient, sin_coefficient_imag

__all__ = [
    "bath_spectrum",
    "dressed_spectrum",
    "SpectrumTable",
    "diffusion_from_spectrum",
    "bin_diffusion_from_spectrum",
    "slope_kernel",
    "windowed_diffusion",
]

_COMPONENTS = ("cc", "ss")


def bath_spectrum(state, omega, n_max=6, component="cc"):
    """N S(omega) of the bare bath, eq. above (two-sided, even in omega); harmonics |n'| <= n_max.

    component 'cc' is dM_x (c_n'), 'ss' is dM_y (sigma_n')."""
    if component not in _COMPONENTS:
        raise ValueError(f"component = {component!r}: must be 'cc' or 'ss'")
    M0 = state.M0
    w = np.abs(np.atleast_1d(np.asarray(omega, dtype=float)))
    out = np.zeros(w.shape)
    coef = cos_coefficient if component == "cc" else sin_coefficient_imag
    for n1 in range(1, int(n_max) + 1):
        x = w / n1
        for family in ("libration", "rotation"):
            k = orbits.kappa_from_frequency(np.where(x > 0, x, -1.0), M0, family)
            ok = np.isfinite(k) & (np.abs(k - 1.0) > 1e-12)
            kk = np.where(ok, k, 0.5)
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                dens = (
                    orbits.phase_space_weight(kk)
                    * orbits.dJ_dkappa(kk, M0)
                    * state.f(kk)
                    * coef(n1, kk) ** 2
                    / np.abs(n1 * orbits.dOmega_dkappa(kk, M0))
                )
            out += np.where(ok & np.isfinite(dens), dens, 0.0)
    return 4.0 * np.pi**2 * out


def dressed_spectrum(state, omega, eps, n_max=6, component="cc"):
    """N S(omega) of the dressed bath, the bare one divided by |eps|^2 of the same component,
    evaluated at omega directly (`SpectrumTable` with eps tabulates it).  eps: callable omega ->
    (eps_cc, eps_ss), such as a `DielectricTensor`."""
    bare = bath_spectrum(state, omega, n_max, component)  # checks the component
    e = eps(np.atleast_1d(np.asarray(omega, dtype=float)))[_COMPONENTS.index(component)]
    return bare / np.abs(e) ** 2


class SpectrumTable:
    """N S_x and N S_y tabulated for fast interpolation, bare or dressed (eps).

    Each (n', branch) contribution to eq. of `bath_spectrum` is computed on a kappa' grid,
    where n' Omega(kappa') is monotonic (no root finding), and interpolated onto a frequency
    grid that is uniform with spacing d_omega and refined near 0 and near the band edges
    n' Omega_0 of the librating branch.  Beyond omega_max the spectrum is taken as zero:
    choose omega_max beyond n_max Omega(kappa) of the populated orbits (default: from the
    state's kappa_max).  eps: callable omega -> (eps_cc, eps_ss) (a `DielectricTensor`), or
    None for the bare bath.
    """

    def __init__(self, state, *, n_max=6, omega_max=None, d_omega=2e-3, n_kappa=20000, eps=None):
        M0 = state.M0
        Om0 = np.sqrt(M0)
        kmax = float(state.kappa_max)
        if omega_max is None:
            omega_max = 1.05 * n_max * float(orbits.frequency(kmax, M0))
        self.n_max = int(n_max)
        self.dressed = eps is not None
        edges = Om0 * np.arange(1, n_max + 1)
        # relative offsets from each band edge n' Omega_0 (S varies fastest just below it)
        near = np.geomspace(1e-7, 0.05, 200)
        grid = [np.arange(0.0, omega_max + d_omega, d_omega), np.geomspace(1e-9, d_omega, 60)]
        grid += [e * (1.0 - near) for e in edges] + [e * (1.0 + near) for e in edges]
        w = np.unique(np.concatenate(grid))
        self.omega = w[(w >= 0.0) & (w <= omega_max)]
        # kappa' grids on both branches, graded towards the separatrix and kappa' = 0
        g = 1.0 - np.geomspace(1e-12, 1.0, n_kappa)[::-1]
        lib = np.unique(np.concatenate([g, 1.0 - np.geomspace(1e-12, 1e-1, n_kappa // 4)]))
        lib = lib[(lib > 0) & (lib < 1)]
        rot = 1.0 + np.geomspace(1e-12, kmax - 1.0, n_kappa)
        self.S = {}
        for comp in _COMPONENTS:
            coef = cos_coefficient if comp == "cc" else sin_coefficient_imag
            total = np.zeros(self.omega.size)
            for kk in (lib, rot):
                with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                    base = (
                        orbits.phase_space_weight(kk)
                        * orbits.dJ_dkappa(kk, M0)
                        * state.f(kk)
                        / np.abs(orbits.dOmega_dkappa(kk, M0))
                    )
                    Om = orbits.frequency(kk, M0)
                for n1 in range(1, self.n_max + 1):
                    dens = base * coef(n1, kk) ** 2 / n1
                    ok = np.isfinite(dens)
                    x, y = n1 * Om[ok], dens[ok]
                    order = np.argsort(x)
                    x, y = x[order], y[order]
                    total += np.interp(self.omega, x, y, left=0.0, right=0.0)
            self.S[comp] = 4.0 * np.pi**2 * total
        if eps is not None:
            e_cc, e_ss = eps(self.omega)
            self.S["cc"] = self.S["cc"] / np.abs(e_cc) ** 2
            self.S["ss"] = self.S["ss"] / np.abs(e_ss) ** 2

    def __call__(self, omega, component):
        """N S(omega), linear interpolation in |omega|; 0 beyond the grid."""
        w = np.abs(np.asarray(omega, dtype=float))
        return np.interp(w, self.omega, self.S[component], right=0.0)


def _test_coefficients(kappa, n_max):
    n = np.arange(1, n_max + 1)[:, None]
    c2 = cos_coefficient(n, kappa[None, :]) ** 2
    s2 = sin_coefficient_imag(n, kappa[None, :]) ** 2
    return n, c2, s2


def diffusion_from_spectrum(table, kappa, M0, per_harmonic=False):
    """N D(kappa) = sum_{n=1}^{n_max} n^2 [c_n^2 N S_x(n Omega) + sigma_n^2 N S_y(n Omega)].

    per_harmonic: return the terms, shape (n_max, 2, kappa): harmonic n = 1 ... n_max, then
    the S_x (c_n) and S_y (sigma_n) parts, instead of their sum."""
    kappa = np.atleast_1d(np.asarray(kappa, dtype=float))
    n, c2, s2 = _test_coefficients(kappa, table.n_max)
    w0 = n * orbits.frequency(kappa, M0)[None, :]
    terms = (n**2)[:, None] * np.stack([c2 * table(w0, "cc"), s2 * table(w0, "ss")], axis=1)
    return terms if per_harmonic else terms.sum(axis=(0, 1))


def bin_diffusion_from_spectrum(table, jbar_lo, jbar_hi, M0, density=None, n_sub=41,
                                per_harmonic=False, lags=None):  # fmt: skip
    """N D from the spectrum (`diffusion_from_spectrum`) averaged over a bin of the rescaled
    action J-bar in [jbar_lo, jbar_hi], as an MD bin averages dJ^2 over its particles:
    weighted by `density` (a callable of J-bar, e.g. `analysis.fits.tracked_density`; uniform
    in J-bar if None) at n_sub points (the midpoints of n_sub + 1 equal parts).
    per_harmonic: the weighted terms, (n_max, 2).  lags: the fit window's lags, for the N D
    that a fit of the finite-time <dJ^2> over them gives (`windowed_diffusion`; a number)."""
    jb = np.linspace(float(jbar_lo), float(jbar_hi), int(n_sub) + 2)[1:-1]
    kappa = orbits.kappa_from_rescaled_action(jb, M0)
    w = np.ones_like(jb) if density is None else np.asarray(density(jb), dtype=float)
    if not (np.all(w >= 0) and w.sum() > 0):
        raise ValueError("density must be >= 0 and not all zero over the bin")
    w = w / w.sum()
    if lags is not None:
        if per_harmonic:
            raise ValueError("per_harmonic is not available with lags")
        return float(windowed_diffusion(table, kappa, M0, lags) @ w)
    terms = diffusion_from_spectrum(table, kappa, M0, per_harmonic=True) @ w
    return terms if per_harmonic else float(terms.sum())


def slope_kernel(lags, x):
    """L(x) such that the least-squares slope (free intercept) of <dJ^2>(t_i) over the lags t_i
    is int domega/(2 pi) S(omega) L(n Omega - omega) per unit n^2 c_n^2: the finite-time kernel
    2 (1 - cos(x t)) / x^2 combined with the slope weights (t_i - mean t) / sum (t_j - mean t)^2.
    At x = 0 the kernel is t^2."""
    t = np.asarray(lags, dtype=float)
    wts = (t - t.mean()) / np.sum((t - t.mean()) ** 2)
    x = np.asarray(x, dtype=float)
    out = np.empty_like(x)
    small = np.abs(x) * t.max() < 1e-3
    xs = x[~small][:, None]
    out[~small] = (2.0 * (1.0 - np.cos(xs * t[None, :])) / xs**2) @ wts
    # series 2(1 - cos y)/x^2 = t^2 (1 - y^2/12 + ...) with y = x t
    out[small] = (t**2 - x[small, None] ** 2 * t**4 / 12.0) @ wts
    return out


def windowed_diffusion(table, kappa, M0, lags, *, x_max=2.0, dx=None, chunk=20000):
    """N D fitted over `lags` like the MD fit: half the least-squares slope of the finite-time
    <dJ^2>(t) (eq. in the module docstring), for each kappa.  Tends to `diffusion_from_spectrum`
    as the window moves to late times.

    The frequency offset x = n Omega - omega runs over |x| <= x_max with spacing dx (default
    0.05 / max lag, resolving the kernel's oscillation period 2 pi / t); beyond x_max the
    slope kernel is ~ cos(x t) / x^2 with weights summing to zero and averages out."""
    kappa = np.atleast_1d(np.asarray(kappa, dtype=float))
    lags = np.asarray(lags, dtype=float)
    dx = 0.05 / float(lags.max()) if dx is None else dx
    x = np.arange(-x_max, x_max + dx / 2, dx)
    L = np.concatenate([slope_kernel(lags, x[i : i + chunk]) for i in range(0, x.size, chunk)])
    L *= dx / (2.0 * np.pi)
    n, c2, s2 = _test_coefficients(kappa, table.n_max)
    w0 = n * orbits.frequency(kappa, M0)[None, :]
    slope = np.zeros(kappa.size)
    for i in range(table.n_max):
        for k in range(kappa.size):
            om = w0[i, k] - x
            Sx = table(om, "cc") @ L
            Sy = table(om, "ss") @ L
            slope[k] += 2.0 * (i + 1) ** 2 * (c2[i, k] * Sx + s2[i, k] * Sy)
    return 0.5 * slope
