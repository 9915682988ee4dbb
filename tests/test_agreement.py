"""The validation summary (analysis.agreement) on rows of known statistics: the bin selection,
the median and mean ratio, the fraction within |z| < 2 and the mean z^2 against their expected
values, the |z| > 3 bins named, and the CSV round trip."""

import re

import numpy as np
import pytest

from hmfdiff.analysis.agreement import (
    agreement,
    beside_separatrix,
    markdown_table,
    read_rows,
    readme_block,
    summary_text,
)
from hmfdiff.analysis.fits import write_validation_csv


def _row(case, dyn, ratio, z, flag=0, n_seeds=20, kappa0=0.5, **kw):
    return dict(
        case=case,
        dynamics=dyn,
        M0=0.7,
        J0=0.3,
        kappa0=kappa0,
        n_particles_in_bin=1000,
        ND_md=ratio,
        ND_md_err=kw.get("ND_md_err", 0.1),
        ND_theory=kw.get("ND_theory", 1.0),
        ND_windowed=kw.get("ND_windowed", 1.0),
        ratio=ratio,
        z=z,
        flag=flag,
        ratio_windowed=kw.get("ratio_windowed", ratio),
        z_windowed=kw.get("z_windowed", z),
        n_seeds=n_seeds,
    )


def test_statistics_of_hand_made_rows():
    rows = [
        _row("a", "bath", 1.1, 1.0),
        _row("a", "bath", 0.9, -3.5, kappa0=0.25),
        _row("a", "bath", 1.3, 0.5),
        _row("a", "bath", 9.0, 50.0, flag=1),  # too few particles: left out
        _row("a", "bath", 1.2, np.nan, flag=5),  # no error: left out
        _row("b", "full", 1.0, 0.0),
    ]
    per = {(e["case"], e["dynamics"]): e for e in agreement(rows)}
    a = per["a", "bath"]
    assert a["bins"] == 3
    assert a["median_dev"] == pytest.approx(0.1)
    assert a["mean_ratio"] == pytest.approx(1.1)
    assert a["mean_ratio_err"] == pytest.approx(np.std([1.1, 0.9, 1.3], ddof=1) / np.sqrt(3))
    assert a["frac_z2"] == pytest.approx(2 / 3)
    assert a["mean_z2"] == pytest.approx((1.0 + 3.5**2 + 0.25) / 3)
    assert a["mean_z2_expected"] == pytest.approx(19 / 17)  # nu/(nu - 2), nu = 19
    assert [r["kappa0"] for r in a["outliers"]] == [0.25]
    pooled = per["all", "all"]
    assert pooled["bins"] == 4 and pooled["mean_ratio"] == pytest.approx(1.075)
    text = summary_text(rows)
    assert "a bath kappa0 = 0.250 (ratio 0.900, z = -3.5)" in text
    assert "flag 0" in text and "separatrix_band_fit" in text
    assert "pooled, all lines: 4" in text


def test_expected_values_match_student_t_samples():
    """Rows whose z are Student-t samples (numpy's generator, independent of scipy's cdf) must
    read their own expected fraction within |z| < 2 and mean z^2."""
    rng = np.random.default_rng(7)
    nu = 9
    z = rng.standard_t(nu, 40000)
    rows = [_row("c", "full", 1.0, float(v), n_seeds=nu + 1) for v in z]
    e = agreement(rows)[0]
    assert e["frac_z2_expected"] == pytest.approx(np.mean(np.abs(z) < 2), abs=0.005)
    assert e["mean_z2_expected"] == pytest.approx(nu / (nu - 2))
    assert e["mean_z2"] == pytest.approx(e["mean_z2_expected"], rel=0.05)
    # errors claimed twice too small (z twice too large) are seen in both statistics
    wide = agreement([_row("c", "full", 1.0, 2 * float(v), n_seeds=nu + 1) for v in z])[0]
    assert wide["frac_z2"] < wide["frac_z2_expected"] - 0.2
    assert wide["mean_z2"] > 3 * wide["mean_z2_expected"]


