"""`kinetic.resonances.resonant_kappas` returns NaN where n Omega(kappa) = n' Omega(kappa*) has
no root: n n' <= 0 by its docstring, including n' = 0 (no finite kappa* can absorb a bath
harmonic n' = 0 since the equation reads n Omega(kappa) = 0, false for Omega > 0).

Bug guarded against: the sign test n n' > 0 relaxed to n n' >= 0, which lets n' = 0 through
(the division guard then uses n' = 1) and returns spurious finite roots of Omega(kappa*) =
n Omega(kappa).
"""

from __future__ import annotations

import numpy as np

from hmfdiff.kinetic.resonances import resonant_kappas


def test_zero_harmonic_has_no_resonance():
    k = np.array([0.2, 0.7, 1.3, 2.0])
    for n, npr in ((1, 0), (3, 0), (0, 1), (0, 0), (-1, 0)):
        assert np.all(np.isnan(resonant_kappas(k, n, npr, 0.5))), (n, npr)
    # and the guard does not remove genuine roots (n = n' gives kappa* = kappa on its branch)
    ks = resonant_kappas(k, 2, 2, 0.5)
    np.testing.assert_allclose(ks[:2, 0], k[:2], rtol=1e-10)
    np.testing.assert_allclose(ks[2:, 1], k[2:], rtol=1e-10)
