"""MD(full) of u = -0.2 with seeds the reference run did not use (issue 23 part 4).

The reference validation (docs/reference/validation.csv, seeds 0-19) has two MD(full) bins at
u = -0.2 far from the separatrix, kappa0 = 1.164 and 1.413, with N D_MD 16 % below the
propagated theory (z = -3.3 and -3.4); a rerun on the same seeds is no independent check.  This
compares each bin of the reference with the fit of realisations 20-39, run by the pipeline in a
worktree whose config raises md.runs.thermal_u-0.2.seeds to 40:

    snakemake -j2 results/md/thermal_u-0.2/full/seeds20-21 ... seeds38-39 \\
        --configfile seeds40.yaml
    python studies/independent_seeds.py MD_DIR RESULTS_DIR docs/reference/validation.csv

MD_DIR is that worktree's results/md; RESULTS_DIR the results/ of a run of the paper's config
(its equilibrium, theory, fits and windowed datasets: the windowed theory columns depend on
the fit's settings only, not on the seeds).
Prints, per bin, N D of both seed sets, their ratios to the propagated theory and the z of each,
and the z of their difference, over the bins the agreement summary uses (flag 0).
"""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

import numpy as np

from hmfdiff.analysis.fits import diffusion_fit, validation_rows
from hmfdiff.analysis.windowed import add_windowed
from hmfdiff.pipeline.io import read_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset

CASE, DYN, FIRST, LAST = "thermal_u-0.2", "full", 20, 39


def main(md_dir, res, reference):
    res = Path(res)
    paths = [Path(md_dir) / CASE / DYN / f"seeds{s - s % 2}-{s - s % 2 + 1}" / f"seed{s}.nc"
             for s in range(FIRST, LAST + 1)]  # fmt: skip
    seeds = [read_dataset(p, required=["sum_dJbar2", "count"]) for p in paths]
    run_fit = read_dataset(res / "fits" / f"{CASE}_{DYN}.nc")
    spec = json.loads(run_fit.attrs["config"])["fit"]
    fit = diffusion_fit(
        seeds,
        window=list(spec["fit_window"]),
        min_particles=int(spec["min_particles"]),
        separatrix_band=float(spec["separatrix_band_fit"]),
    )
    state = state_from_dataset(read_dataset(res / "equilibrium" / f"{CASE}.nc"))
    rows = validation_rows(CASE, fit, read_dataset(res / "theory" / f"{CASE}.nc"), state.f)
    rows = add_windowed(rows, read_dataset(res / "windowed" / f"{CASE}_{DYN}.nc"))
    with open(reference, newline="") as fh:
        ref = [r for r in csv.DictReader(fh) if (r["case"], r["dynamics"]) == (CASE, DYN)]
    print(f"{CASE} MD(full): seeds 0-19 (reference) against seeds {FIRST}-{LAST} (this run)")
    print(" kappa0   ND_prop | ref ND_md ratio   z  | new ND_md ratio   z  | z(new-ref)")
    zs_ref, zs_new = [], []
    for r, n in zip(ref, rows, strict=True):
        a, ea = float(r["ND_md"]), float(r["ND_md_err"])
        b, eb = n["ND_md"], n["ND_md_err"]
        th = n.get("ND_propagated", np.nan)
        if int(r["flag"]) or int(n["flag"]) or not np.isfinite(th):
            continue  # the bins the agreement summary uses (flag 0 in both)
        za, zb = (a - th) / ea, (b - th) / eb
        zs_ref.append(za)
        zs_new.append(zb)
        print(
            f" {float(r['kappa0']):6.3f} {th:9.4g} | {a:9.4g} {a / th:5.3f} {za:+5.1f} |"
            f" {b:9.4g} {b / th:5.3f} {zb:+5.1f} | {(b - a) / np.hypot(ea, eb):+5.1f}"
        )
    for name, z in (("reference", zs_ref), ("new seeds", zs_new)):
        z = np.asarray(z)
        print(
            f"{name}: {z.size} bins, mean z {z.mean():+.2f}, mean z^2 {np.mean(z**2):.2f}, "
            f"|z| < 2: {np.mean(np.abs(z) < 2):.0%}, |z| > 3: {np.sum(np.abs(z) > 3)}"
        )


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__.split("\n\n")[2])
    main(*sys.argv[1:])
