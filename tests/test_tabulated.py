"""Any state as a table f(J-bar): self-consistent M0, and the theory code on tabulated copies."""

import numpy as np
import pytest

from hmfdiff.kinetic.dielectric import DielectricTensor
from hmfdiff.kinetic.diffusion import diffusion_coefficients
from hmfdiff.kinetic.tabulated import TabulatedState, tabulate
from hmfdiff.meanfield import orbits
from hmfdiff.meanfield.equilibrium import EquilibriumError, ThermalState, make_state

CH2 = dict(kind="core_halo", eta1=0.298, eta2=0.051, mu1=-0.517, mu2=0.19, beta1=30.0, beta2=10.0)
KAPPA = np.array([0.1, 0.3, 0.42, 0.5, 0.7, 0.9, 0.99, 1.01, 1.1, 1.5, 2.0])


@pytest.fixture(scope="module", params=["thermal", "ch2"])
def pair(request):
    state = ThermalState(u=-0.1) if request.param == "thermal" else make_state(CH2)
    return state, tabulate(state, n_nodes=2001)


def test_tabulated_copy_has_the_same_M0_and_f(pair):
    state, tab = pair
    assert tab.M0 == pytest.approx(state.M0, abs=1e-10)
    assert tab.mass == pytest.approx(1.0, abs=1e-9)
    np.testing.assert_allclose(tab.f(KAPPA), state.f(KAPPA), rtol=1e-9)
    np.testing.assert_allclose(
        tab.dfdkappa(KAPPA),
        state.dfdkappa(KAPPA),
        rtol=0,
        atol=1e-8 * np.abs(state.dfdkappa(KAPPA)).max(),
    )


def test_tabulated_copy_has_the_energy_of_its_state(pair):
    """u = <p^2>/2 - M0^2/2 = <h> + M0^2/2: the thermal state is built from u = -0.1 itself, so
    its copy must give -0.1 back (the sign of M0^2/2 flipped moves it by M0^2)."""
    state, tab = pair
    assert tab.u == pytest.approx(state.u, abs=1e-8)
    if state.kind == "thermal":
        assert tab.u == pytest.approx(-0.1, abs=1e-8)


def test_tabulated_thermal_entropy_is_the_closed_form():
    """S = -int f ln f dtheta dp of f = C exp(-beta h), with 1/C = sqrt(2 pi/beta) 2 pi
    I0(beta M0) and <h> = u - M0^2/2: S = ln(1/C) + beta (u - M0^2/2).  Guards against the sign
    of the entropy (and a lost ln C)."""
    from scipy.special import i0

    state = ThermalState(u=-0.1)
    tab = tabulate(state, n_nodes=2001)
    b, M0 = state.beta, state.M0
    ref = np.log(np.sqrt(2 * np.pi / b) * 2 * np.pi * i0(b * M0)) + b * (-0.1 - 0.5 * M0**2)
    assert tab.entropy == pytest.approx(ref, abs=1e-7)


@pytest.mark.parametrize("M0", [0.0, 1.0, 1.5, -0.2, float("nan")])
def test_tabulated_state_refuses_a_given_M0_outside_its_range(M0):
    jbar = np.linspace(0.0, 3.0, 50)
    with pytest.raises(EquilibriumError, match="0 < M0 < 1"):
        TabulatedState(jbar, np.exp(-jbar), M0=M0)


def test_tabulated_copy_reproduces_eps(pair):
    state, tab = pair
    omega = np.linspace(0.01, 3.0, 300)
    ref = DielectricTensor(state)(omega)
    got = DielectricTensor(tab, kappa_max=state.kappa_max)(omega)
    for r, g in zip(ref, got, strict=True):
        assert np.max(np.abs(g - r) / np.maximum(1.0, np.abs(r))) < 1e-8


@pytest.mark.parametrize("collective", [False, True])
def test_tabulated_copy_reproduces_ND(pair, collective):
    state, tab = pair
    ref = diffusion_coefficients(state, KAPPA, collective=collective)
    got = diffusion_coefficients(tab, KAPPA, collective=collective)
    for key in ("D", "Dpol"):
        np.testing.assert_allclose(got[key], ref[key], rtol=1e-8, atol=0)


def test_M0_of_a_table_by_direct_phase_space_quadrature():
    """M0 solved from an arbitrary f(J-bar) (not a function of any equilibrium's energy) against
    int f cos(theta) dtheta dp / int f dtheta dp on a (theta, p) grid, with J-bar of each point
    from `orbits.angle_action`: checks the unfolding in J-bar (4 pi per unit J-bar, both
    directions of rotation, J = 2 J-bar below the separatrix)."""
    jbar = np.linspace(0.0, 3.5, 3001)
    f = np.exp(-jbar / 0.25) + 0.1 * np.exp(-((jbar - 1.5) ** 2) / 0.1)
    tab = TabulatedState(jbar, f, M0_guess=0.6)
    theta = (np.arange(600) + 0.5) / 600 * 2 * np.pi - np.pi
    p = np.linspace(-5.0, 5.0, 2001)
    TH, P = np.meshgrid(theta, p, indexing="ij")
    kappa, _, _ = orbits.angle_action(TH, P, tab.M0)
    jb = orbits.rescaled_action(kappa, tab.M0)
    fp = np.where(jb <= jbar[-1], np.exp(np.interp(jb, jbar, np.log(f))), 0.0)
    M_direct = np.sum(fp * np.cos(TH)) / np.sum(fp)
    assert tab.M0 == pytest.approx(M_direct, abs=2e-6)  # measured 1.4e-7
    # mass: 4 pi int f dJ-bar (the unfolding) against the (theta, p) sum
    cell = (2 * np.pi / theta.size) * (p[1] - p[0])
    assert tab.mass == pytest.approx(np.sum(fp) * cell, rel=2e-6)  # measured 2.6e-7


@pytest.mark.parametrize(
    "jbar, f, match",
    [
        (np.linspace(0, 3, 50), -np.ones(50), "> 0"),
        (np.linspace(3, 0, 50), np.ones(50), "increasing"),
        (np.linspace(0, 3, 3), np.ones(3), "size"),
    ],
)
def test_bad_tables_are_refused(jbar, f, match):
    with pytest.raises(EquilibriumError, match=match):
        TabulatedState(jbar, f)
