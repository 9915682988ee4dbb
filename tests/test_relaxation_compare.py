"""The N-body relaxation comparison (analysis.relaxation_compare) on synthetic ensembles that
neither the kinetic code nor the package's sampling made: numpy draws of a piecewise-uniform
J-bar distribution whose two blocks exchange weight as exp(-tau/tau_md), tau = t/N, and of |M|
relaxing exponentially with Gaussian noise of known sigma/sqrt(N).

Every answer is known in closed form: the coarse-grained entropy of a piecewise-uniform density
(the bins resolve it, so coarse-grained = exact), its deficit to the uniform state (the
relative entropy of the two block weights), the L1 distance between two such densities
(2 (1 - q) |p - p'|), the 1/e time of the deficit (a root of the closed form).  Errors are
checked against the scatter of many ensembles: z = (estimate - truth) / error must have a
spread near one."""

import types

import numpy as np
import pytest
import xarray as xr
from scipy.optimize import brentq

from hmfdiff.analysis import relaxation_compare as rc
from hmfdiff.pipeline.layouts.relaxation_md import relaxation_md_dataset

# J-bar bins: block A = bins 0-3 ([0, 0.4]), block B = bins 4-11 ([0.4, 1.2]); a fraction Q of
# the particles lies beyond the last edge (overflow) at all times
EDGES = np.linspace(0.0, 1.2, 13)
L_A, L_B, L = 0.4, 0.8, 1.2
Q = 0.05
P_EQ_A = L_A / L  # weight of block A in the uniform (thermal) state
P0 = 0.9  # weight of block A at tau = 0
TAU_MD = 0.4  # e-folding of the MD's block weight in tau = t/N
TAU_KIN = 1.6  # ... of the "lenard_balescu" evolution's (the "landau" one equals the MD's)
M_INF, M_START, TAU_M, SIGMA_M = 0.62, 0.70, 0.3, 0.5
# MD schedule in tau: uniform, of the coarseness of a real schedule (t_R/N ~ 0.2 falls between
# samples 0.025 apart; a schedule much denser than the noise of the entropy makes the first
# crossing of 1/e jump to noise dips: tried at 0.005, the z of t_R had a spread of 2.2)
TAUS = np.linspace(0.0, 0.8, 33)


def weight_a(tau, tau_e):
    return P_EQ_A + (P0 - P_EQ_A) * np.exp(-np.asarray(tau, dtype=float) / tau_e)


def bin_probabilities(p):
    """Probabilities of the 12 bins and the overflow for block-A weight p (any shape)."""
    p = np.asarray(p, dtype=float)[..., None]
    return np.concatenate(
        [
            np.broadcast_to((1 - Q) * p / 4, p.shape[:-1] + (4,)),
            np.broadcast_to((1 - Q) * (1 - p) / 8, p.shape[:-1] + (8,)),
            np.broadcast_to(Q, p.shape[:-1] + (1,)),
        ],
        axis=-1,
    )


def entropy_exact(p):
    """-int f ln f dtheta dp of the in-range part: f = (1-Q) p / (4 pi L_A) on block A and
    (1-Q)(1-p) / (4 pi L_B) on block B (phase volume 4 pi per unit J-bar)."""
    a, b = (1 - Q) * p, (1 - Q) * (1 - p)
    return -a * np.log(a / (4 * np.pi * L_A)) - b * np.log(b / (4 * np.pi * L_B))


def deficit_exact(p):
    """S_eq - S = (1 - Q) KL(p || p_eq) for the two block weights."""
    return (1 - Q) * (p * np.log(p / P_EQ_A) + (1 - p) * np.log((1 - p) / (1 - P_EQ_A)))


def relaxation_tau_exact(tau_e):
    """tau at which the entropy deficit has fallen to 1/e of its initial value."""
    target = deficit_exact(P0) / np.e
    return brentq(lambda s: deficit_exact(weight_a(s, tau_e)) - target, 0.0, 20 * tau_e)


