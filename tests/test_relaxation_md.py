"""Tests of the N-body relaxation analysis (analysis.relaxation_md, analysis.relaxation_compare):
histogram densities and entropies against the states they sample, the binning of a kinetic f,
relaxation times and power laws on synthetic data of known answer, and the whole comparison on
synthetic ensembles drawn from a known evolution f(J-bar, t/N)."""

import numpy as np
import pytest
import xarray as xr

from hmfdiff.analysis import relaxation_md as rm
from hmfdiff.analysis.relaxation_compare import compare_relaxation
from hmfdiff.dynamics import sampling
from hmfdiff.meanfield import orbits
from hmfdiff.meanfield.equilibrium import CoreHaloState, ThermalState

HOT = dict(eta1=0.3, eta2=0.01, mu1=-0.5, mu2=1.2, beta1=40.0, beta2=2.0)


def test_histogram_of_a_sample_estimates_the_state():
    """J-bar of particles sampled from a thermal state, binned: fractions agree with the exact
    CDF (chi-square), and the histogram entropy with the coarse-grained entropy of the state."""
    st = ThermalState(M0=0.7)
    rng = np.random.default_rng(3)
    th, p = sampling.sample_state(st, 200000, rng)
    kappa = np.sqrt(p**2 / (4 * st.M0) + np.sin(0.5 * th) ** 2)
    jbar = orbits.rescaled_action(kappa, st.M0)
    edges = np.linspace(0.0, 2.5, 26)
    hist = np.histogram(jbar, edges)[0]
    over = int(np.sum(jbar >= edges[-1]))
    P = rm.bin_fractions(hist, over)
    Q = rm.state_bin_fractions(st, edges)
    chi2 = np.sum((P - Q) ** 2 * hist.sum() / Q)
    assert chi2 < 60  # 25 bins: chi2 ~ 25 +- 7
    S_hist = rm.entropy_from_histogram(hist, edges, over)
    S_state = -np.sum(Q * np.log(Q / (4 * np.pi * np.diff(edges))))
    assert S_hist == pytest.approx(S_state, abs=3e-3)


def test_kinetic_bin_fractions_integrate_the_density():
    """f = exp(-J-bar)/(4 pi) on nodes: the mass in [a, b] is exp(-a) - exp(-b)."""
    j = np.linspace(0.0, 3.0, 301)
    w = np.full(j.size, j[1] - j[0])
    w[0] = w[-1] = 0.5 * (j[1] - j[0])
    f = np.exp(-j) / (4 * np.pi)
    edges = np.array([0.0, 0.5, 1.0, 2.0, 3.0])
    P = rm.kinetic_bin_fractions(j, w, np.stack([f, 2 * f]), edges)
    exact = np.exp(-edges[:-1]) - np.exp(-edges[1:])
    np.testing.assert_allclose(P[0], exact, rtol=2e-4)
    np.testing.assert_allclose(P[1], 2 * exact, rtol=2e-4)


def test_relaxation_time_and_power_law_on_known_data():
    t = np.linspace(0.0, 50.0, 501)
    assert rm.relaxation_time(t, 3.0 * np.exp(-t / 7.0)) == pytest.approx(7.0, rel=1e-3)
    assert rm.relaxation_time(t, 1.0 + 2.0 * np.exp(-t / 7.0), floor=1.0) == pytest.approx(
        7.0, rel=1e-3
    )
    assert np.isnan(rm.relaxation_time(t, np.ones_like(t)))
    n = np.array([500.0, 1000.0, 2000.0, 4000.0])
    alpha, err, amp = rm.power_law_fit(n, 3.0 * n**1.3, 0.01 * 3.0 * n**1.3)
    assert alpha == pytest.approx(1.3, abs=1e-9) and amp == pytest.approx(3.0, rel=1e-9)
    assert 0 < err < 0.05


def _synthetic_evolution(state, thermal, tau0, jbar_max):
    """A kinetic-like dataset: f(tau) = (1 - a) f_state + a f_thermal, a = 1 - exp(-tau/tau0)."""
    j = np.linspace(0.0, jbar_max, 2001)
    w = np.full(j.size, j[1] - j[0])
    w[0] = w[-1] = 0.5 * (j[1] - j[0])

    def dens(st):
        g, c = sampling.jbar_cdf_table(st)
        return np.gradient(np.interp(j, g, c / c[-1]), j) / (4 * np.pi)

    f0, f1 = dens(state), dens(thermal)
    tau = np.concatenate([[0.0], np.geomspace(1e-3, 20 * tau0, 200)])
    a = 1.0 - np.exp(-tau / tau0)
    f = (1 - a)[:, None] * f0 + a[:, None] * f1
    M0 = (1 - a) * state.M0 + a * thermal.M0
    return xr.Dataset(
        {
            "f": (("tau", "Jbar"), f),
            "cell_width": (("Jbar",), w),
            "M0": (("tau",), M0),
        },
        coords={"tau": tau, "Jbar": j},
        attrs={"case": "hot", "equation": "lenard_balescu"},
    ), (tau, f, w, j)


