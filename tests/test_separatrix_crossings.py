"""Separatrix-crossing measurements (`hmfdiff.analysis.separatrix_crossings`) on synthetic
orbits and series with a known answer: pendulum orbits in a frozen field at any phase, orbits
integrated in a slowly modulated field whose crossings follow from the adiabatic invariance of
J-bar, kappa series with a known number of crossings, spread and rms."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from hmfdiff.analysis import separatrix_crossings as sc
from hmfdiff.meanfield import orbits


def _pendulum(t_eval, theta0, p0, modulus, phase=lambda t: 0.0):
    """theta'' = -|M|(t) sin(theta - phi(t)) integrated tightly (DOP853); (theta, p) at t_eval."""

    def rhs(t, y):
        return [y[1], -modulus(t) * np.sin(y[0] - phase(t))]

    sol = solve_ivp(
        rhs,
        (t_eval[0], t_eval[-1]),
        [theta0, p0],
        method="DOP853",
        t_eval=t_eval,
        rtol=1e-11,
        atol=1e-12,
    )
    assert sol.success
    return sol.y[0], sol.y[1]


def test_kappa_is_the_orbits_label_in_a_frozen_field_at_any_phase():
    """On exact orbits (`orbits.phase_point`) of a field of amplitude 0.6 along phi = 2.2, the
    instantaneous kappa is the orbit's kappa at every angle, for both families; rotating every
    angle and the field by the same angle changes nothing."""
    M, phi = 0.6, 2.2
    kappa = np.array([0.3, 0.9, 0.999, 1.001, 1.2, 2.5])
    w = np.linspace(0.0, 2.0 * np.pi, 50)[:, None]
    th, p = orbits.phase_point(w, kappa[None, :], M, sign=np.array([1, 1, 1, -1, 1, -1]))
    theta = th + phi
    Mx = np.full(w.shape[0], M * np.cos(phi))
    My = np.full(w.shape[0], M * np.sin(phi))
    k = sc.instantaneous_kappa(theta, p, Mx, My)
    np.testing.assert_allclose(k, np.broadcast_to(kappa, k.shape), rtol=1e-10)
    rot = 1.3
    k2 = sc.instantaneous_kappa(
        theta + rot,
        p,
        M * np.cos(phi + rot) * np.ones_like(Mx),
        M * np.sin(phi + rot) * np.ones_like(My),
    )
    np.testing.assert_allclose(k2, k, rtol=1e-12)


def test_kappa_side_is_the_side_of_the_energy():
    """sign(kappa_inst - 1) = sign(h_inst - |M|) with h_inst = p^2/2 - |M| cos(theta - phi), and
    kappa^2 = (h_inst + |M|)/(2 |M|) (eq. hmfkappa), on random points and fields."""
    rng = np.random.default_rng(3)
    theta = rng.uniform(-np.pi, np.pi, (40, 30))
    p = rng.normal(0.0, 1.5, (40, 30))
    Mx = rng.uniform(-0.8, 0.8, 40)
    My = rng.uniform(-0.8, 0.8, 40)
    M = np.hypot(Mx, My)[:, None]
    phi = np.arctan2(My, Mx)[:, None]
    h = 0.5 * p**2 - M * np.cos(theta - phi)
    k = sc.instantaneous_kappa(theta, p, Mx, My)
    np.testing.assert_allclose(k**2, (h + M) / (2.0 * M), rtol=1e-10, atol=1e-13)
    assert np.array_equal(np.sign(k - 1.0), np.sign(h - M))


def test_crossing_times_of_a_sinusoid():
    """kappa = 1 + 0.1 sin(2 pi t / 10) sampled every 0.37 over t in [0.05, 100]: 20 crossings
    (t = 5, 10, ..., 100 minus the one at 100 outside, plus none at the start), at the zeros to
    the linear interpolation's accuracy, directions alternating (first one inwards, at t = 5)."""
    t = np.arange(0.05, 99.9, 0.37)
    kappa = 1.0 + 0.1 * np.sin(2.0 * np.pi * t / 10.0)
    part, time, direction = sc.crossing_times(t, kappa)
    assert part.size == 19
    np.testing.assert_allclose(time, 5.0 * np.arange(1, 20), atol=0.02)
    np.testing.assert_array_equal(direction, np.where(np.arange(19) % 2 == 0, -1, 1))


def test_hysteresis_band_removes_flicker():
    """The same sinusoid with noise of rms 0.005: without a band the noise adds crossings near
    each zero; a band of 0.03 (6 noise rms) gives back exactly the 19 crossings, each within the
    time the sinusoid takes to cross half the band after the zero."""
    rng = np.random.default_rng(7)
    t = np.arange(0.05, 99.9, 0.01)
    clean = 0.1 * np.sin(2.0 * np.pi * t / 10.0)
    kappa = np.stack([1.0 + clean + 0.005 * rng.standard_normal(t.size) for _ in range(3)], 1)
    part0, _, _ = sc.crossing_times(t, kappa, band=0.0)
    assert part0.size > 3 * 19 * 2
    part, time, direction = sc.crossing_times(t, kappa, band=0.03)
    assert part.size == 3 * 19
    np.testing.assert_array_equal(np.bincount(part), [19, 19, 19])
    lag = time - np.repeat(5.0 * np.arange(1, 20)[None, :], 3, 0).ravel()
    # 0.03 of a slope 2 pi 0.1 / 10: a delay of ~0.48, noise included
    assert np.all((lag > 0.2) & (lag < 0.8))
    assert set(direction[part == 1][:2]) == {-1, 1}


