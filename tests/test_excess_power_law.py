"""The finite-N excess fit (`analysis.scaling.excess_power_law`) against synthetic excesses of a
known exponent: the exponent and its error calibrated, the fixed-exponent chi^2 distributed as
chi^2 on points - 1 degrees of freedom, and a wrong exponent rejected when the data can tell."""

import numpy as np
import pytest

from hmfdiff.analysis.scaling import excess_power_law

N = np.array([1e3, 4e3, 1.6e4, 6.4e4, 2.56e5])


def test_noiseless_excess_gives_its_exponent():
    y = 0.3 * (N / 1e4) ** -0.7
    r = excess_power_law(N, y, 0.1 * y, exponents=(0.7, 1.0))
    assert r["a"] == pytest.approx(0.7, abs=1e-8)
    assert r["A"] == pytest.approx(0.3, rel=1e-8)
    assert r["chi2"] < 1e-12
    assert r["fixed"][0.7][0] < 1e-12
    assert r["fixed"][1.0][1] < 1e-6


def test_exponent_error_and_fixed_chi2_are_calibrated():
    rng = np.random.default_rng(2026)
    true = 0.5 * (N / 1e4) ** -0.5
    err = 0.15 * true + 0.01
    pulls, c2_true, p_true, p_one = [], [], [], []
    for _ in range(400):
        y = true + err * rng.standard_normal(N.size)
        r = excess_power_law(N, y, err)
        pulls.append((r["a"] - 0.5) / r["a_err"])
        c2_true.append(r["fixed"][0.5][0])
        p_true.append(r["fixed"][0.5][1])
        p_one.append(r["fixed"][1.0][1])
    pulls = np.array(pulls)
    assert abs(np.mean(pulls)) < 0.2
    assert 0.85 < np.std(pulls) < 1.2
    # chi^2 at the true exponent, A refitted: 4 degrees of freedom (standard error 0.14 here)
    assert abs(np.mean(c2_true) - (N.size - 1)) < 0.5
    # the true exponent is rejected at 5 % about 5 % of the time, N^-1 nearly always
    assert 0.02 < np.mean(np.array(p_true) < 0.05) < 0.09
    assert np.mean(np.array(p_one) < 0.05) > 0.9


@pytest.mark.parametrize(
    "args",
    [
        (N[:2], [0.1, 0.2], [0.01, 0.01]),
        (N, [0.1] * 5, [0.01, 0.01, 0.0, 0.01, 0.01]),
        (N, [0.1, np.nan, 0.1, 0.1, 0.1], [0.01] * 5),
    ],
)
def test_bad_input_is_refused(args):
    with pytest.raises(ValueError, match="excess_power_law"):
        excess_power_law(*args)
