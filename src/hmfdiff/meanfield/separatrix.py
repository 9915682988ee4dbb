"""Orbits of the HMF pendulum as functions of the signed distance to the separatrix.

eta = kappa - 1 (eta < 0 librating, eta > 0 rotating) labels an orbit without the loss of
digits that kappa, J-bar or h suffer next to the separatrix: J-bar_s - J-bar ~ |eta| ln(1/|eta|)
falls below one ulp of J-bar_s at |eta| ~ 1e-17, and h - M0 = 2 M0 eta (2 + eta) below one ulp
of M0 at the same distance, while core orbits resonate (n Omega = n' Omega') with rotating
orbits at |eta| ~ 1e-20 and below (Omega -> 0 only as 1/ln(1/|eta|)).  Everything here is
computed from eta and the complementary elliptic parameter p = 1 - m, which eta gives exactly:

    librating (k = kappa):    p = 1 - kappa^2 = |eta| (2 - |eta|)
    rotating (k = 1/kappa):   p = 1 - 1/kappa^2 = eta (2 + eta) / (1 + eta)^2

K(m) comes from `scipy.special.ellipkm1(p)` (accurate for any p > 0), E(m) - 1 from its series
in p (Byrd & Friedman 900.07) below p = 0.1, where `ellipe` returns 1 + O(p ln p) rounded:

    K = sum_n a_n p^n (L - c_n),   E - 1 = sum_{n>=1} b_n p^n (L - d_n),   L = ln(4/sqrt p),
    a_n = ((2n-1)!!/(2n)!!)^2, c_n = c_{n-1} + 2/((2n-1) 2n), b_n = a_{n-1} (2n-1)/(2n),
    d_n = c_n - 1/((2n-1) 2n).

With them (paper eqs. hmfaction, hmfomega, domdk, hmfcm, hmfsm; `orbits` and `fourier` give the
same functions of kappa away from the separatrix):

    J-bar - J-bar_s = -(4 sqrt(M0)/pi) (p K - (E - 1))           librating
                    =  (4 sqrt(M0)/pi) (eta E + (E - 1))         rotating
    <cos theta> + 1 = 2 E/K (librating), 2 kappa^2 (E/K - p) (rotating)

and the primitive of <cos theta> in J-bar from the separatrix, P = int_{J-bar_s}^{J-bar}
<cos theta> dJ-bar', from the phase-space integral of cos(theta) over the region the orbit
encloses (area 4 pi J-bar):

    4 pi P = (16 sqrt(M0)/3) (p K - 2 p E + (E - 1))                      librating
           = (16 sqrt(M0)/3) (c3 + g + c3 g)                               rotating
    with c3 = kappa^3 - 1, g = (1 + p) E - 1 - 2 p K

so that a cell's integral of <cos theta> is a difference of P (no cancellation between its
terms: each is O(p ln p) next to the separatrix).
"""

from __future__ import annotations

import numpy as np
from scipy import special

__all__ = [
    "complementary_parameter",
    "elliptic_K_Em1",
    "jbar_offset",
    "eta_from_jbar_offset",
    "djbar_deta",
    "energy_offset",
    "frequency",
    "dOmega_deta",
    "cos_average_plus_one",
    "cos_primitive",
    "fourier_parts",
]

#: below this p, E - 1 from its series (20 terms: p^20 = 1e-20 relative at most)
SERIES_P = 0.1
_N_SERIES = 22


def _series_coefficients(n_terms):
    a, b, c, d = [1.0], [0.0], [0.0], [0.0]
    for n in range(1, n_terms):
        a.append(a[-1] * ((2 * n - 1) / (2 * n)) ** 2)
        c.append(c[-1] + 2.0 / ((2 * n - 1) * (2 * n)))
        b.append(a[n - 1] * (2 * n - 1) / (2 * n))
        d.append(c[n] - 1.0 / ((2 * n - 1) * (2 * n)))
    return np.array(a), np.array(b), np.array(c), np.array(d)


_A, _B, _C, _D = _series_coefficients(_N_SERIES)
#: E - 1 = L sum_n b_n p^n - sum_n b_n d_n p^n, as polynomials in p (highest power first)
_B_POLY = _B[::-1].copy()
_BD_POLY = (_B * _D)[::-1].copy()


