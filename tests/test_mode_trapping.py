"""studies/mode_trapping.py: the bounce frequency it compares with the mode's damping, against
the trapped orbits of the resonance's pendulum integrated numerically, and the reference
file's omega_b / gamma against that formula (a stale reference fails)."""

import re
from pathlib import Path

import numpy as np
import pytest
from _studies import load_study
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parents[1]


def _pendulum_period(n, dOmega_dJ, A, dJ0):
    """Period of psi = n w - omega0 t for H = Omega' dJ^2 / 2 - A cos psi (near the resonance
    n Omega = omega0): d psi/dt = n Omega' dJ, d dJ/dt = -n A sin psi, started with a small dJ0
    at the stable point (psi = 0 for Omega' > 0, pi for Omega' < 0)."""
    psi0 = 0.0 if dOmega_dJ > 0 else np.pi

    def rhs(t, y):
        return [n * dOmega_dJ * y[1], -n * A * np.sin(y[0])]

    def through(t, y):  # psi through its stable point in the starting direction: once a period
        return y[0] - psi0

    through.direction = np.sign(n * dOmega_dJ * dJ0)
    guess = 2 * np.pi / (n * np.sqrt(abs(dOmega_dJ) * A))
    sol = solve_ivp(
        rhs,
        (0, 10.5 * guess),
        [psi0, dJ0],
        events=through,
        rtol=1e-11,
        atol=1e-15,
        max_step=guess / 50,
    )
    t = sol.t_events[0]
    t = t[t > 0.5 * guess]
    assert t.size >= 5
    return np.mean(np.diff(t))


def test_bounce_frequency_is_the_small_oscillation_of_the_resonance_pendulum():
    study = load_study("mode_trapping")
    for n, dOm, c_n, power, N, gamma in [
        (2, -0.1398, 0.1268, 0.03013, 4000, 0.00742),
        (1, -0.13, 0.295, 0.007, 1000, 0.019),
    ]:
        res = {"dOmega_dJ": dOm, "c_n": c_n}
        study.HARMONIC = n
        wb = study.bounce_over_gamma(N, gamma, power, res) * gamma
        A = np.sqrt(2 * power / N) * c_n  # the mode's amplitude times the orbit's coefficient
        # small oscillations: a trapped orbit far inside the separatrix of the resonance
        dJ0 = 1e-3 * np.sqrt(A / abs(dOm))
        period = _pendulum_period(n, dOm, A, dJ0)
        assert abs(2 * np.pi / period / wb - 1) < 1e-4, (n, wb, 2 * np.pi / period)


def test_reference_bounce_ratios_follow_from_its_mode_parameters():
    study = load_study("mode_trapping")
    text = (ROOT / "docs" / "reference" / "mode_trapping.txt").read_text()
    head = re.compile(
        r"(\w+): M0 = [\d.]+, omega0 = [\d.]+, gamma = ([\d.]+), peak \S+ = [\d.]+, "
        r"N <dM_x\^2>_mode = ([\d.]+); resonance kappa = [\d.]+ \(J-bar [\d.]+\), "
        r"c_2 = ([\d.]+), dOmega/dJ = (-?[\d.]+)\n  omega_b / gamma at N = (.*)"
    )
    found = head.findall(text)
    assert len(found) == 3
    for _case, gamma, power, c2, dOm, cells in found:
        res = {"dOmega_dJ": float(dOm), "c_n": float(c2)}
        for cell in cells.split(", "):
            N, said = cell.split(": ")
            x = study.bounce_over_gamma(float(N), float(gamma), float(power), res)
            # printed to 3 figures, from mode parameters themselves rounded to about 4
            y = float(said)
            tol = 0.5 * 10.0 ** (np.floor(np.log10(y)) - 2) + 1e-3 * y
            assert abs(x - y) <= tol, (N, x, said)


def _lorentz(w, w0=1.44, g=0.0756):
    return g / ((w - w0) ** 2 + g**2) + 0.3


def _noisy(model, om, rel=0.02, seed=0):
    rng = np.random.default_rng(seed)
    err = rel * model
    return model + err * rng.standard_normal(om.size), err