def relaxation_tau_sampled(tau_e):
    """The same crossing of the exact deficit sampled at TAUS and joined by straight lines (the
    estimator's definition: its target on this schedule; 0.2 % above the exact one here, the
    deficit being convex), by inverting the decreasing polyline."""
    x = deficit_exact(weight_a(TAUS, tau_e))
    return float(np.interp(deficit_exact(P0) / np.e, x[::-1], TAUS[::-1]))


def m_exact(tau):
    return M_INF + (M_START - M_INF) * np.exp(-np.asarray(tau) / TAU_M)


def kinetic_dataset(tau_e, equation):
    """A kinetic evolution in the layout the comparison reads: f on cell-centred J-bar nodes
    (cells of width h tiling [0, 1.3], faces on the bin edges), overflow mass Q in [1.2, 1.3]."""
    h = 0.01
    j = (np.arange(130) + 0.5) * h
    tau = np.linspace(0.0, 10 * tau_e, 2001)
    p = weight_a(tau, tau_e)[:, None]
    f = np.where(j < L_A, (1 - Q) * p / L_A, np.where(j < L, (1 - Q) * (1 - p) / L_B, Q / 0.1)) / (
        4 * np.pi
    )
    return xr.Dataset(
        {
            "f": (("tau", "Jbar"), f),
            "cell_width": (("Jbar",), np.full(j.size, h)),
            "M0": (("tau",), m_exact(tau)),
        },
        coords={"tau": tau, "Jbar": j},
        attrs={"case": "synthetic", "equation": equation},
    )


KINETIC = {
    "lenard_balescu": kinetic_dataset(TAU_KIN, "lenard_balescu"),
    "landau": kinetic_dataset(TAU_MD, "landau"),
}


def md_ensemble(n, R, rng, tau_e=TAU_MD, own_tau_e=None):
    """R realisations of n particles at t = tau N, in the relaxation_md layout; with own_tau_e,
    histograms of the other J-bar measures too: 'own' relaxing with own_tau_e, 'static' a copy
    of the main one."""

    def draw(te):
        c = rng.multinomial(n, bin_probabilities(weight_a(TAUS, te)), size=(R, TAUS.size))
        return c.transpose(1, 0, 2)  # (time, realisation, bin)

    counts = draw(tau_e)
    M = m_exact(TAUS)[:, None] + SIGMA_M / np.sqrt(n) * rng.standard_normal((TAUS.size, R))
    extra = {}
    if own_tau_e is not None:
        own = draw(own_tau_e)
        extra = dict(hist_own=own[..., :-1], overflow_own=own[..., -1])
        extra.update(hist_static=counts[..., :-1], overflow_static=counts[..., -1])
    return synthetic_dataset(counts, M, n, M_START, **extra)


def synthetic_dataset(counts, M, n, M0, **extra):
    """counts (time, realisation, bin + overflow) and |M| (time, realisation) at t = TAUS n, in
    the relaxation_md layout."""
    zeros = np.zeros(M.shape)
    out = {
        "time": TAUS * n,
        "M_abs": M,
        "M_phase": zeros,
        "energy": zeros,
        "momentum": zeros,
        "M0_actions": M.mean(axis=1),
        "hist": counts[..., :-1],
        "overflow": counts[..., -1],
        "wall_time_s": 0.0,
        **extra,
    }
    return relaxation_md_dataset(
        out,
        EDGES,
        case="synthetic",
        state=types.SimpleNamespace(M0=M0),
        n_particles=n,
        run={"dt": 0.1, "tau_max": float(TAUS[-1]), "seed": 0},
    )


@pytest.fixture
def known_states(monkeypatch):
    """The initial and thermal states as their (known) bin fractions and M0: the comparison's
    only use of them (their J-bar CDF is tested in test_relaxation_md)."""
    fractions = {
        "initial": bin_probabilities(P0)[:-1],
        "thermal": bin_probabilities(P_EQ_A)[:-1],
    }
    monkeypatch.setattr(rc, "state_bin_fractions", lambda state, edges: fractions[state.name])
    initial = types.SimpleNamespace(name="initial", M0=M_START)
    thermal = types.SimpleNamespace(name="thermal", M0=m_exact(np.inf))
    return initial, thermal


