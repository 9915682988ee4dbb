"""Tests of the ensemble engine (hmfdiff.dynamics.ensemble): R independent HMF systems in one
kernel, against the single-system kernel, conservation laws, thread independence, and a thermal
state that must stay thermal."""

import numpy as np
import pytest
from scipy import stats

from hmfdiff.dynamics import ensemble, integrator, sampling
from hmfdiff.meanfield.equilibrium import ThermalState


@pytest.mark.parametrize(
    "M0, dt, n_steps",
    [
        (0.7, 0.05, 100),
        # hot (T ~ 0.5) at a long step: the chunks on the long polynomial path (drift angles up to
        # ~0.4), which the first case never takes
        (0.2, 0.15, 300),
    ],
)
def test_one_realisation_follows_the_single_system_kernel(M0, dt, n_steps):
    """Same initial conditions (the same p, sin and cos of the angles and magnetisation): the
    ensemble kernel and the single-system one (`Particles.open_steps`, `close_steps`) do the
    same arithmetic in the same order (chunks of 4096: N = 5000 spans two chunks), so p, sin
    and cos agree to the bit, and so does the magnetisation of the last step; that one is summed
    in float32 within each chunk, so it differs from a float64 sum of the final state by the
    chunk sums' rounding and the closing kick's division by the norm (measured 2e-7 at most;
    the norm is within 2e-6 of 1 between the kernel's periodic divisions)."""
    state = ThermalState(M0=M0)
    ens = ensemble._initial_ensemble(state, 5000, 3, seed=11)
    single = integrator.Particles(ens.theta[1].copy(), ens.p[1].copy())
    single.S, single.C = ens.S[1].copy(), ens.C[1].copy()
    out = single.open_steps(n_steps, dt=dt, field="self", fx=ens.M[1, 0], fy=ens.M[1, 1])
    single.close_steps(dt=dt, fx=out[-1, 0], fy=out[-1, 1])
    ens.advance(n_steps, dt)
    np.testing.assert_array_equal(ens.p[1], single.p)
    np.testing.assert_array_equal(ens.S[1], single.S)
    np.testing.assert_array_equal(ens.C[1], single.C)
    np.testing.assert_array_equal(ens.M[1], out[-1, :2])
    m = single.moments()
    assert ens.M[1] == pytest.approx(m[:2], abs=1e-6)


def _energy_error(dt, t_end=100.0):
    state = ThermalState(M0=0.6)
    ens = ensemble._initial_ensemble(state, 1000, 4, seed=3)
    e0, p0 = ens.energy(), ens.moments()[:, 2]
    kinetic = 0.5 * ens.moments()[:, 3]  # the scale of the energy (u itself is near 0 here)
    err = 0.0
    for _ in range(10):
        ens.advance(int(round(t_end / 10 / dt)), dt)
        err = max(err, float(np.max(np.abs(ens.energy() - e0) / kinetic)))
    return err, float(np.max(np.abs(ens.moments()[:, 2] - p0)))


def test_energy_and_momentum_are_conserved_at_the_configured_dt():
    """Velocity Verlet: bounded energy error of order dt^2; the total momentum is conserved
    exactly in exact arithmetic (the mean-field forces cancel pairwise), here to the float32
    state's rounding: each kick rounds p by ~1e-7 / sqrt(12), so <p> of N = 1000 walks by about
    1.1e-9 a step, 5e-8 over 2000 steps (measured 6e-8)."""
    err, dp = _energy_error(0.05)
    assert err < 2e-4
    assert dp < 4e-7
    err_half, _ = _energy_error(0.025)
    assert 2.5 < err / err_half < 6.0  # second order


def test_output_does_not_depend_on_the_thread_count():
    state = ThermalState(M0=0.5)
    kw = dict(
        n_particles=600,
        n_realisations=5,
        dt=0.1,
        times=ensemble.measurement_times(20.0, 6, 0.1),
        jbar_edges=np.linspace(0.0, 1.5, 16),
        seed=5,
        progress=lambda msg: None,
    )
    a = ensemble.run_ensemble(state, threads=1, **kw)
    b = ensemble.run_ensemble(state, threads=2, **kw)
    keys = ["M_abs", "M_phase", "energy", "momentum"]
    keys += [f"{h}{m}" for h in ("hist", "overflow") for m in ensemble.ACTION_MEASURES]
    for key in keys:
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)


