"""Damped collective modes: zeros of eps_cc, eps_ss continued below the real frequency axis.

eps(omega) of `dielectric` is analytic in the upper half plane and given on the real axis as
its boundary value from above (the Landau prescription omega + i0).  A collective mode is a
zero of its analytic continuation into the lower half plane, omega_0 - i gamma (time goes as
exp(-i omega t), so gamma > 0 is a damping rate); Landau (1946) continued by deforming the
velocity contour.  Here the continuation is made numerically from the real axis alone, with
the AAA rational approximation (Nakatsukasa, Sete & Trefethen 2018, SIAM J. Sci. Comput. 40,
A1494): eps on a fine real grid is replaced by a rational function in barycentric form,

    r(z) = N(z)/D(z) = sum_j w_j f_j/(z - z_j) / sum_j w_j/(z - z_j),

whose zeros and poles are eigenvalues of (m+1) x (m+1) generalized eigenvalue problems
(section 3 of the AAA paper).  A rational function analytic continuation is only as good as
its stability: a zero is kept when it stays put as the real grid, its range and the tolerance
change, and zeros that sit on a pole (Froissart doublets, the paper's spurious pole-zero
pairs) are dropped.  The same route (a rational or Pade continuation of a response function
sampled on the real axis) is taken for the linear response of stellar systems by Weinberg
(1994, ApJ 421, 481) and Fouvry & Prunet (2022, MNRAS 511, 3393).

Why the least-damped mode matters: near marginal stability the dressed fluctuations carry
a factor 1/|eps|^2 that peaks, for a weakly damped mode at omega_0 - i gamma, as a Lorentzian of
half width gamma about omega_0; the Lenard-Balescu equation holds when the mode's lifetime
1/gamma is short against the relaxation (Weinberg 1998, MNRAS 297, 101; Lau & Binney 2019,
MNRAS 490, 478; Yamaguchi & Barre 2026, arXiv:2603.17738 for the HMF).  `least_damped_modes`
reports both the continued zero and that model-free real-axis Lorentzian.

Analytic structure to keep in mind.  The continued eps of an inhomogeneous HMF state is not
single valued: every term l has branch points where the pole omega/l leaves the range of
Omega(kappa), at omega = 0 (the separatrix, where Omega -> 0 with an essential singularity of
G ~ exp(-pi sqrt(M0)/Omega)) and at omega = l Omega_0 (the bottom of the well, a weak
(omega - l Omega_0)^|l| log singularity), and a smooth Fermi edge of f (core-halo) has poles
of f' at complex energies mu +- i pi/beta, which become poles of the continued eps at a
distance ~ pi |dOmega/dh| l / beta below the real axis.  AAA mimics the branch cuts with strings
of poles; the continuation below a real segment between branch points is what is reported.

The homogeneous HMF (M0 = 0, Maxwellian of temperature T, only l = +-1) is the test with a
known answer: eps(omega) = 1 - (1 + zeta Z(zeta))/(2 T), zeta = omega/sqrt(2 T), with the plasma
dispersion function Z(zeta) = i sqrt(pi) w(zeta) (Fried & Conte 1961), entire in omega, so its
zeros are found by Newton's method directly (`homogeneous_eps`, `homogeneous_roots`); the
state is stable for T > 1/2 (Inagaki & Konishi 1993; Chavanis, Vatteville & Bouchet 2005,
Eur. Phys. J. B 46, 61), with a purely damped zero -i gamma, gamma ~ sqrt(2T)(2T - 1)/sqrt(pi),
as T -> 1/2.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import linalg, special

from .dielectric import DielectricTensor

__all__ = [
    "AAAApproximant",
    "aaa",
    "homogeneous_eps",
    "homogeneous_roots",
    "lorentzian_peak",
    "continued_zeros",
    "fit_real_axis",
    "fermi_edge_singularities",
    "ModeReport",
    "least_damped_modes",
]


# --------------------------------------------------------------------------------------------
# AAA rational approximation
# --------------------------------------------------------------------------------------------


class AAAApproximant:
    """Rational function in barycentric form r(z) = sum w_j f_j/(z - z_j) / sum w_j/(z - z_j).

    support (z_j), values (f_j) and weights (w_j) are 1-d complex arrays of length m; r is of
    type (m-1, m-1) and interpolates r(z_j) = f_j.  `errors` is the max error on the sample
    after each step of the greedy AAA iteration.
    """

    def __init__(self, support, values, weights, errors=()):
        self.support = np.asarray(support, dtype=complex)
        self.values = np.asarray(values, dtype=complex)
        self.weights = np.asarray(weights, dtype=complex)
        self.errors = np.asarray(errors, dtype=float)

    @property
    def n_terms(self):
        return self.support.size

    def __call__(self, z):
        z = np.asarray(z, dtype=complex)
        flat = z.ravel()
        with np.errstate(divide="ignore", invalid="ignore"):
            C = 1.0 / (flat[:, None] - self.support[None, :])
            r = (C @ (self.weights * self.values)) / (C @ self.weights)
        # at a support point the barycentric formula is 0/0 (inf/inf): r = f_j there
        i, j = np.nonzero(flat[:, None] == self.support[None, :])
        r[i] = self.values[j]
        return r.reshape(z.shape)

    def _eig(self, top_row):
        """Finite eigenvalues of the arrowhead pencil (E, B) of the AAA paper, eq. (3.4):
        E = [[0, top_row], [1, diag(z_j)]], B = diag(0, 1, ..., 1)."""
        m = self.n_terms
        E = np.zeros((m + 1, m + 1), dtype=complex)
        E[0, 1:] = top_row
        E[1:, 0] = 1.0
        E[1:, 1:] = np.diag(self.support)
        B = np.eye(m + 1, dtype=complex)
        B[0, 0] = 0.0
        ev = linalg.eigvals(E, B)
        return ev[np.isfinite(ev)]

    def poles(self):
        """Zeros of the denominator D(z) = sum w_j/(z - z_j) (the poles of r)."""
        return self._eig(self.weights)

    def zeros(self):
        """Zeros of the numerator N(z) = sum w_j f_j/(z - z_j) (the zeros of r)."""
        return self._eig(self.weights * self.values)

    def residues(self, poles=None):
        """Residues N(p)/D'(p) at the poles p."""
        p = self.poles() if poles is None else np.asarray(poles, dtype=complex)
        C = 1.0 / (p[:, None] - self.support[None, :])
        N = C @ (self.weights * self.values)
        dD = -(C**2) @ self.weights
        return N / dD