def test_one_comparison_against_closed_forms(known_states, tmp_path):
    """One set of ensembles (N = 1000 with R = 20, N = 2000 with R = 10, as particles_per_size
    gives), written to netCDF and read back: every column against its closed form."""
    rng = np.random.default_rng(20)
    md = []
    for n, R in ((1000, 20), (2000, 10)):
        path = tmp_path / f"N{n}.nc"
        md_ensemble(n, R, rng).to_netcdf(path)
        md.append(xr.load_dataset(path))
    ds, rows, summary = rc.compare_relaxation(md[::-1], KINETIC, *known_states)
    # the layout: tau = t/N, and the pooled entropy of the file against the closed form within
    # 4 jackknife errors of the comparison's S_md (the same pooled histogram)
    for i, d in enumerate(md):
        np.testing.assert_allclose(d["tau"].values, TAUS, rtol=1e-12)
        dev = d["entropy"].values - entropy_exact(weight_a(TAUS, TAU_MD))
        assert np.all(np.abs(dev) < 4 * ds["S_md_err"].values[i])
    assert len(rows) == 2 * TAUS.size
    # thermal reference: uniform in-range density
    assert summary["S_eq_coarse"] == pytest.approx(-(1 - Q) * np.log((1 - Q) / (4 * np.pi * L)))
    np.testing.assert_allclose(ds["P_thermal"].values, (1 - Q) / 12)
    # kinetic relaxation times: exact up to the interpolation of the kinetic tau grid
    for eq, tau_e in (("lenard_balescu", TAU_KIN), ("landau", TAU_MD)):
        assert summary["tau_relax_coarse"][eq] == pytest.approx(
            relaxation_tau_exact(tau_e), rel=1e-3
        )
    tau_r = relaxation_tau_sampled(TAU_MD)
    for row in rows:
        n, tau = row["n_particles"], row["tau"]
        assert tau == pytest.approx(row["time"] / n, rel=1e-12)
        # kinetic columns at the MD's t/N (not at t): exact up to the linear interpolation on
        # the kinetic tau grid (spacing h = 0.008: h^2/8 max|f''| < 3e-5 for M and S)
        assert row["M_lenard_balescu"] == pytest.approx(m_exact(tau), abs=1e-4)
        assert row["M_landau"] == pytest.approx(m_exact(tau), abs=1e-4)
        S_kin = entropy_exact(weight_a(tau, TAU_KIN))
        assert row["S_lenard_balescu"] == pytest.approx(S_kin, abs=1e-4)
        # MD columns within 4 of their errors; the errors themselves of the right size
        # (standard error of the mean of R values of spread SIGMA_M / sqrt(N))
        R = 20 if n == 1000 else 10
        assert abs(row["M_md"] - m_exact(tau)) < 4 * row["M_md_err"]
        assert row["M_md_err"] == pytest.approx(SIGMA_M / np.sqrt(n * R), rel=0.6)
        assert abs(row["S_md"] - entropy_exact(weight_a(tau, TAU_MD))) < 4 * row["S_md_err"]
        d_true = 2 * (1 - Q) * abs(weight_a(tau, TAU_MD) - weight_a(tau, TAU_KIN))
        # per-bin differences > 5 times the per-bin noise (~ 2e-3 at R N = 2e4): there the
        # estimate sum_b |P_md - P_kin| is unbiased
        if d_true > 0.2:
            assert (
                abs(row["l1_distance_lenard_balescu"] - d_true)
                < 4 * row["l1_distance_lenard_balescu_err"]
            )
    # MD relaxation time in t, = tau_R N at both N (an error t against t/N moves it by N)
    for n in (1000, 2000):
        t_r, err = summary["t_relax_md"][n], summary["t_relax_md_err"][n]
        assert abs(t_r - tau_r * n) < 4 * err
        assert 0 < err < 0.05 * tau_r * n
    assert summary["exponent"] == pytest.approx(1.0, abs=4 * summary["exponent_err"])
    # two sizes: the fitted power law passes through both points (A alone, the value at N = 1,
    # is an extrapolation over ln 1000 with the error of alpha: no test of its own)
    for n in (1000, 2000):
        fitted = summary["prefactor"] * n ** summary["exponent"]
        assert fitted == pytest.approx(summary["t_relax_md"][n], rel=1e-9)
    # the dataset on the tau grid, N ascending
    assert list(ds["N"].values) == [1000, 2000]
    np.testing.assert_allclose(ds["tau"].values, TAUS, rtol=1e-12)
    np.testing.assert_allclose(ds["t_relax_md"].values / ds["N"].values, tau_r, rtol=0.05)
    np.testing.assert_allclose(ds["M_lenard_balescu"].values, m_exact(TAUS), atol=1e-4)


