"""The diffusion fit recovers a known diffusion coefficient from synthetic random walks."""

import numpy as np
import pytest
import xarray as xr

from hmfdiff.analysis.fits import FitError, diffusion_fit, fit_slope, kappa_of_jbar
from hmfdiff.meanfield import orbits

M0 = 0.6


def synthetic_md(
    D_jbar,
    seed,
    n_part=400,
    n_samples=161,
    dt_sample=1.0,
    max_lag=60,
    origin_every=5,
    N=1000,
    n_blocks=4,
):
    """An MD-like dataset: particles in each J-bar_0 bin random-walk in J-bar with diffusion
    coefficient D_jbar[bin]/N; <dJbar^2> accumulated over time origins as the MD does."""
    rng = np.random.default_rng(seed)
    js = orbits.action_separatrix(M0, +1)
    edges = np.array([0.2, 0.4, 0.6, js + 0.2, js + 0.4])
    nb = edges.size - 1
    n_lag = int(max_lag / dt_sample) + 1
    s = np.zeros((nb, n_lag, n_blocks))
    c = np.zeros((nb, n_lag, n_blocks), dtype=np.int64)
    origins = np.arange(0, n_samples - n_lag + 1, int(origin_every / dt_sample))
    for b in range(nb):
        steps = rng.normal(0.0, np.sqrt(2 * D_jbar[b] / N * dt_sample), (n_part, n_samples - 1))
        traj = np.concatenate([np.zeros((n_part, 1)), np.cumsum(steps, axis=1)], axis=1)
        for k, t0 in enumerate(origins):
            d2 = ((traj[:, t0 : t0 + n_lag] - traj[:, t0 : t0 + 1]) ** 2).sum(0)
            blk = k * n_blocks // len(origins)
            s[b, :, blk] += d2
            c[b, :, blk] += n_part
    lag = np.arange(n_lag) * dt_sample
    ds = xr.Dataset(
        {
            "sum_dJbar2": (("bin", "lag"), s.sum(-1)),
            "count": (("bin", "lag"), c.sum(-1)),
            "sum_dJbar2_block": (("bin", "lag", "block"), s),
            "count_block": (("bin", "lag", "block"), c),
            "n_particles_in_bin": ("bin", np.full(nb, n_part)),
            "jbar_edges": ("edge", edges),
            "jbar0": ("bin", 0.5 * (edges[1:] + edges[:-1])),
        },
        coords={"lag": ("lag", lag)},
    )
    ds.attrs.update(N=N, M0_actions=M0, dynamics="bath", seed=seed)
    return ds


D_TRUE = np.array([0.5, 1.0, 2.0, 3.0])  # N D in J-bar units, per bin


def test_fit_slope_exact_line():
    lag = np.arange(20.0)
    slope, icpt = fit_slope(lag, 3.0 * lag + 2.0, (5, 15))
    assert slope == pytest.approx(3.0) and icpt == pytest.approx(2.0)


def test_recovers_known_D_and_converts_to_J():
    seeds = [synthetic_md(D_TRUE, s) for s in range(6)]
    fit = diffusion_fit(seeds, window=(10, 60), min_particles=10)
    jbar0 = fit["jbar0"].values
    lib = jbar0 < orbits.action_separatrix(M0, +1)
    expected = D_TRUE * np.where(lib, 4.0, 1.0)  # J = 2 J-bar below the separatrix
    nd, err = fit["ND_md"].values, fit["ND_md_err"].values
    assert np.all(np.isfinite(err)) and np.all(err > 0)
    z = (nd - expected) / err
    assert np.all(np.abs(z) < 4), (nd, expected, err)
    assert np.all(np.abs(nd / expected - 1) < 0.15)
    # the error is an honest scale: the relative errors are a few per cent, not zero
    assert np.all(err / nd > 0.005)


def test_single_seed_uses_blocks():
    fit = diffusion_fit([synthetic_md(D_TRUE, 11)], window=(10, 60), min_particles=10)
    assert "blocks of time origins" in fit.attrs["error_method"]
    assert np.all(np.isfinite(fit["ND_md_err"].values))


def test_flags_and_bad_window():
    ds = synthetic_md(D_TRUE, 3)
    fit = diffusion_fit([ds], window=(10, 60), min_particles=10_000)
    assert np.all(fit["flag"].values == 1)  # too few particles, flagged not dropped
    assert np.all(np.isfinite(fit["ND_md"].values))
    with pytest.raises(FitError, match="outside the measured lags"):
        diffusion_fit([ds], window=(10, 600))


def test_kappa_of_jbar_round_trip():
    k = np.array([0.2, 0.7, 0.99, 1.01, 1.5])
    np.testing.assert_allclose(kappa_of_jbar(orbits.rescaled_action(k, M0), M0), k, rtol=1e-9)


def test_tracked_density_counts_every_particle():
    """4 pi N f(kappa(J-bar)) per unit J-bar integrates to N over both orbit families, and the
    uniform test particles add n_test: the weights of the theory's bin average are normalised."""
    from scipy.integrate import quad

    from hmfdiff.analysis.fits import theory_bin_average, tracked_density
    from hmfdiff.meanfield.equilibrium import ThermalState

    st = ThermalState(u=-0.2)
    fit = xr.Dataset({"M0": ((), st.M0)})
    fit.attrs.update(
        N=1000.0, n_test=50, dynamics="full", test_sampling="uniform", jbar_range=[0.0, 2.0]
    )
    js = orbits.action_separatrix(st.M0, +1)
    rho = lambda j: float(tracked_density(np.array([j]), fit, st.f)[0])  # noqa: E731
    total = quad(rho, 0, js, limit=200)[0] + quad(rho, js, 12.0, limit=200)[0]
    assert total == pytest.approx(1000.0 + 50.0, rel=1e-6)
    # a constant D averages to itself; the separatrix band makes a bin NaN
    k = np.linspace(0.01, 3.0, 400)
    D = np.where(np.abs(k - 1) < 0.01, np.nan, 2.5)
    theory = xr.Dataset({"D_lenard_balescu": ("kappa", D)}, coords={"kappa": k})
    fit["jbar_edges"] = ("edge", np.array([0.2, 0.5, js - 0.001, js + 0.2, js + 0.5]))
    avg = theory_bin_average(theory, fit, st.f)
    np.testing.assert_allclose(avg[[0, 3]], 2.5, rtol=1e-12)
    assert np.isnan(avg[1]) and np.isnan(avg[2])  # these bins reach into the separatrix band
