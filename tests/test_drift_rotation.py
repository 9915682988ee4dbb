"""The MD's drift as a rotation of (sin theta, cos theta) in float32 (issue 23 part 2): the
polynomial sincos of the drift angle against numpy, a free rotation against its exact answer on
each of the kernel's paths (the short and the long polynomial ones, |dt p| <= DRIFT_SHORT and
<= DRIFT_MAX, and the general one for fast particles), the norm of (sin, cos) over a long call,
and the actions measured from (sin, cos, p) against those from (theta, p)."""

import mpmath
import numpy as np
import pytest

from hmfdiff.dynamics import elementary, integrator, sampling
from hmfdiff.dynamics.integrator import Field
from hmfdiff.meanfield import orbits

HALF_ULP = 2.0**-24  # float32's half ulp of 1 (6e-8): the state's rounding per operation


def drift32(dt, p):
    """The drift angle of one step as the kernel forms it: float32(dt) * float32(p), rounded."""
    return float(np.float32(np.float32(dt) * np.float32(p)))


@pytest.mark.parametrize("short", [False, True], ids=["long", "short"])
def test_drift_sincos_matches_numpy_on_its_domain(short):
    """The float32 polynomials of the step's rotation are sin and cos of their float32
    argument to about half an ulp (0.55 measured: nearly correctly rounded) over their domain;
    the Taylor polynomials they replaced erred by 1.0 ulp, and the short ones taken over the
    long domain err by 1.2e-6, 41 ulps."""
    top = elementary.DRIFT_SHORT if short else elementary.DRIFT_MAX
    x = np.concatenate([np.linspace(-top, top, 200_001), [0.0, 1e-30]]).astype(np.float32)
    s, c = elementary.sincos_drift_array(x, short=short)
    assert s.dtype == np.float32 and c.dtype == np.float32
    xs = x.astype(np.float64)
    ulp_s = np.spacing(np.abs(np.sin(xs)).astype(np.float32)).astype(np.float64)
    ulp_c = np.spacing(np.cos(xs).astype(np.float32)).astype(np.float64)
    assert np.max(np.abs(s - np.sin(xs)) / ulp_s) < 0.75
    assert np.max(np.abs(c - np.cos(xs)) / ulp_c) < 0.75


def exact_free_angles(S0, C0, p, dt, n):
    """The start's angle atan2(S0, C0) advanced by n drift angles `drift32(dt, p)`, wrapped, in
    40-digit arithmetic."""
    mpmath.mp.dps = 40
    out = []
    for s0, c0, pp in zip(S0, C0, p, strict=True):
        x = mpmath.atan2(mpmath.mpf(float(s0)), mpmath.mpf(float(c0)))
        x += n * mpmath.mpf(drift32(dt, pp))
        out.append(float(mpmath.atan2(mpmath.sin(x), mpmath.cos(x))))
    return np.array(out)


