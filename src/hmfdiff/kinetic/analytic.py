"""Closed forms of the paper (section "Analytical results for highly magnetized states", app. C).

Every function returns N*D (the 1/N of the paper factored out).  Conventions of the library:
<dJ^2> = 2 D dt, f normalised to int f dtheta dp = 1, W = phase_space_weight (2 on rotating
orbits), s_n = -i sigma_n, and the general (numerical) formulas

    N D_dif(kappa) = 2 pi^2 sum_{n,n'} sum_{kappa*} n^2 W dJ/dkappa f / |n' Omega'|  (at kappa*)
                     x [ c_n(kappa)^2 c_n'(kappa*)^2 / |eps_cc(n Omega)|^2
                         + sigma_n(kappa)^2 sigma_n'(kappa*)^2 / |eps_ss(n Omega)|^2 ],
    N D_pol(kappa) = the same with n^2 W dJ/dkappa f -> n n' W df/dkappa,
    eps_cc(omega)  = 1 + 2 pi sum_{l != 0} int dkappa W c_l^2 f' / (Omega - omega/l),
                     omega -> omega + i0 (Im part + i pi W c_l^2 f' / |Omega'| at each pole),

with kappa* the roots of n Omega(kappa) = n' Omega(kappa*) (eqs. hmfCEdif, hmfCEpol, hmfD,
hmfepscc, hmfepsss).  eps_ss is the same with sigma_l^2.

Corrections to the printed formulas (each verified in tests/test_analytic.py):

* eq. (coeff-analytic-ncoll), D_pol: the factor (kappa^2 - 1) must read (1 - kappa^2); as printed
  D_pol has the sign of df/dkappa reversed and the thermal identity D_pol = -beta Omega D_dif fails.
* eq. (coeff-analytic-ncoll) is the n = n' = +-1, kappa* = kappa term of the general formula
  alone (c_{+-1} = 0 on librating orbits, so only the sine part contributes).  The |n|,|n'| <= 2
  librating sum adds the n = n' = +-2 cosine term: D_full = D_sech4 (1 + 2 c_2^4 / sigma_1^4),
  independent of f and M0 (1.0011 at kappa = 0.3, 1.168 at 0.8, 1.516 at 0.9, 2.18 at 0.95,
  5.70 at 0.99): the sech^4 form is 14 % low at kappa = 0.8 and 34 % low at 0.9.
* eq. (hmffch2k): kappa_i = sqrt((mu_i/M0 + 1)/2), not sqrt(mu_i/M0 + 1).
* eq. (hmfepscc/ss-ch): with df/dkappa = -sum_i w_i delta(kappa - kappa_i) the general eps gives
  eps(omega) = 1 - 2 pi sum_{l >= 1} sum_i W_i w_i c_l(kappa_i)^2 [1/(Omega_i - omega/l)
  + 1/(Omega_i + omega/l)]: the sum runs over l >= 1 *or* over all l != 0 without the
  (omega -> -omega) term; the printed form (all l plus omega -> -omega) counts every term twice.
  g_l(kappa_i) stands for -w_i c_l(kappa_i)^2 (the delta function integrated out).
* app. C, eq. (eps_cc_ap): the real part is right (b = beta, w = omega); the imaginary part has
  the wrong sign for the library's (and the paper's own "+ i pi g/|Omega'|") convention,
  and its Theta(sqrt(M0) - omega/2) Theta(omega) must be Theta(2 sqrt(M0) - omega)
  Theta(omega - 3 sqrt(M0)/2): the definition integrates kappa over [0, 1] only, so the pole
  kappa_p^2 = 4 - 2 omega/sqrt(M0) must lie in [0, 1].
* app. C, eq. (eps_ss_ap): the constant 64 pi sinh(b M0)/sqrt(M0) must be
  16 pi C sinh(beta M0)/sqrt(M0) (C and a factor 4 wrong), the Ei term lacks the factor C, and
  the imaginary part 16 pi^3 b C (sqrt(M0) - w) alpha_3 must be
  -64 pi^2 beta C (sqrt(M0) - omega) alpha_3, with Theta(sqrt(M0) - omega) Theta(omega
  - 3 sqrt(M0)/4) for the same reason as above.
* The prefactors pi/2 (cc, l = +-2) and 2 pi (ss, l = +-1) of eqs. (eps_cc_ap_def,
  eps_ss_ap_def) follow from the general eps with c_2 ~ kappa^2/2, |s_1| ~ kappa, W = 1: they
  are right.
"""

