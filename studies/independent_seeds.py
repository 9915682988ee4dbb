"""MD(full) with seeds the reference run did not use (issue 23 part 4).

The reference validation (docs/reference/validation.csv, seeds 0-19) has two MD(full) bins at
u = -0.2 far from the separatrix, kappa0 = 1.164 and 1.413, with N D_MD 16 % below the
propagated theory (z = -3.3 and -3.4); a rerun on the same seeds is no independent check.  This
compares each bin of a validation table (seeds 0-19) with the fit of realisations 20-39 of the
same case, run by the pipeline in a worktree whose config raises md.runs.CASE.seeds to 40:

    snakemake -j2 results/md/thermal_u-0.2/full/seeds20-21 ... seeds38-39 \\
        --configfile seeds40.yaml
    python studies/independent_seeds.py MD_DIR RESULTS_DIR VALIDATION_CSV [CASE]

CASE defaults to thermal_u-0.2.  MD_DIR is that worktree's results/md; RESULTS_DIR the
results/ of a run of the paper's config
(its equilibrium, theory, fits and windowed datasets: the windowed theory columns depend on
the fit's settings only, not on the seeds).
Prints, per bin, N D of both seed sets, their ratios to the propagated theory and the z of each,
the z of their difference, and the ratio and z of both sets together (the mean of the two
means), over the bins the agreement summary uses (flag 0).
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

DYN, FIRST, LAST = "full", 20, 39


def seed_path(md_dir, case, seed):
    """The realisation's file in whichever block of seeds the pipeline ran it."""
    found = sorted((Path(md_dir) / case / DYN).glob(f"seeds*/seed{seed}.nc"))
    if len(found) != 1:
        sys.exit(f"{md_dir}/{case}/{DYN}: {len(found)} files for seed {seed}, expected one")
    return found[0]


def main(md_dir, res, reference, case="thermal_u-0.2"):
    res = Path(res)
    paths = [seed_path(md_dir, case, s) for s in range(FIRST, LAST + 1)]
    seeds = [read_dataset(p, required=["sum_dJbar2", "count"]) for p in paths]
    run_fit = read_dataset(res / "fits" / f"{case}_{DYN}.nc")
    spec = json.loads(run_fit.attrs["config"])["fit"]
    fit = diffusion_fit(
        seeds,
        window=list(spec["fit_window"]),
        min_particles=int(spec["min_particles"]),
        separatrix_band=float(spec["separatrix_band_fit"]),
    )
    state = state_from_dataset(read_dataset(res / "equilibrium" / f"{case}.nc"))
    rows = validation_rows(case, fit, read_dataset(res / "theory" / f"{case}.nc"), state.f)
    rows = add_windowed(rows, read_dataset(res / "windowed" / f"{case}_{DYN}.nc"))
    with open(reference, newline="") as fh:
        ref = [r for r in csv.DictReader(fh) if (r["case"], r["dynamics"]) == (case, DYN)]
    print(f"{case} MD(full): seeds 0-19 (reference) against seeds {FIRST}-{LAST} (this run)")
    print(
        " kappa0   ND_prop | ref ND_md ratio   z  | new ND_md ratio   z  | z(new-ref) |"
        " both: ratio   z"
    )
    zs_ref, zs_new, zs_both = [], [], []
    for r, n in zip(ref, rows, strict=True):
        a, ea = float(r["ND_md"]), float(r["ND_md_err"])
        b, eb = n["ND_md"], n["ND_md_err"]
        th = n.get("ND_propagated", np.nan)
        if int(r["flag"]) or int(n["flag"]) or not np.isfinite(th):
            continue  # the bins the agreement summary uses (flag 0 in both)
        za, zb = (a - th) / ea, (b - th) / eb
        # both sets together: the mean of two means over equally many realisations
        m, em = 0.5 * (a + b), 0.5 * np.hypot(ea, eb)
        zs_ref.append(za)
        zs_new.append(zb)
        zs_both.append((m - th) / em)
        print(
            f" {float(r['kappa0']):6.3f} {th:9.4g} | {a:9.4g} {a / th:5.3f} {za:+5.1f} |"
            f" {b:9.4g} {b / th:5.3f} {zb:+5.1f} | {(b - a) / np.hypot(ea, eb):+5.1f}      |"
            f"       {m / th:5.3f} {zs_both[-1]:+5.1f}"
        )
    for name, z in (("reference", zs_ref), ("new seeds", zs_new), ("both", zs_both)):
        print(z_summary(name, z))


def z_summary(name, z):
    """One line: the number of bins, mean z, mean z^2, the fractions within 2 and beyond 3."""
    z = np.asarray(z)
    return (
        f"{name}: {z.size} bins, mean z {z.mean():+.2f}, mean z^2 {np.mean(z**2):.2f}, "
        f"|z| < 2: {np.mean(np.abs(z) < 2):.0%}, |z| > 3: {np.sum(np.abs(z) > 3)}"
    )


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__.split("\n\n")[2])
    main(*sys.argv[1:])