@pytest.mark.parametrize(
    "p",
    [
        # the bound (sum p^8)^(1/8) < DRIFT_SHORT / dt: the short polynomial path
        [1e-3, 0.7, -2.3, 3.0, -2.5, 1.1],
        # all |dt p| <= 0.4 (and the bound < DRIFT_MAX / dt): the long polynomial path
        [1e-3, 0.7, -2.3, 8.0, -7.5, 3.3],
        # fast particles in the chunk (|dt p| up to 12.5): the general path for all of them
        [1e-3, 0.7, -2.3, 9.9, 10.5, 100.0, -250.0],
    ],
    ids=["short", "long", "general"],
)
def test_free_rotation_follows_the_exact_angle(p):
    """No field: the angle advances by the step's drift angle exactly, each step.  After
    20 000 steps of dt = 0.05 the angle (atan2 of the rotated sin, cos) is within one half
    ulp of float32 per step (1.2e-3; measured up to 7.4e-4: the rotation's rounding, which a
    nearly constant angle makes coherent, a relative frequency error below 1e-6); a wrong
    coefficient of d^5 (1/100 for 1/120) errs by 2.5e-3 at |d| = 0.15 and far more on the long
    path.  p is unchanged and (sin, cos) of unit norm to float32's precision after the
    closing kick."""
    p = np.array(p)
    theta0 = np.linspace(-3.1, 3.1, p.size)
    P = integrator.Particles(theta0, p)
    S0, C0 = P.S.copy(), P.C.copy()
    dt, n = 0.05, 0
    for _ in range(500):
        integrator.leapfrog(P, 40, dt, Field.STATIC, fx=0.0, fy=0.0)
        n += 40
    err = np.abs(sampling.wrap_angle(P.theta - exact_free_angles(S0, C0, p, dt, n)))
    assert np.max(err) < n * HALF_ULP
    np.testing.assert_array_equal(P.p, p.astype(np.float32))
    norm2 = P.S.astype(np.float64) ** 2 + P.C.astype(np.float64) ** 2
    assert np.max(np.abs(norm2 - 1)) < 4 * HALF_ULP


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
        ([0.5, -2.0, 4.5, 8.0, -9.4], "long"),  # bound 9.69: 0.485, |dt p| up to 0.47
    ],
)
def test_one_drift_is_the_exact_rotation_on_each_taylor_path(p, path):
    """One step in no field rotates (sin theta, cos theta) by d = `drift32(dt, p)`: against the
    rotation in 40-digit arithmetic, to float32's rounding, on the path the chunk's bound
    picks.  The bound is that of the float32 rotation S cos d + C sin d itself: sin d and
    cos d each within one half-ulp u = 2^-24 relative, two products and a sum each rounded,
    |S| + |C| <= sqrt(2): at most (1 + 2 sqrt(2)) u = 2.3e-7, whether or not the compiler fuses
    a product into an FMA (measured 8e-8 on one CPU, 1.4e-7 on a Rocket Lake, 2026-11-27).  A
    path taken beyond its domain (the short polynomial at |d| = 0.47 errs by 1.4e-6) fails."""
    p = np.array(p)
    dt = 0.05
    bound = float(np.sum(p**8) ** 0.125) * dt
    assert (bound <= elementary.DRIFT_SHORT) == (path == "short") and bound <= elementary.DRIFT_MAX
    P = integrator.Particles(np.linspace(-2.9, 2.8, p.size), p)
    S0, C0 = P.S.copy(), P.C.copy()
    P.open_steps(1, dt=dt, field=Field.STATIC)
    np.testing.assert_array_equal(P.p, p.astype(np.float32))
    mpmath.mp.dps = 40
    for i in range(p.size):
        d = mpmath.mpf(drift32(dt, p[i]))
        s = mpmath.mpf(float(S0[i])) * mpmath.cos(d) + mpmath.mpf(float(C0[i])) * mpmath.sin(d)
        c = mpmath.mpf(float(C0[i])) * mpmath.cos(d) - mpmath.mpf(float(S0[i])) * mpmath.sin(d)
        err = max(abs(float(P.S[i]) - float(s)), abs(float(P.C[i]) - float(c)))
        assert err < (1 + 2 * np.sqrt(2)) * HALF_ULP, (i, path, err)


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
    """Particle 0 accelerated uniformly from rest (F = 20, dt = 0.05: its drift angle passes
    DRIFT_SHORT at step 4 and DRIFT_MAX at step 10, and reaches 3) among slow ones: the chunk's
    bound on |p|, grown by each step's largest kick between refreshes, must keep the chunk off
    a polynomial path beyond its domain.  Against the same steps in float64 with numpy's sin and
    cos: p within 1e-4 (float32's ulp of p ~ 60 is 3.8e-6; measured 1.2e-5), sin and cos
    within 3e-5 (measured 6e-6); a bound that does not grow errs by 5e-2."""
    theta0, p0 = np.linspace(-3.0, 3.0, 8), np.linspace(-0.5, 0.5, 8)
    p0[0] = 0.0
    dt, n = 0.05, 60
    S, C, p, field = accelerated_reference(theta0, p0, 20.0, dt, n)
    assert p[0] == pytest.approx(20.0 * dt * (n - 0.5))  # the field does what it is meant to
    P = integrator.Particles(theta0, p0)
    P.open_steps(n, dt=dt, field=Field.EXTERNAL, history=field)
    assert np.max(np.abs(P.p - p)) < 1e-4
    assert max(np.max(np.abs(P.S - S)), np.max(np.abs(P.C - C))) < 3e-5


def test_the_norm_of_sin_and_cos_stays_near_one_over_a_long_call():
    """A float32 rotation by a nearly constant angle changes the norm of (sin, cos) coherently,
    by up to ~4e-8 a step (1e-3 after 2e4 steps, measured on some angles): the kernel divides
    by the norm every `_BOUND_REFRESH` (32) steps, so within one long call, with no closing
    kick, the norm stays within 32 half ulps, 2e-6, of 1 (measured 2.0e-6; ensemble intervals
    run 1e5 steps and more)."""
    rng = np.random.default_rng(5)
    p = rng.uniform(-4.0, 4.0, 5000)
    P = integrator.Particles(rng.uniform(-np.pi, np.pi, p.size), p)
    P.open_steps(20_000, dt=0.05, field=Field.STATIC)
    norm2 = P.S.astype(np.float64) ** 2 + P.C.astype(np.float64) ** 2
    assert np.max(np.abs(np.sqrt(norm2) - 1)) < 4e-6