def test_errors_match_the_scatter_of_many_ensembles(known_states):
    """200 independent sets of ensembles: z = (estimate - truth) / error of <|M|>, S, the
    distance, t_R and the exponent has mean ~ 0 and spread ~ 1 (200-1200 samples: its mean is
    known to ~ 0.07, |mean| < 0.3 is 4 sigma; the bounds of the spread are argued below).  A time
    dependence N^0.2 in tau makes the expected exponent 1.2.  The ensembles drawn from the
    "landau" evolution itself: the distance averages to its noise floor."""
    rng = np.random.default_rng(2017)
    alpha_true = 1.2
    sizes = ((1000, 20), (2000, 10))
    tau_e = {n: TAU_MD * (n / 1000) ** (alpha_true - 1) for n, _ in sizes}
    j = [6, 16, 28]  # tau = 0.15, 0.4, 0.7: early, late, very late (t_R/N ~ 0.2)
    z = {k: [] for k in ("M", "S", "d", "t_R", "alpha")}
    floor_ratio = []
    for _ in range(200):
        md = [md_ensemble(n, R, rng, tau_e[n]) for n, R in sizes]
        ds, rows, summary = rc.compare_relaxation(md, KINETIC, *known_states)
        for n, _ in sizes:
            sel = [r for r in rows if r["n_particles"] == n]
            for k in j:
                r, tau = sel[k], TAUS[k]
                p = weight_a(tau, tau_e[n])
                z["M"].append((r["M_md"] - m_exact(tau)) / r["M_md_err"])
                z["S"].append((r["S_md"] - entropy_exact(p)) / r["S_md_err"])
                d_true = 2 * (1 - Q) * abs(p - weight_a(tau, TAU_KIN))
                z["d"].append(
                    (r["l1_distance_lenard_balescu"] - d_true) / r["l1_distance_lenard_balescu_err"]
                )
            t_true = relaxation_tau_sampled(tau_e[n]) * n
            z["t_R"].append((summary["t_relax_md"][n] - t_true) / summary["t_relax_md_err"][n])
        z["alpha"].append((summary["exponent"] - alpha_true) / summary["exponent_err"])
        # tau_e = TAU_MD at N = 1000 (the first N): there the "landau" f is the MD's own
        floor_ratio.append(
            ds["l1_distance_landau"].values[0, 1:].mean()
            / ds["l1_distance_noise_floor"].values[0, 1:].mean()
        )
    for k, v in z.items():
        v = np.asarray(v)
        assert np.all(np.isfinite(v)), k
        assert abs(v.mean()) < 0.3, (k, v.mean())
        # errors from 10 jackknife groups (or 10-20 realisations for <|M|>) make z a Student t
        # with 9-19 dof, std 1.06-1.13; its heavy tails give the sample std a relative error of
        # ~ sqrt(3.2 / n) / 2 = 6 % at n = 200 (measured: 1.03 alpha, 1.11 M, 1.15 S and d,
        # 1.19 t_R; t_R over four other seeds 1.09-1.19)
        assert 0.8 < v.std() < 1.3, (k, v.std())
    # E|x| = sqrt(2/pi) sigma for Gaussian noise: the floor is the mean distance of a perfect
    # match (mean over 200 ensembles of 24 times: a few % of scatter)
    assert np.mean(floor_ratio) == pytest.approx(1.0, abs=0.1)