def aaa(z, f, tol=1e-11, max_terms=150):
    """AAA rational approximation of samples f at points z (Nakatsukasa, Sete & Trefethen 2018).

    Greedy loop (their section 2): start from r = mean(f); at each step move the sample point
    where |f - r| is largest into the support set, then choose the weights w as the right
    singular vector of the smallest singular value of the Loewner matrix
    A_ij = (F_i - f_j)/(Z_i - z_j) over the remaining points Z_i (least squares on the
    linearised residual f D - N); stop when max |f - r| <= tol max |f| or after max_terms
    support points.  Returns an `AAAApproximant`.
    """
    Z = np.asarray(z, dtype=complex).ravel()
    F = np.asarray(f, dtype=complex).ravel()
    if Z.shape != F.shape:
        raise ValueError("z and f must have the same number of points")
    keep = np.isfinite(F)
    Z, F = Z[keep], F[keep]
    M = Z.size
    max_terms = int(min(max_terms, M - 1))
    scale = np.max(np.abs(F))
    free = np.ones(M, dtype=bool)  # sample points not (yet) in the support set
    C = np.empty((M, 0), dtype=complex)
    idx = []
    R = np.full(M, np.mean(F))
    errors = []
    w = np.ones(0, dtype=complex)
    for _ in range(max_terms):
        j = int(np.argmax(np.where(free, np.abs(F - R), -1.0)))
        idx.append(j)
        free[j] = False
        with np.errstate(divide="ignore", invalid="ignore"):
            C = np.column_stack([C, 1.0 / (Z - Z[j])])
        fj = F[idx]
        Cf = C[free]
        A = F[free, None] * Cf - Cf * fj[None, :]  # Loewner matrix
        _, _, Vh = np.linalg.svd(A, full_matrices=False)
        w = Vh[-1].conj()
        R = F.copy()
        R[free] = (Cf @ (w * fj)) / (Cf @ w)
        err = float(np.max(np.abs(F - R)))
        errors.append(err)
        if err <= tol * scale:
            break
    return AAAApproximant(Z[idx], F[idx], w, errors)