def test_expected_median_is_the_noise_floor():
    """The median of |ratio - 1| expected from the errors alone: 0.6745 sigma for Gaussian
    errors (many seeds), sigma for Cauchy (two seeds: median |t_1| = 1); for a mixture of
    errors it is the sample median of numpy's t draws (independent of scipy's cdf); the
    windowed comparison divides the error by its own theory."""
    many = agreement([_row("a", "bath", 1.0, 0.0, n_seeds=10**6, ND_md_err=0.1)])[0]
    assert many["median_dev_expected"] == pytest.approx(0.1 * 0.6744897502, rel=1e-5)
    two = agreement([_row("a", "bath", 1.0, 0.0, n_seeds=2, ND_md_err=0.05)])[0]
    assert two["median_dev_expected"] == pytest.approx(0.05, rel=1e-9)
    rng = np.random.default_rng(11)
    sig = rng.uniform(0.02, 0.12, 400)
    rows = [_row("a", "full", 1.0, 0.0, n_seeds=20, ND_md_err=s) for s in sig]
    draws = np.median(np.abs(rng.standard_t(19, (4000, sig.size)) * sig), axis=1)
    assert agreement(rows)[0]["median_dev_expected"] == pytest.approx(np.mean(draws), rel=0.01)
    # relative errors: 0.05 / 2 against the asymptotic theory, 0.05 / 0.5 against the windowed
    row = _row("a", "bath", 1.0, 0.0, n_seeds=2, ND_md_err=0.05, ND_theory=2.0, ND_windowed=0.5)
    assert agreement([row])[0]["median_dev_expected"] == pytest.approx(0.025, rel=1e-9)
    assert agreement([row], "windowed")[0]["median_dev_expected"] == pytest.approx(0.1, rel=1e-9)


def test_windowed_block_uses_the_windowed_columns():
    rows = [_row("a", "bath", 1.0, 0.0, ratio_windowed=1.5, z_windowed=4.0)]
    e = agreement(rows, "windowed")[0]
    assert e["median_dev"] == pytest.approx(0.5) and len(e["outliers"]) == 1
    assert agreement(rows)[0]["outliers"] == []


def test_propagated_block_uses_its_columns_and_only_where_present(tmp_path):
    """The propagated theory's block reads ratio_propagated / z_propagated / ND_propagated; a
    table written before those columns existed (docs/reference of 2026-11-26 had none) gives
    the other two blocks and no empty third one, in the summary and in the README block."""
    old = [_row("a", "bath", 1.0, 0.0)]
    new = [dict(r, ND_propagated=0.5, ratio_propagated=2.0, z_propagated=-5.0) for r in old]
    e = agreement(new, "propagated")[0]
    assert e["median_dev"] == pytest.approx(1.0) and len(e["outliers"]) == 1
    assert "propagated" not in summary_text(old) and "propagated" not in readme_block(old)
    assert "MD against the propagated theory" in summary_text(new)
    assert "propagated Landau" in summary_text(new)
    assert "propagated (finite-N) theory" in readme_block(new)
    path = tmp_path / "validation.csv"
    write_validation_csv(new, path)
    assert summary_text(read_rows(path)) == summary_text(new)


def test_csv_round_trip_keeps_the_degrees_of_freedom(tmp_path):
    rows = [_row("a", "bath", 1.0 + 0.01 * i, 0.1 * i, n_seeds=40) for i in range(5)]
    path = tmp_path / "validation.csv"
    write_validation_csv(rows, path)
    back = read_rows(path)
    assert [r["n_seeds"] for r in back] == [40] * 5
    assert summary_text(back) == summary_text(rows)
    table = markdown_table(back)
    assert "| a | bath | 5 |" in table and "(1.05)" in table  # E[z^2] = 39/37


