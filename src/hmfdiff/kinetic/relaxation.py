"""Collisional relaxation f(J-bar, tau) by the Landau and Lenard-Balescu equations (eq. hmflb,
paper's Conclusions), with a self-consistent magnetisation.

State.  f on a grid of cells fixed in eta = kappa - 1, the orbit's signed distance to the
separatrix (`hmfdiff.kinetic.grid.action_grid`: packed on the steep edges of the initial f and
graded geometrically in |eta| down to layer_eta_min next to the separatrix); at magnetisation
M the cells' J-bar scale as sqrt(M) and the separatrix J-bar_s = 4 sqrt(M)/pi is always a face
(the *frame* M).  J is an adiabatic invariant of the slow change of M0, so f(J-bar) is held
fixed while M0 is re-solved from M0 = int f <cos theta> / int f after every step
(`grid.solve_grid_M0`, cell integrals of <cos theta> at the new M0), and f is then carried to
the cells of the new frame (`grid.remap`, f(J-bar) unchanged, mass conserved): the separatrix
sweeps through f, and the cells next to it are filled with what it sweeps in.  f stays even in
p; the current leaving the libration band splits equally between the two directions of
rotation.

Energy per particle u = sum_i m_i h_i(M0) + M0^2/2 with cell-average energies h_i.  At fixed M0
the collision step conserves sum m h exactly (`collision`); the M0 update at fixed f(J-bar)
changes u only at second order in the change of M0, because du/dM0 = M0 - sum m <cos theta> =
0 at the self-consistent M0; the remap changes it by its interpolation error.

Time stepping.  Backward Euler in ln f with the collision weights (orbits, resonances, dielectric
factor) frozen over a step, solved by Newton to rounding: it is stable for this stiff problem,
conserves mass, and S = -sum m ln f cannot decrease over a step (S is concave and the frozen
operator produces entropy for any f).  The step is controlled by step doubling: the difference
between one step and two half steps, relative to max f, is kept below `rtol`.
"""

from __future__ import annotations

import inspect
import time
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy import linalg

from .collision import CollisionOperator, geometry, jacobian_assembly, resonance_events
from .dielectric import DielectricTensor
from .grid import (
    JS_HAT,
    action_grid,
    grid_energy,
    grid_entropy,
    grid_mass,
    grid_thermal_state,
    magnetisation_map,
    project_state,
    remap,
    solve_grid_M0,
    thermal_fit,
)
from .tabulated import PHASE_VOLUME_PER_JBAR, TabulatedState

__all__ = [
    "EQUATIONS",
    "RelaxationSettings",
    "evolve",
]

EQUATIONS = ("landau", "lenard_balescu")
#: how the resonances read d ln f/dh in a face (`collision._derivative_at`): 'interpolated'
#: (second order in the relaxation times, but each resonance's current is shared between two
#: faces, so that the local rates carry node-to-node noise that does not fall with the grid);
#: 'mixed' (read the same way, the current handed to the face the resonance lies in: smooth,
#: second-order face currents, but relaxation times that converge more slowly: ch2*'s Landau
#: tau_R +4.4 % from the default grid to 1.5 times its nodes, docs/reference/
#: separatrix_layer.txt); 'face' (the face's own quotient: first order)
DERIVATIVE = "interpolated"
#: ln f is kept above this (f = 0 cannot be represented in ln f)
LOG_FLOOR = -700.0