# --------------------------------------------------------------------------------------------
# The homogeneous HMF: a known answer
# --------------------------------------------------------------------------------------------


def _zeta_Z(zeta):
    """1 + zeta Z(zeta) with Z(zeta) = i sqrt(pi) w(zeta), the Landau-continued plasma
    dispersion function (Z = int e^{-t^2}/(t - zeta) dt / sqrt(pi) for Im zeta > 0)."""
    return 1.0 + zeta * 1j * np.sqrt(np.pi) * special.wofz(zeta)


def homogeneous_eps(omega, T):
    """eps(omega) of the homogeneous HMF (M0 = 0) with a Maxwellian of temperature T.

    eps = 1 + pi int f0'(p)/(p - omega) dp (|l| = 1, f0 normalised to one on [0, 2 pi) x R)
        = 1 - (1 + zeta Z(zeta))/(2 T),  zeta = omega/sqrt(2 T),
    valid for every complex omega (wofz is entire, so this is the Landau continuation below
    the real axis); eps(0) = 1 - 1/(2T) (unstable below T = 1/2) and eps -> 1 + 1/(2 omega^2) at
    large |omega| on the real axis (attractive coupling: the sign opposite to a plasma's)."""
    zeta = np.asarray(omega, dtype=complex) / np.sqrt(2.0 * T)
    return 1.0 - _zeta_Z(zeta) / (2.0 * T)


def _homogeneous_deps(omega, T):
    s = np.sqrt(2.0 * T)
    zeta = np.asarray(omega, dtype=complex) / s
    Z = 1j * np.sqrt(np.pi) * special.wofz(zeta)
    # d(1 + zeta Z)/dzeta = Z + zeta Z' with Z' = -2 (1 + zeta Z)
    return -(Z - 2.0 * zeta * (1.0 + zeta * Z)) / (2.0 * T * s)


def homogeneous_roots(T, starts=None, tol=1e-14, max_iter=100):
    """Zeros of `homogeneous_eps` in the lower half plane by Newton's method on the exact
    function, from a grid of starting points (default Re in [0, 4], Im in [-3, -0.01] in
    units of sqrt(T)); distinct converged roots with Re >= 0 sorted by damping (the mirror
    images -conj(omega) are not listed)."""
    if starts is None:
        X, Y = np.meshgrid(np.linspace(0.0, 4.0, 9), -np.geomspace(0.01, 3.0, 9))
        starts = np.sqrt(T) * (X + 1j * Y).ravel()
    z = np.asarray(starts, dtype=complex).copy()
    with np.errstate(all="ignore"):  # starts that run off to infinity give nan, dropped below
        for _ in range(max_iter):
            step = homogeneous_eps(z, T) / _homogeneous_deps(z, T)
            z = z - step
            if np.all(~np.isfinite(step) | (np.abs(step) < tol * (1.0 + np.abs(z)))):
                break
        ok = np.isfinite(z) & (z.imag < 0)
        ok[ok] = np.abs(homogeneous_eps(z[ok], T)) < 1e-12
    roots = []
    for r in z[ok]:
        r = complex(abs(r.real), r.imag)  # fold the mirror image -conj(r) onto Re >= 0
        if all(abs(r - q) > 1e-9 for q in roots):
            roots.append(r)
    return np.array(sorted(roots, key=lambda r: -r.imag))


# --------------------------------------------------------------------------------------------
# Real-axis Lorentzian (model free)
# --------------------------------------------------------------------------------------------


