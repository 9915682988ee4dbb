"""Action-angle variables of the HMF pendulum h = p^2/2 - M0 cos(theta) (paper, appendix A).

Orbits are labelled by kappa = sqrt((h + M0) / (2 M0)) (eq. hmfkappa): kappa < 1 librates,
kappa > 1 rotates, kappa = 1 is the separatrix.  Complete elliptic integrals K(k), E(k) are
written with the *modulus* k as in the paper; scipy takes the parameter m = k^2, so every call
below goes through `_K_E`, which also keeps 1 - m accurate near the separatrix.

Conventions (checked against integrated orbits in tests/test_orbits.py):

* J is the action of one torus, J = (1/2pi) oint p dtheta.  A rotating J labels two tori, one
  for each direction of motion; phase-space integrals must count both
  (`phase_space_weight` returns the multiplicity).
* J-bar (`rescaled_action`: J/2 on librating orbits, J on rotating ones) is continuous across
  the separatrix; `jbar_separatrix` and `kappa_from_rescaled_action` are its only separatrix
  value and inverse in the library.
* The angle w advances as Omega t.  Librating orbits have w = 0 at theta = 0, p > 0;
  rotating orbits have w = 0 at theta = 0 and w = +theta-like for p > 0 and w = -theta-like
  for p < 0 (eq. w), so the map (w, kappa, sign) -> (theta, p) covers both directions.
"""

from __future__ import annotations

import numpy as np
from scipy import special

__all__ = [
    "kappa_from_energy",
    "energy_from_kappa",
    "action",
    "action_separatrix",
    "dJ_dkappa",
    "frequency",
    "dOmega_dkappa",
    "period",
    "nome",
    "kappa_from_action",
    "kappa_from_frequency",
    "angle_action",
    "phase_point",
    "phase_space_weight",
    "rescaled_action",
    "jbar_separatrix",
    "kappa_from_rescaled_action",
    "kappa_grid",
]


def _as_array(x):
    return np.asarray(x, dtype=float)


def _modulus_parameter(kappa):
    """Return (m, m1) = (k^2, 1 - k^2) of the elliptic modulus of each orbit.

    k = kappa on librating orbits and k = 1/kappa on rotating orbits; m1 is computed as a
    product of differences so that it keeps full relative precision near kappa = 1.
    """
    kappa = _as_array(kappa)
    lib = kappa < 1.0
    with np.errstate(divide="ignore", invalid="ignore"):
        m = np.where(lib, kappa**2, 1.0 / kappa**2)
        m1 = np.where(lib, (1.0 - kappa) * (1.0 + kappa), (kappa - 1.0) * (kappa + 1.0) / kappa**2)
    return m, m1, lib


def _K(m, m1):
    """Complete elliptic integral K of parameter m, with m1 = 1 - m given accurately: ellipkm1(m1)
    where m1 < 0.5, else ellipk(m), each evaluated only where it is used."""
    m, m1 = np.broadcast_arrays(_as_array(m), _as_array(m1))
    K = np.empty(m.shape)
    near = m1 < 0.5
    far = ~near
    K[near] = special.ellipkm1(m1[near])
    K[far] = special.ellipk(m[far])
    return K


def _K_E(m, m1):
    """Complete elliptic integrals K and E of parameter m, with m1 = 1 - m given accurately."""
    return _K(m, m1), special.ellipe(m)


def _E_minus_m1K(m, m1):
    """E(m) - (1 - m) K(m) without cancellation at small m (DLMF 19.25.1).

    With K - E = (m/3) R_D(0, m1, 1), E - m1 K = m K - (m/3) R_D(0, m1, 1) = m (K - R_D/3),
    a product of m and an O(1) difference: accurate from kappa -> 0 to the separatrix.
    """
    return m * (_K(m, m1) - special.elliprd(0.0, m1, 1.0) / 3.0)


def _ellipf(phi, m):
    """Incomplete elliptic integral F(phi | m) for |phi| <= pi/2, via Carlson's R_F.

    F = sin(phi) R_F(cos^2 phi, 1 - m sin^2 phi, 1).  scipy.special.ellipkinc (scipy 1.17.1)
    returns K(m) instead of F at isolated values of phi (e.g. phi = 1.2031855608267839,
    m = 0.25), which corrupts the angle variable; R_F has no such defect.
    """
    s = np.sin(phi)
    c = np.cos(phi)
    return s * special.elliprf(c * c, 1.0 - m * s * s, 1.0)


def kappa_from_energy(h, M0):
    """kappa = sqrt((h + M0) / (2 M0)), eq. (hmfkappa)."""
    return np.sqrt(np.maximum(_as_array(h) + M0, 0.0) / (2.0 * M0))


