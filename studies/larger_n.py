"""One case's MD at a larger N against the propagated theory at that N, bin by bin beside the
reference run's (issue 23 part 4).

MD(full) of u = 0.0 at N = 5e5 lies 11-19 % below the propagated theory in the bin
kappa0 = 1.039, just outside the separatrix band, with both independent seed sets
(docs/reference/independent_seeds_u0.0_full.txt).  Whether that is a finite-N effect (the
u = 0.2475 residual at N = 1e6 was gone at 4e6) shows in the same bins at a larger N, run by
the pipeline in a worktree whose config sets md.runs.CASE.n_particles (and seeds):

    snakemake -j2 results/fits/CASE_full.nc results/windowed/CASE_full.nc --configfile ...
    python studies/larger_n.py RUN_RESULTS THEORY_RESULTS VALIDATION_CSV CASE [DYNAMICS]

RUN_RESULTS is that worktree's results/ (its fit, its windowed dataset: the propagated theory
at its N and fit window, and its equilibrium); THEORY_RESULTS the results/ of a run of the
paper's config (the theory grid, which does not depend on N); VALIDATION_CSV the reference.
Prints per bin N D at the larger N, the propagated theory there, their ratio and z, and the
reference's ratio and z, over the bins the agreement summary uses (flag 0 in both).
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np
from independent_seeds import z_summary  # a sibling script: studies/ is on sys.path

from hmfdiff.analysis.fits import validation_rows
from hmfdiff.analysis.windowed import add_windowed
from hmfdiff.pipeline.io import read_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset


def main(run_res, theory_res, reference, case, dyn="full"):
    run_res, theory_res = Path(run_res), Path(theory_res)
    fit = read_dataset(run_res / "fits" / f"{case}_{dyn}.nc")
    state = state_from_dataset(read_dataset(run_res / "equilibrium" / f"{case}.nc"))
    rows = validation_rows(case, fit, read_dataset(theory_res / "theory" / f"{case}.nc"), state.f)
    rows = add_windowed(rows, read_dataset(run_res / "windowed" / f"{case}_{dyn}.nc"))
    with open(reference, newline="") as fh:
        ref = [r for r in csv.DictReader(fh) if (r["case"], r["dynamics"]) == (case, dyn)]
    print(
        f"{case} MD({dyn}): N = {fit.attrs['N']:.3g}, {int(fit.attrs['n_seeds'])} realisations "
        f"(fit window {[float(x) for x in fit.attrs['fit_window']]}), against the reference"
    )
    print(" kappa0 | this run: ND_md  error  ND_prop ratio   z  | reference: ratio   z")
    zs = []
    for r, n in zip(ref, rows, strict=True):
        th = n.get("ND_propagated", np.nan)
        if int(r["flag"]) or int(n["flag"]) or not np.isfinite(th):
            continue
        z = (n["ND_md"] - th) / n["ND_md_err"]
        zs.append(z)
        print(
            f" {n['kappa0']:6.3f} | {n['ND_md']:9.4g} {n['ND_md_err']:6.2g} {th:9.4g}"
            f" {n['ND_md'] / th:5.3f} {z:+5.1f} | {float(r['ratio_propagated']):5.3f}"
            f" {float(r['z_propagated']):+5.1f}"
        )
    print(z_summary("this run", zs))


if __name__ == "__main__":
    if len(sys.argv) not in (5, 6):
        sys.exit(__doc__.split("\n\n")[2])
    main(*sys.argv[1:])
