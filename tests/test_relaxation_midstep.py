"""Guards for hmfdiff.kinetic.relaxation: the orbits of each step are those of the
mid-step magnetisation.

`evolve` builds the collision operator of each step at a predicted mid-step M0 (the docstring:
this makes the energy error of the M0 update third order).  A bug that drops the prediction
(orbits of the step's start) or gets its sign wrong changes u by less than the tolerance of
the conservation tests, so the prediction is checked here directly against the trajectory
M0(tau) that the run itself records: the magnetisation handed to the operator factory (the
testing seam of `evolve`) must be the run's M0 half-way through that step, found by cubic
interpolation of the recorded M0(tau), not the formula of the code.  And the implicit step
itself (`_backward_euler`) against a direct solve of a linear operator's step."""

import warnings

import numpy as np
from scipy import sparse
from scipy.interpolate import CubicSpline

from hmfdiff.kinetic.relaxation import Kinetics, RelaxationSettings, _backward_euler, evolve
from hmfdiff.meanfield.equilibrium import make_state

HOT = dict(kind="core_halo", eta1=0.3, eta2=0.01, mu1=-0.5, mu2=1.2, beta1=40.0, beta2=2.0)


def test_each_step_uses_the_orbits_of_its_mid_step_magnetisation():
    """Guards against orbits frozen at the step's start (prediction dropped: the error is half
    the step's change of M0) and a predictor of the wrong sign (1.5 times that change); with
    the mid-step prediction the error is second order (measured median below 5 % of the
    change).  Reference: M0 at tau_{k-1} + dtau_k / 2 from a cubic spline through the recorded
    (tau, M0) of the same run."""
    state = make_state(HOT)
    s = RelaxationSettings(
        equation="landau",
        n_nodes=48,
        kappa_max=3.5,
        tau_max=4.0,
        thermal_tol=0.0,
        dlog_omega=0.1,
        layer_eta_min=1e-4,
    )
    seen = []
    kinetics = {}

    def factory(grid, f, M):
        seen.append(M)
        kin = kinetics.setdefault(id(grid), Kinetics(grid, s))
        return kin.operator(f, M)

    out = evolve(state, s, operator=factory)
    tau, M0 = out["tau"], out["M0"]
    n = out["n_steps"]
    # calls: the flux at tau = 0 (its operator serves step 1), one per step k >= 2, the flux at
    # the end
    assert len(seen) == n + 1 and n >= 8
    used = np.asarray(seen[1:n])  # steps 2 ... n
    mid = CubicSpline(tau, M0)(0.5 * (tau[1:n] + tau[2 : n + 1]))
    change = np.abs(np.diff(M0))[1:n]
    assert np.all(change > 0)
    rel = np.abs(used - mid) / change
    # the steps after the layer next to the separatrix has adapted (tau > 0.01), where M0(tau)
    # is smooth enough for the spline to be the reference
    late = tau[1:n] > 0.01
    assert late.sum() >= 6
    assert np.median(rel[late]) < 0.2, rel


class _LinearOperator:
    """rate(y) = A (e^y - e^y0) with the Jacobian d rate / dy = A diag(e^y), A sparse."""

    def __init__(self, A, y0):
        self.A = sparse.csr_matrix(A)
        self.f0 = np.exp(y0)

    def rate(self, y):
        return self.A @ (np.exp(y) - self.f0)

    def jacobian(self, y):
        return self.A @ sparse.diags(np.exp(y))


def test_backward_euler_solves_a_linear_step_and_reports_a_singular_one():
    """One implicit step vol (e^y - e^y0) = dt A (e^y - e^y0) + dt A (e^y0 - f0) of a linear
    operator, against numpy's direct solve of the same linear system for e^y; and a step
    whose Newton matrix is exactly singular (dt A = vol) comes back unchanged and flagged,
    with no warning."""
    rng = np.random.default_rng(3)
    n = 40
    vol = rng.uniform(0.5, 1.5, n)
    y0 = rng.normal(-1.0, 0.3, n)
    A = -np.diag(rng.uniform(1, 2, n)) + 0.1 * rng.uniform(0, 1, (n, n)) * (
        rng.random((n, n)) < 0.2
    )
    y_ref = y0 + 0.05 * rng.normal(size=n)  # the operator's reference point f0 = e^y_ref
    op = _LinearOperator(A, y_ref)
    dt = 0.3
    y, ok = _backward_euler(op, vol, y0, dt)
    assert ok
    # vol f - vol f_prev = dt A (f - f0)  =>  (diag(vol) - dt A) f = vol f_prev - dt A f0
    f = np.linalg.solve(np.diag(vol) - dt * A, vol * np.exp(y0) - dt * A @ np.exp(y_ref))
    np.testing.assert_allclose(np.exp(y), f, rtol=1e-10)
    singular = _LinearOperator(np.diag(vol / dt), y_ref)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        y1, ok1 = _backward_euler(singular, vol, y0, dt)
    assert not ok1 and np.array_equal(y1, y0)
