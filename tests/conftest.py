"""Shared helpers for the tests: numerically integrated pendulum orbits (independent of the
elliptic-function closed forms under test), and the grouping of the tests for pytest-xdist.

The suite runs on two workers (`-n 2 --dist loadgroup`, pyproject.toml).  Every test of a
module that uses the shared smoke build (`_smoke.smoke_workdir`) joins the xdist group "smoke",
so that one worker builds it once and runs those tests one after another: some of them edit the
build's sources and dry-run it (and put them back), which a test reading it on the other worker
must not see.  All other tests make what they need in their own temporary folders.
"""

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


SMOKE_GROUP = "smoke"


@pytest.hookimpl(tryfirst=True)  # before xdist reads the group marks into the node ids
def pytest_collection_modifyitems(config, items):
    """Put the tests of every module that uses the shared smoke build in one xdist group."""
    uses = {}
    for item in items:
        path = item.path
        if path not in uses:
            uses[path] = "smoke_workdir" in path.read_text()
        if uses[path]:
            item.add_marker(pytest.mark.xdist_group(SMOKE_GROUP))


@pytest.fixture
def orbit():
    return integrate_orbit
