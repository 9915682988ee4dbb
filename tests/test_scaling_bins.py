"""Guards for hmfdiff.analysis.scaling: the bins drawn in the 1/N figure and the pairing of
each MD dynamics with its own and the other kinetic theory."""

import numpy as np

from hmfdiff.analysis import scaling
from hmfdiff.analysis.fits import THEORY_OF


def test_drawn_bins_spread_over_the_valid_bins_from_first_to_last():
    """Guards against an off-by-one in the spread (e.g. linspace to size - 2: the last valid
    bin never drawn).  Valid bins 1, 2, 3, 5, 6, 7, 8, 9 of ten; four spread evenly over the
    eight valid ones are positions 0, 7/3, 14/3, 7 -> 0, 2, 5, 7 (by hand), i.e. bins
    1, 3, 7, 9: both ends included, every one valid."""
    kappa0 = np.linspace(0.1, 1.9, 10)
    valid = np.array([0, 1, 1, 1, 0, 1, 1, 1, 1, 1], dtype=bool)
    assert scaling.drawn_bins(kappa0, valid, n=4) == [1, 3, 7, 9]
    # fewer valid bins than asked: all of them
    assert scaling.drawn_bins(kappa0, np.eye(10, dtype=bool)[2] | np.eye(10, dtype=bool)[6]) == [
        2,
        6,
    ]
    assert scaling.drawn_bins(kappa0, np.zeros(10, dtype=bool)) == []


def test_drawn_bins_nearest_each_target_in_increasing_kappa():
    """Targets pick the bin whose centre is nearest (0.52 -> 0.5, 1.28 -> 1.3; by hand),
    returned in increasing kappa0 whatever the order of the targets or of the bins."""
    kappa0 = np.array([1.5, 0.1, 1.3, 0.5, 0.9])
    assert scaling.drawn_bins(kappa0, np.ones(5, bool), targets=[1.28, 0.52]) == [3, 2]


def test_other_theory_is_the_other_kinetic_equation():
    """Guards against the comparison curve being the dynamics' own theory (or the two swapped):
    MD(bath) is bare (Landau) and is compared with the dressed Lenard-Balescu curve; MD(full)
    is dressed and is compared with Landau (the physics of the paper, not read from the
    module)."""
    assert THEORY_OF == {"bath": "landau", "full": "lenard_balescu"}
    assert scaling.OTHER_THEORY == {"bath": "lenard_balescu", "full": "landau"}
