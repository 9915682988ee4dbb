"""The measured magnetisation spectrum of MD against theory (hmfdiff.analysis.md_spectrum):
the Welch window's kernel, the expectation of the Welch estimate of a process of known
spectrum, and the slowly rotating frame of MD(full)."""

import numpy as np
import pytest

from hmfdiff.analysis import md_spectrum
from hmfdiff.analysis.fluctuations import welch_spectrum


def ar1(n_real, n_t, a, sigma, rng):
    """Realisations of x_{j+1} = a x_j + sigma xi_j, started in its stationary law."""
    x = np.empty((n_real, n_t))
    x[:, 0] = rng.normal(0, sigma / np.sqrt(1 - a * a), n_real)
    xi = rng.normal(0, sigma, (n_real, n_t))
    for j in range(1, n_t):
        x[:, j] = a * x[:, j - 1] + xi[:, j]
    return x


def ar1_spectrum(omega, a, sigma, dt):
    """Two-sided spectrum of the AR(1) process sampled every dt (int S domega/2pi = var)."""
    return dt * sigma**2 / np.abs(1 - a * np.exp(-1j * np.asarray(omega) * dt)) ** 2


def test_window_kernel_is_normalised():
    seg, dt = 64, 0.25
    nu = np.linspace(-np.pi / dt, np.pi / dt, 200001)
    K = md_spectrum.window_kernel(nu, seg, dt)
    assert np.trapezoid(K, nu) / (2 * np.pi) == pytest.approx(1.0, rel=1e-6)
    flat = md_spectrum.smoothed(lambda w: np.full(np.shape(w), 3.0), [0.0, 1.0, 5.0], seg, dt)
    np.testing.assert_allclose(flat, 3.0, rtol=2e-3)  # the kernel's far tails are cut


def test_smoothed_theory_is_the_expectation_of_the_welch_estimate():
    """A sharply peaked AR(1) spectrum (a = 0.97): the Welch mean over many realisations
    matches the theory convolved with the window within its errors, and not the bare theory
    near the peak (so the convolution is what makes the comparison like for like)."""
    dt, seg, a, sigma = 0.25, 64, 0.97, 1.0
    x = ar1(400, 1024, a, sigma, np.random.default_rng(3))
    omega, S, err, _ = welch_spectrum(x, dt, seg)
    sm = md_spectrum.smoothed(lambda w: ar1_spectrum(w, a, sigma, dt), omega, seg, dt)
    raw = ar1_spectrum(omega, a, sigma, dt)
    k = slice(2, None)  # bins 0, 1 carry the subtraction of each segment's mean
    z = (S[k] - sm[k]) / err[k]
    assert np.mean(np.abs(z) < 2) > 0.9 and np.max(np.abs(z)) < 4.5
    assert abs(S[2] / raw[2] - 1) > 10 * err[2] / S[2]  # the peak is visibly smoothed


def test_slowly_rotating_frame_separates_the_components():
    """M = (M0 + a(t) + i b(t)) e^{i phi(t)} with phi drifting by 3 rad over the run: in the
    frame of the running mean direction the transverse spectrum is that of b (well above the
    resolution); in the fixed frame it would be swamped by a and by the drift."""
    rng = np.random.default_rng(8)
    dt, seg, n_t = 0.25, 64, 4096
    a_ = 0.03 * ar1(1, n_t, 0.9, 1.0, rng)[0]
    b_ = 0.005 * ar1(1, n_t, 0.5, 1.0, rng)[0]
    phi = 3.0 * np.linspace(0, 1, n_t) ** 2
    m = (0.7 + a_ + 1j * b_) * np.exp(1j * phi)
    par, perp = md_spectrum._slow_frame(m.real, m.imag, seg)
    om, S_b, err_b, _ = welch_spectrum(b_, dt, seg)
    _, S_perp, _, _ = welch_spectrum(perp, dt, seg)
    _, S_fixed, _, _ = welch_spectrum(m.imag, dt, seg)
    k = om > 4 * 2 * np.pi / (seg * dt)
    assert np.median(np.abs(S_perp[k] / S_b[k] - 1)) < 0.05
    assert np.median(np.abs(S_fixed[k] / S_b[k] - 1)) > 0.2
    _, S_a, _, _ = welch_spectrum(a_, dt, seg)
    _, S_par, _, _ = welch_spectrum(par, dt, seg)
    assert np.median(np.abs(S_par[k] / S_a[k] - 1)) < 0.05


