"""Tests of the HMF molecular dynamics (hmfdiff.dynamics): kernels against numpy / scipy, the
integrator's conservation laws and reversibility, the frame of the magnetisation, determinism,
and the <dJ^2> accumulator on synthetic data with a known answer."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from hmfdiff.dynamics import accumulator, elementary, integrator, md, sampling
from hmfdiff.dynamics.integrator import Field
from hmfdiff.dynamics.settings import MDRun
from hmfdiff.meanfield import equilibrium, orbits
from hmfdiff.pipeline.layouts.md import md_dataset

M0 = 0.72846  # paper case (u, M0) = (-0.1, 0.72846)


@pytest.fixture(scope="module")
def state():
    return equilibrium.ThermalState(M0=M0)


def thermal_particles(state, n, seed):
    th, p = sampling.sample_thermal(state, n, sampling.make_rng(seed))
    th, _ = sampling.rotate_to_x_axis(th)
    return th, p - p.mean()


# ------------------------------------------------------------------ kernels vs references
def test_sincos_matches_numpy():
    x = np.linspace(-4 * np.pi, 4 * np.pi, 400_001)
    x = np.concatenate([x, np.arange(-8, 9) * np.pi / 4, np.arange(-8, 9) * np.pi / 2 + 1e-9])
    s, c = elementary.sincos_array(x)
    ts, tc = np.sin(x), np.cos(x)
    assert np.max(np.abs(s - ts)) < 4.5e-16
    assert np.max(np.abs(c - tc)) < 4.5e-16
    ms, mc = np.abs(ts) > 1e-12, np.abs(tc) > 1e-12
    assert np.max(np.abs(s - ts)[ms] / np.abs(ts[ms])) < 1e-15
    assert np.max(np.abs(c - tc)[mc] / np.abs(tc[mc])) < 1e-15


def test_wrapped_sincos_matches_numpy():
    """The half-angle sincos of the MD step, on its domain [-pi, pi] (angles are wrapped)."""
    x = np.concatenate([np.linspace(-np.pi, np.pi, 400_001), [-np.pi, np.pi, 0.0, 1e-300]])
    s, c = elementary.sincos_wrapped_array(x)
    ts, tc = np.sin(x), np.cos(x)
    assert np.max(np.abs(s - ts)) < 6e-16
    assert np.max(np.abs(c - tc)) < 6e-16
    ms, mc = np.abs(ts) > 1e-3, np.abs(tc) > 1e-3
    assert np.max(np.abs(s - ts)[ms] / np.abs(ts[ms])) < 1e-12
    assert np.max(np.abs(c - tc)[mc] / np.abs(tc[mc])) < 1e-12


def test_action_agm_matches_orbits():
    kappa = np.concatenate(
        [
            np.logspace(-8, -1, 30),
            np.linspace(0.1, 0.99, 200),
            1 - np.logspace(-14, -2, 40),
            1 + np.logspace(-14, -2, 40),
            np.linspace(1.01, 60, 200),
        ]
    )
    for m0 in (0.05, M0, 0.95):
        J, Jb = elementary.actions_from_kappa(kappa, m0)
        Jref = orbits.action(kappa, m0)
        assert np.max(np.abs(J / Jref - 1)) < 1e-13
        np.testing.assert_array_equal(Jb, np.where(kappa < 1, 0.5 * J, J))


def test_actions_of_phase_points(state):
    """J from (theta, p), through kappa^2 = p^2/(4 M0) + sin^2(theta/2), equals orbits.action
    of the orbit through that point, also in a rotated frame."""
    rng = np.random.default_rng(5)
    kappa = np.concatenate([rng.uniform(0.01, 0.99, 500), rng.uniform(1.01, 4.0, 500)])
    w = rng.uniform(0, 2 * np.pi, kappa.size)
    sign = np.where(rng.random(kappa.size) < 0.5, -1.0, 1.0)
    th, p = orbits.phase_point(w, kappa, M0, sign)
    alpha = 2.1
    J, Jb = elementary.actions(sampling.wrap_angle(th + alpha), p, M0, phase=alpha)
    Jref = orbits.action(kappa, M0)
    assert np.max(np.abs(J / Jref - 1)) < 1e-11
    np.testing.assert_allclose(Jb, orbits.rescaled_action(kappa, M0), rtol=1e-11)
    # extreme orbits through theta = 0 (kappa = p / (2 sqrt(M0))): tiny kappa, separatrix, tails
    kx = np.concatenate(
        [
            np.logspace(-8, -1, 30),
            1 - np.logspace(-14, -2, 30),
            1 + np.logspace(-14, -2, 30),
            np.linspace(1.01, 80, 50),
        ]
    )
    p = 2 * np.sqrt(M0) * kx
    J, _ = elementary.actions(np.zeros_like(p), p, M0)
    assert np.max(np.abs(J / orbits.action(p / (2 * np.sqrt(M0)), M0) - 1)) < 1e-13


def test_frame_actions_read_float32_state_in_place_at_an_index():
    """frame_actions on the MD's float32 (sin, cos, p) at an index of tracked particles (read
    in place) equals the same points gathered and widened to float64 first, bit for bit, in
    the index's order; and agrees with orbits.action to the float32 rounding of the points."""
    rng = np.random.default_rng(8)
    n = 5000
    kappa = np.concatenate([rng.uniform(0.01, 0.99, n // 2), rng.uniform(1.01, 3.0, n // 2)])
    th, p = orbits.phase_point(rng.uniform(0, 2 * np.pi, n), kappa, M0, 1.0)
    S, C, P = (np.asarray(a, dtype=np.float32) for a in (np.sin(th), np.cos(th), p))
    idx = rng.permutation(n)[: n // 3]  # unsorted: the output follows the index
    J, Jb = elementary.frame_actions(S, C, P, M0, 0.4, index=idx)
    wide = [a[idx].astype(np.float64) for a in (S, C, P)]
    Jw, Jbw = elementary.frame_actions(*wide, M0, 0.4)
    np.testing.assert_array_equal(J, Jw)
    np.testing.assert_array_equal(Jb, Jbw)
    th32 = np.arctan2(S[idx].astype(float), C[idx].astype(float))
    Jref = elementary.actions(th32, P[idx].astype(float), M0, phase=0.4)[0]
    np.testing.assert_allclose(J, Jref, rtol=1e-12)
    with pytest.raises(IndexError, match="index must lie in"):
        elementary.frame_actions(S, C, P, M0, index=[0, n])


# ------------------------------------------------------------------ integrator
def test_full_dynamics_conserves_energy_and_momentum(state):
    """H/N and sum p of the full HMF dynamics (eq. hmfmdfull); the energy error of the
    2nd-order velocity Verlet scales as dt^2 (measured: 3.5e-5 relative at dt = 0.05, N = 4000,
    T = 100).  The forces sum to zero, so sum p moves by the float32 state's rounding only: each
    kick rounds p (|p| < 4) by up to 2.4e-7, randomly, so <p> walks by about
    1e-7 / sqrt(12 N) a step, 3e-8 over the 4000 steps at dt = 0.025 (measured 2.8e-8); a field
    one step stale, or a kick of the wrong sign in one term, moves it by 1e-3 or more."""
    th, p = thermal_particles(state, 4000, seed=3)
    errs = []
    for dt in (0.05, 0.025):
        P = integrator.Particles(th, p)

        def energy_momentum(P=P):
            m = P.moments()
            return 0.5 * m[3] - 0.5 * (m[0] ** 2 + m[1] ** 2), m[2]

        e0, p0 = energy_momentum()
        err, perr = 0.0, 0.0
        for _ in range(int(round(100 / dt / 40))):
            integrator.leapfrog(P, 40, dt=dt, field=Field.SELF)
            e, pm = energy_momentum()
            err = max(err, abs(e - e0) / abs(e0))
            perr = max(perr, abs(pm - p0))
        errs.append(err)
        assert perr < 2e-7  # forces sum to zero: momentum conserved to round-off
    assert errs[0] < 1e-4
    assert 3.0 < errs[0] / errs[1] < 5.5  # second order


def test_time_reversibility(state):
    """100 steps forward and 100 back return to the start, to the float32 state's rounding
    (6e-8 a step) amplified by the dynamics' chaos: measured 1e-5 (2e-4 after 400 steps each
    way); a closing kick of dt instead of dt/2 leaves 3e-2."""
    th, p = thermal_particles(state, 3000, seed=4)
    P = integrator.Particles(th, p)
    integrator.leapfrog(P, 100, dt=0.05, field=Field.SELF)
    assert np.max(np.abs(P.p - p)) > 1e-2  # it did move
    integrator.leapfrog(P, 100, dt=-0.05, field=Field.SELF)
    assert np.max(np.abs(sampling.wrap_angle(P.theta - th))) < 1e-4
    assert np.max(np.abs(P.p - p)) < 1e-4


def test_static_field_pendulum_keeps_action_and_matches_ode():
    """Bath particles in the static field (theta'' = -M0 sin theta) keep J to O(dt^2), and the
    trajectory converges to an accurate ODE solution at second order (at dt = 0.02 and 0.01;
    below dt ~ 0.005 the float32 state's rounding, ~1e-4 here over 1000-2000 steps, takes
    over from the truncation error)."""
    rng = np.random.default_rng(11)
    kappa = np.concatenate([np.linspace(0.05, 0.95, 40), np.linspace(1.05, 3.0, 40)])
    th0, p0 = orbits.phase_point(
        rng.uniform(0, 2 * np.pi, kappa.size),
        kappa,
        M0,
        np.where(rng.random(kappa.size) < 0.5, -1.0, 1.0),
    )
    J0 = orbits.action(kappa, M0)
    errs = []
    for dt in (0.05, 0.025):
        P = integrator.Particles(th0, p0)
        err = 0.0
        for _ in range(25):
            integrator.leapfrog(P, int(round(4 / dt)), dt=dt, field=Field.STATIC, fx=M0)
            err = max(err, np.max(np.abs(elementary.actions(P.theta, P.p, M0)[0] / J0 - 1)))
        errs.append(err)
    assert errs[0] < 2e-3
    assert 3.0 < errs[0] / errs[1] < 5.5
    # trajectory against scipy's DOP853 over t = 10
    y0 = np.concatenate([th0[::8], p0[::8]])
    n = y0.size // 2
    sol = solve_ivp(
        lambda t, y: np.concatenate([y[n:], -M0 * np.sin(y[:n])]),
        (0, 10),
        y0,
        method="DOP853",
        rtol=1e-12,
        atol=1e-12,
    )
    errs = []
    for dt in (0.02, 0.01):
        P = integrator.Particles(th0[::8], p0[::8])
        integrator.leapfrog(P, int(round(10 / dt)), dt=dt, field=Field.STATIC, fx=M0)
        errs.append(np.max(np.abs(sampling.wrap_angle(P.theta - sol.y[:n, -1]))))
        assert np.max(np.abs(P.p - sol.y[n:, -1])) < 2.0 * errs[-1]
    # measured 1.03e-3 and 2.5e-4 (orbits within 0.05 of the separatrix in kappa)
    assert errs[1] < 4e-4
    assert 3.0 < errs[0] / errs[1] < 5.5


def test_rotation_leaves_frame_actions_unchanged(state):
    """Rotating every particle by one angle changes no action measured in the magnetisation
    frame, at t = 0 and after 200 steps of the full dynamics: to the float32 state's rounding
    of the rotated angles (6e-8; measured 5e-8 in J at t = 0), grown by the chaos of the
    dynamics (measured 3.4e-6 at t = 10); a dynamics that is not invariant under rotation
    gives 1e-2."""
    th, p = thermal_particles(state, 2000, seed=6)
    th = sampling.wrap_angle(th + 0.3)  # magnetisation off the x axis
    alpha = 1.234
    P1, P2 = integrator.Particles(th, p), integrator.Particles(th + alpha, p)
    for k in range(2):
        J = []
        for P in (P1, P2):
            m = P.moments()
            J.append(elementary.actions(P.theta, P.p, M0, np.arctan2(m[1], m[0]))[0])
        assert np.max(np.abs(J[0] - J[1])) < (2e-7 if k == 0 else 3e-5)
        for P in (P1, P2):
            integrator.leapfrog(P, 200, dt=0.05, field=Field.SELF)


# ------------------------------------------------------------------ accumulator
def test_accumulator_deterministic_drift():
    """J_i(s) = a_i + v_i s: the sums are sum over origins and particles of (v_i L)^2, per bin
    of J-bar(t0), computed here by brute force."""
    rng = np.random.default_rng(2)
    n, n_samp, max_lag, oe, nb = 50, 40, 10, 3, 3
    a = rng.uniform(0.5, 2.0, n)  # rotating (J-bar = J)
    v = rng.normal(0, 0.01, n)
    edges = np.array([0.4, 1.0, 1.5, 2.5])
    acc = accumulator.DisplacementAccumulator(n, edges, n_samp, max_lag, oe, nb)
    traj = a[None, :] + v[None, :] * np.arange(n_samp)[:, None]
    for s in range(n_samp):
        acc.add(s, traj[s], traj[s])
    n_orig = (n_samp - 1 - max_lag) // oe + 1
    exp = np.zeros((3, max_lag + 1))
    cnt = np.zeros((3, max_lag + 1))
    for o in range(n_orig):
        t0 = o * oe
        b = np.searchsorted(edges, traj[t0], side="right") - 1
        for L in range(max_lag + 1):
            d = traj[t0 + L] - traj[t0]
            for i in range(n):
                if 0 <= b[i] < 3:
                    exp[b[i], L] += d[i] ** 2
                    cnt[b[i], L] += 1
    np.testing.assert_allclose(acc.acc[0].sum(-1), exp, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(acc.acc[1].sum(-1), exp, rtol=1e-12, atol=1e-18)
    np.testing.assert_array_equal(acc.acc[3].sum(-1), cnt)
    assert acc.acc[3][..., 0].sum() > 0 and np.all(acc.acc[3].sum(axis=(0, 1)) > 0)


def test_accumulator_bins_edges_and_shuffled_particles():
    """Bins as numpy's searchsorted gives them (edges[b] <= J-bar < edges[b + 1], the last edge
    in the last bin, outside or NaN in none), per origin; the sums, counts and particles per
    bin against brute force, for particles in no particular order whose bins change between
    origins; and the sums do not depend on the order the particles are passed in."""
    rng = np.random.default_rng(11)
    n, n_samp, max_lag, oe = 400, 30, 8, 4
    edges = np.array([0.2, 0.5, 0.6, 1.1, 1.7])
    jb = rng.uniform(0.0, 2.0, (n_samp, n))
    jb[:, :40] = rng.choice(np.r_[edges, 0.1, 1.8], (n_samp, 40))  # on the edges and beyond
    jb[:, 40:45] = np.nan
    lib = rng.random(n) < 0.5
    J = np.where(lib, 2.0 * jb, jb)
    perm = rng.permutation(n)
    accs = [accumulator.DisplacementAccumulator(n, edges, n_samp, max_lag, oe, 2) for _ in "ab"]
    for s in range(n_samp):
        accs[0].add(s, J[s], jb[s])
        accs[1].add(s, J[s, perm], jb[s, perm])
    n_orig = (n_samp - 1 - max_lag) // oe + 1
    exp = np.zeros((4, 4, max_lag + 1))
    seen = np.zeros((n, 4), dtype=bool)
    for o in range(n_orig):
        t0 = o * oe
        b = np.searchsorted(edges, jb[t0], side="right") - 1
        b[jb[t0] == edges[-1]] = 3
        for i in np.flatnonzero((b >= 0) & (b < 4)):
            seen[i, b[i]] = True
            d, db = J[t0 : t0 + max_lag + 1, i] - J[t0, i], jb[t0 : t0 + max_lag + 1, i] - jb[t0, i]
            exp[:, b[i]] += [d**2, db**2, d, np.ones_like(d)]
    assert exp[3, :, 0].sum() < n * n_orig  # some particles fell outside the bins
    for acc in accs:
        got = acc.acc.sum(-1)
        np.testing.assert_allclose(got[:3], exp[:3], rtol=1e-12, atol=1e-15)
        np.testing.assert_array_equal(got[3], exp[3])
        np.testing.assert_array_equal(acc.n_particles_in_bin, seen.sum(0))


def test_accumulator_random_walk_librating():
    """Random walk of J-bar with step sigma on librating orbits (J = 2 J-bar): the mean squared
    displacements are sigma^2 L for J-bar and 4 sigma^2 L for J."""
    rng = np.random.default_rng(7)
    n, n_samp, max_lag, oe = 20000, 60, 20, 5
    sigma = 1e-3
    jb = np.cumsum(rng.normal(0, sigma, (n_samp, n)), axis=0) + rng.uniform(0.2, 0.4, n)
    acc = accumulator.DisplacementAccumulator(n, [0.0, 0.3, 1.0], n_samp, max_lag, oe, 4)
    for s in range(n_samp):
        acc.add(s, 2 * jb[s], jb[s])
    msd_bar = acc.acc[1].sum(-1) / acc.acc[3].sum(-1)
    msd = acc.acc[0].sum(-1) / acc.acc[3].sum(-1)
    lags = np.arange(max_lag + 1)
    np.testing.assert_allclose(
        msd_bar[:, 1:], np.broadcast_to(sigma**2 * lags[1:], (2, max_lag)), rtol=0.05
    )
    np.testing.assert_allclose(
        msd[:, 1:], 4 * np.broadcast_to(sigma**2 * lags[1:], (2, max_lag)), rtol=0.05
    )
    assert np.all(msd[:, 0] == 0)
    # every particle is counted once per origin in one bin
    n_orig = (n_samp - 1 - max_lag) // oe + 1
    assert np.all(acc.acc[3].sum(axis=(0, 2)) == n * n_orig)


def test_accumulator_refuses_negative_actions_and_inconsistent_jbar():
    """The accumulator holds each action signed by its librating flag (J-bar = J/2): a negative
    J, or a J-bar that is neither J nor J/2, would be read wrongly, so it stops with the
    sample's index; NaN (a particle lost) stays NaN and falls in no bin."""
    edges = [0.0, 1.0, 2.0]
    J = np.array([0.5, 1.2, 1.6, np.nan])
    negative = np.array([0.5, -1.2, 1.6, np.nan])
    neither = np.array([0.5, 0.84, 1.6, np.nan])  # J-bar 0.7 J
    for Jt, Jbt in ((negative, negative), (J, neither)):
        acc = accumulator.DisplacementAccumulator(4, edges, 12, 6, 3, 2)
        acc.add(0, J, J)
        with pytest.raises(ValueError, match="sample 1: 1 particles with J < 0 or J-bar"):
            acc.add(1, Jt, Jbt)
    acc = accumulator.DisplacementAccumulator(4, edges, 12, 6, 3, 2)
    for s in range(12):
        acc.add(s, J, np.array([0.25, 1.2, 1.6, np.nan]))
    np.testing.assert_array_equal(acc.n_particles_in_bin, [1, 2])


# ------------------------------------------------------------------ driver
# bins of J-bar_0: 6 uniform bins over [0, 1.5] (kappa_max is the orbit with J-bar = 1.5)
RUN = dict(
    dt=0.05,
    t_max=20.0,
    sample_every=0.5,
    max_lag=5.0,
    origin_every=1.0,
    kappa_max=float(orbits.kappa_from_rescaled_action(1.5, M0)),
    n_bins=6,
    n_blocks=4,
)


def run_dataset(state, run, seed, **kw):
    return md_dataset(md.run_md(state, run, seed, progress=None, **kw))


def test_run_md_deterministic_and_thread_independent(state):
    run = MDRun(**RUN, dynamics="full", n_particles=3000, n_test=50, jbar_range=(0.2, 1.4))
    np.testing.assert_allclose(run.jbar_edges(M0), np.linspace(0.0, 1.5, 7), rtol=1e-12)
    a = run_dataset(state, run, 9, threads=2)
    b = run_dataset(state, run, 9, threads=2)
    c = run_dataset(state, run, 9, threads=1)
    for v in ("sum_dJ2", "sum_dJbar2", "count", "Mx", "My", "energy", "sample_p"):
        np.testing.assert_array_equal(a[v].values, b[v].values)
        np.testing.assert_array_equal(a[v].values, c[v].values)
    d = run_dataset(state, run, 9, threads=2, member=1)
    assert not np.array_equal(a["sum_dJ2"].values, d["sum_dJ2"].values)
    # energy per particle conserved and equal to the thermal u up to sampling noise
    e = a["energy"].values
    assert np.max(np.abs(e - e[0])) < 1e-4 * abs(e[0])
    assert abs(e[0] - state.u) < 0.02
    assert np.all(a["count"].values[:, 0] == a["count"].values[:, -1])
    np.testing.assert_allclose(a["sum_dJ2_block"].sum("block"), a["sum_dJ2"])


def test_run_md_full_lags_depend_only_on_the_origins_they_read(state):
    """<dJ^2> at a lag reads the samples of the origins 0 ... t_max - max_lag only: a run cut to
    t_max - (max_lag - L) with max_lag = L gives MD(full) the same sums to the bit at lags <= L
    (what lets thermal_u0.2475 run t_max 700, max_lag 200 for its fit window 50-200)."""
    full = MDRun(**RUN, dynamics="full", n_particles=3000, n_test=50)
    cut = MDRun(**dict(RUN, t_max=17.0, max_lag=2.0), dynamics="full", n_particles=3000, n_test=50)
    assert cut.n_origins == full.n_origins
    a = run_dataset(state, full, 4)
    b = run_dataset(state, cut, 4)
    assert b.sizes["lag"] < a.sizes["lag"]
    short = a.isel(lag=slice(0, b.sizes["lag"]))
    np.testing.assert_array_equal(short["lag"].values, b["lag"].values)
    for v in ("sum_dJbar2", "sum_dJ2", "count", "sum_dJbar2_block"):
        np.testing.assert_array_equal(short[v].values, b[v].values)
    assert np.any(short["sum_dJbar2"].values[:, 1:] > 0)


def test_run_md_bath(state):
    run = MDRun(
        **dict(RUN, t_equilibrate=1.0),
        dynamics="bath",
        n_particles=3000,
        n_test=400,
        test_sampling="f",
    )
    ds = run_dataset(state, run, 1, threads=2)
    e = ds["energy"].values  # bath energy in the static field: conserved
    assert np.max(np.abs(e - e[0])) < 1e-4
    assert ds.attrs["dynamics"] == "bath" and ds.attrs["n_tracked"] == 400
    n_pairs = int(ds["count"].values[:, 0].sum())  # (origin, particle) pairs inside the edges
    assert 0.8 * 400 * ds.attrs["n_origins"] < n_pairs <= 400 * ds.attrs["n_origins"]
    assert np.all(ds["n_particles_in_bin"].values <= 400)
    for v in ds.data_vars:
        assert "units" in ds[v].attrs and "long_name" in ds[v].attrs


@pytest.mark.parametrize(
    "change, word",
    [
        (dict(n_particles=0), "n_particles"),
        (dict(n_particles=10.5), "n_particles"),
        (dict(dt=-0.1), "dt"),
        (dict(max_lag=50.0), "max_lag"),
        (dict(sample_every=0.07), "sample_every"),
        (dict(origin_every=0.75), "origin_every"),
        (dict(dynamics="both"), "dynamics"),
        (dict(n_blocks=100), "n_blocks"),
        (dict(threads=0), "threads"),
        (dict(test_sampling="uniform", n_test=5, jbar_range=(1.0, 0.5)), "jbar_range"),
    ],
)
def test_run_md_validates_inputs(state, change, word):
    kw = dict(RUN, dynamics="full", n_particles=100, n_test=0)
    kw.update(change)
    with pytest.raises(ValueError, match=word):
        md.run_md(state, MDRun(**kw), seed=0, progress=None)


def test_run_md_refuses_more_threads_than_cores(state):
    import numba

    run = MDRun(**RUN, dynamics="full", n_particles=100, n_test=0)
    too_many = numba.config.NUMBA_NUM_THREADS + 1
    with pytest.raises(ValueError, match=rf"threads = {too_many} must be an integer in \[1, "):
        md.run_md(state, run, seed=0, threads=too_many, progress=None)


# ------------------------------------------------------------------ compiled-kernel cache
_JOB = """
import json, sys
from hmfdiff.dynamics.kernel_cache import cache_counts, use_kernel_cache
use_kernel_cache(sys.argv[1])
# start together: announce on stdout, then block on stdin until the test releases both jobs
print("ready", flush=True)
assert sys.stdin.readline().strip() == "go", "the test never released this job"
from hmfdiff.dynamics import md
from hmfdiff.dynamics.settings import MDRun
from hmfdiff.meanfield.equilibrium import ThermalState
run = MDRun(dynamics=sys.argv[2], n_particles=500, n_test=10, dt=0.1, t_max=4.0,
            sample_every=0.5, max_lag=2.0, origin_every=0.5, n_blocks=1)
res = md.run_md(ThermalState(M0=0.7), run, seed=1, progress=None)
print(json.dumps({**cache_counts(), "sum": float(res.sums.sum())}))
"""
#: a safety net for a broken job, not a timing assumption: the waits below are blocking reads
JOB_TIMEOUT = 600


def _two_jobs_together(tmp_path, shared, dynamics):
    """Start two MD jobs, wait (blocking reads of their stdout) until both have set up the
    kernel cache and said 'ready', then release both at once through their stdin."""
    import json
    import select
    import subprocess
    import sys

    script = tmp_path / "job.py"
    script.write_text(_JOB)
    procs = [
        subprocess.Popen(
            [sys.executable, str(script), str(shared), dynamics],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for _ in range(2)
    ]
    try:
        for p in procs:
            ready, _, _ = select.select([p.stdout], [], [], JOB_TIMEOUT)
            line = p.stdout.readline() if ready else ""
            if line.strip() != "ready":
                for q in procs:
                    q.kill()
                pytest.fail(f"a job never said ready ({line!r}): {p.communicate()[1][-3000:]}")
        for p in procs:
            p.stdin.write("go\n")
            p.stdin.flush()
        outs = [p.communicate(timeout=JOB_TIMEOUT) for p in procs]
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
                p.wait()
    for p, (_out, err) in zip(procs, outs, strict=True):
        assert p.returncode == 0, err[-3000:]
    return [json.loads(out.strip().splitlines()[-1]) for out, _ in outs]


@pytest.mark.parametrize("dynamics", ["bath", "full"])
def test_two_md_jobs_started_together_share_the_warmed_kernels(tmp_path, dynamics):
    """The workflow's design: one job warms the shared cache of the kernel version, then MD
    jobs started together each load every kernel from a private copy: both succeed, neither
    compiles, and they compute the same numbers."""
    import subprocess
    import sys

    from hmfdiff.dynamics import kernel_cache

    shared = tmp_path / "kernels" / kernel_cache.kernel_version()
    warm = subprocess.run(
        [
            sys.executable,
            "-c",
            f"from hmfdiff.dynamics import kernel_cache as k; k.warm({str(shared)!r})",
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert warm.returncode == 0, warm.stderr[-3000:]
    assert (shared / "ready.json").is_file()
    assert not list(shared.parent.glob(".*tmp-*"))  # the scratch directory was renamed
    before = sorted(p.relative_to(shared) for p in shared.rglob("*"))
    r1, r2 = _two_jobs_together(tmp_path, shared, dynamics)
    for r in (r1, r2):
        assert r["hits"] >= 3 and r["misses"] == 0, r
    assert r1["sum"] == r2["sum"]
    assert sorted(p.relative_to(shared) for p in shared.rglob("*")) == before  # read only


def test_two_md_jobs_started_together_with_a_cold_cache(tmp_path):
    """Without a warmed cache both jobs compile, each into its own copy: both succeed and the
    shared directory is never written."""
    shared = tmp_path / "kernels" / "missing"
    r1, r2 = _two_jobs_together(tmp_path, shared, "full")
    for r in (r1, r2):
        assert r["hits"] == 0 and r["misses"] >= 3, r
    assert r1["sum"] == r2["sum"]
    assert not shared.exists()
