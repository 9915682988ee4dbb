"""The relaxation's Newton solves and M0 solve as hmfdiff ran them until rxspeed (commit
ae01749), kept as the baseline that `bench_relaxation.py --study cost` measures the present
code against in the same run: each of a step's three backward-Euler solves (one step, two half
steps) assembled its own Jacobian, the rate at every new Newton matrix was evaluated twice, and
M0 was found by brentq on `grid.magnetisation_map` with eta(J-bar offset) by Newton steps over
every cell edge until all had converged (and one evaluation per bisection step where they
did not); f was remapped with a Python loop over the cells
that span old edges; the dielectric tensor's quadrature formed its whole matrix of
1/(Omega - x0) at once, and kappa(Omega) bisected every point 80 times (by bisection alone
until Newton's iteration replaced it, `kappa_from_frequency` here); the tabulated state's M0
was bracketed on 9 points over +- 0.01 of its guess (`tabulated_solve_M0`).

`previous_path()` puts them in place of the present ones.
"""

from __future__ import annotations

import contextlib
import warnings

import numpy as np
from scipy import linalg, optimize

from hmfdiff.kinetic import dielectric as D
from hmfdiff.kinetic import relaxation as R
from hmfdiff.kinetic import tabulated as T
from hmfdiff.kinetic.grid import JS_HAT, _limited_slopes, frame_offsets
from hmfdiff.meanfield import orbits, separatrix
from hmfdiff.meanfield.equilibrium import EquilibriumError


def _newton_matrix(op, vol, level, d, dt, gauge, scales):
    m = vol * np.exp(level + d)
    jac = R._jacobian(op, d, level)
    A = np.diag(m) - dt * jac
    if gauge is not None:
        A[:, gauge] = m - dt * R._call(op, "rate", d, level)  # d r / d level
    A = A * scales[None, :]
    rows = np.max(np.abs(A), axis=1)
    rows = np.where(rows > 0, rows, 1.0)
    A = A / rows[:, None]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", linalg.LinAlgWarning)
        lu, piv = linalg.lu_factor(A, check_finite=False)
    if np.any(np.diag(lu) == 0.0):
        return None
    return lu, piv, rows


def backward_euler_offsets(op, vol, level0, d0, dt, gauge, scales, tol=1e-13, max_iter=50):
    m0 = vol * np.exp(level0 + d0)
    level, d = float(level0), d0.copy()
    lu = None
    last = np.inf
    age = 0
    for _ in range(max_iter):
        f = np.exp(level + d)
        if lu is None:
            lu = _newton_matrix(op, vol, level, d, dt, gauge, scales)
            if lu is None:
                return level, d, False
            last, age = np.inf, 0
        else:
            age += 1
        r = vol * f - m0 - dt * R._call(op, "rate", d, level)
        w = linalg.lu_solve(lu[:2], -r / lu[2], check_finite=False) * scales
        if not np.all(np.isfinite(w)):
            return level, d, False
        dlevel = 0.0
        if gauge is not None:
            dlevel, w[gauge] = w[gauge], 0.0
        change = np.abs(dlevel + w)
        size = np.max(change)
        step = min(1.0, 2.0 / max(size, 1e-300))
        level += step * dlevel
        d = d + step * w
        floor = R.LOG_FLOOR - level
        d = np.maximum(d, floor)
        rel = (scales < 1e-8) & (np.abs(w) <= 1e-6 * scales)
        bound = tol if age == 0 else 1e-2 * tol
        if step == 1.0 and np.max(np.where(rel, 0.0, change * f)) <= bound * np.max(f):
            return level, d, True
        if step < 1.0 or size > 0.5 * last:
            lu = None
        last = size
    return level, d, False


def doubling_solves(op, vol, start, dt, scales, memo):
    """One step dt and two half steps from `start`, each solve on its own."""

    def solve(s, h):
        level, d, ok = backward_euler_offsets(op, vol, s.level, s.d, h, s.gauge, scales)
        return R._LogDensity(s.grid, level, d), ok

    one, ok = solve(start, dt)
    if not ok:
        return one, start, False
    half, ok = solve(start, 0.5 * dt)
    if not ok:
        return one, start, False
    two, ok = solve(half, 0.5 * dt)
    return one, two, ok


