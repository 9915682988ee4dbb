"""Guards for hmfdiff.kinetic.relaxation: the orbits of each step are those of the
mid-step magnetisation.

`evolve` builds the collision operator of each step at a predicted mid-step M0 (the docstring:
this makes the energy error of the M0 update third order).  A bug that drops the prediction
(orbits of the step's start) or gets its sign wrong changes u by less than the tolerance of
the conservation tests, so the prediction is checked here directly against the trajectory
M0(tau) that the run itself records: the magnetisation handed to the operator factory (the
testing seam of `evolve`) must be the run's M0 half-way through that step, found by cubic
interpolation of the recorded M0(tau), not the formula of the code."""

import numpy as np
from scipy.interpolate import CubicSpline

from hmfdiff.kinetic.relaxation import RelaxationSettings, _Operator, evolve
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
        equation="landau", n_nodes=48, kappa_max=3.5, tau_max=4.0, thermal_tol=0.0
    )
    seen = []

    def factory(grid, f, M):
        seen.append(M)
        return _Operator(grid, f, M, s).op

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
    assert np.median(rel) < 0.2, rel
