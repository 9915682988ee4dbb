"""The numbers docs/errata.md quotes, recomputed from the library: each quote is formatted here
from a direct computation and must stand on the page as written (tests/test_readme_numbers.py
counts these quotes as covering their numbers)."""

from __future__ import annotations

import numpy as np
import pytest
from _smoke import ROOT
from scipy import special

from hmfdiff.kinetic import analytic as A
from hmfdiff.meanfield import orbits
from hmfdiff.meanfield.equilibrium import CoreHaloState, ThermalState

ERRATA = "docs/errata.md"
#: the ellipkinc defect: an angle at which scipy 1.17.1 returns K(m), and its parameter
PHI, M = 1.2031855608267839, 0.25

#: (page, quote) of every number recomputed below
ERRATA_QUOTES = [
    (ERRATA, "normalised to 1 to within 1e-14"),
    (ERRATA, 'M0 = 0.7995 and a raw mass of 1.0011 (the paper\'s "M0 = 0.8")'),
    (ERRATA, "it is 1.1 % low at kappa = 0.5 and 34 % low at 0.9"),
    (ERRATA, "(scipy 1.17.1, the pinned version)"),
    (ERRATA, "e.g. phi = 1.2031855608267839, m = 0.25"),
    (ERRATA, "Phys. Rev. E 95, 022111, 2017"),
    (ERRATA, "(kappa^2 - 1) must read (1 - kappa^2)"),
    (ERRATA, "2E/K - 1 (libration), 1 - 2 kappa^2 (1 - E/K) (rotation)"),
    (ERRATA, '"p > 1", "p < 1"'),
    (ERRATA, "p > 0, p < 0"),
    (ERRATA, "sqrt(mu_i/M0 + 1) lacks a factor 1/2"),
    (ERRATA, "sqrt((mu_i/M0 + 1)/2)"),
    (ERRATA, "Theta(omega - 3 sqrt(M0)/2) Theta(2 sqrt(M0) - omega)"),
    (ERRATA, "Theta(omega - 3 sqrt(M0)/4) Theta(sqrt(M0) - omega)"),
    (ERRATA, "16 pi C sinh(beta M0)/sqrt(M0)"),
    (ERRATA, "a factor 2 on the kappa > 1"),
]


def _page():
    return " ".join((ROOT / ERRATA).read_text().split())


@pytest.mark.parametrize("quote", [q for _, q in ERRATA_QUOTES])
def test_quote_is_on_the_page(quote):
    assert quote in _page()


def test_thermal_normalisation_counting_both_rotations():
    state = ThermalState(M0=0.72846)
    q = state.quadrature()
    assert abs(q.integrate(state.f(q.kappa)) - 1.0) < 1e-14


def test_ch2_magnetisation_and_raw_mass():
    ch2 = CoreHaloState(0.298, 0.051, -0.517, 0.19, 30.0, 10.0)
    assert f"{ch2.M0:.4f}" == "0.7995"
    assert f"{ch2.mass:.4f}" == "1.0011"


def test_sech4_deficit_against_the_n2_sum():
    """The same for every f (the ratio is 1/(1 + 2 c_2^4/sigma_1^4)): two states agree."""
    for state in (ThermalState(M0=0.72846), ThermalState(M0=0.9)):
        low = [
            1.0 - A.landau_D_sech4(k, state) / A.landau_D_librating_sum(k, state, n_max=2)
            for k in (0.5, 0.9)
        ]
        assert f"{100 * low[0]:.1f}" == "1.1"
        assert f"{100 * low[1]:.0f}" == "34"


def test_scipy_ellipkinc_defect_is_still_there_and_avoided():
    import scipy

    assert scipy.__version__ == "1.17.1"
    wrong = special.ellipkinc(PHI, M)
    assert wrong == pytest.approx(special.ellipk(M), rel=1e-12)  # K(m), not F(phi | m)
    # F(phi | m) < K(m) for phi < pi/2; the library's R_F form gives the quadrature's value
    t = np.linspace(0.0, PHI, 20001)
    direct = np.trapezoid(1.0 / np.sqrt(1.0 - M * np.sin(t) ** 2), t)
    assert orbits._ellipf(PHI, M) == pytest.approx(direct, rel=1e-8)
    assert direct < wrong - 0.1