def test_bins_beside_the_separatrix_band_are_counted_apart():
    """A line's usable bins next to its separatrix-flagged bins (in bin order) form the group
    'beside separatrix'; the |z| > 3 counts of each group stand against Student t's expectation,
    2 P(|t_nu| > 3) per bin, here from numpy's t samples (not scipy's distribution)."""
    line = [
        _row("a", "full", 1.0, 0.5, kappa0=0.80),
        _row("a", "full", 1.3, 4.0, kappa0=0.94),  # beside the band, an outlier
        _row("a", "full", 1.0, 0.0, flag=2, kappa0=0.98),
        _row("a", "full", 1.0, 0.0, flag=2, kappa0=1.01),
        _row("a", "full", 1.1, 1.0, kappa0=1.04),  # beside the band
        _row("a", "full", 0.7, -3.2, kappa0=1.20),  # an outlier elsewhere
    ]
    # the next line starts with a usable bin: it is not beside line a's flagged bins
    other = [_row("b", "bath", 1.0, 0.2, kappa0=0.2), _row("b", "bath", 1.0, 0.1, kappa0=0.3)]
    rows = line + other
    assert beside_separatrix(rows) == [False, True, True, True, True, False, False, False]
    rows_b_first = other + [_row("b", "bath", 1.0, 0.0, flag=2)] + line
    assert beside_separatrix(rows_b_first)[:4] == [False, True, False, False]
    per = {e["case"]: e for e in agreement(rows) if e["dynamics"] == "all"}
    assert per["beside separatrix"]["bins"] == 2 and per["elsewhere"]["bins"] == 4
    assert [r["kappa0"] for r in per["beside separatrix"]["outliers"]] == [0.94]
    assert [r["kappa0"] for r in per["elsewhere"]["outliers"]] == [1.20]
    assert per["beside separatrix"]["mean_z2"] == pytest.approx((16.0 + 1.0) / 2)
    p3 = np.mean(np.abs(np.random.default_rng(3).standard_t(19, 2_000_000)) > 3.0)
    assert per["elsewhere"]["outliers_expected"] == pytest.approx(4 * p3, rel=0.03)
    assert per["all"]["outliers_expected"] == pytest.approx(6 * p3, rel=0.03)
    text = summary_text(rows)
    assert "a full kappa0 = 0.940 (ratio 1.300, z = +4.0) [beside the separatrix band]" in text
    assert "a full kappa0 = 1.200 (ratio 0.700, z = -3.2)\n" in text + "\n"
    assert "pooled, beside the separatrix band: 2" in text and "pooled, elsewhere: 4" in text
    assert "beside the separatrix band 1 (" in text and "elsewhere 1 (" in text
    block = readme_block(rows)
    assert "| *beside the separatrix band* | all | 2 |" in block
    assert "- a full kappa0 = 0.940 (ratio 1.300, z = +4.0) [beside the separatrix band]" in block


# ---- no statistics where there are none (issue 36) ------------------------------------------
def test_lines_with_fewer_than_four_seeds_print_no_statistics():
    """With n_seeds <= 3 Student t has nu <= 2 and an infinite E[z^2] (the smoke run's MD(full)
    has 2 seeds and printed 'inf'): such a line, and a pooled line holding it, says 'no
    statistics' instead of numbers; a line of 4 seeds keeps them."""
    few = [_row("a", "full", 1.0 + 0.1 * i, 0.5 * i, n_seeds=3) for i in range(4)]
    four = [_row("b", "bath", 1.0 + 0.1 * i, 0.5 * i, n_seeds=4) for i in range(4)]
    text = summary_text(few + four)
    assert not re.search(r"\b(inf|nan)\b", text), text
    lines = {line.split(":")[0]: line for line in text.splitlines() if ":" in line}
    assert lines["a full vs Lenard-Balescu"].endswith(
        ": 4 bins, 3 seeds: no statistics (below 4 seeds Student t's expected z^2 is infinite)"
    )
    assert lines["pooled, all lines"].startswith("pooled, all lines: 8 bins, 3-4 seeds: no stat")
    # nu = 3: median |t_3| = 0.7649 (x sigma 0.1), P(|t_3| < 2) = 0.861, E[t^2] = 3; the rows:
    # |ratio - 1| = 0, 0.1, 0.2, 0.3, z = 0, 0.5, 1, 1.5 (mean z^2 0.875)
    assert lines["b bath vs Landau"] == (
        "b bath vs Landau: 4  0.150 (0.076)  1.150 +- 0.065  1.00 (0.86)  0.88 (3.00)"
    )


def test_toy_size_summary_says_it_has_no_statistics():
    """Where the workflow passes an N below TOY_SIZE (the smoke config: N = 5000, mean ratio
    '113.864 +- 112.739' from one bin of a near-zero theory) the first line says there are no
    statistics and each line gives only bins, seeds and the median |ratio - 1|."""
    rows = [_row("a", "bath", r, z, n_seeds=10) for r, z in ((1.2, 1.0), (478.7, 3.8), (0.9, -1))]
    text = summary_text(rows, sizes={"a": 5000, "b": 500000})
    first, *rest = text.splitlines()
    assert first.startswith("TOY SIZE, NO STATISTICS (a N = 5000: below N = 1e+05")
    assert "b N =" not in first
    assert "a bath vs Landau: 3 bins, 10 seeds, median |ratio - 1| 0.200; no statistics" in text
    for word in ("+-", "expected", "478", "|z| >", "mean"):
        assert word not in "\n".join(rest), word
    # at paper size the same rows give the numbers
    assert summary_text(rows, sizes={"a": 500000}) == summary_text(rows)
    assert "+-" in summary_text(rows)