def lorentzian_peak(omega, amp):
    """Largest interior local maximum of amp = |1/eps(omega)|^2 on increasing real omega and its
    half width at half maximum (linear interpolation of the crossings of amp = peak/2).

    Returns (omega_peak, peak, half_width); half_width is the mean of the two sides when both
    are found on the grid, the one side found otherwise (nan if none).  For a weakly damped mode
    omega_0 - i gamma, eps ~ c (omega - omega_0 + i gamma) near omega_0 and the half width is
    gamma."""
    omega = np.asarray(omega, dtype=float)
    amp = np.asarray(amp, dtype=float)
    interior = np.flatnonzero((amp[1:-1] >= amp[:-2]) & (amp[1:-1] >= amp[2:])) + 1
    if not interior.size:
        return np.nan, np.nan, np.nan
    k = int(interior[np.argmax(amp[interior])])
    half = 0.5 * amp[k]
    sides = []
    below = np.flatnonzero(amp[:k] < half)
    if below.size:
        i = below[-1]  # amp[i] < half <= amp[i+1]
        x = omega[i] + (half - amp[i]) * (omega[i + 1] - omega[i]) / (amp[i + 1] - amp[i])
        sides.append(omega[k] - x)
    above = np.flatnonzero(amp[k:] < half)
    if above.size:
        i = k + above[0]  # amp[i-1] >= half > amp[i]
        x = omega[i - 1] + (amp[i - 1] - half) * (omega[i] - omega[i - 1]) / (amp[i - 1] - amp[i])
        sides.append(x - omega[k])
    hw = float(np.mean(sides)) if sides else np.nan
    return float(omega[k]), float(amp[k]), hw


# --------------------------------------------------------------------------------------------
# Zeros of eps continued below the real axis
# --------------------------------------------------------------------------------------------


def continued_zeros(r, froissart=1e-8, scale=1.0):
    """Zeros of the approximant r with Im <= 0 that are not Froissart doublets (a pole closer
    than froissart * scale), as a complex array sorted by damping (least damped first)."""
    zs = r.zeros()
    ps = r.poles()
    zs = zs[zs.imag <= 0.0]
    if ps.size and zs.size:
        d = np.min(np.abs(zs[:, None] - ps[None, :]), axis=1)
        zs = zs[d > froissart * scale]
    return zs[np.argsort(-zs.imag)]


def _eps_function(tensor, component):
    idx = {"cc": 0, "ss": 1}[component]

    def fun(omega):
        return tensor(omega)[idx]

    return fun


def _r_ss(fun, Om0):
    """Radius that excludes the neutral rotation of eps_ss (as in `stability`): where
    |eps_ss - eps_ss(0)| exceeds 100 |eps_ss(0)|."""
    w = np.geomspace(1e-6 * Om0, Om0, 400)
    e = fun(w)
    e0 = abs(e[0].real)
    far = np.flatnonzero(np.abs(e - e[0].real) > 100.0 * e0)
    return float(w[far[0]]) if far.size else float(w[0])


def _ellipk_complex(m):
    """K(m) for complex parameter m off the cut m > 1: pi / (2 AGM(1, sqrt(1 - m)))."""
    a = np.ones_like(np.asarray(m, dtype=complex))
    b = np.sqrt(1.0 - np.asarray(m, dtype=complex))
    for _ in range(60):
        a, b = 0.5 * (a + b), np.sqrt(a * b)
        if np.all(np.abs(a - b) <= 1e-16 * np.abs(a)):
            break
    return np.pi / (2.0 * a)


def fermi_edge_singularities(state, l):
    """Singularities of the continued eps below the real axis that a smooth Fermi edge of a
    core-halo state puts there: f'(h) = d/dh [eta/(1 + exp(beta (h - mu)))] has double poles at
    h* = mu + i pi (2k + 1)/beta, so the continued term 2 pi i G(omega/l) has double poles at
    omega = l Omega(h*) (Omega of the librating branch, continued to complex kappa^2 =
    (h* + M0)/(2 M0)), the k = 0 one nearest the real axis.  Returns the complex omega of each
    edge on the librating branch (-M0 < mu < M0), an empty array for other states.  An
    independent check of the AAA continuation: its poles must land there."""
    mus = getattr(state, "mu", None)
    betas = getattr(state, "betas", None)
    if mus is None or betas is None or getattr(state, "shape", "fermi") != "fermi":
        return np.zeros(0, dtype=complex)
    out = []
    M0 = state.M0
    for mu, beta in zip(mus, betas, strict=True):
        if -M0 < mu < M0:
            m = (mu + 1j * np.pi / beta + M0) / (2.0 * M0)
            out.append(l * np.pi * np.sqrt(M0) / (2.0 * _ellipk_complex(m)))
    return np.array(out, dtype=complex)