@dataclass
class RelaxationSettings:
    """Numerical settings of one evolution (every one is stored with the result)."""

    equation: str = "lenard_balescu"
    n_nodes: int = 600
    kappa_max: float = 3.0
    n_max: int = 6
    l_max: int = 6
    rtol: float = 1e-3
    tau_max: float = 1e4
    thermal_tol: float = 1e-4
    dtau_first: float = 0.0  # 0: from the initial rate
    max_steps: int = 2000
    flux_times: tuple = (0.0,)
    #: tau_early of dM0dtau_early = (M0(tau_early) - M0(0)) / tau_early (a step ends there)
    early_window: float = 0.5
    #: the step tolerance while tau < early_window (None: rtol): M0's early rate is what is left
    #: of the layer's fast transient, and backward Euler's error in it falls only as
    #: sqrt(rtol) (hot halo, Landau, default grid: 1.14e-4, 1.38e-4, 1.50e-4, 1.54e-4 at
    #: 1e-3, 1e-4, 1e-5, 1e-6)
    early_rtol: float | None = 1e-5
    feature_share: float = 0.25
    separatrix_share: float = 0.4
    #: the grid next to the separatrix (`grid.action_grid`): a resolution dlog_omega in
    #: ln Omega, at least min_per_decade nodes per decade of |kappa - 1| below 1e-2, down to
    #: the innermost pair at kappa = 1 -+ layer_eta_min (no node closer to the separatrix)
    layer_eta_min: float = 1e-16
    #: None: 6 / n_nodes (the grid refines as a whole with n_nodes)
    dlog_omega: float | None = None
    min_per_decade: float = 1.0
    eps_panels: int = 48
    eps_order: int = 20
    eps_refresh: float = 0.01

    def __post_init__(self):
        if self.equation not in EQUATIONS:
            raise ValueError(f"equation = {self.equation!r}: must be one of {EQUATIONS}")
        if not self.rtol > 0 or not self.tau_max > 0:
            raise ValueError("rtol and tau_max must be > 0")
        if self.early_rtol is not None and not self.early_rtol > 0:
            raise ValueError(f"early_rtol = {self.early_rtol!r}: must be > 0")
        if not self.early_window > 0:
            raise ValueError(f"early_window = {self.early_window!r}: must be > 0")
        if not 1e-300 <= self.layer_eta_min < 0.02:
            raise ValueError(f"layer_eta_min = {self.layer_eta_min!r}: must be in [1e-300, 0.02)")
        if self.dlog_omega is None:
            self.dlog_omega = 6.0 / self.n_nodes
        if not self.dlog_omega >= 0:
            raise ValueError(f"dlog_omega = {self.dlog_omega!r}: must be >= 0")
        if not self.min_per_decade > 0:
            raise ValueError(f"min_per_decade = {self.min_per_decade!r}: must be > 0")

    def as_dict(self):
        return {k: getattr(self, k) for k in self.__dataclass_fields__}

    @classmethod
    def from_mapping(cls, equation, mapping):
        """Settings from a config mapping (unknown keys refused, naming them)."""
        if "separatrix_band" in mapping:
            raise ValueError(
                "relaxation settings: separatrix_band was renamed layer_eta_min (the innermost "
                "grid nodes sit at kappa = 1 -+ layer_eta_min; none closer to the separatrix)"
            )
        unknown = sorted(set(mapping) - set(cls.__dataclass_fields__))
        if unknown:
            raise ValueError(f"relaxation settings: unknown key(s) {unknown}")
        kw = dict(mapping)
        if "flux_times" in kw:
            kw["flux_times"] = tuple(float(t) for t in kw["flux_times"])
        return cls(equation=equation, **kw)


@dataclass
class _History:
    tau: list = field(default_factory=list)
    f: list = field(default_factory=list)
    M0: list = field(default_factory=list)
    u: list = field(default_factory=list)
    S: list = field(default_factory=list)
    mass: list = field(default_factory=list)
    beta_fit: list = field(default_factory=list)
    distance: list = field(default_factory=list)


def _call(op, name, d, level):
    """op.name(d, level) for the collision operator (ln f = level + d); operators of the testing
    seam whose methods take ln f alone get level + d."""
    method = getattr(op, name)
    try:
        two = len(inspect.signature(method).parameters) >= 2
    except (TypeError, ValueError):
        two = False
    return method(d, level) if two else method(level + d)


