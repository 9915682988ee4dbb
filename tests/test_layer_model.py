"""The finite-N layer model of `studies/separatrix_layer.py finite_n`: the kinetic equation on
the reproduction's grid with the innermost cells spanning the N-body's layer |kappa - 1| <
delta(N) (layer_eta_min = delta; docs/reference/separatrix_crossings.txt: delta = 0.2727
N^-0.490, 9.24e-3 at N = 1e3, 2.38e-3 at 1.6e4).  What the issue asks of any layer model: mass
and energy kept, the thermal state of the same energy a fixed point to 1e-10, and no bias of M0
(the lumped pair of the earlier grid biased it by 1.4e-4 to 8e-3)."""

from __future__ import annotations

import numpy as np
import pytest

from hmfdiff.kinetic.grid import grid_energy, grid_mass, project_state
from hmfdiff.kinetic.relaxation import Kinetics, RelaxationSettings, evolve, make_grid
from hmfdiff.meanfield.equilibrium import ThermalState, make_state

HOT = dict(kind="core_halo", eta1=0.3, eta2=0.01, mu1=-0.5, mu2=1.2, beta1=40.0, beta2=2.0)
#: the layer at N = 1e3 and 1.6e4
DELTAS = (9.24e-3, 2.38e-3)


@pytest.fixture(scope="module")
def hot():
    return make_state(HOT)


@pytest.mark.parametrize("delta", DELTAS)
def test_layer_cells_span_the_layer(hot, delta):
    grid = make_grid(hot, RelaxationSettings(equation="landau", kappa_max=3.5, layer_eta_min=delta))
    s = grid.sep
    assert grid.eta[s - 1] == pytest.approx(-delta) and grid.eta[s] == pytest.approx(delta)
    # one cell a side, from the separatrix to just beyond the layer
    assert grid.eta_edges[s] == 0.0
    assert delta < -grid.eta_edges[s - 1] < 1.1 * delta
    assert delta < grid.eta_edges[s + 1] < 1.1 * delta


@pytest.mark.parametrize("delta", DELTAS)
def test_no_bias_of_M0_or_of_the_energy(hot, delta):
    """The state projected on the layer model's grid keeps its self-consistent M0 and its energy
    per particle (measured: M0 - M0_state = -4.5e-7 and +1.4e-7, u - u_state = 6.3e-7 and
    -2.0e-7, as on the resolved grid, +1.6e-7 and -2.2e-7)."""
    grid = make_grid(hot, RelaxationSettings(equation="landau", kappa_max=3.5, layer_eta_min=delta))
    f, M = project_state(hot, grid)
    assert grid_mass(grid, f, M) == pytest.approx(1.0, abs=1e-14)
    assert abs(M - hot.M0) < 1e-6
    assert abs(grid_energy(grid, f, M) - hot.u) < 1e-6


@pytest.mark.parametrize("equation", ["landau", "lenard_balescu"])
def test_operator_keeps_mass_and_energy_on_the_layer_grid(hot, equation):
    s = RelaxationSettings(
        equation=equation, n_nodes=120, kappa_max=3.5, n_max=4, l_max=4, layer_eta_min=DELTAS[0]
    )
    grid = make_grid(hot, s)
    f, M = project_state(hot, grid)
    op = Kinetics(grid, s).operator(f, M)
    r = op.rate(np.log(f))
    assert abs(r.sum()) < 1e-13 * np.max(np.abs(r))
    assert abs(np.dot(r, grid.eps_hat)) < 1e-12 * np.max(np.abs(r))
    assert op.entropy_production(np.log(f)) > 0


def test_thermal_state_is_a_fixed_point_of_the_layer_model():
    s = RelaxationSettings(
        equation="landau",
        n_nodes=80,
        kappa_max=3.5,
        dlog_omega=0.05,
        layer_eta_min=DELTAS[0],
        tau_max=100.0,
        thermal_tol=0.0,
        dtau_first=1.0,
        flux_times=(0.0,),
    )
    out = evolve(ThermalState(u=-0.1), s)
    assert out["n_steps"] >= 3 and out["tau"][-1] == pytest.approx(100.0)
    assert np.max(np.abs(out["f"] / out["f"][0] - 1.0)) < 1e-10
    assert np.max(np.abs(out["M0"] - out["M0"][0])) < 1e-12
    assert np.max(np.abs(out["u"] - out["u"][0])) < 1e-13