from __future__ import annotations

import numpy as np
from scipy import special

from ..meanfield import orbits
from ..meanfield.equilibrium import ThermalState
from ..meanfield.fourier import cos_coefficient, sin_coefficient_imag

__all__ = [
    "landau_D_sech4",
    "landau_Dpol_sech4",
    "landau_D_small_kappa",
    "landau_Dpol_small_kappa",
    "landau_D_librating_sum",
    "landau_Dpol_librating_sum",
    "landau_coefficients_resonant",
    "two_step_dielectric",
    "two_step_D",
    "mb_dielectric_appendix_c",
    "mb_D_appendix_c",
    "mb_Dpol_appendix_c",
]


def _f(x):
    return np.asarray(x, dtype=float)


# ---------------------------------------------------------------------------------------------
# 1. Landau (no collective effects), kappa < 1
# ---------------------------------------------------------------------------------------------


def _sech4_parts(kappa):
    """(K, sech^4(pi K'/(2K)), E - (1 - kappa^2) K) for 0 < kappa < 1.

    E - (1 - m) K = m (K - R_D(0, 1 - m, 1)/3) (DLMF 19.25.1) avoids the cancellation of the
    printed form at small kappa.
    """
    k = _f(kappa)
    k = np.where((k > 0.0) & (k < 1.0), k, np.nan)  # outside 0 < kappa < 1: NaN
    m = k * k
    m1 = (1.0 - k) * (1.0 + k)
    K = special.ellipk(m)
    Kp = special.ellipk(m1)
    x = np.pi * Kp / (2.0 * K)
    sech4 = (1.0 / np.cosh(x)) ** 4
    EmK = m * (K - special.elliprd(0.0, m1, 1.0) / 3.0)
    return K, sech4, EmK


def landau_D_sech4(kappa, state):
    """N D_dif, Landau, eq. (coeff-analytic-ncoll) (first line), valid for 0 < kappa < 1.

    4 pi^8 kappa^2 (1 - kappa^2) sech^4(pi K'/2K) f / (K^5 [E - (1 - kappa^2) K]): the
    n = n' = +-1, kappa* = kappa term of eq. (hmfCEdif) with eps = 1 (librating resonance only;
    the rotating root of Omega(kappa*) = Omega(kappa) and the n = n' = +-2 term are left out).
    NaN outside 0 < kappa < 1 (kappa -> 0: use `landau_D_small_kappa`).
    """
    k = _f(kappa)
    K, sech4, EmK = _sech4_parts(k)
    return 4.0 * np.pi**8 * k**2 * (1.0 - k**2) * sech4 / (K**5 * EmK) * state.f(k)


def landau_Dpol_sech4(kappa, state):
    """N D_pol, Landau, eq. (coeff-analytic-ncoll) (second line) with the sign corrected.

    pi^9 kappa (1 - kappa^2) sech^4 f' / (2 sqrt(M0) K^6 [E - (1 - kappa^2) K]); the paper prints
    (kappa^2 - 1).  Valid for 0 < kappa < 1, same terms as `landau_D_sech4`.
    """
    k = _f(kappa)
    K, sech4, EmK = _sech4_parts(k)
    pref = np.pi**9 * k * (1.0 - k**2) * sech4 / (2.0 * np.sqrt(state.M0) * K**6 * EmK)
    return pref * state.dfdkappa(k)


def landau_D_small_kappa(kappa, state):
    """N D_dif ~ 32 pi^2 kappa^4 f, eq. (coeff-analytic-ncoll-exp); relative error -13/8 kappa^2.

    Leading term of `landau_D_sech4` as kappa -> 0 (D_sech4 = 32 pi^2 kappa^4 f (1 - 13 kappa^2/8
    + O(kappa^4))).
    """
    k = _f(kappa)
    return 32.0 * np.pi**2 * k**4 * state.f(k)


