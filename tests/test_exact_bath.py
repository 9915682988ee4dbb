"""The exact-orbit bath of MD(bath) (hmfdiff.dynamics.exact_bath): truncated Fourier series
against the elliptic-function orbits, the synthesised magnetisation against the integrated bath
from identical initial conditions, the directly integrated fallback, and N*D of MD(bath) with
both baths; the random tracked subset of MD(full); the synthesis accumulated over many chunks
of the non-uniform FFT (lowered chunk size, and a production-size bath at the default one)
against the bath integrated by scipy's DOP853."""

import dataclasses

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from hmfdiff.analysis.fits import diffusion_fit
from hmfdiff.dynamics import exact_bath, integrator, md, sampling
from hmfdiff.dynamics.integrator import Field
from hmfdiff.dynamics.settings import MDRun
from hmfdiff.meanfield import equilibrium, orbits
from hmfdiff.meanfield.fourier import cos_coefficient
from hmfdiff.pipeline.layouts.md import md_dataset

M0 = 0.72846


@pytest.fixture(scope="module")
def state():
    return equilibrium.ThermalState(M0=M0)


def bath_particles(state, n, seed):
    th, p = sampling.sample_thermal(state, n, sampling.make_rng(seed))
    th, _ = sampling.rotate_to_x_axis(th)
    return th, p


def integrated_magnetisation(th, p, dt, n_steps):
    """(Mx, My) at every step of a bath integrated by velocity Verlet in the static field."""
    P = integrator.Particles(th, p)
    h = integrator.leapfrog(P, n_steps, dt, field=Field.STATIC, fx=M0)
    return np.vstack([[np.mean(np.cos(th)), np.mean(np.sin(th))], h]), P


def pendulum_magnetisation(th, p, times):
    """(Mx, My) at `times` of particles moving in the static field -M0 sin theta, integrated by
    scipy's adaptive DOP853 (rtol = atol = 1e-12): independent of the orbits' Fourier series,
    of the non-uniform FFT and of this package's integrators."""
    n = th.size

    def rhs(_, y):
        return np.concatenate([y[n:], -M0 * np.sin(y[:n])])

    y0 = np.concatenate([th, p])
    sol = solve_ivp(rhs, (0.0, times[-1]), y0, "DOP853", times, rtol=1e-12, atol=1e-12)
    assert sol.success
    return np.stack([np.cos(sol.y[:n]).mean(0), np.sin(sol.y[:n]).mean(0)], axis=1)


@pytest.mark.parametrize("tol", [1e-6, 1e-10])
def test_truncated_series_meets_the_tolerance_on_exact_orbits(tol):
    """cos theta and sin theta from the N_i harmonics kept for each orbit against theta(w) of
    the Jacobi elliptic functions (orbits.phase_point), which the series never uses: the error
    is below the tolerance and not far below it (the bound is not wildly loose)."""
    # (closer to the separatrix than 1e-5, scipy's elliptic functions lose ~1e-10 themselves)
    kappa = np.concatenate(
        [[1e-3, 0.2, 0.6, 0.9, 0.99, 0.9999, 1 - 1e-5], [1 + 1e-5, 1.0001, 1.01, 1.3, 2.5]]
    )
    w = np.linspace(0, 2 * np.pi, 257)[:-1]
    n_keep = exact_bath.harmonics_needed(kappa, tol)
    assert np.all(n_keep <= exact_bath.MAX_HARMONICS)
    assert np.all(np.diff(n_keep[:7]) > 0)  # more harmonics towards the separatrix
    worst = 0.0
    for k, nk in zip(kappa, n_keep, strict=True):
        for sign in (1.0, -1.0):
            th, _ = orbits.phase_point(w, k, M0, sign)
            c, s = exact_bath.harmonic_amplitudes(k, int(nk), sign)
            n = np.arange(1, nk + 1)[:, None]
            cos_ser = cos_coefficient(0, k) + 2 * (c[0][:, None] * np.cos(n * w)).sum(0)
            sin_ser = 2 * (s[0][:, None] * np.sin(n * w)).sum(0)
            err = max(np.max(np.abs(cos_ser - np.cos(th))), np.max(np.abs(sin_ser - np.sin(th))))
            assert err <= tol, (k, sign, nk, err)
            worst = max(worst, err)
    assert worst > 1e-3 * tol