def test_summary_lines_define_and_report_t_R():
    """The summary text states what t_R is (HMF time t, entropy deficit fallen by e), how its
    error is estimated (jackknife over groups of realisations) and that tau_R^coarse is the
    kinetic time in t/N; the numbers it prints are those of a summary made up here: t_R/N and
    t_R/(tau_R^coarse N) by hand (an N lost or doubled moves them by >= a factor 2)."""
    summary = {
        "case": "hot",
        "S_eq_coarse": 2.0,
        "exponent": 1.1,
        "exponent_err": 0.1,
        "prefactor": 0.04,
        "tau_relax_coarse": {"landau": 40.0, "lenard_balescu": 120.0},
        "t_relax_md": {1000: 36000.0, 4000: 168000.0},
        "t_relax_md_err": {1000: 4500.0, 4000: 12000.0},
        "jackknife_groups": {1000: 10, 4000: 10},
    }
    text = "\n".join(rc.summary_lines(summary))
    for phrase in (
        "HMF time t (not t/N)",
        "S_eq - S(t) has fallen to 1/e",
        "jackknife standard error over 10 groups of realisations",
        "tau = t/N",
        "fine-grained",
    ):
        assert phrase in text, phrase
    assert "landau: tau_R^coarse = 40" in text
    assert "lenard_balescu: tau_R^coarse = 120" in text
    # N = 1000: t_R/N = 36, 36/40 = 0.9 (landau), 36/120 = 0.3; N = 4000: 42, 1.05, 0.35
    assert "MD N = 1000: t_R = 3.6e+04 +- 4.5e+03, t_R/N = 36;" in text
    assert "t_R/(tau_R^coarse N) = 0.900 (landau)" in text
    assert "t_R/(tau_R^coarse N) = 0.300 (lenard_balescu)" in text
    assert "MD N = 4000: t_R = 1.68e+05 +- 1.2e+04, t_R/N = 42;" in text
    assert "t_R/(tau_R^coarse N) = 1.050 (landau)" in text
    assert "alpha = 1.100 +- 0.100" in text


def test_jackknife_groups_reported(known_states):
    """The summary records the number of jackknife groups actually used: min(10, R)."""
    rng = np.random.default_rng(5)
    md = [md_ensemble(1000, 20, rng), md_ensemble(2000, 6, rng)]
    _, _, summary = rc.compare_relaxation(md, KINETIC, *known_states)
    assert summary["jackknife_groups"] == {1000: 10, 2000: 6}


def test_relaxation_time_of_each_action_measure(known_states):
    """t_R is also computed from the histograms of J-bar measured with each realisation's |M|
    and with the static M0: a copy of the main histograms gives the same t_R to the last digit,
    histograms relaxing twice as slowly give twice the time (within errors), and the summary
    and dataset carry both."""
    rng = np.random.default_rng(5)
    md = [md_ensemble(n, R, rng, own_tau_e=2 * TAU_MD) for n, R in ((1000, 20), (2000, 10))]
    ds, _, summary = rc.compare_relaxation(md, KINETIC, *known_states)
    for i, n in enumerate((1000, 2000)):
        t_s, e_s = summary["t_relax_md_measures"][n]["_static"]
        assert t_s == summary["t_relax_md"][n] and e_s == summary["t_relax_md_err"][n]
        t_o, e_o = summary["t_relax_md_measures"][n]["_own"]
        assert abs(t_o - relaxation_tau_sampled(2 * TAU_MD) * n) < 4 * e_o
        assert ds["t_relax_md_own"].values[i] == t_o
        assert ds["t_relax_md_static_err"].values[i] == e_s
    lines = rc.summary_lines(summary)
    assert any("each realisation's own |M|: t_R/N" in line for line in lines)


