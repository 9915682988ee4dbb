"""The step doubling's three backward-Euler solves share the rate and Jacobian of their common
start (`relaxation._doubling_solves`): the result must be bitwise that of three independent
solves, each evaluating its own, on a nonlinear toy operator that conserves mass."""

from types import SimpleNamespace

import numpy as np

from hmfdiff.kinetic import relaxation as R


class ToyOperator:
    """rate_i = sum_j K_ij (f_j^2 - f_i^2) with K symmetric: nonlinear, mass-conserving."""

    def __init__(self, n, seed=0):
        rng = np.random.default_rng(seed)
        K = rng.random((n, n))
        self.K = K + K.T
        np.fill_diagonal(self.K, 0.0)
        self.evaluations = 0

    def rate(self, d, level):
        self.evaluations += 1
        g = np.exp(2 * (level + d))
        return self.K @ g - self.K.sum(axis=1) * g

    def jacobian_dense(self, d, level):
        g2 = 2 * np.exp(2 * (level + d))
        J = self.K * g2[None, :]
        J[np.diag_indices_from(J)] = -self.K.sum(axis=1) * g2
        return np.asfortranarray(J)


def test_shared_start_gives_the_independent_solves_bitwise():
    n = 12
    grid = SimpleNamespace(sep=5)
    rng = np.random.default_rng(1)
    d = rng.normal(0, 0.3, n)
    d[grid.sep - 1] = 0.0
    start = R._LogDensity(grid, -0.2, d)
    vol, scales, dt = np.full(n, 0.5), np.ones(n), 0.05
    op = ToyOperator(n)
    one, two, ok = R._doubling_solves(op, vol, start, dt, scales, {})
    assert ok
    ref = ToyOperator(n)

    def solve(s, h):
        level, dd, conv = R._backward_euler_offsets(ref, vol, s.level, s.d, h, s.gauge, scales)
        assert conv
        return R._LogDensity(grid, level, dd)

    one_ref = solve(start, dt)
    two_ref = solve(solve(start, 0.5 * dt), 0.5 * dt)
    for a, b in ((one, one_ref), (two, two_ref)):
        assert a.level == b.level and np.array_equal(a.d, b.d)
    assert abs(np.sum(vol * two.f) - np.sum(vol * start.f)) < 1e-12  # mass kept
    assert op.evaluations < ref.evaluations  # the start's rate was evaluated once, not twice
