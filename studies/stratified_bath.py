"""Does stratified sampling of the bath's actions make MD(bath) more precise?

    python studies/stratified_bath.py run OUT [--case thermal_u0.0] [--seeds 40]
    python studies/stratified_bath.py analyse OUT [--case thermal_u0.0]

MD(bath) measures the diffusion its test particles undergo in the field of N independent orbits
(the exact bath).  In the default draw the N actions are independent draws from f; here a
second variant draws them stratified: J-bar from the inverse CDF of f at u_i = (i + U_i) / N
(one particle in each of N equal-probability strata, in random order), the angles and the
directions of rotation still independent and uniform, so that the bath keeps its physics (its
fluctuations come from its phases) and loses only the Poisson scatter of how many orbits each
range of actions holds.  `run` draws --seeds realisations of the case's MD(bath) (the md
section of config/config.yaml, seed s as the pipeline's seed s) with each variant; `analyse`
fits N D per bin for both (`analysis.fits.diffusion_fit`, the pipeline's fit settings) and
prints per bin the two errors over seeds and the summary: the median ratio of the errors
(stratified / independent) and what it is worth in CPU time (ratio^2).

Expectation: a test orbit's N D is the bath's spectrum at its resonances averaged over the fit
window's resolution, a sum over thousands of orbits per resolution cell with random phases:
its scatter is that of the phases (exponential per cell), with a Poisson part in the number
of orbits per cell of relative size 1/sqrt(thousands).  Stratifying the actions removes only
the latter.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import yaml

CONFIG = "config/config.yaml"
VARIANTS = ("independent", "stratified")


def _run_record(case):
    from hmfdiff.dynamics.runs import md_runs

    with open(CONFIG) as f:
        cfg = yaml.safe_load(f)
    return cfg, md_runs(cfg)[(case, "bath")]


def stratified_state_sampler(original):
    """sample_state with the bath's actions stratified (the first call of a run, the N);
    later calls (test particles) as before."""
    from hmfdiff.dynamics import sampling

    calls = {"n": 0}

    def sample(state, n, rng, method="auto", table=None):
        calls["n"] += 1
        if calls["n"] > 1:
            return original(state, n, rng, method=method, table=table)
        jbar_g, cdf = sampling.jbar_cdf_table(state) if table is None else table
        u = (rng.permutation(n) + rng.random(n)) / n * cdf[-1]
        kappa = sampling.kappa_from_rescaled_action(np.interp(u, cdf, jbar_g), state.M0)
        return sampling._phase_points_from_kappa(kappa, state.M0, rng)

    return sample


def run(out, case, seeds):
    from hmfdiff.dynamics import md
    from hmfdiff.meanfield.equilibrium import make_state
    from hmfdiff.pipeline.io import write_dataset
    from hmfdiff.pipeline.layouts.md import md_dataset

    cfg, rec = _run_record(case)
    state = make_state(cfg["cases"][case])
    original = md.sampling.sample_state
    for variant in VARIANTS:
        folder = Path(out) / case / variant
        folder.mkdir(parents=True, exist_ok=True)
        for seed in range(seeds):
            path = folder / f"seed{seed}.nc"
            if path.exists():
                continue
            t0 = time.perf_counter()
            if variant == "stratified":
                md.sampling.sample_state = stratified_state_sampler(original)
            try:
                ds = md_dataset(md.run_md(state, rec, seed, 1, progress=None))
            finally:
                md.sampling.sample_state = original
            prov = {"md": rec.to_dict(realisation_only=True), "seed": seed, "variant": variant}
            write_dataset(ds, path, prov, case=case)
            print(f"{variant} seed {seed}: {time.perf_counter() - t0:.1f} s", flush=True)


def analyse(out, case):
    from hmfdiff.analysis.fits import diffusion_fit
    from hmfdiff.pipeline.io import read_dataset

    _, rec = _run_record(case)
    spec = rec.fit_settings()
    fits = {}
    for variant in VARIANTS:
        files = sorted((Path(out) / case / variant).glob("seed*.nc"))
        data = [read_dataset(p) for p in files]
        fits[variant] = diffusion_fit(
            data,
            window=spec["fit_window"],
            min_particles=spec["min_particles"],
            separatrix_band=spec["separatrix_band_fit"],
        )
    a, b = fits["independent"], fits["stratified"]
    ok = (a["flag"].values == 0) & (b["flag"].values == 0)
    print(f"# MD(bath) of {case}: actions of the bath independent or stratified")
    print(f"# (studies/stratified_bath.py; {a.sizes['seed']} and {b.sizes['seed']} seeds)")
    print("  kappa0    ND_indep     err_indep    ND_strat     err_strat   err ratio")
    ratio = b["ND_md_err"].values[ok] / a["ND_md_err"].values[ok]
    for i, r in zip(np.flatnonzero(ok), ratio, strict=True):
        print(
            f"  {a['kappa0'].values[i]:6.3f} {a['ND_md'].values[i]:11.4g} "
            f"{a['ND_md_err'].values[i]:12.3g} {b['ND_md'].values[i]:11.4g} "
            f"{b['ND_md_err'].values[i]:12.3g} {r:10.3f}"
        )
    # the error of a standard error over R seeds is about 1/sqrt(2(R-1)) relative
    n_seeds = a.sizes["seed"]
    print(
        f"bins compared: {ok.sum()}; error stratified / independent: median "
        f"{np.median(ratio):.3f}, mean {np.mean(ratio):.3f} +- "
        f"{np.std(ratio, ddof=1) / np.sqrt(ratio.size):.3f} (one bin's ratio scatters by about "
        f"{np.sqrt(2.0 / (2 * (n_seeds - 1))):.2f}); CPU time for equal precision: "
        f"x{np.median(ratio) ** 2:.2f}"
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("step", choices=("run", "analyse"))
    ap.add_argument("out")
    ap.add_argument("--case", default="thermal_u0.0")
    ap.add_argument("--seeds", type=int, default=40)
    args = ap.parse_args(argv)
    if args.step == "run":
        run(args.out, args.case, args.seeds)
    else:
        analyse(args.out, args.case)
    return 0


if __name__ == "__main__":
    sys.exit(main())