def _thermal_M0_by_bisection(u):
    """Thermal M0 of energy u, independently: M = I1(beta M)/I0(beta M) with
    beta = 1 / (2 (u + M^2/2)), solved for M by bisection (the magnetised root)."""
    from scipy import optimize, special

    def g(m):
        beta = 1.0 / (2.0 * (u + 0.5 * m * m))
        return special.i1e(beta * m) / special.i0e(beta * m) - m

    lo = np.sqrt(max(-2.0 * u, 0.0)) + 1e-9  # beta > 0 needs u + M^2/2 > 0
    return optimize.brentq(g, max(lo, 1e-3), 1 - 1e-12, xtol=1e-14)


def test_end_state_against_the_thermal_state_of_each_realisation_energy():
    """Realisations drawn with energies scattered about u0 end at the thermal M0 of their own
    energy: the comparison's reference is the mean of those (not the M0 of u0), their
    difference from the end |M| is zero, and the summary says so."""
    u0 = -0.073
    energies = u0 + np.array([-0.012, 0.004, 0.010, 0.015, -0.002])
    m_own = np.array([_thermal_M0_by_bisection(e) for e in energies])
    o = rc.own_energy_thermal(energies, m_own)
    assert o["M0_thermal_own"][0] == pytest.approx(m_own.mean(), abs=1e-9)
    assert o["M_end_minus_own"][0] == pytest.approx(0.0, abs=1e-9)
    assert o["energy0"][1] == pytest.approx(energies.std(ddof=1) / np.sqrt(5), rel=1e-12)
    # the state's energy alone would put the reference off by the mean energy's shift
    m_u0 = _thermal_M0_by_bisection(u0)
    off = rc.own_energy_thermal(energies, np.full(5, m_u0))["M_end_minus_own"][0]
    assert off == pytest.approx(m_u0 - m_own.mean(), abs=1e-9) and abs(off) > 1e-3


def test_entropy_change_since_t0_and_its_error(known_states):
    """S_md_change = S_md(tau) - S_md(0) against the closed form within 4 of its jackknife
    errors at every N and tau; its error is that of the difference, 0 at tau = 0."""
    rng = np.random.default_rng(11)
    md = [md_ensemble(n, R, rng) for n, R in ((1000, 20), (2000, 10))]
    ds, _, _ = rc.compare_relaxation(md, KINETIC, *known_states)
    truth = entropy_exact(weight_a(TAUS, TAU_MD)) - entropy_exact(weight_a(0.0, TAU_MD))
    change, err = ds["S_md_change"].values, ds["S_md_change_err"].values
    assert np.all(change[:, 0] == 0) and np.all(err[:, 0] == 0)
    assert np.all(np.abs(change[:, 1:] - truth[1:]) < 4 * err[:, 1:])


def ensemble_of_weights(p, n, R, rng):
    """R realisations of n particles whose block-A weight is p (one value per sample of TAUS),
    in the relaxation_md layout, |M| = M_INF throughout."""
    c = rng.multinomial(n, bin_probabilities(p), size=(R, TAUS.size)).transpose(1, 0, 2)
    return synthetic_dataset(c, np.full((TAUS.size, R), M_INF), n, M_INF)