def test_the_three_action_measures():
    """J-bar measured with <|M|>, with each realisation's |M| and with a static M0: one
    realisation's own |M| is the ensemble mean (same histograms to the count); a static M0
    equal to the state's is the mean field's at t = 0 up to the sample's O(1/sqrt N) |M|, and
    a static M0 far off (0.4 for a state of M0 0.6) moves several times more (0.04-0.08 of
    the particles, against < 0.01)."""
    state = ThermalState(M0=0.6)
    kw = dict(
        n_particles=2000,
        dt=0.1,
        times=np.array([0.0, 5.0, 20.0]),
        jbar_edges=np.linspace(0.0, 1.5, 16),
        seed=3,
        progress=lambda msg: None,
    )
    one = ensemble.run_ensemble(state, n_realisations=1, **kw)
    np.testing.assert_array_equal(one["hist_own"], one["hist"])
    np.testing.assert_array_equal(one["overflow_own"], one["overflow"])
    many = ensemble.run_ensemble(state, n_realisations=4, **kw)
    assert np.any(many["hist_own"] != many["hist"])  # each realisation its own |M|
    # static M0 = the state's: the histograms differ from the mean field's by the few particles
    # that the difference |M| - M0 ~ 1/sqrt(N) carries across a bin edge
    moved = np.abs(many["hist_static"] - many["hist"]).sum(axis=-1) / kw["n_particles"]
    assert np.all(moved < 0.015), moved
    off = ensemble.run_ensemble(state, n_realisations=4, M0_static=0.4, **kw)
    moved_off = np.abs(off["hist_static"] - off["hist"]).sum(axis=-1) / kw["n_particles"]
    assert np.all(moved_off > 0.03), moved_off


def test_measurement_times_are_whole_steps_dense_early():
    t = ensemble.measurement_times(1000.0, 30, 0.05)
    assert t[0] == 0.0 and t[-1] == pytest.approx(1000.0)
    steps = t / 0.05
    np.testing.assert_allclose(steps, np.rint(steps), atol=1e-9)
    assert np.all(np.diff(t) > 0)
    assert np.diff(t)[0] < np.diff(t)[-1] / 100  # dense early, sparse late
    # 0, then 29 times from 10 dt = 0.5 to 1000 in the ratio (2000)^(1/28) = 1.31 (no two of
    # them round to the same step): all 30 kept, the second at t_first
    assert t.size == 30 and t[1] == pytest.approx(0.5)
    assert t[2] == pytest.approx(0.05 * np.rint(0.5 * 2000 ** (1 / 28) / 0.05))


def test_thermal_state_stays_thermal():
    """A thermal state is stationary: after t = 200 (50 orbital periods at the centre) the pooled
    J-bar histogram of 20 x 1000 particles agrees with f_thermal by a chi-square test."""
    state = ThermalState(M0=0.6)
    M0 = state.M0
    edges = np.concatenate(
        [np.linspace(0.0, 0.95, 12) * sampling.jbar_separatrix(M0), [1.2, 1.5, 2.0]]
    )
    out = ensemble.run_ensemble(
        state,
        n_particles=1000,
        n_realisations=20,
        dt=0.05,
        times=np.array([0.0, 200.0]),
        jbar_edges=edges,
        seed=2,
        progress=lambda msg: None,
    )
    jg, cdf = sampling.jbar_cdf_table(state)
    prob = np.diff(np.interp(edges, jg, cdf / cdf[-1]))
    for k in (0, 1):
        counts = out["hist"][k].sum(axis=0)
        total = counts.sum() + out["overflow"][k].sum()
        expected = total * prob
        chi2 = np.sum((counts - expected) ** 2 / expected)
        pval = stats.chi2.sf(chi2, df=counts.size - 1)
        assert pval > 1e-3, (k, chi2, counts, expected)
    assert abs(np.mean(out["M_abs"][-1]) - M0) < 0.02


def test_bad_input_is_refused():
    state = ThermalState(M0=0.5)
    with pytest.raises(ValueError, match="n_particles"):
        ensemble.run_ensemble(
            state,
            n_particles=1,
            n_realisations=2,
            dt=0.1,
            times=[0.0, 1.0],
            jbar_edges=[0.0, 1.0],
            seed=0,
        )
    with pytest.raises(ValueError, match="multiples of dt"):
        ensemble.run_ensemble(
            state,
            n_particles=10,
            n_realisations=2,
            dt=0.1,
            times=[0.0, 0.15],
            jbar_edges=[0.0, 1.0],
            seed=0,
        )


def test_each_realisation_starts_at_rest_with_its_magnetisation_on_x():
    """Each realisation's mean momentum is removed and its angles are rotated so that its own
    magnetisation lies on x (an ensemble whose centres of mass drift would carry the sampling
    noise of <p>, ~ 1/sqrt(N), into every action); the draws stay those of the state."""
    state = ThermalState(M0=0.6)
    ens = ensemble._initial_ensemble(state, 400, 5, seed=3)
    # to the float32 state's rounding of each p and angle (half an ulp: 2^-24 relative)
    half_ulp = 2.0**-24
    np.testing.assert_allclose(ens.p.mean(axis=1), 0.0, atol=half_ulp * np.abs(ens.p).max())
    np.testing.assert_allclose(np.sin(ens.theta).mean(axis=1), 0.0, atol=half_ulp)
    assert np.all(np.cos(ens.theta).mean(axis=1) > 0.4)
    assert np.all(ens.p.std(axis=1) > 0.5)  # momenta drawn, not zeroed
