"""The J-bar grid on which the kinetic equations evolve f, and the state on it.

`action_grid`: n_nodes nodes of rescaled action J-bar, placed by a density in kappa (at the
initial M0) that mixes a uniform part, a part packed round the separatrix (kappa = 1, whose
rotating orbits are the resonant partners of the core) and a part on the steep edges of the
initial f(h); each node carries the cell between the mid-points to its neighbours, of phase
volume 4 pi width.  On this grid: the self-consistent M0 of a tabulated f (`solve_grid_M0`),
the energy and entropy per particle (`grid_energy`, `grid_entropy`), the projection of an
equilibrium state (`project_state`), the thermal state of a given energy (`grid_thermal_state`)
and the distance of f to its best thermal fit (`thermal_fit`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import optimize

from ..meanfield import orbits
from ..meanfield.equilibrium import EquilibriumError, thermal_beta, thermal_M0_from_energy
from ..meanfield.fourier import cos_coefficient
from .tabulated import PHASE_VOLUME_PER_JBAR

__all__ = [
    "ActionGrid",
    "action_grid",
    "solve_grid_M0",
    "grid_energy",
    "grid_entropy",
    "project_state",
    "grid_thermal_state",
    "thermal_fit",
]


@dataclass(frozen=True)
class ActionGrid:
    """Nodes J-bar_i and cell widths w_i (cells between midpoints; phase volume 4 pi w_i)."""

    jbar: np.ndarray
    width: np.ndarray

    @property
    def volume(self):
        return PHASE_VOLUME_PER_JBAR * self.width


def _feature_density(state, kappa):
    """sqrt|d^2 ln f/dh^2| |dh/dkappa|: large across the steep edges of f(h), zero for a
    thermal state (ln f linear in h)."""
    M0 = state.M0
    h = orbits.energy_from_kappa(kappa, M0)
    with np.errstate(divide="ignore"):
        logf = np.log(np.maximum(state.f_energy(h), 1e-300))
    d2 = np.gradient(np.gradient(logf, h), h)
    return np.sqrt(np.abs(d2)) * 4.0 * M0 * kappa


def _family_centred(cdf, kf, n_nodes):
    """Cell-centred positions u in (0, 1) of the nodes, n_lib of them on (0, u_s) and the rest
    on (u_s, 1), u_s = cdf(kappa = 1)/cdf(kappa_max): the separatrix is a face of the grid."""
    us = float(np.interp(1.0, kf, cdf)) / cdf[-1]
    n_lib = min(max(int(round(us * n_nodes)), 1), n_nodes - 1)
    lib = (np.arange(n_lib) + 0.5) / n_lib * us
    rot = us + (np.arange(n_nodes - n_lib) + 0.5) / (n_nodes - n_lib) * (1.0 - us)
    return np.concatenate((lib, rot))


def action_grid(
    M0,
    n_nodes,
    kappa_max,
    state=None,
    feature_share=0.25,
    separatrix_share=0.4,
    separatrix_band=0.0,
):
    """n_nodes cell-centred J-bar nodes on (0, J-bar(kappa_max)) at magnetisation M0.

    Uniform in kappa, except that with a state F(h) a share `feature_share` of the nodes is
    placed by equidistributing sqrt|d^2 ln F/dh^2| (the steep edges of a core-halo state,
    where the dielectric tensor needs ln f resolved) and a share `separatrix_share` with a
    density 1/(|kappa - 1| + 0.01) (the rotating orbits just above the separatrix span every
    frequency from 0 to Omega_0: they are the resonant partners of the core).  The density is
    smoothed over 0.02 in kappa, so that neighbouring cells differ little in size (the node
    quadrature is second order only on a smooth grid).  The nodes are cell-centred in each
    orbit family separately, so that the separatrix is a face of the grid: a node that fell
    arbitrarily close to it would carry the logarithmic dip of <cos theta> (and the
    1/(|kappa - 1| ln^3) derivative d<cos theta>/dM0) into the node quadratures of M0; with
    it, dM0 of the hot halo responded 2 % wrong at 150 nodes and its dF/dM0 scattered by a
    factor 2 from one n_nodes to the next (tests/test_relaxation_convergence.py).

    separatrix_band > 0: no node within |kappa - 1| < separatrix_band.  The nodes there (and
    those within half a cell of the band's edge) are replaced by one pair at J-bar_s -+ Delta,
    Delta the J-bar distance of kappa = 1 + separatrix_band from the separatrix (which stays a
    face): f has no structure inside the band, where the orbit-averaged theory does not hold
    (the fluctuating magnetisation of N particles moves the separatrix by |delta kappa| ~
    1/(M0 sqrt N)), while the band's resonances are all kept (the collision operator's
    sub-cells still span it).  The grid then has a few nodes fewer than n_nodes.
    """
    if n_nodes < 8 or not kappa_max > 1.0:
        raise ValueError(f"action grid: n_nodes = {n_nodes} must be >= 8, kappa_max > 1")
    u = (np.arange(n_nodes) + 0.5) / n_nodes
    kappa = u * kappa_max
    if state is not None:
        kf = np.linspace(0.0, kappa_max, 20001)
        uniform = 1.0 - feature_share - separatrix_share
        parts = [(uniform, np.ones_like(kf)), (separatrix_share, 1.0 / (np.abs(kf - 1.0) + 0.01))]
        dens = _feature_density(state, kf)
        if np.trapezoid(dens, kf) > 1e-12 * kappa_max:
            parts.append((feature_share, dens))
        else:  # thermal: no steep edge
            parts[0] = (uniform + feature_share, parts[0][1])
        density = sum(w * p / np.trapezoid(p, kf) for w, p in parts if w > 0)
        width = 0.02 / (kf[1] - kf[0])
        kernel = np.exp(-0.5 * (np.arange(-4 * width, 4 * width + 1) / width) ** 2)
        density = np.convolve(density, kernel / kernel.sum(), mode="same")
        cdf = np.concatenate(([0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(kf))))
        kappa = np.interp(_family_centred(cdf, kf, n_nodes) * cdf[-1], cdf, kf)
    kappa = np.where(np.abs(kappa - 1.0) < 1e-9, 1.0 + 1e-9, kappa)
    jbar = orbits.rescaled_action(kappa, M0)
    if separatrix_band > 0.0:
        jbar = _clear_separatrix_band(jbar, M0, separatrix_band)
    edges = np.concatenate(([0.0], 0.5 * (jbar[1:] + jbar[:-1]), [1.5 * jbar[-1] - 0.5 * jbar[-2]]))
    return ActionGrid(jbar, np.diff(edges))


def _clear_separatrix_band(jbar, M0, band):
    """The nodes outside |kappa - 1| < band (and half a cell beyond its edges), and one pair at
    J-bar_s -+ Delta, Delta = J-bar(1 + band) - J-bar_s (`action_grid`)."""
    js = orbits.jbar_separatrix(M0)
    delta = float(orbits.rescaled_action(np.array([1.0 + band]), M0)[0]) - js
    if not 0.0 < delta < min(js, jbar[-1] - js):
        raise ValueError(f"action grid: separatrix_band = {band} does not fit the grid")
    near = int(np.argmin(np.abs(np.abs(jbar - js) - delta)))
    spacing = np.diff(jbar)[min(near, jbar.size - 2)]
    keep = jbar[np.abs(jbar - js) >= delta + 0.5 * spacing]
    return np.unique(np.concatenate((keep, [js - delta, js + delta])))


def _node_c0(grid, M0):
    return cos_coefficient(0, orbits.kappa_from_rescaled_action(grid.jbar, M0))


def solve_grid_M0(grid, f, guess):
    """Self-consistent M0 = sum m_i <cos theta>_i / sum m_i of the grid state, nearest guess."""
    m = grid.volume * f
    mass = m.sum()

    def g(M):
        return float(np.dot(m, _node_c0(grid, M)) / mass - M)

    for half in (1e-3, 1e-2, 0.1, 0.5):
        lo, hi = max(guess - half, 1e-4), min(guess + half, 1.0 - 1e-9)
        if g(lo) * g(hi) < 0:
            return optimize.brentq(g, lo, hi, xtol=1e-15, rtol=1e-15)
    raise EquilibriumError(f"no self-consistent M0 near {guess} for the grid state")


def grid_energy(grid, f, M0):
    """Energy per particle u = sum m h / sum m + M0^2/2."""
    m = grid.volume * f
    h = orbits.energy_from_kappa(orbits.kappa_from_rescaled_action(grid.jbar, M0), M0)
    return float(np.dot(m, h) / m.sum() + 0.5 * M0**2)


def grid_entropy(grid, f):
    """S = -int f ln f dtheta dp = -sum m_i ln f_i."""
    m = grid.volume * f
    with np.errstate(divide="ignore", invalid="ignore"):
        return float(-np.sum(np.where(f > 0, m * np.log(f), 0.0)))


def project_state(state, grid):
    """f_i = F(h(J-bar_i; M0)) for a state F(h) (`state.f_energy`), with M0 solved
    self-consistently on the grid's quadrature and f normalised; returns (f, M0)."""

    def f_of(M):
        h = orbits.energy_from_kappa(orbits.kappa_from_rescaled_action(grid.jbar, M), M)
        return state.f_energy(h)

    def g(M):
        f = f_of(M)
        m = grid.volume * f
        return float(np.dot(m, _node_c0(grid, M)) / m.sum() - M)

    M0 = None
    for half in (1e-3, 1e-2, 0.05):
        lo, hi = max(state.M0 - half, 1e-4), min(state.M0 + half, 1.0 - 1e-9)
        if g(lo) * g(hi) < 0:
            M0 = optimize.brentq(g, lo, hi, xtol=1e-15, rtol=1e-15)
            break
    if M0 is None:
        raise EquilibriumError(f"no self-consistent M0 on the grid near M0 = {state.M0}")
    f = f_of(M0)
    f = f / np.sum(grid.volume * f)
    if np.any(f <= 0):
        raise EquilibriumError("the state vanishes at a grid node (ln f): lower kappa_max")
    return f, float(M0)


