"""studies/mode_trapping.py: the bounce frequency it compares with the mode's damping, against
the trapped orbits of the resonance's pendulum integrated numerically, and the reference
file's omega_b / gamma against that formula (a stale reference fails)."""

import re
from pathlib import Path

import numpy as np
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
