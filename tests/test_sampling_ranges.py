"""Guards for the range checks of hmfdiff.dynamics.sampling.sample_uniform_jbar: an empty or
reversed J-bar range is refused instead of silently sampling outside the requested range."""

import numpy as np
import pytest

from hmfdiff.dynamics import sampling


@pytest.mark.parametrize("jbar_range", [(1.0, 0.5), (0.7, 0.7), (-0.1, 0.5), (0.1, np.inf)])
def test_uniform_jbar_refuses_an_empty_reversed_or_unbounded_range(jbar_range):
    """Guards against the check 0 <= Jbar_min < Jbar_max < inf never firing for Jbar_min >=
    Jbar_max (lo + (hi - lo) u then samples [hi, lo], outside what was asked, with no error).
    Reference: the documented contract of the function."""
    with pytest.raises(ValueError, match="jbar_range"):
        sampling.sample_uniform_jbar(0.6, 10, jbar_range, sampling.make_rng(1))


def test_uniform_jbar_stays_inside_a_valid_range():
    """The accepted case: every sampled J-bar lies in [Jbar_min, Jbar_max] (to the rounding of
    the round trip through the phase point, < 1e-9)."""
    from hmfdiff.meanfield import orbits

    M0 = 0.6
    th, p = sampling.sample_uniform_jbar(M0, 500, (0.3, 0.9), sampling.make_rng(2))
    kappa, _, _ = orbits.angle_action(th, p, M0)
    jbar = orbits.rescaled_action(kappa, M0)
    assert jbar.min() > 0.3 - 1e-9 and jbar.max() < 0.9 + 1e-9
