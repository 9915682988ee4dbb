"""Initial conditions for the molecular dynamics of the HMF model (paper, sec. "Comparison with
simulations").

All random numbers come from ``numpy.random.default_rng(SeedSequence([seed, member]))`` (one
generator per run, see `make_rng`), never from inside numba kernels, so a run is reproducible
for any thread count.

* `sample_thermal`: the Maxwell-Boltzmann state f_eq(theta, p) of eq. (hmfeq), sampled exactly:
  p ~ Normal(0, 1/sqrt(beta)) and theta ~ von Mises(0, beta M0).
* `sample_state`: any stationary state f(kappa), sampled exactly through its kappa marginal and
  uniform angle w.  In the rescaled action J-bar (J/2 on librating orbits, J on rotating ones)
  the density of J-bar is 4 pi f(kappa(J-bar)): librating orbits have one torus per J and
  dJ = 2 dJ-bar, rotating ones two tori (both directions) and dJ = dJ-bar.  It is bounded and
  continuous across the separatrix, so its cumulative distribution is tabulated on a fine grid
  and inverted; kappa then follows from J-bar (`orbits.kappa_from_rescaled_action`).
* `sample_uniform_jbar`: test particles uniform in J-bar over [Jbar_min, Jbar_max], with
  uniform angle and a random direction of rotation, to populate tails and rotating orbits.
* `rotate_to_x_axis`: rotate all angles by one angle so that the magnetisation lies on x.
"""

from __future__ import annotations

import numpy as np

from ..meanfield import orbits

# J-bar <-> kappa lives in `orbits`; jbar_separatrix stays importable here for older callers
from ..meanfield.orbits import jbar_separatrix, kappa_from_rescaled_action  # noqa: F401

__all__ = [
    "make_rng",
    "wrap_angle",
    "magnetisation",
    "rotate_to_x_axis",
    "sample_thermal",
    "jbar_cdf_table",
    "sample_kappa",
    "sample_state",
    "sample_uniform_jbar",
]


def make_rng(seed, member=0):
    """The run's generator: default_rng(SeedSequence([seed, member]))."""
    if int(seed) != seed or seed < 0:
        raise ValueError(f"seed = {seed!r} must be a non-negative integer")
    if int(member) != member or member < 0:
        raise ValueError(f"member = {member!r} must be a non-negative integer")
    return np.random.default_rng(np.random.SeedSequence([int(seed), int(member)]))


def wrap_angle(theta):
    """theta wrapped into [-pi, pi)."""
    return np.mod(np.asarray(theta, dtype=float) + np.pi, 2.0 * np.pi) - np.pi


def magnetisation(theta):
    """(Mx, My) = (mean cos theta, mean sin theta), eq. (hmfmdfull)."""
    theta = np.asarray(theta, dtype=float)
    return float(np.mean(np.cos(theta))), float(np.mean(np.sin(theta)))


def rotate_to_x_axis(theta, *others):
    """Rotate `theta` (and every array in `others`) by the angle that puts the magnetisation of
    `theta` on the positive x axis.  Returns (theta_rotated, [others_rotated...], phase)."""
    mx, my = magnetisation(theta)
    phase = float(np.arctan2(my, mx))
    out = [wrap_angle(np.asarray(theta) - phase)]
    out += [wrap_angle(np.asarray(o) - phase) for o in others]
    return (*out, phase)


def sample_thermal(state, n, rng):
    """Exact sample of f_eq(theta, p) ∝ exp(-beta (p^2/2 - M0 cos theta)), eq. (hmfeq)."""
    beta, M0 = state.beta, state.M0
    p = rng.normal(0.0, 1.0 / np.sqrt(beta), size=n)
    theta = rng.vonmises(0.0, beta * M0, size=n)
    return wrap_angle(theta), p


def _kappa_grid(state, n_grid):
    kmax = float(state.kappa_max)
    g = np.linspace(0.0, kmax, n_grid)
    # graded towards the separatrix, where J-bar(kappa) has a logarithmic derivative
    near = 10.0 ** -np.linspace(1.0, 13.0, 200)
    extra = [1.0 - near, 1.0 + near]
    for k in getattr(state, "step_kappas", []) if getattr(state, "shape", "") == "step" else []:
        extra.append([k * (1 - 1e-13), k * (1 + 1e-13)])
    g = np.unique(np.concatenate([g, *extra]))
    return g[(g >= 0.0) & (g <= kmax)]


def jbar_cdf_table(state, n_grid=20001):
    """Tabulated cumulative distribution of J-bar for the state: (jbar_grid, cdf).

    The density of J-bar is 4 pi f(kappa(J-bar)) (see the module docstring); the table
    integrates it with the trapezoid rule in J-bar on a kappa grid graded towards kappa = 1,
    and normalises by its total (which equals 1 to the accuracy of the grid, see the tests).
    """
    kappa = _kappa_grid(state, n_grid)
    jbar = orbits.rescaled_action(kappa, state.M0)
    dens = 4.0 * np.pi * state.f(kappa)
    cells = 0.5 * (dens[1:] + dens[:-1]) * np.diff(jbar)
    cdf = np.concatenate([[0.0], np.cumsum(cells)])
    return jbar, cdf


def sample_kappa(state, n, rng, table=None):
    """Exact-in-distribution sample of kappa from the kappa marginal of f (inverse CDF in J-bar).

    Within a grid cell the CDF is interpolated linearly in J-bar (density constant per cell);
    the grid has ~2e4 nodes, so the sampling error is far below any Monte-Carlo noise.
    """
    jbar_g, cdf = jbar_cdf_table(state) if table is None else table
    u = rng.random(n) * cdf[-1]
    jbar = np.interp(u, cdf, jbar_g)
    return kappa_from_rescaled_action(jbar, state.M0)


def _phase_points_from_kappa(kappa, M0, rng):
    n = kappa.size
    w = rng.random(n) * 2.0 * np.pi
    sign = np.where(rng.random(n) < 0.5, -1.0, 1.0)
    theta, p = orbits.phase_point(w, kappa, M0, sign)
    return wrap_angle(theta), p


def sample_state(state, n, rng, method="auto", table=None):
    """Sample n particles (theta, p) from the state's f.

    method 'auto': exact thermal sampler (`sample_thermal`) for a ThermalState, else the kappa
    marginal ('kappa'): kappa from f, w uniform, direction of rotation +-1 with probability 1/2.
    table: `jbar_cdf_table(state)` if already computed (it depends on the state only: callers
    that sample one state many times pass it once instead of recomputing it, ~10 ms each).
    """
    if method == "auto":
        method = "thermal" if getattr(state, "kind", "") == "thermal" else "kappa"
    if method == "thermal":
        return sample_thermal(state, n, rng)
    if method == "kappa":
        kappa = sample_kappa(state, n, rng, table=table)
        return _phase_points_from_kappa(kappa, state.M0, rng)
    raise ValueError(f"method = {method!r}: must be 'auto', 'thermal' or 'kappa'")


def sample_uniform_jbar(M0, n, jbar_range, rng):
    """Test particles uniform in the rescaled action J-bar over jbar_range = (min, max), with w
    uniform and a random direction of rotation."""
    lo, hi = (float(x) for x in jbar_range)
    if not (0.0 <= lo < hi and np.isfinite(hi)):
        raise ValueError(f"jbar_range = {jbar_range!r}: need 0 <= Jbar_min < Jbar_max < inf")
    jbar = lo + (hi - lo) * rng.random(n)
    kappa = kappa_from_rescaled_action(jbar, M0)
    return _phase_points_from_kappa(kappa, M0, rng)
