"""The grid on which the kinetic equations evolve f, and the state on it.

Cells are fixed in eta = kappa - 1, the orbit's signed distance to the separatrix
(`meanfield.separatrix`), not in J-bar.  At magnetisation M every orbit quantity is a function
of eta times a power of M: J-bar = sqrt(M) (4/pi + x^(eta)) (x^ the reduced offset from the
separatrix J-bar_s = 4 sqrt(M)/pi), cell widths sqrt(M) w^, energies h - M = M eps^(eta),
frequencies sqrt(M) Omega^(eta), and <cos theta> and the Fourier coefficients depend on eta
alone.  So the grid stretches uniformly in J-bar with sqrt(M) (J-bar = 0 stays put), the
separatrix is always a cell face, and the layer next to it can be graded geometrically in |eta|
down to 1e-30 and beyond: J-bar_s - J-bar ~ |eta| ln(1/|eta|) is carried as an offset, never
as a difference of J-bars.

Outside the layer |eta| > layer_eta_max, n_nodes nodes are placed by a density in kappa that
mixes a uniform part, a part packed round the separatrix and a part on the steep edges of the
initial f(h); inside it, layer_per_decade nodes per decade of |eta| on each side, down to the
pair at -+ layer_eta_min, with the separatrix the face between them.

Every cell quantity is a cell average (its integral over J-bar divided by its width): the
reduced energy eps^ = <2 eta (2 + eta)> by Gauss-Legendre quadrature in ln|eta| (in eta far
from the separatrix), <cos theta> as the difference of its primitive
(`separatrix.cos_primitive`) over the width.  With cell averages, the energy
u = sum_i m_i h_i + M^2/2 and the magnetisation M = sum_i m_i <cos theta>_i / sum_i m_i of a
piecewise-constant f are exact integrals, and dh_i/dM = -<cos theta>_i at fixed J-bar, so that
du/dM = 0 at the self-consistent M.

f(J-bar) is fixed while M changes (J is an adiabatic invariant): `solve_grid_M0` finds the M
self-consistent with f on the cells of the frame M_frame, and `remap` carries f from the cells
of one frame to those of another (f(J-bar) unchanged, mass conserved); next to the separatrix
the new cells are filled with what the moving separatrix sweeps in.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import optimize

from ..meanfield import orbits, separatrix
from ..meanfield.equilibrium import EquilibriumError, thermal_beta, thermal_M0_from_energy
from .tabulated import PHASE_VOLUME_PER_JBAR

__all__ = [
    "ActionGrid",
    "action_grid",
    "frame_offsets",
    "magnetisation_map",
    "solve_grid_M0",
    "remap",
    "grid_energy",
    "grid_entropy",
    "project_state",
    "grid_thermal_state",
    "thermal_fit",
]

#: J-bar_s / sqrt(M): the separatrix in reduced units
JS_HAT = 4.0 / np.pi
#: cells with both edges within this |eta| are integrated in ln|eta|
LOG_CELL = 0.2


@dataclass(frozen=True)
class ActionGrid:
    """Cells fixed in eta; reduced quantities (M = 1), scaled by `frame` methods.

    eta, eta_edges: node and cell-edge eta (increasing; the separatrix edge is eta = 0 at
    index `sep`); xhat, xhat_edges: reduced offsets (J-bar - J-bar_s)/sqrt(M); width_hat:
    reduced cell widths; eps_hat: cell averages of (h - M)/M; cos_avg: cell averages of
    <cos theta>; settings: how the grid was made."""

    eta: np.ndarray
    eta_edges: np.ndarray
    sep: int
    xhat: np.ndarray
    xhat_edges: np.ndarray
    width_hat: np.ndarray
    eps_hat: np.ndarray
    cos_avg: np.ndarray
    settings: dict

    @property
    def size(self):
        return self.eta.size

    def width(self, M):
        """Cell widths in J-bar at magnetisation M."""
        return np.sqrt(M) * self.width_hat

    def volume(self, M):
        """Phase volume 4 pi width of each cell at M."""
        return PHASE_VOLUME_PER_JBAR * self.width(M)

    def jbar(self, M):
        """Node J-bar at M (rounded next to the separatrix: for output and plotting only)."""
        return np.sqrt(M) * (JS_HAT + self.xhat)

    def jbar_edges(self, M):
        return np.sqrt(M) * (JS_HAT + self.xhat_edges)

    def energy_offset(self, M):
        """Cell-average h - M at M."""
        return M * self.eps_hat

    def kappa(self):
        return 1.0 + self.eta


def _feature_density(state, kappa):
    """sqrt|d^2 ln f/dh^2| |dh/dkappa|: large across the steep edges of f(h), zero for a
    thermal state (ln f linear in h)."""
    M0 = state.M0
    h = orbits.energy_from_kappa(kappa, M0)
    with np.errstate(divide="ignore"):
        logf = np.log(np.maximum(state.f_energy(h), 1e-300))
    d2 = np.gradient(np.gradient(logf, h), h)
    return np.sqrt(np.abs(d2)) * 4.0 * M0 * kappa


def _outer_density(M0, kappa_max, state, feature_share, separatrix_share):
    """(kf, density): the density in kappa (integral 1 over (0, kappa_max)) mixing a uniform
    part, a part 1/(|kappa - 1| + 0.01) round the separatrix and a part on the steep edges of
    the state's f(h), smoothed over 0.02 in kappa."""
    kf = np.linspace(0.0, kappa_max, 20001)
    uniform = 1.0 - feature_share - separatrix_share
    parts = [(uniform, np.ones_like(kf)), (separatrix_share, 1.0 / (np.abs(kf - 1.0) + 0.01))]
    dens = _feature_density(state, kf) if state is not None else np.zeros_like(kf)
    if np.trapezoid(dens, kf) > 1e-12 * kappa_max:
        parts.append((feature_share, dens))
    else:  # thermal: no steep edge
        parts[0] = (uniform + feature_share, parts[0][1])
    density = sum(w * p / np.trapezoid(p, kf) for w, p in parts if w > 0)
    width = 0.02 / (kf[1] - kf[0])
    kernel = np.exp(-0.5 * (np.arange(-4 * width, 4 * width + 1) / width) ** 2)
    density = np.convolve(density, kernel / kernel.sum(), mode="same")
    return kf, density / np.trapezoid(density, kf)