def test_synthesised_magnetisation_matches_the_integrated_bath(state):
    """From identical initial conditions, Mx, My of the exact bath and of the bath integrated
    with dt and dt/2 differ by the integrator's error: small and second order in dt."""
    th, p = bath_particles(state, 3000, seed=1)
    T = 20.0
    errs = []
    for dt in (0.02, 0.01):
        n = int(round(T / dt))
        eb = exact_bath.ExactBath(th, p, M0, dt=dt, n_steps=n, tolerance=1e-11)
        mi, P = integrated_magnetisation(th, p, dt, n)
        assert eb.n_direct == 0
        assert np.max(np.abs(eb.history[0] - mi[0])) < 5e-11  # truncation + FFT, ~ tolerance each
        errs.append(np.max(np.abs(eb.history - mi)))
        # mean momentum from d<p>/dt = -M0 My, against the integrated particles: within the
        # time integral of the field's error
        assert abs(eb.momentum[-1] - np.mean(P.p)) < 0.1 * M0 * T * errs[-1]
        assert eb.energy == pytest.approx(np.mean(0.5 * p**2 - M0 * np.cos(th)), rel=1e-14)
    assert errs[1] < 1e-5
    assert 3.5 < errs[0] / errs[1] < 4.5  # the integrator's O(dt^2), nothing else


def test_orbits_beyond_the_harmonic_cap_are_integrated_directly(state):
    """With a cap of 6 harmonics the outer orbits go to the direct integrator; the total is
    still the bath's magnetisation."""
    th, p = bath_particles(state, 2000, seed=2)
    dt, n = 0.01, 1000
    full = exact_bath.ExactBath(th, p, M0, dt=dt, n_steps=n, tolerance=1e-10)
    capped = exact_bath.ExactBath(th, p, M0, dt=dt, n_steps=n, tolerance=1e-10, max_harmonics=6)
    assert capped.n_direct > 100 and capped.max_harmonics_used <= 6
    mi, _ = integrated_magnetisation(th, p, dt, n)
    err_full = np.max(np.abs(full.history - mi))
    err_capped = np.max(np.abs(capped.history - mi))
    assert err_capped < err_full  # the directly integrated part follows the integrator exactly
    assert np.max(np.abs(capped.history - full.history)) < 2 * err_full


def test_synthesis_over_many_chunks_matches_the_integrated_orbits(state):
    """A bath of 2000 orbits (25 000 harmonics) synthesised in chunks of 3001 harmonics, i.e.
    nine calls of the transform, the last one short, over 400 time steps, against the same
    particles integrated by DOP853: every chunk's orbits, at every time, are in the sum.
    Measured: max error 7e-11 at tolerance 1e-10 (DOP853's own error is below 1e-11); the
    bound 3 tolerance leaves room for the transform's rms error ~ tolerance over 800 values.
    Seen failing: only the first chunk kept (error 1e-2), one orbit skipped at each chunk
    boundary (1e-3), later chunks one time step late (8e-4)."""
    th, p = bath_particles(state, 2000, seed=11)
    dt, n, tol, chunk = 0.05, 400, 1e-10, 3001
    eb = exact_bath.ExactBath(th, p, M0, dt=dt, n_steps=n, tolerance=tol, chunk_points=chunk)
    assert eb.n_direct == 0 and eb.n_points > 8 * chunk and eb.n_points % chunk != 0
    ref = pendulum_magnetisation(th, p, dt * np.arange(n + 1))
    assert np.max(np.abs(eb.history - ref)) < 3 * tol


def test_production_size_bath_spans_several_default_chunks(state):
    """A production-size bath (50 000 orbits at the production tolerance 1e-9: 580 000
    harmonics, more than the default chunk of 500 000) over 100 steps, against DOP853.
    Measured: max error 7e-10 (the transform's rms error is set to ~ tolerance); bound 3e-9.
    Seen failing: second chunk dropped (error 1e-3), the last orbit of the last chunk dropped
    (1e-5), the second chunk one time step late (5e-5)."""
    th, p = bath_particles(state, 50_000, seed=12)
    dt, n, tol = 0.05, 100, 1e-9
    eb = exact_bath.ExactBath(th, p, M0, dt=dt, n_steps=n, tolerance=tol)
    assert eb.n_direct == 0 and eb.n_points > exact_bath._CHUNK_POINTS
    ref = pendulum_magnetisation(th, p, dt * np.arange(n + 1))
    assert np.max(np.abs(eb.history - ref)) < 3 * tol


