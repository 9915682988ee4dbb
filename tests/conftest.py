"""Shared helpers for the tests: numerically integrated pendulum orbits (independent of the
elliptic-function closed forms under test), and the grouping of the tests for pytest-xdist.

The suite runs on two workers (`-n 2 --dist loadgroup`, pyproject.toml).  Every test that
uses the shared smoke build (`_smoke.smoke_workdir`, in its own code or a fixture's) joins the
xdist group "smoke", so that one worker builds it once and runs those tests one after
another: some of them edit the build's sources and dry-run it (and put them back), which a test
reading it on the other worker must not see.  All other tests, those of the same modules too,
make what they need in their own temporary folders and run on either worker.
"""

import inspect

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp


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


def action_by_quadrature(kappa, M0, rtol=1e-13):
    """J = (1/2 pi) oint p dtheta of the pendulum orbit kappa, p = sqrt(2 (h + M0 cos theta)),
    h = M0 (2 kappa^2 - 1), by scipy quad (independent of the elliptic closed forms)."""
    h = M0 * (2.0 * kappa**2 - 1.0)

    def p(t):
        return np.sqrt(max(2.0 * (h + M0 * np.cos(t)), 0.0))

    if kappa < 1.0:
        tmax = 2.0 * np.arcsin(kappa)
        return 4.0 * quad(p, 0.0, tmax, epsabs=1e-14, epsrel=rtol)[0] / (2.0 * np.pi)
    return 2.0 * quad(p, 0.0, np.pi, epsabs=1e-14, epsrel=rtol)[0] / (2.0 * np.pi)


SMOKE_GROUP = "smoke"


_NAMES_SMOKE = {}  # function -> whether its source names smoke_workdir


def uses_smoke_build(item):
    """Whether a test reaches `_smoke.smoke_workdir`: its own code or that of any fixture it
    requests (directly or through other fixtures: pytest lists the closure) names it."""
    funcs = [getattr(item, "function", None)]
    info = getattr(item, "_fixtureinfo", None)
    if info is not None:
        funcs += [d.func for defs in info.name2fixturedefs.values() for d in defs]
    for func in funcs:
        if func not in _NAMES_SMOKE:
            try:
                _NAMES_SMOKE[func] = "smoke_workdir" in inspect.getsource(func)
            except (TypeError, OSError):  # builtins, C functions: not ours
                _NAMES_SMOKE[func] = False
        if _NAMES_SMOKE[func]:
            return True
    return False


@pytest.hookimpl(tryfirst=True)  # before xdist reads the group marks into the node ids
def pytest_collection_modifyitems(config, items):
    """Put every test that uses the shared smoke build in one xdist group (the other tests of
    the same modules run on either worker)."""
    for item in items:
        if uses_smoke_build(item):
            item.add_marker(pytest.mark.xdist_group(SMOKE_GROUP))


@pytest.fixture
def orbit():
    return integrate_orbit