def _as_eta(eta):
    eta = np.asarray(eta, dtype=float)
    if np.any(eta == 0.0) or np.any(eta <= -1.0) or not np.all(np.isfinite(eta)):
        raise ValueError("eta = kappa - 1 must be finite, non-zero and > -1")
    return eta


def complementary_parameter(eta):
    """(m, p = 1 - m, librating) of the orbits eta = kappa - 1, p without cancellation."""
    eta = np.atleast_1d(_as_eta(eta))
    lib = eta < 0.0
    a = np.abs(eta)
    with np.errstate(divide="ignore", invalid="ignore"):
        p = np.where(lib, a * (2.0 - a), eta * (2.0 + eta) / (1.0 + eta) ** 2)
        kappa = 1.0 + eta
        m = np.where(lib, kappa**2, 1.0 / kappa**2)
    return m, p, lib


def elliptic_K_Em1(m, p):
    """K(m) and E(m) - 1 with p = 1 - m given accurately (series for E - 1 below p = 0.1)."""
    m = np.asarray(m, dtype=float)
    p = np.asarray(p, dtype=float)
    near = p < 0.5
    K = np.empty(np.broadcast(m, p).shape)
    K[near] = special.ellipkm1(p[near])
    K[~near] = special.ellipk(m[~near])
    em1 = np.empty_like(K)
    small = p < SERIES_P
    ps = p[small]
    L = np.log(4.0) - 0.5 * np.log(ps)
    em1[small] = L * np.polyval(_B_POLY, ps) - np.polyval(_BD_POLY, ps)
    em1[~small] = special.ellipe(m[~small]) - 1.0
    return K, em1


def _parts(eta):
    m, p, lib = complementary_parameter(eta)
    K, em1 = elliptic_K_Em1(m, p)
    return np.atleast_1d(np.asarray(eta, dtype=float)), m, p, lib, K, em1


def _shaped(value, eta):
    """value (computed on atleast_1d(eta)) in the shape of eta."""
    return np.reshape(value, np.shape(eta))


def jbar_offset(eta, M0):
    """J-bar - J-bar_s (< 0 librating, > 0 rotating), J-bar_s = 4 sqrt(M0)/pi."""
    eta0 = eta
    eta, m, p, lib, K, em1 = _parts(eta)
    c = 4.0 * np.sqrt(M0) / np.pi
    return _shaped(np.where(lib, -c * (p * K - em1), c * (eta * (1.0 + em1) + em1)), eta0)


def djbar_deta(eta, M0):
    """dJ-bar/dkappa: (4 sqrt(M0)/pi) kappa K (librating), (4 sqrt(M0)/pi) K(1/kappa) (rotating),
    eq. (hmfjacob) with J-bar = J/2 below the separatrix."""
    eta0 = eta
    eta, m, p, lib, K, em1 = _parts(eta)
    c = 4.0 * np.sqrt(M0) / np.pi
    return _shaped(np.where(lib, c * (1.0 + eta) * K, c * K), eta0)


def _jbar_offset_and_slope(eta, M0):
    """`jbar_offset` and `djbar_deta` of the same orbits (their elliptic integrals once)."""
    eta, m, p, lib, K, em1 = _parts(eta)
    c = 4.0 * np.sqrt(M0) / np.pi
    x = np.where(lib, -c * (p * K - em1), c * (eta * (1.0 + em1) + em1))
    return x, np.where(lib, c * (1.0 + eta) * K, c * K)


