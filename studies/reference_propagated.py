"""Add the propagated theory's columns (ND_propagated, ratio_propagated, z_propagated) to a
validation.csv that predates them (docs/reference/validation.csv of 2026-11-26).

The propagated theory (`analysis.propagated`) needs no MD data: the state, the spectrum table
and the fit's settings (N, lags, window, bins, tracked particles) all follow from the config,
so this computes, for each case and dynamics, what the windowed rule of the present code
writes for that table's run, and fills the three columns from the table's own ND_md and
ND_md_err:

    python studies/reference_propagated.py config/config.yaml docs/reference/validation.csv

The file is rewritten in place (every other column unchanged).
"""

from __future__ import annotations

import csv
import json
import sys

import numpy as np
import xarray as xr
import yaml

from hmfdiff.analysis.fits import write_validation_csv
from hmfdiff.analysis.propagated import add_propagated, propagated_at_bins
from hmfdiff.analysis.windowed import spectrum_table
from hmfdiff.dynamics.runs import md_runs
from hmfdiff.kinetic.spectrum import diffusion_from_spectrum
from hmfdiff.meanfield.equilibrium import make_state
from hmfdiff.pipeline.layouts.equilibrium import equilibrium_dataset, state_from_dataset


def fit_settings(run, M0):
    """The fields of a fit dataset (`fits.diffusion_fit`) that the propagation reads."""
    edges = run.jbar_edges(M0)
    lag = np.arange(0.0, run.max_lag + 1e-9, run.sample_every)
    return xr.Dataset(
        {
            "jbar_edges": ("edge", edges),
            "jbar0": ("bin", 0.5 * (edges[1:] + edges[:-1])),
            "lag": ("lag", lag),
            "M0": M0,
        },
        attrs=run.attrs(M0) | {"fit_window": list(run.fit_window)},
    )


def main(config_path, csv_path):
    cfg = yaml.safe_load(open(config_path))
    with open(csv_path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    grid = cfg["grids"]["equilibrium"]
    th = cfg["theory"]
    for (case, dyn), run in sorted(md_runs(cfg).items()):
        sel = [r for r in rows if (r["case"], r["dynamics"]) == (case, dyn)]
        if not sel:
            continue
        spec = cfg["cases"][case]
        state = state_from_dataset(
            equilibrium_dataset(make_state(spec), grid["n_kappa"], grid["kappa_max"])
        )
        fit = fit_settings(run, state.M0)
        table = spectrum_table(fit, state, n_max=th["n_max"], l_max=th["l_max"])
        nd = propagated_at_bins(
            fit, lambda k, t=table, m=state.M0: diffusion_from_spectrum(t, k, m), state.f
        )
        for r in sel:
            r["ND_md"], r["ND_md_err"] = float(r["ND_md"]), float(r["ND_md_err"])
        add_propagated(sel, nd)
        print(f"{case} {dyn}: {json.dumps(spec)}; {np.isfinite(nd).sum()} bins", flush=True)
    write_validation_csv(rows, csv_path)  # the pipeline's writer: same columns, atomic


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__.split("\n\n")[2])
    main(*sys.argv[1:])
