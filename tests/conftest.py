"""Shared helpers for the tests: numerically integrated pendulum orbits (independent of the
elliptic-function closed forms under test)."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp


def pendulum_rhs(t, y, M0):
    theta, p = y
    return [p, -M0 * np.sin(theta)]


def integrate_orbit(kappa, M0, sign=1.0, n_periods=1.0, n_samples=None, t_end=None):
    """Integrate h = p^2/2 - M0 cos(theta) from theta = 0, p = sign * 2 sqrt(M0) kappa (the point
    w = 0 of the angle convention) with DOP853 at rtol 1e-12.

    Returns the period measured from the orbit (time between successive upward crossings of
    p = 0 for librating orbits, or of theta = 2 pi n for rotating ones) and, if n_samples is
    given, (t, theta, p) sampled uniformly over one period.
    """
    p0 = sign * 2.0 * np.sqrt(M0) * kappa
    y0 = [0.0, p0]
    lib = kappa < 1
    if lib:

        def event(t, y, M0):
            return y[0]  # theta = 0 crossing (upwards when p > 0)

        event.direction = 1.0
    else:

        def event(t, y, M0):
            return np.sin(0.5 * y[0])  # theta = 2 pi crossing

        event.direction = 0.0
    T_guess = 4.0 * np.pi / np.sqrt(M0) / max(kappa, 0.05) + 200.0
    sol = solve_ivp(
        pendulum_rhs,
        (0.0, t_end or T_guess),
        y0,
        args=(M0,),
        method="DOP853",
        rtol=1e-12,
        atol=1e-13,
        events=event,
        dense_output=True,
    )
    times = sol.t_events[0]
    times = times[times > 1e-6]
    period = times[0]
    if n_samples is None:
        return period
    t = np.arange(n_samples) * period / n_samples
    theta, p = sol.sol(t)
    return period, t, theta, p


@pytest.fixture
def orbit():
    return integrate_orbit
