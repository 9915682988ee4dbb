"""Any state as a table f(J-bar) on a grid of actions, with its self-consistent magnetisation.

The table is indexed by the rescaled action J-bar (`orbits.rescaled_action`: J/2 on librating
orbits, J on rotating ones).  J-bar is continuous across the separatrix and the phase-space
volume per unit J-bar is 4 pi on both sides (librating: dw dJ = 2 pi * 2 dJ-bar; rotating: two
directions of rotation, 2 x 2 pi dJ-bar), so one table covers both orbit families, with f even
in p.  The separatrix sits at J-bar_s = 4 sqrt(M0)/pi and moves with M0: a node below it is a
librating torus of action 2 J-bar, a node above it a pair of rotating tori of action J-bar.

Between nodes, ln f is a quintic spline in the one-particle energy h(J-bar; M0), which increases
monotonically with J-bar across both families: a thermal f = C exp(-beta h) is interpolated
exactly, and every f(h) smoothly.  Beyond the last node f = 0.

M0 is the fixed point M0 = int f cos(theta) dtheta dp / int f dtheta dp with f(J-bar) held fixed
(orbits, hence cos(theta) along them, depend on M0), solved by `solve_M0`.

`TabulatedState` offers what the theory code asks of a state (`M0`, `f(kappa)`,
`dfdkappa(kappa)`, `kappa_max`, `quadrature()`), so `DielectricTensor`, `resonance_table` and
`diffusion_coefficients` accept it unchanged.
"""

from __future__ import annotations

import numpy as np
from scipy import interpolate, optimize

from ..meanfield import orbits
from ..meanfield.equilibrium import EquilibriumError, PhaseSpaceQuadrature
from ..meanfield.fourier import cos_coefficient

__all__ = [
    "PHASE_VOLUME_PER_JBAR",
    "energy_of_jbar",
    "TabulatedState",
    "tabulate",
    "jbar_table_grid",
]

#: phase-space volume dtheta dp per unit J-bar, on both sides of the separatrix
PHASE_VOLUME_PER_JBAR = 4.0 * np.pi


def energy_of_jbar(jbar, M0):
    """One-particle energy h(J-bar; M0) = M0 (2 kappa^2 - 1), increasing across both families."""
    return orbits.energy_from_kappa(orbits.kappa_from_rescaled_action(jbar, M0), M0)


def jbar_table_grid(M0, kappa_max, n):
    """n table nodes from J-bar = 0 to J-bar(kappa_max), uniform in kappa at magnetisation M0."""
    kappa = np.linspace(0.0, kappa_max, n)
    kappa = kappa[np.abs(kappa - 1.0) > 1e-12]
    return orbits.rescaled_action(kappa, M0)


class _LogInterpolant:
    """ln f as a quintic spline in h inside the table, linear in h outside (f > 0 required)."""

    def __init__(self, h, logf):
        self.h0, self.h1 = h[0], h[-1]
        k = 5 if h.size > 5 else 3
        self.spline = interpolate.make_interp_spline(h, logf, k=k)
        self.dspline = self.spline.derivative()
        self.slope0 = float(self.dspline(self.h0))
        self.slope1 = float(self.dspline(self.h1))
        self.y0, self.y1 = logf[0], logf[-1]

    def __call__(self, h, nu=0):
        h = np.asarray(h, dtype=float)
        inside = np.clip(h, self.h0, self.h1)
        val = self.spline(inside) if nu == 0 else self.dspline(inside)
        if nu == 0:
            val = np.where(h < self.h0, self.y0 + self.slope0 * (h - self.h0), val)
            val = np.where(h > self.h1, self.y1 + self.slope1 * (h - self.h1), val)
        else:
            val = np.where(h < self.h0, self.slope0, val)
            val = np.where(h > self.h1, self.slope1, val)
        return val