def test_lineshape_fits_recover_a_shift_and_a_tilt():
    """The two line-shape models of `lineshape`: a line moved by delta is fitted back by the
    shift model (delta within its resolution, chi^2 far below the tilt's), and a tilted line
    by the tilt model (b recovered, chi^2 far below the shift's)."""
    mt = load_study("mode_trapping")
    om = np.linspace(1.44 - 0.3, 1.44 + 0.3, 49)
    grid = np.arange(-0.05, 0.05 + 1e-12, 2.5e-4)
    x = (om - 1.44) / 0.0756

    shifted, err = _noisy(1.3 * _lorentz(om + 0.0139), om)
    chi_s, amp, delta = mt._fit_shift(shifted, err, _lorentz, om, grid)
    chi_t, _, _ = mt._fit_tilt(shifted, err, _lorentz(om), x)
    assert abs(delta + 0.0139) < 1e-3 and abs(amp - 1.3) < 0.02
    assert chi_s < 2 * om.size < chi_t

    tilted, err = _noisy(0.9 * _lorentz(om) * (1 - 0.1 * x), om, seed=1)
    chi_t, amp, b = mt._fit_tilt(tilted, err, _lorentz(om), x)
    chi_s, _, _ = mt._fit_shift(tilted, err, _lorentz, om, grid)
    assert abs(b + 0.1) < 0.003 and abs(amp - 0.9) < 0.02
    assert chi_t < 2 * om.size < chi_s


def test_longer_runs_have_segments_of_half_their_length(monkeypatch):
    """`run ... T_MAX` runs the hot-halo record to T_MAX with lags (the Welch segments) to
    T_MAX / 2; without it, the 1/N study's t_max 1000 and lags to 500."""
    monkeypatch.chdir(ROOT)
    mt = load_study("mode_trapping")
    short = mt.md_run("corehalo_hothalo", 16000)
    long = mt.md_run("corehalo_hothalo", 16000, 4000.0)
    assert (short.t_max, short.max_lag) == (1000.0, 500.0)
    assert (long.t_max, long.max_lag) == (4000.0, 2000.0)
    assert long.n_particles == short.n_particles == 16000
    assert long.lag_samples * long.sample_every == 2000.0


def test_narrow_bands_only_for_the_near_critical_state_and_its_control():
    """The hot halo keeps its bands (omega0 - 0.15 ... + 0.06; -+ max(4 gamma, 0.15)); thermal
    u = 0.2475, whose MD spectrum has a floor below omega ~ 0.13, and its control u = 0.23 get
    omega0 -+ 4 gamma."""
    mt = load_study("mode_trapping")
    assert mt.band_offsets("corehalo_hothalo", 0.0074, "power") == (0.15, 0.06)
    assert mt.band_offsets("corehalo_hothalo", 0.0074, "fit") == (0.15, 0.15)
    assert mt.band_offsets("corehalo_hothalo_b10", 0.0756, "fit") == (4 * 0.0756, 4 * 0.0756)
    lo, hi = mt.band_offsets("thermal_u0.2475", 0.01672, "power")
    assert lo == hi == 4 * 0.01672 and 0.196 - lo > 0.12
    assert mt.band_offsets("thermal_u0.23", 0.04573, "power") == (4 * 0.04573, 4 * 0.04573)


def _narrow_gaussian(rng, n, dt, omega0, gamma):
    """A noise-driven damped oscillator's record (Gaussian): x'' + 2 gamma x' + omega0^2 x = noise,
    by its exact spectral synthesis (independent complex Gaussian amplitudes)."""
    omega = 2 * np.pi * np.fft.rfftfreq(n, dt)
    amp = 1.0 / np.sqrt((omega0**2 - omega**2) ** 2 + (2 * gamma * omega) ** 2)
    X = amp * (rng.standard_normal(omega.size) + 1j * rng.standard_normal(omega.size))
    X[0] = 0
    return np.fft.irfft(X, n)