def landau_Dpol_small_kappa(kappa, state):
    """N D_pol ~ 8 pi^2 kappa^3 f'/sqrt(M0), eq. (coeff-analytic-ncoll-exp).

    Leading term of the sign-corrected `landau_Dpol_sech4` (relative error -15/8 kappa^2).
    """
    k = _f(kappa)
    return 8.0 * np.pi**2 * k**3 * state.dfdkappa(k) / np.sqrt(state.M0)


def landau_coefficients_resonant(kappa, state, n_max=2, include_rotating=False):
    """(N D_dif, N D_pol) of the Landau formula (eps = 1), resonances truncated at n_max.

    Sums eq. (hmfCEdif)/(hmfCEpol) with eps = 1 over 1 <= |n|, |n'| <= n_max and over the
    librating roots kappa* of n Omega(kappa) = n' Omega(kappa*) (kappa* = kappa for n = n';
    other librating roots appear for n != n' with n_max >= 3, and only where c_n c_n' or
    sigma_n sigma_n' is non zero).  With include_rotating=True the rotating roots (weight W = 2,
    both directions) are added as well; that is the full Landau sum truncated at n_max, valid for
    any kappa != 1 (the librating-only sum is meant for kappa < 1).
    Only resonances with sign(n) = sign(n') exist (Omega > 0); the (-n, -n') term equals (n, n').
    """
    k = _f(kappa)
    M0 = state.M0
    Om = orbits.frequency(k, M0)
    D = np.zeros_like(k)
    P = np.zeros_like(k)
    families = ["libration"] + (["rotation"] if include_rotating else [])
    for n in range(1, n_max + 1):
        cn = cos_coefficient(n, k)
        sn = sin_coefficient_imag(n, k)
        for n2 in range(1, n_max + 1):
            for fam in families:
                ks = orbits.kappa_from_frequency(n * Om / n2, M0, fam)
                if n2 == n:  # kappa itself is the root on its own branch: no bisection error
                    own = (k < 1.0) if fam == "libration" else (k > 1.0)
                    ks = np.where(own, k, ks)
                # no root, or a root rounding onto the separatrix (weight -> 0 there)
                ok = np.isfinite(ks) & (np.abs(ks - 1.0) > 1e-12)
                ks = np.where(ok, ks, 0.5)
                W = orbits.phase_space_weight(ks)
                coupling = (cn * cos_coefficient(n2, ks)) ** 2 + (
                    sn * sin_coefficient_imag(n2, ks)
                ) ** 2
                inv = 1.0 / (n2 * np.abs(orbits.dOmega_dkappa(ks, M0)))
                d = n**2 * W * orbits.dJ_dkappa(ks, M0) * state.f(ks) * inv * coupling
                p = n * n2 * W * state.dfdkappa(ks) * inv * coupling
                D += np.where(ok, d, 0.0)
                P += np.where(ok, p, 0.0)
    # factor 2: the (-n, -n') terms
    return 4.0 * np.pi**2 * D, 4.0 * np.pi**2 * P


def landau_D_librating_sum(kappa, state, n_max=2, include_rotating=False):
    """N D_dif, Landau, librating resonances with |n|, |n'| <= n_max, for kappa < 1.

    For n_max = 2 this is the sech^4 form (n = n' = +-1) plus the n = n' = +-2 cosine term,
    both at kappa* = kappa.  See `landau_coefficients_resonant`.
    """
    return landau_coefficients_resonant(kappa, state, n_max, include_rotating)[0]


def landau_Dpol_librating_sum(kappa, state, n_max=2, include_rotating=False):
    """N D_pol companion of `landau_D_librating_sum` (kappa < 1)."""
    return landau_coefficients_resonant(kappa, state, n_max, include_rotating)[1]


# ---------------------------------------------------------------------------------------------
# 2. Two-step core-halo, eqs. (hmffch2, hmffch2k, partial-ch, hmfepscc/ss-ch)
# ---------------------------------------------------------------------------------------------


def _step_data(state):
    if getattr(state, "shape", None) != "step":
        raise ValueError("the two-step closed forms need CoreHaloState(..., shape='step')")
    ki = np.asarray(state.step_kappas, dtype=float)
    wi = np.asarray(state.step_weights, dtype=float)
    if np.any(np.abs(ki - 1.0) < 1e-12):
        raise ValueError("a step sits on the separatrix kappa = 1: Omega = 0 there")
    return ki, wi