def eta_from_jbar_offset(x, M0, guess=None, iterations=64):
    """The orbit eta with J-bar - J-bar_s = x (x != 0, x > -J-bar_s).

    Newton steps in ln|eta| on the side of the sign of x, from `guess` (eta of a nearby
    orbit, used where it lies on that side) or from the leading asymptotic
    |x| = (4 sqrt(M0)/pi) |eta| (L + 1/2); points that have not converged to 1e-15 relative
    (the librating bottom kappa -> 0, where dJ-bar/dkappa vanishes) go through bisection in
    ln|eta|.  Relative accuracy of eta ~ 1e-14 for any |x| down to ~1e-300."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 0:
        g = None if guess is None else np.atleast_1d(guess)
        return eta_from_jbar_offset(x[None], M0, g, iterations)[0]
    if np.any(x == 0.0) or not np.all(np.isfinite(x)):
        raise ValueError("the J-bar offset from the separatrix must be finite and non-zero")
    c = 4.0 * np.sqrt(M0) / np.pi
    if np.any(x <= -c):
        raise ValueError(f"J-bar offset {x.min()} is at or below -J-bar_s = {-c} (J-bar <= 0)")
    lib = x < 0.0
    sgn = np.where(lib, -1.0, 1.0)
    target = np.abs(x)
    # start: the asymptotic |x| = c |eta| (ln(4/sqrt(2|eta|)) + 1/2), or the guess
    a = np.minimum(target / c, 0.5)
    for _ in range(3):
        a = np.minimum(target / (c * (np.log(4.0) - 0.5 * np.log(2.0 * a) + 0.5)), 0.5)
    if guess is not None:
        g = np.broadcast_to(np.asarray(guess, dtype=float), x.shape)
        use = (np.sign(g) == sgn) & (np.abs(g) < 1.0) & (g != 0.0)
        a = np.where(use, np.abs(g), a)
    t = np.log(a)
    done = np.zeros(x.shape, dtype=bool)
    F = np.zeros(x.shape)
    act = np.arange(x.size)  # the points still iterated
    for _ in range(12):
        e = sgn[act] * np.exp(t[act])
        e = np.where(lib[act], np.maximum(e, -1.0 + 1e-16), e)
        xe, dx = _jbar_offset_and_slope(e, M0)
        with np.errstate(divide="ignore", invalid="ignore"):
            F[act] = Fa = np.log(np.abs(xe)) - np.log(target[act])
            dF = np.abs(e) * dx / np.abs(xe)
            step = np.where(dF > 1e-3, Fa / dF, 0.0)
        step = np.clip(np.nan_to_num(step), -5.0, 5.0)
        t[act] = np.minimum(t[act] - step, np.where(lib[act], 0.0, np.inf))
        conv = np.abs(Fa) < 4e-15  # the rounding floor of ln|x| (measured ~7e-15 at worst)
        done[act] = conv
        act = act[~conv]
        if act.size == 0:
            break
    eta = sgn * np.exp(t)
    bad = ~(done | (np.abs(F) < 1e-13))
    if np.any(bad):
        eta[bad] = _bisect_offset(x[bad], M0, iterations)
    return eta


def _bisect_offset(x, M0, iterations):
    lib = x < 0.0
    sgn = np.where(lib, -1.0, 1.0)
    lo = np.full(x.shape, np.log(1e-305))
    hi = np.where(lib, 0.0, np.log(np.maximum(2.0 * np.abs(x) / np.sqrt(M0) + 2.0, 2.0)))
    target = np.abs(x)
    if x.size > 8:
        for _ in range(iterations):
            mid = 0.5 * (lo + hi)
            e = sgn * np.exp(mid)
            e = np.where(lib, np.maximum(e, -1.0 + 1e-16), e)
            below = np.abs(jbar_offset(e, M0)) < target
            lo = np.where(below, mid, lo)
            hi = np.where(below, hi, mid)
        return _polish_offset(x, M0, sgn, lib, 0.5 * (lo + hi))
    # a few points (the usual case): the midpoints of 6 bisections for every outcome are
    # evaluated at once, then followed down (the same steps, 63 points per call)
    n, rows = x.size, np.arange(x.size)[:, None]
    done = 0
    while done < iterations:
        k = min(6, iterations - done)
        L, H, mids = lo[:, None], hi[:, None], []
        for _ in range(k):  # level l: 2^l intervals, child 2i not below the midpoint, 2i+1 below
            mid = 0.5 * (L + H)
            mids.append(mid)
            L = np.stack([L, mid], axis=2).reshape(n, -1)
            H = np.stack([mid, H], axis=2).reshape(n, -1)
        mid = np.concatenate(mids, axis=1)
        e = sgn[:, None] * np.exp(mid)
        e = np.where(lib[:, None], np.maximum(e, -1.0 + 1e-16), e)
        below = np.abs(jbar_offset(e, M0)) < target[:, None]
        node = np.zeros((n, 1), dtype=int)
        for level in range(k):
            node = 2 * node + below[rows, 2**level - 1 + node]
        lo, hi = L[rows, node][:, 0], H[rows, node][:, 0]
        done += k
    return _polish_offset(x, M0, sgn, lib, 0.5 * (lo + hi))


def _polish_offset(x, M0, sgn, lib, t):
    """eta from the bisection's ln|eta| = t."""
    eta = sgn * np.exp(t)
    eta = np.where(lib, np.maximum(eta, -1.0 + 1e-16), eta)
    for _ in range(3):  # Newton in eta polishes the last digits (dx/deta = dJ-bar/dkappa > 0)
        xe, dx = _jbar_offset_and_slope(eta, M0)
        step = (xe - x) / dx
        new = eta - step
        ok = (np.sign(new) == sgn) & (new > -1.0) & np.isfinite(new)
        eta = np.where(ok, new, eta)
    return eta