@dataclass
class ModeReport:
    """Least-damped zero of one component of eps continued below the real axis, and the
    real-axis Lorentzian of |1/eps|^2.

    omega0, gamma: the zero omega0 - i gamma of the base fit (nan if none credible);
    spread: max distance of the matching zero over the variant fits (grid density, range,
    tolerance), or inf if some variant has no zero within `match` of it;
    zeros: all credible zeros of the base fit (Re >= 0, least damped first), spreads: the
    largest distance of each to the nearest zero of a variant fit, stable_mask: which are
    stable (spread below `stable` times its depth and below match Omega_0, and no pole
    nearer than a tenth of its depth: the pole-zero strings that mimic a branch cut);
    nearest_pole: the pole of the base fit nearest the mode (a zero next to a pole of the
    continued eps, such as the double pole of a Fermi edge, may leave the real axis unmoved);
    peak_omega, peak_amp, half_width: the real-axis Lorentzian (`lorentzian_peak`);
    fit_error: max |eps - r| / max |eps| of the base fit on its sample; n_terms: its size;
    uhp_error: max |r - eps| at test points above the real axis, against the direct
    quadrature of `DielectricTensor.upper_half_plane` with 4 x the panels (a check of the
    continuation's other side); r_excluded: radius round omega = 0 excluded (eps_ss's neutral
    rotation), else 0.
    """

    component: str
    omega0: float
    gamma: float
    spread: float
    zeros: np.ndarray
    spreads: np.ndarray
    stable_mask: np.ndarray
    nearest_pole: complex
    peak_omega: float
    peak_amp: float
    half_width: float
    fit_error: float
    n_terms: int
    uhp_error: float
    r_excluded: float
    variants: list = field(default_factory=list)

    @property
    def quality(self):
        """gamma/omega0 (nan for a purely damped zero, omega0 = 0)."""
        return self.gamma / self.omega0 if self.omega0 > 0 else np.nan


def fit_real_axis(fun, w_lo, w_hi, n, tol=1e-10, max_terms=150):
    """AAA fit of fun (eps on real frequencies, Landau boundary value from above) sampled at n
    uniform points on [w_lo, w_hi] and mirrored with fun(-omega) = conj fun(omega), the
    reality of the response.  Returns (approximant, omega, fun(omega)) on the positive side."""
    w = np.linspace(w_lo, w_hi, n)
    e = fun(w)
    z = np.concatenate([-w[::-1], w])
    f = np.concatenate([np.conj(e[::-1]), e])
    return aaa(z, f, tol=tol, max_terms=max_terms), w, e