def eta_from_jbar_offset(x, M0, guess=None, iterations=64):
    x = np.asarray(x, dtype=float)
    c = 4.0 * np.sqrt(M0) / np.pi
    lib = x < 0.0
    sgn = np.where(lib, -1.0, 1.0)
    target = np.abs(x)
    a = np.minimum(target / c, 0.5)
    for _ in range(3):
        a = np.minimum(target / (c * (np.log(4.0) - 0.5 * np.log(2.0 * a) + 0.5)), 0.5)
    if guess is not None:
        g = np.broadcast_to(np.asarray(guess, dtype=float), x.shape)
        use = (np.sign(g) == sgn) & (np.abs(g) < 1.0) & (g != 0.0)
        a = np.where(use, np.abs(g), a)
    t = np.log(a)
    done = np.zeros(x.shape, dtype=bool)
    for _ in range(12):
        e = sgn * np.exp(t)
        e = np.where(lib, np.maximum(e, -1.0 + 1e-16), e)
        xe = separatrix.jbar_offset(e, M0)
        with np.errstate(divide="ignore", invalid="ignore"):
            F = np.log(np.abs(xe)) - np.log(target)
            dF = np.abs(e) * separatrix.djbar_deta(e, M0) / np.abs(xe)
            step = np.where(dF > 1e-3, F / dF, 0.0)
        step = np.clip(np.nan_to_num(step), -5.0, 5.0)
        t = np.where(done, t, np.minimum(t - step, np.where(lib, 0.0, np.inf)))
        done |= np.abs(F) < 4e-15
        if done.all():
            break
    eta = sgn * np.exp(t)
    bad = ~(done | (np.abs(F) < 1e-13))
    if np.any(bad):
        eta[bad] = bisect_offset(x[bad], M0, iterations)
    return eta


def bisect_offset(x, M0, iterations):
    """`separatrix._bisect_offset` with one evaluation per bisection."""
    lib = x < 0.0
    sgn = np.where(lib, -1.0, 1.0)
    lo = np.full(x.shape, np.log(1e-305))
    hi = np.where(lib, 0.0, np.log(np.maximum(2.0 * np.abs(x) / np.sqrt(M0) + 2.0, 2.0)))
    target = np.abs(x)
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        e = sgn * np.exp(mid)
        e = np.where(lib, np.maximum(e, -1.0 + 1e-16), e)
        below = np.abs(separatrix.jbar_offset(e, M0)) < target
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    eta = sgn * np.exp(0.5 * (lo + hi))
    eta = np.where(lib, np.maximum(eta, -1.0 + 1e-16), eta)
    for _ in range(3):
        step = (separatrix.jbar_offset(eta, M0) - x) / separatrix.djbar_deta(eta, M0)
        new = eta - step
        ok = (np.sign(new) == sgn) & (new > -1.0) & np.isfinite(new)
        eta = np.where(ok, new, eta)
    return eta


def magnetisation_map(grid, f, M_cells, M):
    f = np.asarray(f, dtype=float)
    mass_hat = np.sqrt(M_cells) * np.sum(f * grid.width_hat)
    if M == M_cells:
        return float(np.dot(f, grid.cos_avg * grid.width_hat) / np.sum(f * grid.width_hat))
    y = frame_offsets(grid, M_cells, M)
    P = np.zeros_like(y)
    ok = (y != 0.0) & (y > -JS_HAT)
    if np.any(ok):
        eta = eta_from_jbar_offset(y[ok], 1.0, guess=grid.eta_edges[ok])
        P[ok] = separatrix.cos_primitive(eta, 1.0)
    P[y <= -JS_HAT] = -16.0 / 3.0 / (4.0 * np.pi)
    return float(np.sqrt(M) * np.dot(f, np.diff(P)) / mass_hat)


def solve_grid_M0(grid, f, M_cells, guess=None):
    guess = M_cells if guess is None else guess

    def g(M):
        return magnetisation_map(grid, f, M_cells, M) - M

    for half in (1e-4, 1e-3, 1e-2, 0.1, 0.5):
        lo, hi = max(guess - half, 1e-4), min(guess + half, 1.0 - 1e-9)
        if g(lo) * g(hi) < 0:
            return optimize.brentq(g, lo, hi, xtol=1e-15, rtol=1e-15)
    raise EquilibriumError(f"no self-consistent M0 near {guess} for the grid state")


def remap(grid, f, M_from, M_to):
    """`grid.remap`, its cells that span old edges filled one by one."""
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
        """int over [a, b] (inside old cell i) of its linear reconstruction."""
        return (b - a) * (f[i] + slope[i] * (0.5 * (a + b) - cy[i]))

    k = np.clip(np.searchsorted(y, x, side="right") - 1, 0, n - 1)
    lo_k, hi_k = k[:-1], k[1:]
    xm = 0.5 * (x[1:] + x[:-1])
    out = f[lo_k] + slope[lo_k] * (xm - cy[lo_k])
    span = np.flatnonzero(hi_k != lo_k)
    if span.size:
        mass = np.diff(y) * f
        cum = np.concatenate(([0.0], np.cumsum(mass)))
        for j in span:
            a, b = lo_k[j], hi_k[j]
            top = min(x[j + 1], y[-1])
            m = piece(a, x[j], y[a + 1]) + (cum[b] - cum[a + 1])
            if top > y[b]:
                m += piece(b, y[b], top)
            out[j] = max(m, 0.0) / grid.width_hat[j]
    out[x[:-1] >= y[-1]] = 0.0  # beyond the old top edge: f = 0
    out = np.maximum(out, 0.0)
    old_mass = np.sqrt(M_from) * np.sum(f * grid.width_hat)
    new_mass = np.sqrt(M_to) * np.sum(out * grid.width_hat)
    return out * (old_mass / new_mass)


