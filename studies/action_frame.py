"""Does MD(full)'s N D depend on the frame its actions are measured in? (issue 23 part 4)

MD(full) measures each tracked particle's J-bar in the frame of the instantaneous
magnetisation (its direction atan2(My, Mx)) with the state's modulus M0 (`dynamics.md`).  A
slow wander of the direction or of |M| moves every particle's measured J-bar together and, if
it is not monotonic in time, can bend <dJ^2>(lag) at long lags.  This reruns realisations of an
existing md file's settings (the same seeds: the same N particles, the same field) with the
actions measured either in the fixed frame of the initial magnetisation (phase 0, `fixed`) or
with the instantaneous modulus |M(t)| instead of M0 (`own`), writing md files to studies/out/,
and compares them seed by seed with the pipeline's files, as `studies/test_particles.py`:

    python studies/action_frame.py run MODE MD_FILE FIRST LAST   # MODE: fixed or own
    python studies/action_frame.py phase MD_FILES...   # <dphi^2>(lag) of M's direction
    python studies/test_particles.py MD_DIR studies/out/frame_MODE RESULTS CASE FIRST LAST

MD_FILE: any seed file of the pipeline's run (its settings are taken from its provenance).
A probe: the frame is changed by replacing `dynamics.md`'s atan2 (fixed) or wrapping its
frame_actions (own) for this process only; the pipeline's code is not changed.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

from hmfdiff.dynamics import md
from hmfdiff.dynamics.settings import MDRun
from hmfdiff.meanfield.equilibrium import ThermalState
from hmfdiff.pipeline.io import read_dataset, write_dataset
from hmfdiff.pipeline.layouts.md import md_dataset

OUT = Path(__file__).resolve().parent / "out"


class _Math:
    """math, with atan2 as the probe wants it; records the last |M| it saw."""

    def __init__(self, mode):
        self.mode = mode
        self.modulus = None

    def __getattr__(self, name):
        return getattr(math, name)

    def atan2(self, y, x):
        self.modulus = math.hypot(x, y)
        return 0.0 if self.mode == "fixed" else math.atan2(y, x)


def run(mode, md_file, first, last):
    if mode not in ("fixed", "own"):
        sys.exit(f"MODE must be fixed or own, not {mode!r}")
    meta = json.loads(read_dataset(md_file).attrs["config"])
    settings = MDRun(**meta["md"])
    state = ThermalState(M0=float(meta["M0"]))
    probe = _Math(mode)
    md.math = probe
    if mode == "own":
        frame_actions = md.frame_actions

        def own_modulus(S, C, p, M0, phase, out):
            return frame_actions(S, C, p, probe.modulus, phase, out)

        md.frame_actions = own_modulus
    folder = OUT / f"frame_{mode}" / settings.case / settings.dynamics / "seeds"
    folder.mkdir(parents=True, exist_ok=True)
    for seed in range(int(first), int(last) + 1):
        ds = md_dataset(md.run_md(state, settings, seed, 1, progress=lambda m: None))
        prov = {"md": settings.to_dict(realisation_only=True), "seed": seed, "M0": state.M0}
        prov["probe"] = f"actions measured with frame mode {mode!r} (studies/action_frame.py)"
        write_dataset(ds, folder / f"seed{seed}.nc", prov, case=settings.case)
        print(f"seed {seed} done ({ds.attrs['wall_time_s']:.0f} s)", flush=True)


def phase(files, lags=(10.0, 100.0, 300.0, 500.0)):
    """Mean square change of the direction of M over lags (Mx_fine, My_fine of the md files):
    lag^2 growth is a steady turn, lag growth a random walk."""
    out = []
    for f in files:
        ds = read_dataset(f, required=["Mx_fine", "My_fine"])
        t = ds["time_fine"].values
        phi = np.unwrap(np.arctan2(ds["My_fine"].values, ds["Mx_fine"].values))
        steps = [int(round(lag / (t[1] - t[0]))) for lag in lags]
        out.append([np.mean((phi[k:] - phi[:-k]) ** 2) for k in steps])
    mean = np.mean(out, axis=0)
    text = ", ".join(f"{v:.2e} ({lag:g})" for lag, v in zip(lags, mean, strict=True))
    print(f"{len(files)} realisations: <dphi^2>(lag) = {text}")


if __name__ == "__main__":
    if len(sys.argv) >= 3 and sys.argv[1] == "phase":
        phase(sys.argv[2:])
    elif len(sys.argv) == 6 and sys.argv[1] == "run":
        run(*sys.argv[2:])
    else:
        sys.exit(__doc__.split("\n\n")[2])