# ------------------------------------------------------------------ windowed theory
def fake_fit(M0, lag, window, edges, dynamics="bath"):
    """The fields of a fit dataset that `windowed_at_bins` reads."""
    import xarray as xr

    ds = xr.Dataset(
        {"M0": ((), M0)},
        coords={"lag": ("lag", lag), "jbar_edges": ("edge", edges)},
    )
    ds.attrs.update(
        dynamics=dynamics,
        fit_window=list(window),
        N=1000.0,
        n_test=500,
        test_sampling="uniform",
        jbar_range=[0.0, float(edges[-1])],
        n_tracked_from_f=0,
    )
    return ds


def test_windowed_prediction_per_bin_tends_to_the_asymptotic_one():
    """Bins of librating orbits: fitted over an early window the finite-time prediction differs
    from the asymptotic D by several per cent; over a late window it agrees to ~1 %."""
    from hmfdiff.analysis.windowed import windowed_at_bins
    from hmfdiff.meanfield.equilibrium import ThermalState

    state = ThermalState(M0=0.72846)
    edges = np.array([0.1, 0.2, 0.3, 0.4])
    lag = np.arange(0.0, 3001.0, 5.0)
    dev = {}
    for name, window in (("early", (5.0, 40.0)), ("late", (1500.0, 3000.0))):
        fit = fake_fit(state.M0, lag, window, edges)
        nd_w, nd_s = windowed_at_bins(fit, state, n_max=4, l_max=4, n_sub=3)
        assert np.all(np.isfinite(nd_w)) and np.all(nd_s > 0)
        dev[name] = np.abs(nd_w / nd_s - 1)
    assert np.all(dev["late"] < 0.015), dev
    assert np.max(dev["early"]) > 0.05, dev


def test_windowed_columns_of_the_validation_rows():
    import xarray as xr

    from hmfdiff.analysis.windowed import add_windowed

    rows = [
        dict(case="c", dynamics="bath", ND_md=1.1, ND_md_err=0.05, flag=0),
        dict(case="c", dynamics="bath", ND_md=2.0, ND_md_err=0.5, flag=0),
        dict(case="c", dynamics="bath", ND_md=2.0, ND_md_err=0.5, flag=1),
    ]
    win = xr.Dataset({"ND_windowed": ("bin", [1.0, 2.5, 3.0]), "ND_spectrum": ("bin", [1, 2, 3])})
    add_windowed(rows, win)
    assert rows[0]["ratio_windowed"] == pytest.approx(1.1)
    assert rows[0]["z_windowed"] == pytest.approx(2.0)
    assert rows[1]["z_windowed"] == pytest.approx(-1.0)


def test_agreement_counts_only_frequencies_with_spectral_power():
    """Bins where the theory is below 1e-3 of its in-band maximum (the numerical floor of the
    bath synthesis) are left out of the summary; the others are counted exactly."""
    omega = np.linspace(0.0, 5.0, 501)
    theory = np.where(omega < 2.0, 1.0, 1e-6)
    err = np.full_like(omega, 0.1)
    measured = theory.copy()
    measured[(omega > 1.0) & (omega < 2.0)] += 0.3  # 3 sigma high on 99 of the 195 bins kept
    measured[omega >= 2.0] = 1e-12  # ratio 1e-6 and |z| ~ 0 at the floor: must not count
    stats = md_spectrum.agreement(omega, measured, err, theory)
    kept = (omega > 0.05) & (omega < 2.0)
    assert stats["n_compared"] == kept.sum()
    high = kept & (omega > 1.0)
    assert stats["frac_z_lt_2"] == pytest.approx(1.0 - high.sum() / kept.sum())
    assert stats["median_ratio"] == pytest.approx(1.3 if high.sum() > kept.sum() / 2 else 1.0)
