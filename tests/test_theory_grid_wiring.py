"""`kinetic.theory.theory_grid` (the arrays behind figs. 4-6, 9, 10) against independent
references: the documented omega grid and separatrix mask, the action and frequency from
quadrature of p(theta) along the pendulum orbit, the thermal identity D_pol = -beta Omega D
for Landau and Lenard-Balescu separately, and the dressing of the bare (n, n') = (1, 1)
librating resonance by 1/|eps_ss(Omega)|^2.

Bugs guarded against: a wrong omega range (4 M0 for 4 sqrt(M0)), a mask narrower than the
band, J replaced by J-bar, the Lenard-Balescu arrays computed without collective effects, the
Landau D_pol taken from the Lenard-Balescu result, and a non-finite guard that never fires.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import action_by_quadrature

import hmfdiff.kinetic.theory as theory
from hmfdiff.kinetic.dielectric import DielectricTensor
from hmfdiff.meanfield.equilibrium import ThermalState

M0 = 0.64
ACC = {"n_panels": 12, "order": 10}


@pytest.fixture(scope="module")
def state():
    return ThermalState(M0=M0)


@pytest.fixture(scope="module")
def grid(state):
    g = theory.theory_grid(
        state,
        n_kappa=3,
        kappa_min=0.3,
        kappa_max=0.8,
        separatrix_band=0.04,
        n_max=2,
        l_max=2,
        omega=np.array([0.1, 0.5]),
        **ACC,
    )
    assert np.allclose(g["kappa"], [0.3, 0.55, 0.8])
    return g


def _action_quadrature(kappa):
    return action_by_quadrature(kappa, M0, rtol=1e-12)


def test_default_omega_runs_from_zero_to_four_omega0():
    """fig. eps: omega from 0 to 4 Omega_0 with Omega_0 = Omega(kappa -> 0) = sqrt(M0) (the
    small-oscillation frequency of h = p^2/2 - M0 cos theta); M0 = 0.64 gives 3.2, 4 M0 = 2.56."""
    om = theory.default_omega(M0, n=5)
    np.testing.assert_allclose(om, np.linspace(0.0, 3.2, 5), rtol=0, atol=1e-14)


def test_mask_is_exactly_the_separatrix_band(state):
    """|kappa - 1| < band is NaN, everything else finite (band 0.04; kappa 0.97, 0.98, 1.02,
    1.03 lie inside it, 0.95 and 1.05 outside; band/2 would leave 0.97 and 1.03 unmasked)."""
    g = theory.theory_grid(
        state,
        n_kappa=11,
        kappa_min=0.95,
        kappa_max=1.05,
        separatrix_band=0.04,
        n_max=1,
        l_max=1,
        omega=np.array([0.1]),
        **ACC,
    )
    inside = np.abs(g["kappa"] - 1.0) < 0.04 - 1e-12
    assert inside.sum() == 7  # 0.97 ... 1.03
    np.testing.assert_array_equal(g["masked"], inside)
    for arr in (g["J"], g["Omega"], g["landau"]["D"], g["lenard_balescu"]["Dpol"]):
        assert np.all(np.isnan(arr[inside])) and np.all(np.isfinite(arr[~inside]))


def test_action_and_frequency_against_orbit_quadrature(grid):
    """J is the action (1/2 pi) oint p dtheta of one torus, not J-bar = J/2 (librating kappa here);
    Omega = dh/dJ by a central difference of the quadrature J (step 1e-4: error ~1e-8)."""
    for k, J, Jbar, Om in zip(grid["kappa"], grid["J"], grid["Jbar"], grid["Omega"], strict=True):
        Jq = _action_quadrature(k)
        assert J == pytest.approx(Jq, rel=1e-9)
        assert Jbar == pytest.approx(Jq / 2.0, rel=1e-9)
        d = 1e-4
        dh = M0 * 2.0 * ((k + d) ** 2 - (k - d) ** 2)
        dJ = _action_quadrature(k + d) - _action_quadrature(k - d)
        assert Om == pytest.approx(dh / dJ, rel=1e-6)


def test_thermal_identity_for_each_theory(grid, state):
    """Thermal f: df/dkappa = -beta Omega(kappa*) J'(kappa*) f and n' Omega(kappa*) = n Omega(kappa)
    make every resonance term obey D_pol = -beta Omega(kappa) D_dif, with or without the
    dressing by eps (exact up to rounding)."""
    for name in ("landau", "lenard_balescu"):
        D, P = grid[name]["D"], grid[name]["Dpol"]
        np.testing.assert_allclose(P, -state.beta * grid["Omega"] * D, rtol=1e-10, err_msg=name)


def test_lenard_balescu_dresses_the_11_resonance_by_eps_ss(grid, state):
    """On a librating orbit c_1 = 0, so the (n, n') = (1, 1) librating term is pure sine and its
    Lenard-Balescu value is the Landau one divided by |eps_ss(Omega(kappa))|^2, with eps from
    an independent `DielectricTensor` of the same state and accuracy (|eps_ss|^-2 = 0.011,
    0.020, 0.104 at kappa = 0.3, 0.55, 0.8: strong screening, far from the Landau value 1)."""
    r = np.flatnonzero((grid["resonances"]["n"] == 1) & (grid["resonances"]["nprime"] == 1))
    r = r[grid["resonances"]["branch"][r] == 0][0]
    g_l = grid["landau"]["gamma"][:, r]
    g_lb = grid["lenard_balescu"]["gamma"][:, r]
    _, ess = DielectricTensor(state, l_max=2, **ACC)(grid["Omega"])
    dress = 1.0 / np.abs(ess) ** 2
    assert np.all(dress < 0.5)
    np.testing.assert_allclose(g_lb, g_l * dress, rtol=1e-10)


def test_non_finite_coefficients_raise(state, monkeypatch):
    """A NaN D outside the separatrix band must raise FloatingPointError, not reach a file."""
    real = theory.coefficients_from_table

    def poisoned(*args, **kwargs):
        out = dict(real(*args, **kwargs))
        out["D"] = np.array(out["D"], dtype=float)
        out["D"][0] = np.nan
        return out

    monkeypatch.setattr(theory, "coefficients_from_table", poisoned)
    with pytest.raises(FloatingPointError, match="non-finite D"):
        theory.theory_grid(
            state, n_kappa=2, kappa_min=0.3, kappa_max=0.5, n_max=1, l_max=1, omega=[0.1], **ACC
        )