def branch_term(self, x0, sgn, Om, w, Gcc, Gss, A, branch, l):
    """`DielectricTensor._branch_term` with the whole n_omega x n_nodes matrix at once."""
    pole = (x0 > 0.0) & (x0 < A)
    R = np.subtract(Om[None, :], x0[:, None])
    with np.errstate(divide="ignore"):
        np.divide(1.0, R, out=R)  # in place: one array of n_omega x n_nodes, not three
    # a frequency exactly on a node (measure zero) drops that node's term, an error of
    # order w_j G'(x0); the nodes increase, so such hits are found by bisection
    j = np.minimum(np.searchsorted(Om, x0), Om.size - 1)
    hit = np.flatnonzero(Om[j] == x0)
    R[hit, j[hit]] = 0.0
    kp = np.full(x0.shape, np.nan)
    if np.any(pole):
        kp[pole] = self._kappa_of(x0[pole], branch)
    # the three quadratures in one pass over R: sum w R, sum w G_cc R, sum w G_ss R
    sumw, tcc, tss = (R @ np.column_stack([w, w * Gcc, w * Gss])).T
    with np.errstate(divide="ignore", invalid="ignore"):
        logt = np.where(pole, np.log(np.abs(A - x0) / np.abs(x0)), 0.0)
    out = []
    for comp, t in (("cc", tcc), ("ss", tss)):
        t = t.astype(complex)
        if np.any(pole):
            G0 = np.zeros(x0.shape)
            G0[pole] = D.pole_density(self.state, kp[pole], l, comp)
            t = t - G0 * sumw + G0 * logt + 1j * np.pi * sgn * G0
        out.append(t)
    return out[0], out[1]


def bisect(fun, target, lo, hi, iters=80):
    """`orbits._bisect` iterating every point iters times."""
    lo = np.broadcast_to(np.asarray(lo, float), np.shape(target)).copy()
    hi = np.broadcast_to(np.asarray(hi, float), np.shape(target)).copy()
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        below = fun(mid) < target
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return 0.5 * (lo + hi)


def kappa_from_frequency(omega, M0, family, kappa_max=1e6):
    """`orbits.kappa_from_frequency` by bisection of Omega(kappa) on each family."""
    omega = np.asarray(omega, dtype=float)
    s = np.sqrt(M0)
    if family == "libration":
        ok = (omega > 0) & (omega < s)
        k = orbits._bisect(
            lambda k: -orbits.frequency(k, M0), -np.where(ok, omega, 0.5 * s), 0.0, 1.0
        )
    elif family == "rotation":
        ok = omega > 0
        hi = np.maximum(np.where(ok, omega, s) / (2.0 * s) * 2.0 + 2.0, 2.0)
        hi = np.minimum(hi, kappa_max)
        k = orbits._bisect(lambda k: orbits.frequency(k, M0), np.where(ok, omega, s), 1.0, hi)
    else:
        raise ValueError(f"family must be 'libration' or 'rotation', got {family!r}")
    return np.where(ok, k, np.nan)


def tabulated_solve_M0(jbar, f, guess=None, order=24):
    """`tabulated.solve_M0` bracketing on 9 points over guess +- 0.01, then wider."""
    jbar = np.asarray(jbar, dtype=float)
    logf = np.log(np.asarray(f, dtype=float))

    def g(M):
        return T._magnetisation_map(jbar, logf, M, order) - M

    for half in (0.01, 0.05, 0.2) if guess is not None else ():
        lo, hi = max(guess - half, 1e-3), min(guess + half, 0.999)
        grid = np.linspace(lo, hi, 9)
        vals = np.array([g(M) for M in grid])
        idx = np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))
        if idx.size:
            roots = [optimize.brentq(g, grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15) for i in idx]
            return min(roots, key=lambda r: abs(r - guess))
    return _PRESENT_SOLVE_M0(jbar, f, guess=None, order=order)


_PRESENT_SOLVE_M0 = T.solve_M0


@contextlib.contextmanager
def swapped(*swaps):
    """(module or class, name, replacement) put in place for the block, then restored."""
    saved = [(where, k, getattr(where, k)) for where, k, _ in swaps]
    for where, k, v in swaps:
        setattr(where, k, v)
    try:
        yield
    finally:
        for where, k, v in saved:
            setattr(where, k, v)


def previous_path():
    """`relaxation.evolve` with the solves above in place of the present ones."""
    return swapped(
        (R, "_doubling_solves", doubling_solves),
        (R, "solve_grid_M0", solve_grid_M0),
        (R, "remap", remap),
        (D.DielectricTensor, "_branch_term", branch_term),
        (orbits, "_bisect", bisect),
        (orbits, "kappa_from_frequency", kappa_from_frequency),
        (T, "solve_M0", tabulated_solve_M0),
    )
