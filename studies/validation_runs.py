"""Two full reproductions' MD-against-theory tables, line by line: did a change of the MD's
settings or code change its precision, or only its realisations?

    python studies/validation_runs.py A.csv B.csv [OUT]

A and B are `results/validation.csv` of two runs of the same config's cases and seeds (for
example docs/reference/validation_ddf04b7.csv and docs/reference/validation.csv).  Over the
bins both runs use (flag 0), per line (case, dynamics): the ratio of B's error of N D_MD to
A's (median, range; the precision), the paired difference (N D_B - N D_A) / error_A (mean and
rms: near zero where B repeats A's trajectories, of order sqrt(2) where the chaotic dynamics
made other realisations of the same ensemble), and each run's median |ratio - 1| against the
propagated theory with the median its errors alone would give (the statistical floor; both
from `hmfdiff.analysis.agreement`).  Then the same over all lines.
"""

from __future__ import annotations

import sys

import numpy as np
from _realisations import emit

from hmfdiff.analysis.agreement import agreement, read_rows


def _usable(rows):
    return {(r["case"], r["dynamics"], round(r["kappa0"], 6)): r for r in rows if r["flag"] == 0}


def _line(label, pairs):
    ea = np.array([a["ND_md_err"] for a, _ in pairs])
    eb = np.array([b["ND_md_err"] for _, b in pairs])
    dz = np.array([(b["ND_md"] - a["ND_md"]) / a["ND_md_err"] for a, b in pairs])
    ratio = eb / ea
    pooled = [
        next(e for e in agreement(list(run), "propagated") if e["case"] == "all")
        for run in zip(*pairs, strict=True)
    ]
    meds = "; ".join(
        f"median |ratio - 1| {name} {e['median_dev']:.3f} ({e['median_dev_expected']:.3f})"
        for name, e in zip("AB", pooled, strict=True)
    )
    return (
        f"{label}: {len(pairs)} bins; error B / error A median {np.median(ratio):.3f}, range "
        f"{ratio.min():.3f}-{ratio.max():.3f}; (B - A) / error A mean {dz.mean():+.2f}, rms "
        f"{np.sqrt((dz**2).mean()):.2f}; {meds}"
    )


def main(a_path, b_path, out=None):
    a, b = _usable(read_rows(a_path)), _usable(read_rows(b_path))
    both = sorted(set(a) & set(b))
    if not both:
        sys.exit(f"{a_path} and {b_path} share no usable bin")
    lines = [
        "# Two runs' MD-against-theory tables, bin by bin (studies/validation_runs.py)",
        f"# A: {a_path}; B: {b_path}; bins with flag 0 in both; medians against the propagated",
        "# theory, in brackets the median the MD's errors alone give",
    ]
    for line in sorted({k[:2] for k in both}):
        pairs = [(a[k], b[k]) for k in both if k[:2] == line]
        lines.append(_line(f"{line[0]} {line[1]}", pairs))
    lines.append(_line("all lines", [(a[k], b[k]) for k in both]))
    emit(lines, out)


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    main(*sys.argv[1:])