def test_bottom_passages_ignore_the_wrap_at_the_x_point():
    """A rotating particle, theta = 1.1 t wrapped to [-pi, pi): one passage per revolution, at
    t = 2 pi k / 1.1, none where theta wraps at +-pi; a librating one alternates directions; a
    particle wobbling about the X point (theta = pi + 0.2 sin t, wrapped) makes none."""
    t = np.arange(0.0, 60.0, 0.3)
    rot = np.mod(1.1 * t + np.pi, 2 * np.pi) - np.pi
    lib = 2.0 * np.sin(0.5 * t + 0.3)
    wob = np.mod(np.pi + 0.2 * np.sin(t) + np.pi, 2 * np.pi) - np.pi
    part, time, direction = sc.bottom_passages(t, np.stack([rot, lib, wob], 1), phase=0.0)
    r = part == 0
    n_rev = int(np.floor(1.1 * 59.7 / (2 * np.pi)))
    np.testing.assert_allclose(time[r], 2 * np.pi * np.arange(1, n_rev + 1) / 1.1, atol=0.02)
    assert np.all(direction[r] == 1)
    d_lib = direction[part == 1]
    assert d_lib.size > 5 and np.all(d_lib[1:] * d_lib[:-1] == -1)
    assert not np.any(part == 2)


def test_modulated_pendulum_crossings_against_energy_and_adiabatic_invariance():
    """A particle in |M|(t) = 0.7 (1 + 0.1 sin(2 pi t / 400)) along a rotating phase
    phi = 0.002 t, with J-bar = J-bar_s(0.7 * 1.05): its kappa_inst crosses 1 exactly where its
    energy crosses the instantaneous separatrix (sign changes of p^2/2 - |M| cos(theta - phi)
    - |M| on the same samples), and by the adiabatic invariance of J-bar its family changes where
    J-bar_s(|M|(t)) = J-bar, i.e. sin(2 pi t / 400) = 1/2: at t = 33.3, 166.7 (+ 400 k), six
    changes in [0, 1200] alternating rotation -> libration (trapping) and back."""
    M0, a, Tm = 0.7, 0.1, 400.0
    modulus = lambda t: M0 * (1.0 + a * np.sin(2 * np.pi * t / Tm))  # noqa: E731
    phase = lambda t: 0.002 * t  # noqa: E731
    jbar0 = float(orbits.jbar_separatrix(M0 * (1.0 + a / 2)))
    k0 = float(orbits.kappa_from_rescaled_action(np.array([jbar0]), M0)[0])
    th0, p0 = orbits.phase_point(0.4, k0, M0, 1.0)
    t = np.arange(0.0, 1200.0, 0.25)
    theta, p = _pendulum(t, float(th0), float(p0), modulus, phase)
    Mt, ph = modulus(t), phase(t)
    Mx, My = Mt * np.cos(ph), Mt * np.sin(ph)
    k = sc.instantaneous_kappa(theta[:, None], p[:, None], Mx, My)
    energy = 0.5 * p**2 - Mt * np.cos(theta - ph) - Mt
    n_energy = int(np.count_nonzero(np.diff(np.sign(energy)) != 0))
    part, _, _ = sc.crossing_times(t, k)
    assert part.size == n_energy and n_energy >= 6
    passages = sc.bottom_passages(t, theta[:, None], ph)
    changes = sc.family_changes(*passages)
    expected = np.sort(
        np.concatenate([np.array([Tm / 12, 5 * Tm / 12]) + Tm * j for j in range(3)])
    )
    assert changes[1].size == 6
    np.testing.assert_allclose(changes[1], expected, atol=20.0)
    np.testing.assert_array_equal(changes[2], [-1, 1, -1, 1, -1, 1])
    # J-bar (frozen field, instantaneous |M|) across each change: the adiabatic jump, O(eps)
    jbar = sc.rescaled_action_in_field(k, Mt)
    jump, before, keep = sc.action_jumps(t, jbar, passages, changes)
    assert keep.all()
    np.testing.assert_allclose(before, jbar0, rtol=0.02)
    assert np.max(np.abs(jump)) < 0.02 * jbar0