def _jacobian(op, d, level):
    dense = getattr(op, "jacobian_dense", None)
    if dense is not None:
        return _call(op, "jacobian_dense", d, level)
    return _call(op, "jacobian", d, level).toarray()


def _newton_matrix(vol, level, d, dt, gauge, scales, rate, jac):
    """LU of the Newton matrix of the backward-Euler step in the unknowns (Delta d_j / s_j,
    Delta level in the gauge node's column), columns multiplied by the offsets' natural scales
    s_j and rows divided by their largest entry (returned with the LU); None if exactly
    singular.  rate, jac: the rate and its dense Jacobian at ln f = level + d (`_jacobian`).
    Dense LU: the collision operator couples every node to its resonant partners (~12 % of
    the matrix filled at 600 nodes), where LAPACK factorises 4x faster than SuperLU."""
    m = vol * np.exp(level + d)
    n = m.size
    A = np.multiply(jac, -dt, order="F")  # diag(m) - dt jac in LAPACK's order (no copy there;
    # `CollisionOperator.jacobian_dense` gives jac in it)
    diag = np.arange(n)
    A[diag, diag] += m
    if gauge is not None:
        A[:, gauge] = m - dt * rate  # d r / d level
    A *= scales[None, :]
    rows = np.maximum(A.max(axis=1), -A.min(axis=1))  # row equilibration (the nodes next to
    rows = np.where(rows > 0, rows, 1.0)  # the separatrix have tiny masses, enormous couplings)
    A /= rows[:, None]
    with warnings.catch_warnings():  # an exactly singular matrix is reported by the caller
        warnings.simplefilter("ignore", linalg.LinAlgWarning)
        lu, piv = linalg.lu_factor(A, overwrite_a=True, check_finite=False)
    if np.any(np.diag(lu) == 0.0):
        return None
    return lu, piv, rows


def _backward_euler_offsets(
    op, vol, level0, d0, dt, gauge, scales, tol=1e-13, max_iter=50, at_start=None
):
    """Solve vol f - vol f0 = dt rate(f) for ln f = level + d by damped Newton iterations
    that reuse their factorised matrix while it contracts the correction by at least half an
    iteration (and refactorise otherwise).  With a gauge node, d stays 0 there and the level
    is an unknown, so that the offsets d next to the separatrix, where ln f of neighbouring
    cells differ below its own rounding, keep their digits; scales: the offsets' natural size
    per node (the unknowns are Delta d / scales); at_start: None or (rate, Jacobian) at the
    start (`_rate_jacobian`), when another solve from there has them.  Returns (level, d,
    converged)."""
    m0 = vol * np.exp(level0 + d0)
    level, d = float(level0), d0.copy()
    lu = None
    last = np.inf
    age = 0  # iterations since the matrix was factorised
    for it in range(max_iter):
        f = np.exp(level + d)
        jac = None
        if it == 0 and at_start is not None:
            rate, jac = at_start
        else:
            rate = _call(op, "rate", d, level)
        if lu is None:
            if jac is None:
                jac = _jacobian(op, d, level)
            lu = _newton_matrix(vol, level, d, dt, gauge, scales, rate, jac)
            if lu is None:  # exactly singular
                return level, d, False
            last, age = np.inf, 0
        else:
            age += 1
        r = vol * f - m0 - dt * rate
        w = linalg.lu_solve(lu[:2], -r / lu[2], check_finite=False) * scales
        if not np.all(np.isfinite(w)):
            return level, d, False
        dlevel = 0.0
        if gauge is not None:
            dlevel, w[gauge] = w[gauge], 0.0
        change = np.abs(dlevel + w)  # |Delta ln f| per node
        size = np.max(change)
        step = min(1.0, 2.0 / max(size, 1e-300))
        level += step * dlevel
        d = d + step * w
        floor = LOG_FLOOR - level
        d = np.maximum(d, floor)
        # converged: |Delta ln f| f below tol max f, except where the offsets are below 1e-6
        # of their natural size (next to the separatrix, where ln f is set by a flux balance
        # that double precision resolves only to ~1e-10 of the offsets: their mass is nil)
        rel = (scales < 1e-8) & (np.abs(w) <= 1e-6 * scales)
        # with a reused matrix the iteration contracts only linearly: its last correction must
        # fall 100 times lower than a fresh Newton step's for the same error
        bound = tol if age == 0 else 1e-2 * tol
        if step == 1.0 and np.max(np.where(rel, 0.0, change * f)) <= bound * np.max(f):
            return level, d, True
        if step < 1.0 or size > 0.5 * last:  # slow: a fresh Jacobian next
            lu = None
        last = size
    return level, d, False


