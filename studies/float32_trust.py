"""Does the float32 MD state move any diffusion coefficient?  (issue 23 part 2)

Two full reproductions of the paper's config with the same seeds: RUN_A with the float32 state
and steps (`integrator.STATE_DTYPE`), RUN_B with the float64 kernel before it.  Same seeds give
the same initial conditions (to float32's rounding), after which the chaotic N-body dynamics
parts the trajectories: the two runs are correlated samples, not copies.  The comparison is
therefore paired, realisation by realisation: per bin the mean over seeds of
N D_A(seed) - N D_B(seed) and its standard error, whose z should scatter as N(0, 1) if the
precision does not matter; a bias of the float32 steps would show in the pooled mean
difference, which the pairing makes more sensitive than either run's own error.

    python studies/float32_trust.py RUN_A/results RUN_B/results

Prints, per case and dynamics (the bins the agreement summary uses, flag 0 in both), the mean
ratio N D_A / N D_B over bins, the pooled relative difference with its standard error, the
bins' mean z^2 and the largest |z|; then the same pooled over the lines of each dynamics.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from hmfdiff.pipeline.io import read_dataset


def paired(a, b):
    """(relative differences per bin, their standard errors, ratio of means) over the bins
    both fits use; the seeds must be the same."""
    if not np.array_equal(a["seed"].values, b["seed"].values):
        sys.exit("the two fits hold different seeds: no paired comparison")
    use = (a["flag"].values == 0) & (b["flag"].values == 0)
    da = a["ND_md_seed"].values[:, use]
    db = b["ND_md_seed"].values[:, use]
    n = da.shape[0]
    d = da - db
    ref = db.mean(axis=0)
    rel = d.mean(axis=0) / ref
    err = d.std(axis=0, ddof=1) / np.sqrt(n) / ref
    return rel, err, da.mean(axis=0) / ref


def main(run_a, run_b):
    run_a, run_b = Path(run_a), Path(run_b)
    pooled_rel, pooled_err = [], []
    print("line: bins  mean N D_A/N D_B (range)  pooled rel. difference +- se  mean z^2  max|z|")
    for path in sorted((run_a / "fits").glob("*.nc")):
        a = read_dataset(path)
        b = read_dataset(run_b / "fits" / path.name)
        rel, err, ratio = paired(a, b)
        z = rel / err
        w = 1.0 / err**2
        mean = np.sum(w * rel) / np.sum(w)
        se = 1.0 / np.sqrt(np.sum(w))
        pooled_rel.append((path.stem, rel))
        pooled_err.append((path.stem, err))
        print(
            f"{path.stem}: {rel.size}  {ratio.mean():.4f} ({ratio.min():.3f}-{ratio.max():.3f})"
            f"  {mean:+.2e} +- {se:.1e}  {np.mean(z**2):.2f}  {np.max(np.abs(z)):.1f}"
        )
    for dyn in ("bath", "full"):
        rel = np.concatenate([r for n, r in pooled_rel if n.endswith(dyn)])
        err = np.concatenate([e for n, e in pooled_err if n.endswith(dyn)])
        w = 1.0 / err**2
        z = rel / err
        print(
            f"pooled, MD({dyn}): {rel.size} bins, relative difference "
            f"{np.sum(w * rel) / np.sum(w):+.2e} +- {1.0 / np.sqrt(np.sum(w)):.1e}, mean z^2 "
            f"{np.mean(z**2):.2f}, |z| > 3: {int(np.sum(np.abs(z) > 3))}"
        )


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(*sys.argv[1:])