def test_linear_ramp_one_escape_with_a_small_jump_and_a_bystander():
    """|M| falls linearly from 0.8 to 0.4 over t in [0, 800]: a librating particle with
    J-bar = J-bar_s(0.64) escapes into rotation once, at t = 320 (adiabatic invariance; within a
    few half-orbits), with |Delta J-bar| far below J-bar (eps = |d|M|/dt| / (|M| sqrt|M|) ~ 1e-3);
    a deep librating bystander (kappa 0.5) never changes family and does not leak into the
    first particle's averages."""
    modulus = lambda t: 0.8 - 0.4 * np.clip(t / 800.0, 0.0, 1.0)  # noqa: E731
    jbar0 = float(orbits.jbar_separatrix(0.64))
    k0 = float(orbits.kappa_from_rescaled_action(np.array([jbar0]), 0.8)[0])
    t = np.arange(0.0, 700.0, 0.25)
    cols = []
    for kk, w in ((0.5, 1.0), (k0, 0.1)):  # the bystander first: column 0
        th0, p0 = orbits.phase_point(w, kk, 0.8, 1.0)
        cols.append(_pendulum(t, float(th0), float(p0), modulus))
    theta = np.stack([c[0] for c in cols], 1)
    p = np.stack([c[1] for c in cols], 1)
    Mt = modulus(t)
    k = sc.instantaneous_kappa(theta, p, Mt, np.zeros_like(Mt))
    passages = sc.bottom_passages(t, theta)
    changes = sc.family_changes(*passages)
    assert changes[0].tolist() == [1]
    assert changes[2].tolist() == [1]
    assert abs(changes[1][0] - 320.0) < 15.0
    jbar = sc.rescaled_action_in_field(k, Mt)
    jump, before, keep = sc.action_jumps(t, jbar, passages, changes)
    assert keep.all()
    assert abs(before[0] - jbar0) < 0.01 * jbar0
    assert abs(jump[0]) < 0.01 * jbar0


def test_kappa_spread_over_a_period():
    """kappa = 1.01 + A sin(2 pi t / W) + a linear trend: the running mean over W removes the
    sinusoid and the (linear) trend exactly, leaving A/sqrt(2); white noise of rms s leaves
    s sqrt(1 - 1/n_w); a series far from the separatrix (kappa = 1.5) is not selected."""
    W, dt, A = 12.5, 0.5, 0.004  # 25 samples a period; 48 whole periods selected
    t = np.arange(0.0, 612.0, dt)
    near = 1.01 + A * np.sin(2 * np.pi * t / W) + 1e-5 * t
    far = 1.5 + 0.1 * np.sin(2 * np.pi * t / W)
    spread, n = sc.kappa_spread_over_period(t, np.stack([near, far], 1), W, near=0.05)
    assert n == t.size - 24
    assert spread == pytest.approx(A / np.sqrt(2.0), rel=1e-10)
    rng = np.random.default_rng(11)
    s = 0.003
    noisy = 1.0 + s * rng.standard_normal((t.size, 40))
    spread, n = sc.kappa_spread_over_period(t, noisy, W)
    assert spread == pytest.approx(s * np.sqrt(1 - 1 / 25), rel=0.02)


def test_separatrix_motion_of_a_known_series():
    """|M| = 0.7 + 0.01 xi (xi unit Gaussian): rms dM = 0.01 (about the series' own mean),
    kappa-width 0.01 / 1.4, sqrt(N) rms dM = 0.01 sqrt(N)."""
    rng = np.random.default_rng(5)
    m = 0.7 + 0.01 * rng.standard_normal(200_000)
    out = sc.separatrix_motion(m, 2500)
    assert out["rms_dM"] == pytest.approx(0.01, rel=0.01)
    assert out["kappa_width"] == pytest.approx(0.01 / 1.4, rel=0.01)
    assert out["sqrtN_rms_dM"] == pytest.approx(0.5, rel=0.01)
    assert out["M0"] == pytest.approx(0.7, abs=1e-4)


def test_crossing_rate_and_its_error():
    """Poisson counts of rate 0.02 over 200 realisations of particle-time 5000: the rate within
    3 standard errors, and the error equal to the Poisson one, sqrt(rate / exposure) / sqrt(R)."""
    rng = np.random.default_rng(2)
    e = np.full(200, 5000.0)
    c = rng.poisson(0.02 * e)
    rate, err = sc.crossing_rate(c, e)
    assert abs(rate - 0.02) < 3 * err
    assert err == pytest.approx(np.sqrt(0.02 / 5000.0 / 200), rel=0.15)


def test_scaling_exponent_recovers_a_power_law():
    """y = 3 N^-0.5 exactly: b = -0.5, a = 3; with 5% scatter and its errors, b within 3 sigma."""
    N = np.array([1e3, 2e3, 4e3, 8e3, 1.6e4])
    b, db, a, _ = sc.scaling_exponent(N, 3.0 * N**-0.5, 0.01 * 3.0 * N**-0.5)
    assert b == pytest.approx(-0.5, abs=1e-12) and a == pytest.approx(3.0, rel=1e-12)
    rng = np.random.default_rng(4)
    y = 3.0 * N**-0.5 * (1 + 0.05 * rng.standard_normal(N.size))
    b, db, _, _ = sc.scaling_exponent(N, y, 0.05 * y)
    assert abs(b + 0.5) < 3 * db
