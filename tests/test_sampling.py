"""Tests of the MD initial conditions (hmfdiff.dynamics.sampling): the kappa marginal of the samples
against f integrated by the independent phase-space quadrature (chi-square, fixed seeds)."""

import numpy as np
import pytest
from scipy import stats

from hmfdiff.dynamics import sampling
from hmfdiff.meanfield import equilibrium, orbits


@pytest.fixture(scope="module")
def thermal():
    return equilibrium.ThermalState(M0=0.72846)


@pytest.fixture(scope="module")
def core_halo():
    return equilibrium.CoreHaloState(0.298, 0.051, -0.517, 0.19, 30, 10)


def kappa_bin_probabilities(state, edges):
    """P(kappa in bin) = int_bin f dtheta dp by the state's phase-space quadrature (which
    counts both directions of rotation)."""
    q = equilibrium.PhaseSpaceQuadrature(state.M0, state.kappa_max, breaks=list(edges[1:-1]))
    idx = np.searchsorted(edges, q.kappa, side="right") - 1
    f = state.f(q.kappa) * q.weights
    return np.array([f[idx == i].sum() for i in range(edges.size - 1)])


def chi2_pvalue(kappa, state, edges):
    prob = kappa_bin_probabilities(state, edges)
    obs = np.histogram(kappa, edges)[0]
    exp = prob * kappa.size
    return stats.chisquare(obs, exp * obs.sum() / exp.sum()).pvalue, prob.sum()


def sample_kappa_of(theta, p, M0):
    return np.sqrt(p**2 / (4 * M0) + np.sin(theta / 2) ** 2)


EDGES = np.array(
    [0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.97, 1.0, 1.03, 1.2, 1.5, 2.0, 10.0]
)


def test_thermal_sampler_kappa_marginal(thermal):
    th, p = sampling.sample_thermal(thermal, 200_000, sampling.make_rng(1))
    pval, total = chi2_pvalue(sample_kappa_of(th, p, thermal.M0), thermal, EDGES)
    assert abs(total - 1) < 1e-8  # f normalised; the bins cover the support
    assert pval > 1e-3
    # magnetisation and kinetic energy of the sample
    assert abs(np.mean(np.cos(th)) - thermal.M0) < 5e-3
    assert abs(np.mean(p**2) - 1 / thermal.beta) < 5e-3


@pytest.mark.parametrize("which", ["thermal", "core_halo"])
def test_kappa_marginal_sampler(which, thermal, core_halo):
    state = thermal if which == "thermal" else core_halo
    th, p = sampling.sample_state(state, 100_000, sampling.make_rng(2), method="kappa")
    kappa = sample_kappa_of(th, p, state.M0)
    pval, _ = chi2_pvalue(kappa, state, EDGES)
    assert pval > 1e-3
    # angles uniform on the orbit: the magnetisation of the sample is the state's M0
    assert abs(np.mean(np.cos(th)) - state.M0) < 6e-3
    # both directions of rotation equally likely
    rot = kappa > 1
    assert abs(np.mean(np.sign(p[rot]))) < 4 / np.sqrt(rot.sum())


def test_cdf_table_normalised(core_halo):
    _, cdf = sampling.jbar_cdf_table(core_halo)
    assert abs(cdf[-1] - 1) < 1e-6


def test_uniform_jbar_test_particles(thermal):
    M0 = thermal.M0
    th, p = sampling.sample_uniform_jbar(M0, 20_000, (0.1, 1.6), sampling.make_rng(3))
    kappa, w, sign = orbits.angle_action(th, p, M0)
    jbar = orbits.rescaled_action(kappa, M0)
    assert stats.kstest((jbar - 0.1) / 1.5, "uniform").pvalue > 1e-3
    assert stats.kstest(w / (2 * np.pi), "uniform").pvalue > 1e-3


def test_rescaled_action_inverse(thermal):
    M0 = thermal.M0
    k = np.concatenate([np.linspace(0.01, 0.99, 50), np.linspace(1.01, 4, 50)])
    np.testing.assert_allclose(
        orbits.kappa_from_rescaled_action(orbits.rescaled_action(k, M0), M0), k, rtol=1e-10
    )


def test_rotation_to_x_axis_and_seeds(thermal):
    a = sampling.sample_state(thermal, 1000, sampling.make_rng(4, 0))
    b = sampling.sample_state(thermal, 1000, sampling.make_rng(4, 0))
    c = sampling.sample_state(thermal, 1000, sampling.make_rng(4, 1))
    np.testing.assert_array_equal(a[0], b[0])
    assert not np.array_equal(a[0], c[0])
    th, extra, phase = sampling.rotate_to_x_axis(a[0] + 0.5, np.zeros(3))
    mx, my = sampling.magnetisation(th)
    assert abs(my) < 1e-14 and mx > 0
    np.testing.assert_allclose(extra, sampling.wrap_angle(-phase * np.ones(3)))