def _synthetic_ensemble(kin, n, R, edges, times_tau, rng):
    """Histograms drawn from the synthetic f at t/N, R realisations of n particles."""
    tau, f, w, j = kin
    P = rm.kinetic_bin_fractions(j, w, f, edges)
    P_t = rm.interpolate_in_time(tau, P, times_tau)
    over = np.clip(1.0 - P_t.sum(axis=-1), 0.0, 1.0)
    probs = np.concatenate([P_t, over[:, None]], axis=-1)
    probs /= probs.sum(axis=-1, keepdims=True)
    counts = np.stack([rng.multinomial(n, probs[k], size=R) for k in range(times_tau.size)])
    t = times_tau * n
    return xr.Dataset(
        {
            "hist": (("t", "realisation", "jbar"), counts[..., :-1]),
            "overflow": (("t", "realisation"), counts[..., -1]),
            "M_abs": (("t", "realisation"), np.full((t.size, R), 0.7)),
            "jbar_edges": (("jbar_edge",), edges),
        },
        coords={"t": t},
        attrs={"case": "hot", "n_particles": n},
    )


def test_comparison_recovers_a_known_relaxation():
    """Ensembles drawn from f(J-bar, t/N) itself: the distance to it stays at the noise floor,
    the MD relaxation time is the kinetic one times N, and the exponent is 1."""
    state = CoreHaloState(**HOT)
    thermal = ThermalState(M0=0.7018283971660635)
    tau0 = 5.0
    edges = np.linspace(0.0, float(orbits.rescaled_action(3.0, state.M0)), 31)
    kin_ds, kin = _synthetic_evolution(state, thermal, tau0, 1.2 * edges[-1])
    rng = np.random.default_rng(11)
    times_tau = np.concatenate([[0.0], np.geomspace(0.01, 40.0, 40)])
    md = [_synthetic_ensemble(kin, n, 20, edges, times_tau, rng) for n in (500, 1000, 2000)]
    ds, rows, summary = compare_relaxation(md, {"lenard_balescu": kin_ds}, state, thermal)
    tau_kin = summary["tau_relax_coarse"]["lenard_balescu"]
    assert np.isfinite(tau_kin)
    for n, t_r in summary["t_relax_md"].items():
        err = summary["t_relax_md_err"][n]
        assert abs(t_r / n - tau_kin) < max(4 * err / n, 0.05 * tau_kin)
    assert summary["exponent"] == pytest.approx(1.0, abs=max(4 * summary["exponent_err"], 0.05))
    # drawn from the evolution itself: the distance is the sampling noise at every time
    ratio = ds["l1_distance_lenard_balescu"].values / ds["l1_distance_noise_floor"].values
    assert np.mean(ratio) < 1.3 and np.max(ratio) < 3.0
    assert len(rows) == 3 * times_tau.size


def _snapshot_dataset():
    """A comparison dataset made up here: 10 J-bar bins of width 0.3, largest N = 200 at five
    times; the MD occupies bins 0-5 at every time, bin 6 only at the first time, bins 7-9
    never, and bin 3 is empty at the last time; the thermal and kinetic fractions have tails
    down to 1e-12 in the empty bins (what drew the old axis down to 1e-10)."""
    edges = np.linspace(0.0, 3.0, 11)
    tau = np.array([0.0, 0.1, 0.2, 0.4, 0.8])
    P = np.zeros((2, tau.size, 10))
    P[:, :, :6] = [0.3, 0.25, 0.2, 0.12, 0.08, 0.05]
    P[:, 0, 6] = 0.02
    P[:, -1, 3] = 0.0
    tail = [0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 1e-8, 1e-10, 1e-12]
    return xr.Dataset(
        {
            "P_md": (("N", "tau", "jbar"), P),
            "P_md_err": (("N", "tau", "jbar"), 0.1 * P),
            "P_thermal": (("jbar",), np.array(tail)),
            "P_lenard_balescu": (("tau", "jbar"), np.tile(tail, (tau.size, 1))),
        },
        coords={
            "N": [100, 200],
            "tau": tau,
            "jbar": 0.5 * (edges[1:] + edges[:-1]),
            "jbar_edges": (("jbar_edge",), edges),
        },
    )