def two_step_dielectric(omega, state, l_max=6):
    """(eps_cc, eps_ss)(omega) of the two-step core-halo state, eq. (hmfepscc/ss-ch) corrected.

    With df/dkappa = -sum_i w_i delta(kappa - kappa_i) (w_i = state.step_weights):
        eps(omega) = 1 - 2 pi sum_{l=1}^{l_max} sum_i W_i w_i X_l(kappa_i)^2
                         [1/(Omega_i - omega/l) + 1/(Omega_i + omega/l)],
    X_l = c_l for cc and sigma_l for ss (|s_l| = |sigma_l|).  Both are real and even in omega,
    and diverge at omega = +- l Omega(kappa_i) (returned as they come: +-inf or huge values).
    Valid for any real omega; for steps on librating orbits only odd l (ss) and even l (cc)
    contribute.  Returns real arrays.
    """
    om = _f(omega)
    ki, wi = _step_data(state)
    M0 = state.M0
    Oi = orbits.frequency(ki, M0)
    Wi = orbits.phase_space_weight(ki)
    ecc = np.ones_like(om)
    ess = np.ones_like(om)
    with np.errstate(divide="ignore"):
        for l in range(1, l_max + 1):
            for k, w, O, W in zip(ki, wi, Oi, Wi, strict=True):
                res = 1.0 / (O - om / l) + 1.0 / (O + om / l)
                ecc = ecc - 2.0 * np.pi * W * w * cos_coefficient(l, k) ** 2 * res
                ess = ess - 2.0 * np.pi * W * w * sin_coefficient_imag(l, k) ** 2 * res
    return ecc, ess


def two_step_D(kappa, state, n_max=2, collective=True, l_max=6):
    """N D_dif of the two-step core-halo state with kappa* = kappa, eq. (hmfCEdif) + (hmffch2k).

    N D = 2 pi^2 sum_{0 < |n| <= n_max} n^2 W dJ/dkappa f(kappa) / |n Omega'(kappa)|
          x [c_n^4 / eps_cc(n Omega)^2 + sigma_n^4 / eps_ss(n Omega)^2]
    (n' = n only, as in the paper; valid for librating kappa < 1, where for n_max <= 2 the
    kappa* = kappa root is the only librating one; rotating roots carry f = 0 when both steps
    lie inside the separatrix).  eps from `two_step_dielectric` (collective=False: eps = 1).
    D_pol of this state is a sum of delta functions at kappa_i and has no pointwise closed form.
    """
    k = _f(kappa)
    M0 = state.M0
    Om = orbits.frequency(k, M0)
    base = orbits.phase_space_weight(k) * orbits.dJ_dkappa(k, M0) * state.f(k)
    base = base / np.abs(orbits.dOmega_dkappa(k, M0))
    D = np.zeros_like(k)
    for n in range(1, n_max + 1):
        if collective:
            ecc, ess = two_step_dielectric(n * Om, state, l_max)
        else:
            ecc = ess = 1.0
        term = cos_coefficient(n, k) ** 4 / ecc**2 + sin_coefficient_imag(n, k) ** 4 / ess**2
        D += n * term  # n^2 / |n|
    return 4.0 * np.pi**2 * base * D  # 2 pi^2 x 2 (the -n terms)


# ---------------------------------------------------------------------------------------------
# 3. Maxwell-Boltzmann, M0 -> 1, appendix C
# ---------------------------------------------------------------------------------------------


def _mb_constants(M0):
    """(state, beta, C e^{beta M0} = f(kappa = 0)) of the thermal state, eq. (gaussian-def)."""
    st = ThermalState(M0=M0)
    return st, st.beta, float(st.f(0.0))


def _exp_ei(y):
    """e^{-y} Ei(y) for real y != 0 without overflow (asymptotic series for |y| > 600)."""
    y = _f(y)
    big = np.abs(y) > 600.0
    yb = np.where(big, y, 1.0)
    ys = np.where(big, 1.0, y)
    series = np.zeros_like(yb)
    term = 1.0 / yb
    for k in range(1, 30):  # (1/y) sum_k k!/y^k, error ~ 30!/600^30 < 1e-50
        series = series + term
        term = term * k / yb
    with np.errstate(over="ignore"):
        direct = np.exp(-ys) * special.expi(ys)
    return np.where(big, series, direct)


