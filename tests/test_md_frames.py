"""The frame in which the MD measures actions, and the field that drives the tracers of the
exact bath (hmfdiff.dynamics.md).

MD(full) measures every action in the frame of the instantaneous magnetisation (angles rotated
by arg(Mx + i My)); MD(bath) with the exact bath drives its tracers by the synthesised M(t)
of the bath step by step.  Both are checked against references the test computes itself: the
magnetisation of the stored angles, the pendulum action of the stored phase points, and the
same tracers driven by a bath integrated at a small time step."""

import numpy as np
import pytest

from hmfdiff.dynamics import md
from hmfdiff.dynamics.settings import MDRun
from hmfdiff.meanfield import equilibrium, orbits

M0 = 0.72846


@pytest.fixture(scope="module")
def state():
    return equilibrium.ThermalState(M0=M0)


def small_run(**kw):
    base = dict(
        dt=0.05,
        t_max=20.0,
        sample_every=0.5,
        max_lag=10.0,
        origin_every=2.0,
        kappa_max=2.0,
        n_bins=4,
        n_blocks=2,
        fit_window=None,
    )
    base.update(kw)
    return MDRun(**base)


def test_md_full_measures_actions_in_the_frame_of_the_magnetisation(state):
    """All N particles of MD(full) stored, mean momentum kept (the magnetisation turns, by
    about half a radian here): at every sample the stored angles have mean sin 0 and mean cos
    |M| of the stored series (the frame of M), and each stored J is the pendulum action of its
    stored (theta, p) at M0 (scipy's elliptic integrals, kappa^2 = p^2/(4 M0) + sin^2(theta/2)).
    Guards against the frame's angle taken as atan2(Mx, My) or of the start, which leaves J
    consistent with the stored angles but not with M."""
    n = 600
    run = small_run(dynamics="full", n_particles=n, n_test=0, n_store=n, zero_momentum=False)
    res = md.run_md(state, run, 7, threads=1, progress=None)
    th, p, J = res.sample_theta, res.sample_p, res.sample_J
    assert th.shape == (res.series["Mx"].size, n)
    phase = np.unwrap(np.arctan2(res.series["My"], res.series["Mx"]))
    assert np.ptp(phase) > 0.2  # the magnetisation turned: the frame matters
    mod = np.hypot(res.series["Mx"], res.series["My"])
    # to the float32 state's rounding of the angles (half an ulp of 1: 6e-8)
    np.testing.assert_allclose(np.sin(th).mean(axis=1), 0.0, atol=2.0**-24)
    np.testing.assert_allclose(np.cos(th).mean(axis=1), mod, rtol=2.0**-23)
    kappa = np.sqrt(p**2 / (4.0 * M0) + np.sin(0.5 * th) ** 2)
    np.testing.assert_allclose(J, orbits.action(kappa, M0), rtol=1e-9)


def test_exact_bath_tracers_feel_the_bath_of_their_own_time_step(state):
    """The same bath and tracers (same seed) with the exact bath and with the bath integrated at
    dt = 0.01: the tracers' stored phase points agree to the integrator's error (measured max
    |dtheta| 6.9e-5, |dp| 3.4e-5 over t = 20; bound 1e-3), while tracers driven by the exact
    bath's field one step late drift apart (measured 0.061 and 0.027): the field of N = 300
    particles fluctuates by |delta M| ~ 0.06."""
    out = {}
    for bath in ("exact", "integrated"):
        run = small_run(dynamics="bath", n_particles=300, n_test=20, n_store=20, dt=0.01, bath=bath)
        res = md.run_md(state, run, 5, threads=1, progress=None)
        out[bath] = res
    a, b = out["exact"], out["integrated"]
    np.testing.assert_allclose(a.series["Mx"], b.series["Mx"], atol=1e-4)
    assert np.ptp(a.series["My"]) > 0.05  # a fluctuating field drives the tracers
    dth = np.angle(np.exp(1j * (a.sample_theta - b.sample_theta)))
    assert np.max(np.abs(dth)) < 1e-3, np.max(np.abs(dth))
    assert np.max(np.abs(a.sample_p - b.sample_p)) < 1e-3