def _side_nodes(side, v_end, n_outer, kf, outer, eta_min, dlog_omega, min_per_decade):
    """|eta| of the nodes on one side (-1 librating, +1 rotating): at the integers of the
    cumulative node count from v = |eta| = eta_min, with the node density per unit v the sum of
    n_outer times the outer density, |d ln Omega/dv| / dlog_omega (a fixed resolution in
    ln Omega, which resolves the resonances n Omega = n' Omega' with the core's edges at every
    distance from the separatrix, where Omega -> 0 as 1/ln(1/|eta|)), and min_per_decade per
    decade of v below 1e-2 (so that the innermost pair sits at eta_min)."""
    far = np.linspace(0.02, v_end * (1.0 - 1e-9), 4000)
    near = np.geomspace(eta_min, 0.02, 4000)[:-1]
    v = np.concatenate((near, far))
    eta = side * v
    rho = n_outer * np.interp(1.0 + eta, kf, outer)
    if dlog_omega > 0:
        dlnom = np.abs(separatrix.dOmega_deta(eta, 1.0) / separatrix.frequency(eta, 1.0))
        rho = rho + dlnom / dlog_omega
    rho = rho + np.where(v < 1e-2, min_per_decade / (v * np.log(10.0)), 0.0)
    # cumulative count: trapezoid in ln v on the geometric part, in v beyond
    g = rho * v
    lnv = np.log(v)
    inc = np.where(
        np.arange(v.size - 1) < near.size - 1,
        0.5 * (g[1:] + g[:-1]) * np.diff(lnv),
        0.5 * (rho[1:] + rho[:-1]) * np.diff(v),
    )
    cum = np.concatenate(([0.0], np.cumsum(inc)))
    n = int(np.floor(cum[-1] - 0.5))
    targets = np.arange(n + 1, dtype=float)
    # interpolate ln v in the count (v spans many decades next to the separatrix)
    nodes = np.exp(np.interp(targets, cum, lnv))
    nodes[0] = eta_min
    return nodes[nodes < v_end * (1.0 - 1e-12)]