def _pv_x_integrals(a, b):
    """PV int_0^1 x^j e^{-b x} / (a - x) dx for j = 1, 2 (real a != 0, 1; b > 0).

    int_0^1 e^{-bx}/(a - x) dx = e^{-ab} [Ei(ab) - Ei(b(a - 1))] (substitute v = b(a - x); a PV
    integral when 0 < a < 1, which Ei's own PV definition gives), then
    x/(a - x) = -1 + a/(a - x) and x^2/(a - x) = -(a + x) + a^2/(a - x).
    """
    e0 = _exp_ei(a * b) - np.exp(-b) * _exp_ei(b * (a - 1.0))
    m0 = -np.expm1(-b) / b  # int_0^1 e^{-bx} dx
    m1 = (1.0 - np.exp(-b) * (1.0 + b)) / b**2  # int_0^1 x e^{-bx} dx
    ae0 = np.where(a == 0.0, 0.0, a * e0)  # a log|a| -> 0: the pole at the end x = 0
    i1 = -m0 + ae0
    i2 = -a * m0 - m1 + a * ae0
    return i1, i2


def _mb_half(om, M0, beta, f0):
    """The l > 0 halves (l = 2 for cc, l = 1 for ss) of eqs. (eps_cc_ap_def, eps_ss_ap_def) at
    real omega + i0 (any sign of omega; a pole only for omega > 0)."""
    s = np.sqrt(M0)
    b = 2.0 * beta * M0
    # f = f0 e^{-b x}, kappa^(2j) f' dkappa = pref x^j e^{-b x} dx with x = kappa^2
    pref = -2.0 * beta * M0 * f0
    # cc: int_0^1 kappa^4 f' / (s(1 - kappa^2/4) - omega/2) dkappa, x = kappa^2,
    # s(1 - x/4) - omega/2 = (s/4)(a - x), a = 4 - 2 omega/s
    a_cc = 4.0 - 2.0 * om / s
    a_ss = 4.0 - 4.0 * om / s
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        _, i2 = _pv_x_integrals(a_cc, b)
        i1, _ = _pv_x_integrals(a_ss, b)
        in_cc = (a_cc > 0) & (a_cc < 1)
        in_ss = (a_ss > 0) & (a_ss < 1)
        im_cc = np.where(in_cc, np.pi * a_cc**2 * np.exp(-b * np.where(in_cc, a_cc, 0.0)), 0.0)
        im_ss = np.where(in_ss, np.pi * a_ss * np.exp(-b * np.where(in_ss, a_ss, 0.0)), 0.0)
    # 1/((s/4)(a - x) - i0) = (4/s) [PV 1/(a - x) + i pi delta(x - a)]; real and imaginary
    # parts scaled apart: at the logarithmic end-point divergence the real part is infinite
    # and the imaginary part finite (a complex product would make both NaN)
    c = pref * 4.0 / s
    return _complex(c * i2, c * im_cc), _complex(c * i1, c * im_ss)


def _complex(re, im):
    out = np.empty(np.broadcast(re, im).shape, dtype=complex)
    out.real, out.imag = re, im
    return out


