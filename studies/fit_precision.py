"""What one md setting adds to the error of N D_MD: two fits of the same case and seeds.

    python studies/fit_precision.py FIT_A FIT_B [--out FILE]

FIT_A, FIT_B: two results of rule fit (results/fits/{case}_{dynamics}.nc) of the same case and
seeds that differ in one md setting: md.n_track (config/experiments/md_track_10k.yaml) or
md.sample_every (config/experiments/md_sample_10.yaml).  With n_track the dynamics are the same
realisation by realisation (the tracked particles are drawn after the initial conditions), so
per seed and bin B - A is the noise of the tracked sample alone; with sample_every the
integrator advances in other chunks, its float32 rounding differs and the chaotic
trajectories part, so B - A holds the realisations' own scatter too.  Prints per bin N D and
its error (over seeds) in both, the spread over seeds of A and of the paired difference, and
the summaries: the ratio of the errors (median, range, mean) and the mean ratio of the
variances (paired difference over the seeds' spread).
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
import xarray as xr


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("fit_a")
    ap.add_argument("fit_b")
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    a, b = xr.open_dataset(args.fit_a), xr.open_dataset(args.fit_b)
    na, nb = (d.attrs.get("n_tracked_from_f", "?") for d in (a, b))
    sa_, sb_ = (float(d["lag"].values[1] - d["lag"].values[0]) for d in (a, b))
    if (a.sizes["bin"], a.sizes["seed"]) != (b.sizes["bin"], b.sizes["seed"]) or not np.allclose(
        a["kappa0"].values, b["kappa0"].values
    ):
        sys.exit("error: the two fits have different bins or seeds")
    sa = a["ND_md_seed"].transpose("seed", "bin").values
    sb = b["ND_md_seed"].transpose("seed", "bin").values
    ok = (a["flag"].values == 0) & (b["flag"].values == 0)
    out = [
        "# N D_MD per bin with two settings of the MD, same seeds (studies/fit_precision.py)",
        f"# A: {args.fit_a} (n_track {na}, sample_every {sa_}); B: {args.fit_b} "
        f"(n_track {nb}, sample_every {sb_}); "
        f"{sa.shape[0]} seeds; n: tracked particles in the bin, summed over seeds",
        "  kappa0        n_A        n_B      ND_A     err_A      ND_B     err_B   sd_seeds"
        "  sd_paired",
    ]
    va = np.var(sa, axis=0, ddof=1)
    vd = np.var(sb - sa, axis=0, ddof=1)
    for i in np.flatnonzero(ok):
        out.append(
            f"  {a['kappa0'].values[i]:6.3f} {a['n_particles_in_bin'].values[i]:10.0f} "
            f"{b['n_particles_in_bin'].values[i]:10.0f} {a['ND_md'].values[i]:9.3g} "
            f"{a['ND_md_err'].values[i]:9.2g} {b['ND_md'].values[i]:9.3g} "
            f"{b['ND_md_err'].values[i]:9.2g} {np.sqrt(va[i]):10.2g} {np.sqrt(vd[i]):10.2g}"
        )
    ratio = b["ND_md_err"].values[ok] / a["ND_md_err"].values[ok]
    shift = (b["ND_md"].values[ok] - a["ND_md"].values[ok]) / a["ND_md_err"].values[ok]
    out.append(
        f"bins compared: {ok.sum()} of {ok.size}; error B / error A: median "
        f"{np.median(ratio):.3f}, range {ratio.min():.3f}-{ratio.max():.3f}, mean "
        f"{np.mean(ratio):.3f}; mean (B - A) / error A {np.mean(shift):+.3f}; variance of the "
        f"paired difference over the seeds' variance of A: mean {np.mean(vd[ok] / va[ok]):.4f}, "
        f"max {np.max(vd[ok] / va[ok]):.4f}"
    )
    from _realisations import emit

    emit(out, args.out)


if __name__ == "__main__":
    main()