def action_grid(
    M0,
    n_nodes,
    kappa_max,
    state=None,
    feature_share=0.25,
    separatrix_share=0.4,
    layer_eta_min=1e-24,
    dlog_omega=0.02,
    min_per_decade=1.0,
):
    """The grid (`ActionGrid`).  On each side of the separatrix, nodes at a density in
    |eta| = |kappa - 1| that adds (`_side_nodes`): n_nodes times a density in kappa (uniform,
    with shares packed on the steep edges of the state's f(h) and round the separatrix); a
    fixed resolution dlog_omega in ln Omega (Omega -> 0 only logarithmically at the
    separatrix, so that this grades the layer next to it geometrically-and-more in |eta|); and
    min_per_decade nodes per decade below |eta| = 1e-2, down to the innermost pair at
    -+ layer_eta_min (no node closer to the separatrix).  M0 sets where the state's edges lie
    in kappa; the grid itself is M-free."""
    if n_nodes < 8 or not kappa_max > 1.0:
        raise ValueError(f"action grid: n_nodes = {n_nodes} must be >= 8, kappa_max > 1")
    if not 1e-300 <= layer_eta_min < 0.02:
        raise ValueError(f"action grid: layer_eta_min = {layer_eta_min} must lie in [1e-300, 0.02)")
    if not dlog_omega >= 0 or not min_per_decade > 0:
        raise ValueError(
            f"action grid: dlog_omega = {dlog_omega} must be >= 0 and min_per_decade = "
            f"{min_per_decade} > 0"
        )
    kf, outer = _outer_density(M0, kappa_max, state, feature_share, separatrix_share)
    args = (n_nodes, kf, outer, layer_eta_min, dlog_omega, min_per_decade)
    lib = _side_nodes(-1.0, 1.0, *args)
    rot = _side_nodes(+1.0, kappa_max - 1.0, *args)
    eta = np.concatenate((-lib[::-1], rot))
    return _grid_from_nodes(
        eta,
        dict(
            n_nodes=int(n_nodes),
            kappa_max=float(kappa_max),
            feature_share=float(feature_share),
            separatrix_share=float(separatrix_share),
            layer_eta_min=float(layer_eta_min),
            dlog_omega=float(dlog_omega),
            min_per_decade=float(min_per_decade),
        ),
    )


def _edges_between(eta):
    """Cell edges between consecutive nodes (eta increasing, none zero): the separatrix (0)
    between the last librating and the first rotating node, geometric means of |eta| between
    nodes of one side within LOG_CELL, midpoints in the reduced offset elsewhere."""
    a, b = eta[:-1], eta[1:]
    same = np.sign(a) == np.sign(b)
    small = same & (np.maximum(np.abs(a), np.abs(b)) <= LOG_CELL)
    geo = np.sign(a) * np.sqrt(np.abs(a) * np.abs(b))
    xa, xb = separatrix.jbar_offset(a, 1.0), separatrix.jbar_offset(b, 1.0)
    mids = np.empty_like(a)
    far = same & ~small
    if np.any(far):
        mids[far] = separatrix.eta_from_jbar_offset(0.5 * (xa[far] + xb[far]), 1.0)
    mids[small] = geo[small]
    mids[~same] = 0.0
    return mids


def _grid_from_nodes(eta, settings):
    eta = np.asarray(eta, dtype=float)
    if np.any(eta == 0.0) or np.any(np.diff(eta) <= 0) or eta[0] <= -1.0:
        raise ValueError("grid nodes must be distinct, increasing, non-zero and above eta = -1")
    if not (eta[0] < 0.0 < eta[-1]):
        raise ValueError("the grid needs nodes on both sides of the separatrix")
    inner = _edges_between(eta)
    xn = separatrix.jbar_offset(eta, 1.0)
    x_top = xn[-1] + 0.5 * (xn[-1] - xn[-2])
    top = float(separatrix.eta_from_jbar_offset(np.array([x_top]), 1.0)[0])
    edges = np.concatenate(([-1.0], inner, [top]))
    sep = int(np.flatnonzero(edges == 0.0)[0])
    xe = _offset_with_separatrix(edges)
    width = np.diff(xe)
    if not np.all(width > 0):
        raise FloatingPointError("a grid cell has no width")
    P = _cos_primitive_with_separatrix(edges)
    cos_avg = np.diff(P) / width
    eps_hat = _cell_average(edges, lambda e: 2.0 * e * (2.0 + e))
    return ActionGrid(eta, edges, sep, xn, xe, width, eps_hat, cos_avg, settings)


