"""Where in lag an MD bin departs from the propagated theory (issue 23 part 4).

The fit takes half the slope of <dJ^2>(lag) over one window (100-500 for most cases).  A
deficit that appears only at long lags (the MD's <dJ^2> bending down) points to something else
than one that holds at every lag (a D that is simply lower).  This prints, for chosen bins of a
fit dataset (`fits.diffusion_fit`, the pooled `msd` of its realisations), the ratio of the MD's
slope to the propagated theory's (`analysis.propagated`, the same lags, bins and tracked
density) over successive lag windows:

    python studies/lag_windows.py FIT_FILE RESULTS_DIR CASE KAPPA0 [KAPPA0 ...]

RESULTS_DIR holds the case's equilibrium and theory (results/ of a run of the paper's config).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from hmfdiff.analysis import propagated
from hmfdiff.analysis.fits import fit_slope
from hmfdiff.pipeline.io import read_dataset
from hmfdiff.pipeline.layouts.equilibrium import state_from_dataset

WINDOWS = ((4, 20), (20, 50), (50, 100), (100, 200), (200, 300), (300, 500), (100, 500))


def main(fit_file, res, case, kappas):
    fit = read_dataset(fit_file, required=["msd"])
    dyn = fit.attrs["dynamics"]
    state = state_from_dataset(read_dataset(Path(res) / "equilibrium" / f"{case}.nc"))
    theory = read_dataset(Path(res) / "theory" / f"{case}.nc")
    N = float(fit.attrs["N"])
    nd = propagated.nd_from_theory(theory, dyn)
    lag, msd_th = propagated.propagated_msd_at_bins(fit, nd, state.f)
    print(f"{case} MD({dyn}), N = {N:.3g}, {int(fit.attrs['n_seeds'])} realisations "
          "(MD slope / propagated theory's slope over lag windows)")  # fmt: skip
    print(" kappa0  " + " ".join(f"{lo:>4d}-{hi:<4d}" for lo, hi in WINDOWS))
    for k in kappas:
        b = int(np.argmin(np.abs(fit["kappa0"].values - k)))
        th = msd_th[:, b]
        md = fit["msd"].values[b]
        ratios = [
            fit_slope(lag, md[None, :], win)[0][0] / fit_slope(lag, th[None, :], win)[0][0]
            for win in WINDOWS
        ]
        print(f" {fit['kappa0'].values[b]:6.3f}  " + " ".join(f"{r:9.3f}" for r in ratios))


if __name__ == "__main__":
    if len(sys.argv) < 5:
        sys.exit(__doc__.split("\n\n")[2])
    main(*sys.argv[1:4], [float(k) for k in sys.argv[4:]])
