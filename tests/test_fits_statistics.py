"""Guards for hmfdiff.analysis.fits: the error bar of N*D_MD (standard error of the
mean, ddof 1), the fit window's inclusive ends, the tracked density of MD(bath), and the
log-linear interpolation of the theory.  Every reference is a synthetic input whose answer is
known in closed form (exact straight lines, exact exponentials, a uniform density), not the
code's own formulae."""

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import quad

from hmfdiff.analysis.fits import diffusion_fit, fit_slope, theory_at_bins, tracked_density
from hmfdiff.meanfield import orbits

M0 = 0.6
N = 1000.0
LAG = np.arange(0.0, 41.0)


def _line_dataset(slopes, seed, block_slopes=None):
    """An md-like dataset whose <dJbar^2>(lag) is the exact line slopes[b] * lag + 0.3 in each
    bin b (counts 100 per lag), and, per block k, block_slopes[k][b] * lag + 0.3."""
    js = orbits.action_separatrix(M0, +1)
    edges = np.array([0.2, 0.4, js + 0.2, js + 0.4])
    nb = edges.size - 1
    slopes = np.asarray(slopes, dtype=float)
    count = np.full((nb, LAG.size), 100)
    msd = slopes[:, None] * LAG[None, :] + 0.3
    if block_slopes is None:
        block_slopes = [slopes, slopes]
    blk = np.stack([np.asarray(b)[:, None] * LAG[None, :] + 0.3 for b in block_slopes], axis=-1)
    cb = np.full(blk.shape, 100)
    ds = xr.Dataset(
        {
            "sum_dJbar2": (("bin", "lag"), msd * count),
            "count": (("bin", "lag"), count),
            "sum_dJbar2_block": (("bin", "lag", "block"), blk * cb),
            "count_block": (("bin", "lag", "block"), cb),
            "n_particles_in_bin": ("bin", np.full(nb, 1000)),
            "jbar_edges": ("edge", edges),
            "jbar0": ("bin", 0.5 * (edges[1:] + edges[:-1])),
        },
        coords={"lag": ("lag", LAG)},
    )
    ds.attrs.update(N=N, M0_actions=M0, dynamics="bath", seed=seed)
    return ds


def _jacobian(ds):
    """(dJ/dJ-bar)^2 per bin: 4 below the separatrix (J = 2 J-bar), 1 above."""
    return np.where(ds["jbar0"].values < orbits.action_separatrix(M0, +1), 4.0, 1.0)


def test_error_of_the_seed_mean_is_the_standard_error_with_ddof_1():
    """Guards against std instead of std/sqrt(n) and against sqrt(n) vs sqrt(n - 1) (ddof 0):
    five seeds whose <dJbar^2> are exact lines of known slopes a_k, so that the per-seed N*D is
    exactly N a_k/2 (times 4 on librating bins) and the error must be the sample standard
    deviation (ddof 1) of those known values over sqrt(5), computed here by hand."""
    rng = np.random.default_rng(5)
    a = rng.uniform(0.5, 1.5, size=(5, 3)) * 1e-3  # (seed, bin)
    seeds = [_line_dataset(a[k], k) for k in range(5)]
    fit = diffusion_fit(seeds, window=(10.0, 40.0), min_particles=10)
    per_seed = 0.5 * N * a * _jacobian(seeds[0])[None, :]
    mean = per_seed.sum(0) / 5
    sem = np.sqrt(((per_seed - mean) ** 2).sum(0) / 4) / np.sqrt(5)
    np.testing.assert_allclose(fit["ND_md_seed"].values, per_seed, rtol=1e-9)
    np.testing.assert_allclose(fit["ND_md"].values, mean, rtol=1e-9)
    np.testing.assert_allclose(fit["ND_md_err"].values, sem, rtol=1e-9)


def test_single_seed_error_from_blocks_is_the_standard_error_of_the_block_slopes():
    """Guards against a lost 1/2 (or N, or jacobian) in the per-block slopes of a single seed
    and against a wrong standard error over blocks: four blocks with exact lines of known
    slopes; the error must be std(ddof 1)/sqrt(4) of N b_k/2 (times 4 on librating bins)."""
    b = np.array([[1.0, 2.0, 3.0], [1.2, 2.1, 2.5], [0.9, 1.7, 3.3], [1.1, 2.4, 2.9]]) * 1e-3
    ds = _line_dataset(b.mean(0), 0, block_slopes=list(b))
    fit = diffusion_fit([ds], window=(10.0, 40.0), min_particles=10)
    per_block = 0.5 * N * b * _jacobian(ds)[None, :]
    mean = per_block.mean(0)
    sem = np.sqrt(((per_block - mean) ** 2).sum(0) / 3) / 2.0
    np.testing.assert_allclose(fit["ND_md"].values, mean, rtol=1e-9)
    np.testing.assert_allclose(fit["ND_md_err"].values, sem, rtol=1e-9)