def _rate_jacobian(op, d, level):
    """The rate and its dense Jacobian at ln f = level + d."""
    return _call(op, "rate", d, level), _jacobian(op, d, level)


def _doubling_solves(op, vol, start, dt, scales, memo):
    """The step doubling's backward-Euler solves from `start` (a `_LogDensity`): one step dt
    and two half steps; returns (one, two, converged).  The step and the first half step begin
    at the same state with the same frozen operator: the rate and Jacobian there are evaluated
    once (kept in memo, a dict that lives as long as start and op, for a retried step)."""
    if "start" not in memo:
        memo["start"] = _rate_jacobian(op, start.d, start.level)

    def solve(s, h, at_start=None):
        level, d, ok = _backward_euler_offsets(
            op, vol, s.level, s.d, h, s.gauge, scales, at_start=at_start
        )
        return _LogDensity(s.grid, level, d), ok

    one, ok = solve(start, dt, memo["start"])
    if not ok:
        return one, start, False
    half, ok = solve(start, 0.5 * dt, memo["start"])
    if not ok:
        return one, start, False
    two, ok = solve(half, 0.5 * dt)
    return one, two, ok


def _backward_euler(op, vol, y0, dt, tol=1e-13, max_iter=50):
    """Solve vol e^y - vol e^y0 = dt * rate(y) by damped Newton (`_backward_euler_offsets`
    without a gauge); returns (y, converged)."""
    _, y, ok = _backward_euler_offsets(
        op, vol, 0.0, np.asarray(y0, float), dt, None, np.ones(np.size(y0)), tol, max_iter
    )
    return y, ok


def _interpolated_dielectric(tensor, geom, M, n_max, l_max):
    """eps_cc, eps_ss tabulated once and interpolated linearly in omega: at the faces'
    frequencies n nu_a (dense where the grid is) below 1.2 l_max Omega_0, where the librating
    poles make eps change fast; on 200 geometric points above, where only rotating orbits
    contribute and eps is smooth; on a geometric grid below 0.05 Omega_0 (eps_ss ~ eps_ss(0) +
    c omega^2 there)."""
    Om0 = np.sqrt(M)
    faces = (np.arange(1, n_max + 1)[:, None] * (Om0 * geom.nu)[None, :]).ravel()
    cut = 1.2 * l_max * Om0
    top = max(faces.max(), cut) * 1.01
    om = np.unique(
        np.concatenate(
            [
                np.geomspace(1e-5 * Om0, 0.05 * Om0, 40),
                faces[(faces < cut) & (faces > 1e-5 * Om0)],
                np.geomspace(cut, top, 200),
            ]
        )
    )
    e_cc, e_ss = tensor(om)

    def eps(w):
        out = []
        for e in (e_cc, e_ss):
            out.append(np.interp(w, om, e.real) + 1j * np.interp(w, om, e.imag))
        return out[0], out[1]

    return eps


def dielectric_nodes(grid):
    """The nodes a tabulated f for the dielectric tensor keeps: those whose J-bar differs from
    the separatrix's by more than 1e-9 of it (the layer's mass is negligible there, and its
    J-bar would round to J-bar_s)."""
    return np.flatnonzero(np.abs(grid.xhat) > 1e-9 * JS_HAT)