def grid_thermal_state(grid, u, M0_guess):
    """The thermal state f = C exp(-beta h) on the grid with energy per particle u and a
    self-consistent M0 (the end point of the evolution); returns (f, M0, beta)."""
    x0 = thermal_M0_from_energy(u) if M0_guess is None else M0_guess

    def state(M0, beta):
        h = orbits.energy_from_kappa(orbits.kappa_from_rescaled_action(grid.jbar, M0), M0)
        f = np.exp(-beta * (h - h.min()))
        return f / np.sum(grid.volume * f), h

    def residual(x):
        M0, beta = x
        f, h = state(M0, beta)
        m = grid.volume * f
        c0 = cos_coefficient(0, orbits.kappa_from_rescaled_action(grid.jbar, M0))
        return [np.dot(m, c0) - M0, np.dot(m, h) + 0.5 * M0**2 - u]

    sol = optimize.root(residual, [x0, thermal_beta(x0)], method="hybr", tol=1e-13)
    M0, beta = sol.x
    if not np.max(np.abs(residual(sol.x))) < 1e-11:
        raise EquilibriumError(f"no thermal state on the grid with u = {u}: {sol.message}")
    return state(M0, beta)[0], float(M0), float(beta)


def thermal_fit(grid, f, M0):
    """Weighted least-squares fit ln f = a - beta h over the grid; returns (beta, distance)
    with distance = max |f - exp(a - beta h)| / max f."""
    h = orbits.energy_from_kappa(orbits.kappa_from_rescaled_action(grid.jbar, M0), M0)
    w = grid.volume * f
    A = np.stack([np.ones_like(h), -h], axis=1) * np.sqrt(w)[:, None]
    coef, *_ = np.linalg.lstsq(A, np.log(f) * np.sqrt(w), rcond=None)
    fit = np.exp(coef[0] - coef[1] * h)
    return float(coef[1]), float(np.max(np.abs(f - fit)) / np.max(f))