def test_fig12_snapshot_panel_draws_only_the_md_data():
    """Figure 12(d): the J-bar axis ends at the last edge of a bin the MD occupies (2.1, not
    3.0), the log axis's floor is set by the smallest MD density drawn (not by the 1e-12 tails
    of the theory), no point or error bar is drawn in an empty bin, and the three snapshots
    differ in marker and in lightness (luminance steps > 0.2 of a sequential colormap)."""
    from hmfdiff.analysis.figures.relaxation_md_figures import _snapshot_panel
    from hmfdiff.analysis.figures.style import plt

    ds = _snapshot_dataset()
    fig, ax = plt.subplots()
    try:
        _snapshot_panel(ax, ds)
        vol = 4 * np.pi * 0.3
        assert ax.get_xlim() == pytest.approx((0.0, 2.1))
        P = ds["P_md"].values[-1]
        lowest = P[P > 0].min() / vol
        lo, hi = ax.get_ylim()
        assert 0.1 * lowest < lo < lowest
        assert hi > 0.3 / vol
        snaps = [0, 2, 4]  # first, middle, last time
        bars = [c for c in ax.containers if type(c).__name__ == "ErrorbarContainer"]
        assert len(bars) == 3
        markers, lum = [], []
        for bar, j in zip(bars, snaps, strict=True):
            line = bar.lines[0]
            x, y = line.get_xdata(), line.get_ydata()
            occupied = ds["jbar"].values[P[j] > 0]
            np.testing.assert_allclose(x, occupied)
            np.testing.assert_allclose(y, P[j][P[j] > 0] / vol)
            markers.append(line.get_marker())
            r, g, b = plt.matplotlib.colors.to_rgb(line.get_color())
            lum.append(0.2126 * r + 0.7152 * g + 0.0722 * b)
        assert len(set(markers)) == 3
        assert np.min(np.abs(np.diff(np.sort(lum)))) > 0.2
    finally:
        plt.close(fig)


def test_fig13_draws_the_coarse_grained_kinetic_times(monkeypatch):
    """Figure 13 reads `tau_relax_coarse_{eq}` (a made-up 40 and 120 here): each kinetic line
    is t_R/N = tau_R^coarse, independent of N, and its legend names tau_R^coarse with its
    value; the MD points are t_relax_md / N with their jackknife errors / N.  (A figure still
    looking for another name draws no kinetic line at all: that is what this catches.)"""
    from hmfdiff.analysis.figures import relaxation_md_figures as rmf

    drawn = []
    monkeypatch.setattr(rmf, "save_figure", lambda fig, *a, **k: drawn.append(fig))
    ds = xr.Dataset(
        {
            "t_relax_md": (("N",), [3.6e4, 1.68e5]),
            "t_relax_md_err": (("N",), [4.5e3, 1.2e4]),
            "tau_relax_coarse_landau": ((), 40.0),
            "tau_relax_coarse_lenard_balescu": ((), 120.0),
        },
        coords={"N": [1000, 4000]},
        attrs={"case": "hot", "exponent": 1.1, "exponent_err": 0.1, "prefactor": 16.0},
    )
    rmf.fig13_relaxation_time({"relaxation_comparison": [ds]}, None, None)
    ax = drawn[0].axes[0]
    try:
        labels = {line.get_label(): line for line in ax.get_lines()}
        for name, tau in (("Landau", 40.0), ("Lenard-Balescu", 120.0)):
            (lab,) = [k for k in labels if k.startswith(name + ":")]
            assert r"\tau_R^{\rm coarse}" in lab and f"={tau:g}" in lab
            np.testing.assert_allclose(labels[lab].get_ydata(), tau)
        (pts,) = [c for c in ax.containers if type(c).__name__ == "ErrorbarContainer"]
        np.testing.assert_allclose(pts.lines[0].get_ydata(), [36.0, 42.0])
        (bars,) = pts.lines[2]
        np.testing.assert_allclose(  # the error bars: t_R/N -+ err/N
            [seg[:, 1] for seg in bars.get_segments()], [[31.5, 40.5], [39.0, 45.0]]
        )
    finally:
        rmf.plt.close(drawn[0])