class TabulatedState:
    """A state given by f on a grid of rescaled actions J-bar, M0 self-consistent.

    Parameters
    ----------
    jbar : increasing array of J-bar >= 0 (the table's nodes; f = 0 beyond the last one)
    f : f at the nodes, > 0 (ln f is interpolated)
    M0 : the magnetisation, if already known to be self-consistent with f (else solved)
    M0_guess : start of the search for the self-consistent M0 (else the largest root)
    normalise : divide f by its mass (int f dtheta dp), kept as `mass`
    order : Gauss-Legendre order of the phase-space quadrature (`PhaseSpaceQuadrature`)
    """

    kind = "tabulated"

    def __init__(self, jbar, f, M0=None, *, M0_guess=None, normalise=True, order=24):
        jbar = np.asarray(jbar, dtype=float)
        f = np.asarray(f, dtype=float)
        if jbar.ndim != 1 or jbar.shape != f.shape or jbar.size < 4:
            raise EquilibriumError("a tabulated state needs 1-d jbar and f of equal size >= 4")
        if not np.all(np.isfinite(jbar)) or jbar[0] < 0 or np.any(np.diff(jbar) <= 0):
            raise EquilibriumError("tabulated jbar must be finite, >= 0 and strictly increasing")
        if not np.all(np.isfinite(f)) or np.any(f <= 0):
            raise EquilibriumError("tabulated f must be finite and > 0 at every node (ln f)")
        self.jbar = jbar
        self.order = int(order)
        self._logf = np.log(f)
        if M0 is None:
            M0 = solve_M0(jbar, f, guess=M0_guess, order=self.order)
        if not np.isfinite(M0) or not 0.0 < M0 < 1.0:
            raise EquilibriumError(f"M0 = {M0!r} is outside the allowed range 0 < M0 < 1")
        self.M0 = float(M0)
        self._kappa_max = float(orbits.kappa_from_rescaled_action(jbar[-1:], self.M0)[0])
        self._interp = _interpolant(jbar, self._logf, self.M0)
        self.mass = float(self.quadrature().integrate(self._raw_f(self.quadrature().kappa)))
        if normalise:
            self._logf = self._logf - np.log(self.mass)
            self._interp = _interpolant(jbar, self._logf, self.M0)

    @property
    def params(self):
        return {"n_nodes": int(self.jbar.size), "jbar_max": float(self.jbar[-1])}

    @property
    def f_table(self):
        """f at the table's nodes (normalised if the state was)."""
        return np.exp(self._logf)

    @property
    def kappa_max(self):
        """kappa of the last node: f = 0 beyond it."""
        return self._kappa_max

    def _raw_f(self, kappa):
        kappa = np.asarray(kappa, dtype=float)
        h = orbits.energy_from_kappa(kappa, self.M0)
        return np.where(kappa <= self.kappa_max, np.exp(self._interp(h)), 0.0)

    def f_energy(self, h):
        h = np.asarray(h, dtype=float)
        hmax = orbits.energy_from_kappa(self.kappa_max, self.M0)
        return np.where(h <= hmax, np.exp(self._interp(h)), 0.0)

    def f(self, kappa):
        """f(kappa) (phase-space density, both directions of rotation equal)."""
        return self._raw_f(kappa)

    def dfdkappa(self, kappa):
        """df/dkappa = f d(ln f)/dh * 4 M0 kappa."""
        kappa = np.asarray(kappa, dtype=float)
        h = orbits.energy_from_kappa(kappa, self.M0)
        return self.f(kappa) * self._interp(h, 1) * 4.0 * self.M0 * kappa

    def f_jbar(self, jbar):
        """f at rescaled actions J-bar."""
        return self.f(orbits.kappa_from_rescaled_action(jbar, self.M0))

    def quadrature(self, order=None):
        return PhaseSpaceQuadrature(self.M0, self.kappa_max, order=order or self.order)

    @property
    def u(self):
        """Energy per particle u = <h> + M0^2/2 (kinetic plus potential)."""
        q = self.quadrature()
        f = self.f(q.kappa)
        return float(
            q.integrate(f * orbits.energy_from_kappa(q.kappa, self.M0)) / q.integrate(f)
            + 0.5 * self.M0**2
        )

    @property
    def entropy(self):
        """S = -int f ln f dtheta dp."""
        q = self.quadrature()
        f = self.f(q.kappa)
        with np.errstate(divide="ignore", invalid="ignore"):
            return float(-q.integrate(np.where(f > 0, f * np.log(f), 0.0)))


def _interpolant(jbar, logf, M0):
    return _LogInterpolant(energy_of_jbar(jbar, M0), logf)


def _magnetisation_map(jbar, logf, M0, order):
    """int f cos(theta) / int f with the table's f(J-bar) and orbits of magnetisation M0."""
    interp = _interpolant(jbar, logf, M0)
    kmax = float(orbits.kappa_from_rescaled_action(jbar[-1:], M0)[0])
    q = PhaseSpaceQuadrature(M0, kmax, order=order)
    f = np.exp(interp(orbits.energy_from_kappa(q.kappa, M0)))
    return q.integrate(f * cos_coefficient(0, q.kappa)) / q.integrate(f)


def solve_M0(jbar, f, guess=None, order=24):
    """Self-consistent M0 of the table f(J-bar): root of int f cos(theta) / int f - M0.

    With a guess, the root nearest to it (searched in guess +- 0.001 on 3 points, then +- 0.01
    and wider on 9: a guess from a nearby state, as in a relaxation, finds its root in the first
    bracket); otherwise the largest root in (0.01, 0.99).
    """
    jbar = np.asarray(jbar, dtype=float)
    logf = np.log(np.asarray(f, dtype=float))

    def g(M):
        return _magnetisation_map(jbar, logf, M, order) - M

    if guess is not None:
        for half, points in ((0.001, 3), (0.01, 9), (0.05, 9), (0.2, 9)):
            lo, hi = max(guess - half, 1e-3), min(guess + half, 0.999)
            grid = np.linspace(lo, hi, points)
            vals = np.array([g(M) for M in grid])
            idx = np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))
            if idx.size:
                roots = [
                    optimize.brentq(g, grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15) for i in idx
                ]
                return min(roots, key=lambda r: abs(r - guess))
    grid = np.linspace(0.01, 0.99, 50)
    vals = np.array([g(M) for M in grid])
    idx = np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))
    if not idx.size:
        raise EquilibriumError("no magnetised self-consistent M0 in (0.01, 0.99) for the table")
    return max(optimize.brentq(g, grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15) for i in idx)


def tabulate(state, n_nodes=4001, kappa_max=None, solve=True):
    """A `TabulatedState` copy of `state` (thermal, core-halo, ...): f at n_nodes J-bar nodes
    uniform in kappa up to kappa_max (default state.kappa_max), M0 re-solved from the table
    (or taken from `state` if solve=False)."""
    kmax = float(state.kappa_max if kappa_max is None else kappa_max)
    jbar = jbar_table_grid(state.M0, kmax, n_nodes)
    f = state.f(orbits.kappa_from_rescaled_action(jbar, state.M0))
    M0 = None if solve else state.M0
    return TabulatedState(jbar, f, M0=M0, M0_guess=state.M0)
