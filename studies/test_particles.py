"""Passive test particles against the system's own particles in the same MD(full) realisations
(issue 23 part 4).

In MD(full) the tracked particles are part of the N that make the magnetisation; test particles
move in the same self-consistent field but do not feed back.  With the same seed the N
particles are drawn first and evolve the same whatever the test particles are, so two runs
that differ only in their test particles see the same field, realisation by realisation.  This
compares, bin by bin and seed by seed, run A (the production's mix: n_track = 1e5 of the N
plus 2e4 test particles uniform in J-bar) with run B (100 of the N tracked, 1e5 test particles
uniform in J-bar over a few bins): a difference would be the particle's own part in the field
(its wake), which the kinetic theory puts at order 1/N in N D:

    python studies/test_particles.py MD_A MD_B RESULTS_DIR CASE FIRST LAST

MD_A, MD_B: the results/md folders of the two runs (seed files found in any block);
RESULTS_DIR: results/ of a run of the paper's config (fit settings, equilibrium, theory).
Prints, per bin where both fits are usable, N D of each against the propagated theory of its
own tracked particles, and the mean over seeds of the per-seed ratio B / A with its standard
error (paired: the field's noise common to both cancels).  Also checks that the two runs'
magnetisation histories agree.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
from independent_seeds import DYN, seed_path  # a sibling script: studies/ is on sys.path

from hmfdiff.analysis.fits import diffusion_fit
from hmfdiff.analysis.propagated import nd_from_theory, propagated_at_bins
from hmfdiff.pipeline.io import read_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset


def seed_files(md_dir, case, first, last):
    return [seed_path(md_dir, case, s) for s in range(first, last + 1)]


def main(md_a, md_b, res, case, first, last):
    res, first, last = Path(res), int(first), int(last)
    spec = json.loads(read_dataset(res / "fits" / f"{case}_{DYN}.nc").attrs["config"])["fit"]
    state = state_from_dataset(read_dataset(res / "equilibrium" / f"{case}.nc"))
    nd_th = nd_from_theory(read_dataset(res / "theory" / f"{case}.nc"), DYN)
    fits, m_hist = [], []
    for md in (md_a, md_b):
        seeds = [read_dataset(p) for p in seed_files(md, case, first, last)]
        m_hist.append(np.array([np.hypot(s["Mx"].values, s["My"].values) for s in seeds]))
        fits.append(
            diffusion_fit(
                seeds,
                window=list(spec["fit_window"]),
                min_particles=int(spec["min_particles"]),
                separatrix_band=float(spec["separatrix_band_fit"]),
            )
        )
    print(
        f"{case} MD({DYN}), seeds {first}-{last}: |M|(t) of A and B differ by at most "
        f"{np.max(np.abs(m_hist[0] - m_hist[1])):.1e} (the same field)"
    )
    a, b = fits
    prop = [propagated_at_bins(f, nd_th, state.f) for f in fits]
    print(" kappa0 | A: n/seed  ND_md / propagated | B: n/seed  ND_md / propagated | B/A paired")
    for i in range(a.sizes["bin"]):
        if a["flag"].values[i] or b["flag"].values[i] or not np.isfinite(prop[1][i]):
            continue
        ra = a["ND_md_seed"].values[:, i]
        rb = b["ND_md_seed"].values[:, i]
        q = rb / ra
        n_seeds = q.size
        line = f" {float(a['kappa0'][i]):6.3f} |"
        for f, p in ((a, prop[0][i]), (b, prop[1][i])):
            nd, err = float(f["ND_md"][i]), float(f["ND_md_err"][i])
            n = int(f["n_particles_in_bin"][i]) // n_seeds
            line += f" {n:7d}  {nd / p:5.3f} +- {err / p:.3f}       |"
        # the ratio of the means, its error from the per-seed pairs (delta method)
        r = rb.mean() / ra.mean()
        d = rb / rb.mean() - ra / ra.mean()
        line += f" {r:5.3f} +- {r * d.std(ddof=1) / np.sqrt(n_seeds):.3f}"
        print(line)


if __name__ == "__main__":
    if len(sys.argv) != 7:
        sys.exit(__doc__.split("\n\n")[2])
    main(*sys.argv[1:])