def _offset_with_separatrix(eta):
    """Reduced offsets of eta (0 at eta = 0, -4/pi at eta = -1: J-bar = 0)."""
    eta = np.asarray(eta, dtype=float)
    out = np.zeros_like(eta)
    bottom = eta <= -1.0
    ok = (eta != 0.0) & ~bottom
    out[ok] = separatrix.jbar_offset(eta[ok], 1.0)
    out[bottom] = -JS_HAT
    return out


def _cos_primitive_with_separatrix(eta):
    """P^ = int from the separatrix of <cos theta> dJ-bar^ at eta (0 at 0; at eta = -1, the
    limit kappa -> 0: -(16/3)/(4 pi) (p K + (2m - 1) E - 1) with m = 0)."""
    eta = np.asarray(eta, dtype=float)
    out = np.zeros_like(eta)
    bottom = eta <= -1.0
    ok = (eta != 0.0) & ~bottom
    out[ok] = separatrix.cos_primitive(eta[ok], 1.0)
    # kappa = 0: p = 1, K = E = pi/2: 4 pi P = (16/3)(pi/2 - pi/2 - 1) = -16/3
    out[bottom] = -16.0 / 3.0 / (4.0 * np.pi)
    return out


_GL8 = np.polynomial.legendre.leggauss(8)


def _cell_average(edges, g, order=8):
    """Averages over J-bar of g(eta) on each cell [edges_i, edges_i+1] (reduced units): Gauss-
    Legendre in ln|eta| for cells within LOG_CELL of the separatrix (the cells that end on it
    on [ln|e| - 60, ln|e|], in 20 panels: the integrand falls as eta^2), in eta elsewhere."""
    x, w = np.polynomial.legendre.leggauss(order)
    lo, hi = edges[:-1], edges[1:]
    out = np.empty(lo.size)
    for i, (a, b) in enumerate(zip(lo, hi, strict=True)):
        if a == 0.0 or b == 0.0:
            e = b if a == 0.0 else a
            u_edges = np.linspace(np.log(abs(e)) - 60.0, np.log(abs(e)), 21)
            u = (
                0.5 * (u_edges[:-1, None] + u_edges[1:, None]) + 0.5 * np.diff(u_edges)[:, None] * x
            ).ravel()
            wu = (0.5 * np.diff(u_edges)[:, None] * w).ravel()
            eta = np.sign(e) * np.exp(u)
            jac = wu * np.abs(eta) * separatrix.djbar_deta(eta, 1.0)
        elif max(abs(a), abs(b)) <= LOG_CELL:
            ua, ub = np.log(abs(a)), np.log(abs(b))
            u = 0.5 * (ua + ub) + 0.5 * (ub - ua) * x
            eta = np.sign(a) * np.exp(u)
            jac = 0.5 * abs(ub - ua) * w * np.abs(eta) * separatrix.djbar_deta(eta, 1.0)
        else:
            eta = 0.5 * (a + b) + 0.5 * (b - a) * x
            jac = 0.5 * (b - a) * w * separatrix.djbar_deta(np.maximum(eta, -1.0 + 1e-300), 1.0)
        out[i] = np.sum(jac * g(eta)) / np.sum(jac)
    return out


def frame_offsets(grid, M_cells, M):
    """Reduced offsets, in the frame of magnetisation M, of the cell edges of the frame M_cells
    (the same J-bar): x^ rho + (4/pi)(rho - 1), rho = sqrt(M_cells/M), with rho - 1 formed
    without cancellation."""
    rho_m1 = (M_cells - M) / (np.sqrt(M) * (np.sqrt(M_cells) + np.sqrt(M)))
    return grid.xhat_edges * (1.0 + rho_m1) + JS_HAT * rho_m1


def _cos_primitive_at_offsets(y, guess_eta):
    """P^ at reduced offsets y (0 at 0; J-bar <= 0 at or below -4/pi)."""
    y = np.asarray(y, dtype=float)
    out = np.zeros_like(y)
    ok = (y != 0.0) & (y > -JS_HAT)
    if np.any(ok):
        eta = separatrix.eta_from_jbar_offset(y[ok], 1.0, guess=guess_eta[ok])
        out[ok] = separatrix.cos_primitive(eta, 1.0)
    out[y <= -JS_HAT] = -16.0 / 3.0 / (4.0 * np.pi)
    return out