def test_fig13_draws_the_bands_and_the_reference_points(monkeypatch):
    """The kinetic times' uncertainty (`tau_relax_coarse_{eq}_band`) is shaded over exactly its
    range, and the N-body times of runs not rebuilt (`t_relax_md_reference`) are drawn at
    t_R/N beside the run's own; a band of NaN draws nothing."""
    from hmfdiff.analysis.figures import relaxation_md_figures as rmf

    drawn = []
    monkeypatch.setattr(rmf, "save_figure", lambda fig, *a, **k: drawn.append(fig))
    ds = xr.Dataset(
        {
            "t_relax_md": (("N",), [3.6e4, 1.68e5]),
            "t_relax_md_err": (("N",), [4.5e3, 1.2e4]),
            "tau_relax_coarse_landau": ((), 40.0),
            "tau_relax_coarse_landau_band": (("bound",), [38.0, 43.0]),
            "tau_relax_coarse_lenard_balescu": ((), 120.0),
            "tau_relax_coarse_lenard_balescu_band": (("bound",), [np.nan, np.nan]),
            "t_relax_md_reference": (("N_reference",), [4.4e5, 1.1e6]),
            "t_relax_md_reference_err": (("N_reference",), [2e4, 5e4]),
        },
        coords={"N": [1000, 4000], "N_reference": [8000, 16000]},
        attrs={"case": "hot", "exponent": 1.1, "exponent_err": 0.1, "prefactor": 16.0},
    )
    rmf.fig13_relaxation_time({"relaxation_comparison": [ds]}, None, None)
    ax = drawn[0].axes[0]
    try:
        spans = [p for p in ax.patches if "grid, harmonics" in p.get_label()]
        assert len(spans) == 1 and spans[0].get_label().startswith("Landau")
        span = spans[0]  # a Rectangle (matplotlib >= 3.9) or a Polygon, y in data units
        if hasattr(span, "get_height"):
            ys = [span.get_y(), span.get_y() + span.get_height()]
        else:
            ys = np.asarray(span.get_xy())[:, 1]
        assert (min(ys), max(ys)) == pytest.approx((38.0, 43.0))
        bars = [c for c in ax.containers if type(c).__name__ == "ErrorbarContainer"]
        ref = [b for b in bars if "reference" in b.get_label()]
        assert len(ref) == 1
        np.testing.assert_allclose(ref[0].lines[0].get_ydata(), [55.0, 68.75])
        assert ax.get_xlim()[1] >= 16000
    finally:
        rmf.plt.close(drawn[0])


def test_fig16_d_draws_the_reference_points_and_the_layer_model(monkeypatch):
    """Panel (d) of figure 16 draws the N-body rate N/t_R of the runs not rebuilt
    (`t_relax_md_reference`) beside the run's own, and the finite-N layer model's rate
    1/tau_R^coarse(N) (`tau_relax_coarse_{eq}_layer_model` on `N_layer_{eq}`)."""
    from hmfdiff.analysis.figures import relaxation_md_figures as rmf

    drawn = []
    monkeypatch.setattr(rmf, "save_figure", lambda fig, *a, **k: drawn.append(fig))
    tau, sizes, initial = [0.0, 0.25, 0.5], [1000, 4000], ["state", "thermal"]
    ones = np.ones((2, 2))
    rates = xr.Dataset(
        {
            "dS_md": (("initial", "N", "tau"), np.zeros((2, 2, 3))),
            "dS_md_err": (("initial", "N", "tau"), np.zeros((2, 2, 3))),
            "entropy_rate_md": (("initial", "N"), 0.01 * ones),
            "entropy_rate_md_err": (("initial", "N"), 0.001 * ones),
            "current_md": (("initial", "N"), 0.005 * ones),
            "current_md_err": (("initial", "N"), 0.001 * ones),
        },
        coords={"initial": initial, "N": sizes, "tau": tau},
        attrs={"case": "hot", "tau_window": 0.5, "core_edge_jbar": 0.12},
    )
    cmp_ = xr.Dataset(
        {
            "t_relax_md": (("N",), [3.6e4, 1.68e5]),
            "t_relax_md_err": (("N",), [4.5e3, 1.2e4]),
            "tau_relax_coarse_lenard_balescu": ((), 120.0),
            "t_relax_md_reference": (("N_reference",), [4.4e5, 1.1e6]),
            "t_relax_md_reference_err": (("N_reference",), [2e4, 5e4]),
            "tau_relax_coarse_lenard_balescu_layer_model": (
                ("N_layer_lenard_balescu",),
                [100.0, 80.0],
            ),
        },
        coords={"N": sizes, "N_reference": [8000, 16000], "N_layer_lenard_balescu": [1000, 64000]},
    )
    rmf.fig16_relaxation_rates(
        {"relaxation_rates": [rates], "relaxation_comparison": [cmp_]}, None, None
    )
    ax = drawn[0].axes[3]
    try:
        bars = [c for c in ax.containers if type(c).__name__ == "ErrorbarContainer"]
        (ref,) = [b for b in bars if "reference" in b.get_label()]
        np.testing.assert_allclose(ref.lines[0].get_ydata(), [8000 / 4.4e5, 16000 / 1.1e6])
        (model,) = [line for line in ax.get_lines() if "layer" in line.get_label()]
        np.testing.assert_allclose(model.get_xdata(), [1000, 64000])
        np.testing.assert_allclose(model.get_ydata(), [0.01, 0.0125])
        assert ax.get_xlim()[1] >= 64000
    finally:
        rmf.plt.close(drawn[0])