def energy_from_kappa(kappa, M0):
    """One-particle energy h = M0 (2 kappa^2 - 1)."""
    return M0 * (2.0 * _as_array(kappa) ** 2 - 1.0)


def action(kappa, M0):
    """Action J(kappa), eq. (hmfaction).

    Librating: (8 sqrt(M0)/pi) [E(kappa) - (1 - kappa^2) K(kappa)];
    rotating: (4 sqrt(M0)/pi) kappa E(1/kappa).  J jumps from 8 sqrt(M0)/pi to 4 sqrt(M0)/pi
    across the separatrix (one rotating torus encloses half the separatrix area).
    """
    kappa = _as_array(kappa)
    m, m1, lib = _modulus_parameter(kappa)
    s = np.sqrt(M0)
    # each branch at its own points only (the librating one at kappa = 1 would be inf - inf)
    kappa, m, m1, lib = np.broadcast_arrays(kappa, m, m1, lib)
    J = np.empty(kappa.shape)
    rot = ~lib
    J[lib] = 8.0 * s / np.pi * _E_minus_m1K(m[lib], m1[lib])
    J[rot] = 4.0 * s / np.pi * kappa[rot] * special.ellipe(m[rot])
    return J


def action_separatrix(M0, side):
    """Action at the separatrix seen from the librating (side=-1) or rotating (side=+1) side."""
    return (8.0 if side < 0 else 4.0) * np.sqrt(M0) / np.pi


def dJ_dkappa(kappa, M0):
    """dJ/dkappa, eq. (hmfjacob): (8 sqrt(M0)/pi) kappa K(kappa) or (4 sqrt(M0)/pi) K(1/kappa)."""
    kappa = _as_array(kappa)
    m, m1, lib = _modulus_parameter(kappa)
    K = _K(m, m1)
    s = np.sqrt(M0)
    return np.where(lib, 8.0 * s / np.pi * kappa * K, 4.0 * s / np.pi * K)


