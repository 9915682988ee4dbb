"""docs/reference/finite_n_exponents.txt is what studies/finite_n_exponents.py prints from the
reference files beside it: a rebuilt relaxation summary or spectrum table that is copied in
without rerunning the study makes this fail (the exponents the docs quote would be stale)."""

import contextlib
import io
from pathlib import Path

from _studies import load_study

ROOT = Path(__file__).resolve().parents[1]


def test_exponents_file_is_the_study_output_of_the_reference_files():
    study = load_study("finite_n_exponents")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        study.main([])
    stored = (ROOT / "docs" / "reference" / "finite_n_exponents.txt").read_text()
    body = [line for line in stored.splitlines() if not line.startswith("# ")]
    printed = [line for line in out.getvalue().splitlines() if not line.startswith("# ")]
    assert printed == body
