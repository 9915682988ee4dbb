"""Convergence of the collisional relaxation near the separatrix (issue 20, parts 1c and 2).

The initial rate of the magnetisation, dM0/dtau = N / (1 - dF/dM0), with (f fixed in J-bar,
M0 = F = int 4 pi f <cos theta> dJ-bar, <cos theta> = c0)

    N = 4 pi int G-bar dc0/dJ-bar dJ-bar          (the current times d<cos theta>/dJ-bar),
    dF/dM0 = (1 / 2 M0) int 4 pi c0 d(J-bar f)/dJ-bar dJ-bar

(J-bar = sqrt(M0) j(kappa): at fixed J-bar, d/dM0 = -(J-bar / 2 M0) d/dJ-bar, then by parts).
Both integrals are done here by scipy quad in kappa, with the substitution s = ln|kappa - 1|
within 0.1 of the separatrix where c0 -> -1 and dJ-bar/dkappa -> infinity logarithmically;
they are compared with what the grid (`action_grid`, `solve_grid_M0`) and the discrete
operator (`collision`) give.
"""

import numpy as np
import pytest
from scipy import integrate

from hmfdiff.kinetic.grid import project_state, solve_grid_M0
from hmfdiff.kinetic.relaxation import Kinetics, RelaxationSettings, make_grid
from hmfdiff.meanfield import orbits, separatrix
from hmfdiff.meanfield.equilibrium import make_state
from hmfdiff.meanfield.fourier import cos_coefficient

CH2 = dict(kind="core_halo", eta1=0.298, eta2=0.051, mu1=-0.517, mu2=0.19, beta1=30.0, beta2=10.0)
HOT = dict(kind="core_halo", eta1=0.3, eta2=0.01, mu1=-0.5, mu2=1.2, beta1=40.0, beta2=2.0)
KAPPA_MAX = {"ch2": 2.5, "hot": 3.5}


@pytest.fixture(scope="module")
def states():
    return {"ch2": make_state(CH2), "hot": make_state(HOT)}


def _kappa_integral(g, kmax, split=0.1):
    """int_0^kmax g(kappa) dkappa; s = ln|kappa - 1| within `split` of the separatrix."""
    quad = lambda fun, a, b: integrate.quad(fun, a, b, limit=200, epsabs=0.0, epsrel=1e-10)[0]  # noqa: E731
    total = quad(g, 0.0, 1.0 - split) + quad(g, 1.0 + split, kmax)
    for side in (-1.0, 1.0):
        total += quad(lambda s, c=side: g(1.0 + c * np.exp(s)) * np.exp(s), -34.5, np.log(split))
    return total


def _djbar_dkappa(kappa, M0):
    return orbits.dJ_dkappa(kappa, M0) * np.where(kappa < 1.0, 0.5, 1.0)


def _grid(state, case, n_nodes, equation="landau"):
    s = RelaxationSettings(
        equation=equation, n_nodes=n_nodes, kappa_max=KAPPA_MAX[case], dlog_omega=0.04
    )
    grid = make_grid(state, s)
    f, M0 = project_state(state, grid)
    return s, grid, f, M0


def _continuum_M0_response(state, kmax):
    """dM0/d epsilon of f -> f (1 + epsilon J-bar/J-bar_s) (normalised), f fixed in J-bar:
    int 4 pi f g (c0 - M0) dJ-bar / (1 - dF/dM0)."""
    M0 = state.M0
    js = orbits.jbar_separatrix(M0)

    def g(k):
        return orbits.rescaled_action(k, M0) / js

    num = _kappa_integral(
        lambda k: (
            4 * np.pi * state.f(k) * g(k) * (cos_coefficient(0, k) - M0) * _djbar_dkappa(k, M0)
        ),
        kmax,
    )
    dF = _kappa_integral(
        lambda k: (
            4
            * np.pi
            * cos_coefficient(0, k)
            * (
                _djbar_dkappa(k, M0) * state.f(k)
                + orbits.rescaled_action(k, M0) * state.dfdkappa(k)
            )
        ),
        kmax,
    ) / (2.0 * M0)
    return num / (1.0 - dF), dF


def _grid_M0_response(grid, f, M0, eps=1e-3):
    g = grid.jbar(M0) / orbits.jbar_separatrix(M0)
    up = solve_grid_M0(grid, f * (1 + eps * g), M0)
    down = solve_grid_M0(grid, f * (1 - eps * g), M0)
    return (up - down) / (2 * eps)