class _Dielectric:
    """eps(omega) of the grid state, recomputed only when f has changed by more than
    `refresh` (relative to max f) since it was last computed (the weights then lag by less)."""

    def __init__(self, settings):
        self.s = settings
        self.f_ref = None
        self.eps = None
        self.n_evaluations = 0

    def __call__(self, grid, f, M, geom):
        s = self.s
        if self.f_ref is not None:
            change = np.max(np.abs(f - self.f_ref)) / np.max(self.f_ref)
            if change <= s.eps_refresh:
                return self.eps
        # the dielectric tensor of f(J-bar) with its own self-consistent M0 (eps_ss(0) = 0
        # needs it: with the grid's M0, which differs by the quadrature error, 1/|eps_ss|^2
        # at low frequency would be wrong by orders of magnitude)
        keep = dielectric_nodes(grid)
        tab = TabulatedState(grid.jbar(M)[keep], np.maximum(f[keep], np.exp(LOG_FLOOR)), M0_guess=M)
        tensor = DielectricTensor(tab, l_max=s.l_max, n_panels=s.eps_panels, order=s.eps_order)
        self.eps = _interpolated_dielectric(tensor, geom, M, s.n_max, s.l_max)
        self.f_ref = f.copy()
        self.n_evaluations += 1
        return self.eps


class Kinetics:
    """The grid, its reduced geometry and resonances (computed once), and the collision
    operator of a state f at magnetisation M (`operator`)."""

    def __init__(self, grid, settings):
        self.grid = grid
        self.settings = settings
        self.geom = geometry(grid)
        self.events = resonance_events(self.geom, settings.n_max, derivative=DERIVATIVE)
        self.dielectric = _Dielectric(settings)
        A = self.events.A
        self.assembly = jacobian_assembly(
            (self.events.C @ self.geom.D).tocsr(),
            self.events.P,
            None if A is None else (A @ self.geom.D).tocsr(),
        )

    def operator(self, f, M):
        eps = None
        if self.settings.equation == "lenard_balescu":
            eps = self.dielectric(self.grid, f, M, self.geom)
        return CollisionOperator(self.geom, self.events, M, eps, self.assembly)


def make_grid(state, settings):
    """The grid of `settings` for the initial state."""
    s = settings
    return action_grid(
        state.M0,
        s.n_nodes,
        s.kappa_max,
        state,
        s.feature_share,
        s.separatrix_share,
        s.layer_eta_min,
        s.dlog_omega,
        s.min_per_decade,
    )


def face_jbar(grid, M):
    """J-bar of the faces between nodes (the current's positions) at M."""
    return np.sqrt(M) * (JS_HAT + 0.5 * (grid.xhat[1:] + grid.xhat[:-1]))


def _floor(f):
    return np.maximum(f, np.exp(LOG_FLOOR))


def early_rate(tau, M0, window):
    """(M0(window) - M0(0)) / window, M0 interpolated linearly in tau (NaN if the evolution
    ended before the window)."""
    tau, M0 = np.asarray(tau), np.asarray(M0)
    if not tau[-1] >= window * (1 - 1e-12):
        return float("nan")
    return float((np.interp(window, tau, M0) - M0[0]) / window)


def initial_rate(grid, op, d, M0, level=0.0, h=1e-6):
    """dM0/dtau of the state ln f = level + d at M0: sum_i (dm_i/dtau) <cos theta>_i / mass (the
    change of f at fixed orbits) over 1 - dF/dM0 (the self-consistent response of M0 to it)."""
    f = np.exp(level + d)
    num = float(np.dot(_call(op, "rate", d, level), grid.cos_avg)) / grid_mass(grid, f, M0)
    dF = (magnetisation_map(grid, f, M0, M0 + h) - magnetisation_map(grid, f, M0, M0 - h)) / (2 * h)
    return num / (1.0 - dF)


