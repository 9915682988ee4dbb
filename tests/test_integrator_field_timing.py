"""Guards for hmfdiff.dynamics.integrator: the timing of the field felt by test
particles in `advance_system`."""

import numpy as np

from hmfdiff.dynamics.integrator import Particles, advance_system


def test_a_test_particle_on_a_bath_particle_follows_it_exactly():
    """Guards against test particles feeling the magnetisation one step late (or early): a test
    particle started on the phase point of one of the interacting particles of MD(full) feels,
    at every kick, the same field as that particle, so the two trajectories coincide to
    rounding (the known answer); a field shifted by one step separates them at O(dt^2) per
    step."""
    rng = np.random.default_rng(3)
    th = rng.uniform(-np.pi, np.pi, 5)
    p = rng.normal(0.0, 0.6, 5)
    bath = Particles(th, p)
    test = Particles(th[:2], p[:2])
    M = bath.moments()[:2]
    for _ in range(4):  # several calls: the field at the start of each call matters too
        M = advance_system(bath, test, dynamics="full", M=M, n_steps=50, dt=0.05, M0=0.5)
    assert np.max(np.abs(bath.theta - th)) > 0.5  # the particles have moved
    np.testing.assert_allclose(test.theta, bath.theta[:2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(test.p, bath.p[:2], rtol=0, atol=1e-12)
