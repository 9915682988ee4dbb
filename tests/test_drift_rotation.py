"""The MD's drift as a rotation of (sin theta, cos theta) (issue 23 part 2): the Taylor sincos of
the drift angle against numpy, a free rotation against its exact answer on each of the
kernel's paths (the short and the long Taylor ones, |dt p| <= DRIFT_SHORT and <= DRIFT_MAX, and
the general one for fast particles), and the actions measured from (sin, cos, p) against those
from (theta, p)."""

import mpmath
import numpy as np
import pytest

from hmfdiff.dynamics import elementary, integrator, sampling
from hmfdiff.dynamics.integrator import Field
from hmfdiff.meanfield import orbits


@pytest.mark.parametrize("short", [False, True], ids=["long", "short"])
def test_drift_sincos_matches_numpy_on_its_domain(short):
    top = elementary.DRIFT_SHORT if short else elementary.DRIFT_MAX
    x = np.concatenate([np.linspace(-top, top, 200_001), [0.0, 1e-300]])
    s, c = elementary.sincos_drift_array(x, short=short)
    assert np.max(np.abs(s - np.sin(x))) < 2e-16
    assert np.max(np.abs(c - np.cos(x))) < 2e-16
    big = np.abs(x) > 1e-3
    assert np.max(np.abs(s[big] / np.sin(x[big]) - 1)) < 5e-16


def exact_free_angles(theta0, p, dt, n):
    """theta0 + n dt p, wrapped, in 40-digit arithmetic (dt and p as the floats given)."""
    mpmath.mp.dps = 40
    out = []
    for t0, pp in zip(theta0, p, strict=True):
        x = mpmath.mpf(float(t0)) + n * mpmath.mpf(dt) * mpmath.mpf(float(pp))
        out.append(float(mpmath.atan2(mpmath.sin(x), mpmath.cos(x))))
    return np.array(out)


@pytest.mark.parametrize(
    "p, tol",
    [
        # the bound (sum p^8)^(1/8) < DRIFT_SHORT / dt: the short Taylor path
        ([1e-3, 0.7, -2.3, 3.0, -2.5, 1.1], 2e-12),
        # all |dt p| <= 0.4 (and the bound < DRIFT_MAX / dt): the long Taylor path
        ([1e-3, 0.7, -2.3, 8.0, -7.5, 3.3], 2e-12),
        # fast particles in the chunk (|dt p| up to 12.5): the general path for all of them
        ([1e-3, 0.7, -2.3, 9.9, 10.5, 100.0, -250.0], 3e-11),
    ],
)
def test_free_rotation_follows_the_exact_angle(p, tol):
    """No field: theta(t) = theta0 + p t exactly.  After 20 000 steps of dt = 0.05 the angle
    (atan2 of the rotated sin, cos) is within a few 1e-13 (1e-11 for |dt p| ~ 10, where the
    drift angle's own rounding, ulp(12.5) per step, dominates, as it did for a stored theta),
    and (sin, cos) is of unit norm after the closing kick."""
    p = np.array(p)
    theta0 = np.linspace(-3.1, 3.1, p.size)
    P = integrator.Particles(theta0, p)
    dt, n = 0.05, 0
    for _ in range(500):
        integrator.leapfrog(P, 40, dt, Field.STATIC, fx=0.0, fy=0.0)
        n += 40
    err = np.abs(sampling.wrap_angle(P.theta - exact_free_angles(theta0, p, dt, n)))
    assert np.max(err) < tol
    np.testing.assert_array_equal(P.p, p)
    assert np.max(np.abs(P.S**2 + P.C**2 - 1)) < 1e-15


def test_frame_actions_agree_with_actions_of_angles():
    """(J, J-bar) from (sin theta, cos theta, p) in a rotated frame against those from (theta,
    p), on random orbits, deeply trapped ones (theta - phase ~ 1e-6), near the separatrix and
    with (sin, cos) off unit norm by 1e-12 (a rotated pair between closing kicks)."""
    M0 = 0.6
    rng = np.random.default_rng(2)
    kappa = np.concatenate(
        [
            rng.uniform(0.01, 3.0, 2000),
            np.logspace(-7, -2, 50),
            1 - np.logspace(-12, -3, 40),
            1 + np.logspace(-12, -3, 40),
        ]
    )
    w = rng.uniform(0, 2 * np.pi, kappa.size)
    sign = np.where(rng.random(kappa.size) < 0.5, -1.0, 1.0)
    th, p = orbits.phase_point(w, kappa, M0, sign)
    phase = -2.4
    theta = sampling.wrap_angle(th + phase)
    J, Jb = elementary.actions(theta, p, M0, phase=phase)
    S, C = np.sin(theta), np.cos(theta)
    scale = 1 + 1e-12 * rng.uniform(-1, 1, theta.size)
    Js, Jbs = elementary.frame_actions(S * scale, C * scale, p, M0, phase)
    # rounding: (sin, cos) hold the angle to ~1e-16 absolute, as theta does; near the bottom
    # of the well (kappa ~ |theta - phase| / 2) that is dJ ~ 2 sqrt(M0) kappa d(theta)
    tol = 2e-11 * J + 1e-14 * kappa
    assert np.all(np.abs(Js - J) <= tol)
    assert np.all(np.abs(Jbs - Jb) <= tol)
    # and the points are those orbits (away from the separatrix, where rounding may move a
    # point across it, and the bottom of the well)
    np.testing.assert_allclose(J[:2000], orbits.action(kappa[:2000], M0), rtol=1e-9)