def test_band_kurtosis_is_zero_for_a_gaussian_mode_and_negative_for_a_saturated_one():
    """A linear noise-driven mode (Gaussian) gives a kurtosis excess over its surrogates of 0
    within its error, although its own band-passed kurtosis is biased below 0 by the record's
    few independent samples; the same mode with its amplitude clipped (saturated: the
    envelope held below 1.2 rms) gives a clearly negative excess."""
    mt = load_study("mode_trapping")
    rng = np.random.default_rng(11)
    dt, n, omega0, gamma = 0.25, 4000, 0.196, 0.0167
    lo, hi = omega0 - 4 * gamma, omega0 + 4 * gamma
    raw, diff, clipped = [], [], []
    for _ in range(40):
        x = _narrow_gaussian(rng, n, dt, omega0, gamma)
        k, k0 = mt.band_kurtosis_excess(x, dt, lo, hi, rng)
        raw.append(k)
        diff.append(k - k0)
        # the envelope of the band-passed mode, limited: analytic signal scaled where large
        y = mt.band_passed(x, dt, lo, hi)
        Y = np.fft.fft(y)
        Y[n // 2 + 1 :] = 0
        Y[1 : n // 2] *= 2
        z = np.fft.ifft(Y)
        env = np.abs(z)
        cap = 1.2 * np.sqrt(np.mean(y**2))
        y_sat = np.real(z * np.minimum(1.0, cap / np.maximum(env, 1e-300)))
        k, k0 = mt.band_kurtosis_excess(y_sat, dt, lo, hi, rng)
        clipped.append(k - k0)
    raw, diff, clipped = map(np.array, (raw, diff, clipped))
    err = diff.std(ddof=1) / np.sqrt(diff.size)
    assert raw.mean() < -0.1  # the bias the surrogates remove
    assert abs(diff.mean()) < 3 * err, (diff.mean(), err)
    assert clipped.mean() < -0.3 and clipped.mean() < diff.mean() - 5 * err


def test_separatrix_reference_motion_is_rms_over_twice_the_mean_modulus():
    """Each line of the reference file's `separatrix` output: the separatrix motion in kappa
    is rms(|M| - M-bar) / (2 M-bar) of the quoted sqrt(N) rms and M-bar / M0, and its ratio to
    1 - kappa_res is the quoted one (a lost factor or a stale line fails)."""
    head = re.compile(r"^(\S+): M0 = ([\d.]+), .*1 - kappa_res = ([\d.e+-]+),")
    line = re.compile(
        r"N = (\d+) .*M-bar / M0 = ([\d.]+) .*sqrt\(N\) rms\(\|M\| - M-bar\) = ([\d.]+); "
        r"separatrix motion in kappa ([\d.e+-]+) = ([\d.e+-]+) \(1 - kappa_res\)"
    )
    names = ("mode_separatrix_u0.2475.txt", "mode_separatrix_u0.23.txt")
    rows = list(_reference_rows(names, head, line))
    for h, m in rows:
        M0, gap = float(h[2]), float(h[3])
        N, ratio, srms, motion, over = (float(v) for v in m.groups())
        assert abs(srms / np.sqrt(N) / (2 * ratio * M0) / motion - 1) < 2e-3, m[0]
        assert abs(motion / gap / over - 1) < 5e-3, m[0]
    assert len(rows) >= 11


def _reference_rows(names, head, line):
    """(head match, line match) of each row of the reference files `names` that `line`
    matches, with the last row before it that `head` matched (its state's line)."""
    h = None
    for name in names:
        for row in (ROOT / "docs" / "reference" / name).read_text().splitlines():
            if m := head.match(row):
                h = m
            elif m := line.search(row):
                yield h, m


def test_case_spec_reads_the_configs_then_thermal_names(monkeypatch):
    """A case of config.yaml comes from it; thermal_u<U> in no config is the thermal state of
    energy U; any other name is refused in one line."""
    monkeypatch.chdir(ROOT)
    mt = load_study("mode_trapping")
    assert mt.case_spec("thermal_u0.2475") == {"kind": "thermal", "u": 0.2475}
    assert mt.case_spec("thermal_u0.23") == {"kind": "thermal", "u": 0.23}
    assert mt.case_spec("corehalo_hothalo_b10")["beta1"] == 10.0
    with pytest.raises(SystemExit, match="nor thermal_u<U>"):
        mt.case_spec("thermal_hot")


def _damped_oscillator(omega0, gamma, source, n_real, n_t, dt, seed):
    """Realisations (n_real, n_t) of x = Re z, dz/dt = (i omega0 - gamma) z + white noise (the
    exact discretisation), whose two-sided spectrum is the pair of Lorentzians
    source (gamma^2 ... ) / ((omega -+ omega0)^2 + gamma^2), source their height at gamma = 1
    (S(omega0) = source / gamma up to the mirror line), started in the stationary state."""
    rng = np.random.default_rng(seed)
    var = 2.0 * source  # <|z|^2>: C(0) = var / 2 = int S domega / 2 pi = source (both lines)
    step = np.exp((1j * omega0 - gamma) * dt)
    kick = np.sqrt(var * (1.0 - np.exp(-2.0 * gamma * dt)) / 2.0)
    noise = kick * (rng.standard_normal((n_real, n_t)) + 1j * rng.standard_normal((n_real, n_t)))
    z = np.empty((n_real, n_t), dtype=complex)
    z[:, 0] = np.sqrt(var / 2.0) * (rng.standard_normal(n_real) + 1j * rng.standard_normal(n_real))
    for k in range(1, n_t):
        z[:, k] = z[:, k - 1] * step + noise[:, k]
    return z.real


def test_width_fit_tells_a_weaker_source_from_a_stronger_damping():
    """`width` against damped oscillators of known source and damping, both carrying 2/3 of
    the linear line's power: one with the linear damping and 2/3 of its source (a = 2/3, g =
    1), one with the linear source and 3/2 of its damping (a = 1, g = 3/2).  The fit recovers
    each (within three jackknife errors, errors small enough to tell them apart), the right
    one-parameter hypothesis has the lower chi^2, and the power over the fit band (omega0 -
    gamma ... omega0 + 4 gamma) is that of the true line, (a / g) (arctan(4 / g) + arctan(1 /
    g)) / (arctan(4) + arctan(1)) of the linear one (2/3 and 0.577)."""
    from hmfdiff.analysis.fluctuations import welch_spectrum

    mt = load_study("mode_trapping")
    omega0, gamma, dt, seg = 0.196, 0.0167, 0.25, 4000

    def linear(w):  # the exact spectrum of the linear oscillator (source 1 / gamma at omega0)
        w = np.abs(np.asarray(w, dtype=float))
        return (
            2.0
            * gamma
            * (1 / ((w - omega0) ** 2 + gamma**2) + 1 / ((w + omega0) ** 2 + gamma**2))
            / 2
        )

    for a_true, g_true, seed in ((2 / 3, 1.0, 3), (1.0, 1.5, 4)):
        # power ~ source / damping: the oscillator's variance is a_true / g_true of the linear
        x = _damped_oscillator(omega0, g_true * gamma, a_true / g_true, 60, 2 * seg, dt, seed)
        rows = [welch_spectrum(r[None, :], dt, seg) for r in x]
        om = rows[0][0]
        S = np.array([r[1] for r in rows])
        r = mt.source_and_width(om, S, dt, seg, linear, omega0, gamma)
        assert abs(r["g"] - g_true) < 3 * r["g_err"] and r["g_err"] < 0.1, r
        assert abs(r["a"] - a_true) < 3 * r["a_err"] and r["a_err"] < 0.1, r
        lo, hi = -mt.WIDTH_FIT[0], mt.WIDTH_FIT[1]
        in_band = a_true / g_true * (np.arctan(hi / g_true) + np.arctan(lo / g_true))
        in_band /= np.arctan(hi) + np.arctan(lo)
        assert abs(r["power"] - in_band) < 3 * r["power_err"], r
        if g_true == 1.0:
            assert r["chi2_source"] < r["chi2_damping"], r
        else:
            assert r["chi2_damping"] < r["chi2_source"], r


def test_slow_separatrix_motion_keeps_only_what_lies_below_the_line():
    """`width`'s slow separatrix motion: |M| = M-bar (1 + 2 d cos(0.02 t)) + a mode at omega0 of
    amplitude 0.015 M-bar (the u = 0.2475 mode's at N = 1e6) gives d / sqrt(2) within 1 %,
    d = 2e-4 ... 8e-3 (the mode, inside the line, is not counted: without the taper it leaks
    into the slow band), and the line's place
    whose n = 2 resonance lies that far inside the separatrix, for both states' M0 (u = 0.23's
    line reaches past the librating band's edge 2 sqrt(M0), which must not leave it undefined),
    moves up the line as the motion grows."""
    import types

    import xarray as xr

    mt = load_study("mode_trapping")
    dt, n_t = 0.25, 8000
    t = dt * np.arange(n_t)
    for M0, omega0, gamma in ((0.063237, 0.19604, 0.01672), (0.178691, 0.35646, 0.04573)):
        edges = []
        for d in (2e-4, 2e-3, 8e-3):
            mod = M0 * (1 + 2 * d * np.cos(0.02 * t)) + 0.015 * M0 * np.cos(omega0 * t)
            ds = xr.Dataset(
                {
                    "Mx_fine": ("time_fine", mod * np.cos(0.3)),
                    "My_fine": ("time_fine", mod * np.sin(0.3)),
                }
            )
            state = types.SimpleNamespace(M0=M0)
            slow, edge = mt._slow_separatrix_motion([ds, ds], n_t, dt, state, omega0, gamma)
            assert abs(slow / (d / np.sqrt(2)) - 1) < 0.01, (d, slow)
            edges.append(edge)
        assert np.all(np.isfinite(edges)) and np.all(np.diff(edges) > 0), edges


def test_width_reference_edges_are_where_the_resonance_meets_the_slow_motion():
    """Each line of the reference file's `width` output: the place in the line it quotes,
    (omega - omega0) / gamma, is where the n = 2 librating resonance lies the quoted slow
    motion inside the separatrix (1 - kappa_res(omega / 2) = dkappa_slow), recomputed from the
    orbits (a stale file or a changed orbit frequency fails)."""
    from hmfdiff.meanfield import orbits

    head = re.compile(r"^(\S+): M0 = ([\d.]+), omega0 = ([\d.]+), gamma = ([\d.]+)$")
    line = re.compile(
        r"slow separatrix motion ([\d.e+-]+) = 1 - kappa_res at \(omega - omega0\) / gamma = "
        r"([+-][\d.]+)"
    )
    rows = list(_reference_rows(("mode_width_u0.2475.txt",), head, line))
    for h, m in rows:
        M0, omega0, gamma = (float(v) for v in h.groups()[1:])
        slow, edge = float(m[1]), float(m[2])
        kappa = orbits.kappa_from_frequency((omega0 + edge * gamma) / 2, M0, "libration")
        assert abs((1 - float(kappa)) / slow - 1) < 0.02, m[0]
    assert len(rows) >= 7


def test_modulus_needs_no_frame_where_the_direction_wanders():
    """|M| = M-bar + a damped oscillation of known spectrum, its direction a random walk of
    ~2.8 rad rms over a Welch segment (as at small N): the spectrum of |M| gives the oscillation's
    power over omega0 -+ 4 gamma (1 within three errors), while M_parallel, projected on the
    direction averaged over a segment, loses part of it (less than 0.9)."""
    import xarray as xr

    from hmfdiff.analysis.md_spectrum import smoothed

    mt = load_study("mode_trapping")
    omega0, gamma, dt, seg, var = 0.196, 0.0167, 0.25, 4000, 1e-4

    def linear(w):
        w = np.abs(np.asarray(w, dtype=float))
        lor = 1 / ((w - omega0) ** 2 + gamma**2) + 1 / ((w + omega0) ** 2 + gamma**2)
        return var * gamma * lor

    x = _damped_oscillator(omega0, gamma, var, 40, 2 * seg, dt, 7)
    rng = np.random.default_rng(8)
    phi = np.cumsum(rng.standard_normal(x.shape) * np.sqrt(4e-3 * dt), axis=1)
    mod = 0.063 + x
    data = [
        xr.Dataset({"Mx_fine": ("t", m * np.cos(p)), "My_fine": ("t", m * np.sin(p))})
        for m, p in zip(mod, phi, strict=True)
    ]
    for ds in data:
        ds.attrs["m_every"] = dt
    om, S, _ = mt._modulus_spectra(data, 1.0, 2 * seg, seg)
    ((_, _, ratio, err),) = mt._band_ratios(om, S, seg, dt, linear, omega0, gamma, ((-4, 4),))
    assert abs(ratio - 1) < 3 * err and err < 0.1, (ratio, err)
    om, S, _ = mt._spectra(data, 1.0, slice(0, 2 * seg), seg)
    band = np.abs(om - omega0) < 4 * gamma
    parallel = S[:, band].mean(0).sum() / smoothed(linear, om[band], seg, dt).sum()
    assert parallel < 0.9, (parallel, ratio)
