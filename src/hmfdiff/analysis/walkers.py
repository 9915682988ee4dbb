"""Monte-Carlo walkers in the rescaled action: what the MD fit reads from particles that only
diffuse with a local D(J-bar), fitted like the MD.

The MD fit (`fits.diffusion_fit`) takes half the slope of <dJ^2>(lag) over a window of lags for
the particles whose J-bar lay in a bin at the time origin.  Walkers that start in the bin and
obey the Ito equation

    dJbar = D'(Jbar) dt + sqrt(2 D(Jbar)) dW

(the Fokker-Planck form dP/dt = d/dJbar [D dP/dJbar] of a Hamiltonian random forcing, no
friction) carry only local quasi-linear diffusion, but wander over D(J-bar) during the window
as the particles do.  `analysis.propagated` solves the same equation exactly for the bin's
density; this module samples it, with the separatrix treatable either way:

* crossing (default): J-bar is continuous across kappa = 1 and the phase-space measure per unit
  J-bar is 4 pi on both families (one librating torus of J = 2 J-bar, two rotating tori of
  J = J-bar), so one variable with D_Jbar = D_J (dJbar/dJ)^2 (D_J / 4 below the separatrix)
  serves both, with zero net flux lost at kappa = 1; the MD measures dJ-bar too.
* reflecting at `barrier` (a J-bar): a walker that would cross is mirrored back, i.e. the
  families do not exchange particles: a bound on what crossing can do.

D is piecewise linear between `nodes` (its derivative, the Ito drift, piecewise constant),
walls at the first and last node reflect.  Euler-Maruyama with step dt: the step sqrt(2 D dt)
must be small against the scale on which D changes (`walk_msd` does not check it).
"""

from __future__ import annotations

import numpy as np

from .fits import fit_slope

__all__ = ["walk_msd", "walker_nd"]


def _reflect(x, lo, hi):
    """Mirror x into [lo, hi] (once; steps are far shorter than the interval)."""
    x = np.where(x < lo, 2.0 * lo - x, x)
    return np.where(x > hi, 2.0 * hi - x, x)


def walk_msd(nodes, d_nodes, start, lags, *, dt, seed=0, batches=8, barrier=None):
    """<(Jbar - Jbar_0)^2>(lag) of walkers started at `start` (J-bar values), per batch.

    nodes, d_nodes: J-bar nodes (increasing) and D_Jbar there (not N D); lags: the lags at which
    to record (multiples of dt after rounding); batches: the walkers split into this many
    independent groups (the spread of their fits is the Monte-Carlo error); barrier: a J-bar
    the walkers may not cross (reflecting), None to cross freely.  Returns (batch, lag).
    """
    nodes = np.asarray(nodes, dtype=float)
    d_nodes = np.asarray(d_nodes, dtype=float)
    if nodes.ndim != 1 or nodes.size < 2 or np.any(np.diff(nodes) <= 0):
        raise ValueError("nodes must be increasing, at least two")
    if d_nodes.shape != nodes.shape or np.any(~np.isfinite(d_nodes)) or np.any(d_nodes < 0):
        raise ValueError("D must be finite and non-negative at every node")
    slope = np.diff(d_nodes) / np.diff(nodes)
    x0 = np.asarray(start, dtype=float).ravel()
    if np.any((x0 < nodes[0]) | (x0 > nodes[-1])):
        raise ValueError("walkers must start between the first and last node")
    lags = np.asarray(lags, dtype=float)
    steps = np.rint(lags / dt).astype(int)
    if np.any(steps < 0):
        raise ValueError("lags must be non-negative")
    rng = np.random.default_rng(seed)
    x = x0.copy()
    side = None if barrier is None else x0 >= barrier
    out = np.zeros((batches, lags.size))
    groups = np.array_split(np.arange(x0.size), batches)

    def record(s):
        hit = steps == s
        if hit.any():
            d2 = (x - x0) ** 2
            for g, idx in enumerate(groups):
                out[g, hit] = d2[idx].mean()

    record(0)
    for s in range(1, int(steps.max()) + 1 if steps.size else 1):
        cell = np.clip(np.searchsorted(nodes, x) - 1, 0, slope.size - 1)
        D = d_nodes[cell] + slope[cell] * (x - nodes[cell])
        x = x + slope[cell] * dt + np.sqrt(2.0 * np.maximum(D, 0.0) * dt) * rng.normal(size=x.size)
        x = _reflect(x, nodes[0], nodes[-1])
        if barrier is not None:
            x = np.where(side, np.maximum(x, 2.0 * barrier - x), np.minimum(x, 2.0 * barrier - x))
        record(s)
    return out


def walker_nd(lags, msd, window, N, jac2=1.0):
    """N D that the MD fit reads from msd (J-bar^2, last axis the lags): half the slope of
    jac2 * msd over the window (`fits.fit_slope`), times N; jac2 = (dJ/dJbar)^2 of the bin
    (4 librating, 1 rotating) as in `fits.diffusion_fit`."""
    return 0.5 * N * fit_slope(np.asarray(lags, dtype=float), jac2 * np.asarray(msd), window)[0]