def magnetisation_map(grid, f, M_cells, M):
    """F(M) = int f <cos theta>(J-bar; M) / int f for f on the cells of the frame M_cells, f(J-bar)
    held fixed: the cell integrals as differences of <cos theta>'s primitive at the cells' edges
    seen from the separatrix of M.  The self-consistent M0 is the fixed point F(M0) = M0."""
    f = np.asarray(f, dtype=float)
    mass_hat = np.sqrt(M_cells) * np.sum(f * grid.width_hat)
    if M == M_cells:
        return float(np.dot(f, grid.cos_avg * grid.width_hat) / np.sum(f * grid.width_hat))
    y = frame_offsets(grid, M_cells, M)
    P = _cos_primitive_at_offsets(y, grid.eta_edges)
    return float(np.sqrt(M) * np.dot(f, np.diff(P)) / mass_hat)


def solve_grid_M0(grid, f, M_cells, guess=None):
    """The M self-consistent with f on the cells of the frame M_cells, f(J-bar) held fixed:
    the root of `magnetisation_map`(M) - M nearest the guess."""
    guess = M_cells if guess is None else guess
    known = {}  # brentq evaluates the bracket's ends again

    def g(M):
        if M not in known:
            known[M] = magnetisation_map(grid, f, M_cells, M) - M
        return known[M]

    for half in (1e-4, 1e-3, 1e-2, 0.1, 0.5):
        lo, hi = max(guess - half, 1e-4), min(guess + half, 1.0 - 1e-9)
        if g(lo) * g(hi) < 0:
            return optimize.brentq(g, lo, hi, xtol=1e-15, rtol=1e-15)
    raise EquilibriumError(f"no self-consistent M0 near {guess} for the grid state")


def _limited_slopes(f, centre):
    """Slopes of f between cell centres (reduced offsets of one frame), limited by the
    monotonised-central rule, so that the linear pieces create no new extremum and keep f > 0
    within each cell; zero in the end cells."""
    d = np.diff(f) / np.diff(centre)
    s = np.zeros_like(f)
    left, right = d[:-1], d[1:]
    central = (f[2:] - f[:-2]) / (centre[2:] - centre[:-2])
    same = left * right > 0
    mag = np.minimum(np.minimum(2.0 * np.abs(left), 2.0 * np.abs(right)), np.abs(central))
    s[1:-1] = np.where(same, np.sign(central) * mag, 0.0)
    return s


def remap(grid, f, M_from, M_to):
    """f on the cells of the frame M_to from f on the cells of the frame M_from, f(J-bar)
    fixed: the old f is reconstructed linearly in each old cell (limited slopes, the cell's
    mass kept) and integrated over each new cell's overlap with the old cells; a new cell
    inside one old cell takes the reconstruction's mean over it.  Second order in the cell
    width, so that the energy at fixed f(J-bar) changes only at O(shift x width^2); the total
    mass is conserved exactly (the part beyond the top cell, where f is negligible, is put back
    by a uniform factor).  Offsets are compared as offsets, never through J-bar, so that the
    cells next to the separatrix are filled with the old f at the J-bar they now cover."""
    f = np.asarray(f, dtype=float)
    if M_from == M_to:
        return f.copy()
    rho = np.sqrt(M_from / M_to)
    y = frame_offsets(grid, M_from, M_to)  # old edges in the new frame
    x = grid.xhat_edges
    n = f.size
    centre_old = 0.5 * (grid.xhat_edges[1:] + grid.xhat_edges[:-1])
    slope = _limited_slopes(f, centre_old) / rho  # per unit offset of the new frame
    cy = 0.5 * (y[1:] + y[:-1])  # old centres in the new frame

    def piece(i, a, b):
        """int over [a, b] (inside old cells i) of their linear reconstruction."""
        return (b - a) * (f[i] + slope[i] * (0.5 * (a + b) - cy[i]))

    k = np.clip(np.searchsorted(y, x, side="right") - 1, 0, n - 1)
    lo_k, hi_k = k[:-1], k[1:]
    xm = 0.5 * (x[1:] + x[:-1])
    out = f[lo_k] + slope[lo_k] * (xm - cy[lo_k])
    j = np.flatnonzero(hi_k != lo_k)  # new cells that span old edges
    if j.size:
        mass = np.diff(y) * f
        cum = np.concatenate(([0.0], np.cumsum(mass)))
        a, b = lo_k[j], hi_k[j]
        top = np.minimum(x[j + 1], y[-1])
        m = piece(a, x[j], y[a + 1]) + (cum[b] - cum[a + 1])
        m = np.where(top > y[b], m + piece(b, y[b], top), m)
        out[j] = np.maximum(m, 0.0) / grid.width_hat[j]
    out[x[:-1] >= y[-1]] = 0.0  # beyond the old top edge: f = 0
    out = np.maximum(out, 0.0)
    old_mass = np.sqrt(M_from) * np.sum(f * grid.width_hat)
    new_mass = np.sqrt(M_to) * np.sum(out * grid.width_hat)
    return out * (old_mass / new_mass)


