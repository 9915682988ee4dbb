"""analysis.walkers against known answers: constant D, linear D (Ito drift), the barrier."""

import numpy as np
import pytest

from hmfdiff.analysis.walkers import walk_msd, walker_nd

LAGS = np.arange(0.0, 201.0, 2.0)
WINDOW = (50.0, 200.0)


def test_constant_d_gives_d():
    # walls far away: <dx^2> = 2 D t, so the fit reads N D exactly (up to Monte Carlo)
    N, D = 1e6, 0.3e-6
    nodes = np.linspace(0.0, 1.0, 11)
    start = np.linspace(0.45, 0.55, 20000)
    msd = walk_msd(nodes, np.full(11, D), start, LAGS, dt=0.5, seed=1, batches=10)
    nd = walker_nd(LAGS, msd, WINDOW, N)
    assert nd.mean() == pytest.approx(N * D, rel=3.0 * nd.std(ddof=1) / np.sqrt(nd.size) / 0.3)
    assert nd.mean() == pytest.approx(N * D, rel=0.02)
    # the J jacobian of librating bins multiplies it by 4
    assert walker_nd(LAGS, msd.mean(0), WINDOW, N, jac2=4.0) == pytest.approx(4 * nd.mean())


def test_linear_d_has_the_ito_drift():
    # D = b x: d<(x - x0)^2>/dt = 2 D(x0) + 4 b^2 t (no wall reached: x0 = 1 lies 3 sd of the
    # spread at lag 200 above D = 0), so the slope over uniformly spaced lags in [t1, t2] is
    # 2 D(x0) + 2 b^2 (t1 + t2): the drift adds 6 % here, a walk without it fails
    N, b = 1e4, 2.5e-4
    nodes = np.linspace(0.0, 3.0, 3)
    msd = walk_msd(nodes, b * nodes, np.ones(200000), LAGS, dt=0.5, seed=2, batches=8)
    expected = N * (b + b**2 * (WINDOW[0] + WINDOW[1]))
    assert walker_nd(LAGS, msd.mean(0), WINDOW, N) == pytest.approx(expected, rel=0.015)


def test_barrier_reflects():
    # D large below J-bar = 0.5, small above: walkers started just above stay in the slow
    # region with the barrier (<dx^2> about 2 D t of the slow side) and leak into the fast
    # region without it
    nodes = np.array([0.0, 0.499, 0.5, 1.0])
    d = np.array([1e-2, 1e-2, 1e-6, 1e-6])
    start = np.full(4000, 0.5005)
    held = walk_msd(nodes, d, start, [0.0, 20.0], dt=0.05, seed=3, batches=1, barrier=0.5)
    free = walk_msd(nodes, d, start, [0.0, 20.0], dt=0.05, seed=3, batches=1)
    assert held[0, 0] == 0.0
    assert held[0, 1] < 3.0 * 2e-6 * 20.0
    assert free[0, 1] > 100.0 * 2e-6 * 20.0


def test_bad_input():
    with pytest.raises(ValueError):
        walk_msd([0.0, 1.0], [1.0, -1.0], [0.5], LAGS, dt=0.5)
    with pytest.raises(ValueError):
        walk_msd([0.0, 1.0], [1.0, 1.0], [2.0], LAGS, dt=0.5)
