"""studies/validation_runs.py: two validation tables compared line by line, on tables whose
answers are known by construction (B's errors 1.1 times A's, B's values half of A's error
above A's), and the bins it must leave out (flagged in either run)."""

import csv
import re
from pathlib import Path

import numpy as np
from _studies import load_study

COLUMNS = ["case", "dynamics", "kappa0", "flag", "ND_md", "ND_md_err", "ND_propagated",
           "ratio_propagated", "z_propagated", "n_seeds"]  # fmt: skip


def _table(path, nd, err, theory, flags):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(COLUMNS)
        for i, (v, e, t, f) in enumerate(zip(nd, err, theory, flags, strict=True)):
            w.writerow(["thermal_u0.0", "full", 0.1 * (i + 1), f, v, e, t, v / t, (v - t) / e, 20])


def test_errors_and_paired_changes_of_two_runs(tmp_path):
    rng = np.random.default_rng(1)
    n = 12
    theory = rng.uniform(0.5, 2.0, n)
    err_a = 0.04 * theory
    nd_a = theory + err_a * rng.standard_normal(n)
    flags_a = [0] * n
    flags_b = [0] * n
    flags_b[3] = 2  # a bin the second run flags: left out of both
    nd_b = nd_a + 0.5 * err_a
    nd_b[3] = 100.0  # would wreck every statistic if it were used
    _table(tmp_path / "a.csv", nd_a, err_a, theory, flags_a)
    _table(tmp_path / "b.csv", nd_b, 1.1 * err_a, theory, flags_b)
    load_study("validation_runs").main(tmp_path / "a.csv", tmp_path / "b.csv", tmp_path / "out")
    text = (tmp_path / "out").read_text()
    line = next(s for s in text.splitlines() if s.startswith("thermal_u0.0 full:"))
    assert line.startswith(f"thermal_u0.0 full: {n - 1} bins;")
    assert "error B / error A median 1.100, range 1.100-1.100" in line
    assert "(B - A) / error A mean +0.50, rms 0.50" in line
    keep = np.arange(n) != 3
    med = lambda nd: np.median(np.abs(nd[keep] / theory[keep] - 1))  # noqa: E731
    got = [float(x) for x in re.findall(r"median \|ratio - 1\| [AB] ([\d.]+)", line)]
    assert got == [round(med(nd_a), 3), round(med(nd_b), 3)]


def test_reference_file_is_the_output_on_the_reference_tables(tmp_path):
    """docs/reference/validation_runs.txt, which the docs quote, is what the study gives on the
    two reference tables it names (a stale copy fails)."""
    root = Path(__file__).resolve().parents[1] / "docs" / "reference"
    load_study("validation_runs").main(
        root / "validation_ddf04b7.csv", root / "validation_2d87738.csv", tmp_path / "out"
    )
    body = [s for s in (tmp_path / "out").read_text().splitlines() if not s.startswith("#")]
    kept = (root / "validation_runs.txt").read_text().splitlines()
    assert body == [s for s in kept if not s.startswith("#")]