def grid_energy(grid, f, M):
    """Energy per particle u = M + sum m_i (h_i - M) / sum m_i + M^2/2 (cell averages)."""
    m = grid.width_hat * f
    return float(M + M * np.dot(m, grid.eps_hat) / m.sum() + 0.5 * M**2)


def grid_entropy(grid, f, M):
    """S = -int f ln f dtheta dp = -sum m_i ln f_i."""
    m = grid.volume(M) * f
    with np.errstate(divide="ignore", invalid="ignore"):
        return float(-np.sum(np.where(f > 0, m * np.log(f), 0.0)))


def grid_mass(grid, f, M):
    return float(np.sum(grid.volume(M) * f))


def project_state(state, grid):
    """f_i = F(h_i(M)) for a state F(h) (`state.f_energy`) at the cell-average energies, with
    M solved self-consistently on the grid's cells and f normalised; returns (f, M)."""

    def f_of(M):
        return state.f_energy(M * (1.0 + grid.eps_hat))

    def g(M):
        m = grid.width_hat * f_of(M)
        return float(np.dot(m, grid.cos_avg) / m.sum() - M)

    M0 = None
    for half in (1e-3, 1e-2, 0.05):
        lo, hi = max(state.M0 - half, 1e-4), min(state.M0 + half, 1.0 - 1e-9)
        if g(lo) * g(hi) < 0:
            M0 = optimize.brentq(g, lo, hi, xtol=1e-15, rtol=1e-15)
            break
    if M0 is None:
        raise EquilibriumError(f"no self-consistent M0 on the grid near M0 = {state.M0}")
    f = f_of(M0)
    f = f / np.sum(grid.volume(M0) * f)
    if np.any(f <= 0):
        raise EquilibriumError("the state vanishes at a grid node (ln f): lower kappa_max")
    return f, float(M0)


def grid_thermal_state(grid, u, M0_guess):
    """The thermal state f_i = C exp(-beta (h_i - M)) on the grid with energy per particle u
    and a self-consistent M (the end point of the evolution); returns (f, M, beta)."""
    x0 = thermal_M0_from_energy(u) if M0_guess is None else M0_guess

    def state(M, beta):
        e = grid.eps_hat * M
        f = np.exp(-beta * (e - e.min()))
        return f / np.sum(grid.volume(M) * f)

    def residual(x):
        M, beta = x
        f = state(M, beta)
        m = grid.width_hat * f
        return [np.dot(m, grid.cos_avg) / m.sum() - M, grid_energy(grid, f, M) - u]

    sol = optimize.root(residual, [x0, thermal_beta(x0)], method="hybr", tol=1e-13)
    M, beta = sol.x
    if not np.max(np.abs(residual(sol.x))) < 1e-11:
        raise EquilibriumError(f"no thermal state on the grid with u = {u}: {sol.message}")
    return state(M, beta), float(M), float(beta)


def thermal_fit(grid, f, M):
    """Weighted least-squares fit ln f = a - beta (h - M) over the grid; returns (beta,
    distance) with distance = max |f - exp(a - beta (h - M))| / max f."""
    e = grid.eps_hat * M
    w = grid.width_hat * f
    A = np.stack([np.ones_like(e), -e], axis=1) * np.sqrt(w)[:, None]
    coef, *_ = np.linalg.lstsq(A, np.log(f) * np.sqrt(w), rcond=None)
    fit = np.exp(coef[0] - coef[1] * e)
    return float(coef[1]), float(np.max(np.abs(f - fit)) / np.max(f))