def energy_offset(eta, M0):
    """h - M0 = 2 M0 (kappa^2 - 1) = 2 M0 eta (2 + eta)."""
    eta = np.asarray(eta, dtype=float)
    return 2.0 * M0 * eta * (2.0 + eta)


def frequency(eta, M0):
    """Omega, eq. (hmfomega): pi sqrt(M0)/(2 K) librating, pi sqrt(M0) kappa/K rotating."""
    eta0 = eta
    eta, m, p, lib, K, em1 = _parts(eta)
    s = np.sqrt(M0)
    return _shaped(np.where(lib, np.pi * s / (2.0 * K), np.pi * s * (1.0 + eta) / K), eta0)


def dOmega_deta(eta, M0):
    """dOmega/dkappa, eq. (domdk), from p: librating -pi sqrt(M0) kappa (K - R_D(0, p, 1)/3) /
    (2 p K^2), rotating pi sqrt(M0) kappa^2 E / ((kappa^2 - 1) K^2)."""
    eta0 = eta
    eta, m, p, lib, K, em1 = _parts(eta)
    s = np.sqrt(M0)
    kappa = 1.0 + eta
    rd = special.elliprd(0.0, p, 1.0)
    lib_part = -np.pi * s * kappa * (K - rd / 3.0) / (2.0 * p * K**2)
    rot_part = np.pi * s * kappa**2 * (1.0 + em1) / (eta * (2.0 + eta) * K**2)
    return _shaped(np.where(lib, lib_part, rot_part), eta0)


def cos_average_plus_one(eta):
    """<cos theta> + 1 on the orbit (c_0 + 1): 2 E/K librating, 2 kappa^2 (E/K - p) rotating."""
    eta0 = eta
    eta, m, p, lib, K, em1 = _parts(eta)
    E = 1.0 + em1
    return _shaped(np.where(lib, 2.0 * E / K, 2.0 * (1.0 + eta) ** 2 * (E / K - p)), eta0)


def cos_primitive(eta, M0):
    """P = int_{J-bar_s}^{J-bar} <cos theta> dJ-bar' (module docstring), signed like the offset."""
    eta0 = eta
    eta, m, p, lib, K, em1 = _parts(eta)
    c3 = eta * (3.0 + eta * (3.0 + eta))
    g = em1 + p * (1.0 + em1) - 2.0 * p * K
    lib_part = p * K - 2.0 * p * (1.0 + em1) + em1
    rot_part = c3 + g + c3 * g
    return _shaped(
        16.0 * np.sqrt(M0) / 3.0 * np.where(lib, lib_part, rot_part) / (4.0 * np.pi), eta0
    )


def fourier_parts(eta):
    """(kappa, m, p, librating, K, E) of the orbits eta, the arguments of the Fourier
    coefficients' formulas (`fourier.cos_coefficient_eta`)."""
    shape = np.shape(eta)
    eta, m, p, lib, K, em1 = _parts(eta)
    return tuple(np.reshape(v, shape) for v in (1.0 + eta, m, p, lib, K, 1.0 + em1))