@pytest.mark.parametrize("case", ["ch2", "hot"])
def test_self_consistent_M0_response_matches_quadrature(states, case):
    """The grid's M0 (`solve_grid_M0`) responds to a change of f at fixed f(J-bar) as the
    continuum does: this needs 1 - dF/dM0, whose integrand has the 1/(|kappa - 1| ln^3) dip of
    c0 at the separatrix; with a node within ~1e-9 of the separatrix (before the separatrix was
    made a face of the grid) the node quadrature of dF/dM0 scattered between 0.05 and 0.11 for
    the hot halo (quadrature: 0.0952) from one n_nodes to the next."""
    state = states[case]
    ref, dF = _continuum_M0_response(state, 6.0)
    # the two routes to dF/dM0 agree (F(M0 +- 1e-5) at fixed f(J-bar) by quad: 0.1273562 and
    # 0.0951701, measured once): the quadrature resolves the separatrix
    assert dF == pytest.approx({"ch2": 0.1273562, "hot": 0.0951701}[case], abs=1e-6)
    for n in (150, 300):
        _, grid, f, M0 = _grid(state, case, n)
        # measured |relative error| at 150/300/600/1200 nodes: ch2 3.1e-4, 7.3e-5, 1.6e-5,
        # 2.7e-6 (second order); hot 5.9e-4, 5.6e-4, 3.3e-4, 2.4e-4 (the f of the hot halo is
        # large at the separatrix: the log dip of c0 in the two cells that touch it)
        assert _grid_M0_response(grid, f, M0) == pytest.approx(ref, rel=2e-3)


# The current moment 4 pi int G-bar dphi/dJ-bar dJ-bar = sum_a (4 pi G-bar_a) (phi_{a+1} - phi_a)
# (= sum_i phi_i dm_i/dtau) for phi = max(c0, c0(1 + delta)): the numerator N of dM0/dtau with
# the logarithmic region |kappa - 1| < delta cut out.  References: the Fokker-Planck current of
# the analytic hot halo (`flux.fokker_planck_current`, the diffusion coefficients, not the
# discrete operator) integrated against dc0/dkappa (central differences) by composite
# Gauss-Legendre, 8 points on 150 (300) panels graded geometrically towards the cut:
# `python benchmarks/bench_relaxation.py --study separatrix`; 150 and 300 panels agree to
# 4e-5 (Lenard-Balescu) and 1e-8 (Landau) relative, scipy quad to 1e-5 (Landau, delta = 1e-3).
# Inside |kappa - 1| < 1e-3 the continuum integrand does not converge (see the benchmark): the
# full N is not tested here.
CLIPPED_MOMENT = {("lenard_balescu", 1e-3): 1.13163e-3, ("landau", 3e-2): -9.98324e-3}


@pytest.mark.parametrize("equation, delta", sorted(CLIPPED_MOMENT))
def test_current_moment_of_clipped_cos_matches_fokker_planck_quadrature(states, equation, delta):
    """The discrete current at tau = 0 (orbits, resonances, 16 pi^3, dressing) weighted by
    d<cos theta>/dJ-bar outside the separatrix band, against the continuum.  Measured relative
    errors of the grid at 150/300/600/900/1200 nodes: Lenard-Balescu (delta = 1e-3) +1.8 %,
    +0.8 %, +0.2 % (150-600); Landau (delta = 0.03) -0.3 %, -0.07 %, +0.3 %, +0.08 %, +0.05 %
    (the Landau moment with delta = 1e-3 has a -5.5 % outlier at 600 nodes: the current of
    the faces near kappa = 1.001 is spiky, so delta = 0.03 is tested).  Dropping the dressing
    changes the Lenard-Balescu moment 30-fold; 4 pi or 2 slips fail the tolerance."""
    state = states["hot"]
    s, grid, f, M0 = _grid(state, "hot", 300, equation)
    phi = np.maximum(
        separatrix.cos_average_plus_one(grid.eta) - 1.0, cos_coefficient(0, 1.0 + delta)
    )
    flux = Kinetics(grid, s).operator(f, M0).face_flux(np.log(f))  # 4 pi G-bar
    moment = float(np.dot(flux, np.diff(phi)))
    assert moment == pytest.approx(CLIPPED_MOMENT[equation, delta], rel=0.02)
