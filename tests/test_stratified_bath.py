"""studies/stratified_bath.py: its stratified draw puts exactly one of the bath's N orbits in
each of N equal-probability strata of f's J-bar distribution, and leaves the test particles'
draw (the second call of a run) to the pipeline's sampler."""

from pathlib import Path

import numpy as np
from _studies import load_study

from hmfdiff.dynamics import sampling
from hmfdiff.meanfield import orbits
from hmfdiff.meanfield.equilibrium import make_state

ROOT = Path(__file__).resolve().parents[1]


def test_one_orbit_per_stratum_and_test_particles_untouched():
    state = make_state({"kind": "thermal", "M0": 0.6})
    n = 4000
    table = sampling.jbar_cdf_table(state)
    calls = []

    def original(state, n, rng, method="auto", table=None):
        calls.append(n)
        return np.zeros(n), np.zeros(n)

    sample = load_study("stratified_bath").stratified_state_sampler(original)
    theta, p = sample(state, n, np.random.default_rng(3), table=table)
    kappa, _, _ = orbits.angle_action(theta, p, state.M0)
    jbar = orbits.rescaled_action(kappa, state.M0)
    u = np.interp(jbar, *table) / table[1][-1]  # the CDF of each orbit's action
    counts = np.bincount(np.minimum((u * n).astype(int), n - 1), minlength=n)
    # one per stratum up to the inversion's rounding at the strata's edges
    assert np.mean(counts == 1) > 0.99, np.bincount(counts)
    assert calls == []
    sample(state, 7, np.random.default_rng(4))
    assert calls == [7]