def test_thermal_control_measures_the_plug_in_entropy_bias(known_states):
    """Controls drawn from the thermal fractions themselves, M = N R = 400 particles per
    sample: the coarse entropy is the plug-in estimate, low by sum_b (1 - p_b) / 2M over the 12
    in-range bins, (11 + Q) / 2M = 1.4e-2 (the bin widths enter linearly: no bias).  Over 40
    independent controls the mean offset must find it (its error is set by the overflow's
    count, which moves the in-range entropy at first order), the jackknife errors of offset and
    drift must match their scatter, and a stationary control's drift must average to zero.
    One comparison with a control: the state's t_R moves by less than its error."""
    rng = np.random.default_rng(7)
    n, R = 40, 10
    S_eq = entropy_exact(P_EQ_A)
    bias = -(11 + Q) / (2 * n * R)
    got = np.array(
        [
            [
                v
                for key in ("offset", "drift")
                for v in rc.thermal_control(
                    ensemble_of_weights(np.full(TAUS.size, P_EQ_A), n, R, rng), EDGES, S_eq
                )[key]
            ]
            for _ in range(40)
        ]
    )
    off, off_err, drift, drift_err = got.T
    assert abs(off.mean() - bias) < 3 * off.std(ddof=1) / np.sqrt(off.size)
    assert abs(off.mean()) > 5 * off.std(ddof=1) / np.sqrt(off.size)
    assert abs(drift.mean()) < 3 * drift.std(ddof=1) / np.sqrt(drift.size)
    # jackknife over 10 groups: its error has ~ 24 % scatter; the rms z of 40 values is known
    # to ~ 0.15
    for v, e, truth in ((off, off_err, bias), (drift, drift_err, 0.0)):
        assert 0.6 < np.sqrt(np.mean(((v - truth) / e) ** 2)) < 1.6
    state = ensemble_of_weights(weight_a(TAUS, TAU_MD), 1000, 20, rng)
    control = ensemble_of_weights(np.full(TAUS.size, P_EQ_A), 1000, 20, rng)
    _, _, summary = rc.compare_relaxation([state], KINETIC, *known_states, controls=[control])
    t_r, t_r_err = summary["t_relax_md"][1000], summary["t_relax_md_err"][1000]
    assert abs(summary["thermal_control"][1000]["t_relax"][0] - t_r) < t_r_err


def test_relaxation_time_against_the_control_level(known_states):
    """An ensemble that relaxes to a state other than the thermal one (block-A weight P_C, as a
    histogram broadened by the measurement would), with a control that sits at P_C: the offset
    is the closed-form entropy difference, the deficit to S_eq never falls to 1/e of its start
    (t_R NaN or late), and t_R against the control's level is the 1/e time of
    S(P_C) - S(p(tau)), found by root-finding on the closed form."""
    P_C = 0.6
    rng = np.random.default_rng(8)
    n, R = 1000, 40

    def weight(tau):
        return P_C + (P0 - P_C) * np.exp(-np.asarray(tau, dtype=float) / TAU_MD)

    state = ensemble_of_weights(weight(TAUS), n, R, rng)
    control = ensemble_of_weights(np.full(TAUS.size, P_C), n, R, rng)
    ds, _, summary = rc.compare_relaxation([state], KINETIC, *known_states, controls=[control])
    c = summary["thermal_control"][n]
    offset_exact = entropy_exact(P_C) - entropy_exact(P_EQ_A)
    assert abs(c["offset"][0] - offset_exact) < 4 * c["offset"][1]
    assert c["offset"][1] < 0.1 * abs(offset_exact)

    def excess(tau):
        return entropy_exact(P_C) - entropy_exact(weight(tau))

    x = excess(TAUS)
    t_expected = float(np.interp(excess(0.0) / np.e, x[::-1], TAUS[::-1])) * n
    t_r, t_r_err = c["t_relax"]
    assert abs(t_r - t_expected) < 4 * t_r_err
    assert 0 < t_r_err < 0.05 * t_expected
    # the plain t_R (deficit to S_eq) is another quantity here: well apart
    assert not abs(summary["t_relax_md"][n] - t_expected) < 4 * t_r_err
    np.testing.assert_allclose(ds["t_relax_md_vs_control"].values, [t_r])
    assert np.isfinite(ds["S_control"].values).all()


def test_thermal_control_must_match_an_ensemble(known_states):
    rng = np.random.default_rng(9)
    state = ensemble_of_weights(weight_a(TAUS, TAU_MD), 200, 10, rng)
    control = ensemble_of_weights(np.full(TAUS.size, P_EQ_A), 400, 5, rng)
    with pytest.raises(ValueError, match="N = \\[400\\]"):
        rc.compare_relaxation([state], KINETIC, *known_states, controls=[control])
