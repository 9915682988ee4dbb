"""Closed forms of `kinetic.analytic` in limits with an independent reference.

* Appendix C with orbit='expanded' and no collective effects: with sigma_1 = kappa,
  c_2 = kappa^2/2, J' = 4 sqrt(M0) kappa, |Omega'| = sqrt(M0) kappa/2 the n = 1 (sine) and
  n = 2 (cosine) terms give N D = 32 pi^2 kappa^4 f (1 + R), R = 2 c_2^4/sigma_1^4.  The
  leading term is `landau_D_small_kappa` (eq. coeff-analytic-ncoll-exp); R is checked against
  the exact Fourier coefficients of `meanfield.fourier` at small kappa, where
  2 (c_2/sigma_1)^4 -> kappa^4/8 (exact/leading - 1 measured: 3.1e-3 at kappa = 0.05, 1.3e-2
  at 0.1; tolerance 3 %).  Guards c_2 = kappa^2/4 (R = kappa^4/128) in the expanded orbit.
* The two-step forms divide by Omega(kappa_i): a step on the separatrix (Omega = 0) must be
  refused, not turned into numbers.  Guards a range check that never fires.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from hmfdiff.kinetic import analytic
from hmfdiff.meanfield.equilibrium import ThermalState
from hmfdiff.meanfield.fourier import cos_coefficient, sin_coefficient_imag

M0 = 0.9


@pytest.mark.parametrize("kappa", [0.05, 0.1])
def test_expanded_appendix_c_landau_terms(kappa):
    st = ThermalState(M0=M0)
    D = float(analytic.mb_D_appendix_c(kappa, M0, orbit="expanded", collective=False))
    lead = float(analytic.landau_D_small_kappa(kappa, st))
    assert lead == pytest.approx(32 * np.pi**2 * kappa**4 * float(st.f(kappa)), rel=1e-12)
    R = D / lead - 1.0
    R_exact = 2.0 * (float(cos_coefficient(2, kappa)) / float(sin_coefficient_imag(1, kappa))) ** 4
    assert R == pytest.approx(R_exact, rel=3e-2)


def test_two_step_refuses_a_step_on_the_separatrix():
    st = SimpleNamespace(
        shape="step", M0=0.6, step_kappas=[0.5, 1.0], step_weights=[0.3, 0.1], f=lambda k: 0 * k
    )
    with pytest.raises(ValueError, match="separatrix"):
        analytic.two_step_dielectric(np.array([0.1, 0.5]), st)
    with pytest.raises(ValueError, match="separatrix"):
        analytic.two_step_D(np.array([0.3]), st)