def mb_dielectric_appendix_c(omega, M0):
    """(eps_cc, eps_ss)(omega), complex, of the thermal state as M0 -> 1, appendix C corrected.

    Closed form of the definitions eqs. (eps_cc_ap_def, eps_ss_ap_def):
        eps_cc = 1 + (pi/2) int_0^1 kappa^4 f'/(s (1 - kappa^2/4) - omega/2) + (omega -> -omega)
        eps_ss = 1 + 2 pi  int_0^1 kappa^2 f'/(s (1 - kappa^2/4) - omega)   + (omega -> -omega)
    f = C exp(-beta M0 (2 kappa^2 - 1)), omega -> omega + i0 (Im eps < 0 for omega > 0, and
    eps(-omega) = conj eps(omega)).  With s = sqrt(M0), b = 2 beta M0, a = 4 - 2 omega/s
    (cc), a = 4 - 4 omega/s (ss), x = kappa^2, the integrals reduce to
    PV int_0^1 x^j e^{-bx}/(a - x) dx, j = 2 (cc), 1 (ss), written with Ei = scipy.special.expi.
    For omega > 0 the real part equals the paper's eq. (eps_cc_ap) and, after the corrections
    listed in the module docstring, eq. (eps_ss_ap).  Leading order in kappa (all l but +-2
    (cc) / +-1 (ss) and all rotating orbits neglected): valid as M0 -> 1 (beta M0 >> 1).
    Finite at omega = +-2 s (cc), +-s (ss) (pole at the end kappa = 0, where the integrand is
    regular); logarithmically divergent, with the tiny weight f(kappa = 1), at omega = +-3 s/2
    (cc) and +-3 s/4 (ss) (pole at the end kappa = 1 of the definitions' range).
    """
    om = _f(omega)
    _, beta, f0 = _mb_constants(M0)
    cc_p, ss_p = _mb_half(om, M0, beta, f0)
    cc_m, ss_m = _mb_half(-om, M0, beta, f0)
    # l = -2 (-1) term: 1/(Omega + (omega + i0)/l') = conj of the l > 0 half at -omega
    cc, ss = cc_p + np.conj(cc_m), ss_p + np.conj(ss_m)
    eps_cc = _complex(1.0 + (np.pi / 2.0) * cc.real, (np.pi / 2.0) * cc.imag)
    eps_ss = _complex(1.0 + 2.0 * np.pi * ss.real, 2.0 * np.pi * ss.imag)
    return eps_cc, eps_ss


def _mb_coefficients(kappa, M0, orbit, collective, which):
    k = _f(kappa)
    st = ThermalState(M0=M0)
    s = np.sqrt(M0)
    if orbit == "exact":
        Om = orbits.frequency(k, M0)
        dOm = np.abs(orbits.dOmega_dkappa(k, M0))
        dJ = orbits.dJ_dkappa(k, M0)
        c1, c2 = cos_coefficient(1, k), cos_coefficient(2, k)
        s1, s2 = sin_coefficient_imag(1, k), sin_coefficient_imag(2, k)
    elif orbit == "expanded":
        Om = s * (1.0 - k**2 / 4.0)
        dOm = s * k / 2.0
        dJ = 4.0 * s * k
        c1, c2, s1, s2 = 0.0 * k, k**2 / 2.0, k, 0.0 * k
    else:
        raise ValueError("orbit must be 'exact' or 'expanded'")
    fac = dJ * st.f(k) if which == "D" else st.dfdkappa(k)
    out = np.zeros_like(k)
    for n, cn, sn in ((1, c1, s1), (2, c2, s2)):
        if collective:
            ecc, ess = mb_dielectric_appendix_c(n * Om, M0)
            acc, ass = np.abs(ecc) ** 2, np.abs(ess) ** 2
        else:
            acc = ass = 1.0
        out = out + n * (cn**4 / acc + sn**4 / ass)  # n^2/|n| (D) or n n/|n| (D_pol)
    return 4.0 * np.pi**2 * fac / dOm * out


def mb_D_appendix_c(kappa, M0, orbit="exact", collective=True):
    """N D_dif of the thermal state as M0 -> 1 with the appendix-C dielectric (fig. 7(f)).

    Terms of eq. (hmfCEdif) with n, n' in -2..2 at kappa* = kappa (n' = n; the only librating
    root), dressed by 1/|eps(n Omega(kappa))|^2 from `mb_dielectric_appendix_c`.
    orbit='exact' uses the exact c_n, sigma_n, J', Omega, Omega'; orbit='expanded' their
    leading-order forms (c_2 = kappa^2/2, sigma_1 = kappa, J' = 4 sqrt(M0) kappa,
    Omega = sqrt(M0)(1 - kappa^2/4)), as in the appendix.  Valid for kappa < 1, M0 -> 1.
    """
    return _mb_coefficients(kappa, M0, orbit, collective, "D")


def mb_Dpol_appendix_c(kappa, M0, orbit="exact", collective=True):
    """N D_pol companion of `mb_D_appendix_c` (eq. hmfCEpol, same terms).

    With orbit='exact' it equals -beta Omega(kappa) mb_D_appendix_c exactly (thermal f)."""
    return _mb_coefficients(kappa, M0, orbit, collective, "Dpol")
