"""Linear (Vlasov) stability of a state: no zero of eps_cc(omega) or eps_ss(omega) in the upper
half plane (eqs. hmfepscc, hmfepsss), counted by the argument principle on the real axis.

eps(omega) is analytic for Im omega > 0 (the Landau prescription gives its boundary value on
the real axis), tends to 1 as |omega| -> infinity and satisfies eps(-conj(omega)) =
conj(eps(omega)), so the number of zeros in the upper half plane is

    Z = (1/pi) Delta_{0 < omega < infinity} arg eps(omega)

(the negative half of the real axis adds the same change of argument).  A Nyquist curve that
winds round the origin betrays growing modes; zeros come in pairs (omega, -conj(omega)) unless
purely imaginary.

The sine component vanishes at omega = 0 for every self-consistent state: the neutral rotation
of the whole system, eps_ss ~ eps_ss(0) + c omega^2 with eps_ss(0) = 0 up to the truncation
|l| <= l_max.  That double zero (shifted to +-sqrt(-eps_ss(0)/c) by the truncation) is not an
instability: it is excluded by a small half circle |omega| = r in the upper half plane, on which
eps_ss ~ c omega^2 turns by -2 pi, so Z_ss = (1/pi) Delta_{r < omega < infinity} arg eps_ss - 1,
with r where |eps_ss - eps_ss(0)| exceeds 100 |eps_ss(0)|.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..meanfield import orbits
from .dielectric import DielectricTensor

__all__ = [
    "VlasovInstabilityError",
    "StabilityReport",
    "winding",
    "vlasov_stability",
    "growing_mode",
    "check_vlasov_stable",
]


class VlasovInstabilityError(ValueError):
    """A state with growing modes (zeros of eps in the upper half plane)."""


@dataclass(frozen=True)
class StabilityReport:
    """Zero counts in the upper half plane and the evidence behind them."""

    zeros_cc: int
    zeros_ss: int
    winding_cc: float  # (1/pi) Delta arg eps_cc over 0 < omega < infinity (integer if resolved)
    winding_ss: float  # the same for eps_ss from r, minus 1 for the half circle round 0
    eps_cc0: float  # eps_cc(0+), real
    eps_ss0: float  # eps_ss(0+): zero up to the truncation l_max
    r_ss: float  # radius of the half circle that excludes the neutral rotation
    l_max: int

    @property
    def stable(self):
        return self.zeros_cc == 0 and self.zeros_ss == 0

    @property
    def unstable_components(self):
        return [c for c, z in (("eps_cc", self.zeros_cc), ("eps_ss", self.zeros_ss)) if z != 0]


def _frequencies(state, l_max, n):
    """Real frequencies from 1e-6 Omega_0 to past the continuum (l_max Omega(kappa_max))."""
    Om0 = np.sqrt(state.M0)
    top = l_max * float(orbits.frequency(state.kappa_max, state.M0))
    small = np.geomspace(1e-6 * Om0, 0.05 * Om0, n // 8)
    body = np.linspace(0.05 * Om0, 1.05 * top, n)[1:]
    tail = np.geomspace(1.05 * top, 100.0 * top, n // 8)[1:]
    return np.concatenate([small, body, tail])


def _refined_phase(fun, omega, max_jump=0.5, rounds=12):
    """Unwrapped arg fun(omega), inserting frequencies where arg jumps by more than max_jump."""
    for _ in range(rounds):
        val = fun(omega)
        jump = np.abs(np.angle(val[1:] / val[:-1]))
        bad = np.flatnonzero(jump > max_jump)
        if not bad.size:
            break
        omega = np.sort(np.concatenate([omega, 0.5 * (omega[bad] + omega[bad + 1])]))
    return omega, val, np.unwrap(np.angle(val))


def winding(fun, omega):
    """(1/pi) times the change of arg fun along the increasing real frequencies `omega`
    (refined where the argument turns fast): for a function analytic in the upper half plane
    with fun(-conj w) = conj fun(w) and fun -> 1 at infinity, the number of its zeros with
    Im w > 0 when omega runs from 0+ to beyond the last change of argument."""
    _, _, phase = _refined_phase(fun, np.asarray(omega, dtype=float))
    return float((phase[-1] - phase[0]) / np.pi)


def vlasov_stability(state, l_max=6, n_omega=1500, **accuracy):
    """Count the zeros of eps_cc and eps_ss in the upper half plane (`StabilityReport`)."""
    tensor = DielectricTensor(state, l_max=l_max, **accuracy)
    omega = _frequencies(state, l_max, n_omega)
    e_cc0, e_ss_all = tensor(omega[:1])[0][0], tensor(omega)[1]
    w_cc = winding(lambda w: tensor(w)[0], omega)
    ss0 = float(e_ss_all[0].real)
    far = np.flatnonzero(np.abs(e_ss_all - ss0) > 100.0 * abs(ss0))
    r = float(omega[far[0]]) if far.size else float(omega[0])
    # the half circle |omega| = r round the neutral rotation turns eps_ss ~ c omega^2 by -2 pi
    w_ss = winding(lambda w: tensor(w)[1], omega[omega >= r]) - 1.0
    return StabilityReport(
        zeros_cc=int(round(w_cc)),
        zeros_ss=int(round(w_ss)),
        winding_cc=w_cc,
        winding_ss=w_ss,
        eps_cc0=float(e_cc0.real),
        eps_ss0=ss0,
        r_ss=r,
        l_max=int(l_max),
    )


def growing_mode(state, component="cc", l_max=6, im_min=0.02, **accuracy):
    """The zero of eps_cc (component 'cc') or eps_ss ('ss') with the largest imaginary part
    above im_min Omega_0: a scan of |eps| on a grid of the upper half plane
    (`DielectricTensor.upper_half_plane`), then Newton steps.  Returns the complex frequency
    (growth rate = imaginary part) or None if |eps| has no zero there."""
    tensor = DielectricTensor(state, l_max=l_max, **accuracy)
    idx = 0 if component == "cc" else 1
    Om0 = np.sqrt(state.M0)
    top = l_max * float(orbits.frequency(state.kappa_max, state.M0))
    X, Y = np.meshgrid(np.linspace(0.02 * Om0, top, 400), np.geomspace(im_min * Om0, Om0, 40))
    Z = (X + 1j * Y).ravel()
    vals = np.abs(tensor.upper_half_plane(Z)[idx])
    z = Z[np.argmin(vals)]
    for _ in range(50):
        e0 = tensor.upper_half_plane(z)[idx]
        d = 1e-7 * Om0
        slope = (tensor.upper_half_plane(z + d)[idx] - e0) / d
        z = z - e0 / slope
        if abs(e0) < 1e-12 or z.imag <= 0:
            break
    if z.imag < 0.5 * im_min * Om0 or abs(tensor.upper_half_plane(z)[idx]) > 1e-8:
        return None
    return complex(z)


def check_vlasov_stable(state, name, l_max=6, **kw):
    """Return the `StabilityReport` of a stable state; raise VlasovInstabilityError naming the
    state and the unstable component(s) otherwise."""
    rep = vlasov_stability(state, l_max=l_max, **kw)
    if not rep.stable:
        parts = ", ".join(
            f"{c} has {z} zero(s) in the upper half plane"
            for c, z in (("eps_cc", rep.zeros_cc), ("eps_ss", rep.zeros_ss))
            if z != 0
        )
        raise VlasovInstabilityError(
            f"state {name!r} (M0 = {state.M0:.6g}) is Vlasov-unstable: {parts} "
            f"(growing modes; argument principle on the real axis, l_max = {l_max}); "
            "a collisional evolution or MD run from it would not start from an equilibrium"
        )
    return rep