@pytest.mark.parametrize("window, slope", [((5.0, 15.0), 20.0), ((4.0, 16.0), 20.0)])
def test_fit_window_includes_both_ends(window, slope):
    """Guards against an off-by-one in the fit window (a half-open [t_min, t_max)): the least-
    squares slope of y = x^2 over integer lags symmetric about their mean m is exactly 2 m, so
    over [5, 15] (both ends included) it is 20; dropping the last lag gives 19, the first 21."""
    lag = np.arange(0.0, 21.0)
    got, icpt = fit_slope(lag, lag**2, window)
    assert got == pytest.approx(slope, rel=1e-12)
    # the intercept of the same exact fit: mean(y) - slope * mean(x)
    x = np.arange(window[0], window[1] + 1)
    assert icpt == pytest.approx(np.mean(x**2) - slope * np.mean(x), rel=1e-12)


def test_md_bath_tracks_only_its_test_particles():
    """Guards against MD(bath) weighting its bins with the bath's density 4 pi N f (the bath
    particles are not tracked in MD(bath)): the tracked density of MD(bath) with 50 test
    particles uniform on J-bar in [0, 2] is the constant 25 per unit J-bar there, 0 beyond, and
    integrates to 50 (scipy quad)."""
    from hmfdiff.meanfield.equilibrium import ThermalState

    st = ThermalState(u=-0.2)
    fit = xr.Dataset({"M0": ((), st.M0)})
    fit.attrs.update(
        N=1000.0, n_test=50, dynamics="bath", test_sampling="uniform", jbar_range=[0.0, 2.0]
    )
    j = np.array([0.1, 0.5, 1.3, 1.9, 2.5, 4.0])
    np.testing.assert_allclose(tracked_density(j, fit, st.f), [25, 25, 25, 25, 0, 0], atol=1e-12)
    js = orbits.action_separatrix(st.M0, +1)
    rho = lambda x: float(tracked_density(np.array([x]), fit, st.f)[0])  # noqa: E731
    total = quad(rho, 0, js, limit=200)[0] + quad(rho, js, 6.0, limit=200, points=[2.0])[0]
    assert total == pytest.approx(50.0, rel=1e-6)


def test_theory_is_interpolated_log_linearly_within_each_family():
    """Guards against linear (instead of log-linear) interpolation of N D and against mixing
    the two orbit families: N D = exp(3 kappa) (librating) and 10 exp(-kappa) (rotating) on a
    coarse grid is reproduced exactly between the nodes (log-linear interpolation of an
    exponential is exact; linear interpolation is off by up to 8 % here), and kappa0 between
    the last librating and first rotating node is NaN."""
    k = np.concatenate([np.linspace(0.1, 0.9, 5), np.linspace(1.1, 2.9, 7)])
    D = np.where(k < 1, np.exp(3 * k), 10 * np.exp(-k))
    theory = xr.Dataset({"D_landau": ("kappa", D)}, coords={"kappa": k})
    kappa0 = np.array([0.25, 0.47, 0.83, 1.2, 2.0, 2.77, 0.95, 1.05])
    got = theory_at_bins(theory, kappa0, "bath")
    expected = np.where(kappa0 < 1, np.exp(3 * kappa0), 10 * np.exp(-kappa0))
    np.testing.assert_allclose(got[:6], expected[:6], rtol=1e-12)
    assert np.all(np.isnan(got[6:]))


def test_validation_row_ratio_and_z_score():
    """Guards against an inverted ratio (theory/MD) or a z-score with the wrong sign or scale
    in results/validation.csv: a fit of three bins with N D_MD = 3, 1.5, 2.2 and errors 0.5,
    0.25, NaN against a constant theory N D = 2 (the centre of every bin) gives ratio = N D_MD/2
    = 1.5, 0.75, 1.1 and z = (N D_MD - 2)/error = 2, -2, NaN, the last row flagged 5 (no
    error)."""
    from hmfdiff.analysis.fits import validation_rows

    edges = np.array([0.1, 0.2, 0.3, 0.4])
    jb0 = 0.5 * (edges[1:] + edges[:-1])
    kappa0 = orbits.kappa_from_rescaled_action(jb0, M0)
    fit = xr.Dataset(
        {
            "ND_md": ("bin", [3.0, 1.5, 2.2]),
            "ND_md_err": ("bin", [0.5, 0.25, np.nan]),
            "flag": ("bin", np.zeros(3, dtype=np.int8)),
            "kappa0": ("bin", kappa0),
            "J0": ("bin", orbits.action(kappa0, M0)),
            "n_particles_in_bin": ("bin", [500, 500, 500]),
            "M0": ((), M0),
        },
        coords={"jbar_edges": ("edge", edges)},
    )
    fit.attrs.update(dynamics="bath", n_seeds=4, min_particles=10, separatrix_band=0.02)
    k = np.linspace(0.01, 0.99, 50)
    theory = xr.Dataset(
        {
            "D_landau": ("kappa", np.full(k.size, 2.0)),
            "D_lenard_balescu": ("kappa", np.ones(k.size)),
        },
        coords={"kappa": k},
    )
    rows = validation_rows("c", fit, theory)
    np.testing.assert_allclose([r["ND_theory"] for r in rows], 2.0, rtol=1e-12)
    np.testing.assert_allclose([r["ratio"] for r in rows], [1.5, 0.75, 1.1], rtol=1e-12)
    np.testing.assert_allclose([r["z"] for r in rows[:2]], [2.0, -2.0], rtol=1e-12)
    assert np.isnan(rows[2]["z"])
    assert [r["flag"] for r in rows] == [0, 0, 5]