def md_run(**kw):
    base = dict(
        dt=0.05,
        t_max=60.0,
        sample_every=0.5,
        max_lag=30.0,
        origin_every=2.0,
        kappa_max=float(orbits.kappa_from_rescaled_action(1.5, M0)),
        n_bins=6,
        n_blocks=4,
        fit_window=(10.0, 30.0),
    )
    base.update(kw)
    return MDRun(**base)


def test_md_bath_exact_and_integrated_give_the_same_ND(state):
    """MD(bath) with the exact and the integrated bath (dt = 0.025) from the same seed, i.e.
    identical initial conditions: fitted N*D agree within 1 % in the bins away from the
    separatrix, and far inside the statistical error (10-40 % here) in the others, where
    tracers are chaotic and the integrator's phase error decorrelates them; the exact bath
    integrates no bath particle."""
    nd, err = {}, {}
    for bath in ("exact", "integrated"):
        run = md_run(dynamics="bath", n_particles=20000, n_test=3000, bath=bath, dt=0.025)
        ds = md_dataset(md.run_md(state, run, 3, threads=1, progress=None))
        fit = diffusion_fit([ds], run.fit_window, min_particles=50, separatrix_band=0.05)
        ok = fit["flag"].values == 0
        far = np.abs(fit["kappa0"].values[ok] - 1.0) > 0.1
        nd[bath], err[bath] = fit["ND_md"].values[ok], fit["ND_md_err"].values[ok]
        if bath == "exact":
            assert ds.attrs["bath_n_direct"] == 0 and ds.attrs["bath_harmonics_total"] > 20000
            assert ds.attrs["wall_bath_synthesis_s"] > 0
            mx_exact = ds["Mx"].values
        else:
            # the same bath up to the integrator's error (a few % of the fluctuations)
            assert np.max(np.abs(ds["Mx"].values - mx_exact)) < 0.1 * np.std(mx_exact)
    assert far.sum() >= 3
    np.testing.assert_allclose(nd["exact"][far], nd["integrated"][far], rtol=0.01)
    assert np.all(np.abs(nd["exact"] - nd["integrated"]) < 0.1 * err["exact"])


def test_md_full_tracks_a_random_subset(state):
    """MD(full) with n_track < N: the dynamics is untouched (same magnetisation), and the
    tracked particles' actions are those of the same particles in a run tracking all N."""
    n = 600
    common = dict(dynamics="full", n_particles=n, n_test=40, t_max=20.0, max_lag=10.0)
    all_run = md_run(**common, n_store=n + 40, fit_window=None)
    sub_run = dataclasses.replace(all_run, n_track=150)
    a = md_dataset(md.run_md(state, all_run, 4, progress=None))
    b = md_dataset(md.run_md(state, sub_run, 4, progress=None))
    np.testing.assert_array_equal(a["Mx"].values, b["Mx"].values)
    assert b.attrs["n_tracked"] == 190 and b.attrs["n_tracked_from_f"] == 150
    # which of the N particles each tracked column is: the one of `a` with the same actions
    Ja, Jb = a["sample_J"].values, b["sample_J"].values
    track = np.array([np.flatnonzero((Ja[:, :n] == Jb[:, [j]]).all(0))[0] for j in range(150)])
    assert np.unique(track).size == 150 and np.all(np.diff(track) > 0)
    # a random draw, not the first 150: spread over the N (a uniform draw of 150 of 600 has
    # ~1e-7 chance of missing the top fifth)
    assert track.max() >= 0.8 * n and track.min() < 0.2 * n
    np.testing.assert_array_equal(Jb[:, 150:], Ja[:, n:])  # then the test particles
    assert b["count"].values[:, 0].sum() < 0.4 * a["count"].values[:, 0].sum()


def test_magnetisation_stored_every_m_every(state):
    run = md_run(dynamics="bath", n_particles=2000, n_test=50, m_every=0.1, t_equilibrate=1.0)
    ds = md_dataset(md.run_md(state, run, 5, progress=None))
    assert ds.sizes["time_fine"] == 601
    np.testing.assert_array_equal(ds["Mx_fine"].values[::5], ds["Mx"].values)
    assert ds["time_fine"].values[-1] == pytest.approx(run.t_max)
    for v in ("Mx_fine", "My_fine"):
        assert ds[v].attrs["units"] == "1" and "long_name" in ds[v].attrs