#: a step that would end on a time whose current is stored ends FAST x its length before it,
#: and a step of that length follows: the layer next to the separatrix, whose cells relax on
#: times down to ~1e-10 and which each frame remap disturbs, has settled into the balance of
#: the current through it when the current is stored (the state's other modes move by FAST x
#: the step, as in any step, with tau advanced)
FAST = 1e-3


#: nodes closer to the separatrix than this reduced offset keep their offsets of ln f when f
#: is remapped (their ln f differ below its rounding; `_LogDensity.remapped`)
DEEP_OFFSET = 1e-8


class _LogDensity:
    """ln f = level + d on the grid: d = 0 at the gauge node (the innermost librating one) and
    the offsets d of the nodes next to the separatrix carry the digits by which their ln f
    differ (d ~ -beta (h - M0) there), the level the common part."""

    def __init__(self, grid, level, d):
        self.grid = grid
        self.gauge = grid.sep - 1
        self.level = float(level)
        self.d = np.asarray(d, dtype=float)

    @property
    def f(self):
        return np.exp(self.level + self.d)

    def scales(self, M):
        """The Newton unknowns' natural size per node: |h_i - h_gauge| for the offsets (at most
        1), 1 for the level (in the gauge node's column)."""
        e = M * self.grid.eps_hat
        out = np.minimum(np.abs(e - e[self.gauge]), 1.0)
        out[self.gauge] = 1.0
        return out

    @classmethod
    def of_state(cls, grid, state, M, f):
        """The projection f (`project_state`) of a state F(h) as a level and offsets, the deep
        nodes' offsets from d ln F/dh at the separatrix (second order in h - M)."""
        gauge = grid.sep - 1
        e = M * grid.eps_hat
        level = float(np.log(f[gauge]))
        d = np.log(f) - level
        deep = np.abs(grid.xhat) < DEEP_OFFSET
        if np.any(deep):
            step = 1e-4 * M
            lnF = [float(np.log(state.f_energy(M + e[gauge] + k * step))) for k in (-1, 0, 1)]
            s1 = (lnF[2] - lnF[0]) / (2 * step)
            s2 = (lnF[2] - 2 * lnF[1] + lnF[0]) / step**2
            de = e[deep] - e[gauge]
            d[deep] = s1 * de + 0.5 * s2 * de**2
        return cls(grid, level, d)

    def remapped(self, M_from, M_to):
        """The state carried to the frame M_to: f(J-bar) fixed (`grid.remap`, conservative),
        except the deep nodes (|x^| < DEEP_OFFSET), whose offsets are kept: a remap at fixed
        J-bar would fill cells narrower than the frame's shift with the f found a shift away,
        unsettling the balance of the current through them.  The total mass is kept by a
        common factor."""
        grid = self.grid
        if M_from == M_to:
            return _LogDensity(grid, self.level, self.d.copy())
        f = self.f
        keep = np.abs(grid.xhat) < DEEP_OFFSET
        f_new = _floor(remap(grid, f, M_from, M_to))
        f_new[keep] = f[keep]
        factor = (
            np.sum(grid.width_hat * f)
            * np.sqrt(M_from)
            / (np.sum(grid.width_hat * f_new) * np.sqrt(M_to))
        )
        gauge = self.gauge
        if keep[gauge]:  # the gauge node in the kept layer: its offset stays 0
            level = self.level + np.log(factor)
        else:  # a grid that stops short of DEEP_OFFSET: the level is ln f at the gauge node
            level = float(np.log(f_new[gauge] * factor))
        d = np.log(f_new * factor) - level
        d[keep] = self.d[keep]
        return _LogDensity(grid, level, d)