@pytest.mark.parametrize(
    "p, path",
    [
        ([0.5, 1.5, -2.5, 3.0], "short"),  # chunk bound 3.08: dt |p| <= 0.154 <= DRIFT_SHORT
        ([0.5, -2.0, 4.5, 6.0, -6.8], "long"),  # bound 7.1: 0.355, |dt p| up to 0.34
    ],
)
def test_one_drift_is_the_exact_rotation_on_each_taylor_path(p, path):
    """One step in no field rotates (sin theta, cos theta) by d = dt p: against the rotation
    in 40-digit arithmetic, to rounding (4e-16), on the path the chunk's bound picks.  A path
    taken beyond its domain (the short polynomial at |d| = 0.34 errs by 5e-15) fails here."""
    p = np.array(p)
    dt = 0.05
    bound = float(np.sum(p**8) ** 0.125) * dt
    assert (bound <= elementary.DRIFT_SHORT) == (path == "short") and bound <= elementary.DRIFT_MAX
    P = integrator.Particles(np.linspace(-2.9, 2.8, p.size), p)
    S0, C0 = P.S.copy(), P.C.copy()
    P.open_steps(1, dt=dt, field=Field.STATIC)
    np.testing.assert_array_equal(P.p, p)
    mpmath.mp.dps = 40
    for i in range(p.size):
        d = mpmath.mpf(dt) * mpmath.mpf(float(p[i]))
        s = mpmath.mpf(float(S0[i])) * mpmath.cos(d) + mpmath.mpf(float(C0[i])) * mpmath.sin(d)
        c = mpmath.mpf(float(C0[i])) * mpmath.cos(d) - mpmath.mpf(float(S0[i])) * mpmath.sin(d)
        assert abs(P.S[i] - float(s)) < 4e-16 and abs(P.C[i] - float(c)) < 4e-16, (i, path)


def accelerated_reference(theta0, p0, F, dt, n):
    """The kernel's steps with numpy's sin and cos of the drift angle, in a field that at each
    step kicks particle 0 by exactly F (F along its direction of motion): (S, C, p) after n
    steps opened by a half kick, and that field, one row per step, as `open_steps` takes it."""
    S, C, p = np.sin(theta0), np.cos(theta0), np.array(p0, dtype=float)
    field = np.zeros((n, 4))
    for j in range(n):
        fx, fy = -F * S[0], F * C[0]
        field[j, 2:] = fx, fy
        p = p + (0.5 * dt if j == 0 else dt) * (fy * C - fx * S)
        d = dt * p
        S, C = S * np.cos(d) + C * np.sin(d), C * np.cos(d) - S * np.sin(d)
    return S, C, p, field


def test_a_particle_accelerated_through_every_path_keeps_exact_rotations():
    """Particle 0 accelerated uniformly from rest (F = 5, dt = 0.05: its drift angle passes
    DRIFT_SHORT at step 16 and DRIFT_MAX at step 40) among slow ones: the chunk's bound on |p|,
    grown by each step's largest kick between refreshes, must keep the chunk off a Taylor path
    beyond its domain.  Against the same steps with numpy's sin and cos: 1e-14 (a bound that
    does not grow gives 4e-13)."""
    theta0, p0 = np.linspace(-3.0, 3.0, 8), np.linspace(-0.5, 0.5, 8)
    p0[0] = 0.0
    dt, n = 0.05, 60
    S, C, p, field = accelerated_reference(theta0, p0, 5.0, dt, n)
    assert p[0] == pytest.approx(5.0 * dt * (n - 0.5))  # the field does what it is meant to
    P = integrator.Particles(theta0, p0)
    P.open_steps(n, dt=dt, field=Field.EXTERNAL, history=field)
    assert np.max(np.abs(P.p - p)) < 5e-14
    assert max(np.max(np.abs(P.S - S)), np.max(np.abs(P.C - C))) < 5e-14