def least_damped_modes(
    state,
    component="cc",
    l_max=6,
    w_max=4.0,
    n_omega=1500,
    tol=1e-10,
    max_terms=150,
    depth=0.5,
    froissart=1e-8,
    match=1e-2,
    stable=0.05,
    variants=((1.37, 1.0, 1.0), (1.0, 0.75, 1.0), (1.0, 1.5, 1.0), (1.0, 1.0, 10.0)),
    tensor=None,
    **accuracy,
):
    """Least-damped zero of eps_cc (component 'cc') or eps_ss ('ss') of `state` below the real
    axis, by AAA continuation of eps sampled on the real axis, with a stability check.

    eps is sampled at n_omega uniform frequencies on (w_lo, w_max Omega_0] and mirrored to
    negative frequencies with eps(-omega) = conj eps(omega) (so that zeros with Re ~ 0 are
    continued from both sides); w_lo = 0 for eps_cc, and the neutral-rotation radius r of
    `stability` for eps_ss, whose double zero at the origin (shifted by the truncation l_max)
    is no mode: zeros with |omega| < 2 r are dropped.  Credible zeros: Im <= 0, not a Froissart
    doublet, 0 <= Re <= 0.9 w_max Omega_0 and depth -Im <= depth Omega_0 (deeper the real-axis
    data no longer constrain the continuation).

    variants: (density factor, range factor, tolerance factor) of the refits whose zeros must
    reproduce the base fit's zeros; the least-damped zero that is stable (moves by less than
    `stable` times its depth and by less than match Omega_0) is the mode.  Zeros strung along
    a branch cut out of omega = l Omega_0 move from fit to fit and are dropped.  The cost is
    five AAA fits and 5 x n_omega evaluations of eps (about 5 s on one core at the defaults).
    Returns a `ModeReport`.
    """
    if tensor is None:
        tensor = DielectricTensor(state, l_max=l_max, **accuracy)
    fun = _eps_function(tensor, component)
    Om0 = float(np.sqrt(state.M0))
    r_ex = _r_ss(fun, Om0) if component == "ss" else 0.0
    w_lo = r_ex if component == "ss" else 1e-4 * Om0

    def credible(r, wmax):
        zs = continued_zeros(r, froissart=froissart, scale=Om0)
        ok = (
            (zs.real >= 0.0)
            & (zs.real <= 0.9 * wmax)
            & (-zs.imag <= depth * Om0)
            & (np.abs(zs) >= 2.0 * r_ex)
        )
        return zs[ok]

    r, w, e = fit_real_axis(fun, w_lo, w_max * Om0, n_omega, tol, max_terms)
    zs = credible(r, w_max * Om0)
    fit_error = float(r.errors[-1] / np.max(np.abs(e)))
    # the other side: the fit against the direct quadrature above the real axis, on a rule
    # with 4 x the panels (near the axis the quadrature, not the fit, is the limit: thermal
    # u = 0.2475 at Im = 0.02 Omega_0 reads 7e-2 with the default rule, 1e-6 with this one)
    ref = DielectricTensor(
        state,
        l_max=tensor.l_max,
        n_panels=4 * tensor.n_panels,
        order=tensor.order,
        kappa_max=tensor.kappa_max,
    )
    zt = np.linspace(0.1, 0.9 * w_max, 9) * Om0 + 1j * np.array([0.02, 0.05, 0.1])[:, None] * Om0
    idx = {"cc": 0, "ss": 1}[component]
    uhp_error = float(np.max(np.abs(r(zt) - ref.upper_half_plane(zt)[idx])))

    # every credible zero of the base fit against the nearest zero of each variant fit
    spreads = np.zeros(zs.size)
    var_out = []
    for dens, rng, tolf in variants:
        rv, _, _ = fit_real_axis(
            fun, w_lo, rng * w_max * Om0, int(round(dens * n_omega)), tol * tolf, max_terms
        )
        zv = credible(rv, rng * w_max * Om0)
        if zs.size and zv.size:
            d = np.min(np.abs(zs[:, None] - zv[None, :]), axis=1)
        else:
            d = np.full(zs.size, np.inf)
        spreads = np.maximum(spreads, d)
        var_out.append(((dens, rng, tolf), zv, rv.n_terms))
    # stable: moves by less than `stable` times its own depth (and less than match Omega_0),
    # and is no link of a pole-zero string (a pole closer than a tenth of its depth)
    pz = r.poles()
    pz = pz[np.isfinite(pz) & (np.abs(pz) < 1e6 * Om0)]
    if pz.size and zs.size:
        pole_dist = np.min(np.abs(zs[:, None] - pz[None, :]), axis=1)
    else:
        pole_dist = np.full(zs.size, np.inf)
    ok = (
        (spreads <= stable * np.abs(zs.imag))
        & (spreads <= match * Om0)
        & (pole_dist > 0.1 * np.abs(zs.imag))
    )
    z0 = zs[ok][0] if np.any(ok) else complex(np.nan, np.nan)
    spread = float(spreads[ok][0]) if np.any(ok) else np.nan

    # real-axis Lorentzian, refined on a fine grid round the peak of the coarse one
    amp = 1.0 / np.abs(e) ** 2
    wp, _, hw = lorentzian_peak(w, amp)
    if np.isfinite(wp):
        span = max(5.0 * (hw if np.isfinite(hw) else 0.0), 20.0 * (w[1] - w[0]))
        wf = np.linspace(max(wp - span, w_lo), wp + span, 801)
        wp, pk, hw = lorentzian_peak(wf, 1.0 / np.abs(fun(wf)) ** 2)
    else:
        pk = np.nan
    return ModeReport(
        component=component,
        omega0=float(z0.real),
        gamma=float(-z0.imag),
        spread=spread,
        zeros=zs,
        spreads=spreads,
        stable_mask=ok,
        nearest_pole=complex(pz[np.argmin(np.abs(pz - z0))])
        if pz.size and np.isfinite(z0)
        else complex(np.nan, np.nan),
        peak_omega=wp,
        peak_amp=pk,
        half_width=hw,
        fit_error=fit_error,
        n_terms=r.n_terms,
        uhp_error=uhp_error,
        r_excluded=r_ex,
        variants=var_out,
    )
