"""Guard for hmfdiff.kinetic.stability.winding: the change of argument is followed through
zeros that lie closer to the real axis than the spacing of the frequencies given (the
refinement of `_refined_phase`), not read off the coarse samples alone."""

import numpy as np
import pytest

from hmfdiff.kinetic.stability import winding


def test_double_zero_just_above_the_axis_is_counted_on_a_coarse_grid():
    """Guards against the refinement never firing (phase unwrapped on the given samples only).
    g(w) = [(w - z)(w + conj z) / (w + i)^2]^2 with z = 1 + 0.005 i is analytic in the upper
    half plane, g(-conj w) = conj g(w), g -> 1, and has four zeros there (z and -conj z, each
    double): the argument principle gives winding 4.  Between the samples w = 1 -+ 0.025 the
    argument of (w - z)^2 turns by 2 pi - 4 atan(0.005/0.025) = 2 pi - 0.79 (by hand), which
    the samples alone read as -0.79: unwrapping them without refinement gives winding 2
    (measured 2.00), bisecting the gaps where the argument jumps by more than 0.5 gives 4
    (measured 4.00)."""
    z = 1.0 + 0.005j
    # spacing 0.05 from 0.025 on, so that w = 1 lies mid-gap; 1e-6 ... 400 so that the ends add
    # < 0.01 to the winding
    omega = np.concatenate([np.geomspace(1e-6, 0.02, 40), np.linspace(0.025, 400.025, 8001)])

    def g(w):
        return ((w - z) * (w + np.conj(z)) / (w + 1j) ** 2) ** 2

    assert winding(g, omega) == pytest.approx(4.0, abs=0.1)
