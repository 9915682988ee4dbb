"""Collisional relaxation f(J-bar, tau) by the Landau and Lenard-Balescu equations (eq. hmflb,
paper's Conclusions), with a self-consistent magnetisation.

State.  f on a fixed grid of rescaled actions J-bar (`hmfdiff.kinetic.grid.action_grid`, packed
round the separatrix and on the steep edges of the initial f), node masses m_i = 4 pi w_i f_i.
J is an adiabatic invariant of the slow change of M0, so f(J-bar) is held fixed while M0 is
re-solved from
M0 = sum_i m_i <cos theta>(J-bar_i; M0) after every step (`solve_grid_M0`).  The separatrix
J-bar_s = 4 sqrt(M0)/pi moves with M0: a node it passes changes family at fixed J-bar, i.e. a
librating torus of action J becomes the pair of rotating tori of action J/2, each direction
receiving half of its particles (the area-preserving separatrix crossing; f stays even in p).

Energy per particle u = sum_i m_i h(J-bar_i; M0) + M0^2/2.  At fixed M0 the collision step
conserves sum m h exactly (`collision`); the M0 update at fixed f(J-bar) changes u only at
second order in the change of M0, because d u/d M0 = M0 - sum m <cos theta> = 0 at the
self-consistent M0.

Time stepping.  Backward Euler in ln f with the collision weights (orbits, resonances, dielectric
factor) frozen over a step, solved by Newton to rounding: it is stable for this stiff problem,
conserves mass, and S = -sum m ln f cannot decrease over a step (S is concave and the frozen
operator produces entropy for any f).  The step is controlled by step doubling: the difference
between one step and two half steps, relative to max f, is kept below `rtol`.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy import linalg

from .collision import CollisionOperator, geometry, resonance_events
from .dielectric import DielectricTensor
from .grid import (
    action_grid,
    grid_energy,
    grid_entropy,
    grid_thermal_state,
    project_state,
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
    feature_share: float = 0.25
    separatrix_share: float = 0.4
    #: no grid node within |kappa - 1| < separatrix_band (`grid.action_grid`; 0: none)
    separatrix_band: float = 0.0
    eps_panels: int = 48
    eps_order: int = 20
    eps_refresh: float = 0.01

    def __post_init__(self):
        if self.equation not in EQUATIONS:
            raise ValueError(f"equation = {self.equation!r}: must be one of {EQUATIONS}")
        if not self.rtol > 0 or not self.tau_max > 0:
            raise ValueError("rtol and tau_max must be > 0")
        if not 0.0 <= self.separatrix_band < 0.5:
            raise ValueError(f"separatrix_band = {self.separatrix_band!r}: must be in [0, 0.5)")

    def as_dict(self):
        return {k: getattr(self, k) for k in self.__dataclass_fields__}

    @classmethod
    def from_mapping(cls, equation, mapping):
        """Settings from a config mapping (unknown keys refused, naming them)."""
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


def _backward_euler(op, vol, y0, dt, tol=1e-13, max_iter=50):
    """Solve vol e^y - vol e^y0 = dt * rate(y) by damped Newton; returns (y, converged)."""
    m0 = vol * np.exp(y0)
    y = y0.copy()
    for _ in range(max_iter):
        f = np.exp(y)
        scale = 1.0 / (vol * f)  # rows relative to each node's mass: well conditioned
        r = vol * f - m0 - dt * op.rate(y)
        # dense LU: the collision operator couples every node to its resonant partners (~12 %
        # of the matrix filled at 600 nodes), where LAPACK factorises 4x faster than SuperLU
        Jm = np.eye(y.size) - dt * (scale[:, None] * op.jacobian(y).toarray())
        with warnings.catch_warnings():  # an exactly singular matrix is reported below
            warnings.simplefilter("ignore", linalg.LinAlgWarning)
            lu, piv = linalg.lu_factor(Jm, check_finite=False)
        if np.any(np.diag(lu) == 0.0):  # exactly singular
            return y, False
        d = linalg.lu_solve((lu, piv), -scale * r, check_finite=False)
        if not np.all(np.isfinite(d)):
            return y, False
        step = min(1.0, 2.0 / max(np.max(np.abs(d)), 1e-300))
        y = np.maximum(y + step * d, LOG_FLOOR)
        if step == 1.0 and np.max(np.abs(d) * f) <= tol * np.max(f):
            return y, True
    return y, False


def _interpolated_dielectric(tensor, geom, n_max, l_max):
    """eps_cc, eps_ss tabulated once and interpolated linearly in omega: at the faces'
    frequencies n nu_a (dense where the grid is) below 1.2 l_max Omega_0, where the librating
    poles make eps change fast; on 200 geometric points above, where only rotating orbits
    contribute and eps is smooth; on a geometric grid below 0.05 Omega_0 (eps_ss ~ eps_ss(0) +
    c omega^2 there)."""
    Om0 = np.sqrt(geom.M0)
    faces = (np.arange(1, n_max + 1)[:, None] * geom.nu[None, :]).ravel()
    cut = 1.2 * l_max * Om0
    top = max(faces.max(), cut) * 1.01
    om = np.unique(
        np.concatenate(
            [
                np.geomspace(1e-5 * Om0, 0.05 * Om0, 40),
                faces[faces < cut],
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


class _Dielectric:
    """eps(omega) of the grid state, recomputed only when f has changed by more than
    `refresh` (relative to max f) since it was last computed (the weights then lag by less)."""

    def __init__(self, settings):
        self.s = settings
        self.f_ref = None
        self.eps = None
        self.n_evaluations = 0

    def __call__(self, grid, f, geom):
        s = self.s
        if self.f_ref is not None:
            change = np.max(np.abs(f - self.f_ref)) / np.max(self.f_ref)
            if change <= s.eps_refresh:
                return self.eps
        # the dielectric tensor of f(J-bar) with its own self-consistent M0 (eps_ss(0) = 0
        # needs it: with the grid's M0, which differs by the quadrature error, 1/|eps_ss|^2
        # at low frequency would be wrong by orders of magnitude)
        tab = TabulatedState(grid.jbar, np.maximum(f, np.exp(LOG_FLOOR)), M0_guess=geom.M0)
        tensor = DielectricTensor(tab, l_max=s.l_max, n_panels=s.eps_panels, order=s.eps_order)
        self.eps = _interpolated_dielectric(tensor, geom, s.n_max, s.l_max)
        self.f_ref = f.copy()
        self.n_evaluations += 1
        return self.eps


class _Operator:
    """The collision operator of a state f on the grid with orbits of magnetisation M0."""

    def __init__(self, grid, f, M0, settings, dielectric=None):
        self.geom = geometry(grid.jbar, M0)
        self.events = resonance_events(self.geom, settings.n_max)
        eps = None
        if settings.equation == "lenard_balescu":
            dielectric = dielectric or _Dielectric(settings)
            eps = dielectric(grid, f, self.geom)
        self.op = CollisionOperator(self.geom, self.events, eps)


def evolve(state, settings, progress=None, operator=None):
    """Evolve `state` (any object with M0 and f_energy(h)) under the Landau or Lenard-Balescu
    equation until thermalised (max |f - f_eq| / max f_eq < thermal_tol, f_eq the thermal
    state of the same energy on the grid) or tau_max.

    operator: None (the collision operator of `settings.equation`), or a factory
    (grid, f, M0) -> an object with the methods of `CollisionOperator` (rate, jacobian,
    face_flux, entropy_production), called wherever the collision operator would be built: a
    testing seam, so that an operator of known spectrum runs through the same stepper, step
    control and time bookkeeping.

    Each step uses the orbits of the predicted mid-step magnetisation
    M0 + (dM0/dtau) dtau/2 (from the previous step), which makes the energy error of the M0
    update third order in its change per step.  progress(dict) is called after every accepted
    step with tau, M0, S, u, thermal_distance_max (max |f - f_eq| / max f_eq).

    Returns a dict: per accepted step 'tau', 'f' (T, N), 'M0', 'u', 'S', 'mass', 'beta_fit',
    'distance' (max |f - f_eq| / max f_eq); at `settings.flux_times` (and the end) 'tau_flux',
    'flux' (T', N-1) (the current G-bar through each face) and 'Sdot'; the grid ('jbar',
    'width', 'jbar_face'); the thermal end point ('f_eq', 'M0_eq', 'beta_eq', 'S_eq'); the
    settings, step counts and wall time.
    """
    s = settings
    t0 = time.perf_counter()
    grid = action_grid(
        state.M0,
        s.n_nodes,
        s.kappa_max,
        state,
        s.feature_share,
        s.separatrix_share,
        s.separatrix_band,
    )
    f, M0 = project_state(state, grid)
    y = np.log(f)
    vol = grid.volume
    hist = _History()
    u0 = grid_energy(grid, f, M0)
    f_eq, M0_eq, beta_eq = grid_thermal_state(grid, u0, None)
    flux_times = sorted({float(t) for t in s.flux_times if 0.0 < t < s.tau_max})
    tau_flux, flux, sdot = [], [], []

    def record(tau, y, M0):
        f = np.exp(y)
        hist.tau.append(tau)
        hist.f.append(f)
        hist.M0.append(M0)
        hist.u.append(grid_energy(grid, f, M0))
        hist.S.append(grid_entropy(grid, f))
        hist.mass.append(float(np.sum(vol * f)))
        hist.beta_fit.append(thermal_fit(grid, f, M0)[0])
        dist = float(np.max(np.abs(f - f_eq)) / np.max(f_eq))
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

    dielectric = _Dielectric(s)

    def make_operator(f, M0):
        if operator is not None:
            return operator(grid, f, M0)
        return _Operator(grid, f, M0, s, dielectric).op

    def record_flux(tau, y, M0):
        op = make_operator(np.exp(y), M0)
        tau_flux.append(tau)
        flux.append(op.face_flux(y) / PHASE_VOLUME_PER_JBAR)
        sdot.append(op.entropy_production(y))
        return op

    tau = 0.0
    dist = record(tau, y, M0)
    op = record_flux(tau, y, M0)
    rate0 = np.max(np.abs(op.rate(y)) / vol)
    dt = s.dtau_first or (s.rtol * np.max(f) / rate0 if rate0 > 0 else s.tau_max)
    dM0dt = 0.0
    fresh = False  # the operator of tau = 0 serves the first step (dM0/dtau unknown: 0)
    n_rejected = n_steps = 0
    while tau < s.tau_max * (1 - 1e-12) and dist >= s.thermal_tol and n_steps < s.max_steps:
        dt = min(dt, s.tau_max - tau)
        upcoming = [t for t in flux_times if t > tau * (1 + 1e-12)]
        if upcoming:
            dt = min(dt, upcoming[0] - tau)
        if fresh:  # a new step: orbits at the predicted mid-step M0 (kept if it is rejected)
            op = make_operator(np.exp(y), M0 + 0.5 * dM0dt * dt)
            fresh = False
        y1, ok1 = _backward_euler(op, vol, y, dt)
        yh, okh = _backward_euler(op, vol, y, 0.5 * dt) if ok1 else (y, False)
        y2, ok2 = _backward_euler(op, vol, yh, 0.5 * dt) if okh else (y, False)
        if not (ok1 and okh and ok2):
            n_rejected += 1
            dt *= 0.25
            continue
        fmax = np.max(np.exp(y))
        err = np.max(np.abs(np.exp(y2) - np.exp(y1))) / (s.rtol * fmax)
        if err > 1.0:
            n_rejected += 1
            dt *= max(0.2, 0.9 / np.sqrt(err))
            continue
        tau += dt
        n_steps += 1
        y = y2
        M0_new = solve_grid_M0(grid, np.exp(y), M0)
        dM0dt = (M0_new - M0) / dt
        M0 = M0_new
        dist = record(tau, y, M0)
        fresh = True
        if any(abs(tau - t) <= 1e-9 * max(t, 1.0) for t in flux_times):
            record_flux(tau, y, M0)
        dt *= min(4.0, 0.9 / np.sqrt(max(err, 1e-12)))
    if tau_flux[-1] != tau:
        record_flux(tau, y, M0)
    out = {k: np.asarray(v) for k, v in hist.__dict__.items()}
    out.update(
        tau_flux=np.asarray(tau_flux),
        flux=np.asarray(flux),
        Sdot=np.asarray(sdot),
        jbar=grid.jbar,
        width=grid.width,
        jbar_face=0.5 * (grid.jbar[1:] + grid.jbar[:-1]),
        settings=s.as_dict(),
        n_steps=n_steps,
        n_rejected=n_rejected,
        n_dielectric=dielectric.n_evaluations,
        thermalised=bool(dist < s.thermal_tol),
        wall_time=time.perf_counter() - t0,
        u_state=float(getattr(state, "u", np.nan)),
        M0_state=float(state.M0),
        f_eq=f_eq,
        M0_eq=M0_eq,
        beta_eq=beta_eq,
        S_eq=grid_entropy(grid, f_eq),
    )
    return out
