"""Vlasov stability by the argument principle: stable states pass, a two-stream state is refused,
and its MD(full) run departs from it exponentially at the growth rate of the zero of eps_cc."""

import numpy as np
import pytest

from hmfdiff.dynamics.integrator import Field, Particles, leapfrog
from hmfdiff.dynamics.sampling import make_rng, sample_state
from hmfdiff.kinetic.stability import (
    VlasovInstabilityError,
    check_vlasov_stable,
    growing_mode,
    vlasov_stability,
    winding,
)
from hmfdiff.kinetic.tabulated import TabulatedState
from hmfdiff.meanfield.equilibrium import ThermalState, make_state

CH2 = dict(kind="core_halo", eta1=0.298, eta2=0.051, mu1=-0.517, mu2=0.19, beta1=30.0, beta2=10.0)
HOT = dict(kind="core_halo", eta1=0.3, eta2=0.01, mu1=-0.5, mu2=1.2, beta1=40.0, beta2=2.0)


def two_stream_state():
    """A magnetised core (M0 = 0.43) with two counter-rotating beams at J-bar = 2 (p ~ +-2):
    f is not a decreasing function of the energy."""
    jbar = np.linspace(0.0, 5.0, 2001)
    f = np.exp(-((jbar - 2.0) ** 2) / (2 * 0.1**2)) + 3.0 * np.exp(-jbar / 0.3) + 1e-12
    return TabulatedState(jbar, f, M0_guess=0.5)


@pytest.fixture(scope="module")
def unstable():
    return two_stream_state()


OMEGA = np.concatenate([np.geomspace(1e-6, 0.05, 100), np.linspace(0.05, 50.0, 3000)[1:]])


@pytest.mark.parametrize(
    "zeros, expected",
    [([0.5 + 0.1j], 2), ([0.3 - 0.1j], 0), ([0.2j], 1), ([0.4 + 0.2j, 1.1 + 0.05j], 4)],
)
def test_winding_counts_zeros_of_known_functions(zeros, expected):
    """g(w) = prod (w - z)(w + conj z) / (w + i)^2 (or (w - z)/(w + i) for imaginary z): analytic
    in the upper half plane, g(-conj w) = conj g(w), g -> 1; zeros above the axis are counted."""

    def g(w):
        out = np.ones_like(w, dtype=complex)
        for z in zeros:
            if z.real == 0:
                out *= (w - z) / (w + 1j)
            else:
                out *= (w - z) * (w + np.conj(z)) / (w + 1j) ** 2
        return out

    assert winding(g, OMEGA) == pytest.approx(expected, abs=0.1)


@pytest.mark.parametrize(
    "name, state",
    [
        ("thermal u=-0.1", lambda: ThermalState(u=-0.1)),
        ("thermal M0=0.9", lambda: ThermalState(M0=0.9)),
        ("ch2*", lambda: make_state(CH2)),
        ("hot halo", lambda: make_state(HOT)),
    ],
)
def test_stable_states_pass(name, state):
    st = state()
    rep = check_vlasov_stable(st, name)
    assert rep.stable and rep.zeros_cc == 0 and rep.zeros_ss == 0
    # the windings are integers: the counting is resolved, not rounded from noise
    assert abs(rep.winding_cc) < 1e-3 and abs(rep.winding_ss) < 1e-3
    # the neutral rotation: eps_ss(0) = 0 up to the truncation l_max = 6
    assert abs(rep.eps_ss0) < 1e-3 and rep.eps_cc0 > 0


def test_two_stream_state_is_refused(unstable):
    rep = vlasov_stability(unstable)
    assert rep.zeros_cc == 2 and abs(rep.winding_cc - 2.0) < 1e-3
    with pytest.raises(VlasovInstabilityError, match=r"'two-stream'.*eps_cc has 2 zero"):
        check_vlasov_stable(unstable, "two-stream")


def _envelope_growth(M_abs, t, period, n):
    """Growth rate of the envelope of |M(t)| - |M(0)| in its linear phase (between 4 and 30
    times the 1/sqrt(N) noise), fitted over windows of one period."""
    dev = np.abs(M_abs - M_abs[: max(1, int(period / (t[1] - t[0])))].mean())
    win = int(round(period / (t[1] - t[0])))
    k = dev.size // win
    A = dev[: k * win].reshape(k, win).max(axis=1)
    tc = t[: k * win].reshape(k, win).mean(axis=1)
    sel = (A > 4 / np.sqrt(n)) & (A < 30 / np.sqrt(n))
    return np.polyfit(tc[sel], np.log(A[sel]), 1)[0], sel.sum()


def test_md_of_the_unstable_state_departs_exponentially(unstable):
    """MD(full) from the two-stream state: the deviation of |M| grows exponentially at the rate
    Im(omega) of the zero of eps_cc (0.163), while ch2* stays at the noise level."""
    mode = growing_mode(unstable, "cc")
    assert mode is not None and mode.imag > 0.1
    n, dt, steps = 200_000, 0.05, 800
    t = dt * np.arange(1, steps + 1)
    th, p = sample_state(unstable, n, make_rng(7))
    M = leapfrog(Particles(th, p), steps, dt, Field.SELF)
    rate, n_fit = _envelope_growth(np.hypot(M[:, 0], M[:, 1]), t, 2 * np.pi / mode.real, n)
    assert n_fit >= 3
    assert rate == pytest.approx(mode.imag, rel=0.3)
    th, p = sample_state(make_state(CH2), n, make_rng(7))
    M = leapfrog(Particles(th, p), steps, dt, Field.SELF)
    M_abs = np.hypot(M[:, 0], M[:, 1])
    assert np.max(np.abs(M_abs - M_abs[:20].mean())) < 10 / np.sqrt(n)
