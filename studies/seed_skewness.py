"""How often a bin lies beyond |z| = 3 when the per-realisation N D are skewed (issue 23 part 4).

The agreement summary counts bins with |z| > 3 against Student t with n_seeds - 1 degrees of
freedom, which holds for normally distributed per-realisation values.  N D of one realisation
(half the slope of its <dJ^2>(lag) over the fit window) is right-skewed, like a sum of a few
squares: a sample that misses the rare high values has both a low mean and a small standard
error, so low z come more often than Student t says and high z less often.  This takes each
line's per-seed N D (`ND_md_seed` of results/fits/{case}_{dynamics}.nc) over its bins of flag 0,
divides each bin's values by the bin's mean (the shape, free of the bin's level), pools the
shapes of the MD(bath) lines and of the MD(full) lines, and draws samples of n_seeds values
from each pool (with replacement), reporting the tail probabilities of
z = (mean - 1) / (standard error of the mean) and the number of such bins expected among the
summary's bins:

    python studies/seed_skewness.py RESULTS_DIR

The pooled shapes are slightly wider than one bin's (bins differ a little in shape), so the
tails are if anything overstated.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy import stats

from hmfdiff.pipeline.io import read_dataset

CASES = ("thermal_u-0.2", "thermal_u0.0", "thermal_u0.2475", "corehalo_ch2")
DRAWS = 200_000


def pooled_shapes(res, dynamics):
    """(per-seed N D / the bin's mean, pooled over the lines' bins of flag 0; n_seeds; bins)."""
    shapes, n_seeds, n_bins = [], set(), 0
    for case in CASES:
        fit = read_dataset(Path(res) / "fits" / f"{case}_{dynamics}.nc", required=["ND_md_seed"])
        v = fit["ND_md_seed"].values[:, fit["flag"].values == 0]
        shapes.append((v / v.mean(0)).ravel())
        n_seeds.add(fit.sizes["seed"])
        n_bins += v.shape[1]
    if len(n_seeds) != 1:
        sys.exit(f"{dynamics}: lines with different numbers of seeds {sorted(n_seeds)}")
    return np.concatenate(shapes), n_seeds.pop(), n_bins


def main(res):
    rng = np.random.default_rng(2026_11_27)
    expected = {}
    for dyn in ("bath", "full"):
        s, n, n_bins = pooled_shapes(res, dyn)
        draws = rng.choice(s, size=(DRAWS, n))
        z = (draws.mean(1) - 1.0) / (draws.std(1, ddof=1) / np.sqrt(n))
        p_lo, p_hi, p_in = np.mean(z < -3), np.mean(z > 3), np.mean(np.abs(z) < 2)
        t3, t2 = stats.t.sf(3, n - 1), 1 - 2 * stats.t.sf(2, n - 1)
        expected[dyn] = (n_bins * (p_lo + p_hi), n_bins * 2 * t3)
        print(
            f"MD({dyn}): {s.size} per-seed values over {n_bins} bins, {n} seeds per line; "
            f"skewness {stats.skew(s):.2f}, relative std {s.std():.2f}"
        )
        print(
            f"  P(z < -3) {p_lo:.4f}, P(z > 3) {p_hi:.4f} (Student t: {t3:.4f} each); "
            f"P(|z| < 2) {p_in:.3f} (Student t: {t2:.3f}); mean z^2 {np.mean(z**2):.2f}"
        )
        print(
            f"  bins with |z| > 3 expected among {n_bins}: {expected[dyn][0]:.2f} "
            f"(Student t: {expected[dyn][1]:.2f}), of them below: "
            f"{n_bins * p_lo:.2f}"
        )
    e, t = (sum(v[i] for v in expected.values()) for i in (0, 1))
    print(f"all lines: bins with |z| > 3 expected {e:.2f} (Student t: {t:.2f})")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__.split("\n\n")[2])
    main(sys.argv[1])