def frequency(kappa, M0):
    """Orbital frequency Omega = dh/dJ, eq. (hmfomega).

    pi sqrt(M0) / (2 K(kappa)) for kappa < 1 and pi sqrt(M0) kappa / K(1/kappa) for kappa > 1;
    Omega(0) = Omega_0 = sqrt(M0) and Omega -> 0 at the separatrix.
    """
    kappa = _as_array(kappa)
    m, m1, lib = _modulus_parameter(kappa)
    K = _K(m, m1)
    s = np.sqrt(M0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(lib, np.pi * s / (2.0 * K), np.pi * s * kappa / K)


def dOmega_dkappa(kappa, M0):
    """dOmega/dkappa, eq. (domdk).

    Librating: -pi sqrt(M0) [E - (1-kappa^2) K] / (2 kappa (1-kappa^2) K^2), written without the
    cancellation of the printed form at small kappa (limit -sqrt(M0) kappa / 2);
    rotating: pi sqrt(M0) kappa^2 E(1/kappa) / ((kappa^2 - 1) K(1/kappa)^2).
    """
    kappa = _as_array(kappa)
    m, m1, lib = _modulus_parameter(kappa)
    K, E = _K_E(m, m1)
    s = np.sqrt(M0)
    with np.errstate(divide="ignore", invalid="ignore"):
        # (E - m1 K)/(kappa m1) = kappa (K - R_D/3)/m1 on librating orbits
        lib_part = (
            -np.pi * s * kappa * (K - special.elliprd(0.0, m1, 1.0) / 3.0) / (2.0 * m1 * K**2)
        )
        rot_part = np.pi * s * kappa**2 * E / ((kappa**2 - 1.0) * K**2)
    return np.where(lib, lib_part, rot_part)


def period(kappa, M0):
    """Time for the angle w to advance by 2 pi: 2 pi / Omega."""
    return 2.0 * np.pi / frequency(kappa, M0)


def nome(k_m, k_m1=None):
    """Jacobi nome q = exp(-pi K(k') / K(k)) for parameter m = k^2 (m1 = 1 - m if given)."""
    m = _as_array(k_m)
    m1 = 1.0 - m if k_m1 is None else _as_array(k_m1)
    Kp = np.where(m < 0.5, special.ellipkm1(m), special.ellipk(m1))  # K(k') has parameter m1
    K = np.where(m1 < 0.5, special.ellipkm1(m1), special.ellipk(m))
    with np.errstate(divide="ignore", over="ignore"):
        return np.exp(-np.pi * Kp / K)


def _bisect(fun, target, lo, hi, iters=80):
    """iters bisections of fun(x) = target (fun elementwise, increasing) in [lo, hi].  A point
    whose midpoint rounds onto an end of its interval is final (the next steps would repeat or
    close the interval) and is not iterated further."""
    shape = np.shape(target)
    lo = np.broadcast_to(_as_array(lo), shape).flatten()
    hi = np.broadcast_to(_as_array(hi), shape).flatten()
    target = np.broadcast_to(_as_array(target), shape).ravel()
    act = np.arange(lo.size)
    for _ in range(iters):
        a, b = lo[act], hi[act]
        mid = 0.5 * (a + b)
        below = fun(mid) < target[act]
        lo[act] = np.where(below, mid, a)
        hi[act] = np.where(below, b, mid)
        act = act[(mid != a) & (mid != b)]
        if act.size == 0:
            break
    return (0.5 * (lo + hi)).reshape(shape)


def kappa_from_action(J, M0, family):
    """Invert J(kappa) on one orbit family: family='libration' (kappa < 1) or 'rotation'.

    J is single valued in kappa only within a family (it jumps at the separatrix), so the family
    must be given.  Out-of-range actions raise ValueError.
    """
    J = _as_array(J)
    s = np.sqrt(M0)
    if family == "libration":
        Jmax = 8.0 * s / np.pi
        if np.any((J < 0) | (J > Jmax)):
            raise ValueError(f"librating action J must lie in [0, {Jmax:.6g}] for M0={M0}")
        return _bisect(lambda k: action(k, M0), J, 0.0, 1.0)
    if family == "rotation":
        Jmin = 4.0 * s / np.pi
        if np.any(J < Jmin):
            raise ValueError(f"rotating action J must be >= {Jmin:.6g} for M0={M0}")
        hi = np.maximum(J / (2.0 * s) + 2.0, 2.0)  # J ~ 2 sqrt(M0) kappa at large kappa
        return _bisect(lambda k: action(np.maximum(k, 1.0 + 1e-300), M0), J, 1.0, hi)
    raise ValueError(f"family must be 'libration' or 'rotation', got {family!r}")


#: t = ln(m1/m) below which kappa rounds to 1 on either side of the separatrix (m1 < 2e-35)
_T_DEEP = -80.0


def _log_inverse_frequency(t, librating):
    """(ln F, d ln F/dt) at t = ln(m1/m) (m = k^2 the elliptic parameter, m1 = 1 - m):
    F = pi sqrt(M0)/(2 Omega) = K(m) on librating orbits, pi sqrt(M0)/Omega = sqrt(m) K(m) on
    rotating ones (eq. hmfomega), with d ln K/dt = -(E - m1 K)/(2K) = -m (K - R_D(0, m1, 1)/3)
    /(2K) and d ln(sqrt(m) K)/dt = -E/(2K).  ln F is smooth and monotonic in t, linear at both
    ends (ln F ~ ln(ln 4 - t/2) at the separatrix, t -> -inf)."""
    m = special.expit(-t)
    m1 = special.expit(t)
    K = _K(m, m1)
    if librating:
        return np.log(K), -m * (K - special.elliprd(0.0, m1, 1.0) / 3.0) / (2.0 * K)
    return np.log(np.sqrt(m) * K), -special.ellipe(m) / (2.0 * K)


_INVERSE_TABLES = {}


def _inverse_frequency_table(librating):
    """(t, ln F(t)) on _T_DEEP <= t <= 40, the start of the Newton iteration (M0-independent)."""
    if librating not in _INVERSE_TABLES:
        t = np.concatenate([np.linspace(_T_DEEP, -5.0, 200), np.linspace(-5.0, 40.0, 900)[1:]])
        _INVERSE_TABLES[librating] = (t, _log_inverse_frequency(t, librating)[0])
    return _INVERSE_TABLES[librating]


def kappa_from_frequency(omega, M0, family, kappa_max=1e6, max_iter=30):
    """Solve Omega(kappa) = omega on one family.

    Omega decreases with kappa on libration and increases on rotation.  Newton's iteration on
    ln(1/Omega) in t = ln(m1/m) (`_log_inverse_frequency`), from a tabulated inverse; a point
    whose step has not fallen below 1e-11 (relative) after max_iter steps, and the deep ones
    within ~1e-35 of the separatrix (kappa = 1 to rounding) are solved by bisection.  kappa is
    that of the root to rounding where the inverse is well conditioned; near the bottom of the
    well (omega -> Omega_0, kappa -> 0) Omega changes by less than its rounding over a range
    of kappa, and any kappa in it is returned.  Rotating kappa is capped at kappa_max.

    Returns NaN where there is no root (omega >= Omega_0 on libration, omega <= 0).
    """
    omega = _as_array(omega)
    s = np.sqrt(M0)
    if family not in ("libration", "rotation"):
        raise ValueError(f"family must be 'libration' or 'rotation', got {family!r}")
    librating = family == "libration"
    shape = omega.shape
    w = omega.ravel()
    ok = (w > 0) & (w < s) if librating else w > 0
    scale = np.pi * s / (2.0 if librating else 1.0)
    target = np.log(scale / np.where(ok, w, 1.0))
    tt, lnF = _inverse_frequency_table(librating)
    t = np.interp(-target, -lnF, tt)  # ln F decreases with t
    act = np.flatnonzero(ok & (target <= lnF[0]))
    slow = np.zeros(w.shape, dtype=bool)
    slow[ok & (target > lnF[0])] = True
    for _ in range(max_iter):
        if act.size == 0:
            break
        val, slope = _log_inverse_frequency(t[act], librating)
        step = (val - target[act]) / slope
        t[act] -= step
        act = act[~(np.abs(step) <= 1e-11 * np.maximum(1.0, np.abs(t[act])))]
    slow[act] = True
    with np.errstate(over="ignore"):
        k = np.sqrt(special.expit(-t)) if librating else np.sqrt(1.0 + np.exp(t))
    if not librating:
        # Omega ~ 2 sqrt(M0) kappa for large kappa
        hi = np.minimum(np.maximum(np.where(ok, w, s) / (2.0 * s) * 2.0 + 2.0, 2.0), kappa_max)
        k = np.minimum(k, hi)
    if np.any(slow):
        ws = w[slow]
        if librating:
            k[slow] = _bisect(lambda x: -frequency(x, M0), -ws, 0.0, 1.0)
        else:
            k[slow] = _bisect(lambda x: frequency(x, M0), ws, 1.0, hi[slow])
    return np.where(ok, k, np.nan).reshape(shape)


def angle_action(theta, p, M0):
    """Map phase-space points (theta, p) to (kappa, w, sign), eq. (w).

    theta is taken modulo 2 pi in (-pi, pi]; w is returned in [0, 2 pi).  sign is +1 or -1:
    the direction of rotation for kappa > 1 (sign of p) and +1 for librating orbits.
    """
    theta = np.angle(np.exp(1j * _as_array(theta)))  # wrap to (-pi, pi]
    theta, p = np.broadcast_arrays(theta, _as_array(p))
    # kappa^2 = (h + M0)/(2 M0) = p^2/(4 M0) + sin^2(theta/2), free of the cancellation in h + M0
    kappa = np.sqrt(p**2 / (4.0 * M0) + np.sin(0.5 * theta) ** 2)
    m, m1, lib = _modulus_parameter(kappa)
    K = _K(m, m1)
    with np.errstate(divide="ignore", invalid="ignore"):
        # librating: sin(phi) = sin(theta/2)/kappa = sn(u), cos(phi) = p/(2 sqrt(M0) kappa) = cn(u),
        # u = F(phi, kappa) = 2 K w / pi; phi from atan2 covers both signs of p without the
        # precision loss of arcsin at the turning points.  F(phi) = 2 j K + F(phi - j pi).
        # (each branch evaluated on its own orbits only: the incomplete integrals are the cost)
        w = np.empty(np.broadcast(kappa, p).shape)
        L, R = lib, ~lib
        phi = np.arctan2(np.sin(0.5 * theta[L]), p[L] / (2.0 * np.sqrt(M0)))
        j = np.round(phi / np.pi)
        F_lib = 2.0 * j * K[L] + _ellipf(phi - j * np.pi, m[L])
        w[L] = np.pi * F_lib / (2.0 * K[L])
        # rotating: w = +- pi F(theta/2, 1/kappa) / K(1/kappa)
        F_rot = _ellipf(0.5 * theta[R], m[R])
        w[R] = np.where(p[R] >= 0, 1.0, -1.0) * np.pi * F_rot / K[R]
    w = np.mod(w, 2.0 * np.pi)
    sign = np.where(lib, 1.0, np.where(p >= 0, 1.0, -1.0))
    return kappa, w, sign


def phase_point(w, kappa, M0, sign=1.0):
    """Inverse map (w, kappa, sign) -> (theta, p) through Jacobi elliptic functions.

    Librating: theta = 2 arcsin(kappa sn(u, kappa)), p = 2 sqrt(M0) kappa cn(u, kappa),
    u = 2 K w / pi.  Rotating: theta = 2 am(u, 1/kappa), p = 2 sqrt(M0) kappa dn(u, 1/kappa),
    u = K w / pi, with theta -> -theta, p -> -p for sign = -1.  theta is returned in (-pi, pi].
    """
    w = _as_array(w)
    kappa = _as_array(kappa)
    sign = _as_array(sign)
    w, kappa, sign = np.broadcast_arrays(w, kappa, sign)
    m, m1, lib = _modulus_parameter(kappa)
    K = _K(m, m1)
    s = np.sqrt(M0)
    u = np.where(lib, 2.0 * K * w / np.pi, K * w / np.pi)
    sn, cn, dn, ph = special.ellipj(u, m)
    theta_lib = 2.0 * np.arcsin(np.clip(kappa * sn, -1.0, 1.0))
    p_lib = 2.0 * s * kappa * cn
    theta_rot = sign * 2.0 * ph
    p_rot = sign * 2.0 * s * kappa * dn
    theta = np.where(lib, theta_lib, theta_rot)
    p = np.where(lib, p_lib, p_rot)
    return np.angle(np.exp(1j * theta)), p


def phase_space_weight(kappa):
    """Number of tori with a given kappa: 1 for librating, 2 for rotating (both directions)."""
    return np.where(_as_array(kappa) < 1.0, 1.0, 2.0)


def rescaled_action(kappa, M0):
    """The paper's J-bar (footnote to fig. hmfdiff): J/2 for kappa < 1, J for kappa > 1.

    J-bar is continuous across the separatrix and is the abscissa of figures 9 and 10.
    """
    kappa = _as_array(kappa)
    J = action(kappa, M0)
    return np.where(kappa < 1.0, 0.5 * J, J)


def jbar_separatrix(M0):
    """J-bar at the separatrix, 4 sqrt(M0)/pi from both sides (J-bar is continuous there)."""
    return action_separatrix(M0, +1)


def kappa_from_rescaled_action(jbar, M0, n_newton=6):
    """kappa of the orbit with rescaled action J-bar (J = 2 J-bar below the separatrix).

    A start from a tabulated inverse, then Newton steps on J(kappa) within the orbit family;
    points that have not converged to 1e-13 relative go through bisection
    (`kappa_from_action`).  J-bar <= 0 gives kappa = 0.
    """
    jbar = _as_array(jbar)
    lib = jbar < jbar_separatrix(M0)
    # table of the inverse, graded towards the separatrix
    near = 10.0 ** -np.linspace(0.5, 15.0, 300)
    kt = np.unique(
        np.concatenate(
            [
                np.linspace(0.0, 1.0, 400)[:-1],
                1.0 - near,
                1.0 + near,
                1.0
                + np.geomspace(
                    0.3, max(4.0, 2.0 * float(np.max(jbar, initial=0.0)) / np.sqrt(M0)), 400
                ),
            ]
        )
    )
    k = np.interp(jbar, rescaled_action(kt, M0), kt)
    J_target = np.where(lib, 2.0 * jbar, jbar)
    lo = np.where(lib, 0.0, 1.0 + 1e-16)
    hi = np.where(lib, 1.0 - 1e-16, np.inf)
    k = np.clip(k, lo, hi)
    for _ in range(n_newton):
        with np.errstate(divide="ignore", invalid="ignore"):
            step = (action(k, M0) - J_target) / dJ_dkappa(k, M0)
        k = np.clip(k - np.nan_to_num(step), lo, hi)
    bad = ~(np.abs(action(k, M0) - J_target) <= 1e-13 * np.maximum(J_target, 1e-300))
    bad &= J_target > 0
    for fam, sel in (("libration", bad & lib), ("rotation", bad & ~lib)):
        if np.any(sel):
            k[sel] = kappa_from_action(J_target[sel], M0, fam)
    return np.where(jbar <= 0.0, 0.0, k)


def kappa_grid(n_kappa, kappa_max, gap=1e-6):
    """A kappa grid on both sides of the separatrix, denser towards kappa = 1 and excluding it.

    Half the points lie on (0, 1 - gap], half on [1 + gap, kappa_max]; each half is uniform in
    a variable that clusters points towards the separatrix, where J and Omega vary fastest.
    """
    n_lib = n_kappa // 2
    n_rot = n_kappa - n_lib
    s = np.linspace(0.0, 1.0, n_lib)
    lib = (1.0 - gap) * np.sin(0.5 * np.pi * s)  # clusters near 1
    t = np.linspace(0.0, 1.0, n_rot)
    rot = 1.0 + gap + (kappa_max - 1.0 - gap) * t**2  # clusters near 1
    return np.concatenate([lib, rot])