def evolve(state, settings, progress=None, operator=None):
    """Evolve `state` (any object with M0 and f_energy(h)) under the Landau or Lenard-Balescu
    equation until thermalised (max |f - f_eq| / max f_eq < thermal_tol, f_eq the thermal
    state of the same energy on the grid, carried to the frame of the current M0) or tau_max.

    operator: None (the collision operator of `settings.equation`), or a factory
    (grid, f, M0) -> an object with the methods of `CollisionOperator` (rate, jacobian,
    face_flux, entropy_production), called wherever the collision operator would be built: a
    testing seam, so that an operator of known spectrum runs through the same stepper, step
    control and time bookkeeping.

    Each step uses the orbits of the predicted mid-step magnetisation
    M0 + (dM0/dtau) dtau/2 (from the previous step): f is carried to that frame, stepped there,
    M0 re-solved with f(J-bar) fixed, and f carried to the frame of the new M0.  progress(dict)
    is called after every accepted step with tau, M0, S, u, thermal_distance_max.

    Returns a dict: per accepted step 'tau', 'f' (T, N) (on the cells of the frame M0(tau)),
    'M0', 'u', 'S', 'mass', 'beta_fit', 'distance' (max |f - f_eq| / max f_eq); at
    `settings.flux_times` (and the end) 'tau_flux', 'flux' (T', N-1) (the current G-bar
    through each face) and 'Sdot'; the grid ('grid': the `ActionGrid`, 'eta', 'xhat',
    'width_hat'); the thermal end point ('f_eq', 'M0_eq', 'beta_eq', 'S_eq'); the settings,
    step counts and wall time.
    """
    s = settings
    t0 = time.perf_counter()
    grid = make_grid(state, s)
    f, M0 = project_state(state, grid)
    lnf = _LogDensity.of_state(grid, state, M0, f)
    hist = _History()
    u0 = grid_energy(grid, f, M0)
    f_eq, M0_eq, beta_eq = grid_thermal_state(grid, u0, None)
    flux_times = sorted({float(t) for t in s.flux_times if 0.0 < t < s.tau_max})
    stops = sorted(set(flux_times) | ({s.early_window} if s.early_window < s.tau_max else set()))
    tau_flux, flux, sdot, M_flux = [], [], [], []
    kin = Kinetics(grid, s) if operator is None else None

    def record(tau, lnf, M0):
        f = lnf.f
        hist.tau.append(tau)
        hist.f.append(f)
        hist.M0.append(M0)
        hist.u.append(grid_energy(grid, f, M0))
        hist.S.append(grid_entropy(grid, f, M0))
        hist.mass.append(grid_mass(grid, f, M0))
        hist.beta_fit.append(thermal_fit(grid, f, M0)[0])
        eq_here = remap(grid, f_eq, M0_eq, M0)
        dist = float(np.max(np.abs(f - eq_here)) / np.max(eq_here))
        hist.distance.append(dist)
        if progress is not None:
            progress(
                {
                    "tau": tau,
                    "M0": M0,
                    "S": hist.S[-1],
                    "u": hist.u[-1],
                    "thermal_distance_max": dist,
                }
            )
        return dist

    def make_operator(f, M):
        if operator is not None:
            return operator(grid, f, M)
        return kin.operator(f, M)

    def record_flux(tau, lnf, M0):
        op = make_operator(lnf.f, M0)
        tau_flux.append(tau)
        flux.append(_call(op, "face_flux", lnf.d, lnf.level) / PHASE_VOLUME_PER_JBAR)
        sdot.append(_call(op, "entropy_production", lnf.d, lnf.level))
        M_flux.append(M0)
        return op

    tau = 0.0
    dist = record(tau, lnf, M0)
    op = record_flux(tau, lnf, M0)
    dM0dtau_initial = initial_rate(grid, op, lnf.d, M0, lnf.level)
    mid, M_mid = lnf, M0
    memo = {}
    vol = grid.volume(M0)
    scales = lnf.scales(M0)
    rate0 = np.max(np.abs(_call(op, "rate", lnf.d, lnf.level)) / vol)
    dt = s.dtau_first or (s.rtol * np.max(f) / rate0 if rate0 > 0 else s.tau_max)
    dM0dt = 0.0
    fresh = False  # the operator of tau = 0 serves the first step (dM0/dtau unknown: 0)
    n_rejected = n_steps = 0
    settling = False

    def stored_at(t):  # a step ends on a stop to rounding (relative: the early window's
        # steps can be far shorter than an absolute tolerance, and end near a stop unstored)
        return any(abs(t - x) <= 1e-12 * abs(x) for x in flux_times)

    while tau < s.tau_max * (1 - 1e-12) and dist >= s.thermal_tol and n_steps < s.max_steps:
        dt = min(dt, s.tau_max - tau)
        upcoming = [t for t in stops if t > tau * (1 + 1e-12)]
        if upcoming:
            dt = min(dt, upcoming[0] - tau)
        ends = tau + dt
        # a step onto a stored time: first all of it but FAST, then the rest (FAST)
        onto = stored_at(ends) or ends >= s.tau_max * (1 - 1e-12)
        if onto and not settling and dt > 1e-12 * max(ends, 1.0):
            dt *= 1.0 - FAST
            settling = True
        else:
            settling = False
        if fresh:  # a new step: f in the frame of the predicted mid-step M0 (kept if rejected)
            M_mid = M0 + 0.5 * dM0dt * dt
            mid = lnf.remapped(M0, M_mid)
            op = make_operator(mid.f, M_mid)
            vol = grid.volume(M_mid)
            scales = mid.scales(M_mid)
            memo = {}  # what the solves from mid with op share
            fresh = False
        one, two, ok = _doubling_solves(op, vol, mid, dt, scales, memo)
        if not ok:
            n_rejected += 1
            dt *= 0.25
            continue
        fmax = np.max(mid.f)
        early = s.early_rtol is not None and tau < s.early_window * (1 - 1e-12)
        err = np.max(np.abs(two.f - one.f)) / ((s.early_rtol if early else s.rtol) * fmax)
        if err > 1.0:
            n_rejected += 1
            dt *= max(0.2, 0.9 / np.sqrt(err))
            continue
        tau += dt
        n_steps += 1
        M0_new = solve_grid_M0(grid, two.f, M_mid, guess=M0 + dM0dt * dt)
        lnf = two.remapped(M_mid, M0_new)
        dM0dt = (M0_new - M0) / dt
        M0 = M0_new
        dist = record(tau, lnf, M0)
        fresh = True
        if stored_at(tau):
            record_flux(tau, lnf, M0)
        dt *= min(4.0, 0.9 / np.sqrt(max(err, 1e-12)))
    if tau_flux[-1] != tau:
        record_flux(tau, lnf, M0)
    out = {k: np.asarray(v) for k, v in hist.__dict__.items()}
    M_hist = out["M0"]
    out.update(
        tau_flux=np.asarray(tau_flux),
        flux=np.asarray(flux),
        Sdot=np.asarray(sdot),
        M0_flux=np.asarray(M_flux),
        dM0dtau_initial=dM0dtau_initial,
        dM0dtau_early=early_rate(out["tau"], out["M0"], s.early_window),
        ln_f_level=lnf.level,
        ln_f_offsets=lnf.d,
        grid=grid,
        eta=grid.eta,
        xhat=grid.xhat,
        width_hat=grid.width_hat,
        jbar=np.sqrt(M_hist)[:, None] * (JS_HAT + grid.xhat)[None, :],
        width=np.sqrt(M_hist)[:, None] * grid.width_hat[None, :],
        settings=s.as_dict(),
        n_steps=n_steps,
        n_rejected=n_rejected,
        n_dielectric=0 if kin is None else kin.dielectric.n_evaluations,
        thermalised=bool(dist < s.thermal_tol),
        wall_time=time.perf_counter() - t0,
        u_state=float(getattr(state, "u", np.nan)),
        M0_state=float(state.M0),
        f_eq=f_eq,
        M0_eq=M0_eq,
        beta_eq=beta_eq,
        S_eq=grid_entropy(grid, f_eq, M0_eq),
    )
    return out
